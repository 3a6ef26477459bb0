"""The layout file's schema (pydantic models over plain data).

Every quantity is read through :func:`balance.io.units.parse_quantity`, so after validation a
model holds SI floats (degrees for angles); a dimensional quantity written as a bare number
other than 0 is refused there, with the likely unit proposed (docs/layout-format.md,
"Quantities and units").  These models are only the file's shape; the engine the physics
sees is built by :mod:`balance.io.layout_reader`.  Their building blocks (:class:`Strict`,
:func:`quantity`, :func:`positive`, the models built from the table of layout fields or
from a dataclass of :mod:`balance.core`) are in :mod:`balance.io.spec_blocks`.

The models of the optional sections ``balance:``, ``gas:`` and ``flywheel:`` are in
:mod:`balance.io.schema_options`, imported only for a layout that has one of them
(:func:`settings_models`).

The concern sections that :attr:`balance.core.engine.Engine.sections` holds have their own
modules (:mod:`balance.io.layout_sections`), whose models are built from the same blocks.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import BeforeValidator, Discriminator, Field, Tag, model_validator

from balance.io.layout_fields import (
    GEOMETRY,
    LUMPED_KEYS,
    MASS_KEYS,
    MASSES,
    PART_KEYS,
    entry_fields,
    placed,
)
from balance.io.located import Hints
from balance.io.problems import FieldProblem
from balance.io.several_cranks import CrankshaftSpec, OutputSpec, check_opposed_block
from balance.io.spec_blocks import (
    Angle,
    Length,
    OptLength,
    Speed,
    Strict,
    TableSpec,
    exactly_one,
    positive,
)

if TYPE_CHECKING:  # imported with settings_models(), for a layout that has one of them
    from balance.io.schema_options import BalanceSpec, FlywheelSpec, GasSpec

__all__ = [
    "LAYOUT_HINTS",
    "SETTINGS_FIELDS",
    "THROW_ID_VALID",
    "CrankLinkSpec",
    "CrankSpec",
    "CylinderSpec",
    "GeometrySpec",
    "LayoutSpec",
    "LinkSpec",
    "MassesSpec",
    "settings_models",
]


class GeometrySpec(TableSpec, rows=placed(GEOMETRY)):
    """Engine-wide crank-slider geometry (SI)."""

    @model_validator(mode="after")
    def _check(self) -> GeometrySpec:
        exactly_one(
            self,
            "stroke",
            "crank_radius",
            "for example 'stroke: 86 mm' (crank_radius is half the stroke)",
            at="stroke",
        )
        self.check_bounds()
        return self

    @property
    def radius(self) -> float:
        """Crank radius [m]."""
        return self.crank_radius if self.crank_radius is not None else self.stroke / 2


class MassesSpec(TableSpec, rows=placed(MASSES)):
    """Engine-wide masses per cylinder, lumped or by part (SI)."""

    @model_validator(mode="after")
    def _check(self) -> MassesSpec:
        given = {k for k in MASS_KEYS if getattr(self, k) is not None}
        lumped = given & set(LUMPED_KEYS)
        parts = given & set(PART_KEYS)
        if lumped and parts:
            first = sorted(parts)[0]
            slider = sorted(parts & {"piston_rod", "crosshead"})
            if slider:  # a crosshead engine's parts (docs/crossheads.md)
                raise FieldProblem(
                    f"'{slider[0]}' given together with lumped masses",
                    "with lumped masses write 'crossheads: true' at the top of the file "
                    "(reciprocating then includes piston rod and crosshead), or give the "
                    "masses by part (piston_group, piston_rod, crosshead, conrod, "
                    "conrod_cg_to_big_end)",
                    (slider[0],),
                )
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
        self.check_bounds()
        return self

    @property
    def by_part(self) -> bool:
        """True when the masses are given by part."""
        return self.piston_group is not None


class LinkSpec(Strict):
    """A cylinder's ``link:`` entry: its rod hangs on another cylinder's rod
    (docs/layout-format.md, "Articulated rods").

    ``master`` is that cylinder's number (1-based, in file order); ``pin_radius`` the
    distance from the crank-pin centre to the link-pin centre on the master rod;
    ``pin_angle`` the direction of that line from the master rod's centre line (big end to
    small end) in the sense of bank angles; ``length`` the link rod's length, link pin to
    piston pin.  The checks that need the other cylinders are in
    :mod:`balance.io.layout_reader`.
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
        positive(self.pin_radius, "pin_radius", allow_zero=True)
        positive(self.length, "length")
        return self


