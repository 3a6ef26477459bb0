"""The building blocks of the layout file's models: a strict model, a quantity read with its
unit, the checks every section shares, and the two kinds of model that are not written out
field by field (docs/layout-format.md).

- :class:`TableSpec`: the models of ``geometry:``, ``masses:`` and a cylinder's entry take
  their fields, unit kinds, defaults and bounds from the one table of numeric fields
  (:mod:`balance.io.layout_fields`), which the command line's ``--vary``/``--scatter``, the
  studies and ``layout expand`` read too;
- :class:`CoreSpec`: a section that is a dataclass of :mod:`balance.core` (``balance:`` and
  its ``shafts:``, ``gas: model:``) takes its fields and defaults from that dataclass; the
  model says only how the file writes each one (its unit kind, or its type).

The layout's models (:mod:`balance.io.schema`, :mod:`balance.io.schema_options`) and each
concern section's (:mod:`balance.io.layout_sections`) are built from these.
"""

from __future__ import annotations

import dataclasses
import typing
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Annotated, Any, ClassVar

from pydantic import BaseModel, BeforeValidator, ConfigDict

from balance.io.layout_fields import CYLINDER, REQUIRED, LayoutField
from balance.io.problems import FieldProblem
from balance.io.units import UnitProblem, check_thousands, likely_unit, parse_quantity

__all__ = [
    "Angle",
    "CoreSpec",
    "Length",
    "OptLength",
    "Speed",
    "Strict",
    "TableSpec",
    "exactly_one",
    "kg_m2",
    "positive",
    "quantity",
]


def _energy(value: Any) -> float | None:
    """An energy [J] from text with a unit ('1.2 kJ'); a bare number other than 0 is refused
    with the likely unit proposed (J from 100 on, kJ below)."""
    if value is None:
        return None
    valid = "give the heat released per cylinder and cycle with a unit, e.g. '1.6 kJ'"
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise UnitProblem(f"expected an energy, got {value!r}", valid)
    bare = value if not isinstance(value, str) else None
    if isinstance(value, str):
        try:
            bare = float(value)
        except ValueError:
            bare = None
    if bare is not None and bare == bare and bare != 0:
        written = str(value).strip()
        suggestion = f"{written} {likely_unit(bare, 'energy')}"
        raise UnitProblem(f"{written} has no unit", f"give a unit, e.g. '{suggestion}'", suggestion)
    if isinstance(value, str) and bare is None:
        check_thousands(value)  # '1,600 J': say so, not "cannot read"
        try:  # J, kJ and MJ without pint
            number = parse_quantity(value, "energy")
        except UnitProblem:
            raise UnitProblem(f"cannot read {value!r} as an energy", valid) from None
    else:
        number = float(value)
    if not (number == number and abs(number) < 1e9):
        raise UnitProblem(f"{value!r} is not a finite energy", valid)
    return number


def quantity(kind: str, likely: Callable[[float], str] | None = None) -> BeforeValidator:
    """The validator of a quantity of unit kind ``kind``, read with its unit into SI.

    Parameters
    ----------
    kind : str
        A kind of :data:`balance.io.units.KINDS`, or ``"energy"`` [J].
    likely : callable, optional
        Proposes the unit of a bare number (default
        :func:`balance.io.units.likely_unit`).

    Returns
    -------
    pydantic.BeforeValidator
        For ``Annotated[float, quantity("length")]``.
    """
    if kind == "energy":
        return BeforeValidator(_energy)
    return BeforeValidator(lambda value: parse_quantity(value, kind, likely))


def kg_m2(number: float) -> str:
    """The unit proposed for a bare moment of inertia of a whole body (a flywheel, a
    powertrain on its mounts): kg m^2 at any size.

    Parameters
    ----------
    number : float
        The bare number (its size does not matter).

    Returns
    -------
    str
        ``"kg m^2"``.
    """
    return "kg m^2"


Length = Annotated[float, quantity("length")]
Angle = Annotated[float, quantity("angle")]
Speed = Annotated[float, quantity("speed")]
OptLength = Annotated[float | None, quantity("length")]


class Strict(BaseModel):
    """A model of a part of an input file: unknown keys refused, values frozen, no value
    converted to another type (``true`` is no number, ``2.0`` no whole number)."""

    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True, strict=True)


def positive(value: float | None, name: str, allow_zero: bool = False) -> None:
    """Raise a :class:`FieldProblem` at ``name`` unless ``value`` is None or above zero (zero
    or more with ``allow_zero``).

    Parameters
    ----------
    value : float or None
        The value [any unit].
    name : str
        The field's key.
    allow_zero : bool
        Whether zero is valid.
    """
    if value is None:
        return
    if value < 0 or (value == 0 and not allow_zero):
        need = "zero or more" if allow_zero else "more than zero"
        raise FieldProblem(
            f"{name} is {value:g}", f"{name} must be {need}", (name,), written=f"{name} is {{}}"
        )


