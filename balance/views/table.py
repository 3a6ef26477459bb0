"""A readable table of a :class:`~balance.core.result.Result`, for the terminal.

Reads the Result's phasors and references directly; no xarray.  Every table is a
:class:`~balance.views.fitted.NumberTable`: its title on a line of its own, a unit in
brackets in every column header of a quantity, and a layout chosen when it is printed so
that no number is ever cut (see :mod:`balance.views.fitted`).  A value the computation
cannot tell from zero (below the rounding threshold of its sums,
:func:`balance.core.phasors.cancel_to_zero`) prints as 0; a ratio that has no reference
(a moment per pitch when every cylinder is in one plane) prints as ``n/a`` with the reason
below its table.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.views.fitted import Column, NumberTable
from balance.views.polar import format_number, phase_deg, safe_ratio, speed_rpm

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.result import Result
    from balance.core.torque import TorqueResult

__all__ = [
    "NO_PITCH",
    "cylinders_table",
    "format_number",
    "format_ratio",
    "pitch_text",
    "render",
    "render_factor_study",
    "render_proposal",
    "render_torque",
    "render_warnings",
]

#: Why a moment has no normalised value: the pitch is undefined.
NO_PITCH = "n/a (all cylinders in one plane)"


def format_ratio(value: float, reference: float) -> str:
    """A normalised value, or ``n/a`` where its reference is undefined (NaN or zero)."""
    if not (math.isfinite(reference) and reference != 0.0):
        return "n/a"
    return format_number(value)


def pitch_text(pitch: float) -> str:
    """The cylinder pitch as printed: ``90 mm``, or ``n/a`` and why."""
    return f"{format_number(pitch * 1e3)} mm" if math.isfinite(pitch) else NO_PITCH


def _pitch_note(result: Result) -> tuple[str, ...]:
    """The note under a table with moments per F1 a, when there is no pitch."""
    if math.isfinite(float(result.reference_moment)) and float(result.reference_moment) != 0:
        return ()
    return ("n/a: no pitch a (all cylinders in one plane), so no moment per F1 a",)


def heading(result: Result) -> list[RenderableType]:
    """The first lines of an analysis: the layout, its speed and model, the references."""
    from rich.text import Text

    engine = result.engine
    p = result.phasors
    bound = float(p.error_bound)
    summary = (
        f"{engine.n_cylinders} cylinder{'s' if engine.n_cylinders != 1 else ''} at "
        f"{speed_rpm(engine.speed):.0f} rpm; model {p.model}"
        + (f" (coefficient error below {bound:.1g})" if math.isfinite(bound) else "")
    )
    norm = (
        f"F1 = m_rec r w^2 = {format_number(float(result.reference_force))} N; "
        f"moments about z = {format_number(float(engine.reference_z) * 1e3)} mm"
    )
    pitch = f"pitch a = {pitch_text(float(result.pitch))}"
    return [Text(str(engine.name), style="bold"), Text(summary), Text(norm), Text(pitch)]


def render(result: Result) -> RenderableType:
    """Rich renderable: heading, free forces and moments per order, rotating, roll, and
    what else the result holds (torque, proposal, mounts, bearing loads)."""
    from rich.console import Group
    from rich.text import Text

    p = result.phasors
    parts: list[RenderableType] = heading(result)
    kinds = [("force", "N", "F1", p.force_forward, p.force_backward, result.reference_force)]
    if result.has_moments:
        kinds.append(
            ("moment", "N m", "F1 a", p.moment_forward, p.moment_backward, result.reference_moment)
        )
    for what, unit, per, forward, backward, reference in kinds:
        both = np.stack([forward, backward], axis=-1)
        mag = np.abs(both)
        phase = phase_deg(both)
        peak = mag[..., 0] + mag[..., 1]
        normalised = safe_ratio(peak, reference)
        rows = [
            [
                str(int(k)),
                format_number(float(mag[i, 0])),
                format_number(float(phase[i, 0])),
                format_number(float(mag[i, 1])),
                format_number(float(phase[i, 1])),
                format_number(float(peak[i])),
                format_ratio(float(normalised[i]), float(reference)),
            ]
            for i, k in enumerate(p.orders)
        ]
        title = (
            "Reciprocating inertia: free forces per order"
            if what == "force"
            else "Reciprocating inertia: free moments per order, about reference_z"
        )
        parts.append(
            NumberTable(
                title,
                [
                    Column("order", key=True),
                    Column("forward", unit),
                    Column("phase", "deg"),
                    Column("backward", unit),
                    Column("phase", "deg"),
                    Column("peak", unit),
                    Column(f"peak / {per}" if what == "force" else f"peak / ({per})"),
                ],
                rows,
                notes=_pitch_note(result) if what == "moment" else (),
            )
        )
    parts.append(
        Text(
            "Rotating masses (order 1, forward): force "
            f"{format_number(float(np.abs(p.rotating_force)))} N at "
            f"{format_number(float(phase_deg(p.rotating_force)))} deg"
        )
    )
    if result.has_moments:
        parts.append(
            Text(
                "Rotating masses (order 1, forward): moment "
                f"{format_number(float(np.abs(p.rotating_moment)))} N m at "
                f"{format_number(float(phase_deg(p.rotating_moment)))} deg"
            )
        )
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
    parts.extend(render_warnings(result))
    return Group(*parts)


def render_warnings(result: Result) -> list[RenderableType]:
    """The plausibility warnings as the table's footer, one line each (none: nothing)."""
    from rich.text import Text

    return [Text(f"warning: {w.field}: {w.message}", style="yellow") for w in result.warnings]


