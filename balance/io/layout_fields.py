"""The numeric fields of a layout file: one table for the schema, the studies and the writer.

Each row of :data:`FIELDS` says of one field of the layout file's ``geometry:``, ``masses:``
and cylinder entries (and of the engine-wide ``speed`` and ``reference_z``):

- its name, as the file, ``--vary``, ``--scatter`` and ``layout expand`` write it;
- its unit kind (:data:`balance.io.units.KINDS`): what a value is read as, and the unit
  ``layout expand`` writes it in (:data:`LAYOUT_UNITS`);
- where the file gives it (:data:`PLACES`): at the top of the file, in ``geometry:`` or
  ``masses:`` (engine-wide, and overridable in a cylinder's entry), or in each cylinder's
  entry only;
- the :class:`~balance.core.engine.Engine` attribute a study sets through it (``parts.X``: the
  :class:`~balance.core.masses.MassParts` array ``X``; a stroke sets the crank radius, half
  of it), if any;
- the bound the file's reader checks (more than zero, or zero or more), its default, and
  its group among the masses (lumped, a part, or a part of the conrod).

The schema (:mod:`balance.io.schema`) makes its ``geometry:``, ``masses:`` and cylinder
models from these rows, the command line's fields (:mod:`balance.io.fields`) and the
studies' rules (:mod:`balance.studies.changes`) read them, and ``layout expand``
(:mod:`balance.io.layout_expand`) writes each value in its row's unit.  The layout format is
in docs/layout-format.md; units and angles in docs/conventions.md.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from balance.core.speed import rad_per_s_to_rpm

__all__ = [
    "CYLINDER",
    "ENGINE",
    "FIELDS",
    "GEOMETRY",
    "GEOMETRY_KEYS",
    "LAYOUT_UNITS",
    "LUMPED_KEYS",
    "MASSES",
    "MASS_KEYS",
    "PART_KEYS",
    "PLACES",
    "REQUIRED",
    "SI_UNITS",
    "LayoutField",
    "entry_fields",
    "exact_number",
    "layout_field",
    "placed",
    "written",
]

#: The top of the layout file (``speed``, ``reference_z``).
ENGINE = "engine"
#: The ``geometry:`` section (every cylinder's, overridable in a cylinder's entry).
GEOMETRY = "geometry"
#: The ``masses:`` section (every cylinder's, overridable in a cylinder's entry).
MASSES = "masses"
#: Each cylinder's entry only (``throw``, ``tdc``, ``bank``, ``z``).
CYLINDER = "cylinder"
#: The places of a field, in the file's order.
PLACES = (ENGINE, GEOMETRY, MASSES, CYLINDER)

#: Default of a field that the file must give.
REQUIRED: Any = ...

#: Unit kind -> the unit ``layout expand`` writes a value in.
LAYOUT_UNITS: dict[str, str] = {
    "length": "mm",
    "mass": "kg",
    "inertia": "kg m^2",
    "angle": "deg",
    "speed": "rpm",
    "fraction": "%",
    "pressure": "bar",
    "energy": "J",
    "torque": "N m",
}
#: Unit kind -> a value (SI; degrees for angles) in its :data:`LAYOUT_UNITS` unit.
_TO_LAYOUT: dict[str, Callable[[float], float]] = {
    "length": lambda v: v * 1e3,
    "mass": lambda v: v * 1.0,
    "inertia": lambda v: v * 1.0,
    "angle": lambda v: v * 1.0,
    "speed": rad_per_s_to_rpm,
    "fraction": lambda v: v * 100,
    "pressure": lambda v: v * 1e-5,
    "energy": lambda v: v * 1.0,
    "torque": lambda v: v * 1.0,
}
#: Unit kind -> the unit of a checked value (SI; degrees for angles), as studies label it.
SI_UNITS: dict[str, str] = {
    "speed": "rad/s",
    "length": "m",
    "mass": "kg",
    "angle": "deg",
    "inertia": "kg m^2",
}


@dataclass(frozen=True)
class LayoutField:
    """One numeric field of the layout file (see the module notes).

    Attributes
    ----------
    name : str
        The key in the layout file.
    kind : str
        Unit kind (:data:`balance.io.units.KINDS`).
    place : str
        Where the file gives it (:data:`PLACES`).
    attribute : str or None
        The :class:`~balance.core.engine.Engine` attribute a study sets through it
        (``parts.X``: a :class:`~balance.core.masses.MassParts` array); None when no study
        changes it.
    minimum : {'positive', 'non-negative'} or None
        The bound the reader checks.
    default : object
        Its value where its place does not give it (:data:`REQUIRED`: the file must).
    group : {'lumped', 'part', 'rod'} or None
        Among the masses: a lumped mass, a part, or a part of the conrod (whose
        engine-wide value is the master rods' on an engine with link rods).
    per_cylinder : bool
        Whether a cylinder's entry may give it (its own field, or an override).
    to_attribute : float
        Factor from the field's value to the attribute's (a stroke is twice the crank
        radius) [1].
    """

    name: str
    kind: str
    place: str
    attribute: str | None = None
    minimum: str | None = None
    default: Any = None
    group: str | None = None
    per_cylinder: bool = True
    to_attribute: float = 1.0

    @property
    def unit(self) -> str:
        """The unit ``layout expand`` writes it in."""
        return LAYOUT_UNITS[self.kind]

    @property
    def si_unit(self) -> str:
        """The unit of a checked value (SI; degrees for angles)."""
        return SI_UNITS[self.kind]


_POSITIVE = "positive"
_NON_NEGATIVE = "non-negative"

#: Every numeric field, in the file's order (the order of the schema's models, of the
#: command line's lists of fields and of ``layout expand``).
FIELDS: tuple[LayoutField, ...] = (
    LayoutField("speed", "speed", ENGINE, "speed", per_cylinder=False),
    LayoutField("throw", "angle", CYLINDER, "throw"),
    LayoutField("tdc", "angle", CYLINDER),
    LayoutField("bank", "angle", CYLINDER, "bank", default=0.0),
    LayoutField("z", "length", CYLINDER, "z", default=REQUIRED),
    LayoutField("stroke", "length", GEOMETRY, "crank_radius", _POSITIVE, to_attribute=0.5),
    LayoutField("crank_radius", "length", GEOMETRY, "crank_radius", _POSITIVE),
    LayoutField("conrod_length", "length", GEOMETRY, "conrod_length", _POSITIVE, REQUIRED),
    LayoutField("offset", "length", GEOMETRY, "offset", default=0.0),
    LayoutField("bore", "length", GEOMETRY, minimum=_POSITIVE, per_cylinder=False),
    LayoutField("reciprocating", "mass", MASSES, "reciprocating_mass", _POSITIVE, group="lumped"),
    LayoutField("rotating", "mass", MASSES, "rotating_mass", _NON_NEGATIVE, group="lumped"),
    LayoutField("piston_group", "mass", MASSES, "parts.piston_group", _POSITIVE, group="part"),
    LayoutField("conrod", "mass", MASSES, "parts.conrod", _POSITIVE, group="rod"),
    LayoutField(
        "conrod_cg_to_big_end",
        "length",
        MASSES,
        "parts.conrod_cg_to_big_end",
        _NON_NEGATIVE,
        group="rod",
    ),
    LayoutField(
        "conrod_inertia", "inertia", MASSES, "parts.conrod_inertia", _POSITIVE, group="rod"
    ),
    LayoutField(
        "crank_unbalance", "mass", MASSES, "parts.crank_unbalance", _NON_NEGATIVE, group="part"
    ),
    # a crosshead engine's slider (docs/crossheads.md): with the piston group it reciprocates
    LayoutField("piston_rod", "mass", MASSES, "parts.piston_rod", _NON_NEGATIVE, group="part"),
    LayoutField("crosshead", "mass", MASSES, "parts.crosshead", _NON_NEGATIVE, group="part"),
    LayoutField("reference_z", "length", ENGINE, "reference_z", per_cylinder=False),
)

_BY_NAME = {f.name: f for f in FIELDS}


def layout_field(name: str) -> LayoutField:
    """The row of the field ``name``.

    Parameters
    ----------
    name : str
        A field's key in the layout file (``stroke``, ``reciprocating``...).

    Returns
    -------
    LayoutField

    Raises
    ------
    KeyError
        If no row has that name.
    """
    return _BY_NAME[name]


def placed(place: str) -> tuple[LayoutField, ...]:
    """The fields that the file gives at ``place`` (:data:`PLACES`), in the file's order.

    Parameters
    ----------
    place : str
        One of :data:`PLACES`.

    Returns
    -------
    tuple of LayoutField
    """
    return tuple(f for f in FIELDS if f.place == place)


def entry_fields() -> tuple[LayoutField, ...]:
    """The fields a cylinder's entry may give: its own (``throw``, ``tdc``, ``bank``,
    ``z``) and the overrides of ``geometry:`` and ``masses:``, in the file's order.

    Returns
    -------
    tuple of LayoutField
    """
    return tuple(f for f in FIELDS if f.per_cylinder)


def written(value: float, kind: str, exact: bool = False) -> str:
    """A checked value (SI; degrees for angles) as ``layout expand`` writes it: the
    fewest significant digits, from ten, that give the number back exactly
    (:func:`exact_number`), and the unit of its kind (:data:`LAYOUT_UNITS`), ``-0`` as ``0``.

    Parameters
    ----------
    value : float
        The value [SI unit of its kind; deg for angles].
    kind : str
        Its unit kind.
    exact : bool
        True (what ``layout expand`` writes): a value that no number in that unit reads
        back to (110000 Pa: '1.1 bar' reads as 110000.00000000001 Pa; 0.086 m: '86 mm'
        reads as 0.08600000000000001 m) is written in the unit it is held in
        (``110000 Pa``, ``0.086 m``), which reads back as it is.  False: always in the
        unit of its kind.

    Returns
    -------
    str
        For example ``"86 mm"``, ``"6000 rpm"``.
    """
    unit = LAYOUT_UNITS[kind]
    text = f"{exact_number(_TO_LAYOUT[kind](value), value, kind, unit)} {unit}"
    base = _BASE_UNITS.get(kind)
    if not exact or base is None or _reads_back(text, value, kind):
        return text
    # no number of the usual unit reads back to this value (110000 Pa is no 'X bar'):
    # the value in the unit it is held in, which reads back as it is
    return f"{exact_number(value, value, kind, base)} {base}".rstrip()


#: Unit kind -> the unit a checked value is held in, as the file writes it (a fraction: bare),
#: where it is not the :data:`LAYOUT_UNITS` one.
_BASE_UNITS: dict[str, str] = {
    "length": "m",
    "pressure": "Pa",
    "speed": "rad/s",
    "fraction": "",
}


def _reads_back(text: str, value: float, kind: str) -> bool:
    """Whether ``text`` read as a quantity of ``kind`` is ``value`` exactly."""
    from balance.io.units import parse_quantity

    try:
        return bool(parse_quantity(text, kind) == value)
    except ValueError:
        return False


def exact_number(
    number: float, value: float | None = None, kind: str | None = None, unit: str = ""
) -> str:
    """A number as ``layout expand`` writes it: ten significant digits when they read back
    exactly (``86``, not ``86.00000000000001``), else the fewest up to 17 that do, so that
    the expanded file reads back to the same floats; ``-0`` as ``0``.

    Parameters
    ----------
    number : float
        The number, in the unit it is written in.
    value, kind, unit : optional
        The value it stands for (SI; degrees for angles), its unit kind and the unit written:
        "reads back" then means that ``"<number> <unit>"`` read as a quantity of that kind
        (:func:`balance.io.units.parse_quantity`) is ``value`` (``8000 rpm``, whose value
        converted to rpm is 7999.999999999999); otherwise (no kind, or one that function
        does not read) that the number is ``number``.

    Returns
    -------
    str
    """

    def reads_back(text: str) -> bool:
        from balance.io.units import KINDS, parse_quantity

        if kind not in KINDS or value is None:  # no kind, or no value to read back to
            return float(text) == number
        return parse_quantity(f"{text} {unit}", kind) == value

    text = f"{number:.17g}"
    for digits in range(10, 17):
        candidate = f"{number:.{digits}g}"
        if reads_back(candidate):
            text = candidate
            break
    return "0" if text in {"-0", "-0.0"} else text


#: The geometry a cylinder's entry may override, in the file's order.
GEOMETRY_KEYS = tuple(f.name for f in placed(GEOMETRY) if f.per_cylinder)
#: The lumped masses (reciprocating, rotating).
LUMPED_KEYS = tuple(f.name for f in placed(MASSES) if f.group == "lumped")
#: The parts behind the lumped masses, in the file's order.
PART_KEYS = tuple(f.name for f in placed(MASSES) if f.group != "lumped")
#: Every field of ``masses:``.
MASS_KEYS = LUMPED_KEYS + PART_KEYS
