"""Units at the boundary: one pint registry, quantities in, SI floats out.

Layout files and the command line give quantities as strings with units (``"86 mm"``,
``"6000 rpm"``).  This module turns each into a float in the unit the core computes in, and
nothing past it sees a unit.

A dimensional quantity (a length, mass, moment of inertia, speed, pressure or volume) written as a
bare number is refused, with the unit it most likely has proposed (``6000`` for a speed: "give a
unit, e.g. '6000 rpm'"; docs/layout-format.md, "Quantities and units"); only 0 may be bare.  Angles
may be bare numbers, read as degrees; fractions may be bare (0.5 = 50 %), but a bare fraction above
2 is refused as a likely percentage (``60`` -> "'60 %'").

Unit names are read as written.  A name of two or more letters, each of its words two or
more letters long, whose other capitalisations are no unit of the same kind, is also read
in any letter case (:data:`ANY_CASE`: ``RPM``, ``Rpm``, ``KG``, ``BAR``, ``DEG``, ``HZ``...).
Where case tells two units of one kind apart (``mm`` and ``Mm``, ``MPa`` and ``mPa``,
``mg`` and ``Mg``) or the name is one letter (``g`` and the gauss ``G``), another case is
refused with the readings named (:data:`CASE_MATTERS`).

The registry is built lazily on first use, so importing :mod:`balance` does not pay for it.

Speeds deserve care.  pint treats the radian as dimensionless, so it will happily convert
``6000 rpm`` to 628 Hz and ``100 Hz`` to 100 rad/s.  Here a speed written with an angle
unit (``rpm``, ``rad/s``, ``deg/s``, ``rev/min``, ``turn/s``) is converted to rad/s as an
angular speed, ``Hz`` (or ``rps``) means revolutions per second, and a bare ``1/s`` is
refused as ambiguous.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Callable
from functools import cache
from typing import TYPE_CHECKING, Any

from balance.core.speed import RAD_PER_S_PER_RPM

if TYPE_CHECKING:  # pragma: no cover
    import pint

__all__ = [
    "ANY_CASE",
    "ARITHMETIC_KINDS",
    "CASE_MATTERS",
    "DIMENSIONAL",
    "KINDS",
    "UnitProblem",
    "check_thousands",
    "likely_unit",
    "parse_quantity",
    "registry",
]


class UnitProblem(ValueError):
    """A value that cannot be read as the quantity asked for.

    ``args[0]`` says what is wrong; :attr:`valid` says what would be valid;
    :attr:`suggestion` is the text proposed instead (``"6000 rpm"``), when there is one.
    """

    def __init__(self, message: str, valid: str, suggestion: str | None = None) -> None:
        super().__init__(message)
        self.valid = valid
        self.suggestion = suggestion


@cache
def registry() -> pint.UnitRegistry:
    """The one pint unit registry of balance (built on first use)."""
    import pint

    ureg: pint.UnitRegistry = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
    ureg.define("@alias revolution = rev")
    return ureg


# kind: (SI target unit, what a bare number means, example, largest sane magnitude)
KINDS: dict[str, tuple[str, str, str, float]] = {
    "length": ("m", "", "'86 mm'", 100.0),
    "mass": ("kg", "", "'0.45 kg'", 1e6),
    "inertia": ("kg * m ** 2", "", "'1.9e-3 kg m^2'", 1e6),
    "angle": ("deg", "degrees", "'90 deg'", 1e6),
    "speed": ("rad / s", "", "'6000 rpm'", 1e8),
    "fraction": ("", "a fraction (0.5 = 50 %)", "'50 %'", 1e3),
    "pressure": ("Pa", "", "'1 bar'", 1e10),
    "volume": ("m ** 3", "", "'2.0 L'", 1e3),
    "torque": ("N * m", "", "'150 N m'", 1e9),
    "rotational_stiffness": ("N * m / radian", "", "'1.5e6 N m/rad'", 1e13),
    "rotational_damping": ("N * m * s / radian", "", "'25 N m s/rad'", 1e10),
    # the layout's own check bounds an energy (balance.io.spec_blocks)
    "energy": ("J", "", "'1.6 kJ'", math.inf),
}

#: Kinds whose bare numbers (other than 0) are refused: every kind with a dimension.
DIMENSIONAL = frozenset(k for k, (_, bare, _, _) in KINDS.items() if not bare)

#: Largest bare number read as a fraction; above it a bare number is taken for a
#: percentage written without its sign (``balance_factor: 60``).
LARGEST_BARE_FRACTION = 2.0

_NUMBER = re.compile(
    r"^\s*([+-]?(?:(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?|(?:nan|inf(?:inity)?)(?![a-z])))"
    r"\s*(.*?)\s*$",
    re.IGNORECASE,
)
# a number written with thousands separators: 13,000 / 13 000 / 13_000 / 13'000
_THOUSANDS = re.compile(r"^\s*([+-]?\d{1,3}(?:[,_' ]\d{3})+(?:\.\d*)?)(?![\d,_'])\s*(.*?)\s*$")
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


# an operator and a number or parenthesis after the unit's start: arithmetic after the unit
_AFTER_UNIT = re.compile(r"[-+*/\u2212\u00d7]\s*[\d.(]")


def _one_angle_unit(unit: Any) -> bool:
    """Whether a unit is one unit of angle to the first power (``deg``, ``grad``; not
    ``deg**2`` or ``percent``, which pint would also convert to degrees)."""
    powers = list(unit._units.values())
    return len(powers) == 1 and powers[0] == 1 and _has_angle(unit)


def _has_angle(unit: Any) -> bool:
    ureg = registry()
    for name in unit._units:
        root = ureg.get_root_units(name)[1]
        if "radian" in root._units or any(a in name for a in _ANGLE_NAMES):
            return True
    return False


def likely_unit(number: float, kind: str) -> str:
    """The unit a bare number of this kind most likely had in mind.

    Lengths of 1 and more are taken for millimetres, smaller ones for metres; masses of
    10 and more for grams (a piston's, a rod's), smaller ones for kilograms; pressures of
    1000 and more for pascals, smaller ones for bar; volumes of 50 and more for cubic
    centimetres, smaller ones for litres; speeds for rpm; moments of inertia of 1 and
    more for kg cm^2 (a conrod's is about 20 kg cm^2), smaller ones for kg m^2; energies
    of 100 and more for joules, smaller ones for kilojoules (the heat released per
    cylinder and cycle is about a kilojoule).
    A field may know better (a powertrain's mass is in kilograms, its inertia in kg m^2):
    see :func:`parse_quantity`'s ``likely``.

    Parameters
    ----------
    number : float
        The bare number as written.
    kind : str
        The unit kind expected (:data:`KINDS`).

    Returns
    -------
    str
        The unit, as a user would write it (``"mm"``, ``"g"``, ``"rpm"`` …).
    """
    size = abs(number)
    if kind == "length":
        return "mm" if size >= 1 else "m"
    if kind == "mass":
        return "g" if size >= 10 else "kg"
    if kind == "pressure":
        return "Pa" if size >= 1000 else "bar"
    if kind == "volume":
        return "cc" if size >= 50 else "L"
    if kind == "inertia":
        return "kg cm^2" if size >= 1 else "kg m^2"
    if kind == "energy":
        return "J" if size >= 100 else "kJ"
    return {
        "speed": "rpm",
        "angle": "deg",
        "fraction": "%",
        "torque": "N m",
        "rotational_stiffness": "N m/rad",
        "rotational_damping": "N m s/rad",
    }[kind]


def _number_text(value: float | int | str) -> str:
    """A number as the user wrote it (text), or shortest-round-trip for a YAML number."""
    if isinstance(value, str):
        return value.strip()
    if isinstance(value, int):
        return str(value)
    return repr(float(value)) if not float(value).is_integer() else str(int(value))


def parse_quantity(value: Any, kind: str, likely: Callable[[float], str] | None = None) -> float:
    """Read a quantity as a float in the SI unit of ``kind``.

    Parameters
    ----------
    value : str or float or int
        ``"86 mm"``, ``"6000 rpm"``, ``"50 %"``...  A bare number (a YAML number, or
        text without a unit) is refused for a dimensional kind (:data:`DIMENSIONAL`)
        unless it is 0; for angles it is degrees, for fractions a fraction (at most
        :data:`LARGEST_BARE_FRACTION`).
    kind : str
        One of :data:`KINDS`: ``length`` [m], ``mass`` [kg], ``inertia`` [kg m^2],
        ``angle`` [deg], ``speed`` [rad/s], ``fraction`` [1], ``pressure`` [Pa],
        ``volume`` [m^3], ``torque`` [N m], ``rotational_stiffness`` [N m/rad],
        ``rotational_damping`` [N m s/rad], ``energy`` [J].
    likely : callable, optional
        The unit to propose for a bare number (given the number); default
        :func:`likely_unit`.

    Returns
    -------
    float
        The value in the SI unit of ``kind`` (degrees for angles).

    Raises
    ------
    UnitProblem
        If the value is not a finite number of the right dimension, or a bare number
        where a unit is required; its ``suggestion`` holds the proposed text.

    Examples
    --------
    >>> round(parse_quantity("6000 rpm", "speed"), 3)
    628.319
    >>> parse_quantity("86 mm", "length")
    0.086
    >>> parse_quantity("0", "length")
    0.0
    """
    target, plain, example, largest = KINDS[kind]
    valid = f"give {kind} with a unit, e.g. {example}" + (
        f", or a plain number in {plain}" if plain else ""
    )
    if isinstance(value, bool) or value is None:
        raise UnitProblem(f"expected {kind}, got {value!r}", valid)
    if isinstance(value, int | float):
        result = float(value)
        bare = True
    elif isinstance(value, str):
        result, bare = _from_text(value, kind, valid)
    else:
        shown = "a list" if isinstance(value, list) else "a mapping"
        raise UnitProblem(f"expected {kind}, got {shown}", valid)
    if not math.isfinite(result):
        raise UnitProblem(f"{value!r} is not a finite number", valid)
    if bare and result != 0:
        _check_bare(value, result, kind, likely)
    if abs(result) > largest:
        raise UnitProblem(
            f"{value!r} is out of range for {kind}",
            f"magnitude at most {largest:g} {target or '(fraction)'}",
        )
    return result


def _check_bare(
    value: Any, number: float, kind: str, likely: Callable[[float], str] | None
) -> None:
    """Refuse a bare number where a unit is required (or a percentage without its sign)."""
    written = _number_text(value)
    if kind in DIMENSIONAL:
        unit = (likely or (lambda n: likely_unit(n, kind)))(number)
        suggestion = f"{written} {unit}"
        raise UnitProblem(f"{written} has no unit", f"give a unit, e.g. '{suggestion}'", suggestion)
    if kind == "fraction" and abs(number) > LARGEST_BARE_FRACTION:
        suggestion = f"{written} %"
        raise UnitProblem(
            f"{written} is read as a fraction ({number * 100:g} %)",
            f"a bare number is a fraction (0.5 = 50 %); did you mean '{suggestion}'?",
            suggestion,
        )


# Common units read without pint (importing pint and building its registry costs about
# half a second): unit text -> (kind, factor to the kind's SI unit).  Each factor is the
# exact definition pint uses; tests/test_units.py checks every entry against pint.
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
    "N m": ("torque", 1.0),
    "N*m": ("torque", 1.0),
    "N·m": ("torque", 1.0),
    "kN m": ("torque", 1e3),
    "kN*m": ("torque", 1e3),
    "lbf ft": ("torque", 1.3558179483314004),
    "ft lbf": ("torque", 1.3558179483314004),
    "N m/rad": ("rotational_stiffness", 1.0),
    "N*m/rad": ("rotational_stiffness", 1.0),
    "kN m/rad": ("rotational_stiffness", 1e3),
    "MN m/rad": ("rotational_stiffness", 1e6),
    "N m/deg": ("rotational_stiffness", 180.0 / math.pi),
    "N m s/rad": ("rotational_damping", 1.0),
    "N*m*s/rad": ("rotational_damping", 1.0),
    "J": ("energy", 1.0),
    "kJ": ("energy", 1e3),
    "MJ": ("energy", 1e6),
}

#: How a torque's unit may be written run together: ``150Nm`` is 150 newton metres where a
#: torque is read (pint alone would read a nanometre).
TORQUE_SPELLINGS = {"Nm": "N m", "kNm": "kN m"}

#: Unit names read in any letter case (lower case -> the name as in the fast table): each
#: has two or more letters in every word, and no other capitalisation of it is a unit of
#: the same kind (a test checks this against pint).
ANY_CASE: dict[str, str] = {
    name.lower(): name
    for name in (
        "cm",
        "in",
        "inch",
        "ft",
        "kg",
        "lb",
        "deg",
        "degree",
        "degrees",
        "rad",
        "rpm",
        "rev/min",
        "Hz",
        "percent",
        "kg cm^2",
        "Pa",
        "kPa",
        "bar",
        "cc",
        "cm^3",
        "lbf ft",
        "ft lbf",
        "kJ",
    )
}

#: Unit names whose letter case tells units apart (lower case -> (the spellings read,
#: what would be valid)): another capitalisation is refused with the readings named.
CASE_MATTERS: dict[str, tuple[tuple[str, ...], str]] = {
    "mm": (("mm", "Mm"), "did you mean 'mm' (millimetres) or 'Mm' (megametres)?"),
    "mpa": (("MPa", "mPa"), "did you mean 'MPa' (megapascals) or 'mPa' (millipascals)?"),
    "mg": (("mg", "Mg"), "did you mean 'mg' (milligrams) or 'Mg' (megagrams)?"),
    "m": (("m",), "for metres write 'm'"),
    "g": (("g",), "for grams write 'g' ('G' is the gauss)"),
}


def check_thousands(text: str) -> None:
    """Refuse a number written with thousands separators (``13,000 rpm``, ``13 000 rpm``).

    Parameters
    ----------
    text : str
        A quantity as written.

    Raises
    ------
    UnitProblem
        With the number written without them proposed (``13000 rpm``).
    """
    thousands = _THOUSANDS.match(text)
    if thousands:
        digits = re.sub(r"[,_' ]", "", thousands.group(1))
        suggestion = f"{digits} {thousands.group(2)}".strip()
        raise UnitProblem(
            f"{text.strip()!r} has a thousands separator",
            f"write the number without it, e.g. '{suggestion}'",
            suggestion,
        )


#: Kinds whose number may be written as arithmetic (``360/7 deg``; :mod:`balance.io.arithmetic`).
ARITHMETIC_KINDS = frozenset({"angle"})
_ARITHMETIC_VALID = (
    "write numbers with + - * / and parentheses, then the unit, e.g. '360/7 deg' or '2*360/5 deg'"
)
_OPERATOR_CHARS = frozenset("*/+-^(\u2212\u00d7")
# a mixed number as inch sizes are written (5-1/8 in): arithmetic would read 5 - 1/8
_MIXED = re.compile(r"^\s*(\d+)\s*-\s*(\d+)\s*/\s*(\d+)\s*$")
# ASCII text of one unsigned number, then nothing or a unit that starts with a letter ("86 mm",
# "1.5e-3 kg m^2"; the number matched as arithmetic matches it, atomically): no arithmetic
# (read_arithmetic would give it as plain), read without importing it
_ONE_NUMBER = re.compile(
    r"\s*(?>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)(?:\s*[A-Za-z%].*)?", re.DOTALL
)


def _arithmetic(text: str, kind: str, valid: str) -> tuple[float, str] | None:
    """The number and unit text of a quantity whose number is arithmetic (``360/7 deg``),
    or None for one number (read by the caller as before).

    Arithmetic is read in the kinds of :data:`ARITHMETIC_KINDS` only: elsewhere it is
    refused with the number to write instead (a length ``5-1/8 in`` is an inch size that
    arithmetic would read as 4.875 in).
    """
    if text.isascii() and _ONE_NUMBER.fullmatch(text):
        return None
    from balance.io.arithmetic import ArithmeticProblem, read_arithmetic

    allowed = kind in ARITHMETIC_KINDS
    try:
        read = read_arithmetic(text)
    except ArithmeticProblem as exc:
        raise UnitProblem(
            f"cannot read {text.strip()!r}: {exc}", _ARITHMETIC_VALID if allowed else valid
        ) from None
    shown = text.strip()
    if read is not None and allowed and read.rest[:1] in _OPERATOR_CHARS:
        raise UnitProblem(
            f"cannot read {shown!r}: arithmetic has numbers, + - * / and parentheses only "
            "(no powers, no names)",
            _ARITHMETIC_VALID,
        )
    if read is None or read.plain:
        return None
    try:
        number = float(read.value)
    except OverflowError:
        raise UnitProblem(f"{shown!r} is out of range for {kind}", valid) from None
    unit = read.rest
    if not allowed:
        mixed = _MIXED.match(read.text)
        if mixed:
            whole, top, bottom = (int(g) for g in mixed.groups())
            if bottom == 0:
                raise UnitProblem(f"cannot read {shown!r}: division by zero", valid)
            plus, minus = whole + top / bottom, whole - top / bottom
            instead = (
                f"write one number: '{plus:.10g} {unit}'".rstrip()
                + f" for {whole} {top}/{bottom}, '{minus:.10g} {unit}'".rstrip()
                + f" for {whole} - {top}/{bottom}"
            )
        else:
            instead = f"write one number, e.g. '{number:.10g} {unit}'".rstrip("' ") + "'"
        raise UnitProblem(
            f"{shown!r}: arithmetic is read in angles only, not in {_KIND_ARTICLE[kind]}",
            instead,
        )
    return number, unit


@functools.lru_cache(maxsize=4096)
def _from_text(text: str, kind: str, valid: str) -> tuple[float, bool]:
    """The value of a quantity's text in the kind's SI unit, and whether it was bare.

    Kept for each text read (a pure function of its arguments; text that is refused is
    refused again, since an exception is not kept): a layout read again, a sweep's points
    and ``layout expand``'s check that each number it writes reads back parse the same
    texts many times."""
    if len(text) > 80:
        raise UnitProblem("value text is too long", valid)
    check_thousands(text)
    computed = _arithmetic(text, kind, valid)
    if computed is not None:
        number, unit_text = computed
    else:
        match = _NUMBER.match(text)
        if not match:
            raise UnitProblem(f"cannot read {text!r} as {kind}", valid)
        number = float(match.group(1))
        if not math.isfinite(number):
            raise UnitProblem(f"{text!r} is not a finite number", valid)
        unit_text = match.group(2)
    if not unit_text:
        return number, True
    if _BIG_EXPONENT.search(unit_text):
        raise UnitProblem(f"unit {unit_text!r} has an absurd exponent", valid)
    if kind == "torque":  # the engineer's newton metre, not pint's nanometre
        unit_text = TORQUE_SPELLINGS.get(unit_text, unit_text)
    fast = _FAST_UNITS.get(unit_text)
    if fast is None and unit_text.lower() in ANY_CASE:
        fast = _FAST_UNITS[ANY_CASE[unit_text.lower()]]
    if fast is not None:
        fast_kind, factor = fast
        if fast_kind == kind:
            return number * factor, False
        raise UnitProblem(
            f"{text!r} is {_KIND_ARTICLE[fast_kind]}, not {_KIND_ARTICLE.get(kind, kind)}", valid
        )
    spellings = CASE_MATTERS.get(unit_text.lower())
    if spellings is not None and unit_text not in spellings[0]:
        raise UnitProblem(f"unit {unit_text!r}: letter case matters here", spellings[1])
    if unit_text.startswith("/"):
        unit_text = "1" + unit_text
    ureg = registry()
    try:
        unit = ureg.parse_units(unit_text)
    except Exception as exc:  # pint raises many types for bad units
        if _AFTER_UNIT.search(unit_text):  # 360 deg/7, 90 deg + 1 deg: not pint's to read
            allowed = kind in ARITHMETIC_KINDS
            raise UnitProblem(
                f"cannot read {text.strip()!r}: "
                + ("the arithmetic goes before the unit" if allowed else "a number after the unit"),
                _ARITHMETIC_VALID if allowed else valid,
            ) from None
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise UnitProblem(f"unknown unit {unit_text!r} ({detail})", valid) from None
    if kind == "speed":
        return _speed(number, unit, text, valid), False
    if kind == "angle" and not _one_angle_unit(unit):  # deg**2, percent: no angles
        raise UnitProblem(
            f"{text.strip()!r} is {_dimension_name(unit)}, not an angle"
            if str(unit.dimensionality) != "dimensionless"
            else f"{text.strip()!r}: {unit_text!r} is not a unit of angle",
            valid,
        )
    try:
        return float(ureg.Quantity(number, unit).to(KINDS[kind][0]).magnitude), False
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
    "torque": "a torque",
    "rotational_stiffness": "a torsional stiffness",
    "rotational_damping": "a torsional damping",
    "energy": "an energy",
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
