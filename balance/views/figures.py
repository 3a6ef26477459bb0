"""What every figure is drawn with: the style, the axes, the titles, the scales and the
order bars (:mod:`balance.views.plots` and the section views draw with these).

matplotlib is imported only inside the functions that draw, so that importing this module
loads none of it.  The figures are built object-oriented (no :mod:`matplotlib.pyplot`);
:func:`styled` puts :data:`STYLE` in force while one is drawn.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from contextlib import AbstractContextManager
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from balance.core.catalogue import speed_rpm
from balance.views import signals
from balance.views.polar import zero_below_rounding
from balance.views.signals import Quantity, Source

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from balance.core.result import Result

__all__ = [
    "BEFORE_COLOUR",
    "STYLE",
    "TOTAL_COLOUR",
    "AxesArg",
    "axis_label",
    "degree_axis",
    "denoise",
    "empty_note",
    "finish",
    "format_value",
    "grid_figure",
    "h_align",
    "layout_heading",
    "layout_name",
    "new_figure",
    "order_bars",
    "order_colour",
    "order_signals",
    "pick_orders",
    "placeholder",
    "scale_of",
    "shared_legend",
    "significant_mask",
    "source_label",
    "speed_text",
    "styled",
    "title_text",
    "v_align",
]

#: Matplotlib settings every figure is drawn and saved with.
STYLE: dict[str, Any] = {
    "figure.dpi": 100,
    "savefig.dpi": 100,
    "savefig.facecolor": "white",
    "figure.facecolor": "white",
    "font.family": "DejaVu Sans",
    "font.size": 10,
    "axes.titlesize": 11,
    "axes.labelsize": 10,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "legend.fontsize": 8.5,
    "figure.titlesize": 12,
    "axes.grid": True,
    "grid.alpha": 0.35,
    "grid.linewidth": 0.6,
    "lines.linewidth": 1.4,
    "axes.formatter.limits": (-4, 5),
    "axes.formatter.use_mathtext": False,
    "legend.framealpha": 0.9,
    "svg.fonttype": "path",
    "svg.hashsalt": "balance",
    "pdf.fonttype": 42,
    "path.simplify": False,
}

#: The colour of a total (the sum of the orders) and of a figure's "before".
TOTAL_COLOUR = "black"
BEFORE_COLOUR = "0.55"

AxesArg = Any  # Axes, a sequence or array of Axes, or None


def styled() -> AbstractContextManager[Any]:
    """Context in which :data:`STYLE` is in force.

    Returns
    -------
    contextlib.AbstractContextManager
        matplotlib's own :func:`matplotlib.rc_context` with :data:`STYLE`.
    """
    import matplotlib as mpl

    settings: Any = STYLE
    return mpl.rc_context(settings)


def order_colour(order: float) -> str:
    """The same colour for the same order in every figure (tab10, order 1 first).

    Parameters
    ----------
    order : float
        Order k [1] (halves round down; below 1, the last colour).

    Returns
    -------
    str
        A matplotlib colour, ``"C0"`` to ``"C9"``.
    """
    return f"C{(round(2 * order) // 2 - 1) % 10}" if order >= 1 else "C9"


def new_figure(
    ax: AxesArg,
    n_axes: int,
    figsize: tuple[float, float],
    *,
    nrows: int = 1,
    ncols: int | None = None,
    polar: bool = False,
    kind: str,
) -> tuple[Figure, list[Axes], bool]:
    """Axes to draw on: new ones in a new figure, or the ones given (checked).

    Parameters
    ----------
    ax : Axes, sequence of Axes or None
        The axes given to a figure function; None makes a new figure.
    n_axes : int
        How many axes the kind draws on.
    figsize : (float, float)
        Size of a new figure [in].
    nrows, ncols : int
        Grid of a new figure (``ncols`` by default as many as ``n_axes`` needs).
    polar : bool
        The axes given must be polar (the phasor kinds); the figure made here has plain
        axes, on which the phasor kinds draw the same polar frame
        (:mod:`balance.views.phasor_plots`).
    kind : str
        The figure kind, for the messages.

    Returns
    -------
    fig : Figure
        The figure drawn on (the root figure of axes given).
    axes : list of Axes
        ``n_axes`` axes.
    owned : bool
        Whether the figure was made here (it then gets a title, :func:`finish`).

    Raises
    ------
    ValueError
        For axes given that are not ``n_axes`` or not polar where they must be.
    """
    from matplotlib.figure import Figure

    if ax is None:
        fig = Figure(figsize=figsize, layout="constrained")
        ncols = ncols if ncols is not None else math.ceil(n_axes / nrows)
        grid = fig.subplots(nrows, ncols, squeeze=False)
        return fig, list(np.ravel(grid))[:n_axes], True
    axes = list(np.ravel(np.asarray(ax, dtype=object)))
    if len(axes) != n_axes:
        raise ValueError(f"plot_{kind}: ax must be {n_axes} axes, got {len(axes)}")
    if polar and any(getattr(a, "name", "") != "polar" for a in axes):
        raise ValueError(f"plot_{kind}: ax must be polar axes (projection='polar')")
    parent = getattr(axes[0], "figure", None)
    if parent is None:  # pragma: no cover - axes always belong to a figure
        raise ValueError(f"plot_{kind}: the axes given belong to no figure")
    root: Figure = getattr(parent, "figure", parent)  # a SubFigure's figure is the root
    return root, axes, False


def grid_figure(
    n_axes: int, size: tuple[float, float], ncols: int = 1
) -> tuple[Figure, list[Axes]]:
    """A figure (constrained layout) of ``n_axes`` axes in rows of ``ncols``, the cells of
    the grid after the last hidden: the figures of the bearing loads, the variable speed
    and the torsion.

    Parameters
    ----------
    n_axes : int
        Number of axes [1].
    size : (float, float)
        Width and height of the figure [in].
    ncols : int
        Axes per row [1].

    Returns
    -------
    fig : matplotlib.figure.Figure
    axes : list of matplotlib.axes.Axes
        The ``n_axes`` axes, row by row.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    grid = fig.subplots(math.ceil(n_axes / ncols), ncols, squeeze=False)
    axes = list(np.ravel(grid))
    for extra in axes[n_axes:]:
        extra.set_visible(False)
    return fig, axes[:n_axes]


