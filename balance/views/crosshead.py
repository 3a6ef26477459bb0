"""Views of the ``guide_forces`` section: each crosshead cylinder's largest guide force and
MAN B&W's H-type and X-type guide-force moments per order (:mod:`balance.core.crosshead`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.phasors import phase_deg
from balance.views.fitted import Column, NumberTable
from balance.views.polar import format_number, json_number, order_value

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.crosshead import GuideForces
    from balance.core.result import Result

__all__ = [
    "REPORT_TITLE",
    "csv_columns",
    "guide_force_table",
    "json_block",
    "report_section",
    "tables",
]


def _part(result: Result) -> GuideForces:
    part: GuideForces = result.part("guide_forces")
    return part


def _entries(orders: Any, values: Any) -> list[dict[str, Any]]:
    amplitude = np.abs(values)
    phase = phase_deg(values)
    return [
        {
            "order": order_value(k),
            "amplitude": json_number(amplitude[i]),
            "phase_deg": json_number(phase[i]),
        }
        for i, k in enumerate(np.asarray(orders))
    ]


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON.

    Parameters
    ----------
    result : Result
        An analysis with the ``guide_forces`` section.

    Returns
    -------
    dict
        ``guide_force_moments``: ``H`` and ``X`` per order (amplitude [N m], phase [deg]) and
        ``lever_m`` per cylinder [m]; and ``cylinders``, whose entries the writer merges
        into the ``cylinders`` section's: a crosshead cylinder's ``guide_force_max_N`` [N]
        (docs/crossheads.md).
    """
    g = _part(result)
    cylinders = [
        {"guide_force_max_N": json_number(g.maximum[i])} if g.crossheads[i] else {}
        for i in range(g.crossheads.size)
    ]
    return {
        "guide_force_moments": {
            "H": _entries(g.orders, g.h_type),
            "X": _entries(g.orders, g.x_type),
            "lever_m": [json_number(v) for v in g.lever],
            "gas": bool(g.with_gas),
        },
        "cylinders": cylinders,
    }


def guide_force_table(result: Result) -> NumberTable:
    """MAN B&W's guide-force moments per order, and each cylinder's largest guide force.

    Parameters
    ----------
    result : Result
        An analysis with the ``guide_forces`` section.

    Returns
    -------
    NumberTable
    """
    g = _part(result)
    columns = [
        Column("order", key=True),
        Column("H-type", "kN m"),
        Column("H phase", "deg"),
        Column("X-type", "kN m"),
        Column("X phase", "deg"),
    ]
    h_phase, x_phase = phase_deg(g.h_type), phase_deg(g.x_type)
    rows = [
        [
            format_number(float(k)),
            format_number(float(abs(g.h_type[i])) / 1e3, 6),
            format_number(float(h_phase[i]), 6),
            format_number(float(abs(g.x_type[i])) / 1e3, 6),
            format_number(float(x_phase[i]), 6),
        ]
        for i, k in enumerate(g.orders)
    ]
    largest = ", ".join(
        f"{i + 1}: {format_number(float(g.maximum[i]) / 1e3)}"
        for i in range(g.crossheads.size)
        if g.crossheads[i]
    )
    what = "gas forces included" if g.with_gas else "inertia only (no gas: section)"
    return NumberTable(
        f"Guide-force moments (MAN B&W H-type sum s N, X-type sum s N dz / L), {what}",
        columns,
        rows,
        notes=[f"largest guide force per cylinder [kN]: {largest}"],
    )


def tables(result: Result) -> list[RenderableType]:
    """The section's table: :func:`guide_force_table`.

    Parameters
    ----------
    result : Result
        An analysis with the ``guide_forces`` section.

    Returns
    -------
    list of rich.console.RenderableType
    """
    return [guide_force_table(result)]


def csv_columns(result: Result) -> list[tuple[str, dict[float, float]]]:
    """The section's columns of the per-order CSV, joined on the order.

    Parameters
    ----------
    result : Result
        An analysis with the ``guide_forces`` section.

    Returns
    -------
    list of (str, dict)
        Each column's header (with its unit) and its values by order [N m, deg].
    """
    g = _part(result)
    orders = [float(k) for k in g.orders]
    out = []
    for name, values in (("h", g.h_type), ("x", g.x_type)):
        amplitude, phase = np.abs(values), phase_deg(values)
        out.append(
            (
                f"guide_force_moment_{name}_amplitude [N m]",
                dict(zip(orders, amplitude.tolist(), strict=True)),
            )
        )
        out.append(
            (
                f"guide_force_moment_{name}_phase [deg]",
                dict(zip(orders, phase.tolist(), strict=True)),
            )
        )
    return out


REPORT_TITLE = "Crosshead guide forces"


def report_section(result: Result, figures: bool) -> str:
    """HTML of the report's guide-force section: :func:`guide_force_table` (MAN B&W's H-type
    and X-type guide-force moments per order) and each cylinder's largest guide force.

    Parameters
    ----------
    result : Result
        An analysis with the ``guide_forces`` section.
    figures : bool
        Whether figures are drawn (the section has none).

    Returns
    -------
    str
    """
    from balance.views.report import escape, html_table

    table = guide_force_table(result)
    html = html_table([c.header for c in table.columns], table.rows, table.title)
    notes = "".join(f"<li>{escape(note)}</li>" for note in table.notes)
    return html + (f'\n<ul class="note notes">{notes}</ul>' if notes else "")