#: What a cylinder's ``throw_id`` may be.
THROW_ID_VALID = (
    "the number of the crank throw this cylinder's rod runs on, a whole number from 1, e.g. "
    "'throw_id: 2' (rods with one throw_id share a throw)"
)


def _throw_id(value: Any) -> int | None:
    """A cylinder's ``throw_id``: a whole number from 1, as written (no unit)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float):
        shown = f"'{value}'" if isinstance(value, str) else type(value).__name__
        raise FieldProblem(f"throw_id is {shown}", THROW_ID_VALID)
    if value != value or value != int(value) or value < 1 or value > 1_000_000:
        raise FieldProblem(f"throw_id is {value:g}", THROW_ID_VALID)
    return int(value)


class CylinderSpec(TableSpec, rows=entry_fields(), entry=True):
    """One cylinder of the explicit form (``throw`` or ``tdc``, ``bank``, ``z``, optional
    ``throw_id``), with optional overrides of ``geometry:`` and ``masses:`` and an
    articulated rod's ``link``.

    ``throw_id`` names the crank throw the rod runs on: rods with one ``throw_id`` share
    the throw's ``crank_unbalance`` (docs/layout-format.md, "Explicit form"); without it
    (on every cylinder), rods at one throw angle and ``z`` share a throw.
    """

    throw_id: Annotated[int | None, BeforeValidator(_throw_id)] = None
    link: LinkSpec | None = None
    # several crankshafts (docs/layout-format.md, "Several crankshafts"; the throw from
    # tdc on a shaft of another sense or phase; the compact block giving the cylinder)
    crankshaft: str | None = Field(default=None, min_length=1, max_length=100)
    opposed: int | None = Field(default=None, ge=1, le=256)
    _shaft_throw: float | None = None
    _block: tuple[str | int, ...] = ("crank",)

    @model_validator(mode="after")
    def _check(self) -> CylinderSpec:
        exactly_one(
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
        self.check_bounds()
        return self

    @property
    def throw_angle(self) -> float:
        """Throw angle [deg], from ``throw`` or from ``bank - tdc`` (on a crankshaft of
        another sense or phase ``sigma (bank - phase) - tdc``)."""
        if self.throw is not None:
            return self.throw
        if self._shaft_throw is not None:
            return self._shaft_throw
        return self.bank - self.tdc


class CrankLinkSpec(
    TableSpec, rows=tuple(f for f in placed(MASSES) if f.group == "rod"), entry=True
):
    """The compact form's ``link:``: on every throw one bank's rod is the master rod and
    every other bank's rod a link rod hung on it (a radial row; docs/layout-format.md,
    "Articulated rods").

    ``master`` is the master bank's number (1-based, in the order of ``banks``);
    ``pin_radius`` and ``length`` are every link rod's (:class:`LinkSpec`); ``pin_angles``
    one link-pin angle per bank other than the master's, in bank order (default: each
    bank's angle less the master bank's); ``conrod``, ``conrod_cg_to_big_end`` (from the
    link pin) and the optional ``conrod_inertia`` describe every link rod.  Each link
    cylinder of the expansion is the explicit form's link cylinder with these values.
    """

    master: int = 1
    pin_radius: Length
    pin_angles: list[Angle] | None = Field(default=None, min_length=1, max_length=63)
    length: Length

    @model_validator(mode="after")
    def _check(self) -> CrankLinkSpec:
        if self.master < 1:
            raise FieldProblem(
                f"master is {self.master}",
                "the number (1-based, in the order of banks) of the bank whose rod is the "
                "master rod on every throw, e.g. 'master: 1'",
                ("master",),
            )
        positive(self.pin_radius, "pin_radius", allow_zero=True)
        positive(self.length, "length")
        for key in ("conrod", "conrod_cg_to_big_end"):
            if getattr(self, key) is None:
                raise FieldProblem(
                    f"missing '{key}'",
                    "give the link rods' conrod (mass) and conrod_cg_to_big_end (their centre "
                    "of gravity from the link pin), e.g. '{conrod: 0.7 kg, "
                    "conrod_cg_to_big_end: 80 mm}'",
                )
        self.check_bounds()
        return self


class CrankSpec(Strict):
    """Compact form: throws, spacing and banks, expanded to the explicit cylinder list; with
    ``row_rotation``, each throw's banks turned by its own angle (the rows of a two-row
    radial); with ``link``, every bank's rod but the master bank's hangs on the master rod of
    its throw."""

    throws: list[Angle] = Field(min_length=1, max_length=256)
    spacing: OptLength = None
    banks: list[Angle] = Field(default_factory=lambda: [0.0], min_length=1, max_length=64)
    bank_count: int | None = Field(default=None, ge=1, le=64)
    split: list[Angle] | None = None
    bank_stagger: Length = 0.0
    row_rotation: list[Angle] | None = None
    link: CrankLinkSpec | None = None
    # a block of several crankshafts (docs/layout-format.md, "Several crankshafts")
    crankshaft: str | None = Field(default=None, min_length=1, max_length=100)
    opposed: list[Annotated[str, Field(min_length=1, max_length=100)]] | None = Field(
        default=None, min_length=2, max_length=2
    )
    z0: Length = 0.0

    @model_validator(mode="after")
    def _check(self) -> CrankSpec:
        if self.opposed is not None:
            check_opposed_block(self)
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
        if self.row_rotation is not None and len(self.row_rotation) != len(self.throws):
            raise FieldProblem(
                f"row_rotation has {len(self.row_rotation)} entries for {len(self.throws)} throws",
                "give one angle per throw, added to every bank angle of that throw's rods "
                "(a two-row radial: [0 deg, 360/14 deg])",
                ("row_rotation",),
            )
        if self.link is not None:
            self._check_link(self.link)
        return self

    def _check_link(self, link: CrankLinkSpec) -> None:
        """A compact ``link:`` fits the banks: a master bank and link banks, all on the
        master's pin."""
        n = len(self.banks)
        if n < 2:
            raise FieldProblem(
                "link with a single bank",
                "a link rod hangs on another bank's master rod: give two or more banks "
                "(banks or bank_count)",
                ("link",),
            )
        if link.master > n:
            raise FieldProblem(
                f"master is {link.master}, but there are {n} banks",
                f"the number of the master rod's bank, 1 to {n} in the order of banks",
                ("link", "master"),
            )
        if link.pin_angles is not None and len(link.pin_angles) != n - 1:
            raise FieldProblem(
                f"pin_angles has {len(link.pin_angles)} entries for {n - 1} link banks",
                "give one link-pin angle per bank other than the master's, in bank order "
                "(or leave pin_angles out: each bank's angle less the master bank's)",
                ("link", "pin_angles"),
            )
        if self.bank_stagger != 0:
            raise FieldProblem(
                "bank_stagger with link",
                "a link rod hangs on its master rod, in the master rod's plane: leave "
                "bank_stagger out (or 0 mm)",
                ("bank_stagger",),
            )
        if self.split is not None and len(set(self.split)) > 1:
            raise FieldProblem(
                "split pins with link",
                "a link rod hangs on its master rod, on the master's pin: give every bank "
                "the same split (or leave split out)",
                ("split",),
            )


