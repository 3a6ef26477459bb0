r"""Figures of a result: compute first (:mod:`balance.views.signals`), then draw.

Every figure is a function ``plot_<kind>(result, *, ax=None, ...)`` that takes the
:class:`~balance.core.result.Result` of :func:`balance.core.analysis.compute` (its complex
phasors and stored references, as they are) and returns a
:class:`matplotlib.figure.Figure`.  The figures are
built object-oriented (no :mod:`matplotlib.pyplot`, no global state): they work headless,
and matplotlib is imported only when a figure is drawn.  Each function draws under a fixed
style (:data:`STYLE`, applied with :func:`matplotlib.rc_context`) so that figures look the
same whatever the user's ``matplotlibrc``; what every figure is drawn with is in
:mod:`balance.views.figures`.

``ax`` may be given to draw into existing axes: one :class:`~matplotlib.axes.Axes` for
single-panel kinds, a sequence of as many axes as the kind has panels otherwise (polar axes
for ``phasors``).  The figure title (layout name) is only set on a figure the function
created, or when ``title`` is given.

The kinds of every analysis (:data:`PLOT_KINDS`):

``crank_star``
    Throws and banks seen from the front (+y up, +x right, crank turning clockwise).
``phasors``
    Polar diagrams of the force and moment phasors, one panel per order on its own scale,
    forward and backward (:mod:`balance.views.phasor_plots`).
``crank_angle``
    Force (y and x) and pitch/yaw couples over one revolution, total and per order.
``locus``
    The path of the force and moment vectors in the transverse plane, per order and total.
``spectrum``
    Peak force and moment per order, as bars.
``roll``
    Roll torque over a revolution (or a cycle with half orders) and its spectrum.

Each section of an analysis draws its own kinds, in its views module's ``PLOTS``
(:mod:`balance.views.sections`): ``torque`` and ``forces`` (:mod:`balance.views.torque`),
``balance`` (:mod:`balance.views.proposal`), ``mounts`` and the bearing loads'.
:func:`plot_kind` finds any kind, :func:`all_kinds` lists them, :func:`applicable_kinds`
gives those a result has something to draw for.

The force and moment drawn are by default the *free* ones: reciprocating inertia plus the
centrifugal force of the rotating masses (``source="free"``; see
:mod:`balance.views.signals`).  Moments are :math:`\sum (z_i - z_{ref}) F_i`, drawn along the
force (docs/conventions.md); ``crank_angle`` shows them as the physical pitch and yaw
couples.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from balance.core.errors import InputError
from balance.views import signals
from balance.views.figures import (
    STYLE,
    TOTAL_COLOUR,
    AxesArg,
    axis_label,
    degree_axis,
    denoise,
    empty_note,
    finish,
    layout_heading,
    new_figure,
    order_bars,
    order_colour,
    order_signals,
    scale_of,
    shared_legend,
    significant_mask,
    source_label,
    styled,
)
from balance.views.phasor_plots import PHASOR_COLUMNS, phasor_panels, plot_phasors
from balance.views.signals import Source

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from balance.core.result import Result

__all__ = [
    "FORMATS",
    "PHASOR_COLUMNS",
    "PLOT_KINDS",
    "STYLE",
    "all_kinds",
    "applicable_kinds",
    "figure_bytes",
    "phasor_panels",
    "plot_crank_angle",
    "plot_crank_star",
    "plot_kind",
    "plot_locus",
    "plot_phasors",
    "plot_roll",
    "plot_spectrum",
    "save_plots",
    "section_kinds",
]

#: File formats :func:`save_plots` writes.
FORMATS = ("png", "svg", "pdf")


# --------------------------------------------------------------------------- kinds


def plot_crank_star(result: Result, *, ax: AxesArg = None, title: str | None = None) -> Figure:
    """Crank star: throws and banks seen along the crank from the front.

    The view is along -z: +y is up, +x to the right, and the crank turns clockwise (from +y
    towards +x).  Each throw is drawn as a spoke at its angle (crank angle 0) with the
    cylinders on it; each bank (bore axis) as a dashed line at its angle.  Labels of
    throws (or banks) too close to sit beside each other are spread apart along their
    ring, each joined to its spoke by a thin line (:func:`_spread_angles`).

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    title : str, optional
        Figure title; by default the layout name and speed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if result.engine.geared:  # several crankshafts, each drawn where it sits
        from balance.views.axes_plots import plot_axes_star

        return plot_axes_star(result, ax=ax, title=title)
    with styled():
        fig, (axes,), owned = new_figure(ax, 1, (6.0, 6.2), kind="crank_star")
        engine = result.engine
        throws = np.mod(np.degrees(np.asarray(engine.throw, dtype=np.float64)), 360.0)
        banks = np.mod(np.degrees(np.asarray(engine.bank, dtype=np.float64)), 360.0)
        cylinders = np.arange(1, engine.n_cylinders + 1)
        circle = np.radians(np.linspace(0.0, 360.0, 361))
        axes.plot(np.sin(circle), np.cos(circle), color="0.75", lw=1.0, zorder=1)
        axes.plot([0.0], [0.0], "o", color="black", ms=6, zorder=4)

        throw_keys = np.round(throws, 6) % 360.0
        spokes = [
            (math.radians(float(t)), cylinders[throw_keys == t], float(t))
            for t in np.unique(throw_keys)
        ]
        throw_texts = [f"{_cylinder_list(on)}\n({t:g}°)" for _, on, t in spokes]
        throw_boxes = [_text_box(text, 0.092, 0.175) for text in throw_texts]
        throw_at = _spread_angles([a for a, _, _ in spokes], throw_boxes, _THROW_RING)
        outer = _THROW_RING
        for (a, _, _), text, box, shown in zip(
            spokes, throw_texts, throw_boxes, throw_at, strict=True
        ):
            tip = (math.sin(a), math.cos(a))
            axes.plot([0.0, tip[0]], [0.0, tip[1]], color="C0", lw=3.0, zorder=3)
            axes.plot([tip[0]], [tip[1]], "o", color="C0", ms=9, zorder=3)
            reach = _place_label(axes, a, shown, box, _THROW_RING, 1.08, text, "C0", 10, "bold")
            outer = max(outer, reach)

        bank_keys = np.round(banks, 6) % 360.0
        bank_ring = max(1.7, outer + 0.1)
        several = len(np.unique(bank_keys)) > 1
        lines = [
            (math.radians(float(b)), cylinders[bank_keys == b], float(b))
            for b in np.unique(bank_keys)
        ]
        bank_texts = [
            f"bank {_signed_angle(b)}\ncyl. {_cylinder_list(on)}"
            if several
            else f"bore axis {_signed_angle(b)}"
            for _, on, b in lines
        ]
        bank_boxes = [_text_box(text, 0.078, 0.16) for text in bank_texts]
        bank_at = _spread_angles([a for a, _, _ in lines], bank_boxes, bank_ring)
        limit = 2.6
        for (a, _, _), text, box, shown in zip(lines, bank_texts, bank_boxes, bank_at, strict=True):
            end = bank_ring - 0.1
            axes.plot(
                [0.0, end * math.sin(a)],
                [0.0, end * math.cos(a)],
                ls="--",
                color="C3",
                lw=1.3,
                zorder=2,
            )
            reach = _place_label(axes, a, shown, box, bank_ring, end, text, "C3", 9, "normal")
            limit = max(limit, reach + 0.1)

        # direction of rotation: from +y towards +x, i.e. clockwise in this view; drawn in
        # the lower left corner, where no bank label goes unless a bank points there
        centre = (-limit + 0.45, -limit + 0.45)
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
        axes.set_xlim(-limit, limit)
        axes.set_ylim(-limit, limit)
        axes.set_aspect("equal")
        axes.grid(False)
        axes.set_xticks([-1.0, 0.0, 1.0])
        axes.set_yticks([-1.0, 0.0, 1.0])
        axes.set_xlabel("x / crank radius [1]  (towards the pin after +y)")
        axes.set_ylabel("y / crank radius [1]  (up)")
        axes.set_title("throws (solid) and banks (dashed), seen from the front")
        return finish(fig, owned, title, f"{layout_heading(result)}: crank star")


