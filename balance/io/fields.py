r"""The grammar of field specifications on the command line: ``--speed``, ``--load``, half
orders, and the fields and values of ``--vary`` and ``--scatter`` (``--orders`` and the check
of a speed: :mod:`balance.io.orders`).

Every function here checks what it reads and raises :class:`~balance.core.errors.InputError`
with what would be valid; the studies (:mod:`balance.studies`) receive checked numbers.

Fields
------
The fields, their unit kinds and the engine attributes they set are the rows of the one
table of layout fields (:mod:`balance.io.layout_fields`).  Engine-wide fields set the
value for every cylinder (replacing per-cylinder overrides):

========================================  =======  =====================================
field                                     kind     meaning
========================================  =======  =====================================
``speed``                                 speed    crank speed
``stroke`` (``geometry.stroke``)          length   twice the crank radius
``crank_radius``                          length   crank radius
``conrod_length``                         length   conrod length
``offset``                                length   desaxé offset
``reciprocating`` (``masses.…``)          mass     reciprocating mass per cylinder
``rotating`` (``masses.…``)               mass     rotating mass per cylinder
``reference_z``                           length   where moments are taken
========================================  =======  =====================================

(``geometry.`` and ``masses.`` prefixes are optional.)  One cylinder's field is written
``cylinders[3].reciprocating`` or ``cylinders.3.reciprocating`` (cylinders numbered from 1,
as in the layout file's error messages); per-cylinder fields are ``throw`` and ``bank``
(angles), ``z``, ``stroke``, ``crank_radius``, ``conrod_length``, ``offset`` (lengths),
``reciprocating`` and ``rotating`` (masses), and for masses given by part the parts
(``piston_group``, ``conrod``, ``conrod_cg_to_big_end``, ``conrod_inertia``,
``crank_unbalance``).  A scatter (``--scatter``) may also move ``throw``, ``bank`` and ``z``
of every cylinder.

Values
------
``start:stop:count`` with units on the ends (``130mm:160mm:31``: 31 values, both ends
included) or a list ``a,b,c`` (``0.4kg,0.5kg,0.7kg``).  As in layout files, a dimensional
value needs its unit (a bare number other than 0 is refused with the likely unit proposed);
angles may be bare degrees.  A tolerance is ``±TOL`` (``+-`` and ``+/-`` also accepted).

Every option that takes a quantity reads it through :func:`parse_option_quantity`, so that
a problem names the option and proposes what to write (``--speed 6000`` -> "give a unit,
e.g. --speed 6000rpm").  The command line passes each function its option's name
(``option="--vary"``); a Python caller gets the parameter's (``vary: conrod_length: 130 has
no unit; give a unit, e.g. conrod_length=130mm``).
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.errors import InputError
from balance.io.layout_fields import (
    CYLINDER,
    FIELDS,
    GEOMETRY,
    MASSES,
    SI_UNITS,
    layout_field,
    placed,
)
from balance.io.limits import MAX_ORDER
from balance.io.orders import check_speed

if TYPE_CHECKING:
    from balance.core.engine import Engine
    from balance.core.speed_model import Load
    from balance.io.crank_form import CrankForm

__all__ = [
    "BALANCE_FIELDS",
    "CRANK_FIELDS",
    "MAX_ORDER",
    "MAX_POINTS",
    "MAX_VALUES",
    "Field",
    "Scatter",
    "Vary",
    "check_varies",
    "load_of",
    "parse_field",
    "parse_half_orders",
    "parse_option_quantity",
    "parse_scatter",
    "parse_speed",
    "parse_values",
    "parse_vary",
]

FloatArray = NDArray[np.float64]


def _option_error(option: str, problem: ValueError, prefix: str = "") -> InputError:
    """The :class:`InputError` of a quantity an option could not read.

    A proposed text is written as it would be typed: after the option on the command line
    (``--speed 6000rpm``; quoted when the unit has a space), after ``prefix`` alone for a
    Python caller (``conrod_length=130mm``).

    Parameters
    ----------
    option : str
        The option (``--speed``) or parameter (``vary``) the text was given to.
    problem : ValueError
        The :class:`balance.io.units.UnitProblem` raised for the text.
    prefix : str
        What the value follows (``conrod_length=`` for ``--vary``).

    Returns
    -------
    InputError
        ``"OPTION: [FIELD: ]problem; what is valid"``.
    """
    valid = getattr(problem, "valid", "")
    suggestion = getattr(problem, "suggestion", None)
    field = prefix.rstrip("=±")
    if suggestion:
        number, _, unit = suggestion.partition(" ")
        typed = f"{number}{unit}" if " " not in unit else f"'{suggestion}'"
        if valid.startswith("give a unit"):
            flag = f"{option} " if option.startswith("-") else ""
            valid = f"give a unit, e.g. {flag}{prefix}{typed}"
        else:
            valid = valid.replace(f"'{suggestion}'", typed)
    where = f"{option}: {field}: " if field else f"{option}: "
    return InputError(f"{where}{problem}; {valid}")


def parse_option_quantity(
    text: str,
    kind: str,
    option: str,
    likely: Callable[[float], str] | None = None,
    prefix: str = "",
) -> float:
    """A quantity given to an option, in SI (degrees for angles).

    Parameters
    ----------
    text : str
        The quantity as written, with its unit (``7000rpm``, ``2.0 L``).
    kind : str
        The unit kind (:data:`balance.io.units.KINDS`).
    option : str
        The option (``--displacement``) or parameter it was given to, for the message.
    likely : callable, optional
        The unit proposed for a bare number (:func:`balance.io.units.likely_unit` by
        default).
    prefix : str
        What the value follows (``conrod_length=`` for ``--vary``), for the message.

    Returns
    -------
    float
        The value in SI (degrees for angles).

    Raises
    ------
    InputError
        Naming ``option``, if the text is no quantity of that kind (a bare number where a
        unit is required proposes the likely unit, see
        :func:`balance.io.units.parse_quantity`).
    """
    from balance.io.units import UnitProblem, parse_quantity

    try:
        return parse_quantity(text, kind, likely)
    except UnitProblem as exc:
        raise _option_error(option, exc, prefix) from None


def parse_speed(text: str | None, option: str = "speed") -> float | None:
    """A crank speed given as text with its unit (``7000rpm``, ``733rad/s``; a bare number is
    refused with the likely unit proposed), checked by :func:`check_speed`.

    Parameters
    ----------
    text : str or None
        The speed as written; None when it is not given.
    option : str
        The option (``--speed``) or parameter it was given to, for the message.

    Returns
    -------
    float or None
        The speed [rad/s]; None for None.

    Raises
    ------
    InputError
        If the text is no speed, or the speed is not a finite number above zero.
    """
    if text is None:
        return None
    speed = parse_option_quantity(text, "speed", option)
    if not speed > 0:  # answered in the unit given
        raise InputError(
            f"{option}: {text.strip()}: the speed must be a finite number above zero, e.g. 6000rpm"
        )
    return check_speed(speed)


# ---------------------------------------------------------------------------------------
# the fields of --vary and --scatter

# from the one table of layout fields (balance.io.layout_fields):
# field name -> (Engine attribute, unit kind); "parts.X" is a MassParts array
CYLINDER_FIELDS: dict[str, tuple[str, str]] = {
    f.name: (f.attribute, f.kind) for f in FIELDS if f.per_cylinder and f.attribute is not None
}
# engine-wide: the speed, every per-cylinder field but the crank's own angles and
# positions, and where moments are taken
ENGINE_FIELDS: dict[str, tuple[str, str]] = {
    f.name: (f.attribute, f.kind) for f in FIELDS if f.place != CYLINDER and f.attribute is not None
}
# fields of every cylinder that only a scatter may move (a sweep sets them one at a time)
_SCATTER_ONLY = {f.name for f in placed(CYLINDER) if f.attribute is not None}
_SECTION = {
    place: {f.name for f in placed(place) if f.attribute is not None}
    for place in (GEOMETRY, MASSES)
}
_CYLINDER = re.compile(r"^cylinders(?:\[(\d+)\]|\.(\d+))\.([a-z_]+)$")
#: Fields of the compact ``crank:`` form a sweep may vary (:mod:`balance.io.crank_form`):
#: name -> unit kind; ``crank.banks[N]`` is bank N's angle.
CRANK_FIELDS: dict[str, str] = {
    "spacing": "length",
    "bank_stagger": "length",
    "banks": "angle",
    "v_angle": "angle",
}
_BANK = re.compile(r"^banks(?:\[(\d+)\]|\.(\d+))$")
#: Fields of the ``balance:`` section a sweep may vary: name -> unit kind.
BALANCE_FIELDS: dict[str, str] = {"balance_factor": "fraction"}
#: Most grid points a sweep may have: a guard against a mistyped count (the grid is
#: computed chunk by chunk, so memory does not bound it; time and the output's size do).
MAX_POINTS = 10**12
#: Most values one varied field may have: its values are held in memory and written as the
#: grid's coordinate (10**6 values are 8 MB).
MAX_VALUES = 10**6


@dataclass(frozen=True)
class Field:
    """A numeric layout field that a sweep or a tolerance study may change.

    Attributes
    ----------
    text : str
        The field as the user wrote it.
    name : str
        A canonical name, usable as a dimension name (``conrod_length``,
        ``cylinder3_reciprocating``).
    attribute : str
        The :class:`~balance.core.engine.Engine` attribute it sets (``parts.X``: the
        :class:`~balance.core.masses.MassParts` array ``X``).
    kind : str
        Unit kind (:data:`balance.io.units.KINDS`): ``speed``, ``length``, ``mass``, ``angle``.
    key : str
        The field's own name (``stroke``, ``throw``...).
    cylinder : int or None
        0-based index of the cylinder, or None for every cylinder.
    crank : CrankForm or None
        For a field of the compact ``crank:`` form (``attribute`` ``crank.KEY``): the
        layout's compact form (:func:`balance.io.crank_form.crank_form`).
    bank : int or None
        For ``crank.banks[N]``: the 0-based index of the bank.
    """

    text: str
    name: str
    attribute: str
    kind: str
    key: str
    cylinder: int | None = None
    crank: CrankForm | None = None
    bank: int | None = None

    @property
    def unit(self) -> str:
        """SI unit of the values (degrees for angles, 1 for fractions)."""
        return SI_UNITS.get(self.kind, "1")

    def to_layout_units(self, values: ArrayLike) -> FloatArray:
        """Values in the unit of the Engine attribute (radians for angles, radius for stroke);
        a field of the ``crank:`` or ``balance:`` section keeps the file's (SI, degrees), which
        :func:`balance.studies.changes.apply_changes` turns into the engine's."""
        v = np.asarray(values, dtype=np.float64)
        if self.attribute.startswith(("crank.", "balance.")):
            return v
        if self.attribute.startswith("shaft."):  # a crankshaft's phase [rad], x or y [m]
            return np.radians(v) if self.kind == "angle" else v
        if self.kind == "angle":
            return np.radians(v)
        to_attribute = layout_field(self.key).to_attribute
        return v * to_attribute if to_attribute != 1.0 else v


