"""The layout file's schema (pydantic models over plain data).

Every quantity is read through :func:`balance.io.units.parse_quantity`, so after validation a
model holds SI floats (degrees for angles); a dimensional quantity written as a bare number
other than 0 is refused there, with the likely unit proposed (``CONTRACT`` §3).  These
models are only the file's shape; the engine the physics sees is
:class:`balance.io.layout_file.Layout`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, Any, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from balance.io.bearings_section import BearingsSpec
from balance.io.problems import FieldProblem
from balance.io.units import parse_quantity

__all__ = [
    "BalanceSettings",
    "CrankSpec",
    "CylinderSpec",
    "FieldProblem",
    "FlywheelSpec",
    "GasModelSpec",
    "GasSpec",
    "GeometrySpec",
    "LayoutSpec",
    "LinkSpec",
    "MassesSpec",
    "ShaftSpec",
]


def _q(kind: str, likely: Callable[[float], str] | None = None) -> BeforeValidator:
    """A quantity of unit kind ``kind``; ``likely`` proposes the unit of a bare number
    (default :func:`balance.io.units.likely_unit`)."""
    return BeforeValidator(lambda value: parse_quantity(value, kind, likely))


def _kg_m2(number: float) -> str:
    """The unit proposed for a bare moment of inertia of a whole body (a flywheel, a
    powertrain on its mounts): kg m^2 at any size."""
    return "kg m^2"


Length = Annotated[float, _q("length")]
Mass = Annotated[float, _q("mass")]
Angle = Annotated[float, _q("angle")]
Speed = Annotated[float, _q("speed")]
Fraction = Annotated[float, _q("fraction")]
OptLength = Annotated[float | None, _q("length")]
OptMass = Annotated[float | None, _q("mass")]
OptInertia = Annotated[float | None, _q("inertia")]
OptBodyInertia = Annotated[float | None, _q("inertia", _kg_m2)]
OptAngle = Annotated[float | None, _q("angle")]
Pressure = Annotated[float, _q("pressure")]
OptPressure = Annotated[float | None, _q("pressure")]
OptFraction = Annotated[float | None, _q("fraction")]


def _energy(value: Any) -> float | None:
    """An energy [J] from text with a unit ('1.2 kJ'); a bare number other than 0 is refused
    with the likely unit proposed (J from 100 on, kJ below)."""
    if value is None:
        return None
    from balance.io.units import UnitProblem, registry

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
        suggestion = f"{written} {'J' if abs(bare) >= 100 else 'kJ'}"
        raise UnitProblem(f"{written} has no unit", f"give a unit, e.g. '{suggestion}'", suggestion)
    if isinstance(value, str) and bare is None:
        try:
            number = float(registry().Quantity(value).to("J").magnitude)
        except Exception:
            raise UnitProblem(f"cannot read {value!r} as an energy", valid) from None
    else:
        number = float(value)
    if not (number == number and abs(number) < 1e9):
        raise UnitProblem(f"{value!r} is not a finite energy", valid)
    return number


OptEnergy = Annotated[float | None, BeforeValidator(_energy)]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)


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


def _exactly_one(
    spec: BaseModel, first: str, second: str, example: str, *, at: str = "", what: str = ""
) -> None:
    """Raise unless exactly one of the fields ``first`` and ``second`` of ``spec`` is given.

    When both are given the problem is located at ``at`` (``second`` unless named); ``what``
    replaces ``"first and second"`` in the message.
    """
    if (getattr(spec, first) is None) == (getattr(spec, second) is None):
        at = at or second
        raise FieldProblem(
            f"give exactly one of {what or f'{first} and {second}'}",
            example,
            (at,) if getattr(spec, at) is not None else (),
        )


class GeometrySpec(_Strict):
    """Engine-wide crank-slider geometry (SI)."""

    stroke: OptLength = None
    crank_radius: OptLength = None
    conrod_length: Length
    offset: Length = 0.0
    bore: OptLength = None

    @model_validator(mode="after")
    def _check(self) -> GeometrySpec:
        _exactly_one(
            self,
            "stroke",
            "crank_radius",
            "for example 'stroke: 86 mm' (crank_radius is half the stroke)",
            at="stroke",
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


class LinkSpec(_Strict):
    """A cylinder's ``link:`` entry: its rod hangs on another cylinder's rod (CONTRACT §5).

    ``master`` is that cylinder's number (1-based, in file order); ``pin_radius`` the
    distance from the crank-pin centre to the link-pin centre on the master rod;
    ``pin_angle`` the direction of that line from the master rod's centre line (big end to
    small end) in the sense of bank angles; ``length`` the link rod's length, link pin to
    piston pin.  The checks that need the other cylinders are in
    :mod:`balance.io.layout_file`.
    """

    master: int
    pin_radius: Length
    pin_angle: Angle
    length: Length

    @model_validator(mode="after")
    def _check(self) -> LinkSpec:
        if self.master < 1:
            raise FieldProblem(
                f"master is {self.master}",
                "the number (1-based, in file order) of the cylinder whose rod carries this "
                "link rod",
                ("master",),
            )
        _positive(self.pin_radius, "pin_radius", allow_zero=True)
        _positive(self.length, "length")
        return self


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
    # articulated rod (CONTRACT §5)
    link: LinkSpec | None = None

    @model_validator(mode="after")
    def _check(self) -> CylinderSpec:
        _exactly_one(
            self,
            "throw",
            "tdc",
            "for example 'throw: 180 deg' or 'tdc: 540 deg' (then throw = bank - tdc)",
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


def _speed_ratio(value: Any) -> int:
    """A balance shaft's speed ratio: a whole number other than 0, as written (no unit)."""
    valid = "a whole number from -64 to 64 other than 0, e.g. 2 or -2 (negative: against the crank)"
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise FieldProblem(f"speed_ratio is {value!r}", valid)
    if value != int(value) or value == 0 or abs(value) > 64:
        raise FieldProblem(f"speed_ratio is {value:g}", valid)
    return int(value)


