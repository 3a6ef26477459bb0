"""A readable rich table of a :class:`~balance.core.result.Result`, for the terminal.

Reads the Result's phasors and references directly; no xarray.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.views.polar import phase_deg, safe_ratio, speed_rpm

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.result import Result
    from balance.core.torque import TorqueResult

__all__ = [
    "cylinders_table",
    "format_number",
    "render",
    "render_factor_study",
    "render_proposal",
    "render_torque",
]


def format_number(value: float, digits: int = 4) -> str:
    """Compact engineering formatting: 0 stays 0, NaN shows as a dash."""
    if not math.isfinite(value):
        return "-"
    if value == 0.0:
        return "0"
    return f"{value:.{digits}g}"


def render(result: Result) -> RenderableType:
    """Rich renderable: summary line, free forces and moments per order, rotating, roll."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    engine = result.engine
    p = result.phasors
    bound = float(p.error_bound)
    title = (
        f"{engine.name}: {engine.n_cylinders} cylinders at "
        f"{speed_rpm(engine.speed):.0f} rpm, model {p.model}"
        + (f" (coefficient error below {bound:.1g})" if math.isfinite(bound) else "")
    )
    norm = Text(
        f"F1 = m_rec r w^2 = {format_number(float(result.reference_force))} N;  "
        f"pitch a = {format_number(float(result.pitch) * 1e3)} mm;  "
        f"moments about z = {format_number(float(engine.reference_z) * 1e3)} mm"
    )
    tables = []
    kinds = [("force", "N", "F1", p.force_forward, p.force_backward, result.reference_force)]
    if result.has_moments:
        kinds.append(
            ("moment", "N m", "F1 a", p.moment_forward, p.moment_backward, result.reference_moment)
        )
    for what, unit, per, forward, backward, reference in kinds:
        table = Table(
            title=f"Reciprocating inertia: free {what}s"
            + (" about reference_z" if what == "moment" else ""),
            title_justify="left",
        )
        table.add_column("order", justify="right")
        for label in (
            f"forward [{unit}]",
            "phase [deg]",
            f"backward [{unit}]",
            "phase [deg]",
            f"peak [{unit}]",
            f"peak / {per}",
        ):
            table.add_column(label, justify="right")
        both = np.stack([forward, backward], axis=-1)
        mag = np.abs(both)
        phase = phase_deg(both)
        peak = mag[..., 0] + mag[..., 1]
        normalised = safe_ratio(peak, reference)
        for i, k in enumerate(p.orders):
            table.add_row(
                str(int(k)),
                format_number(float(mag[i, 0])),
                format_number(float(phase[i, 0])),
                format_number(float(mag[i, 1])),
                format_number(float(phase[i, 1])),
                format_number(float(peak[i])),
                format_number(float(normalised[i])),
            )
        tables.append(table)
    rotating_text = (
        "Rotating (order 1, forward): force "
        f"{format_number(float(np.abs(p.rotating_force)))} N at "
        f"{format_number(float(phase_deg(p.rotating_force)))} deg"
    )
    if result.has_moments:
        rotating_text += (
            f";  moment {format_number(float(np.abs(p.rotating_moment)))} N m at "
            f"{format_number(float(phase_deg(p.rotating_moment)))} deg"
        )
    parts: list[RenderableType] = [Text(title, style="bold"), norm, *tables, Text(rotating_text)]
    if result.roll is not None:
        parts.append(_roll_table(result))
    if result.cylinder_stroke is not None:
        parts.append(cylinders_table(result))
    if result.torque is not None:
        parts.append(render_torque(result.torque))
    if result.balanced is not None:
        parts.extend(render_proposal(result))
    if result.mounts is not None:
        from balance.views.mounts import mounts_tables

        parts.extend(mounts_tables(result.mounts))
    if result.bearings is not None:
        from balance.views.bearings import bearings_tables

        parts.extend(bearings_tables(result.bearings))
    return Group(*parts)