def _valid_fields() -> str:
    return (
        f"valid: {', '.join(ENGINE_FIELDS)}, crank.spacing, crank.bank_stagger, "
        "crank.banks[N], crank.v_angle, balance.balance_factor, crankshafts.NAME.phase (.x, "
        ".y), or cylinders[N].FIELD with "
        f"FIELD one of {', '.join(CYLINDER_FIELDS)}"
    )


def _crank_field(name: str, key: str, layout: Engine, option: str) -> Field:
    """A field of the compact ``crank:`` form (``crank.spacing``, ``crank.banks[2]``)."""
    import difflib

    from balance.io.crank_form import crank_form

    match = _BANK.match(key)
    if key not in CRANK_FIELDS and match is None:
        keys = ["spacing", "bank_stagger", "banks[N]", "v_angle"]
        hint = difflib.get_close_matches(key, keys, n=1)
        more = f"did you mean 'crank.{hint[0]}'? " if hint else ""
        raise InputError(
            f"{option}: '{name}' is not a field of the crank: section a sweep varies; {more}"
            f"valid: {', '.join('crank.' + k for k in keys)}"
        )
    form = crank_form(layout, f"{option}: {name}")
    if match is not None:
        number = int(match.group(1) or match.group(2))
        if not 1 <= number <= len(form.banks):
            raise InputError(f"{option}: '{name}': the layout has banks 1 to {len(form.banks)}")
        return Field(
            name,
            f"crank_bank{number}",
            "crank.banks",
            "angle",
            "banks",
            crank=form,
            bank=number - 1,
        )
    if key == "v_angle" and len(form.banks) != 2:
        raise InputError(
            f"{option}: '{name}': a V angle needs two banks, the layout has "
            f"{len(form.banks)}; vary crank.banks[N]"
        )
    return Field(name, f"crank_{key}", f"crank.{key}", CRANK_FIELDS[key], key, crank=form)


