"""Views of the ``dynamics`` section: the crank train's own motion and what the varying
speed changes in the free forces (:class:`balance.core.dynamics.DynamicsResult`,
docs/dynamics.md).

Every function reads a :class:`~balance.core.result.Result` holding the section's part:
the JSON block, the rich tables, the report section and three figures (the crank speed over
the cycle against the constant-speed line, the reduced inertia :math:`J(\\theta)`, and per
order the free force and roll under both speed models side by side).  The Dataset variables
are in the output catalogue (:data:`balance.core.dynamics.OUTPUTS`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.catalogue import speed_rpm
from balance.views.figures import grid_figure, placeholder, speed_text, title_text
from balance.views.polar import format_number, json_number, order_value

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from rich.console import RenderableType

    from balance.core.dynamics import DynamicsResult
    from balance.core.result import Result

__all__ = [
    "PLOTS",
    "REPORT_TITLE",
    "drawn",
    "json_block",
    "report_section",
    "tables",
]

#: The quantities per order, their unit and how a table names them.
QUANTITIES = (("force", "N", "free force (reciprocating + rotating)"),
              ("moment", "N m", "free moment (reciprocating + rotating)"),
              ("roll", "N m", "roll torque"))  # fmt: skip

_num = json_number


def _part(result: Result) -> DynamicsResult | None:
    """The dynamic model's solution, or None (a constant-speed result: only the bound)."""
    from balance.core.dynamics import DynamicsResult

    part = result.part("dynamics")
    return part if isinstance(part, DynamicsResult) else None


def _given(result: Result) -> DynamicsResult:
    part = _part(result)
    assert part is not None, "the result has no dynamic solution"
    return part


def drawn(result: Result) -> bool:
    """Whether the section's figures have something to draw: the dynamic model's solution.

    Parameters
    ----------
    result : Result
        An analysis with the section's part.

    Returns
    -------
    bool
    """
    return _part(result) is not None


def _bound_ratio(result: Result) -> float:
    """The constant rung's error bound per sum(m r w^2) (NaN without gas forces)."""
    bound = result.part("dynamics").bound
    return math.nan if bound is None else float(bound.ratio)


# --------------------------------------------------------------------------- JSON


def _load_json(p: DynamicsResult) -> dict[str, Any]:
    load = p.load
    if load.kind == "propeller":
        return {"kind": "propeller", "coefficient_Nms2": _num(p.load_coefficient)}
    if load.kind == "power_law":
        return {
            "kind": "power_law",
            "torque_Nm": _num(load.torque),  # type: ignore[union-attr]
            "at_rpm": speed_rpm(load.speed),  # type: ignore[union-attr]
            "exponent": _num(load.exponent),  # type: ignore[union-attr]
        }
    return {"kind": load.kind, "torque_Nm": _num(p.load_torque)}


def _phasor_entries(p: DynamicsResult, quantity: str) -> list[dict[str, Any]]:
    magnitude = p.dynamic.magnitude(quantity)  # type: ignore[arg-type]
    phase = p.dynamic.phase(quantity)  # type: ignore[arg-type]
    peak = p.dynamic.peak(quantity)  # type: ignore[arg-type]
    constant = p.constant_peak(quantity)
    difference = p.difference(quantity)
    return [
        {
            "order": order_value(k),
            "forward": {"magnitude": _num(magnitude[i, 0]), "phase_deg": _num(phase[i, 0])},
            "backward": {"magnitude": _num(magnitude[i, 1]), "phase_deg": _num(phase[i, 1])},
            "peak": _num(peak[i]),
            "peak_constant_speed": _num(constant[i]),
            "difference": _num(difference[i]),
        }
        for i, k in enumerate(p.orders)
    ]


def _roll_entries(p: DynamicsResult) -> list[dict[str, Any]]:
    from balance.core.phasors import phase_deg

    roll = np.asarray(p.dynamic.roll)
    amplitude, phase = np.abs(roll), phase_deg(roll)
    constant = p.constant_peak("roll")
    difference = p.difference("roll")
    return [
        {
            "order": order_value(k),
            "amplitude": _num(amplitude[i]),
            "phase_deg": _num(phase[i]),
            "amplitude_constant_speed": _num(constant[i]),
            "difference": _num(difference[i]),
        }
        for i, k in enumerate(p.orders)
    ]


