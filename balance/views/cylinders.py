"""Views of the ``cylinders`` section: each cylinder's stroke and top dead centre, and its
link rod (:mod:`balance.core.cylinders`)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.views.polar import format_number, json_number

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.cylinders import DeadCentres
    from balance.core.result import Result
    from balance.views.fitted import NumberTable

__all__ = ["cylinders_table", "json_block", "report_columns", "tables"]


def _part(result: Result) -> DeadCentres:
    part: DeadCentres = result.part("cylinders")
    return part


def _cylinder_entries(result: Result) -> list[dict[str, Any]]:
    """The ``cylinders`` list of the JSON (docs/cli.md, "JSON output"): number,
    actual stroke [m], TDC crank angle [deg] in [0, 360); a link cylinder also gets its
    ``link`` (master, pin and rod)."""
    part = _part(result)
    links = result.engine.links
    entries = []
    for i, (stroke, tdc) in enumerate(zip(part.stroke, np.degrees(part.tdc), strict=True)):
        entry: dict[str, Any] = {
            "number": i + 1,
            "stroke_m": json_number(stroke),
            "tdc_crank_deg": json_number(tdc),
        }
        if links is not None and links.master[i] >= 0:
            entry["link"] = {
                "master": int(links.master[i]) + 1,
                "pin_radius_m": json_number(links.pin_radius[i]),
                "pin_angle_deg": json_number(math.degrees(float(links.pin_angle[i]))),
                "length_m": json_number(result.engine.conrod_length[i]),
            }
        entries.append(entry)
    return entries


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``cylinders``.

    Parameters
    ----------
    result : Result
        An analysis with the ``cylinders`` section.

    Returns
    -------
    dict
        ``{"cylinders": [...]}``: each cylinder's number, actual stroke [m], TDC crank angle
        [deg] in [0, 360), and a link cylinder's ``link`` (docs/cli.md, "JSON output").
    """
    return {"cylinders": _cylinder_entries(result)}


def cylinders_table(result: Result) -> NumberTable:
    """Each cylinder's actual stroke and TDC crank angle, and its link rod if it has one.

    Parameters
    ----------
    result : Result
        An analysis with the ``cylinders`` section.

    Returns
    -------
    NumberTable
    """
    from balance.views.fitted import Column, NumberTable

    part = _part(result)
    engine = result.engine
    links = engine.links
    tdc = np.degrees(part.tdc)
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
            format_number(float(part.stroke[i]) * 1e3, 6),
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


def tables(result: Result) -> list[RenderableType]:
    """The section's table: :func:`cylinders_table`.

    Parameters
    ----------
    result : Result
        An analysis with the ``cylinders`` section.

    Returns
    -------
    list of rich.console.RenderableType
    """
    return [cylinders_table(result)]


def report_columns(result: Result) -> list[tuple[str, list[str]]]:
    """The section's columns in the report's table of cylinders: each cylinder's actual
    stroke and the crank angle of its TDC.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`, with the ``cylinders`` section.

    Returns
    -------
    list of (str, list of str)
        Each column's header and its cells, one per cylinder (stroke [mm], TDC [deg]).
    """
    part = _part(result)
    tdc = np.degrees(part.tdc)
    return [
        ("actual stroke [mm]", [format_number(float(v) * 1e3) for v in part.stroke]),
        ("TDC at [deg]", [format_number(float(v)) for v in tdc]),
    ]