def parse_field(text: str, layout: Engine, option: str = "vary") -> Field:
    """Read a field name (see the module notes).

    Parameters
    ----------
    text : str
        The field as written (``conrod_length``, ``masses.reciprocating``,
        ``cylinders[3].throw``).
    layout : Engine
        The layout whose field it is (its cylinders, and whether its masses are by part).
    option : str
        The option (``--vary``) or parameter (``vary``) it was given to, for the message.

    Returns
    -------
    Field

    Raises
    ------
    InputError
        If there is no such numeric field, or the cylinder does not exist.
    """
    import difflib

    name = text.strip()
    match = _CYLINDER.match(name)
    if match:
        number = int(match.group(1) or match.group(2))
        key = match.group(3)
        if key not in CYLINDER_FIELDS:
            hint = difflib.get_close_matches(key, list(CYLINDER_FIELDS), n=1)
            more = f"did you mean '{hint[0]}'? " if hint else ""
            raise InputError(
                f"{option}: '{name}' is not a numeric per-cylinder field; {more}"
                f"valid: {', '.join(CYLINDER_FIELDS)}"
            )
        if not 1 <= number <= layout.n_cylinders:
            raise InputError(
                f"{option}: '{name}': the layout has cylinders 1 to {layout.n_cylinders}"
            )
        attribute, kind = CYLINDER_FIELDS[key]
        _check_parts(layout, attribute, name, option)
        return Field(name, f"cylinder{number}_{key}", attribute, kind, key, number - 1)
    if name.startswith("crank."):
        return _crank_field(name, name[len("crank.") :], layout, option)
    if name.startswith("crankshafts."):  # docs/layout-format.md, "Several crankshafts"
        from balance.io.several_cranks import shaft_field

        dim, attribute, kind, key = shaft_field(name, layout, option)
        return Field(name, dim, attribute, kind, key)
    if name.startswith("balance."):
        key = name[len("balance.") :]
        if key not in BALANCE_FIELDS:
            raise InputError(
                f"{option}: '{name}' is not a field of the balance: section a sweep varies; "
                f"valid: {', '.join('balance.' + k for k in BALANCE_FIELDS)}"
            )
        return Field(name, key, f"balance.{key}", BALANCE_FIELDS[key], key)
    key = name
    for section, keys in _SECTION.items():
        if name.startswith(section + "."):
            key = name[len(section) + 1 :]
            if key not in keys:
                key = "?"
    if key not in ENGINE_FIELDS:
        hint = difflib.get_close_matches(
            name, [*ENGINE_FIELDS, "masses.reciprocating", "geometry.conrod_length"], n=1
        )
        more = f"did you mean '{hint[0]}'? " if hint else ""
        raise InputError(
            f"{option}: '{name}' is not a numeric layout field; {more}{_valid_fields()}"
        )
    attribute, kind = ENGINE_FIELDS[key]
    _check_parts(layout, attribute, name, option)
    return Field(name, key, attribute, kind, key, None)


