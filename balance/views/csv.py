"""CSV view of a :class:`~balance.core.result.Result`: one row per order (no xarray).

The columns are the per-order outputs of the catalogue (:data:`balance.core.catalogue.BASE`),
each read through its getter, and those a section's views add (``csv_columns``,
:mod:`balance.views.sections`).
"""

from __future__ import annotations

import csv
import io
import math
from typing import TYPE_CHECKING

from balance.core.catalogue import BASE
from balance.views.sections import views_of

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.result import Result

__all__ = ["to_csv"]


def _cell(value: float) -> str:
    return "" if not math.isfinite(value) else repr(float(value))


def to_csv(result: Result) -> str:
    """Per-order table: forward and backward magnitude and phase, peak, normalised peak.

    Columns carry their units in brackets, e.g. ``force_forward_magnitude [N]``.  Roll is
    joined on the same order where the roll orders match the orders.  A section whose
    views define ``csv_columns`` adds its columns after these (:mod:`balance.views.sections`).

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    str
        The CSV text, one row per order.
    """
    values = {output.name: output for output in BASE}
    parts = [("force", "N")]
    if result.has_moments:
        parts.append(("moment", "N m"))
    header = ["order"]
    blocks = []
    for what, unit in parts:
        magnitude = values[f"reciprocating_{what}_magnitude"].get(result)
        phase = values[f"reciprocating_{what}_phase"].get(result)
        for j, rotation in enumerate(("forward", "backward")):
            header += [f"{what}_{rotation}_magnitude [{unit}]", f"{what}_{rotation}_phase [deg]"]
            blocks += [magnitude[:, j], phase[:, j]]
        header += [f"{what}_peak [{unit}]", f"{what}_peak_normalised [1]"]
        blocks += [
            values[f"reciprocating_{what}_peak"].get(result),
            values[f"reciprocating_{what}_peak_normalised"].get(result),
        ]
    roll_at: dict[float, int] = {}
    if result.roll is not None:
        header += ["roll_amplitude [N m]", "roll_phase [deg]"]
        roll_at = {float(k): i for i, k in enumerate(result.roll_orders)}
        roll_amplitude = values["roll_amplitude"].get(result)
        roll_phase = values["roll_phase"].get(result)
    # the sections' columns by order (views.sections: a views module's csv_columns)
    extra: list[tuple[str, dict[float, float]]] = []
    for _, views in views_of(result):
        extra += getattr(views, "csv_columns", lambda result: [])(result)
    header += [name for name, _ in extra]
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    for i, k in enumerate(result.orders):
        row = [str(int(k))] + [_cell(float(block[i])) for block in blocks]
        at = roll_at.get(float(k))
        if at is not None:
            row += [_cell(float(roll_amplitude[at])), _cell(float(roll_phase[at]))]
        elif result.roll is not None:
            row += ["", ""]
        row += [_cell(column.get(float(k), math.nan)) for _, column in extra]
        writer.writerow(row)
    return buffer.getvalue()
