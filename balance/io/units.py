"""Units at the boundary: one pint registry, quantities in, SI floats out.

Layout files give quantities as strings with units (``"86 mm"``, ``"6000 rpm"``) or as
plain numbers in SI base units (angles: degrees).  This module turns each into a float in
the unit the core computes in, and nothing past it sees a unit.

The registry is built lazily on first use, so importing :mod:`balance` does not pay for it.

Speeds deserve care.  pint treats the radian as dimensionless, so it will happily convert
``6000 rpm`` to 628 Hz and ``100 Hz`` to 100 rad/s.  Here a speed written with an angle
unit (``rpm``, ``rad/s``, ``deg/s``, ``rev/min``, ``turn/s``) is converted to rad/s as an
angular speed, ``Hz`` (or ``rps``) means revolutions per second, and a bare ``1/s`` is
refused as ambiguous.
"""

from __future__ import annotations

import math
import re
from functools import cache
from typing import TYPE_CHECKING, Any

from balance.core.speed import RAD_PER_S_PER_RPM

if TYPE_CHECKING:  # pragma: no cover
    import pint

__all__ = [
    "KINDS",
    "UnitProblem",
    "parse_quantity",
    "registry",
]


class UnitProblem(ValueError):
    """A value that cannot be read as the quantity asked for.

    ``args[0]`` says what is wrong; :attr:`valid` says what would be valid.
    """

    def __init__(self, message: str, valid: str) -> None:
        super().__init__(message)
        self.valid = valid


@cache
def registry() -> pint.UnitRegistry:
    """The one pint unit registry of balance (built on first use)."""
    import pint

    ureg: pint.UnitRegistry = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
    ureg.define("@alias revolution = rev")
    return ureg


# kind: (SI target unit, plain-number meaning, example, largest sane magnitude)
KINDS: dict[str, tuple[str, str, str, float]] = {
    "length": ("m", "metres", "'86 mm'", 100.0),
    "mass": ("kg", "kilograms", "'0.45 kg'", 1e6),
    "inertia": ("kg * m ** 2", "kg m^2", "'1.9e-3 kg m^2'", 1e6),
    "angle": ("deg", "degrees", "'90 deg'", 1e6),
    "speed": ("rad / s", "rad/s", "'6000 rpm'", 1e8),
    "fraction": ("", "a fraction (0.5 = 50 %)", "'50 %'", 1e3),
    "pressure": ("Pa", "pascals", "'1 bar'", 1e10),
    "volume": ("m ** 3", "cubic metres", "'2.0 L'", 1e3),
}

_NUMBER = re.compile(
    r"^\s*([+-]?(?:(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?|(?:nan|inf(?:inity)?)(?![a-z])))"
    r"\s*(.*?)\s*$",
    re.IGNORECASE,
)
_BIG_EXPONENT = re.compile(r"(\*\*|\^)\s*[+-]?\d{3,}")
_ANGLE_NAMES = ("radian", "degree", "turn", "revolution", "arcminute", "arcsecond", "grade")
_DIMENSION_NAMES = {
    "[length]": "a length",
    "[mass]": "a mass",
    "[mass] * [length] ** 2": "a moment of inertia",
    "1 / [time]": "a speed",
    "dimensionless": "a plain number",
    "[mass] / [length] / [time] ** 2": "a pressure",
    "[length] ** 3": "a volume",
    "[time]": "a time",
}


def _dimension_name(unit: Any) -> str:
    text = str(unit.dimensionality)
    return _DIMENSION_NAMES.get(text, text)


def _has_angle(unit: Any) -> bool:
    ureg = registry()
    for name in unit._units:
        root = ureg.get_root_units(name)[1]
        if "radian" in root._units or any(a in name for a in _ANGLE_NAMES):
            return True
    return False


def parse_quantity(value: Any, kind: str) -> float:
    """Read a quantity as a float in the SI unit of ``kind``.

    Parameters
    ----------
    value : str or float or int
        ``"86 mm"``, ``"6000 rpm"``, ``"50 %"``... or a plain number in SI base units
        (degrees for angles, a fraction for fractions).
    kind : str
        One of :data:`KINDS`: ``length`` [m], ``mass`` [kg], ``inertia`` [kg m^2],
        ``angle`` [deg], ``speed`` [rad/s], ``fraction`` [1], ``pressure`` [Pa].

    Returns
    -------
    float
        The value in the SI unit of ``kind`` (degrees for angles).

    Raises
    ------
    UnitProblem
        If the value is not a finite number of the right dimension.

    Examples
    --------
    >>> round(parse_quantity("6000 rpm", "speed"), 3)
    628.319
    >>> parse_quantity("86 mm", "length")
    0.086
    """
    target, plain, example, largest = KINDS[kind]
    valid = f"give {kind} with a unit, e.g. {example}, or a plain number in {plain}"
    if isinstance(value, bool) or value is None:
        raise UnitProblem(f"expected {kind}, got {value!r}", valid)
    if isinstance(value, int | float):
        number = float(value)
        result = number
    elif isinstance(value, str):
        result = _from_text(value, kind, valid)
    else:
        shown = "a list" if isinstance(value, list) else "a mapping"
        raise UnitProblem(f"expected {kind}, got {shown}", valid)
    if not math.isfinite(result):
        raise UnitProblem(f"{value!r} is not a finite number", valid)
    if abs(result) > largest:
        raise UnitProblem(
            f"{value!r} is out of range for {kind}",
            f"magnitude at most {largest:g} {target or '(fraction)'}",
        )
    return result