def _check_parts(layout: Engine, attribute: str, name: str, option: str) -> None:
    if attribute.startswith("parts.") and layout.mass_parts is None:
        raise InputError(
            f"{option}: '{name}' is a part of the moving masses, but this layout gives them "
            "lumped; vary masses.reciprocating or masses.rotating"
        )


def _quantity(
    text: str,
    field: Field,
    option: str,
    likely: Callable[[float], str] | None = None,
    typed: str = "=",
) -> float:
    """A value of ``field`` for ``option``; a proposal is written as ``FIELD{typed}VALUE``
    for ``--vary`` and ``--scatter`` (``typed``: ``=`` or ``=±``), as the value alone for
    other options."""
    prefix = f"{field.text}{typed}" if option.lstrip("-") in ("vary", "scatter") else ""
    return parse_option_quantity(text.strip(), field.kind, option, likely, prefix)


# a list value that is a number of one to three digits followed by one that starts with
# three digits: a thousands separator read as the list's comma (13,000rpm)
_THOUSANDS_SPLIT = re.compile(r"^[+-]?\d{1,3}$")
_THOUSANDS_REST = re.compile(r"^\d{3}(?!\d)")


def _check_thousands(parts: list[str], field: Field, option: str) -> None:
    for first, second in itertools.pairwise(parts):
        if _THOUSANDS_SPLIT.match(first.strip()) and _THOUSANDS_REST.match(second.strip()):
            joined = first.strip() + second.strip()
            raise InputError(
                f"{option}: {field.text}: '{first.strip()},{second.strip()}' has a thousands "
                f"separator (a comma separates the values of a list); write {joined}"
            )