def cylinders_table(result: Result) -> NumberTable:
    """Each cylinder's actual stroke and TDC crank angle, and its link rod if it has one."""
    assert result.cylinder_stroke is not None and result.cylinder_tdc is not None
    engine = result.engine
    links = engine.links
    tdc = np.degrees(result.cylinder_tdc)
    columns = [Column("cylinder", key=True), Column("stroke", "mm"), Column("TDC at", "deg")]
    if links is not None:
        columns += [
            Column("rod", justify="left"),
            Column("master"),
            Column("link pin radius", "mm"),
            Column("link pin angle", "deg"),
            Column("rod length", "mm"),
        ]
    rows = []
    for i in range(engine.n_cylinders):
        row = [
            str(i + 1),
            format_number(float(result.cylinder_stroke[i]) * 1e3, 6),
            format_number(float(tdc[i]), 6),
        ]
        if links is not None:
            m = int(links.master[i])
            length = format_number(float(engine.conrod_length[i]) * 1e3)
            if m >= 0:
                row += [
                    "link rod",
                    str(m + 1),
                    format_number(float(links.pin_radius[i]) * 1e3),
                    format_number(math.degrees(float(links.pin_angle[i]))),
                    length,
                ]
            else:
                carried = int(np.count_nonzero(links.master == i))
                rod = f"master rod, {carried} link(s)" if carried else "on the crank pin"
                row += [rod, "-", "-", "-", length]
        rows.append(row)
    return NumberTable("Cylinders: stroke and TDC", columns, rows)


def _roll_table(result: Result) -> NumberTable:
    assert result.roll is not None
    amplitude = np.abs(result.roll)
    phase = phase_deg(result.roll)
    normalised = safe_ratio(amplitude, result.reference_roll)
    rows = [
        [
            f"{k:g}",
            format_number(float(amplitude[i])),
            format_number(float(phase[i])),
            format_ratio(float(normalised[i]), float(result.reference_roll)),
        ]
        for i, k in enumerate(np.asarray(result.roll_orders, dtype=np.float64))
    ]
    return NumberTable(
        "Roll torque on the block: sum of a_k cos(k theta + phase_k)",
        [
            Column("order", key=True),
            Column("amplitude a_k", "N m"),
            Column("phase_k", "deg"),
            Column("a_k / (m_rec r^2 w^2)"),
        ],
        rows,
    )


