"""Views of the ``torque`` section: the engine torque with gas forces
(:mod:`balance.core.torque`): JSON, table and the figures ``torque`` and ``forces``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.catalogue import value
from balance.core.errors import InputError
from balance.views.figures import (
    TOTAL_COLOUR,
    AxesArg,
    degree_axis,
    finish,
    layout_heading,
    new_figure,
    styled,
)
from balance.views.fitted import Column, NumberTable
from balance.views.polar import format_number, json_number

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure
    from rich.console import RenderableType

    from balance.core.result import Result
    from balance.core.torque import TorqueResult

__all__ = [
    "FORCE_NAMES",
    "GAS_KINDS",
    "PLOTS",
    "json_block",
    "plot_forces",
    "plot_torque",
    "tables",
]


def _part(result: Result) -> TorqueResult:
    part: TorqueResult = result.part("torque")
    return part


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``torque`` and ``gas``.

    Parameters
    ----------
    result : Result
        An analysis with the ``torque`` section.

    Returns
    -------
    dict
        The mean, largest and smallest torque [N m], the speed fluctuation and the flywheel
        inertia [kg m^2]; the indicated and excess work [J], the non-uniformity and the firing
        TDCs [deg].
    """
    t = _part(result)
    return {
        "torque": {
            "mean_Nm": json_number(t.mean),
            "max_Nm": json_number(t.maximum),
            "min_Nm": json_number(t.minimum),
            "speed_fluctuation": json_number(t.speed_fluctuation),
            "flywheel_inertia_kgm2": json_number(t.flywheel_inertia),
        },
        "gas": {
            "indicated_work_J": json_number(value(result, "indicated_work")),
            "torque_nonuniformity": json_number(t.nonuniformity),
            "excess_work_J": json_number(t.excess_work),
            "firing_tdc_deg": [json_number(v) for v in np.asarray(t.firing_tdc)],
        },
    }


def _render_torque(result: Result) -> RenderableType:
    """Rich renderable of the torque summary of an analysis with gas forces.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`, with the ``torque`` section.

    Returns
    -------
    rich.console.RenderableType
        The table of the mean, largest and smallest torque, the non-uniformity, the
        indicated and excess work, the speed fluctuation and the flywheel inertia.
    """
    t = _part(result)
    rows = [
        ("mean torque", "N m", float(t.mean)),
        ("largest torque", "N m", float(t.maximum)),
        ("smallest torque", "N m", float(t.minimum)),
        ("non-uniformity (M_max - M_min)/M_mean", "1", float(t.nonuniformity)),
        ("indicated work per cycle", "J", float(value(result, "indicated_work"))),
        ("largest excess work", "J", float(t.excess_work)),
        ("speed fluctuation (w_max - w_min)/w_mean", "1", float(t.speed_fluctuation)),
        ("flywheel inertia", "kg m^2", float(t.flywheel_inertia)),
    ]
    return NumberTable(
        "Engine torque with gas forces, over the cycle",
        [
            Column("quantity", key=True, justify="left"),
            Column("value"),
            Column("unit", justify="left"),
        ],
        [[label, format_number(value), unit] for label, unit, value in rows],
    )


def tables(result: Result) -> list[RenderableType]:
    """The section's table: the torque summary over the cycle (torque, non-uniformity, work,
    speed fluctuation, flywheel inertia).

    Parameters
    ----------
    result : Result
        An analysis with the ``torque`` section.

    Returns
    -------
    list of rich.console.RenderableType
    """
    return [_render_torque(result)]


# --------------------------------------------------------------------------- figures


def _no_gas(result: Result, ax: AxesArg, kind: str, title: str | None) -> Figure:
    """A figure that says there is no gas section (for a result without gas forces)."""
    with styled():
        fig, (axes,), owned = new_figure(ax, 1, (8.0, 3.0), kind=kind)
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
        return finish(fig, owned, title, f"{layout_heading(result)}: {kind}")


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
    with styled():
        fig, (axes,), owned = new_figure(ax, 1, (10.0, 4.8), kind="torque")
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
        degree_axis(axes, span)
        axes.set_ylabel("torque [N m]")
        axes.set_title("torque on the crankshaft (+ with rotation), gas and inertia")
        axes.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
        return finish(fig, owned, title, f"{layout_heading(result)}: torque over the cycle")


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
    with styled():
        fig, (top, bottom), owned = new_figure(ax, 2, (10.0, 7.0), nrows=2, ncols=1, kind="forces")
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
            degree_axis(axes, span)
            axes.set_xlabel("crank angle from firing TDC [deg]")
        return finish(fig, owned, title, f"{layout_heading(result)}: forces on cylinder {cylinder}")


#: The figure kinds of the section.
PLOTS = {"torque": plot_torque, "forces": plot_forces}

#: Plot kinds that need gas forces (a ``gas:`` section); asked for without, they say so.
GAS_KINDS = tuple(PLOTS)