def parse_values(text: str, field: Field, option: str = "vary") -> FloatArray:
    """Values of a field from ``start:stop:count`` or ``a,b,c``.

    Parameters
    ----------
    text : str
        The values as written, each with its unit (angles may be bare degrees).
    field : Field
        The field they are for (its unit kind).
    option : str
        The option (``--vary``) or parameter (``vary``) they were given to, for the message.

    Returns
    -------
    ndarray
        The values in SI (degrees for angles).

    Raises
    ------
    InputError
        If the range or list is malformed or a value has the wrong unit.
    """
    spec = text.strip()
    if not spec:
        raise InputError(f"{option}: {field.text}: no values; write start:stop:count or a,b,c")
    if ":" in spec:
        parts = spec.split(":")
        if len(parts) != 3 or not all(p.strip() for p in parts):
            raise InputError(
                f"{option}: {field.text}: cannot read range {spec!r}; write start:stop:count, "
                "e.g. 130mm:160mm:31"
            )
        start = _quantity(parts[0], field, option)
        stop = _quantity(parts[1], field, option)
        try:
            count = int(parts[2])
        except ValueError:
            count = 0
        if count < 1 or str(count) != parts[2].strip():
            raise InputError(
                f"{option}: {field.text}: count {parts[2].strip()!r} is not a whole number above 0"
            )
        if count > MAX_VALUES:
            raise InputError(
                f"{option}: {field.text}: count {count} is more than the {MAX_VALUES} values a "
                "field may have"
            )
        if count == 1 and start != stop:
            raise InputError(f"{option}: {field.text}: one value from {start} to {stop}?")
        for part, value in ((parts[0], start), (parts[1], stop)):
            _check_bound(field, value, option, part.strip())
        values = np.linspace(start, stop, count)
    else:
        parts = spec.split(",")
        if len(parts) > MAX_VALUES:
            raise InputError(
                f"{option}: {field.text}: {len(parts)} values; a field may have at most "
                f"{MAX_VALUES}"
            )
        _check_thousands(parts, field, option)
        values = np.array([_quantity(p, field, option) for p in parts])
        for part, value in zip(parts, values, strict=True):
            _check_bound(field, float(value), option, part.strip())
    return values


@dataclass(frozen=True)
class Vary:
    """One varied field and its values (SI, degrees for angles)."""

    field: Field
    values: FloatArray

    @property
    def dim(self) -> str:
        """The grid dimension's name."""
        return self.field.name


def parse_vary(text: str, layout: Engine, option: str = "vary") -> Vary:
    """Read ``FIELD=VALUES`` (see :func:`parse_field`, :func:`parse_values`).

    Parameters
    ----------
    text : str
        The varied field as written (``conrod_length=130mm:160mm:31``).
    layout : Engine
        The layout swept.
    option : str
        The option (``--vary``) or parameter (``vary``) it was given to, for the message.

    Returns
    -------
    Vary

    Raises
    ------
    InputError
        If the text is malformed, names no numeric field, or gives bad values.
    """
    if "=" not in text:
        raise InputError(
            f"{option}: cannot read {text!r}; write FIELD=start:stop:count, e.g. "
            "conrod_length=130mm:160mm:31"
        )
    name, _, spec = text.partition("=")
    field = parse_field(name, layout, option)
    return Vary(field, parse_values(spec, field, option))