def cylinders_table(result: Result) -> RenderableType:
    """Each cylinder's actual stroke and TDC crank angle, and its link rod if it has one."""
    from rich.markup import escape
    from rich.table import Table

    assert result.cylinder_stroke is not None and result.cylinder_tdc is not None
    engine = result.engine
    links = engine.links
    table = Table(title="Cylinders: stroke and TDC", title_justify="left")
    for label in ("cylinder", "stroke [mm]", "TDC at [deg]"):
        table.add_column(escape(label), justify="right")
    if links is not None:
        table.add_column("rod")
    tdc = np.degrees(result.cylinder_tdc)
    for i in range(engine.n_cylinders):
        row = [str(i + 1), format_number(float(result.cylinder_stroke[i]) * 1e3, 6)]
        row.append(format_number(float(tdc[i]), 6))
        if links is not None:
            m = int(links.master[i])
            if m >= 0:
                row.append(
                    f"link on {m + 1}: pin {format_number(float(links.pin_radius[i]) * 1e3)} mm "
                    f"at {format_number(math.degrees(float(links.pin_angle[i])))} deg, "
                    f"{format_number(float(engine.conrod_length[i]) * 1e3)} mm"
                )
            else:
                carried = int(np.count_nonzero(links.master == i))
                row.append(f"master of {carried}" if carried else "on the pin")
        table.add_row(*row)
    return table


def _roll_table(result: Result) -> RenderableType:
    from rich.table import Table

    assert result.roll is not None
    roll = Table(title="Roll torque on the block (a_k cos(k theta + phase))", title_justify="left")
    roll.add_column("order", justify="right")
    roll.add_column("amplitude [N m]", justify="right")
    roll.add_column("phase [deg]", justify="right")
    roll.add_column("per m_rec r^2 w^2", justify="right")
    amplitude = np.abs(result.roll)
    phase = phase_deg(result.roll)
    normalised = safe_ratio(amplitude, result.reference_roll)
    for i, k in enumerate(np.asarray(result.roll_orders, dtype=np.float64)):
        roll.add_row(
            f"{k:g}",
            format_number(float(amplitude[i])),
            format_number(float(phase[i])),
            format_number(float(normalised[i])),
        )
    return roll


def render_torque(t: TorqueResult) -> RenderableType:
    """Rich renderable of the torque summary of an analysis with gas forces."""
    from rich.markup import escape
    from rich.table import Table

    table = Table(title="Engine torque with gas forces (over the cycle)", title_justify="left")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    rows = [
        ("mean torque [N m]", float(t.mean)),
        ("largest torque [N m]", float(t.maximum)),
        ("smallest torque [N m]", float(t.minimum)),
        ("non-uniformity (M_max - M_min)/M_mean", float(t.nonuniformity)),
        ("indicated work per cycle [J]", float(t.mean * 2.0 * math.pi * t.cycle_deg / 360.0)),
        ("largest excess work [J]", float(t.excess_work)),
        ("speed fluctuation (w_max - w_min)/w_mean", float(t.speed_fluctuation)),
        ("flywheel inertia [kg m^2]", float(t.flywheel_inertia)),
    ]
    for label, value in rows:
        table.add_row(escape(label), format_number(value))
    return table


