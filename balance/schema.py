"""The layout file's schema (pydantic models over plain data).

Every quantity is read through :func:`balance.units.parse_quantity`, so after validation a
model holds SI floats (degrees for angles).  These models are only the file's shape; the
engine the physics sees is :class:`balance.layout.Layout`.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from .units import parse_quantity

__all__ = [
    "BalanceSettings",
    "CrankSpec",
    "CylinderSpec",
    "FieldProblem",
    "GeometrySpec",
    "LayoutSpec",
    "MassesSpec",
]


class FieldProblem(ValueError):
    """A validation problem tied to a field below the model that found it."""

    def __init__(self, message: str, valid: str = "", at: tuple[str | int, ...] = ()) -> None:
        super().__init__(message)
        self.valid = valid
        self.at = at


def _q(kind: str) -> BeforeValidator:
    return BeforeValidator(lambda value: parse_quantity(value, kind))


Length = Annotated[float, _q("length")]
Mass = Annotated[float, _q("mass")]
Angle = Annotated[float, _q("angle")]
Speed = Annotated[float, _q("speed")]
Fraction = Annotated[float, _q("fraction")]
OptLength = Annotated[float | None, _q("length")]
OptMass = Annotated[float | None, _q("mass")]
OptInertia = Annotated[float | None, _q("inertia")]
OptAngle = Annotated[float | None, _q("angle")]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


GEOMETRY_KEYS = ("stroke", "crank_radius", "conrod_length", "offset")
LUMPED_KEYS = ("reciprocating", "rotating")
PART_KEYS = (
    "piston_group",
    "conrod",
    "conrod_cg_to_big_end",
    "conrod_inertia",
    "crank_unbalance",
)
MASS_KEYS = LUMPED_KEYS + PART_KEYS


def _positive(value: float | None, name: str, allow_zero: bool = False) -> None:
    if value is None:
        return
    if value < 0 or (value == 0 and not allow_zero):
        need = "zero or more" if allow_zero else "more than zero"
        raise FieldProblem(f"{name} is {value:g}", f"{name} must be {need}", (name,))


class GeometrySpec(_Strict):
    """Engine-wide crank-slider geometry (SI)."""

    stroke: OptLength = None
    crank_radius: OptLength = None
    conrod_length: Length
    offset: Length = 0.0
    bore: OptLength = None

    @model_validator(mode="after")
    def _check(self) -> GeometrySpec:
        if (self.stroke is None) == (self.crank_radius is None):
            raise FieldProblem(
                "give exactly one of stroke and crank_radius",
                "for example 'stroke: 86 mm' (crank_radius is half the stroke)",
                ("stroke",) if self.stroke is not None else (),
            )
        _positive(self.stroke, "stroke")
        _positive(self.crank_radius, "crank_radius")
        _positive(self.conrod_length, "conrod_length")
        _positive(self.bore, "bore")
        return self

    @property
    def radius(self) -> float:
        """Crank radius [m]."""
        return self.crank_radius if self.crank_radius is not None else self.stroke / 2  # type: ignore[operator]


class MassesSpec(_Strict):
    """Engine-wide masses per cylinder, lumped or by part (SI)."""

    reciprocating: OptMass = None
    rotating: OptMass = None
    piston_group: OptMass = None
    conrod: OptMass = None
    conrod_cg_to_big_end: OptLength = None
    conrod_inertia: OptInertia = None
    crank_unbalance: OptMass = None

    @model_validator(mode="after")
    def _check(self) -> MassesSpec:
        given = {k for k in MASS_KEYS if getattr(self, k) is not None}
        lumped = given & set(LUMPED_KEYS)
        parts = given & set(PART_KEYS)
        if lumped and parts:
            first = sorted(parts)[0]
            raise FieldProblem(
                f"'{first}' given together with lumped masses",
                "give either reciprocating and rotating, or the parts (piston_group, conrod, "
                "conrod_cg_to_big_end, optional conrod_inertia and crank_unbalance)",
                (first,),
            )
        if lumped or not parts:
            for key in LUMPED_KEYS:
                if key not in lumped:
                    raise FieldProblem(
                        f"missing '{key}'",
                        "lumped masses need both reciprocating and rotating (per cylinder)",
                    )
        else:
            for key in ("piston_group", "conrod", "conrod_cg_to_big_end"):
                if key not in parts:
                    raise FieldProblem(
                        f"missing '{key}'",
                        "masses by part need piston_group, conrod and conrod_cg_to_big_end",
                    )
        _positive(self.reciprocating, "reciprocating")
        _positive(self.rotating, "rotating", allow_zero=True)
        _positive(self.piston_group, "piston_group")
        _positive(self.conrod, "conrod")
        _positive(self.conrod_cg_to_big_end, "conrod_cg_to_big_end", allow_zero=True)
        _positive(self.conrod_inertia, "conrod_inertia")
        _positive(self.crank_unbalance, "crank_unbalance", allow_zero=True)
        return self

    @property
    def by_part(self) -> bool:
        """True when the masses are given by part."""
        return self.piston_group is not None


class CylinderSpec(_Strict):
    """One cylinder of the explicit form, with optional per-cylinder overrides."""

    throw: OptAngle = None
    tdc: OptAngle = None
    bank: Angle = 0.0
    z: Length
    # geometry overrides
    stroke: OptLength = None
    crank_radius: OptLength = None
    conrod_length: OptLength = None
    offset: OptLength = None
    # mass overrides
    reciprocating: OptMass = None
    rotating: OptMass = None
    piston_group: OptMass = None
    conrod: OptMass = None
    conrod_cg_to_big_end: OptLength = None
    conrod_inertia: OptInertia = None
    crank_unbalance: OptMass = None

    @model_validator(mode="after")
    def _check(self) -> CylinderSpec:
        if (self.throw is None) == (self.tdc is None):
            raise FieldProblem(
                "give exactly one of throw and tdc",
                "for example 'throw: 180 deg' or 'tdc: 540 deg' (then throw = bank - tdc)",
                ("tdc",) if self.tdc is not None else (),
            )
        if self.stroke is not None and self.crank_radius is not None:
            raise FieldProblem(
                "give at most one of stroke and crank_radius",
                "crank_radius is half the stroke",
                ("crank_radius",),
            )
        for key in (
            "stroke",
            "crank_radius",
            "conrod_length",
            "reciprocating",
            "piston_group",
            "conrod",
            "conrod_inertia",
        ):
            _positive(getattr(self, key), key)
        for key in ("rotating", "crank_unbalance", "conrod_cg_to_big_end"):
            _positive(getattr(self, key), key, allow_zero=True)
        return self

    @property
    def throw_angle(self) -> float:
        """Throw angle [deg], from ``throw`` or from ``bank - tdc``."""
        if self.throw is not None:
            return self.throw
        return self.bank - self.tdc  # type: ignore[operator]

    def overrides(self, keys: tuple[str, ...]) -> dict[str, float]:
        """The override values among ``keys`` that this cylinder gives."""
        return {k: getattr(self, k) for k in keys if getattr(self, k) is not None}


class CrankSpec(_Strict):
    """Compact form: throws, spacing and banks, expanded to the explicit cylinder list."""

    throws: list[Angle] = Field(min_length=1, max_length=256)
    spacing: OptLength = None
    banks: list[Angle] = Field(default_factory=lambda: [0.0], min_length=1, max_length=64)
    bank_count: int | None = Field(default=None, ge=1, le=64)
    split: list[Angle] | None = None
    bank_stagger: Length = 0.0

    @model_validator(mode="after")
    def _check(self) -> CrankSpec:
        if self.bank_count is not None:
            if "banks" in self.model_fields_set:
                raise FieldProblem(
                    "give banks or bank_count, not both",
                    "bank_count: N spaces N banks evenly, 360/N degrees apart from 0",
                    ("bank_count",),
                )
            evenly = [360.0 * j / self.bank_count for j in range(self.bank_count)]
            object.__setattr__(self, "banks", evenly)
        if len(self.throws) > 1 and self.spacing is None:
            raise FieldProblem(
                "missing 'spacing'", "with more than one throw give the axial spacing, e.g. '91 mm'"
            )
        if self.split is not None and len(self.split) != len(self.banks):
            raise FieldProblem(
                f"split has {len(self.split)} entries for {len(self.banks)} banks",
                "give one split angle per bank",
                ("split",),
            )
        return self


class BalanceSettings(_Strict):
    """The ``balance:`` section: settings for the balancing proposal."""

    counterweight_radius: OptLength = None
    balance_factor: Annotated[float | None, _q("fraction")] = None
    orders: list[int] | None = None
    strategy: Literal["per-throw", "two-plane"] = "two-plane"

    @model_validator(mode="after")
    def _check(self) -> BalanceSettings:
        _positive(self.counterweight_radius, "counterweight_radius")
        if self.balance_factor is not None and not 0.0 <= self.balance_factor <= 2.0:
            raise FieldProblem(
                f"balance_factor is {self.balance_factor:.4g}",
                "a share between 0 % and 200 % of the reciprocating mass",
                ("balance_factor",),
            )
        if self.orders is not None and any(k < 1 for k in self.orders):
            raise FieldProblem("orders must be 1 or more", "for example [1, 2]", ("orders",))
        return self


class LayoutSpec(_Strict):
    """A whole layout file."""

    name: str = Field(min_length=1, max_length=200)
    description: str | None = None
    source: str | None = None
    speed: Speed
    cycle: Literal["four-stroke", "two-stroke"] = "four-stroke"
    geometry: GeometrySpec
    masses: MassesSpec
    cylinders: list[CylinderSpec] | None = Field(default=None, min_length=1, max_length=256)
    crank: CrankSpec | None = None
    reference_z: OptLength = None
    pitch: OptLength = None
    firing_order: list[int] | None = None
    balance: BalanceSettings | None = None

    @model_validator(mode="before")
    @classmethod
    def _not_yet(cls, data: Any) -> Any:
        if isinstance(data, dict):
            for key in ("gas", "flywheel"):
                if key in data:
                    raise FieldProblem(
                        f"'{key}' is not supported by this version of balance",
                        "the analysis is inertia-only; remove the section",
                        (key,),
                    )
        return data

    @model_validator(mode="after")
    def _check(self) -> LayoutSpec:
        if (self.cylinders is None) == (self.crank is None):
            raise FieldProblem(
                "give exactly one of 'cylinders' (explicit list) and 'crank' (compact form)",
                "for example 'cylinders: [{throw: 0 deg, bank: 0 deg, z: 0 mm}, ...]'",
                ("crank",) if self.crank is not None else (),
            )
        if self.speed <= 0:
            raise FieldProblem(
                f"speed is {self.speed:g} rad/s", "speed must be more than zero", ("speed",)
            )
        _positive(self.pitch, "pitch")
        return self