def check_varies(varies: list[Vary], option: str = "vary") -> list[Vary]:
    """Check the fields of a sweep together: each once, finite values in range, a grid
    of at most :data:`MAX_POINTS` points.

    Parameters
    ----------
    varies : list of Vary
        The varied fields.
    option : str
        The option (``--vary``) or parameter (``vary``) they were given to, for the message.

    Returns
    -------
    list of Vary
        ``varies``, checked.

    Raises
    ------
    InputError
        Otherwise.
    """
    names = [v.dim for v in varies]
    for name in names:
        if names.count(name) > 1:
            raise InputError(f"{option}: {name} is varied twice; give it once")
    if not varies:
        raise InputError(f"{option}: give at least one field to vary")
    for v in varies:
        if v.values.ndim != 1 or v.values.size == 0 or not np.all(np.isfinite(v.values)):
            raise InputError(f"{option}: {v.field.text}: values must be finite numbers")
        _check_values(v, option)
    total = math.prod(v.values.size for v in varies)
    if total > MAX_POINTS:
        raise InputError(f"{option}: {total:.3g} grid points; at most {MAX_POINTS:.0e}")
    return varies


def _check_values(v: Vary, option: str) -> None:
    """The bounds of every value (SI numbers given from Python: the message shows the SI
    unit)."""
    if v.values.size:
        for value in (float(v.values.min()), float(v.values.max())):
            _check_bound(v.field, value, option, f"{value:g} {v.field.unit}".rstrip(" 1"))


_POSITIVE = frozenset({"speed", "stroke", "crank_radius", "conrod_length"})


def _check_bound(field: Field, value: float, option: str, written: str) -> None:
    """Refuse a value outside its field's bounds, named as written (``-100rpm``)."""
    key = field.key
    if key in _POSITIVE and not value > 0:
        raise InputError(f"{option}: {field.text}: values must be above zero, got {written}")
    if key in {"reciprocating", "rotating"} and value < 0:
        raise InputError(f"{option}: {field.text}: masses cannot be negative, got {written}")
    if key == "balance_factor" and not 0.0 <= value <= 2.0:
        raise InputError(
            f"{option}: {field.text}: {written} is outside 0 % to 200 % (the share of the "
            "reciprocating mass put on the crank)"
        )


@dataclass(frozen=True)
class Scatter:
    """A scattered field and its tolerance (SI, degrees for angles)."""

    field: Field
    tolerance: float


def parse_scatter(text: str, layout: Engine, option: str = "scatter") -> Scatter:
    """Read ``FIELD=±TOL`` (e.g. ``masses.reciprocating=±3g``).

    Parameters
    ----------
    text : str
        The scattered field as written.
    layout : Engine
        The layout scattered.
    option : str
        The option (``--scatter``) or parameter (``scatter``) it was given to, for the
        message.

    Returns
    -------
    Scatter

    Raises
    ------
    InputError
        If the field is not a numeric per-cylinder field or the tolerance is malformed.
    """
    if "=" not in text:
        raise InputError(
            f"{option}: cannot read {text!r}; write FIELD=±TOL, e.g. reciprocating=±3g"
        )
    name, _, spec = text.partition("=")
    key = name.strip()
    if key in _SCATTER_ONLY:
        attribute, kind = CYLINDER_FIELDS[key]
        field = Field(key, key, attribute, kind, key, None)
    else:
        field = parse_field(name, layout, option)
    if field.attribute in {"speed", "reference_z"} or field.attribute.startswith(
        ("crank.", "balance.")
    ):
        raise InputError(
            f"{option}: '{name.strip()}' is not a part or geometry field of a cylinder; "
            "scatter masses, stroke, conrod_length, offset, z, throw or bank"
        )
    spec = spec.strip()
    for prefix in ("±", "+-", "+/-"):
        if spec.startswith(prefix):
            spec = spec[len(prefix) :]
            break
    else:
        raise InputError(f"{option}: {field.text}: write the tolerance as ±TOL, e.g. ±3g")
    tol = _quantity(spec, field, option, _tolerance_unit(field.kind), "=±")
    if not tol >= 0:
        raise InputError(f"{option}: {field.text}: the tolerance must not be negative")
    return Scatter(field, tol)


