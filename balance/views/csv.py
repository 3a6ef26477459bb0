"""CSV view of a :class:`~balance.core.result.Result`: one row per order (no xarray)."""

from __future__ import annotations

import csv
import io
import math
from typing import TYPE_CHECKING

import numpy as np

from balance.views.polar import phase_deg, safe_ratio

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.result import Result

__all__ = ["to_csv"]


def _cell(value: float) -> str:
    return "" if not math.isfinite(value) else repr(float(value))


def to_csv(result: Result) -> str:
    """Per-order table: forward and backward magnitude and phase, peak, normalised peak.

    Columns carry their units in brackets, e.g. ``force_forward_magnitude [N]``.  Roll is
    joined on the same order where the roll orders match the orders.
    """
    p = result.phasors
    parts = [("force", "N", p.force_forward, p.force_backward, result.reference_force)]
    if result.has_moments:
        parts.append(
            ("moment", "N m", p.moment_forward, p.moment_backward, result.reference_moment)
        )
    header = ["order"]
    blocks = []
    for what, unit, forward, backward, reference in parts:
        both = np.stack([forward, backward], axis=-1)
        magnitude = np.abs(both)
        phase = phase_deg(both)
        peak = magnitude[..., 0] + magnitude[..., 1]
        for j, rotation in enumerate(("forward", "backward")):
            header += [f"{what}_{rotation}_magnitude [{unit}]", f"{what}_{rotation}_phase [deg]"]
            blocks += [magnitude[:, j], phase[:, j]]
        header += [f"{what}_peak [{unit}]", f"{what}_peak_normalised [1]"]
        blocks += [peak, safe_ratio(peak, reference)]
    roll_at: dict[float, int] = {}
    if result.roll is not None:
        header += ["roll_amplitude [N m]", "roll_phase [deg]"]
        roll_at = {float(k): i for i, k in enumerate(result.roll_orders)}
        roll_amplitude = np.abs(result.roll)
        roll_phase = phase_deg(result.roll)
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    for i, k in enumerate(p.orders):
        row = [str(int(k))] + [_cell(float(block[i])) for block in blocks]
        at = roll_at.get(float(k))
        if at is not None:
            row += [_cell(float(roll_amplitude[at])), _cell(float(roll_phase[at]))]
        elif result.roll is not None:
            row += ["", ""]
        writer.writerow(row)
    return buffer.getvalue()