#: The radius [crank radii] of the inner edge of the throw labels of the crank star.
_THROW_RING = 1.15


def _signed_angle(angle_deg: float) -> str:
    signed = (angle_deg + 180.0) % 360.0 - 180.0
    return f"{signed:+g}°" if signed else "0°"


def _cylinder_list(numbers: Iterable[Any]) -> str:
    """Cylinder numbers as a label lists them: runs of three or more as ``1-9``."""
    values = sorted(int(n) for n in numbers)
    runs: list[list[int]] = []
    for n in values:
        if runs and n == runs[-1][-1] + 1:
            runs[-1].append(n)
        else:
            runs.append([n])
    return ", ".join(
        f"{run[0]}-{run[-1]}" if len(run) > 2 else ", ".join(map(str, run)) for run in runs
    )


def _text_box(text: str, char: float, line: float) -> tuple[float, float]:
    """Width and height [crank radii] of a label of the crank star: ``char`` per character
    of its longest line and ``line`` per line (the star's axes are about one inch per crank
    radius, so 10 pt text is about 0.09 wide and 0.17 high per character)."""
    rows = text.split("\n")
    return max(len(r) for r in rows) * char + 0.06, len(rows) * line + 0.04


def _extent(angle: float, box: tuple[float, float]) -> tuple[float, float]:
    """Half of a label's extent along a ring at ``angle`` [rad from +y] and across it."""
    w, h = box
    s, c = abs(math.sin(angle)), abs(math.cos(angle))
    return c * w / 2.0 + s * h / 2.0, s * w / 2.0 + c * h / 2.0