def placeholder(
    result: Result, kind: str, title: str | None, text: str, size: tuple[float, float] = (7.0, 3.0)
) -> Figure:
    """The figure of a kind whose section is not in the result: a note saying so (and how
    to ask for it), under the title the figure would have.

    Parameters
    ----------
    result : Result
        The analysis.
    kind : str
        The figure kind (``pin_load``).
    title : str or None
        The caller's title; by default the layout, its speed and the kind.
    text : str
        The note.
    size : (float, float)
        Width and height of the figure [in].

    Returns
    -------
    matplotlib.figure.Figure
    """
    with styled():
        fig, (ax,) = grid_figure(1, size)
        ax.set_axis_off()
        ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, color="0.4")
        default = f"{layout_heading(result)}: {kind.replace('_', ' ')}"
        fig.suptitle(title_text(fig.get_figwidth(), title or default))
        return fig


def title_text(figure_width: float, text: str) -> str:
    """A figure title wrapped to the figure's width.

    Parameters
    ----------
    figure_width : float
        Width of the figure [in] (at most about 10 px per character at 12 pt and 100 dpi).
    text : str
        The title.

    Returns
    -------
    str
        The title with line breaks.
    """
    import textwrap

    return textwrap.fill(text, max(30, int(figure_width * 100.0 / 10.0)))


def finish(
    fig: Figure,
    owned: bool,
    title: str | None,
    default_title: str,
    *,
    y: float | None = None,
) -> Figure:
    """Set the figure title (wrapped to the figure's width) on a figure of our own.

    Parameters
    ----------
    fig : Figure
        The figure drawn.
    owned : bool
        Whether the figure was made by the figure function (:func:`new_figure`).
    title : str or None
        The title asked for; set on any figure.
    default_title : str
        The title of a figure of our own without ``title``.
    y : float, optional
        The top of the title [figure fraction]; by default matplotlib's.

    Returns
    -------
    Figure
        ``fig``.
    """
    if title is not None or owned:
        text = title_text(fig.get_figwidth(), default_title if title is None else title)
        if y is None:
            fig.suptitle(text)
        else:
            fig.suptitle(text, y=y)
    return fig