def render_torque(t: TorqueResult) -> RenderableType:
    """Rich renderable of the torque summary of an analysis with gas forces."""
    rows = [
        ("mean torque", "N m", float(t.mean)),
        ("largest torque", "N m", float(t.maximum)),
        ("smallest torque", "N m", float(t.minimum)),
        ("non-uniformity (M_max - M_min)/M_mean", "1", float(t.nonuniformity)),
        ("indicated work per cycle", "J", float(t.mean * 2.0 * math.pi * t.cycle_deg / 360.0)),
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


def render_proposal(result: Result) -> list[RenderableType]:
    """Rich renderables of the balancing proposal and its residual: a line of the choices,
    the proposal's notes (one line each), the counterweights, the balance shafts and the
    residual."""
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
    out.extend(Text(f"Note: {note}") for note in proposal.notes if note)
    cws = proposal.counterweights
    shafts = proposal.shafts
    if not cws and not shafts:
        out.append(Text("Nothing to cancel: no counterweights or balance shafts are needed."))
    if cws:
        out.append(
            NumberTable(
                "Counterweights (turn with the crank; angle at theta = 0)",
                [
                    Column("z", "mm"),
                    Column("mass", "kg"),
                    Column("radius", "mm"),
                    Column("angle", "deg"),
                    Column("m R", "kg mm"),
                ],
                [
                    [
                        format_number(float(c.z) * 1e3),
                        format_number(float(c.mass)),
                        format_number(float(c.radius) * 1e3),
                        format_number(float(c.angle_deg)),
                        format_number(abs(c.unbalance) * 1e3),
                    ]
                    for c in cws
                ],
            )
        )
    if shafts:
        rows = []
        for i, shaft in enumerate(shafts):
            unbalance = np.array([u for _, u in shaft.planes], dtype=np.complex128)
            angle = phase_deg(unbalance)
            for j, (z, _) in enumerate(shaft.planes):
                first = j == 0
                rows.append(
                    [
                        str(i + 1) if first else "",
                        f"{int(shaft.speed_ratio):+d}" if first else "",
                        format_number(float(shaft.x) * 1e3) if first else "",
                        format_number(float(shaft.y) * 1e3) if first else "",
                        format_number(float(z) * 1e3),
                        format_number(float(np.abs(unbalance[j])) * 1e3),
                        format_number(float(angle[j])),
                    ]
                )
        out.append(
            NumberTable(
                "Balance shafts (eccentric mass at angle + speed ratio x theta)",
                [
                    Column("shaft", key=True),
                    Column("speed ratio"),
                    Column("x", "mm"),
                    Column("y", "mm"),
                    Column("plane z", "mm"),
                    Column("m e", "kg mm"),
                    Column("angle", "deg"),
                ],
                rows,
            )
        )
    force_peak = np.abs(np.stack([balanced.force_forward, balanced.force_backward], -1)).sum(-1)
    moment_peak = np.abs(np.stack([balanced.moment_forward, balanced.moment_backward], -1)).sum(-1)
    force_normalised = safe_ratio(force_peak, result.reference_force)
    moment_normalised = safe_ratio(moment_peak, result.reference_moment)
    roll_at = {float(k): i for i, k in enumerate(result.roll_orders)}
    roll_amplitude = np.abs(result.residual_roll)
    rows = []
    for i, k in enumerate(result.phasors.orders):
        at = roll_at.get(float(k))
        rows.append(
            [
                str(int(k)),
                format_number(float(force_peak[i])),
                format_ratio(float(force_normalised[i]), float(result.reference_force)),
                format_number(float(moment_peak[i])),
                format_ratio(float(moment_normalised[i]), float(result.reference_moment)),
                "-" if at is None else format_number(float(roll_amplitude[at])),
            ]
        )
    out.append(
        NumberTable(
            "Residual with the proposal (all free forces and moments, and roll)",
            [
                Column("order", key=True),
                Column("force peak", "N"),
                Column("force peak / F1"),
                Column("moment peak", "N m"),
                Column("moment peak / (F1 a)"),
                Column("roll", "N m"),
            ],
            rows,
            notes=_pitch_note(result),
        )
    )
    return out


def render_factor_study(study: Mapping[str, Any]) -> list[RenderableType]:
    """Rich renderables of a balance-factor study (:mod:`balance.studies.factor`: its Dataset,
    or any mapping of its variable names to arrays)."""
    from rich.text import Text

    columns = [
        Column("balance factor", "%", key=True),
        Column("vertical peak", "N"),
        Column("horizontal peak", "N"),
        Column("moment peak", "N m"),
    ]
    bearing_columns = {  # with --bearings (balance.studies.factor_bearings)
        "study_largest_main_load": Column("largest main load", "N"),
        "study_largest_internal_moment": Column("largest internal moment", "N m"),
    }
    present = [name for name in bearing_columns if name in study]
    columns += [bearing_columns[name] for name in present]
    names = ["study_vertical_peak", "study_horizontal_peak", "study_moment_peak", *present]
    values = [np.asarray(study[name]) for name in names]
    rows = [
        [f"{100 * f:.4g}", *(format_number(float(column[i])) for column in values)]
        for i, f in enumerate(np.asarray(study["study_factor"]))
    ]
    best = float(np.asarray(study["optimal_balance_factor"]))
    return [
        NumberTable(
            "Balance factor study: residual first order (rotating masses balanced in full)",
            columns,
            rows,
        ),
        Text(f"Factor minimising the larger force peak: {best:.1%}"),
    ]