def _tolerance_unit(kind: str) -> Callable[[float], str]:
    """The unit proposed for a bare tolerance: tolerances are small, so a bare 3 for a
    mass is more likely grams and a bare 0.1 for a length millimetres."""

    def likely(number: float) -> str:
        from balance.io.units import likely_unit

        size = abs(number)
        if kind == "mass":
            return "g" if size >= 0.5 else "kg"
        if kind == "length":
            return "mm" if size >= 0.01 else "m"
        return likely_unit(number, kind)

    return likely


_POWER_LAW = re.compile(r"^(?P<torque>[^@]+)@(?P<at>[^^]+)\^(?P<exponent>.+)$")


def load_of(text: str, option: str = "load") -> Load:
    """A load written as text (the command line's ``--load``).

    Parameters
    ----------
    text : str
        ``mean``, ``propeller``, a torque (``150Nm``: a constant load) or a power law
        ``TORQUE@SPEED^EXPONENT`` (``80Nm@3000rpm^2``).
    option : str
        How messages name the value.

    Returns
    -------
    Load

    Raises
    ------
    InputError
        For text that is none of these, naming what would be valid.
    """
    from balance.core.speed_model import ConstantLoad, MeanLoad, PowerLawLoad, PropellerLoad
    from balance.io.units import parse_quantity

    word = text.strip().lower()
    if word in ("mean", "propeller"):
        return MeanLoad() if word == "mean" else PropellerLoad()
    match = _POWER_LAW.match(text.replace(" ", ""))
    try:
        if match is None:
            return ConstantLoad(parse_quantity(text, "torque"))
        return PowerLawLoad(
            parse_quantity(match["torque"], "torque"),
            parse_quantity(match["at"], "speed"),
            float(match["exponent"]),
        )
    except (ValueError, InputError) as exc:
        raise InputError(
            f"{option}: {text!r}: {exc}; give mean, propeller, a torque such as 150Nm, or a "
            "power law such as 80Nm@3000rpm^2"
        ) from None


_HALF_ORDER = re.compile(r"(\d+(?:\.\d+)?)(?:-(\d+(?:\.\d+)?))?")


def parse_half_orders(spec: str, cycle: str, option: str = "orders") -> NDArray[np.float64]:
    """Orders of a torsional analysis from a spec: halves on a four-stroke.

    Parameters
    ----------
    spec : str
        A range or list: ``0.5-12`` (every half order from 0.5 to 12 on a four-stroke, every
        whole order on a two-stroke), ``4.5,6``, ``1-3,6``.
    cycle : {'four-stroke', 'two-stroke'}
        The engine's cycle: a four-stroke's range steps by 0.5, a two-stroke's by 1.
    option : str
        How messages name the value.

    Returns
    -------
    ndarray of float
        The orders, ascending, each once: multiples of 0.5, whole on a two-stroke.

    Raises
    ------
    InputError
        For a spec that is no range or list, a range that does not increase, an order
        above :data:`MAX_ORDER`, or orders that
        :func:`balance.core.torsion_excitation.order_problem` refuses.
    """
    step = 0.5 if cycle == "four-stroke" else 1.0
    values: list[float] = []
    for part in spec.replace(" ", "").split(","):
        match = _HALF_ORDER.fullmatch(part)
        if not match:
            raise InputError(
                f"{option}: cannot read {spec!r}; write a range or list such as 0.5-12, 4.5,6"
            )
        lo = float(match.group(1))
        hi = float(match.group(2)) if match.group(2) else lo
        if hi < lo:
            raise InputError(f"{option}: {part!r} is not an increasing range")
        if hi > MAX_ORDER:
            raise InputError(f"{option}: {part!r}: orders up to {MAX_ORDER}")
        count = math.floor((hi - lo) / step + 1e-9) + 1
        values.extend(lo + step * np.arange(count))
    orders = np.unique(np.asarray(values, dtype=np.float64))
    from balance.core.torsion_excitation import order_problem

    problem = order_problem(orders, cycle)
    if problem is not None:
        raise InputError(f"{option}: {problem}")
    return orders
