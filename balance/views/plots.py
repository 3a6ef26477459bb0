r"""Figures of a result: compute first (:mod:`balance.views.signals`), then draw.

Every figure is a function ``plot_<kind>(result, *, ax=None, ...)`` that takes the
:class:`~balance.core.result.Result` of :func:`balance.core.analysis.compute` (its complex
phasors and stored references, as they are) and returns a
:class:`matplotlib.figure.Figure`.  The figures are
built object-oriented (no :mod:`matplotlib.pyplot`, no global state): they work headless,
and matplotlib is imported only when a figure is drawn.  Each function draws under a fixed
style (:data:`STYLE`, applied with :func:`matplotlib.rc_context`) so that figures look the
same whatever the user's ``matplotlibrc``.

``ax`` may be given to draw into existing axes: one :class:`~matplotlib.axes.Axes` for
single-panel kinds, a sequence of as many axes as the kind has panels otherwise (polar axes
for ``phasors``).  The figure title (layout name) is only set on a figure the function
created, or when ``title`` is given.

Kinds (:data:`PLOT_KINDS`):

``crank_star``
    Throws and banks seen from the front (+y up, +x right, crank turning clockwise).
``phasors``
    Polar diagrams of the force and moment phasors, one panel per order on its own scale,
    forward and backward.
``crank_angle``
    Force (y and x) and pitch/yaw couples over one revolution, total and per order.
``locus``
    The path of the force and moment vectors in the transverse plane, per order and total.
``spectrum``
    Peak force and moment per order, as bars.
``roll``
    Roll torque over a revolution (or a cycle with half orders) and its spectrum.
``balance``
    Force, moment and roll before and after the proposed balancing.
``torque``
    With gas forces: torque of each cylinder and engine torque over the working cycle
    (without a ``gas:`` section the figure says so and draws nothing).
``forces``
    With gas forces: the forces on one cylinder's crank train over the cycle, P, N, S, T, K
    (the force diagrams of Kolchin and Demidov, *Design of Automotive Engines*, Mir 1984;
    a note without gas).

The force and moment drawn are by default the *free* ones: reciprocating inertia plus the
centrifugal force of the rotating masses (``source="free"``; see
:mod:`balance.views.signals`).  Moments are :math:`\sum (z_i - z_{ref}) F_i`, drawn along the
force as in the CONTRACT; ``crank_angle`` shows them as the physical pitch and yaw couples.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterable, Sequence
from contextlib import AbstractContextManager
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from balance.core.errors import InputError
from balance.views import signals as synthesis
from balance.views.signals import Quantity, Source

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from balance.core.result import Result

__all__ = [
    "FORMATS",
    "GAS_KINDS",
    "PHASOR_COLUMNS",
    "PLOT_KINDS",
    "STYLE",
    "all_kinds",
    "applicable_kinds",
    "figure_bytes",
    "phasor_panels",
    "plot_balance",
    "plot_crank_angle",
    "plot_crank_star",
    "plot_forces",
    "plot_kind",
    "plot_locus",
    "plot_phasors",
    "plot_roll",
    "plot_spectrum",
    "plot_torque",
    "proposal_summary",
    "save_plots",
    "section_kinds",
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

#: File formats :func:`save_plots` writes.
FORMATS = ("png", "svg", "pdf")

#: Share of the largest order below which an order counts as zero in a figure.
ZERO_SHARE = 1e-9

TOTAL_COLOUR = "black"
#: Phasor arrows: forward wide and light, backward thin and dashed on top, so that equal
#: forward and backward phasors (a line locus) both show.
FORWARD_ARROW: dict[str, Any] = {
    "arrowstyle": "-|>",
    "lw": 3.4,
    "alpha": 0.45,
    "mutation_scale": 18,
    "zorder": 2,
}
BACKWARD_ARROW: dict[str, Any] = {
    "arrowstyle": "->",
    "lw": 1.5,
    "linestyle": "--",
    "mutation_scale": 14,
    "zorder": 3,
}
BEFORE_COLOUR = "0.55"

AxesArg = Any  # Axes, a sequence or array of Axes, or None


# --------------------------------------------------------------------------- helpers


def _styled() -> AbstractContextManager[Any]:
    """Context in which :data:`STYLE` is in force (matplotlib's own rc_context)."""
    import matplotlib as mpl

    settings: Any = STYLE
    return mpl.rc_context(settings)


def _order_colour(order: float) -> str:
    """The same colour for the same order in every figure (tab10, order 1 first)."""
    return f"C{(round(2 * order) // 2 - 1) % 10}" if order >= 1 else "C9"


def _new_figure(
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

    ``polar``: axes given must be polar (the phasor kinds); the figure made here has plain
    axes, on which the phasor kinds draw the same polar frame (:func:`_phasor_frame`).
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


def _title_text(figure_width: float, text: str) -> str:
    """A figure title wrapped to the figure's width [in] (at most about 10 px per character
    at 12 pt and 100 dpi)."""
    import textwrap

    return textwrap.fill(text, max(30, int(figure_width * 100.0 / 10.0)))


def _finish(
    fig: Figure,
    owned: bool,
    title: str | None,
    default_title: str,
    *,
    y: float | None = None,
) -> Figure:
    """Set the figure title (wrapped to the figure's width) on a figure of our own; ``y``
    places its top (figure fraction; by default matplotlib's)."""
    if title is not None or owned:
        text = _title_text(fig.get_figwidth(), default_title if title is None else title)
        if y is None:
            fig.suptitle(text)
        else:
            fig.suptitle(text, y=y)
    return fig


def _layout_name(result: Result) -> str:
    return str(result.engine.name)


def _scale(result: Result, quantity: Quantity, normalised: bool) -> tuple[float, str, str]:
    """Divisor, unit and short name of the normalisation of a quantity (stored references)."""
    if quantity == "force":
        unit, per, value = "N", "F1", result.reference_force
    else:
        unit, per, value = "N m", "F1 a", result.reference_moment
    if normalised:
        value = float(value)
        if math.isfinite(value) and value > 0.0:
            return value, f"per {per}", per
    return 1.0, unit, ""


def _axis_label(name: str, unit: str) -> str:
    return f"{name} [{unit}]" if not unit.startswith("per ") else f"{name} / {unit[4:]} [1]"


def _significant(values: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Orders whose size is not zero next to the largest."""
    size = np.nan_to_num(np.abs(values), nan=0.0)
    largest = float(size.max(initial=0.0))
    return np.asarray(size > ZERO_SHARE * largest) if largest > 0 else np.zeros(size.shape, bool)


def _pick_orders(all_orders: NDArray[Any], orders: Iterable[float] | None) -> NDArray[np.bool_]:
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


def _source_label(source: Source) -> str:
    return {
        "free": "free (reciprocating + rotating)",
        "reciprocating": "reciprocating inertia",
        "residual": "residual with the proposal",
    }[source]


def _format(value: float) -> str:
    """Bar labels: whole numbers from 1000 up to 1e6, three significant digits otherwise."""
    if not math.isfinite(value):
        return "-"
    if 1e3 <= abs(value) < 1e6:
        return f"{value:.0f}"
    return f"{value:.3g}"


def _empty_note(axes: Axes, text: str) -> None:
    axes.text(0.5, 0.8, text, transform=axes.transAxes, ha="center", va="center", color="0.4")


def _denoise(values: NDArray[Any], reference: float) -> NDArray[Any]:
    """Zero what is round-off of the phasor sums: parts below ZERO_SHARE of ``reference``.

    Real and imaginary parts (x and y) are treated separately, so that a force along y does
    not show a 1e-14 N wobble in x on an axis scaled to it.
    """
    if not (math.isfinite(reference) and reference > 0.0):
        return values
    limit = ZERO_SHARE * reference
    if np.iscomplexobj(values):
        real = np.where(np.abs(values.real) < limit, 0.0, values.real)
        imag = np.where(np.abs(values.imag) < limit, 0.0, values.imag)
        return np.asarray(real + 1j * imag)
    return np.asarray(np.where(np.abs(values) < limit, 0.0, values))


def _order_signals(
    result: Result,
    quantity: Quantity,
    source: Source,
    orders: Iterable[float] | None,
    normalised: bool,
    theta_deg: NDArray[np.float64],
) -> tuple[NDArray[Any], NDArray[np.complex128], NDArray[np.complex128], str, NDArray[np.bool_]]:
    """The orders picked, each one's signal and their sum (scaled and without round-off),
    the unit, and which orders are large enough to draw."""
    ks, forward, backward = synthesis.phasors_of(result, quantity, source)
    keep = _pick_orders(ks, orders)
    ks, forward, backward = ks[keep], forward[keep], backward[keep]
    divisor, unit, _ = _scale(result, quantity, normalised)
    per_order = synthesis.signal_per_order(forward, backward, ks, theta_deg) / divisor
    peaks = synthesis.peak_of(result, quantity, source)[keep]
    reference = float(np.nansum(peaks)) / divisor
    total = per_order.sum(axis=0)
    return ks, _denoise(per_order, reference), _denoise(total, reference), unit, _significant(peaks)


def _degree_axis(axes: Axes, span: float = 360.0) -> None:
    axes.set_xlim(0.0, span)
    axes.set_xticks(np.arange(0.0, span + 1.0, 90.0 if span <= 360.0 else 180.0))
    axes.set_xlabel("crank angle θ [deg]")


# --------------------------------------------------------------------------- kinds


def plot_crank_star(result: Result, *, ax: AxesArg = None, title: str | None = None) -> Figure:
    """Crank star: throws and banks seen along the crank from the front.

    The view is along -z: +y is up, +x to the right, and the crank turns clockwise (from +y
    towards +x).  Each throw is drawn as a spoke at its angle (crank angle 0) with the
    cylinders on it; each bank (bore axis) as a dashed line at its angle.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    title : str, optional
        Figure title; by default the layout name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    with _styled():
        fig, (axes,), owned = _new_figure(ax, 1, (6.0, 6.2), kind="crank_star")
        engine = result.engine
        throws = np.mod(np.degrees(np.asarray(engine.throw, dtype=np.float64)), 360.0)
        banks = np.mod(np.degrees(np.asarray(engine.bank, dtype=np.float64)), 360.0)
        cylinders = np.arange(1, engine.n_cylinders + 1)
        circle = np.radians(np.linspace(0.0, 360.0, 361))
        axes.plot(np.sin(circle), np.cos(circle), color="0.75", lw=1.0, zorder=1)
        axes.plot([0.0], [0.0], "o", color="black", ms=6, zorder=4)

        bank_keys = np.round(banks, 6) % 360.0
        for bank in np.unique(bank_keys):
            on_bank = cylinders[bank_keys == bank]
            a = math.radians(float(bank))
            axes.plot(
                [0.0, 1.6 * math.sin(a)],
                [0.0, 1.6 * math.cos(a)],
                ls="--",
                color="C3",
                lw=1.3,
                zorder=2,
            )
            label = _signed_angle(float(bank))
            names = ", ".join(str(int(c)) for c in on_bank)
            axes.text(
                1.72 * math.sin(a),
                1.72 * math.cos(a),
                f"bank {label}\ncyl. {names}"
                if len(np.unique(bank_keys)) > 1
                else f"bore axis {label}",
                ha=_ha(a),
                va=_va(a),
                color="C3",
                fontsize=9,
            )

        throw_keys = np.round(throws, 6) % 360.0
        for throw in np.unique(throw_keys):
            on_throw = cylinders[throw_keys == throw]
            a = math.radians(float(throw))
            tip = (math.sin(a), math.cos(a))
            axes.plot([0.0, tip[0]], [0.0, tip[1]], color="C0", lw=3.0, zorder=3)
            axes.plot([tip[0]], [tip[1]], "o", color="C0", ms=9, zorder=3)
            axes.text(
                1.2 * tip[0],
                1.2 * tip[1],
                f"{', '.join(str(int(c)) for c in on_throw)}\n({float(throw):g}°)",
                ha=_ha(a),
                va=_va(a),
                fontsize=10,
                fontweight="bold",
                color="C0",
                zorder=5,
            )

        # direction of rotation: from +y towards +x, i.e. clockwise in this view; drawn in
        # the lower left corner, where no bank label goes unless a bank points there
        centre = (-2.15, -2.15)
        start, end = math.radians(-60.0), math.radians(60.0)
        axes.annotate(
            "",
            xy=(centre[0] + 0.28 * math.sin(end), centre[1] + 0.28 * math.cos(end)),
            xytext=(centre[0] + 0.28 * math.sin(start), centre[1] + 0.28 * math.cos(start)),
            arrowprops={
                "arrowstyle": "-|>",
                "color": "0.3",
                "lw": 1.3,
                "connectionstyle": "arc3,rad=-0.55",
            },
        )
        axes.text(centre[0], centre[1] - 0.05, "rotation", ha="center", va="top", color="0.3")
        axes.set_xlim(-2.6, 2.6)
        axes.set_ylim(-2.6, 2.6)
        axes.set_aspect("equal")
        axes.grid(False)
        axes.set_xticks([-1.0, 0.0, 1.0])
        axes.set_yticks([-1.0, 0.0, 1.0])
        axes.set_xlabel("x / crank radius [1]  (towards the pin after +y)")
        axes.set_ylabel("y / crank radius [1]  (up)")
        axes.set_title("throws (solid) and banks (dashed), seen from the front")
        return _finish(fig, owned, title, f"{_layout_name(result)}: crank star")


def _signed_angle(angle_deg: float) -> str:
    signed = (angle_deg + 180.0) % 360.0 - 180.0
    return f"{signed:+g}°" if signed else "0°"


def _ha(angle_rad: float) -> str:
    s = math.sin(angle_rad)
    return "center" if abs(s) < 0.3 else ("left" if s > 0 else "right")


def _va(angle_rad: float) -> str:
    c = math.cos(angle_rad)
    return "center" if abs(c) < 0.3 else ("bottom" if c > 0 else "top")


#: Polar panels per row of the per-order phasor figure.
PHASOR_COLUMNS = 4

#: Room [in] for the angle labels of a phasor panel beside its circle and above and below
#: it: what :func:`_phasor_frame` leaves on plain axes and :func:`_phasor_figure` lays the
#: panels out with.
_PHASOR_LABEL_ROOM = (0.3, 0.16)


def phasor_panels(
    result: Result,
    *,
    source: Source = "free",
    orders: Iterable[int] | None = None,
) -> list[tuple[Quantity, list[int]]]:
    """The panels of :func:`plot_phasors` with ``scale="per-order"``: for the force and the
    moment, the orders that have a phasor not zero next to the largest of that quantity
    (:data:`ZERO_SHARE`); an empty list draws one panel that says why (zero, not
    computed)."""
    return [(p.quantity, p.shown) for p in _panel_phasors(result, source, orders)]


class _PanelPhasors(NamedTuple):
    """A quantity's phasors and its panels in the per-order phasor figure."""

    quantity: Quantity
    orders: NDArray[np.intp]
    forward: synthesis.ComplexArray
    backward: synthesis.ComplexArray
    #: the orders with a panel of their own (:func:`phasor_panels`)
    shown: list[int]
    #: what the one panel of a quantity without any says: not computed, or all zero
    note: str


def _panel_phasors(
    result: Result, source: Source, orders: Iterable[int] | None
) -> list[_PanelPhasors]:
    """For the force and the moment: its phasors (:func:`balance.views.signals.phasors_of`),
    the orders of its panels and the note of a panel without any; the phasors are computed
    once for both :func:`phasor_panels` and :func:`plot_phasors`."""
    out = []
    for quantity in synthesis.QUANTITIES:
        ks, fwd, bwd = synthesis.phasors_of(result, quantity, source)
        keep = _pick_orders(ks, orders)
        size = synthesis.magnitude_of(result, quantity, source)[keep]  # (orders, 2)
        shown: list[int] = []
        if not np.isnan(size).all():  # computed
            significant = np.asarray(np.asarray(_significant(size)).any(axis=1), dtype=bool)
            shown = [int(k) for k, s in zip(ks[keep], significant, strict=True) if s]
        note = "not computed" if np.isnan(fwd).all() else "all zero"
        out.append(_PanelPhasors(quantity, ks, fwd, bwd, shown, note))
    return out


def plot_phasors(
    result: Result,
    *,
    ax: AxesArg = None,
    source: Source = "free",
    orders: Iterable[int] | None = None,
    normalised: bool = False,
    scale: str = "per-order",
    title: str | None = None,
) -> Figure:
    """Polar diagrams of the force and moment phasors, forward (wide) and backward (dashed).

    Angles are drawn as in the engine frame: 0 (+y) at the top, increasing clockwise (the
    direction of rotation seen from the front).  Each arrow is a phasor at crank angle 0;
    forward phasors turn clockwise at k times crank speed, backward ones anticlockwise.

    By default (``scale="per-order"``) every order that is not zero has a panel of its
    own, with its own radial scale and its magnitudes written under it: a second order a
    hundredth of the first is as readable as the first (one linear scale for all orders
    shrinks it to a dot; a logarithmic radius would distort the lengths a reader compares
    and has no zero at the centre).  The force panels come first, then the moment panels,
    :data:`PHASOR_COLUMNS` to a row.  ``scale="common"`` draws all orders of a quantity on
    one linear scale, two panels.

    The polar frame of each panel (circle, rings with their values, spokes every 45 deg,
    angle labels) is drawn as lines and text (:func:`_phasor_frame`): on the plain axes of
    the figure this function makes, and on the polar axes given as ``ax``, alike.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    ax : sequence of polar Axes, optional
        Axes to draw on: with ``scale="common"`` two (force and moment); per order, one
        per panel of :func:`phasor_panels` (an empty quantity takes one).  A new figure
        otherwise.
    source : {'free', 'reciprocating', 'residual'}
        Which force and moment (see :mod:`balance.views.signals`).
    orders : iterable of int, optional
        Orders to draw; default every order of the result (zero ones are not drawn).
    normalised : bool
        Draw per ``reference_force`` and ``reference_moment`` [1] instead of N and N m.
    scale : {'per-order', 'common'}
        A radial scale per order (panels), or one per quantity.
    title : str, optional
        Figure title; by default the layout name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if scale not in ("per-order", "common"):
        raise ValueError(f"plot_phasors: scale must be 'per-order' or 'common', got {scale!r}")
    if scale == "common":
        return _phasors_common(result, ax, source, orders, normalised, title)

    groups = []
    for quantity, ks, fwd, bwd, ks_shown, note in _panel_phasors(result, source, orders):
        divisor, unit, _ = _scale(result, quantity, normalised)
        name = "force" if quantity == "force" else "moment Σ Δz·F"
        groups.append((ks, fwd / divisor, bwd / divisor, _axis_label(name, unit), ks_shown, note))
    default_title = f"{_layout_name(result)}: phasors at θ\u00a0=\u00a00, {_source_label(source)}"
    with _styled():
        if ax is None:
            fig, axes_list, title_y = _phasor_figure(
                [(label, len(ks_shown)) for _, _, _, label, ks_shown, _ in groups],
                default_title if title is None else title,
            )
            owned = True
        else:
            counts = [max(len(ks_shown), 1) for _, _, _, _, ks_shown, _ in groups]
            fig, given, owned = _new_figure(ax, sum(counts), (1.0, 1.0), polar=True, kind="phasors")
            axes_list, start = [], 0
            for n in counts:
                axes_list.append(given[start : start + n])
                start += n
            title_y = None
        for axes_group, (ks, fwd, bwd, label, ks_shown, note) in zip(
            axes_list, groups, strict=True
        ):
            if not ks_shown:
                note_axes = axes_group[0]
                note_axes.set_axis_off()
                note_axes.text(
                    0.5,
                    0.5,
                    f"{note}: {label}",
                    transform=note_axes.transAxes,
                    ha="center",
                    va="center",
                    color="0.4",
                )
                continue
            shown = {k: (fwd[i], bwd[i]) for i, k in enumerate(ks) if int(k) in ks_shown}
            for axes, k in zip(axes_group, ks_shown, strict=True):
                pf, pb = shown[k]
                largest = max(abs(pf), abs(pb))
                _phasor_frame(axes, 1.12 * largest, [largest / 2.0, largest])
                colour = _order_colour(k)
                significant = _significant(np.array([abs(pf), abs(pb)]))
                for phasor, arrow, visible in (
                    (pf, FORWARD_ARROW, significant[0]),
                    (pb, BACKWARD_ARROW, significant[1]),
                ):
                    if visible:
                        _phasor_arrow(axes, phasor, colour, arrow)
                axes.set_title(
                    f"order {k}\nforward {_format(abs(pf))}, backward {_format(abs(pb))}",
                    fontsize=9,
                    color=colour,
                    pad=8 if axes.name == "polar" else 5,
                )
        return _finish(fig, owned, title, default_title, y=title_y)


def _direction_legend(
    forward: str = "forward (wide):\nturns with\nthe crank",
    backward: str = "backward (dashed):\nturns against\nthe crank",
) -> list[Any]:
    """Legend entries of the phasor arrows, labelled ``forward`` and ``backward``: forward
    wide, backward dashed."""
    from matplotlib.lines import Line2D

    return [
        Line2D([], [], color="black", lw=3.4, alpha=0.45, label=forward),
        Line2D([], [], color="black", lw=1.5, ls="--", label=backward),
    ]


def _phasor_figure(
    groups: Sequence[tuple[str, int]], title: str
) -> tuple[Figure, list[list[Axes]], float]:
    """The figure of the per-order phasor panels, laid out here, in inches: the size of
    everything in it is known (two-line panel titles, angle labels of one size), so it needs
    no layout engine (constrained layout measured every text of every panel twice, and
    saving drew the figure twice for it).

    ``groups``: for the force and the moment, the title of its group of panels and how many
    panels it has (0: a low row for the note that says why).  Returns the figure, the axes
    of each group and where the top of the figure title goes (figure fraction).
    """
    from matplotlib.figure import Figure

    diameter, column, legend = 2.15, 2.8, 1.9  # a panel's circle, its column, the legend's
    side, end = _PHASOR_LABEL_ROOM
    panel_title, gap, group_title, note = 0.42, 0.1, 0.28, 0.55
    margin, title_line = 0.1, 0.2  # around the figure title, one line of it (12 pt)
    ncols = min(PHASOR_COLUMNS, max(max(n for _, n in groups), 1))
    box_width, box_height = diameter + 2.0 * side, diameter + 2.0 * end
    row = panel_title + box_height + gap
    width = column * ncols + legend
    top = 2.0 * margin + title_line * (_title_text(width, title).count("\n") + 1)
    heights = [group_title + math.ceil(n / ncols) * row if n else note for _, n in groups]
    height = top + sum(heights) + margin / 2.0
    left = margin / 2.0
    fig = Figure(figsize=(width, height))

    def rect(x: float, y: float, w: float, h: float) -> tuple[float, float, float, float]:
        """Figure fractions of a box ``w`` by ``h`` [in] whose top left is ``(x, y)`` [in]
        from the figure's top left."""
        return (x / width, 1.0 - (y + h) / height, w / width, h / height)

    axes_groups: list[list[Axes]] = []
    y = top
    for (label, n), h in zip(groups, heights, strict=True):
        if not n:
            axes_groups.append([fig.add_axes(rect(left, y, column * ncols, h))])
        else:
            # over the panels; from the left edge when one column is narrower than it
            fig.text(
                (left + column * ncols / 2.0) / width if ncols > 1 else left / width,
                1.0 - y / height,
                f"{label}: each order on its own scale",
                ha="center" if ncols > 1 else "left",
                va="top",
                fontsize=11,
            )
            panels = []
            for i in range(n):
                r, c = divmod(i, ncols)
                x0 = left + c * column + (column - box_width) / 2.0
                y0 = y + group_title + r * row + panel_title
                panels.append(fig.add_axes(rect(x0, y0, box_width, box_height)))
            axes_groups.append(panels)
        y += h
    fig.legend(
        handles=_direction_legend(),
        loc="center left",
        bbox_to_anchor=((left + column * ncols) / width, 1.0 - (top + height) / 2.0 / height),
        bbox_transform=fig.transFigure,
    )
    return fig, axes_groups, 1.0 - margin / height


def _plane_point(axes: Any, angle: Any, radius: Any) -> tuple[Any, Any]:
    """Data coordinates of the point at ``angle`` [rad] from +y, clockwise, and ``radius``:
    ``(angle, radius)`` on polar axes (set to zero at the top, clockwise), ``(x, y)`` =
    ``radius (sin angle, cos angle)`` on plain axes."""
    if axes.name == "polar":
        return angle, radius
    return radius * np.sin(angle), radius * np.cos(angle)


def _phasor_arrow(axes: Any, phasor: complex, colour: str, arrow: dict[str, Any]) -> None:
    """A phasor as an arrow from the centre (``phasor`` = y + i x: its angle from +y)."""
    axes.annotate(
        "",
        xy=_plane_point(axes, float(np.angle(phasor)), float(abs(phasor))),
        xytext=(0.0, 0.0),
        arrowprops={"color": colour, "shrinkA": 0, "shrinkB": 0, **arrow},
    )


def _phasor_frame(
    axes: Any,
    radius: float,
    rings: Sequence[float],
    *,
    labelled: int = 90,
    fontsize: float = 7.5,
    ring_fontsize: float = 7.0,
) -> None:
    """The polar frame of a phasor panel, drawn as lines and text on the axes (whose own
    axis is switched off): 0 deg (+y) at the top, angles clockwise (the direction of
    rotation); the outer circle at ``radius``, grid circles at ``rings`` with their values
    along 135 deg, spokes every 45 deg, and the angle labelled every ``labelled`` deg.

    On plain axes the data limits leave room for the angle labels inside the axes (the
    title goes above them) and keep the scale equal; on polar axes the radius is the
    axes' ``rmax``.  Drawn this way a panel costs a third of matplotlib's polar axes (no
    tick machinery, no polar transform of the frame), with the same look.
    """
    import matplotlib as mpl

    axes.set_axis_off()
    if axes.name == "polar":
        axes.set_theta_zero_location("N")
        axes.set_theta_direction(-1)
        axes.set_rlim(0.0, radius)
    else:
        # the circle as large as the axes' box [in] allows with room for the angle labels
        # beside it and above and below it (the box shrinks to fit, if it has to)
        side, end = _PHASOR_LABEL_ROOM
        bbox = axes.get_position()
        w, h = bbox.width * axes.figure.get_figwidth(), bbox.height * axes.figure.get_figheight()
        diameter = min(w - 2.0 * side, h - 2.0 * end)
        if diameter <= 0.0:
            diameter = 0.7 * min(w, h)
        per_inch = 2.0 * radius / diameter
        axes.set_xlim(-(diameter / 2.0 + side) * per_inch, (diameter / 2.0 + side) * per_inch)
        axes.set_ylim(-(diameter / 2.0 + end) * per_inch, (diameter / 2.0 + end) * per_inch)
        axes.set_aspect("equal", adjustable="box")
    grid = {
        "color": mpl.rcParams["grid.color"],
        "alpha": mpl.rcParams["grid.alpha"],
        "lw": mpl.rcParams["grid.linewidth"],
        "zorder": 1,
    }
    around = np.linspace(0.0, 2.0 * np.pi, 181)
    for ring in rings:
        axes.plot(*_plane_point(axes, around, np.full(around.shape, ring)), **grid)
    spokes = np.radians(np.arange(0.0, 360.0, 45.0))
    angle = np.repeat(spokes, 3)
    along = np.tile([0.0, radius, np.nan], spokes.size)
    axes.plot(*_plane_point(axes, angle, along), **grid)
    axes.plot(
        *_plane_point(axes, around, np.full(around.shape, radius)),
        color=mpl.rcParams["axes.edgecolor"],
        lw=mpl.rcParams["axes.linewidth"],
        zorder=1.5,
    )
    for degrees in range(0, 360, labelled):
        a = math.radians(degrees)
        axes.annotate(
            f"{degrees}°",
            xy=_plane_point(axes, a, radius),
            xytext=(3.0 * math.sin(a), 3.0 * math.cos(a)),
            textcoords="offset points",
            ha=_ha(a),
            va=_va(a),
            fontsize=fontsize,
        )
    a = math.radians(135.0)
    for ring in rings:
        axes.annotate(
            _format(ring),
            xy=_plane_point(axes, a, ring),
            xytext=(6.0, 0.0),
            textcoords="offset points",
            ha="left",
            va="center",
            fontsize=ring_fontsize,
        )


def _phasors_common(
    result: Result,
    ax: AxesArg,
    source: Source,
    orders: Iterable[int] | None,
    normalised: bool,
    title: str | None,
) -> Figure:
    """:func:`plot_phasors` with ``scale="common"``: every order of a quantity on one
    linear scale, force and moment side by side."""
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MaxNLocator

    with _styled():
        fig, axes_list, owned = _new_figure(ax, 2, (10.0, 5.4), polar=True, kind="phasors")
        legend_orders: dict[int, Line2D] = {}
        for axes, quantity in zip(axes_list, synthesis.QUANTITIES, strict=True):
            ks, fwd, bwd = synthesis.phasors_of(result, quantity, source)
            divisor, unit, _ = _scale(result, quantity, normalised)
            fwd, bwd = fwd / divisor, bwd / divisor
            keep = _pick_orders(ks, orders)
            name = "force" if quantity == "force" else "moment Σ Δz·F"
            axes.set_title(_axis_label(name, unit), pad=14 if axes.name == "polar" else 8)
            if np.isnan(fwd).all():
                axes.set_axis_off()
                _empty_note(axes, "not computed")
                continue
            size = np.concatenate([np.abs(fwd[keep]), np.abs(bwd[keep])])
            shown = _significant(size)
            largest = float(np.nanmax(size, initial=0.0))
            reach = largest if largest > 0 else 1.0
            rings = [r for r in MaxNLocator(nbins=4).tick_values(0.0, reach) if 0.0 < r <= reach]
            _phasor_frame(axes, 1.12 * reach, rings, labelled=45, fontsize=8.5, ring_fontsize=8)
            if not shown.any():
                _empty_note(axes, "all zero")
            n = int(keep.sum())
            for i, (k, pf, pb) in enumerate(zip(ks[keep], fwd[keep], bwd[keep], strict=True)):
                colour = _order_colour(int(k))
                for phasor, arrow, visible in (
                    (pf, FORWARD_ARROW, shown[i]),
                    (pb, BACKWARD_ARROW, shown[n + i]),
                ):
                    if not visible:
                        continue
                    _phasor_arrow(axes, phasor, colour, arrow)
                    legend_orders.setdefault(
                        int(k), Line2D([], [], color=colour, lw=2.0, label=f"order {int(k)}")
                    )
        handles = [legend_orders[k] for k in sorted(legend_orders)]
        handles += _direction_legend("forward (wide)", "backward (dashed)")
        fig.legend(handles=handles, loc="outside right center")
        return _finish(
            fig, owned, title, f"{_layout_name(result)}: phasors at θ = 0, {_source_label(source)}"
        )


def plot_crank_angle(
    result: Result,
    *,
    ax: AxesArg = None,
    source: Source = "free",
    orders: Iterable[int] | None = None,
    normalised: bool = False,
    samples: int = 721,
    title: str | None = None,
) -> Figure:
    """Force (y and x) and the pitch and yaw couples over one revolution.

    Thick black: the sum of the orders of the result; thin: each non-zero order.  The
    couples are :math:`M_x = -\\sum \\Delta z\\,F_y` (pitch) and
    :math:`M_y = \\sum \\Delta z\\,F_x` (yaw) about ``reference_z``.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    ax : sequence of 4 Axes, optional
        Axes for F_y, F_x, M_x and M_y; a new figure otherwise.
    source : {'free', 'reciprocating', 'residual'}
        Which force and moment (see :mod:`balance.views.signals`).
    orders : iterable of int, optional
        Orders to include; default all of the result.
    normalised : bool
        Per ``reference_force`` and ``reference_moment`` [1] instead of N and N m.
    samples : int
        Crank angles over the revolution.
    title : str, optional
        Figure title; by default the layout name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    theta = synthesis.crank_angle_grid(samples)
    with _styled():
        fig, axes_list, owned = _new_figure(ax, 4, (10.0, 7.0), nrows=2, kind="crank_angle")
        for row, quantity in enumerate(synthesis.QUANTITIES):
            ks, per_order, total, unit, shown = _order_signals(
                result, quantity, source, orders, normalised, theta
            )
            split = (
                synthesis.transverse_components
                if quantity == "force"
                else synthesis.couple_components
            )
            first, second = split(per_order)
            first_total, second_total = split(total)
            if quantity == "force":  # (y, x): vertical first
                first, second, first_total, second_total = second, first, second_total, first_total
                names = ("vertical force F_y", "horizontal force F_x")
            else:
                names = ("pitch couple M_x", "yaw couple M_y")
            components = zip((first, second), (first_total, second_total), names, strict=True)
            for col, (values, total_values, name) in enumerate(components):
                axes = axes_list[2 * row + col]
                _degree_axis(axes)
                axes.set_ylabel(_axis_label(name, unit))
                axes.set_title(name)
                if np.isnan(values).all():
                    _empty_note(axes, "not computed")
                    continue
                for k, line, visible in zip(ks, values, shown, strict=True):
                    if visible:
                        axes.plot(
                            theta,
                            line,
                            color=_order_colour(int(k)),
                            lw=1.1,
                            label=f"order {int(k)}",
                            zorder=2,
                        )
                axes.plot(theta, total_values, color=TOTAL_COLOUR, lw=2.6, label="total", zorder=1)
        _shared_legend(fig, axes_list)
        return _finish(
            fig, owned, title, f"{_layout_name(result)}: {_source_label(source)} over a revolution"
        )


def _shared_legend(fig: Figure, axes_list: Sequence[Axes]) -> None:
    """One legend for the figure with every distinct label of the axes, total last."""
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


def plot_locus(
    result: Result,
    *,
    ax: AxesArg = None,
    source: Source = "free",
    orders: Iterable[int] | None = None,
    normalised: bool = False,
    samples: int = 721,
    title: str | None = None,
) -> Figure:
    """Path of the force and moment vectors in the transverse plane over a revolution.

    Each order traces an ellipse (a circle if it only turns one way, a line if forward and
    backward are equal); the total (thick black) is their sum.  The open circle marks crank
    angle 0 and the arrow the direction of travel.  Seen from the front: +y up, +x right.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    ax : sequence of 2 Axes, optional
        Axes for the force and the moment; a new figure otherwise.
    source : {'free', 'reciprocating', 'residual'}
        Which force and moment (see :mod:`balance.views.signals`).
    orders : iterable of int, optional
        Orders to include; default all of the result.
    normalised : bool
        Per ``reference_force`` and ``reference_moment`` [1] instead of N and N m.
    samples : int
        Crank angles over the revolution.
    title : str, optional
        Figure title; by default the layout name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    theta = synthesis.crank_angle_grid(samples)
    with _styled():
        fig, axes_list, owned = _new_figure(ax, 2, (10.5, 5.2), kind="locus")
        for axes, quantity in zip(axes_list, synthesis.QUANTITIES, strict=True):
            ks, per_order, total, unit, shown = _order_signals(
                result, quantity, source, orders, normalised, theta
            )
            name = "force F" if quantity == "force" else "moment Σ Δz·F"
            axes.set_title(name)
            axes.set_xlabel(_axis_label(f"{name}, x", unit))
            axes.set_ylabel(_axis_label(f"{name}, y (up)", unit))
            axes.set_aspect("equal", adjustable="box")
            if np.isnan(per_order).all():
                _empty_note(axes, "not computed")
                continue
            curves = [
                (values, _order_colour(int(k)), 1.2, f"order {int(k)}")
                for k, values, visible in zip(ks, per_order, shown, strict=True)
                if visible
            ]
            curves.insert(0, (total, TOTAL_COLOUR, 2.6, "total"))
            reach = max(float(np.max(np.abs(c[0]), initial=0.0)) for c in curves)
            reach = 1.12 * reach if reach > 0 else 1.0
            for values, colour, width, label in curves:
                x, y = synthesis.transverse_components(values)
                axes.plot(x, y, color=colour, lw=width, label=label, zorder=2 if width < 2 else 1)
                axes.plot([x[0]], [y[0]], "o", color=colour, mfc="white", ms=6)
                _direction_arrow(axes, x, y, colour, reach)
            if not shown.any() and not np.any(np.abs(total) > 0):
                _empty_note(axes, "zero")
            axes.set_xlim(-reach, reach)
            axes.set_ylim(-reach, reach)
            axes.axhline(0.0, color="0.6", lw=0.8, zorder=0)
            axes.axvline(0.0, color="0.6", lw=0.8, zorder=0)
        _shared_legend(fig, axes_list)
        return _finish(
            fig,
            owned,
            title,
            f"{_layout_name(result)}: locus of the {_source_label(source)} force and moment",
        )


def _direction_arrow(
    axes: Axes, x: NDArray[np.float64], y: NDArray[np.float64], colour: str, reach: float
) -> None:
    """An arrowhead on a closed path, where it has moved far enough to show a direction."""
    step = np.hypot(np.diff(x), np.diff(y))
    if step.sum() < 1e-3 * reach:
        return
    start = max(1, len(x) // 24)
    for i in range(start, len(x) - 1):
        if np.hypot(x[i] - x[start - 1], y[i] - y[start - 1]) > 0.04 * reach:
            break
    else:
        return
    axes.annotate(
        "",
        xy=(float(x[i]), float(y[i])),
        xytext=(float(x[start - 1]), float(y[start - 1])),
        arrowprops={"arrowstyle": "-|>", "color": colour, "lw": 1.2, "mutation_scale": 14},
    )


def plot_spectrum(
    result: Result,
    *,
    ax: AxesArg = None,
    source: Source = "free",
    normalised: bool = False,
    log: bool = False,
    title: str | None = None,
) -> Figure:
    """Order spectra: the peak force and peak moment of each order, as bars.

    The peak of order k over a revolution is ``|P+| + |P-|``.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    ax : sequence of 2 Axes, optional
        Axes for the force and the moment; a new figure otherwise.
    source : {'free', 'reciprocating', 'residual'}
        Which force and moment (see :mod:`balance.views.signals`).
    normalised : bool
        Per ``reference_force`` and ``reference_moment`` [1] instead of N and N m.
    log : bool
        Logarithmic vertical axis (zero orders are then not drawn).
    title : str, optional
        Figure title; by default the layout name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    with _styled():
        fig, axes_list, owned = _new_figure(ax, 2, (10.0, 4.6), kind="spectrum")
        for axes, quantity in zip(axes_list, synthesis.QUANTITIES, strict=True):
            ks, _, _ = synthesis.phasors_of(result, quantity, source)
            divisor, unit, _ = _scale(result, quantity, normalised)
            peak = synthesis.peak_of(result, quantity, source) / divisor
            name = "peak force" if quantity == "force" else "peak moment"
            _order_bars(axes, ks, [(peak, "C0", None)], log=log)
            axes.set_title(name)
            axes.set_ylabel(_axis_label(name, unit))
        return _finish(
            fig, owned, title, f"{_layout_name(result)}: order spectrum, {_source_label(source)}"
        )


def _order_bars(
    axes: Axes,
    orders: NDArray[Any],
    series: Sequence[tuple[NDArray[np.float64], str, str | None]],
    *,
    log: bool = False,
    width: float = 0.8,
) -> None:
    """Grouped bars per order, each non-zero bar labelled with its value."""
    from matplotlib.container import BarContainer

    n = len(series)
    positions = np.arange(len(orders), dtype=np.float64)
    bar_width = width / n
    top = 0.0
    for i, (values, colour, label) in enumerate(series):
        shown = _significant(values)
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
            labels=[_format(float(h)) for h in heights[shown]],
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
        _empty_note(axes, "all zero")


def plot_roll(
    result: Result,
    *,
    ax: AxesArg = None,
    residual: bool = False,
    normalised: bool = False,
    samples: int = 721,
    title: str | None = None,
) -> Figure:
    """Roll torque on the block about the crank axis: over the crank angle and its spectrum.

    The torque is positive in the direction of rotation, ``Σ a_k cos(kθ + phase_k)``;
    with half orders (a four-stroke with gas forces) it is drawn over 720 deg.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    ax : sequence of 2 Axes, optional
        Axes for the torque and the spectrum; a new figure otherwise.
    residual : bool
        The roll with the proposed balance shafts.
    normalised : bool
        Per ``m_rec r^2 omega^2`` [1] instead of N m.
    samples : int
        Crank angles drawn.
    title : str, optional
        Figure title; by default the layout name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    ks, roll = synthesis.roll_of(result, residual=residual)
    unit = "N m"
    reference = float(result.reference_roll)
    if normalised and math.isfinite(reference) and reference > 0.0:
        roll = roll / reference
        unit = "per m_rec r² ω²"
    amplitude = np.abs(roll)
    span = synthesis.roll_span_deg(ks)
    theta = synthesis.crank_angle_grid(samples, span)
    with _styled():
        fig, (torque_axes, bar_axes), owned = _new_figure(ax, 2, (10.5, 4.6), kind="roll")
        per_order = _denoise(
            synthesis.roll_signal_per_order(roll, ks, theta), float(np.nansum(amplitude))
        )
        shown = _significant(amplitude)
        _degree_axis(torque_axes, span)
        label = _axis_label("roll torque", unit)
        torque_axes.set_ylabel(label)
        torque_axes.set_title("roll torque on the block (+ with rotation)")
        if np.isnan(amplitude).all():
            _empty_note(torque_axes, "not computed")
        else:
            for k, values, visible in zip(ks, per_order, shown, strict=True):
                if visible:
                    torque_axes.plot(
                        theta,
                        values,
                        color=_order_colour(float(k)),
                        lw=1.1,
                        label=f"order {k:g}",
                        zorder=2,
                    )
            torque_axes.plot(
                theta, per_order.sum(axis=0), color=TOTAL_COLOUR, lw=2.6, label="total", zorder=1
            )
        _order_bars(bar_axes, ks, [(amplitude, "C4", None)])
        bar_axes.set_title("amplitude per order")
        bar_axes.set_ylabel(_axis_label("amplitude", unit))
        _shared_legend(fig, [torque_axes])
        what = "roll with the proposed shafts" if residual else "roll"
        return _finish(fig, owned, title, f"{_layout_name(result)}: {what}")


def plot_balance(
    result: Result,
    *,
    ax: AxesArg = None,
    normalised: bool = False,
    samples: int = 721,
    title: str | None = None,
) -> Figure:
    """The free force, moment and roll before and after the proposed balancing.

    Top: the size of the force and moment vectors and the roll torque over a revolution
    (before dashed grey, after solid); bottom: the peak of each order before and after.
    "Before" is the free force and moment (reciprocating + rotating); "after" the residual
    with every proposed counterweight and balance-shaft mass.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute` with a proposal (``proposal=True``).
    ax : sequence of 6 Axes, optional
        Axes in two rows of three (force, moment, roll); a new figure otherwise.
    normalised : bool
        Force and moment per ``reference_force`` and ``reference_moment`` [1].
    samples : int
        Crank angles over the revolution.
    title : str, optional
        Figure title; by default the layout name and the proposal.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        If the result holds no proposal.
    """
    if not synthesis.has_proposal(result):
        raise InputError(
            "plot_balance: this result has no balancing proposal; analyse with the proposal "
            "enabled (Request(proposal=True), the default, with moments and roll)"
        )
    theta = synthesis.crank_angle_grid(samples)
    with _styled():
        fig, axes_list, owned = _new_figure(ax, 6, (13.0, 7.6), nrows=2, kind="balance")
        for col, quantity in enumerate(synthesis.QUANTITIES):
            divisor, unit, _ = _scale(result, quantity, normalised)
            ks, bf, bb = synthesis.phasors_of(result, quantity, "free")
            _, af, ab = synthesis.phasors_of(result, quantity, "residual")
            before_peak = synthesis.peak_of(result, quantity, "free")
            after_peak = synthesis.peak_of(result, quantity, "residual")
            reference = float(np.nansum(before_peak)) / divisor
            before = _denoise(synthesis.phasor_signal(bf, bb, ks, theta) / divisor, reference)
            after = _denoise(synthesis.phasor_signal(af, ab, ks, theta) / divisor, reference)
            name = "force |F|" if quantity == "force" else "moment |Σ Δz·F|"
            top = axes_list[col]
            _degree_axis(top)
            top.plot(
                theta,
                np.abs(before),
                color=BEFORE_COLOUR,
                ls="--",
                lw=1.8,
                label="before (free)",
                zorder=3,
            )
            top.plot(theta, np.abs(after), color=f"C{col}", lw=2.2, label="after (residual)")
            top.set_ylim(bottom=0.0)
            top.set_title(name)
            top.set_ylabel(_axis_label(name, unit))
            top.legend(loc="upper right")
            bottom = axes_list[3 + col]
            _order_bars(
                bottom,
                ks,
                [
                    (before_peak / divisor, BEFORE_COLOUR, "before"),
                    (after_peak / divisor, f"C{col}", "after"),
                ],
            )
            bottom.set_ylabel(_axis_label("peak", unit))
            bottom.legend(loc="upper right")
        rk, roll = synthesis.roll_of(result)
        _, residual_roll = synthesis.roll_of(result, residual=True)
        ra, qa = np.abs(roll), np.abs(residual_roll)
        span = synthesis.roll_span_deg(rk)
        roll_theta = synthesis.crank_angle_grid(samples, span)
        top = axes_list[2]
        _degree_axis(top, span)
        roll_reference = float(np.nansum(ra))
        top.plot(
            roll_theta,
            _denoise(synthesis.roll_signal(roll, rk, roll_theta), roll_reference),
            color=BEFORE_COLOUR,
            ls="--",
            lw=1.8,
            label="before",
            zorder=3,
        )
        top.plot(
            roll_theta,
            _denoise(synthesis.roll_signal(residual_roll, rk, roll_theta), roll_reference),
            color="C4",
            lw=2.2,
            label="after (with shafts)",
        )
        top.set_title("roll torque")
        top.set_ylabel("roll torque [N m]")
        top.legend(loc="upper right")
        _order_bars(axes_list[5], rk, [(ra, BEFORE_COLOUR, "before"), (qa, "C4", "after")])
        axes_list[5].set_ylabel("roll amplitude [N m]")
        axes_list[5].legend(loc="upper right")
        return _finish(fig, owned, title, f"{_layout_name(result)}: {proposal_summary(result)}")


def proposal_summary(result: Result) -> str:
    """One line describing the proposal of a result (strategy, orders, masses)."""
    part = result.part("proposal")
    if part is None:
        return "no balancing proposal"
    proposal = part.proposal
    n_cw = len(proposal.counterweights)
    n_shaft = len(proposal.shafts)
    parts = [
        f"{n_cw} counterweight{'s' if n_cw != 1 else ''}",
        f"{n_shaft} balance shaft{'s' if n_shaft != 1 else ''}",
    ]
    return (
        f"balancing {proposal.strategy}, orders "
        f"{','.join(map(str, proposal.orders))}: {' and '.join(parts)}"
    )


def _no_gas(result: Result, ax: AxesArg, kind: str, title: str | None) -> Figure:
    """A figure that says there is no gas section (for a result without gas forces)."""
    with _styled():
        fig, (axes,), owned = _new_figure(ax, 1, (8.0, 3.0), kind=kind)
        axes.set_axis_off()
        axes.text(
            0.5,
            0.5,
            "no gas forces: add a gas: section (pressure trace or model) to the layout",
            transform=axes.transAxes,
            ha="center",
            va="center",
            color="0.4",
        )
        return _finish(fig, owned, title, f"{_layout_name(result)}: {kind}")


def plot_torque(result: Result, *, ax: AxesArg = None, title: str | None = None) -> Figure:
    """Torque of each cylinder and engine torque over the working cycle, with the mean.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute` for an engine with a ``gas:`` section;
        without one the figure only says so.
    ax : Axes, optional
        Axes to draw into; a new figure otherwise.
    title : str, optional
        Figure title; by default the layout name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    torque = result.part("torque")
    if torque is None:
        return _no_gas(result, ax, "torque", title)
    theta = np.asarray(torque.crank_angle)
    span = float(theta[1] - theta[0]) * theta.size
    per = np.asarray(torque.cylinder_torque)
    total = np.asarray(torque.engine_torque)
    closed = np.append(theta, span)
    with _styled():
        fig, (axes,), owned = _new_figure(ax, 1, (10.0, 4.8), kind="torque")
        for i, values in enumerate(per):
            axes.plot(
                closed,
                np.append(values, values[0]),
                color=f"C{i % 10}",
                lw=0.9,
                alpha=0.8,
                label=f"cylinder {i + 1}",
            )
        axes.plot(closed, np.append(total, total[0]), color=TOTAL_COLOUR, lw=2.2, label="engine")
        mean = float(torque.mean)
        axes.axhline(mean, color=TOTAL_COLOUR, ls="--", lw=1.0, label=f"mean {mean:.4g} N m")
        _degree_axis(axes, span)
        axes.set_ylabel("torque [N m]")
        axes.set_title("torque on the crankshaft (+ with rotation), gas and inertia")
        axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
        return _finish(fig, owned, title, f"{_layout_name(result)}: torque over the cycle")


FORCE_NAMES = (
    ("piston_force", "P (along the bore)"),
    ("side_thrust", "N (side thrust)"),
    ("rod_force", "S (rod)"),
    ("tangential_force", "T (tangential)"),
    ("radial_force", "K (radial)"),
)


def plot_forces(
    result: Result, *, cylinder: int = 1, ax: AxesArg = None, title: str | None = None
) -> Figure:
    """Forces on one cylinder's crank train over the cycle: P, N, S, T and K.

    These are the force diagrams of the dynamics of the crank mechanism in Kolchin and
    Demidov, *Design of Automotive Engines*, Mir 1984.

    The cycle angle is counted from the cylinder's firing TDC.  :math:`P` is split into the
    gas and the inertia force in the first panel.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute` with gas forces (a note otherwise).
    cylinder : int
        Cylinder number (1-based).
    ax : sequence of 2 Axes, optional
        Axes for P (with its parts) and for N, S, T, K; a new figure otherwise.
    title : str, optional
        Figure title; by default the layout name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    torque = result.part("torque")
    if torque is None:
        return _no_gas(result, ax, "forces", title)
    n_cylinders = result.engine.n_cylinders
    if not 1 <= cylinder <= n_cylinders:
        raise InputError(f"cylinder {cylinder}: expected one of 1 to {n_cylinders}")
    i = cylinder - 1
    theta = np.asarray(torque.crank_angle)
    span = float(theta[1] - theta[0]) * theta.size
    tdc = float(torque.firing_tdc[i])
    order = np.argsort(np.mod(theta - tdc, span))
    alpha = np.mod(theta - tdc, span)[order]
    with _styled():
        fig, (top, bottom), owned = _new_figure(ax, 2, (10.0, 7.0), nrows=2, ncols=1, kind="forces")
        for name, label, colour in (
            ("gas_force", "gas (p - p0) A", "C3"),
            ("inertia_force", "inertia", "C0"),
            ("piston_force", "P = gas + inertia", TOTAL_COLOUR),
        ):
            values = np.asarray(getattr(torque, name)[i])[order] / 1e3
            top.plot(
                alpha, values, color=colour, lw=2.0 if name == "piston_force" else 1.1, label=label
            )
        top.set_ylabel("force [kN]")
        top.set_title("force on the piston pin along the bore (+ towards the crank)")
        top.legend(loc="upper right")
        for (name, label), colour in zip(FORCE_NAMES[1:], ("C2", "C1", "C4", "C5"), strict=True):
            values = np.asarray(getattr(torque, name)[i])[order] / 1e3
            bottom.plot(alpha, values, color=colour, label=label)
        bottom.set_ylabel("force [kN]")
        bottom.set_title("side thrust, rod, tangential and radial force")
        bottom.legend(loc="upper right", ncols=2)
        for axes in (top, bottom):
            _degree_axis(axes, span)
            axes.set_xlabel("crank angle from firing TDC [deg]")
        return _finish(fig, owned, title, f"{_layout_name(result)}: forces on cylinder {cylinder}")


#: Every figure kind and the function that draws it.
PLOT_KINDS: dict[str, Callable[..., Figure]] = {
    "crank_star": plot_crank_star,
    "phasors": plot_phasors,
    "crank_angle": plot_crank_angle,
    "locus": plot_locus,
    "spectrum": plot_spectrum,
    "roll": plot_roll,
    "balance": plot_balance,
    "torque": plot_torque,
    "forces": plot_forces,
}

#: Plot kinds that need gas forces (a ``gas:`` section); asked for without, they say so.
GAS_KINDS = ("torque", "forces")


def section_kinds() -> dict[str, tuple[str, Callable[..., Figure]]]:
    """The figure kinds the sections draw (:mod:`balance.views.sections`): each kind with
    its section's name and function."""
    from balance.core.sections import names
    from balance.views.sections import VIEWS, view

    out: dict[str, tuple[str, Callable[..., Figure]]] = {}
    for name in names():
        if name in VIEWS:
            for kind, draw in getattr(view(name), "PLOTS", {}).items():
                out[kind] = (name, draw)
    return out


def plot_kind(kind: str) -> Callable[..., Figure]:
    """The function that draws figure ``kind`` (:data:`PLOT_KINDS` or a section's)."""
    if kind in PLOT_KINDS:
        return PLOT_KINDS[kind]
    sections = section_kinds()
    if kind not in sections:
        known = [*PLOT_KINDS, *sections]
        raise InputError(f"plot kind {kind!r}: expected one of {', '.join(known)}")
    return sections[kind][1]


def all_kinds() -> list[str]:
    """Every figure kind: :data:`PLOT_KINDS`, then the sections'."""
    return [*PLOT_KINDS, *section_kinds()]


def _metadata(fmt: str) -> dict[str, Any]:
    """File metadata without dates, so that the same result gives the same bytes."""
    if fmt == "svg":
        return {"Date": None}
    if fmt == "pdf":
        return {"CreationDate": None, "ModDate": None}
    return {}


def _agg_canvas(fig: Figure) -> None:
    """Give a figure made without pyplot (whose canvas cannot draw) an Agg canvas, the
    documented way to draw a figure without pyplot.  The layout engine then measures text
    with the canvas's renderer, which a PNG is written with: the text metrics measured for
    the layout are not measured again (matplotlib caches them per renderer)."""
    from matplotlib.backend_bases import FigureCanvasBase

    if type(fig.canvas) is FigureCanvasBase:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)


def figure_bytes(fig: Figure, fmt: str = "png") -> bytes:
    """A figure as the bytes of a ``png``, ``svg`` or ``pdf`` file (under :data:`STYLE`)."""
    import io

    import matplotlib as mpl

    if fmt not in FORMATS:
        raise InputError(f"format {fmt!r}: expected one of {', '.join(FORMATS)}")
    buffer = io.BytesIO()
    with _styled():
        engine = fig.get_layout_engine()
        if engine is None:
            fig.savefig(buffer, format=fmt, metadata=_metadata(fmt))
            return buffer.getvalue()
        # With a layout engine, savefig draws the figure twice: once (without output) to
        # lay it out, once to write it.  Lay it out here instead (the engine measures the
        # text with an Agg renderer at the figure's dpi, as savefig does for a PNG), then
        # write it in one draw without an engine, and give the figure its engine back.
        # (None, not "none": savefig lays out a figure whose engine is "none" too.)
        _agg_canvas(fig)
        engine.execute(fig)
        with mpl.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)  # no rc setting turns None into an engine here
        try:
            fig.savefig(buffer, format=fmt, metadata=_metadata(fmt))
        finally:
            fig.set_layout_engine(engine)
    return buffer.getvalue()


def applicable_kinds(result: Result) -> list[str]:
    """The figure kinds that have something to draw for ``result``, in order: those of
    :data:`PLOT_KINDS` (``balance`` with a proposal, the :data:`GAS_KINDS` with gas forces,
    the others always), then those of every section the result holds."""
    own = [
        k
        for k in PLOT_KINDS
        if (k != "balance" or synthesis.has_proposal(result))
        and (k not in GAS_KINDS or result.part("torque") is not None)
    ]
    return own + [k for k, (name, _) in section_kinds().items() if name in result.parts]


def save_plots(
    result: Result,
    directory: str | os.PathLike[str],
    kinds: Iterable[str] | None = None,
    fmt: str = "png",
    *,
    prefix: str = "",
    force: bool = False,
) -> list[Path]:
    """Draw figures of a result and write them as ``<directory>/<prefix><kind>.<fmt>``.

    Each file is written to a temporary file in the same directory and renamed into place,
    so an interrupted run leaves no partial file.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    directory : path
        Where to write; created if missing.
    kinds : iterable of str, optional
        Kinds of :data:`PLOT_KINDS`; default all that apply (:func:`applicable_kinds`).
    fmt : {'png', 'svg', 'pdf'}
        File format.
    prefix : str
        Prefix of every file name (for example the layout's name and a dash).
    force : bool
        Replace existing files.

    Returns
    -------
    list of Path
        The files written, in the order of ``kinds``.

    Raises
    ------
    InputError
        For an unknown kind or format, a file that exists without ``force``, or ``balance``
        asked for without a proposal.
    """
    from balance.io.atomic import check_target, write_atomic

    if fmt not in FORMATS:
        raise InputError(f"format {fmt!r}: expected one of {', '.join(FORMATS)}")
    if kinds is None:
        chosen = applicable_kinds(result)
    else:
        chosen = list(kinds)
        for kind in chosen:
            plot_kind(kind)  # refuses an unknown kind, naming the known ones
    target_dir = Path(directory)
    target_dir.mkdir(parents=True, exist_ok=True)
    targets = [target_dir / f"{prefix}{kind}.{fmt}" for kind in chosen]
    for target in targets:  # fail before any figure is drawn
        check_target(target, force)
    for kind, target in zip(chosen, targets, strict=True):
        data = figure_bytes(plot_kind(kind)(result), fmt)
        write_atomic(target, data, force)
    return targets