def _spread_angles(
    angles: Sequence[float], boxes: Sequence[tuple[float, float]], ring: float
) -> list[float]:
    """Where labels go on a ring of radius ``ring`` so that none overlaps its neighbours:
    each at its own angle where there is room, otherwise the crowded ones spread apart,
    in the same order, centred on their own angles.

    Parameters
    ----------
    angles : sequence of float
        Each label's own angle [rad from +y, clockwise].
    boxes : sequence of (float, float)
        Each label's width and height [crank radii].
    ring : float
        Radius of the labels' inner edge [crank radii].

    Returns
    -------
    list of float
        The angle of each label [rad], in the order given.
    """
    n = len(angles)
    if n < 2:
        return list(angles)
    turn = 2.0 * math.pi
    wrapped = [a % turn for a in angles]
    order = sorted(range(n), key=lambda i: wrapped[i])
    # cut the circle in its widest gap, so that a crowd around 0 deg stays together
    gaps = [(wrapped[order[(j + 1) % n]] - wrapped[order[j]]) % turn or turn for j in range(n)]
    cut = (gaps.index(max(gaps)) + 1) % n
    order = order[cut:] + order[:cut]
    base = wrapped[order[0]]
    want = [base + (wrapped[i] - base) % turn for i in order]

    def gap(i: int, j: int) -> float:
        """The angle two neighbouring labels need between their centres."""
        ti, ri = _extent(want[i], boxes[order[i]])
        tj, rj = _extent(want[j], boxes[order[j]])
        return (ti + tj + 0.04) / (ring + min(ri, rj))

    clusters = [[i] for i in range(n)]
    while True:
        placed = []
        for members in clusters:
            offsets = [0.0]
            for a, b in itertools.pairwise(members):
                offsets.append(offsets[-1] + gap(a, b))
            centre = sum(want[i] for i in members) / len(members)
            shift = centre - sum(offsets) / len(offsets)
            placed.append([shift + o for o in offsets])
        merged = False
        for c in range(len(clusters) - 1):
            last, first = clusters[c][-1], clusters[c + 1][0]
            if placed[c + 1][0] - placed[c][-1] < gap(last, first) - 1e-12:
                clusters[c : c + 2] = [clusters[c] + clusters[c + 1]]
                merged = True
                break
        if not merged:
            break
    out = [0.0] * n
    for members, where in zip(clusters, placed, strict=True):
        for i, angle in zip(members, where, strict=True):
            out[order[i]] = angle
    return out