def _blocks(value: Any) -> str:
    """Which form ``crank:`` takes: one block (a mapping) or a list of blocks."""
    return "<blocks>" if isinstance(value, list) else "<block>"


CrankForm = Annotated[
    Annotated[CrankSpec, Tag("<block>")]
    | Annotated[list[CrankSpec], Tag("<blocks>"), Field(min_length=1, max_length=64)],
    Discriminator(_blocks),
]


#: The fields of :class:`LayoutSpec` whose models are in :mod:`balance.io.schema_options`.
SETTINGS_FIELDS = frozenset({"balance", "gas", "flywheel"})


def settings_models() -> None:
    """Import the models of the ``balance:``, ``gas:`` and ``flywheel:`` sections
    (:mod:`balance.io.schema_options`) into this module's namespace, where pydantic finds
    the types :class:`LayoutSpec` names when it builds a validator that has those fields.

    The reader calls it before it validates a layout that has one of them, or reports a
    layout's problems with :class:`LayoutSpec` itself; a layout without them does without
    (their models defined, and the gas model of :mod:`balance.core.gas` imported).

    Returns
    -------
    None
    """
    from balance.io import schema_options

    globals().update({name: getattr(schema_options, name) for name in schema_options.__all__})


class LayoutSpec(Strict):
    """A whole layout file but its concern sections (:mod:`balance.io.layout_sections`),
    which their own models read."""

    name: str = Field(min_length=1, max_length=200)
    description: str | None = None
    source: str | None = None
    speed: Speed
    cycle: Literal["four-stroke", "two-stroke"] = "four-stroke"
    geometry: GeometrySpec
    masses: MassesSpec
    cylinders: list[CylinderSpec] | None = Field(default=None, min_length=1, max_length=256)
    crank: CrankForm | None = None
    reference_z: OptLength = None
    pitch: OptLength = None
    firing_order: list[int] | None = None
    # every cylinder a crosshead cylinder, with lumped masses (docs/crossheads.md)
    crossheads: bool = False
    balance: BalanceSpec | None = None
    gas: GasSpec | None = None
    flywheel: FlywheelSpec | None = None
    crankshafts: list[CrankshaftSpec] | None = Field(default=None, min_length=1, max_length=64)
    output: OutputSpec | None = None

    @classmethod
    def model_rebuild(
        cls,
        *,
        force: bool = False,
        raise_errors: bool = True,
        _parent_namespace_depth: int = 2,
        _types_namespace: Any = None,
    ) -> bool | None:
        """pydantic's ``model_rebuild`` (which it calls to build the validator on first
        use), with the models of the optional settings sections imported first
        (:func:`settings_models`) when the model's fields name them: this model can be
        used as any other."""
        if not cls.__pydantic_fields_complete__:
            settings_models()
        return super().model_rebuild(
            force=force,
            raise_errors=raise_errors,
            _parent_namespace_depth=_parent_namespace_depth + (_parent_namespace_depth > 0),
            _types_namespace=_types_namespace,
        )

    @model_validator(mode="after")
    def _check(self) -> LayoutSpec:
        exactly_one(
            self,
            "cylinders",
            "crank",
            "for example 'cylinders: [{throw: 0 deg, bank: 0 deg, z: 0 mm}, ...]'",
            what="'cylinders' (explicit list) and 'crank' (compact form)",
        )
        if self.speed <= 0:
            raise FieldProblem(
                f"speed is {self.speed:g} rad/s",
                "speed must be more than zero",
                ("speed",),
                written="speed is {}",
            )
        positive(self.pitch, "pitch")
        if self.flywheel is not None and self.gas is None and self.flywheel.inertia is None:
            raise FieldProblem(
                "a speed fluctuation to size the flywheel for needs a 'gas' section",
                "the speed fluctuation comes from the gas torque; add gas: {pressure_trace: "
                "...}, or give the flywheel's inertia (a crank that coasts, docs/dynamics.md)",
                ("flywheel",),
            )
        if self.gas is not None and self.gas.bore is None and self.geometry.bore is None:
            raise FieldProblem(
                "missing 'bore'",
                "the gas force needs the bore: give gas.bore or geometry.bore, e.g. '86 mm'",
                ("gas",),
            )
        return self