# Common units read without pint (importing pint and building its registry costs about
# half a second): unit text -> (kind, factor to the kind's SI unit).  Each factor is the
# exact definition pint uses; tests check every entry against pint.
_FAST_UNITS: dict[str, tuple[str, float]] = {
    "m": ("length", 1.0),
    "mm": ("length", 1e-3),
    "cm": ("length", 1e-2),
    "in": ("length", 0.0254),
    "inch": ("length", 0.0254),
    "ft": ("length", 0.3048),
    "kg": ("mass", 1.0),
    "g": ("mass", 1e-3),
    "lb": ("mass", 0.45359237),
    "deg": ("angle", 1.0),
    "degree": ("angle", 1.0),
    "degrees": ("angle", 1.0),
    "°": ("angle", 1.0),
    "rad": ("angle", 180.0 / math.pi),
    "rpm": ("speed", RAD_PER_S_PER_RPM),
    "rev/min": ("speed", RAD_PER_S_PER_RPM),
    "rad/s": ("speed", 1.0),
    "Hz": ("speed", 2.0 * math.pi),
    "%": ("fraction", 0.01),
    "percent": ("fraction", 0.01),
    "kg m^2": ("inertia", 1.0),
    "kg*m^2": ("inertia", 1.0),
    "kg m**2": ("inertia", 1.0),
    "kg*m**2": ("inertia", 1.0),
    "kg·m²": ("inertia", 1.0),
    "g cm^2": ("inertia", 1e-7),
    "kg cm^2": ("inertia", 1e-4),
    "Pa": ("pressure", 1.0),
    "kPa": ("pressure", 1e3),
    "MPa": ("pressure", 1e6),
    "bar": ("pressure", 1e5),
    "L": ("volume", 1e-3),
    "l": ("volume", 1e-3),
    "cc": ("volume", 1e-6),
    "cm^3": ("volume", 1e-6),
}


def _from_text(text: str, kind: str, valid: str) -> float:
    if len(text) > 80:
        raise UnitProblem("value text is too long", valid)
    match = _NUMBER.match(text)
    if not match:
        raise UnitProblem(f"cannot read {text!r} as {kind}", valid)
    number = float(match.group(1))
    if not math.isfinite(number):
        raise UnitProblem(f"{text!r} is not a finite number", valid)
    unit_text = match.group(2)
    if not unit_text:
        return number
    if _BIG_EXPONENT.search(unit_text):
        raise UnitProblem(f"unit {unit_text!r} has an absurd exponent", valid)
    fast = _FAST_UNITS.get(unit_text)
    if fast is not None:
        fast_kind, factor = fast
        if fast_kind == kind:
            return number * factor
        raise UnitProblem(
            f"{text!r} is {_KIND_ARTICLE[fast_kind]}, not {_KIND_ARTICLE.get(kind, kind)}", valid
        )
    if unit_text.startswith("/"):
        unit_text = "1" + unit_text
    ureg = registry()
    try:
        unit = ureg.parse_units(unit_text)
    except Exception as exc:  # pint raises many types for bad units
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise UnitProblem(f"unknown unit {unit_text!r} ({detail})", valid) from None
    if kind == "speed":
        return _speed(number, unit, text, valid)
    try:
        return float(ureg.Quantity(number, unit).to(KINDS[kind][0]).magnitude)
    except Exception:
        raise UnitProblem(
            f"{text!r} is {_dimension_name(unit)}, not {_KIND_ARTICLE.get(kind, kind)}", valid
        ) from None


_KIND_ARTICLE = {
    "length": "a length",
    "mass": "a mass",
    "inertia": "a moment of inertia",
    "angle": "an angle",
    "speed": "a speed",
    "fraction": "a fraction",
    "pressure": "a pressure",
    "volume": "a volume",
}


def _speed(number: float, unit: Any, text: str, valid: str) -> float:
    ureg = registry()
    if str(unit.dimensionality) != "1 / [time]":
        raise UnitProblem(f"{text!r} is {_dimension_name(unit)}, not a speed", valid)
    if _has_angle(unit):
        return float(ureg.Quantity(number, unit).to("rad / s").magnitude)
    names = set(unit._units)
    if names <= {"hertz", "kilohertz"}:
        revs_per_second = float(ureg.Quantity(number, unit).to("Hz").magnitude)
        return 2.0 * math.pi * revs_per_second
    raise UnitProblem(
        f"{text!r} is ambiguous for a speed (revolutions or radians per unit time?)",
        "write rpm, rad/s or Hz (revolutions per second)",
    )