def exactly_one(
    spec: BaseModel, first: str, second: str, example: str, *, at: str = "", what: str = ""
) -> None:
    """Raise unless exactly one of the fields ``first`` and ``second`` of ``spec`` is given.

    Parameters
    ----------
    spec : pydantic.BaseModel
        The validated part of the file.
    first, second : str
        The two fields' names.
    example : str
        What would be valid, for the message.
    at : str
        The field the problem is located at when both are given (default ``second``).
    what : str
        Replaces ``"first and second"`` in the message.

    Raises
    ------
    FieldProblem
        When neither or both are given.
    """
    if (getattr(spec, first) is None) == (getattr(spec, second) is None):
        at = at or second
        raise FieldProblem(
            f"give exactly one of {what or f'{first} and {second}'}",
            example,
            (at,) if getattr(spec, at) is not None else (),
        )


def _add_fields(cls: type, fields: Mapping[str, tuple[Any, Any]]) -> None:
    """Give a model class being created the fields ``{name: (annotation, default)}``, before
    the ones its body declares (pydantic reads the class's annotations after
    ``__init_subclass__``; :data:`REQUIRED`: no default)."""
    own = dict(cls.__annotations__)
    cls.__annotations__.clear()
    for name, (annotation, default) in fields.items():
        cls.__annotations__[name] = annotation
        if default is not REQUIRED:
            setattr(cls, name, default)
    cls.__annotations__.update(own)


class TableSpec(Strict):
    """A model whose numeric fields are rows of the table of layout fields
    (:data:`balance.io.layout_fields.FIELDS`): ``class GeometrySpec(TableSpec,
    rows=placed(GEOMETRY))``.

    Each row becomes a field of its unit kind, with the row's default (None where the row
    is an override in a cylinder's entry, ``entry=True``); :meth:`check_bounds` checks
    the rows' bounds.
    """

    rows: ClassVar[tuple[LayoutField, ...]] = ()

    def __init_subclass__(
        cls, rows: Sequence[LayoutField] = (), entry: bool = False, **kwargs: Any
    ) -> None:
        super().__init_subclass__(**kwargs)
        fields = {}
        for row in rows:
            default = row.default if not entry or row.place == CYLINDER else None
            optional = default is None
            annotation = float | None if optional else float
            fields[row.name] = (Annotated[annotation, quantity(row.kind)], default)
        _add_fields(cls, fields)
        cls.rows = tuple(rows)

    if TYPE_CHECKING:  # the rows' fields: floats [SI] or None

        def __getattr__(self, name: str) -> Any: ...

    def check_bounds(self) -> None:
        """Raise a :class:`FieldProblem` at the first field (in the file's order) below
        its row's bound (more than zero, or zero or more)."""
        for row in self.rows:
            if row.minimum is not None:
                positive(getattr(self, row.name), row.name, row.minimum == "non-negative")

    def overrides(self, keys: tuple[str, ...]) -> dict[str, float]:
        """The values among ``keys`` that this model gives (not None)."""
        return {k: getattr(self, k) for k in keys if getattr(self, k) is not None}


class CoreSpec(Strict):
    """A model of a section that is a dataclass of :mod:`balance.core`: ``class
    BalanceSpec(CoreSpec, core=BalanceSettings, kinds={...}, types={...})``.

    Its fields are the dataclass's, in its order and with its defaults; ``kinds`` names
    the unit kind of each quantity (read with its unit, written by ``layout expand`` in
    the kind's unit), ``types`` the file's type of a field whose type is not the
    dataclass's (a list for a tuple, the allowed texts for a string, a nested model).
    :meth:`to_core` gives the dataclass.
    """

    core_type: ClassVar[type | None] = None
    core_kinds: ClassVar[Mapping[str, str]] = {}

    def __init_subclass__(
        cls,
        core: type | None = None,
        kinds: Mapping[str, str] | None = None,
        types: Mapping[str, Any] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init_subclass__(**kwargs)
        if core is None:
            return
        kinds, types = dict(kinds or {}), dict(types or {})
        hints = typing.get_type_hints(core)
        fields = {}
        for f in dataclasses.fields(core):
            if f.name in types:
                annotation = types[f.name]
            elif f.name in kinds:
                annotation = Annotated[hints[f.name], quantity(kinds[f.name])]
            else:
                annotation = hints[f.name]
            default = REQUIRED if f.default is dataclasses.MISSING else f.default
            fields[f.name] = (annotation, default)
        stray = (set(kinds) | set(types)) - set(fields)
        if stray:
            raise TypeError(f"{cls.__name__}: {core.__name__} has no field {sorted(stray)}")
        _add_fields(cls, fields)
        cls.core_type = core
        cls.core_kinds = kinds

    if TYPE_CHECKING:  # the dataclass's fields

        def __getattr__(self, name: str) -> Any: ...

    def to_core(self) -> Any:
        """The dataclass of :mod:`balance.core` this section is (lists as tuples, nested
        sections as their dataclasses)."""
        assert self.core_type is not None
        names = [f.name for f in dataclasses.fields(self.core_type)]
        return self.core_type(**{name: _core_value(getattr(self, name)) for name in names})


def _core_value(value: Any) -> Any:
    if isinstance(value, CoreSpec):
        return value.to_core()
    if isinstance(value, list):
        return tuple(_core_value(v) for v in value)
    return value
