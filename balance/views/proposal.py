"""Views of the ``proposal`` section: the counterweights and balance shafts proposed, and
what remains with them (:mod:`balance.core.proposal`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.phasors import phase_deg, safe_ratio
from balance.views.fitted import Column, NumberTable
from balance.views.json import roll_entries
from balance.views.polar import format_number, json_number
from balance.views.table import format_ratio, pitch_note

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.balancing import Proposal
    from balance.core.proposal import ProposalResult
    from balance.core.result import Result

__all__ = ["json_block", "proposal_entries", "render_proposal", "tables"]


def _part(result: Result) -> ProposalResult:
    part: ProposalResult = result.part("proposal")
    return part


def proposal_entries(proposal: Proposal) -> dict[str, Any]:
    """The proposal's settings, notes, counterweights and balance shafts as JSON data."""
    counterweights = [
        {
            "z_m": json_number(c.z),
            "mass_kg": json_number(c.mass),
            "radius_m": json_number(c.radius),
            "angle_deg": json_number(c.angle_deg),
        }
        for c in proposal.counterweights
    ]
    shafts = []
    for s in proposal.shafts:
        unbalance = np.array([u for _, u in s.planes], dtype=np.complex128)
        angle = phase_deg(unbalance)
        planes = [
            {
                "z_m": float(z),
                "unbalance_kgm": json_number(np.abs(unbalance[j])),
                "angle_deg": json_number(angle[j]),
            }
            for j, (z, _) in enumerate(s.planes)
        ]
        shafts.append(
            {
                "speed_ratio": int(s.speed_ratio),
                "x_m": json_number(s.x),
                "y_m": json_number(s.y),
                "position_from": {"x": s.x_from, "y": s.y_from},
                "planes": planes,
            }
        )
    factor = proposal.balance_factor
    return {
        "strategy": proposal.strategy,
        "orders": [int(k) for k in proposal.orders],
        "balance_factor": None if factor is None else float(factor),
        "cancel_roll": bool(proposal.cancel_roll),
        "notes": [n for n in proposal.notes if n],
        "counterweights": counterweights,
        "balance_shafts": shafts,
    }


def _residual_peaks(result: Result, quantity: Any, reference: float) -> list[dict[str, Any]]:
    residual = _part(result).residual
    peak = residual.peak(quantity)
    normalised = safe_ratio(peak, reference)
    return [
        {
            "order": int(k),
            "peak": json_number(peak[i]),
            "peak_normalised": json_number(normalised[i]),
        }
        for i, k in enumerate(np.asarray(residual.orders))
    ]


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``proposal`` with its ``residual``."""
    part = _part(result)
    return {
        "proposal": proposal_entries(part.proposal)
        | {
            "residual": {
                "force": _residual_peaks(result, "force", result.reference_force),
                "moment": _residual_peaks(result, "moment", result.reference_moment),
                "roll": roll_entries(result.roll_orders, part.residual_roll),
            }
        }
    }


def render_proposal(result: Result) -> list[RenderableType]:
    """Rich renderables of the balancing proposal and its residual: a line of the choices,
    the proposal's notes (one line each), the counterweights, the balance shafts and the
    residual."""
    from rich.text import Text

    part = _part(result)
    proposal = part.proposal
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
    force_peak = part.residual.peak("force")
    moment_peak = part.residual.peak("moment")
    force_normalised = safe_ratio(force_peak, result.reference_force)
    moment_normalised = safe_ratio(moment_peak, result.reference_moment)
    roll_at = {float(k): i for i, k in enumerate(result.roll_orders)}
    assert part.residual_roll is not None  # a proposal is made with the roll
    roll_amplitude = np.abs(part.residual_roll)
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
            notes=pitch_note(result),
        )
    )
    return out


def tables(result: Result) -> list[RenderableType]:
    """The section's tables: :func:`render_proposal`."""
    return render_proposal(result)


#: The heading of the section in the HTML report.
REPORT_TITLE = "Balancing proposal and residual"

#: What the report says where the analysis has no proposal.
REPORT_ABSENT = "No balancing proposal in this result (analysed without one)."


def report_section(result: Result, figures: bool) -> str:
    """HTML of the report's proposal section (:func:`balance.views.report.proposal_section`)."""
    from balance.views.report import proposal_section

    return proposal_section(result, figures)