def _dynamics_json(p: DynamicsResult) -> dict[str, Any]:
    """The ``"dynamics"`` block of the analysis JSON (docs/dynamics.md, "JSON")."""
    samples = p.samples()
    out: dict[str, Any] = {
        "speed_model": p.speed_model,
        "load": _load_json(p),
        "mean_speed_rpm": speed_rpm(p.mean_speed),
        "speed_min_rpm": speed_rpm(p.speed_min),
        "speed_max_rpm": speed_rpm(p.speed_max),
        "speed_fluctuation": _num(p.speed_fluctuation),
        "speed_fluctuation_constant_speed": _num(p.speed_fluctuation_constant_speed),
        "inertia_kgm2": {
            "min": _num(np.min(p.inertia)),
            "max": _num(np.max(p.inertia)),
            "mean": _num(np.mean(p.inertia)),
        },
        "flywheel_inertia_kgm2": _num(p.flywheel_inertia),
        "samples": {
            "crank_angle_deg": [_num(v) for v in samples["crank_angle"]],
            "speed_rpm": [speed_rpm(float(v)) for v in samples["speed"]],
            "acceleration_rad_s2": [_num(v) for v in samples["acceleration"]],
            "time_s": [_num(v) for v in samples["time"]],
        },
        "force": _phasor_entries(p, "force"),
    }
    largest = {"force": _num(p.largest_difference("force"))}
    if p.has("moment"):
        out["moment"] = _phasor_entries(p, "moment")
        largest["moment"] = _num(p.largest_difference("moment"))
    if p.has("roll"):
        out["roll"] = _roll_entries(p)
        largest["roll"] = _num(p.largest_difference("roll"))
    out["largest_difference"] = largest
    return out


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: the speed model and the constant rung's
    error bound in ``accuracy`` (docs/dynamics.md, "The ladder"), and with the dynamic
    model the ``dynamics`` block (:func:`_dynamics_json`).

    Parameters
    ----------
    result : Result
        An analysis with the ``dynamics`` section.

    Returns
    -------
    dict
        ``{"accuracy": {"speed_model": ..., "speed_bound": ...}}`` (the bound per
        sum(m r w^2) [1], null without gas forces), with ``"dynamics"`` (docs/dynamics.md,
        "JSON") when the result holds the dynamic model's solution.
    """
    part = result.part("dynamics")
    out: dict[str, Any] = {
        "accuracy": {"speed_model": part.speed_model, "speed_bound": _num(_bound_ratio(result))}
    }
    solution = _part(result)
    if solution is not None:
        out["dynamics"] = _dynamics_json(solution)
    return out


# --------------------------------------------------------------------------- tables


def _load_text(p: DynamicsResult) -> str:
    """The load in words, with its numbers."""
    load = p.load
    if load.kind == "propeller":
        return f"propeller, T = c w^2 with c = {format_number(p.load_coefficient)} N m s^2"
    if load.kind == "power_law":
        return (
            f"power law, T = {format_number(load.torque)} N m "  # type: ignore[union-attr]
            f"x (w / {format_number(speed_rpm(load.speed))} rpm)"  # type: ignore[union-attr]
            f"^{format_number(load.exponent)}"  # type: ignore[union-attr]
        )
    what = "mean gas torque" if load.kind == "mean" else "constant torque"
    return f"{what}, {format_number(p.load_torque)} N m"


def _summary_rows(p: DynamicsResult) -> list[tuple[str, str, str]]:
    sized = " (sized)" if p.flywheel_sized else ""
    return [
        ("load", _load_text(p), ""),
        ("mean speed (cycle angle / cycle time)", format_number(speed_rpm(p.mean_speed), 6), "rpm"),
        (
            "lowest / highest speed",
            f"{format_number(speed_rpm(p.speed_min), 6)} / "
            f"{format_number(speed_rpm(p.speed_max), 6)}",
            "rpm",
        ),
        ("speed fluctuation (w_max - w_min)/w_mean", format_number(p.speed_fluctuation), "1"),
        (
            "constant-speed estimate A/(J_mean w^2)",
            format_number(p.speed_fluctuation_constant_speed),
            "1",
        ),
        (
            "reduced inertia J min / mean / max",
            " / ".join(format_number(float(f(p.inertia))) for f in (np.min, np.mean, np.max)),
            "kg m^2",
        ),
        (f"flywheel inertia J_f{sized}", format_number(p.flywheel_inertia), "kg m^2"),
    ]


def _order_rows(p: DynamicsResult, quantity: str) -> list[list[str]]:
    """One row of text per order: the order, the peak (amplitude) under the varying and the
    constant speed, their difference and the difference per the constant-speed value
    [%]."""
    dynamic = p.peak(quantity)
    constant = p.constant_peak(quantity)
    difference = p.difference(quantity)
    rows = []
    for i, k in enumerate(p.orders):
        share = 100.0 * difference[i] / constant[i] if constant[i] > 0.0 else math.nan
        rows.append(
            [
                str(order_value(k)),
                format_number(float(dynamic[i])),
                format_number(float(constant[i])),
                format_number(float(difference[i])),
                format_number(share, 3),
            ]
        )
    return rows


def tables(result: Result) -> list[RenderableType]:
    """The section's tables: the motion, and per order the force, moment and roll under
    both speed models.

    Parameters
    ----------
    result : Result
        An analysis with the ``dynamics`` section.

    Returns
    -------
    list of rich.console.RenderableType
        With the dynamic model's solution: the crank speed over the cycle, a table per
        quantity the result has (force, moment, roll) and the largest differences [%].
        With the constant speed model: one line, the bound on what the speed's fluctuation
        may change [% of sum(m r w^2)].
    """
    from rich.text import Text

    from balance.views.fitted import Column, NumberTable

    p = _part(result)
    bound = 100.0 * _bound_ratio(result)
    if p is None:  # the constant speed model: what it may be off by
        return [
            Text(
                "Speed model constant: the crank speed's fluctuation may change the free "
                f"forces by up to {format_number(bound, 3)} % of sum(m r w^2) (bound)"
            )
        ]
    out: list[RenderableType] = [
        NumberTable(
            "Crank speed over the working cycle (periodic steady state)",
            [
                Column("quantity", key=True, justify="left"),
                Column("value"),
                Column("unit", justify="left"),
            ],
            [list(row) for row in _summary_rows(p)],
        )
    ]
    for quantity, unit, name in QUANTITIES:
        if not p.has(quantity):
            continue
        peak = "amplitude" if quantity == "roll" else "peak"
        out.append(
            NumberTable(
                f"{name[0].upper()}{name[1:]} per order: varying and constant speed",
                [
                    Column("order", key=True),
                    Column(f"{peak} dynamic", unit),
                    Column(f"{peak} constant speed", unit),
                    Column("difference", unit),
                    Column("difference", "%"),
                ],
                _order_rows(p, quantity),
                notes=("per order in time, against the mean crank angle",),
            )
        )
    text = (
        f"Largest difference per the largest constant-speed value: force "
        f"{format_number(100.0 * p.largest_difference('force'), 3)} %"
    )
    if p.has("roll"):
        text += f", roll {format_number(100.0 * p.largest_difference('roll'), 3)} %"
    out.append(Text(text))
    return out


# --------------------------------------------------------------------------- figures


def _not_computed(result: Result, kind: str, title: str | None) -> Figure:
    """A figure that says the variable-speed analysis was not asked for."""
    return placeholder(
        result,
        kind,
        title,
        "no variable-speed analysis in this result:\nask for the dynamic speed model",
    )


def _heading(result: Result, p: DynamicsResult) -> str:
    """The layout's name and the mean crank speed of the variable-speed analysis, as its
    figure titles begin."""
    return f"{result.engine.name} at {speed_text(p.mean_speed)} mean"


def _cycle_axis(ax: Axes, span: float) -> None:
    ax.set_xlim(0.0, span)
    ax.set_xticks(np.arange(0.0, span + 1.0, 90.0 if span <= 360.0 else 180.0))
    ax.set_xlabel("crank angle θ [deg]")


def _closed(p: DynamicsResult, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.append(p.crank_angle, p.cycle_deg), np.append(values, values[0])


def _plot_crank_speed(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``crank_speed``: the crank speed over the working cycle with the
    constant-speed line (the mean speed) and the fluctuation, and the crank's angular
    acceleration."""
    p = _part(result)
    if p is None:
        return _not_computed(result, "crank_speed", title)
    fig, (top, bottom) = grid_figure(2, (9.0, 6.0), 1)
    rpm = 30.0 / math.pi
    angle, speed = _closed(p, p.motion.speed * rpm)
    mean = p.mean_speed * rpm
    top.plot(angle, speed, "C0-", label="varying speed (periodic steady state)")
    top.axhline(
        mean, color="k", ls="--", lw=1.0, label=f"constant speed {format_number(mean, 5)} rpm"
    )
    lo, hi = int(np.argmin(p.motion.speed)), int(np.argmax(p.motion.speed))
    top.plot([p.crank_angle[lo], p.crank_angle[hi]], [speed[lo], speed[hi]], "C3o", ms=4)
    top.set_ylabel("crank speed [rpm]")
    top.set_title(
        f"δ = {format_number(100.0 * p.speed_fluctuation, 3)} % (constant-speed estimate "
        f"{format_number(100.0 * p.speed_fluctuation_constant_speed, 3)} %); "
        f"load: {_load_text(p)}",
        fontsize=9,
    )
    top.legend(loc="best", fontsize=8)
    _cycle_axis(top, p.cycle_deg)
    angle, accel = _closed(p, p.motion.acceleration)
    bottom.plot(angle, accel, "C1-")
    bottom.axhline(0.0, color="0.6", lw=0.6)
    bottom.set_ylabel("angular acceleration [rad/s²]")
    _cycle_axis(bottom, p.cycle_deg)
    fig.suptitle(
        title_text(
            fig.get_figwidth(),
            title or f"{_heading(result, p)}: crank speed over the working cycle",
        )
    )
    return fig