def _place_label(
    axes: Axes,
    own: float,
    shown: float,
    box: tuple[float, float],
    ring: float,
    start: float,
    text: str,
    colour: str,
    size: float,
    weight: str,
) -> float:
    """Write a crank-star label with its inner edge on ``ring`` at angle ``shown`` [rad],
    joined by a thin line from radius ``start`` on its own angle ``own`` when it was moved
    there; returns the radius of its outer edge [crank radii]."""
    _, across = _extent(shown, box)
    centre = ring + across
    x, y = centre * math.sin(shown), centre * math.cos(shown)
    if abs(shown - own) > math.radians(1.0):
        axes.plot(
            [start * math.sin(own), ring * math.sin(shown)],
            [start * math.cos(own), ring * math.cos(shown)],
            color=colour,
            lw=0.7,
            zorder=2,
        )
    axes.text(
        x,
        y,
        text,
        ha="center",
        va="center",
        fontsize=size,
        fontweight=weight,
        color=colour,
        zorder=5,
        bbox={"boxstyle": "square,pad=0.05", "facecolor": "white", "edgecolor": "none"},
    )
    return centre + across


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
    theta = signals.crank_angle_grid(samples)
    with styled():
        fig, axes_list, owned = new_figure(ax, 4, (10.0, 7.0), nrows=2, kind="crank_angle")
        for row, quantity in enumerate(signals.QUANTITIES):
            ks, per_order, total, unit, shown = order_signals(
                result, quantity, source, orders, normalised, theta
            )
            split = (
                signals.transverse_components if quantity == "force" else signals.couple_components
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
                degree_axis(axes)
                axes.set_ylabel(axis_label(name, unit))
                axes.set_title(name)
                if np.isnan(values).all():
                    empty_note(axes, "not computed")
                    continue
                for k, line, visible in zip(ks, values, shown, strict=True):
                    if visible:
                        axes.plot(
                            theta,
                            line,
                            color=order_colour(int(k)),
                            lw=1.1,
                            label=f"order {int(k)}",
                            zorder=2,
                        )
                axes.plot(theta, total_values, color=TOTAL_COLOUR, lw=2.6, label="total", zorder=1)
        shared_legend(fig, axes_list)
        return finish(
            fig, owned, title, f"{layout_heading(result)}: {source_label(source)} over a revolution"
        )


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
    theta = signals.crank_angle_grid(samples)
    with styled():
        fig, axes_list, owned = new_figure(ax, 2, (10.5, 5.2), kind="locus")
        for axes, quantity in zip(axes_list, signals.QUANTITIES, strict=True):
            ks, per_order, total, unit, shown = order_signals(
                result, quantity, source, orders, normalised, theta
            )
            name = "force F" if quantity == "force" else "moment Σ Δz·F"
            axes.set_title(name)
            axes.set_xlabel(axis_label(f"{name}, x", unit))
            axes.set_ylabel(axis_label(f"{name}, y (up)", unit))
            axes.set_aspect("equal", adjustable="box")
            if np.isnan(per_order).all():
                empty_note(axes, "not computed")
                continue
            curves = [
                (values, order_colour(int(k)), 1.2, f"order {int(k)}")
                for k, values, visible in zip(ks, per_order, shown, strict=True)
                if visible
            ]
            curves.insert(0, (total, TOTAL_COLOUR, 2.6, "total"))
            reach = max(float(np.max(np.abs(c[0]), initial=0.0)) for c in curves)
            reach = 1.12 * reach if reach > 0 else 1.0
            for values, colour, width, label in curves:
                x, y = signals.transverse_components(values)
                axes.plot(x, y, color=colour, lw=width, label=label, zorder=2 if width < 2 else 1)
                axes.plot([x[0]], [y[0]], "o", color=colour, mfc="white", ms=6)
                _direction_arrow(axes, x, y, colour, reach)
            if not shown.any() and not np.any(np.abs(total) > 0):
                empty_note(axes, "zero")
            axes.set_xlim(-reach, reach)
            axes.set_ylim(-reach, reach)
            axes.axhline(0.0, color="0.6", lw=0.8, zorder=0)
            axes.axvline(0.0, color="0.6", lw=0.8, zorder=0)
        shared_legend(fig, axes_list)
        return finish(
            fig,
            owned,
            title,
            f"{layout_heading(result)}: locus of the {source_label(source)} force and moment",
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
    with styled():
        fig, axes_list, owned = new_figure(ax, 2, (10.0, 4.6), kind="spectrum")
        for axes, quantity in zip(axes_list, signals.QUANTITIES, strict=True):
            ks, _, _ = signals.phasors_of(result, quantity, source)
            divisor, unit, _ = scale_of(result, quantity, normalised)
            peak = signals.peak_of(result, quantity, source) / divisor
            name = "peak force" if quantity == "force" else "peak moment"
            order_bars(axes, ks, [(peak, "C0", None)], log=log)
            axes.set_title(name)
            axes.set_ylabel(axis_label(name, unit))
        return finish(
            fig, owned, title, f"{layout_heading(result)}: order spectrum, {source_label(source)}"
        )


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
    ks, roll = signals.roll_of(result, residual=residual)
    unit = "N m"
    reference = float(result.reference_roll)
    if normalised and math.isfinite(reference) and reference > 0.0:
        roll = roll / reference
        unit = "per m_rec r² ω²"
    amplitude = np.abs(roll)
    span = signals.roll_span_deg(ks)
    theta = signals.crank_angle_grid(samples, span)
    with styled():
        fig, (torque_axes, bar_axes), owned = new_figure(ax, 2, (10.5, 4.6), kind="roll")
        per_order = denoise(
            signals.roll_signal_per_order(roll, ks, theta), float(np.nansum(amplitude)), ks.size
        )
        shown = significant_mask(amplitude)
        degree_axis(torque_axes, span)
        label = axis_label("roll torque", unit)
        torque_axes.set_ylabel(label)
        torque_axes.set_title("roll torque on the block (+ with rotation)")
        if np.isnan(amplitude).all():
            empty_note(torque_axes, "not computed")
        else:
            for k, values, visible in zip(ks, per_order, shown, strict=True):
                if visible:
                    torque_axes.plot(
                        theta,
                        values,
                        color=order_colour(float(k)),
                        lw=1.1,
                        label=f"order {k:g}",
                        zorder=2,
                    )
            torque_axes.plot(
                theta, per_order.sum(axis=0), color=TOTAL_COLOUR, lw=2.6, label="total", zorder=1
            )
        order_bars(bar_axes, ks, [(amplitude, "C4", None)])
        bar_axes.set_title("amplitude per order")
        bar_axes.set_ylabel(axis_label("amplitude", unit))
        shared_legend(fig, [torque_axes])
        what = "roll with the proposed shafts" if residual else "roll"
        return finish(fig, owned, title, f"{layout_heading(result)}: {what}")


#: The figure kinds of every analysis and the functions that draw them (the sections' own
#: are in their views modules, :func:`section_kinds`).
PLOT_KINDS: dict[str, Callable[..., Figure]] = {
    "crank_star": plot_crank_star,
    "phasors": plot_phasors,
    "crank_angle": plot_crank_angle,
    "locus": plot_locus,
    "spectrum": plot_spectrum,
    "roll": plot_roll,
}


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
    """The function that draws a figure kind.

    Parameters
    ----------
    kind : str
        One of :data:`PLOT_KINDS` or a section's (:func:`all_kinds`).

    Returns
    -------
    callable
        ``function(result, **options) -> Figure``.

    Raises
    ------
    InputError
        For a kind that no figure has, with the kinds there are.
    """
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
    """A figure as the bytes of a ``png``, ``svg`` or ``pdf`` file (under :data:`STYLE`).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    fmt : {'png', 'svg', 'pdf'}
        The file format.

    Returns
    -------
    bytes
        The file's contents, without dates (the same figure gives the same bytes).
    """
    import io

    import matplotlib as mpl

    if fmt not in FORMATS:
        raise InputError(f"format {fmt!r}: expected one of {', '.join(FORMATS)}")
    buffer = io.BytesIO()
    with styled():
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
    :data:`PLOT_KINDS` (always), then those of every section the result holds whose views
    draw for it (a views module's ``drawn(result)``, true when it has none).

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    list of str
    """
    from balance.views.sections import view

    def drawn(name: str) -> bool:
        if name not in result.parts:
            return False
        check = getattr(view(name), "drawn", None)
        return check is None or bool(check(result))

    return [*PLOT_KINDS] + [k for k, (name, _) in section_kinds().items() if drawn(name)]


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
        Kinds of :func:`all_kinds`; default all that apply (:func:`applicable_kinds`).
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
        For an unknown kind or format, a file that exists without ``force``, or a kind
        that refuses the result (``balance`` without a proposal).
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