def layout_name(result: Result) -> str:
    """The layout's name, as figure titles begin.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.

    Returns
    -------
    str
    """
    return str(result.engine.name)


def speed_text(speed: float) -> str:
    """A crank speed as figure titles state it: ``8000 rpm`` (a no-break space, so that a
    wrapped title keeps the number and its unit together).

    Parameters
    ----------
    speed : float
        The crank speed [rad/s].

    Returns
    -------
    str
    """
    return f"{speed_rpm(speed):.6g}\u00a0rpm"


def layout_heading(result: Result) -> str:
    """How every figure title of a result begins: the layout's name and its crank speed
    (``Inline-4, flat crank (Honda K20A) at 8000 rpm``).

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.

    Returns
    -------
    str
    """
    return f"{layout_name(result)} at {speed_text(result.engine.speed)}"


def scale_of(result: Result, quantity: Quantity, normalised: bool) -> tuple[float, str, str]:
    """How a force or moment is drawn: divided by its stored reference, or as it is.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    quantity : {'force', 'moment'}
        The quantity drawn.
    normalised : bool
        Per ``reference_force`` or ``reference_moment`` (when the reference is finite and
        above zero).

    Returns
    -------
    divisor : float
        What the values are divided by [N or N m, or 1].
    unit : str
        The unit drawn: ``"N"``, ``"N m"``, ``"per F1"`` or ``"per F1 a"``.
    per : str
        The reference's short name (``"F1"``, ``"F1 a"``), empty when not normalised.
    """
    if quantity == "force":
        unit, per, value = "N", "F1", result.reference_force
    else:
        unit, per, value = "N m", "F1 a", result.reference_moment
    if normalised:
        value = float(value)
        if math.isfinite(value) and value > 0.0:
            return value, f"per {per}", per
    return 1.0, unit, ""


def axis_label(name: str, unit: str) -> str:
    """An axis label: ``name [unit]``, or ``name / reference [1]`` for a unit ``per ...``.

    Parameters
    ----------
    name : str
        The quantity.
    unit : str
        Its unit, as :func:`scale_of` gives it.

    Returns
    -------
    str
    """
    return f"{name} [{unit}]" if not unit.startswith("per ") else f"{name} / {unit[4:]} [1]"


