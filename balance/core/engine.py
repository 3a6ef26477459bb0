"""The engine: a table of cylinders in plain frozen dataclasses, SI units.

Everything in :mod:`balance.core` computes on an :class:`Engine`; the layout file reader
(:mod:`balance.io.layout_file`) builds one, after checking every value, so that the physics
never sees a unit string or an impossible value.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from balance.core.balance_factor import BalanceFactor
from balance.core.errors import InputError

if TYPE_CHECKING:  # pragma: no cover (annotations only: gas loads when used)
    from balance.core.crankshafts import AxisTable, Crankshafts
    from balance.core.gas import GasInput
    from balance.core.masses import MassParts

__all__ = [
    "CYLINDER_FIELDS",
    "STRATEGIES",
    "BalanceSettings",
    "Engine",
    "Links",
    "PerCylinder",
    "ShaftPosition",
    "bore_pitch",
]

FloatArray = NDArray[np.float64]

#: Counterweight strategies of a balancing proposal.
STRATEGIES = ("two-plane", "per-throw")


def bore_pitch(z: NDArray[np.float64], bank: NDArray[np.float64]) -> float:
    """The bore pitch: the mean axial distance between neighbouring cylinders of one bank.

    The cylinders of a bank are those whose bore axes point the same way (one ``bank``
    angle); a boxer's or a V's two banks are two.  The bore pitch of an inline engine is
    its throw spacing, and so is that of a V whose rods share (or split) the pins; a
    boxer with a throw per cylinder has a bore pitch of twice its throw spacing, and the
    rod stagger of a V or a boxer is not a pitch (docs/conventions.md, "Normalisation and
    ``pitch``").

    Parameters
    ----------
    z : ndarray
        Axial position of each cylinder [m].
    bank : ndarray
        Bank angle of each cylinder [rad].

    Returns
    -------
    float
        The mean gap between the distinct ``z`` of each bank's cylinders, over every bank
        with cylinders in two planes or more [m]; NaN when no bank has (every cylinder in
        one plane, or one cylinder per bank: a single, a twin of two banks, a radial).
    """
    z = np.asarray(z, dtype=np.float64)
    key = np.round(np.mod(np.degrees(np.asarray(bank, dtype=np.float64)), 360.0), 6) % 360.0
    gaps = []
    for b in dict.fromkeys(key.tolist()):  # the banks in the order of their first cylinder
        planes = np.unique(np.round(z[key == b], 12))
        if planes.size > 1:
            gaps.append((float(planes[-1] - planes[0]), planes.size - 1))
    if not gaps:
        return math.nan
    first = gaps[0][0] / gaps[0][1]
    # banks with the same bore pitch to rounding (a boxer's second bank at z + 56.5 mm):
    # that of the first cylinder's bank, as written (113 mm, not 113.00000000000001 mm)
    if all(math.isclose(span / n, first, rel_tol=1e-12) for span, n in gaps):
        return first
    return sum(span for span, _ in gaps) / sum(n for _, n in gaps)


@dataclass(frozen=True)
class ShaftPosition:
    """A balance shaft of the ``balance: shafts:`` section: its speed ratio and where its
    axis is (SI).

    Attributes
    ----------
    speed_ratio : int
        Shaft speed over crank speed, a non-zero integer; negative turns against the crank.
    x, y : float or None
        Position of the shaft axis in the transverse plane [m]; None leaves the coordinate
        to the proposal (its default, or the place that cancels the roll).
    """

    speed_ratio: int
    x: float | None = None
    y: float | None = None


@dataclass(frozen=True)
class BalanceSettings:
    """The ``balance:`` section: settings of the balancing proposal (SI units).

    Attributes
    ----------
    counterweight_radius : float or None
        Radius of the counterweights' centre of gravity [m]; None: the crank radius.
    balance_factor : float, BalanceFactor or None
        The reciprocating mass put on the crank as counterweight: a float is a share of each
        cylinder's reciprocating mass [1]; a
        :class:`~balance.core.balance_factor.BalanceFactor` a share of one cylinder's on
        each throw (``of='one-cylinder'``).
    orders : tuple of int or None
        Orders the proposal cancels; None: 1 and 2.
    strategy : {'two-plane', 'per-throw'}
        Counterweights at the crank ends, or on every throw.
    shafts : tuple of ShaftPosition or None
        The balance shafts the design has room for; None: the proposal chooses them.
    """

    counterweight_radius: float | None = None
    balance_factor: float | BalanceFactor | None = None
    orders: tuple[int, ...] | None = None
    strategy: str = "two-plane"
    shafts: tuple[ShaftPosition, ...] | None = None


@dataclass(frozen=True, eq=False)
class Links:
    """Articulated (master-and-link) rods: which cylinders hang on another cylinder's rod.

    One entry per cylinder of the engine.  A *link cylinder* is one whose rod is hinged on the rod
    of its *master* cylinder (docs/layout-format.md, "Articulated rods"); the two share throw and
    axial position.  For a link cylinder the engine's ``conrod_length`` is the link rod's length
    (link-pin centre to piston-pin centre), its ``crank_radius`` its master's, and its lumped
    masses are those of its piston and link rod split by static equivalence about the link pin
    (:func:`balance.core.masses.two_mass_split`); the physics is in :mod:`balance.core.links`.

    Attributes
    ----------
    master : ndarray of int
        Index (0-based) of the master cylinder of each cylinder; -1 for a cylinder whose
        rod runs on the crank pin (masters and plain cylinders).
    pin_radius : ndarray
        Distance from the crank-pin centre to the link-pin centre on the master rod [m];
        0 where there is no link.
    pin_angle : ndarray
        Direction of the line from the crank-pin centre to the link-pin centre, from the
        master rod's centre line (big end to small end) in the sense of bank angles [rad];
        0 where there is no link.
    """

    master: NDArray[np.intp]
    pin_radius: FloatArray
    pin_angle: FloatArray

    @property
    def linked(self) -> NDArray[np.bool_]:
        """Which cylinders are link cylinders."""
        return np.asarray(self.master >= 0)

    @property
    def link_indices(self) -> NDArray[np.intp]:
        """Indices of the link cylinders, ascending."""
        return np.flatnonzero(self.linked).astype(np.intp)

    @property
    def masters(self) -> NDArray[np.intp]:
        """Indices of the cylinders that carry at least one link rod, ascending."""
        return np.unique(self.master[self.linked]).astype(np.intp)

    def reordered(self, idx: NDArray[np.intp]) -> Links:
        """The links of renumbered cylinders (``idx[new] = old``, a permutation or some of
        the cylinders): every master reference follows its cylinder to its new number (-1,
        a plain rod, where the master is left out)."""
        new_of_old = np.full(self.master.size, -1, dtype=np.intp)
        new_of_old[idx] = np.arange(idx.size, dtype=np.intp)
        old_master = self.master[idx]
        master = np.where(old_master >= 0, new_of_old[np.maximum(old_master, 0)], -1)
        return Links(
            master=np.asarray(master, dtype=np.intp),
            pin_radius=self.pin_radius[idx],
            pin_angle=self.pin_angle[idx],
        )


#: The per-cylinder arrays of a :class:`Engine`, in order.
CYLINDER_FIELDS = (
    "throw",
    "bank",
    "z",
    "crank_radius",
    "conrod_length",
    "offset",
    "reciprocating_mass",
    "rotating_mass",
    "conrod_inertia_correction",
)


@dataclass(frozen=True, eq=False)
class PerCylinder:
    """A layout section's value that holds one entry per cylinder (the crosshead cylinders
    of ``crossheads``), renumbered with the cylinders by :meth:`Engine.reordered`.

    It reads as its array (``numpy.asarray(value)``).

    Attributes
    ----------
    values : ndarray
        One entry per cylinder, in cylinder order.
    """

    values: NDArray[Any]

    def __array__(self, dtype: Any = None, copy: Any = None) -> NDArray[Any]:
        return np.asarray(self.values, dtype=dtype)

    def reordered(self, idx: NDArray[np.intp]) -> PerCylinder:
        """The entries of the renumbered cylinders (``idx``: the old index of each new one)."""
        return PerCylinder(self.values[np.asarray(idx, dtype=np.intp)])


@dataclass(frozen=True, eq=False)
class Engine:
    """An engine as a table of cylinders (SI units, angles in radians).

    Attributes
    ----------
    name : str
        Name of the layout.
    speed : float
        Crank speed [rad/s].
    throw, bank : ndarray
        Throw angle and bank angle of each cylinder [rad], measured from +y in the direction
        of rotation.
    z : ndarray
        Axial position of each cylinder's throw plane [m].
    crank_radius, conrod_length, offset : ndarray
        Crank radius, conrod length and desaxé offset of each cylinder [m].
    reciprocating_mass, rotating_mass : ndarray
        Lumped masses per cylinder [kg], reciprocating at the piston pin and rotating at the
        crank pin radius.
    conrod_inertia_correction : ndarray
        The real conrod's moment of inertia about its centre of gravity less that of its
        two-mass model [kg m^2]; zero when no ``conrod_inertia`` is given.
    reference_z : float
        Axial position about which moments are taken [m].
    pitch : float
        Pitch used to normalise moments [m]: the layout's ``pitch``, else the bore pitch
        (:func:`bore_pitch`); NaN where it is undefined (every cylinder in one plane, or
        one cylinder per bank).
    bore : float
        Cylinder bore [m], NaN if not given (needed only for displacement).
    cycle : str
        ``"four-stroke"`` or ``"two-stroke"``.
    firing_order : tuple of int or None
        Cylinder numbers (1-based) in firing order, if given.
    pitch_given : bool
        Whether ``pitch`` was given in the layout (otherwise it is the bore pitch).
    reference_z_given : bool
        Whether ``reference_z`` was given (otherwise it is the midpoint of the cylinders'
        ``z``, and a study that moves a cylinder moves it too).
    balance : BalanceSettings or None
        The ``balance:`` section, if given.
    gas : GasInput or None
        The ``gas:`` and ``flywheel:`` sections, resolved (pressure trace read, firing TDCs
        placed); None for an inertia-only analysis.
    mass_parts : MassParts or None
        The parts behind the lumped masses of a by-part layout (None for lumped masses), so
        that a sweep of a part or of the conrod length lumps them again.
    sections : mapping of str to object
        What the layout file's concern sections say, read and checked, by the section's
        name (:mod:`balance.core.sections`): the main-bearing positions of ``bearings:``,
        the mount system of ``mounts:``.  A section present here turns its concern on
        (:func:`balance.io.request.build_request`).
    links : Links or None
        Articulated rods (:class:`Links`); None when every rod runs on its crank pin.
    throw_index : ndarray of int or None
        The crank throw each cylinder's rod is on (0-based: the layout's ``throw_id``, or
        the compact form's entry of ``throws``); rods on one throw share its
        ``crank_unbalance``.  None: rods at one throw angle and ``z`` share a throw
        (:func:`balance.core.throws.crank_throws`, the one rule of the core).
    crankshafts : Crankshafts or None
        Several crankshafts geared together and the crankshaft of each cylinder
        (:class:`balance.core.crankshafts.Crankshafts`); None for one crankshaft on the
        frame's ``z`` axis.
    """

    name: str
    speed: float
    throw: FloatArray
    bank: FloatArray
    z: FloatArray
    crank_radius: FloatArray
    conrod_length: FloatArray
    offset: FloatArray
    reciprocating_mass: FloatArray
    rotating_mass: FloatArray
    conrod_inertia_correction: FloatArray
    reference_z: float
    pitch: float
    bore: float = float("nan")
    cycle: str = "four-stroke"
    firing_order: tuple[int, ...] | None = None
    description: str | None = None
    source: str | None = None
    path: str | None = None
    reference_z_given: bool = False
    pitch_given: bool = False
    balance: BalanceSettings | None = None
    gas: GasInput | None = field(default=None, repr=False)
    mass_parts: MassParts | None = field(default=None, repr=False)
    sections: Mapping[str, Any] = field(default_factory=dict, repr=False)
    links: Links | None = field(default=None, repr=False)
    throw_index: NDArray[np.intp] | None = field(default=None, repr=False)
    crankshafts: Crankshafts | None = field(default=None, repr=False)

    def section(self, name: str) -> Any:
        """What the layout's section ``name`` says (None when it has none)."""
        return self.sections.get(name)

    def arrangement_warnings(self) -> list[tuple[str, str, str, float]]:
        """What looks wrong in the arrangement of several crankshafts (none for one):
        per warning its rule, field, message and excess
        (:func:`balance.core.crankshafts.layout_warnings`)."""
        if self.crankshafts is None:
            return []
        from balance.core.crankshafts import layout_warnings

        return layout_warnings(
            self.crankshafts, self.throw, self.bank, self.z, self.crank_radius, self.offset
        )

    def with_section(self, name: str, value: Any) -> Engine:
        """The same engine with the layout section ``name`` given (or replaced) as ``value``."""
        return replace(self, sections={**self.sections, name: value})

    @property
    def axes_named(self) -> bool:
        """Whether the layout names its crank axes (a ``crankshafts:`` section), even one
        that computes as one crankshaft."""
        return self.crankshafts is not None

    @property
    def geared(self) -> bool:
        """Whether the engine has crankshafts other than the one on the frame's ``z`` axis
        turning forward (:func:`balance.core.crankshafts.is_plain`): then its analysis is
        that of several crankshafts geared together."""
        if self.crankshafts is None:
            return False
        from balance.core.crankshafts import is_plain

        return not is_plain(self.crankshafts)

    def axis_table(self) -> AxisTable:
        """Each cylinder's crank axis: sense, phase, position
        (:func:`balance.core.crankshafts.axis_table`; one axis at the origin without
        crankshafts)."""
        from balance.core.crankshafts import Crankshafts, axis_table

        shafts = self.crankshafts
        if shafts is None:
            zero = np.zeros(1)
            shafts = Crankshafts(
                names=("crankshaft",),
                x=zero,
                y=zero,
                rotation=np.ones(1),
                phase=zero,
                of_cylinder=np.zeros(self.n_cylinders, dtype=np.intp),
                opposed=np.full(self.n_cylinders, -1, dtype=np.intp),
            )
        return axis_table(shafts)

    def forward_throw(self) -> FloatArray:
        """Each cylinder's throw as a one-crank cylinder at the same crank angle from TDC
        (:func:`balance.core.crankshafts.forward_throw`); :attr:`throw` itself unless
        :attr:`geared`.

        Returns
        -------
        ndarray
            The throws [rad].
        """
        if not self.geared:
            return self.throw
        from balance.core.crankshafts import forward_throw

        return forward_throw(self.throw, self.bank, self.axis_table())

    def forward_equivalent(self) -> Engine:
        """The one-crank engine whose cylinders are at this engine's crank angles from TDC
        (:meth:`forward_throw`, no crankshafts): what a cylinder's reciprocating motion,
        its forces along the bore and its torque on its crank in the crank's own sense are
        computed on (docs/several-crankshafts.md, "The angles α and β").

        An engine with link rods has every cylinder of a counter-rotating crankshaft
        mirrored across the frame's ``y`` axis instead (throw ``throw - phase``, bank and
        link-pin angle negated, offset kept), so that a master and its link rods stay one
        mechanism (docs/several-crankshafts.md, "Articulated rods"); each cylinder is at the
        same crank angle from TDC either way.

        Returns
        -------
        Engine
            This engine itself unless :attr:`geared`.
        """
        if not self.geared:
            return self
        if not self.has_links:
            return replace(self, throw=self.forward_throw(), crankshafts=None)
        assert self.links is not None
        table = self.axis_table()
        back = table.sense < 0
        return replace(
            self,
            throw=np.where(back, self.throw - table.axis_phase, self.throw + table.axis_phase),
            bank=np.where(back, -self.bank, self.bank),
            links=replace(
                self.links, pin_angle=np.where(back, -self.links.pin_angle, self.links.pin_angle)
            ),
            crankshafts=None,
        )

    @property
    def n_cylinders(self) -> int:
        """Number of cylinders."""
        return int(self.throw.size)

    @property
    def has_links(self) -> bool:
        """Whether some cylinder's rod hangs on another cylinder's rod (:class:`Links`)."""
        return self.links is not None and bool(np.any(self.links.linked))

    @property
    def displacement(self) -> float:
        """Swept volume of all cylinders [m^3] (NaN without a bore)."""
        return float(np.sum(np.pi / 4 * self.bore**2 * 2 * self.crank_radius))

    def with_speed(self, speed: float) -> Engine:
        """The same layout at another crank speed [rad/s].

        Precondition: ``speed`` is finite and above zero; the input is checked once, where
        it is read (:func:`balance.io.orders.check_speed`).
        """
        assert math.isfinite(speed) and speed > 0, "speed: checked by io.orders.check_speed"
        return replace(self, speed=float(speed))

    def reordered(self, order: NDArray[np.intp] | list[int]) -> Engine:
        """The same engine with its cylinders renumbered (``order`` is a permutation).

        Only the numbering changes: every cylinder keeps its throw, bank and position, so
        the crank angle origin stays where it was.  The firing order is dropped (its
        numbers would no longer match); link rods keep their masters (:meth:`Links.reordered`)
        and every rod its crank throw.
        """
        idx = np.asarray(order, dtype=np.intp)
        if sorted(idx.tolist()) != list(range(self.n_cylinders)):
            raise InputError("order must be a permutation of the cylinder indices")
        arrays = {name: getattr(self, name)[idx] for name in CYLINDER_FIELDS}
        gas = self.gas.reordered(idx) if self.gas is not None else None
        parts = self.mass_parts.reordered(idx) if self.mass_parts is not None else None
        links = self.links.reordered(idx) if self.links is not None else None
        throws = self.throw_index[idx] if self.throw_index is not None else None
        shafts = self.crankshafts.reordered(idx) if self.crankshafts is not None else None
        # a section's value with one entry per cylinder is renumbered with the cylinders
        sections = {
            key: value.reordered(idx) if hasattr(value, "reordered") else value
            for key, value in self.sections.items()
        }
        return replace(
            self,
            firing_order=None,
            gas=gas,
            mass_parts=parts,
            links=links,
            throw_index=throws,
            crankshafts=shafts,
            sections=sections,
            **arrays,
        )
