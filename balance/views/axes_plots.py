r"""Figures of engines with several crank axes, each axis drawn where it sits.

- :func:`plot_axes_star`: the crank star of an engine with several crankshafts, in the
  engine frame seen from the front [mm]: each crankshaft at its axis with its name, its sense
  of rotation and its crank pins at crank angle 0 (the engine-frame angle
  :math:`\alpha(0) = \varphi_s + \sigma_s\,\text{throw}`), each cylinder's bore line from its
  axis along its bank (docs/several-crankshafts.md).  :func:`balance.views.plots.plot_crank_star`
  draws it for such an engine.
- :func:`plot_axis_forces`: the free force of each crankshaft's pistons, rods and masses over
  a revolution (its locus, all orders of the analysis) drawn at the crankshaft's axis, with
  its value at crank angle 0: the figure ``crankshaft_forces`` of the ``crankshafts`` section.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.views.figures import AxesArg, finish, layout_heading, new_figure, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from balance.core.result import Result

__all__ = ["plot_axes_star", "plot_axis_forces"]

#: Crank angles per revolution of a drawn locus.
_SAMPLES = 361


def _unit(angle: Any) -> tuple[Any, Any]:
    """Engine-frame direction at an angle from +y towards +x, as (x, y)."""
    return np.sin(angle), np.cos(angle)


def _sense_arrow(axes: Axes, x: float, y: float, radius: float, sense: float) -> None:
    """A curved arrow round an axis in its sense of rotation (clockwise in this view for
    crankshaft 1's sense)."""
    start, end = (math.radians(200.0), math.radians(320.0))
    if sense < 0:
        start, end = end, start
    tail = (x + radius * math.sin(start), y + radius * math.cos(start))
    head = (x + radius * math.sin(end), y + radius * math.cos(end))
    axes.annotate(
        "",
        xy=head,
        xytext=tail,
        arrowprops={
            "arrowstyle": "-|>",
            "color": "0.3",
            "lw": 1.2,
            "connectionstyle": f"arc3,rad={-0.55 * sense}",
        },
    )


def _frame(axes: Axes, xs: list[float], ys: list[float], margin: float) -> None:
    """Equal axes in mm around every point drawn."""
    lo_x, hi_x = min(xs) - margin, max(xs) + margin
    lo_y, hi_y = min(ys) - margin, max(ys) + margin
    half = 0.5 * max(hi_x - lo_x, hi_y - lo_y)
    cx, cy = 0.5 * (lo_x + hi_x), 0.5 * (lo_y + hi_y)
    axes.set_xlim(cx - half, cx + half)
    axes.set_ylim(cy - half, cy + half)
    axes.set_aspect("equal")
    axes.set_xlabel("x [mm]  (towards the pin of crankshaft 1 after +y)")
    axes.set_ylabel("y [mm]  (up)")


def plot_axes_star(result: Result, *, ax: AxesArg = None, title: str | None = None) -> Figure:
    """Crank star of an engine with several crankshafts, each drawn where it sits.

    Parameters
    ----------
    result : Result
        An analysis of an engine with several crankshafts (:attr:`Engine.geared`).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    title : str, optional
        Figure title; by default the layout name and speed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    engine = result.engine
    table = engine.axis_table()
    r = engine.crank_radius * 1e3
    reach = (engine.crank_radius + engine.conrod_length) * 1e3
    alpha = table.axis_phase + table.sense * engine.throw  # pin at theta = 0
    with styled():
        fig, (axes,), owned = new_figure(ax, 1, (7.0, 6.6), kind="crank_star")
        xs: list[float] = []
        ys: list[float] = []
        circle = np.radians(np.linspace(0.0, 360.0, 181))
        for s, name in enumerate(table.names):
            x, y = float(table.x[s]) * 1e3, float(table.y[s]) * 1e3
            on = np.flatnonzero(table.axis == s)
            radius = float(np.max(r[on]))
            cx, cy = _unit(circle)
            axes.plot(x + radius * cx, y + radius * cy, color="0.75", lw=1.0, zorder=1)
            axes.plot([x], [y], "o", color="black", ms=5, zorder=4)
            sense = float(table.rotation[s])
            _sense_arrow(axes, x, y, 1.5 * radius, sense)
            way = "same" if sense > 0 else "opposite"
            axes.text(
                x - 1.9 * radius,
                y + 1.9 * radius,
                f"{name} ({way})",
                ha="center",
                va="center",
                fontsize=9,
                fontweight="bold",
            )
            xs += [x - 2.6 * radius, x + 2.6 * radius]
            ys += [y - 2.6 * radius, y + 2.6 * radius]
            pins: dict[float, list[int]] = {}
            for i in on:
                key = round(math.degrees(float(alpha[i])) % 360.0, 6) % 360.0
                pins.setdefault(key, []).append(int(i) + 1)
            for key, cylinders in pins.items():
                px, py = _unit(math.radians(key))
                axes.plot([x, x + radius * px], [y, y + radius * py], color="C0", lw=2.5, zorder=3)
                axes.plot([x + radius * px], [y + radius * py], "o", color="C0", ms=6, zorder=3)
                axes.text(
                    x + 1.25 * radius * px,
                    y + 1.25 * radius * py,
                    ",".join(map(str, cylinders)),
                    ha="center",
                    va="center",
                    color="C0",
                    fontsize=8,
                )
            for i in on:
                bx, by = _unit(float(engine.bank[i]))
                end = float(reach[i])
                axes.plot(
                    [x, x + end * bx], [y, y + end * by], ls="--", color="C3", lw=1.0, zorder=2
                )
                xs.append(x + end * bx)
                ys.append(y + end * by)
        _frame(axes, xs, ys, 0.05 * (max(xs) - min(xs) + max(ys) - min(ys)) + 1.0)
        axes.set_title(
            "crank pins at θ = 0 (solid, cylinder numbers) and bore lines (dashed), "
            "seen from the front",
            fontsize=9,
        )
        return finish(fig, owned, title, f"{layout_heading(result)}: crank star")


def plot_axis_forces(result: Result, *, ax: AxesArg = None, title: str | None = None) -> Figure:
    """Each crankshaft's free force over a revolution, drawn at its axis.

    The locus of the force vector of each crankshaft's pistons, rods and rotating masses
    (every order of the analysis) is drawn round the crankshaft's axis, at one scale for all
    shafts (the scale bar says how many newtons a millimetre of the drawing is), with an
    arrow for its value at crank angle 0.

    Parameters
    ----------
    result : Result
        An analysis with the ``crankshafts`` section.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure otherwise.
    title : str, optional
        Figure title; by default the layout name and speed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    part = result.part("crankshafts")
    free = part.force.free()
    orders = np.asarray(free.orders, dtype=np.float64)
    theta = np.radians(np.linspace(0.0, 360.0, _SAMPLES))
    turn = np.exp(1j * orders[:, None] * theta[None, :])
    # F = F_y + i F_x per shaft and angle
    force = free.force_forward @ turn + free.force_backward @ np.conj(turn)
    x = np.asarray(part.x, dtype=np.float64) * 1e3
    y = np.asarray(part.y, dtype=np.float64) * 1e3
    largest = float(np.max(np.abs(force))) if force.size else 0.0
    if part.count > 1:
        gaps = [
            math.hypot(x[a] - x[b], y[a] - y[b])
            for a in range(part.count)
            for b in range(a + 1, part.count)
        ]
        room = 0.4 * min(gaps)
    else:
        room = 100.0
    room = room if room > 0 else 100.0
    scale = room / largest if largest > 0 else 0.0  # mm of drawing per N
    with styled():
        fig, (axes,), owned = new_figure(ax, 1, (7.0, 6.6), kind="crankshaft_forces")
        xs: list[float] = []
        ys: list[float] = []
        for s, name in enumerate(part.names):
            f = force[s]
            fx, fy = f.imag * scale, f.real * scale
            axes.plot([x[s]], [y[s]], "o", color="black", ms=5, zorder=4)
            axes.plot(x[s] + fx, y[s] + fy, color=f"C{s}", lw=1.5, label=str(name))
            if abs(f[0]) > 0:
                axes.annotate(
                    "",
                    xy=(x[s] + fx[0], y[s] + fy[0]),
                    xytext=(x[s], y[s]),
                    arrowprops={"arrowstyle": "-|>", "color": f"C{s}", "lw": 1.2},
                )
            axes.text(
                x[s],
                y[s] - 0.9 * room,
                f"{name}: peak {float(np.max(np.abs(f))):.4g} N",
                ha="center",
                va="top",
                fontsize=8,
            )
            xs += [x[s] - room, x[s] + room]
            ys += [y[s] - room, y[s] + room]
        _frame(axes, xs, ys, 0.1 * room)
        if scale > 0:
            axes.set_title(
                f"free force of each crankshaft over a revolution, at its axis "
                f"(1 mm of drawing = {1.0 / scale:.4g} N; arrow: θ = 0)",
                fontsize=9,
            )
        else:
            axes.set_title("free force of each crankshaft: zero", fontsize=9)
        axes.legend(loc="upper right", fontsize=8)
        return finish(fig, owned, title, f"{layout_heading(result)}: crankshaft forces")
