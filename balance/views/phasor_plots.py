"""The phasor figure (kind ``phasors``): polar diagrams of the force and moment phasors at
crank angle 0, forward and backward, one panel per order on its own scale or all orders on
one (:func:`plot_phasors`).

With several crankshafts each order's panel also draws how the shafts' phasors add up to
the engine's, head to tail (the parts a section's ``phasor_layers`` gives,
:mod:`balance.views.sections`; this module names no section).

The polar frame of a panel is drawn as lines and text (:func:`_phasor_frame`), on plain
axes or on polar ones given, alike.  The helpers every figure shares are in
:mod:`balance.views.figures`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from balance.views import signals
from balance.views.figures import (
    AxesArg,
    axis_label,
    empty_note,
    finish,
    format_value,
    h_align,
    layout_heading,
    new_figure,
    order_colour,
    pick_orders,
    scale_of,
    significant_mask,
    source_label,
    styled,
    title_text,
    v_align,
)
from balance.views.signals import Quantity, Source

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from balance.core.phasors import Phasors
    from balance.core.result import Result

__all__ = [
    "BACKWARD_ARROW",
    "FORWARD_ARROW",
    "PART_BACKWARD_ARROW",
    "PART_COLOURS",
    "PART_FORWARD_ARROW",
    "PHASOR_COLUMNS",
    "phasor_panels",
    "plot_phasors",
]

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
    (:func:`balance.views.figures.significant_mask`), the engine's or, where a section splits
    them into parts (several crankshafts), a part's; an empty list draws one panel that
    says why (zero, not computed).

    Parameters
    ----------
    result : Result
        The analysis.
    source : {'reciprocating', 'free', 'residual'}
        Which phasors (:mod:`balance.views.signals`).
    orders : iterable of int, optional
        The orders to consider; default every order of the result.

    Returns
    -------
    list of (str, list of int)
        ``("force", orders)`` and ``("moment", orders)``.
    """
    return [(p.quantity, p.shown) for p in _panel_phasors(result, source, orders)]


class _PanelPhasors(NamedTuple):
    """A quantity's phasors and its panels in the per-order phasor figure."""

    quantity: Quantity
    orders: NDArray[np.intp]
    forward: signals.ComplexArray
    backward: signals.ComplexArray
    #: the orders with a panel of their own (:func:`phasor_panels`)
    shown: list[int]
    #: what the one panel of a quantity without any says: not computed, or all zero
    note: str
    #: the parts whose phasors add up to these (:func:`_layers`): the legend's heading, their
    #: names and forward and backward phasors, shape (parts, orders); none for one part
    heading: str = ""
    parts: tuple[str, ...] = ()
    parts_forward: signals.ComplexArray | None = None
    parts_backward: signals.ComplexArray | None = None


def _panel_phasors(
    result: Result, source: Source, orders: Iterable[int] | None
) -> list[_PanelPhasors]:
    """For the force and the moment: its phasors (:func:`balance.views.signals.phasors_of`),
    the orders of its panels and the note of a panel without any; the phasors are computed
    once for both :func:`phasor_panels` and :func:`plot_phasors`."""
    out = []
    heading, layers = _layers(result, source)
    for quantity in signals.QUANTITIES:
        ks, fwd, bwd = signals.phasors_of(result, quantity, source)
        keep = pick_orders(ks, orders)
        size = signals.magnitude_of(result, quantity, source)[keep]  # (orders, 2)
        names: tuple[str, ...] = ()
        parts_fwd = parts_bwd = None
        if layers and all(bundle.has(quantity) for _, bundle in layers):
            names = tuple(name for name, _ in layers)
            parts_fwd = np.stack([np.asarray(b.pair(quantity)[0]) for _, b in layers])
            parts_bwd = np.stack([np.asarray(b.pair(quantity)[1]) for _, b in layers])
            # an order whose parts are not zero has a panel, though they cancel
            size = np.concatenate([size, np.abs(parts_fwd).T[keep], np.abs(parts_bwd).T[keep]], 1)
        shown: list[int] = []
        if not np.isnan(size).all():  # computed
            significant = np.asarray(np.asarray(significant_mask(size)).any(axis=1), dtype=bool)
            shown = [int(k) for k, s in zip(ks[keep], significant, strict=True) if s]
        note = "not computed" if np.isnan(fwd).all() else "all zero"
        out.append(
            _PanelPhasors(quantity, ks, fwd, bwd, shown, note, heading, names, parts_fwd, parts_bwd)
        )
    return out


