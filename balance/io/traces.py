"""Cylinder pressure traces: a CSV file of crank angle and absolute pressure.

Every problem is reported as ``file:line: gas.pressure_trace: ...`` with what would be valid.
"""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from balance.core.errors import LayoutError, Location

__all__ = ["MAX_TRACE_ROWS", "MAX_TRACE_STEP_DEG", "read_pressure_trace"]

FloatArray = NDArray[np.float64]

#: Largest gap between two points of a pressure trace, wrap-around included [deg].
MAX_TRACE_STEP_DEG = 10.0
#: Most rows read from a pressure trace.
MAX_TRACE_ROWS = 200_000


def _unit_factor(header: str, where: Location, field: str) -> float:
    """Pascals per unit of a pressure column header such as ``pressure [bar]``."""
    from balance.io.units import UnitProblem, parse_quantity

    match = re.search(r"\[(.+?)\]", header)
    if not match:
        return 1.0
    try:
        return parse_quantity(f"1 {match.group(1).strip()}", "pressure")
    except UnitProblem as exc:
        raise LayoutError(str(exc), where, field=field, valid=exc.valid) from None


def read_pressure_trace(
    path: Path, cycle_deg: float, field: str = "gas.pressure_trace"
) -> tuple[FloatArray, FloatArray]:
    """Read a cylinder pressure trace.

    Parameters
    ----------
    path : Path
        CSV file: two columns, crank angle from firing TDC [deg] and absolute pressure (Pa,
        or the unit in brackets of an optional header line, e.g. ``pressure [bar]``).
        Lines starting with ``#`` and blank lines are skipped.
    cycle_deg : float
        Length of the cycle [deg] the trace must cover.
    field : str
        Field name used in error messages.

    Returns
    -------
    angle, pressure : ndarray
        Angles [deg] (strictly increasing, spanning less than one cycle) and pressures [Pa].

    Raises
    ------
    LayoutError
        Naming the file, the line and the problem: a missing or unreadable file, a row that
        is not two numbers, angles that do not increase, a negative pressure, or a trace
        that does not cover the cycle (a gap over :data:`MAX_TRACE_STEP_DEG`).
    """
    name = str(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) else "not UTF-8 text"
        raise LayoutError(
            f"cannot read the trace ({reason})", Location(name), field=field
        ) from None
    angles: list[float] = []
    pressures: list[float] = []
    lines: list[int] = []
    factor = 1.0
    seen_data = False
    for number, row in enumerate(csv.reader(text.splitlines()), start=1):
        where = Location(name, number)
        cells = [c.strip() for c in row]
        if not cells or all(not c for c in cells) or cells[0].startswith("#"):
            continue
        if len(cells) != 2:
            raise LayoutError(
                f"{len(cells)} columns",
                where,
                field=field,
                valid="two columns: crank angle [deg from firing TDC], absolute pressure",
            )
        try:
            angle, pressure = float(cells[0]), float(cells[1])
        except ValueError:
            if not seen_data and not angles:
                factor = _unit_factor(cells[1], where, field)
                seen_data = True
                continue
            raise LayoutError(
                f"cannot read {','.join(cells)!r} as two numbers",
                where,
                field=field,
                valid="crank angle in deg and absolute pressure, e.g. '-180,1.0e5'",
            ) from None
        seen_data = True
        if not (math.isfinite(angle) and math.isfinite(pressure)):
            raise LayoutError("not a finite number", where, field=field)
        pressure *= factor
        if pressure < 0:
            raise LayoutError(
                f"pressure {pressure:g} Pa is negative",
                where,
                field=field,
                valid="absolute pressure, zero or more",
            )
        if angles and angle <= angles[-1]:
            raise LayoutError(
                f"crank angle {angle:g} deg does not increase (previous {angles[-1]:g} deg)",
                where,
                field=field,
                valid="angles in strictly increasing order over one cycle",
            )
        angles.append(angle)
        pressures.append(pressure)
        lines.append(number)
        if len(angles) > MAX_TRACE_ROWS:
            raise LayoutError(f"more than {MAX_TRACE_ROWS} rows", where, field=field)
    if len(angles) < 8:
        raise LayoutError(
            f"{len(angles)} data rows",
            Location(name, lines[-1] if lines else None),
            field=field,
            valid=f"a trace over the whole {cycle_deg:g} deg cycle, every {MAX_TRACE_STEP_DEG:g} "
            "deg or closer",
        )
    span = angles[-1] - angles[0]
    if span > cycle_deg + 1e-9:
        raise LayoutError(
            f"the trace spans {span:g} deg, more than the {cycle_deg:g} deg cycle",
            Location(name, lines[-1]),
            field=field,
            valid=f"one cycle, e.g. -{cycle_deg / 2:g} to {cycle_deg / 2:g} deg",
        )
    if abs(span - cycle_deg) <= 1e-9:  # both ends given: keep one
        angles.pop()
        pressures.pop()
        lines.pop()
    a = np.asarray(angles)
    gaps = np.diff(np.append(a, a[0] + cycle_deg))
    worst = int(np.argmax(gaps))
    if gaps[worst] > MAX_TRACE_STEP_DEG:
        line = lines[worst]
        raise LayoutError(
            f"the trace does not cover the {cycle_deg:g} deg cycle: a gap of {gaps[worst]:g} deg "
            f"after {a[worst]:g} deg",
            Location(name, line),
            field=field,
            valid=f"points every {MAX_TRACE_STEP_DEG:g} deg or closer over the whole cycle",
        )
    return a, np.asarray(pressures)