def _plot_reduced_inertia(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``reduced_inertia``: :math:`J(\\theta)` of the crank train, the flywheel
    included, with its mean and the flywheel's share."""
    p = _part(result)
    if p is None:
        return _not_computed(result, "reduced_inertia", title)
    fig, (ax,) = grid_figure(1, (9.0, 4.0), 1)
    angle, inertia = _closed(p, p.inertia)
    ax.plot(angle, inertia, "C2-", label="J(θ)")
    ax.axhline(float(np.mean(p.inertia)), color="k", ls="--", lw=1.0, label="cycle mean")
    ax.axhline(p.flywheel_inertia, color="0.5", ls=":", lw=1.0, label="flywheel J_f")
    ax.set_ylabel("reduced inertia [kg m²]")
    ax.set_title(
        f"J_f = {format_number(p.flywheel_inertia)} kg m²"
        f"{' (sized)' if p.flywheel_sized else ''}; the layout's masses add "
        f"{format_number(float(np.min(p.inertia)) - p.flywheel_inertia)} to "
        f"{format_number(float(np.max(p.inertia)) - p.flywheel_inertia)} kg m²",
        fontsize=9,
    )
    ax.legend(loc="best", fontsize=8)
    _cycle_axis(ax, p.cycle_deg)
    fig.suptitle(
        title_text(
            fig.get_figwidth(),
            title or f"{_heading(result, p)}: reduced inertia of the crank train",
        )
    )
    return fig


def _bars(ax: Axes, p: DynamicsResult, quantity: str, unit: str, name: str) -> None:
    """Per order: the constant-speed and the varying-speed value and their difference."""
    dynamic, constant = p.peak(quantity), p.constant_peak(quantity)
    difference = p.difference(quantity)
    x = np.arange(p.orders.size)
    width = 0.28
    top = float(max(np.max(dynamic, initial=0.0), np.max(constant, initial=0.0)))
    floor = 1e-9 * top
    ax.set_xticks(x, [str(order_value(k)) for k in p.orders], fontsize=7)
    ax.set_xlim(-0.5, p.orders.size - 0.5)
    ax.set_xlabel("order (multiple of the mean speed)")
    peak = "amplitude" if quantity == "roll" else "peak"
    ax.set_ylabel(f"{peak} [{unit}]")
    if top <= 0.0:
        ax.text(0.5, 0.5, f"the {name} is zero at every order", transform=ax.transAxes,
                ha="center", va="center", color="0.4")  # fmt: skip
        ax.set_title(name, fontsize=9)
        return
    for offset, values, colour, label in (
        (-width, constant, "0.55", "constant speed"),
        (0.0, dynamic, "C0", "varying speed"),
        (width, difference, "C3", "difference |ΔP⁺| + |ΔP⁻|" if quantity != "roll" else "|ΔR|"),
    ):
        shown = np.where(values > floor, values, np.nan)
        ax.bar(x + offset, shown, width, color=colour, label=label)
    ax.set_yscale("log")
    ax.set_title(
        f"{name}: largest difference {format_number(100.0 * p.largest_difference(quantity), 3)} "
        "% of the largest constant-speed value",
        fontsize=9,
    )
    ax.legend(loc="best", fontsize=8)


def _plot_speed_model_orders(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``speed_model_orders``: per order, the whole free force and the roll (and
    the moment) under the constant and the varying crank speed, side by side."""
    p = _part(result)
    if p is None:
        return _not_computed(result, "speed_model_orders", title)
    shown = [q for q in QUANTITIES if p.has(q[0])]
    fig, axes = grid_figure(len(shown), (10.0, 3.4 * len(shown)), 1)
    for ax, (quantity, unit, name) in zip(axes, shown, strict=True):
        _bars(ax, p, quantity, unit, name)
    fig.suptitle(
        title_text(
            fig.get_figwidth(),
            title
            or f"{_heading(result, p)}: free force (reciprocating + rotating), moment and roll per "
            "order, constant and varying speed",
        )
    )
    return fig


#: The figure kinds of the section.
PLOTS: dict[str, Callable[..., Figure]] = {
    "crank_speed": _plot_crank_speed,
    "reduced_inertia": _plot_reduced_inertia,
    "speed_model_orders": _plot_speed_model_orders,
}


# --------------------------------------------------------------------------- report

#: The heading of the section in the HTML report.
REPORT_TITLE = "Variable crank speed"


def _report_tables(p: DynamicsResult, table: Callable[..., str]) -> Sequence[str]:
    summary = table(
        ["quantity", "value", "unit"],
        [list(row) for row in _summary_rows(p)],
        "The crank train's periodic motion over the working cycle",
    )
    out = [summary]
    for quantity, unit, name in QUANTITIES:
        if not p.has(quantity):
            continue
        peak = "amplitude" if quantity == "roll" else "peak"
        out.append(
            table(
                [
                    "order",
                    f"{peak} dynamic [{unit}]",
                    f"{peak} constant speed [{unit}]",
                    f"difference [{unit}]",
                    "difference [%]",
                ],
                _order_rows(p, quantity),
                f"{name[0].upper()}{name[1:]} per order, varying and constant speed",
            )
        )
    return out


def report_section(result: Result, figures: bool) -> str:
    """HTML of the report's variable-speed section, with its three figures.

    Parameters
    ----------
    result : Result
        An analysis with the ``dynamics`` section.
    figures : bool
        Include the three figures (inline SVG) when the result holds the dynamic model's
        solution.

    Returns
    -------
    str
        HTML of the section's body: with the constant speed model one paragraph giving the
        bound [% of sum(m r w^2)]; otherwise the model in words and the tables.
    """
    from balance.views.report import escape, html_figure, html_table

    p = _part(result)
    if p is None:
        bound = format_number(100.0 * _bound_ratio(result), 3)
        return (
            f"<p>{escape('Speed model constant: the crank speed is taken as constant; its ')}"
            f"{escape(f'fluctuation may change the free forces by up to {bound} % of ')}"
            f"{escape('sum(m r w²) (a bound from the constant-speed data, docs/dynamics.md).')}"
            "</p>"
        )
    text = (
        "The rigid crank train's equation of motion, J(θ) dω/dt + ½ J'(θ) ω² = Q(θ) − T_L(ω), "
        "solved for its periodic steady state over the working cycle; the mean speed is the "
        "cycle angle over the cycle time. Orders are taken in time against the mean crank "
        "angle; 'constant speed' is the usual analysis at the same mean speed, and the "
        "difference the size of the vector difference of the phasors."
    )
    html = f"<p>{escape(text)}</p>\n" + "\n".join(_report_tables(p, html_table))
    if figures:
        html += "\n" + "\n".join(
            html_figure(result, kind, caption, 110 + n)
            for n, (kind, caption) in enumerate(
                (
                    ("crank_speed", "Crank speed over the working cycle"),
                    ("reduced_inertia", "Reduced inertia J(θ) of the crank train"),
                    ("speed_model_orders", "Free force and roll per order at both speeds"),
                )
            )
        )
    return html