def _layers(result: Result, source: Source) -> tuple[str, list[tuple[str, Phasors]]]:
    """The parts whose phasors add up to the engine's, from every section of the result
    whose views module has ``phasor_layers(result, source)`` (:mod:`balance.views.sections`;
    several crankshafts, docs/several-crankshafts.md): the legend's heading and each part's
    name and :class:`~balance.core.phasors.Phasors`; no parts when no section splits the
    engine's phasors."""
    from balance.views.sections import views_of

    heading, layers = "", []
    for _, module in views_of(result):
        split = getattr(module, "phasor_layers", None)
        got = None if split is None else split(result, source)
        if got is not None:
            heading, parts = got
            layers.extend(parts)
    return heading, layers


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

    Where a section of the result splits the engine's phasors into parts that add up to
    them (its views module's ``phasor_layers``, :mod:`balance.views.sections`: each
    crankshaft of an engine with several), each order's panel draws the parts' forward
    phasors head to tail from the centre, each in its colour (:data:`PART_COLOURS`) and
    named in the legend, ending at the engine's forward phasor, and their backward ones
    alike (dashed); an order whose parts are not zero has a panel though they cancel, and
    the panel's scale takes in the chains.  Per order only (``scale="common"`` draws the
    engine's alone).

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
    chains: list[tuple[tuple[str, ...], Any, Any]] = []
    heading = ""
    for panel in _panel_phasors(result, source, orders):
        heading = panel.heading
        quantity, ks, fwd, bwd, ks_shown, note = panel[:6]
        divisor, unit, _ = scale_of(result, quantity, normalised)
        name = "force" if quantity == "force" else "moment Σ Δz·F"
        groups.append((ks, fwd / divisor, bwd / divisor, axis_label(name, unit), ks_shown, note))
        if panel.parts_forward is None or panel.parts_backward is None:
            chains.append(((), None, None))
        else:
            chains.append(
                (panel.parts, panel.parts_forward / divisor, panel.parts_backward / divisor)
            )
    colours = _part_colours(chains)
    default_title = f"{layout_heading(result)}: phasors at θ\u00a0=\u00a00, {source_label(source)}"
    with styled():
        if ax is None:
            fig, axes_list, title_y = _phasor_figure(
                [(label, len(ks_shown)) for _, _, _, label, ks_shown, _ in groups],
                default_title if title is None else title,
                _part_legend(heading, colours) if colours else [],
            )
            owned = True
        else:
            counts = [max(len(ks_shown), 1) for _, _, _, _, ks_shown, _ in groups]
            fig, given, owned = new_figure(ax, sum(counts), (1.0, 1.0), polar=True, kind="phasors")
            axes_list, start = [], 0
            for n in counts:
                axes_list.append(given[start : start + n])
                start += n
            title_y = None
        for axes_group, (ks, fwd, bwd, label, ks_shown, note), (parts, parts_fwd, parts_bwd) in zip(
            axes_list, groups, chains, strict=True
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
            shown = {k: (i, fwd[i], bwd[i]) for i, k in enumerate(ks) if int(k) in ks_shown}
            for axes, k in zip(axes_group, ks_shown, strict=True):
                i, pf, pb = shown[k]
                largest = max(abs(pf), abs(pb))
                if parts_fwd is not None and parts_bwd is not None:
                    # the chains of the parts' phasors, head to tail, in the panel too
                    heads = np.concatenate([np.cumsum(parts_fwd[:, i]), np.cumsum(parts_bwd[:, i])])
                    largest = max(largest, float(np.abs(heads).max()))
                _phasor_frame(axes, 1.12 * largest, [largest / 2.0, largest])
                if parts_fwd is not None and parts_bwd is not None:
                    _part_chains(axes, parts, parts_fwd[:, i], parts_bwd[:, i], colours)
                colour = order_colour(k)
                significant = significant_mask(np.array([abs(pf), abs(pb)]))
                for phasor, arrow, visible in (
                    (pf, FORWARD_ARROW, significant[0]),
                    (pb, BACKWARD_ARROW, significant[1]),
                ):
                    if visible:
                        _phasor_arrow(axes, phasor, colour, arrow)
                axes.set_title(
                    f"order {k}\nforward {format_value(abs(pf))}, backward {format_value(abs(pb))}",
                    fontsize=9,
                    color=colour,
                    pad=8 if axes.name == "polar" else 5,
                )
        return finish(fig, owned, title, default_title, y=title_y)


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
    groups: Sequence[tuple[str, int]], title: str, more: Sequence[Any] = ()
) -> tuple[Figure, list[list[Axes]], float]:
    """The figure of the per-order phasor panels, laid out here, in inches: the size of
    everything in it is known (two-line panel titles, angle labels of one size), so it needs
    no layout engine (constrained layout measured every text of every panel twice, and
    saving drew the figure twice for it).

    ``groups``: for the force and the moment, the title of its group of panels and how many
    panels it has (0: a low row for the note that says why).  Returns the figure, the axes
    of each group and where the top of the figure title goes (figure fraction).  ``more``:
    legend entries after those of the arrows (the parts', :func:`_part_legend`).
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
    top = 2.0 * margin + title_line * (title_text(width, title).count("\n") + 1)
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
        handles=[*_direction_legend(), *more],
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


def _phasor_arrow(
    axes: Any,
    phasor: complex,
    colour: str,
    arrow: dict[str, Any],
    start: complex = 0j,
    label: str | None = None,
) -> None:
    """A phasor as an arrow (``phasor`` = y + i x: its angle from +y), from the centre or
    from the point ``start``, the artist labelled ``label`` (not a legend entry)."""
    end, tail = phasor, (0.0, 0.0)
    if start != 0:
        end, tail = start + phasor, _plane_point(axes, float(np.angle(start)), abs(start))
    axes.annotate(
        "",
        xy=_plane_point(axes, float(np.angle(end)), float(abs(end))),
        xytext=tail,
        arrowprops={"color": colour, "shrinkA": 0, "shrinkB": 0, **arrow},
        **({} if label is None else {"label": label}),
    )


#: Colours of the parts whose phasors add up to the engine's (several crankshafts), apart
#: from the colours of the orders (tab10): Dark2.
PART_COLOURS = ("#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d")

#: A part's phasor arrows, head to tail: thinner than the engine's, on top of them.
PART_FORWARD_ARROW: dict[str, Any] = {"arrowstyle": "-|>", "lw": 1.6, "mutation_scale": 12}
PART_BACKWARD_ARROW: dict[str, Any] = {
    "arrowstyle": "->",
    "lw": 1.1,
    "linestyle": "--",
    "mutation_scale": 10,
}


def _part_colours(chains: Sequence[tuple[tuple[str, ...], Any, Any]]) -> dict[str, str]:
    """The colour of each part (:data:`PART_COLOURS`, in turn); none when no part has a
    phasor not zero (nothing of theirs is drawn)."""
    names: tuple[str, ...] = ()
    drawn = False
    for parts, forward, backward in chains:
        if parts:
            names = parts
            drawn = drawn or bool(np.nan_to_num(np.abs(forward)).any())
            drawn = drawn or bool(np.nan_to_num(np.abs(backward)).any())
    if not drawn:
        return {}
    return {name: PART_COLOURS[i % len(PART_COLOURS)] for i, name in enumerate(names)}


def _part_legend(heading: str, colours: dict[str, str]) -> list[Any]:
    """Legend entries of the parts: a heading, then each part's name in its colour."""
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color="none", label=heading)]
    handles += [Line2D([], [], color=c, lw=2.0, label=name) for name, c in colours.items()]
    return handles