def render_proposal(result: Result) -> list[RenderableType]:
    """Rich renderables of the balancing proposal and its residual."""
    from rich.table import Table
    from rich.text import Text

    assert result.balanced is not None and result.residual_roll is not None
    balanced = result.balanced
    proposal = balanced.proposal
    factor = proposal.balance_factor
    choice = (
        f"Proposal: strategy {proposal.strategy}, cancelling orders "
        f"{','.join(map(str, proposal.orders))}"
        + ("" if factor is None else f", balance factor {float(factor):.0%}")
    )
    out: list[RenderableType] = [Text(choice, style="bold")]
    notes = "; ".join(proposal.notes)
    if notes:
        out.append(Text(notes))
    cws = proposal.counterweights
    shafts = proposal.shafts
    if not cws and not shafts:
        out.append(Text("Nothing to cancel: no counterweights or balance shafts are needed."))
    if cws:
        table = Table(title="Counterweights (turn with the crank)", title_justify="left")
        for label in ("z [mm]", "mass [kg]", "radius [mm]", "angle [deg]"):
            table.add_column(label, justify="right")
        for c in cws:
            table.add_row(
                format_number(float(c.z) * 1e3),
                format_number(float(c.mass)),
                format_number(float(c.radius) * 1e3),
                format_number(float(c.angle_deg)),
            )
        out.append(table)
    if shafts:
        table = Table(title="Balance shafts", title_justify="left")
        for label in (
            "shaft",
            "speed ratio",
            "x [mm]",
            "y [mm]",
            "plane z [mm]",
            "unbalance [kg mm]",
            "angle [deg]",
        ):
            table.add_column(label, justify="right")
        for i, shaft in enumerate(shafts):
            unbalance = np.array([u for _, u in shaft.planes], dtype=np.complex128)
            angle = phase_deg(unbalance)
            for j, (z, _) in enumerate(shaft.planes):
                first = j == 0
                table.add_row(
                    str(i + 1) if first else "",
                    f"{int(shaft.speed_ratio):+d}" if first else "",
                    format_number(float(shaft.x) * 1e3) if first else "",
                    format_number(float(shaft.y) * 1e3) if first else "",
                    format_number(float(z) * 1e3),
                    format_number(float(np.abs(unbalance[j])) * 1e3),
                    format_number(float(angle[j])),
                )
        out.append(table)
    table = Table(
        title="Residual with the proposal (all free forces and moments)", title_justify="left"
    )
    for label in (
        "order",
        "force peak [N]",
        "peak / F1",
        "moment peak [N m]",
        "peak / (F1 a)",
        "roll [N m]",
    ):
        table.add_column(label, justify="right")
    force_peak = np.abs(np.stack([balanced.force_forward, balanced.force_backward], -1)).sum(-1)
    moment_peak = np.abs(np.stack([balanced.moment_forward, balanced.moment_backward], -1)).sum(-1)
    force_normalised = safe_ratio(force_peak, result.reference_force)
    moment_normalised = safe_ratio(moment_peak, result.reference_moment)
    roll_at = {float(k): i for i, k in enumerate(result.roll_orders)}
    roll_amplitude = np.abs(result.residual_roll)
    for i, k in enumerate(result.phasors.orders):
        at = roll_at.get(float(k))
        table.add_row(
            str(int(k)),
            format_number(float(force_peak[i])),
            format_number(float(force_normalised[i])),
            format_number(float(moment_peak[i])),
            format_number(float(moment_normalised[i])),
            "-" if at is None else format_number(float(roll_amplitude[at])),
        )
    out.append(table)
    return out


def render_factor_study(study: Mapping[str, Any]) -> list[RenderableType]:
    """Rich renderables of a balance-factor study (:mod:`balance.studies.factor`: its Dataset,
    or any mapping of its variable names to arrays)."""
    from rich.table import Table
    from rich.text import Text

    table = Table(
        title="Balance factor study: residual first order (rotating masses balanced in full)",
        title_justify="left",
    )
    labels = ["factor", "vertical peak [N]", "horizontal peak [N]", "moment peak [N m]"]
    bearing_columns = [  # with --bearings (balance.studies.factor_bearings)
        name
        for name in ("study_largest_main_load", "study_largest_internal_moment")
        if name in study
    ]
    labels += [
        {"study_largest_main_load": "largest main load [N]"}.get(
            name, "largest internal moment [N m]"
        )
        for name in bearing_columns
    ]
    for label in labels:
        table.add_column(label, justify="right")
    vertical = np.asarray(study["study_vertical_peak"])
    horizontal = np.asarray(study["study_horizontal_peak"])
    moment = np.asarray(study["study_moment_peak"])
    extra = [np.asarray(study[name]) for name in bearing_columns]
    for i, f in enumerate(np.asarray(study["study_factor"])):
        table.add_row(
            f"{f:.0%}",
            format_number(float(vertical[i])),
            format_number(float(horizontal[i])),
            format_number(float(moment[i])),
            *(format_number(float(column[i])) for column in extra),
        )
    best = float(np.asarray(study["optimal_balance_factor"]))
    return [table, Text(f"Factor minimising the larger force peak: {best:.1%}")]