class ShaftSpec(_Strict):
    """One entry of ``balance: shafts:``: a balance shaft the design has room for (SI).

    ``x`` and ``y`` locate its axis in the transverse plane; a coordinate left out is the
    proposal's to choose.
    """

    speed_ratio: Annotated[int, BeforeValidator(_speed_ratio)]
    x: OptLength = None
    y: OptLength = None


class BalanceSettings(_Strict):
    """The ``balance:`` section: settings for the balancing proposal."""

    counterweight_radius: OptLength = None
    balance_factor: Annotated[float | None, _q("fraction")] = None
    orders: list[int] | None = None
    strategy: Literal["per-throw", "two-plane"] = "two-plane"
    shafts: list[ShaftSpec] | None = Field(default=None, min_length=1, max_length=64)

    @model_validator(mode="after")
    def _check(self) -> BalanceSettings:
        _positive(self.counterweight_radius, "counterweight_radius")
        for j, shaft in enumerate(self.shafts or ()):
            if any(other.speed_ratio == shaft.speed_ratio for other in (self.shafts or ())[:j]):
                raise FieldProblem(
                    f"a second shaft at speed ratio {shaft.speed_ratio:+d}",
                    "give one shaft per speed ratio (a shaft's eccentrics may sit in two planes)",
                    ("shafts", j, "speed_ratio"),
                )
        if self.balance_factor is not None and not 0.0 <= self.balance_factor <= 2.0:
            raise FieldProblem(
                f"balance_factor is {self.balance_factor:.4g}",
                "a share between 0 % and 200 % of the reciprocating mass",
                ("balance_factor",),
            )
        if self.orders is not None and any(k < 1 for k in self.orders):
            raise FieldProblem("orders must be 1 or more", "for example [1, 2]", ("orders",))
        return self