def significant_mask(values: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Which values a figure draws and labels: those that are not zero by the rule of every
    view (docs/conventions.md, "Zero by symmetry";
    :func:`balance.views.polar.zero_below_rounding`), with the values' own sum as the
    scale and their number as the number of terms.

    The values a figure draws (peaks, phasor magnitudes, amplitudes) were cleaned by the
    analysis already (a phasor sum that cancels is exactly 0); this keeps out of the
    figure what is within the rounding of the values drawn beside it.

    Parameters
    ----------
    values : ndarray
        Sizes (NaN counts as zero) [any unit].

    Returns
    -------
    ndarray of bool
        Of the shape of ``values``; all False when every value is zero.
    """
    size = np.nan_to_num(np.abs(np.asarray(values, dtype=np.float64)), nan=0.0)
    kept = zero_below_rounding(size, float(size.sum()), max(size.size, 1))
    return np.asarray(kept > 0.0)


def pick_orders(all_orders: NDArray[Any], orders: Iterable[float] | None) -> NDArray[np.bool_]:
    """Which of a result's orders a figure draws.

    Parameters
    ----------
    all_orders : ndarray
        The result's orders [1].
    orders : iterable of float or None
        The orders asked for; None: all.

    Returns
    -------
    ndarray of bool
        One entry per order of ``all_orders``.

    Raises
    ------
    ValueError
        For an order asked for that the result does not have.
    """
    if orders is None:
        return np.ones(all_orders.shape, dtype=bool)
    wanted = np.asarray(list(orders), dtype=np.float64)
    missing = [k for k in wanted if not np.any(np.isclose(all_orders, k))]
    if missing:
        raise ValueError(
            f"orders {', '.join(f'{k:g}' for k in missing)} are not in the result "
            f"(it has {', '.join(f'{k:g}' for k in all_orders)})"
        )
    return np.asarray(np.isin(np.round(all_orders * 2), np.round(wanted * 2)))


def source_label(source: Source) -> str:
    """What a source of the force and moment is, as figure titles say it.

    Parameters
    ----------
    source : {'free', 'reciprocating', 'residual'}
        See :mod:`balance.views.signals`.

    Returns
    -------
    str
    """
    return {
        "free": "free (reciprocating + rotating)",
        "reciprocating": "reciprocating inertia",
        "residual": "residual with the proposal",
    }[source]


def format_value(value: float) -> str:
    """A number as bar labels and ring values print it.

    Parameters
    ----------
    value : float
        The number [any unit].

    Returns
    -------
    str
        Whole numbers from 1000 up to 1e6, three significant digits otherwise; ``-`` for
        NaN or infinity.
    """
    if not math.isfinite(value):
        return "-"
    if 1e3 <= abs(value) < 1e6:
        return f"{value:.0f}"
    return f"{value:.3g}"


def empty_note(axes: Axes, text: str) -> None:
    """Write on axes why they show nothing (zero, not computed).

    Parameters
    ----------
    axes : Axes
        The axes.
    text : str
        The note.
    """
    axes.text(0.5, 0.8, text, transform=axes.transAxes, ha="center", va="center", color="0.4")


def denoise(values: NDArray[Any], reference: float, n_terms: int) -> NDArray[Any]:
    """Zero what is round-off of a signal summed over orders: the rule of every view
    (:func:`balance.views.polar.zero_below_rounding`), with the sum of the orders' peaks as
    the scale and the number of phasors summed as the number of terms.

    Real and imaginary parts (y and x) are treated separately, so that a force along y does
    not show a 1e-14 N wobble in x on an axis scaled to it.

    Parameters
    ----------
    values : ndarray, real or complex
        Signals [N, N m, or per their reference].
    reference : float
        The sum of the sizes of the phasors summed into each value, in their unit
        (nothing is zeroed without a finite one above zero).
    n_terms : int
        The number of phasors summed into each value (forward and backward of each order).

    Returns
    -------
    ndarray
        ``values`` with the round-off set to zero.
    """
    if not (math.isfinite(reference) and reference > 0.0):
        return values
    if np.iscomplexobj(values):
        real = zero_below_rounding(values.real, reference, n_terms)
        imag = zero_below_rounding(values.imag, reference, n_terms)
        return np.asarray(real + 1j * imag)
    return zero_below_rounding(values, reference, n_terms)


def order_signals(
    result: Result,
    quantity: Quantity,
    source: Source,
    orders: Iterable[float] | None,
    normalised: bool,
    theta_deg: NDArray[np.float64],
) -> tuple[NDArray[Any], NDArray[np.complex128], NDArray[np.complex128], str, NDArray[np.bool_]]:
    """A force or moment over the crank angle, per order and in total, as drawn.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    quantity : {'force', 'moment'}
        The quantity.
    source : {'free', 'reciprocating', 'residual'}
        See :mod:`balance.views.signals`.
    orders : iterable of float or None
        The orders to draw (:func:`pick_orders`).
    normalised : bool
        Per the stored reference (:func:`scale_of`).
    theta_deg : ndarray
        Crank angles [deg].

    Returns
    -------
    orders : ndarray
        The orders picked.
    per_order : ndarray of complex, shape (orders, angles)
        Each order's signal ``y + i x``, scaled and without round-off (:func:`denoise`).
    total : ndarray of complex
        Their sum, the same way.
    unit : str
        The unit drawn.
    shown : ndarray of bool
        Which orders are large enough to draw: their peaks
        (:func:`balance.views.signals.peak_of`) not zero next to the largest.
    """
    ks, forward, backward = signals.phasors_of(result, quantity, source)
    keep = pick_orders(ks, orders)
    ks, forward, backward = ks[keep], forward[keep], backward[keep]
    divisor, unit, _ = scale_of(result, quantity, normalised)
    per_order = signals.signal_per_order(forward, backward, ks, theta_deg) / divisor
    peaks = signals.peak_of(result, quantity, source)[keep]
    reference = float(np.nansum(peaks)) / divisor
    total = per_order.sum(axis=0)
    return (
        ks,
        denoise(per_order, reference, 2 * ks.size),
        denoise(total, reference, 2 * ks.size),
        unit,
        significant_mask(peaks),
    )


def degree_axis(axes: Axes, span: float = 360.0) -> None:
    """A crank-angle axis from 0 to ``span`` with ticks every 90 (or 180) deg.

    Parameters
    ----------
    axes : Axes
        The axes.
    span : float
        The last crank angle [deg]: 360, or 720 for a four-stroke cycle.
    """
    axes.set_xlim(0.0, span)
    axes.set_xticks(np.arange(0.0, span + 1.0, 90.0 if span <= 360.0 else 180.0))
    axes.set_xlabel("crank angle θ [deg]")


def h_align(angle_rad: float) -> str:
    """Horizontal alignment of a label placed at an angle from +y, clockwise.

    Parameters
    ----------
    angle_rad : float
        The angle [rad].

    Returns
    -------
    str
        ``"center"``, ``"left"`` or ``"right"``.
    """
    s = math.sin(angle_rad)
    return "center" if abs(s) < 0.3 else ("left" if s > 0 else "right")


def v_align(angle_rad: float) -> str:
    """Vertical alignment of a label placed at an angle from +y, clockwise.

    Parameters
    ----------
    angle_rad : float
        The angle [rad].

    Returns
    -------
    str
        ``"center"``, ``"bottom"`` or ``"top"``.
    """
    c = math.cos(angle_rad)
    return "center" if abs(c) < 0.3 else ("bottom" if c > 0 else "top")


def shared_legend(fig: Figure, axes_list: Sequence[Axes]) -> None:
    """One legend for the figure with every distinct label of the axes, total last.

    Parameters
    ----------
    fig : Figure
        The figure.
    axes_list : sequence of Axes
        The axes whose labelled lines go into the legend.
    """
    seen: dict[str, Any] = {}
    for axes in axes_list:
        handles, labels = axes.get_legend_handles_labels()
        for handle, label in zip(handles, labels, strict=True):
            seen.setdefault(label, handle)
    if not seen:
        return
    labels = sorted(
        seen,
        key=lambda s: (s == "total", float(s.split()[-1]) if s.startswith("order") else 0.0, s),
    )
    fig.legend([seen[s] for s in labels], labels, loc="outside right center")


def order_bars(
    axes: Axes,
    orders: NDArray[Any],
    series: Sequence[tuple[NDArray[np.float64], str, str | None]],
    *,
    log: bool = False,
    width: float = 0.8,
) -> None:
    """Grouped bars per order, each non-zero bar labelled with its value.

    Parameters
    ----------
    axes : Axes
        The axes.
    orders : ndarray
        The orders [1], one group of bars each.
    series : sequence of (ndarray, str, str or None)
        Each series' values per order [any unit], colour and legend label.
    log : bool
        Logarithmic vertical axis.
    width : float
        Width of a group [orders].
    """
    from matplotlib.container import BarContainer

    n = len(series)
    positions = np.arange(len(orders), dtype=np.float64)
    bar_width = width / n
    top = 0.0
    for i, (values, colour, label) in enumerate(series):
        shown = significant_mask(values)
        heights = np.where(shown, np.nan_to_num(values, nan=0.0), 0.0)
        offset = (i - (n - 1) / 2.0) * bar_width
        bars = axes.bar(
            positions + offset, heights, bar_width * 0.92, color=colour, label=label, zorder=3
        )
        # labels on the bars that are not zero (an empty label is a text to lay out too)
        labelled = BarContainer(
            [bar for bar, s in zip(bars, shown, strict=True) if s],
            datavalues=heights[shown],
            orientation="vertical",
        )
        axes.bar_label(
            labelled,
            labels=[format_value(float(h)) for h in heights[shown]],
            fontsize=7.5,
            padding=2,
            rotation=90 if n > 1 else 0,
        )
        top = max(top, float(heights.max(initial=0.0)))
    axes.set_xticks(positions, [f"{k:g}" for k in orders])
    axes.set_xlabel("order k [1]")
    axes.grid(axis="x", visible=False)
    if log and top > 0:
        axes.set_yscale("log")
        axes.set_ylim(top * 1e-7, top * 8.0)
    else:
        axes.set_ylim(0.0, top * (1.35 if n > 1 else 1.18) if top > 0 else 1.0)
    if top == 0:
        empty_note(axes, "all zero")