def _part_chains(
    axes: Any,
    parts: Sequence[str],
    forward: Any,
    backward: Any,
    colours: dict[str, str],
) -> None:
    """The parts' forward phasors of one order head to tail from the centre, each in its
    colour and labelled ``"NAME forward"``, ending at their sum, the engine's forward
    phasor; the backward ones alike (dashed, ``"NAME backward"``).  A part's phasor that is
    zero beside the others (:func:`balance.views.figures.significant_mask`) is not drawn."""
    for phasors, arrow, direction in (
        (forward, PART_FORWARD_ARROW, "forward"),
        (backward, PART_BACKWARD_ARROW, "backward"),
    ):
        visible = significant_mask(np.abs(phasors))
        start = 0j
        for name, phasor, shown in zip(parts, phasors, visible, strict=True):
            if shown:
                arrow_of = {**arrow, "zorder": 4}
                _phasor_arrow(
                    axes, complex(phasor), colours[name], arrow_of, start, f"{name} {direction}"
                )
            start = start + complex(phasor)


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
            ha=h_align(a),
            va=v_align(a),
            fontsize=fontsize,
        )
    a = math.radians(135.0)
    for ring in rings:
        axes.annotate(
            format_value(ring),
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

    with styled():
        fig, axes_list, owned = new_figure(ax, 2, (10.0, 5.4), polar=True, kind="phasors")
        legend_orders: dict[int, Line2D] = {}
        for axes, quantity in zip(axes_list, signals.QUANTITIES, strict=True):
            ks, fwd, bwd = signals.phasors_of(result, quantity, source)
            divisor, unit, _ = scale_of(result, quantity, normalised)
            fwd, bwd = fwd / divisor, bwd / divisor
            keep = pick_orders(ks, orders)
            name = "force" if quantity == "force" else "moment Σ Δz·F"
            axes.set_title(axis_label(name, unit), pad=14 if axes.name == "polar" else 8)
            if np.isnan(fwd).all():
                axes.set_axis_off()
                empty_note(axes, "not computed")
                continue
            size = np.concatenate([np.abs(fwd[keep]), np.abs(bwd[keep])])
            shown = significant_mask(size)
            largest = float(np.nanmax(size, initial=0.0))
            reach = largest if largest > 0 else 1.0
            rings = [r for r in MaxNLocator(nbins=4).tick_values(0.0, reach) if 0.0 < r <= reach]
            _phasor_frame(axes, 1.12 * reach, rings, labelled=45, fontsize=8.5, ring_fontsize=8)
            if not shown.any():
                empty_note(axes, "all zero")
            n = int(keep.sum())
            for i, (k, pf, pb) in enumerate(zip(ks[keep], fwd[keep], bwd[keep], strict=True)):
                colour = order_colour(int(k))
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
        return finish(
            fig, owned, title, f"{layout_heading(result)}: phasors at θ = 0, {source_label(source)}"
        )