class GasModelSpec(_Strict):
    """``gas: model:``: a parametric cylinder pressure (polytropes and a Wiebe heat release).

    See :mod:`balance.core.gas` for the equations.  Angles are crank angles from firing TDC.
    """

    compression_ratio: float
    intake_pressure: Pressure = 1.0e5
    exhaust_pressure: Pressure = 1.1e5
    polytropic_compression: float = 1.35
    polytropic_expansion: float = 1.28
    combustion_start: Angle = -15.0
    combustion_duration: Angle = 55.0
    wiebe_a: float = 5.0
    wiebe_m: float = 2.0
    heat_released: OptEnergy = None
    peak_pressure: OptPressure = None

    @model_validator(mode="after")
    def _check(self) -> GasModelSpec:
        _exactly_one(
            self,
            "heat_released",
            "peak_pressure",
            "for example 'peak_pressure: 75 bar' or 'heat_released: 1.6 kJ' (per cylinder "
            "and cycle)",
        )
        if not 1.0 < self.compression_ratio <= 50.0:
            raise FieldProblem(
                f"compression_ratio is {self.compression_ratio:g}",
                "a compression ratio above 1 and at most 50, e.g. 10.5",
                ("compression_ratio",),
            )
        for key in ("polytropic_compression", "polytropic_expansion"):
            value = getattr(self, key)
            if not 1.0 < value < 2.0:
                raise FieldProblem(
                    f"{key} is {value:g}", "a polytropic exponent above 1 and below 2", (key,)
                )
        for key in ("intake_pressure", "exhaust_pressure"):
            _positive(getattr(self, key), key)
        if not 0.0 < self.combustion_duration <= 180.0:
            raise FieldProblem(
                f"combustion_duration is {self.combustion_duration:g} deg",
                "more than 0 and at most 180 deg",
                ("combustion_duration",),
            )
        if not -180.0 < self.combustion_start < 90.0:
            raise FieldProblem(
                f"combustion_start is {self.combustion_start:g} deg",
                "a crank angle from firing TDC between -180 and 90 deg (negative: before TDC)",
                ("combustion_start",),
            )
        if self.combustion_start + self.combustion_duration >= 180.0:
            raise FieldProblem(
                "combustion ends at or after bottom dead centre",
                "combustion_start + combustion_duration must be below 180 deg",
                ("combustion_duration",),
            )
        if not self.wiebe_a > 0:
            raise FieldProblem(
                f"wiebe_a is {self.wiebe_a:g}", "more than zero, e.g. 5", ("wiebe_a",)
            )
        if not self.wiebe_m > -1:
            raise FieldProblem(f"wiebe_m is {self.wiebe_m:g}", "more than -1, e.g. 2", ("wiebe_m",))
        _positive(self.heat_released, "heat_released")
        if self.peak_pressure is not None and not self.peak_pressure > self.intake_pressure:
            raise FieldProblem(
                f"peak_pressure {self.peak_pressure / 1e5:g} bar is not above the intake pressure",
                "a peak pressure above intake_pressure, e.g. '75 bar'",
                ("peak_pressure",),
            )
        return self


class GasSpec(_Strict):
    """The ``gas:`` section: cylinder pressure for the gas forces and the torque."""

    pressure_trace: str | None = Field(default=None, min_length=1, max_length=1000)
    model: GasModelSpec | None = None
    crankcase_pressure: Pressure = 1.0e5
    bore: OptLength = None

    @model_validator(mode="after")
    def _check(self) -> GasSpec:
        _exactly_one(
            self,
            "pressure_trace",
            "model",
            "pressure_trace: a CSV file of crank angle [deg from firing TDC] and absolute "
            "pressure; or model: {compression_ratio: ..., peak_pressure: ...}",
        )
        _positive(self.crankcase_pressure, "crankcase_pressure", allow_zero=True)
        _positive(self.bore, "bore")
        return self


class FlywheelSpec(_Strict):
    """The ``flywheel:`` section: an inertia to check, or a speed fluctuation to size one."""

    inertia: OptBodyInertia = None
    speed_fluctuation: OptFraction = None

    @model_validator(mode="after")
    def _check(self) -> FlywheelSpec:
        _exactly_one(
            self,
            "inertia",
            "speed_fluctuation",
            "for example '{inertia: 0.12 kg m^2}' or '{speed_fluctuation: 1 %}'",
        )
        _positive(self.inertia, "inertia")
        if self.speed_fluctuation is not None and not 0.0 < self.speed_fluctuation < 1.0:
            raise FieldProblem(
                f"speed_fluctuation is {self.speed_fluctuation:.4g} "
                f"({self.speed_fluctuation * 100:.4g} %)",
                "a fraction above 0 and below 100 %, e.g. '1 %'",
                ("speed_fluctuation",),
            )
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
    gas: GasSpec | None = None
    flywheel: FlywheelSpec | None = None
    # validated by balance.io.mounts_section.MountsSpec in balance.io.layout_file (that
    # module reads this one, so the model cannot be named here without an import cycle)
    mounts: dict[str, Any] | None = None
    bearings: BearingsSpec | None = None

    @model_validator(mode="after")
    def _check(self) -> LayoutSpec:
        _exactly_one(
            self,
            "cylinders",
            "crank",
            "for example 'cylinders: [{throw: 0 deg, bank: 0 deg, z: 0 mm}, ...]'",
            what="'cylinders' (explicit list) and 'crank' (compact form)",
        )
        if self.speed <= 0:
            raise FieldProblem(
                f"speed is {self.speed:g} rad/s", "speed must be more than zero", ("speed",)
            )
        _positive(self.pitch, "pitch")
        if self.flywheel is not None and self.gas is None:
            raise FieldProblem(
                "'flywheel' needs a 'gas' section",
                "the speed fluctuation comes from the gas torque; add gas: {pressure_trace: ...}",
                ("flywheel",),
            )
        if self.gas is not None and self.gas.bore is None and self.geometry.bore is None:
            raise FieldProblem(
                "missing 'bore'",
                "the gas force needs the bore: give gas.bore or geometry.bore, e.g. '86 mm'",
                ("gas",),
            )
        return self