#: What the layout file proposes for a missing key and a value of the wrong type.
LAYOUT_HINTS = Hints(
    missing={
        "name": "add a name, e.g. 'name: Inline-4, flat crank'",
        "speed": "add the crank speed, e.g. 'speed: 6000 rpm'",
        "geometry": "add geometry with stroke (or crank_radius) and conrod_length",
        "masses": "add masses: reciprocating and rotating (or the parts)",
        "conrod_length": "add conrod_length, e.g. '143 mm'",
        "z": "add the axial position of the throw plane, e.g. 'z: 91 mm'",
        "throws": "add the throw angles, e.g. 'throws: [0, 180, 180, 0]'",
        "speed_ratio": "add the shaft's speed over crank speed, e.g. 'speed_ratio: 2'",
        "value": "add the balance factor, e.g. '{of: one-cylinder, value: 100 %}'",
        "master": "add the master cylinder's number, e.g. 'master: 1'",
        "pin_radius": "add the link pin's distance from the crank-pin centre, e.g. '46 mm'",
        "pin_angle": "add the link pin's direction from the master rod's centre line, e.g. "
        "'72 deg' (usually this cylinder's bank minus the master's)",
        "length": "add the link rod's length, link pin to piston pin, e.g. '230 mm'",
    },
    types={
        "cylinders": "a list of cylinders, each {throw: ..., bank: ..., z: ...}",
        "geometry": "a mapping with stroke (or crank_radius), conrod_length and offset",
        "masses": "a mapping with reciprocating and rotating (or the parts)",
        "throws": "a list of angles, e.g. [0, 180, 180, 0]",
        "banks": "a list of angles, e.g. [-45 deg, 45 deg]",
        "firing_order": "a list of cylinder numbers, e.g. [1, 3, 4, 2]",
        "master": "the number (1-based, in file order) of the cylinder whose rod carries this "
        "link rod, e.g. 'master: 1'",
        "link": "a mapping {master: 1, pin_radius: 46 mm, pin_angle: 72 deg, length: 230 mm} "
        "(in crank: {master: 1, pin_radius: 46 mm, length: 230 mm, conrod: 0.7 kg, "
        "conrod_cg_to_big_end: 80 mm})",
        "pin_angles": "a list of angles, one per bank other than the master's, e.g. "
        "[72 deg, 144 deg, 216 deg, 288 deg]",
    },
    nouns={
        "cylinders": ("cylinder", "cylinders"),
        "throws": ("throw", "throws"),
        "banks": ("bank", "banks"),
        "shafts": ("shaft", "shafts"),
    },
)
