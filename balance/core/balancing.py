r"""Balancing proposals: crank counterweights, balance shafts and what remains.

A mass turning with the crank at angle :math:`\alpha` (radius R, mass m) puts the force
:math:`m R\omega^2 e^{i(\theta+\alpha)}` on the block: a forward first-order phasor
:math:`U\omega^2` with the unbalance :math:`U = m R e^{i\alpha}` [kg m].  An eccentric
on a shaft turning at :math:`s\omega` (s = ±k) gives the order-k phasor
:math:`U s^2\omega^2`, forward when s > 0 and backward when s < 0.  So

* counterweights cancel the rotating forces and couples and the forward first-order
  reciprocating phasors;
* a shaft at :math:`-\omega` cancels backward first-order phasors (inline-3, split-pin V6);
* shafts at :math:`\pm k\omega` cancel order-k phasors (a Lanchester pair at
  :math:`\pm 2\omega` for the inline-4's second-order force);
* two planes on a mass carrier cancel a couple as well as a force.

A shaft's axis does not change its force, but it changes the roll
(:mod:`balance.core.shafts`: where the axes go, the roll they make, and the placement that
cancels the engine's); the proposal's notes say where the shafts raise an order's roll, and
what shafts fixed by the layout (:class:`~balance.core.engine.ShaftPosition`) leave.

Everything here is plain numpy over the cylinder table; :func:`propose` returns a
:class:`Proposal` and :func:`balance.core.counterweights.proposal_phasors` the phasors
of its masses, from which the
residual is formed.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from balance.core._numerics import mean
from balance.core.balance_factor import BalanceFactor, FactorEquivalents, cylinder_shares
from balance.core.engine import Engine, ShaftPosition
from balance.core.errors import AnalysisError
from balance.core.phasors import rounding_threshold
from balance.core.shafts import BalanceShaft, default_axes, place_shafts
from balance.core.speed import speed_squared
from balance.core.throws import crank_pins, group_least, rods_per_pin

__all__ = [
    "DEFAULT_ORDERS",
    "STRATEGIES",
    "Counterweight",
    "Proposal",
    "balance_shafts",
    "completed_proposal",
    "propose",
]

ComplexArray = NDArray[np.complex128]
#: Force forward, force backward, moment forward, moment backward per order [N, N m].
ByOrder = tuple[dict[int, complex], dict[int, complex], dict[int, complex], dict[int, complex]]
FloatArray = NDArray[np.float64]

DEFAULT_ORDERS = (1, 2)
STRATEGIES = ("two-plane", "per-throw")


@dataclass(frozen=True)
class Counterweight:
    r"""A mass on the crankshaft, turning with it.

    Attributes
    ----------
    z : float
        Axial plane [m].
    unbalance : complex
        :math:`m R e^{i\alpha}` [kg m], the angle measured at crank angle 0 from +y in the
        direction of rotation.
    radius : float
        Radius of the mass's centre of gravity [m].
    sense : int
        The sense its crank axis turns in relative to crankshaft 1 (+1 or -1): with -1 the
        mass turns backward, at :math:`\alpha - \theta` (docs/several-crankshafts.md).
    x, y : float
        Its crank axis's position [m] (the origin for one crank).
    axis : str or None
        The name of its crank axis; None for one crank.
    """

    z: float
    unbalance: complex
    radius: float
    sense: int = 1
    x: float = 0.0
    y: float = 0.0
    axis: str | None = None

    @property
    def mass(self) -> float:
        """Mass at :attr:`radius` [kg]."""
        return abs(self.unbalance) / self.radius

    @property
    def angle_deg(self) -> float:
        """Angle at crank angle 0 [deg], in [0, 360)."""
        return _deg(self.unbalance)


@dataclass(frozen=True)
class Proposal:
    """A balancing proposal and the choices behind it.

    Attributes
    ----------
    counterweights : tuple of Counterweight
        On the crank, in z order.
    shafts : tuple of BalanceShaft
        The balance shafts.
    strategy : {'two-plane', 'per-throw'}
        How the counterweights are placed.
    orders : tuple of int
        The orders the proposal was asked to cancel.
    balance_factor : float or None
        The balance factor as a share of each cylinder's reciprocating mass [1]; None
        without one, or where that share differs from throw to throw (a factor given as a
        share of one cylinder's mass on an engine whose throws carry different numbers of
        rods: :attr:`factor` holds it).
    counterweight_radius : float
        Radius of the counterweights' centres of gravity [m].
    cancel_roll : bool
        Whether the shafts were placed to cancel the roll.
    notes : tuple of str
        What the proposal leaves and why, one sentence each.
    factor : FactorEquivalents or None
        The balance factor as given, with its convention and its value in the other one.
    """

    counterweights: tuple[Counterweight, ...]
    shafts: tuple[BalanceShaft, ...]
    strategy: str
    orders: tuple[int, ...]
    balance_factor: float | None
    counterweight_radius: float
    cancel_roll: bool = False
    notes: tuple[str, ...] = field(default=())
    factor: FactorEquivalents | None = None

    @property
    def is_empty(self) -> bool:
        """True when nothing is proposed."""
        return not self.counterweights and not self.shafts


def _deg(z: complex) -> float:
    value = math.degrees(math.atan2(z.imag, z.real)) % 360.0
    value = round(value, 9)
    return 0.0 if value >= 360.0 or abs(z) == 0 else value + 0.0


def _counterweight_targets(
    layout: Engine, first_order: ComplexArray, shares: NDArray[np.float64] | None = None
) -> ComplexArray:
    r"""Per-cylinder unbalance the counterweights set out to cancel [kg m].

    Parameters
    ----------
    layout : Engine
    first_order : ndarray of complex
        :math:`G_1` of each cylinder's :math:`-s''/r` (1 without offset).
    shares : ndarray, optional
        Share of each cylinder's own reciprocating mass to put on the crank (from the
        balance factor, :func:`balance.core.balance_factor.cylinder_shares`).  Without it,
        the forward share of the first-order reciprocating phasor, :math:`G_1/2` (50 % of
        the reciprocating mass for an unoffset cylinder; for rods on a common pin the vector
        sum turns this into the classical results, e.g. 100 % of one rod for a 90° V-twin).

    Returns
    -------
    ndarray of complex
        :math:`(m_{rot} r + \text{share}\cdot m_{rec} r)\, e^{i\varphi}` per cylinder.
    """
    r = layout.crank_radius
    if shares is None:
        share = 0.5 * np.asarray(first_order, dtype=np.complex128)
    else:
        share = np.asarray(shares, dtype=np.complex128)
    return np.asarray(
        (layout.rotating_mass * r + share * layout.reciprocating_mass * r)
        * np.exp(1j * layout.throw),
        dtype=np.complex128,
    )


def zero_below(value: complex, scale: float, n_terms: int) -> complex:
    """0 for a sum within the rounding of its terms (:func:`balance.core.phasors.cancel_to_zero`:
    relative to ``scale``, absolute below the smallest normal number).

    Parameters
    ----------
    value : complex
        A sum of ``n_terms`` terms.
    scale : float
        The magnitude of its largest term.
    n_terms : int
        How many terms were added.

    Returns
    -------
    complex
        ``value``, or exactly 0 where it cannot be told from rounding.
    """
    return 0j if abs(value) <= rounding_threshold(scale, n_terms) else value


def cancelling_planes(
    force: complex, moment: complex, z_ref: float, z_min: float, z_max: float
) -> tuple[tuple[float, complex], ...]:
    r"""Unbalance-like plane values that put ``-force`` and ``-moment`` (about z_ref).

    Parameters
    ----------
    force, moment : complex
        The phasors to cancel [N, N m] (the moment about ``z_ref``).
    z_ref : float
        The axial position the moment is taken about [m].
    z_min, z_max : float
        The crank's ends [m].

    Returns
    -------
    tuple of (float, complex)
        ``(z, value)`` pairs such that :math:`\sum v = -F` and
        :math:`\sum (z - z_{ref}) v = -M`: one plane where the pair is a single force along
        a line (M/F real and inside the crank), otherwise the two crank ends.
    """
    if force == 0 and moment == 0:
        return ()
    if force != 0:
        arm = moment / force
        span = max(z_max - z_min, 0.0)
        if abs(arm.imag) <= 1e-9 * (abs(arm) + span + 1e-300):
            z_star = z_ref + arm.real
            if z_min - 1e-12 <= z_star <= z_max + 1e-12 or z_max == z_min:
                return ((z_star, -force),)
    if z_max == z_min:
        raise AnalysisError(
            "a couple cannot be cancelled with all cylinders in one plane; give reference_z "
            "in the cylinders' plane"
        )
    a, b = z_min - z_ref, z_max - z_ref
    v_b = (-moment + a * force) / (b - a)  # v_a + v_b = -F ; a v_a + b v_b = -M
    v_a = -force - v_b
    return ((z_min, v_a), (z_max, v_b))


def propose(
    layout: Engine,
    first_order: ComplexArray,
    force_forward: ComplexArray,
    force_backward: ComplexArray,
    moment_forward: ComplexArray,
    moment_backward: ComplexArray,
    orders: Sequence[int] | NDArray[np.integer],
    *,
    cancel: Iterable[int] | None = None,
    strategy: str = "two-plane",
    balance_factor: float | BalanceFactor | None = None,
    counterweight_radius: float | None = None,
    fixed_shafts: Sequence[ShaftPosition] | None = None,
    cancel_roll: bool = False,
    roll: ComplexArray | None = None,
) -> Proposal:
    r"""Propose counterweights and balance shafts for a layout.

    Parameters
    ----------
    layout : Engine
    first_order : ndarray of complex
        :math:`G_1` of each cylinder (from the analysis' acceleration coefficients).
    force_forward, force_backward, moment_forward, moment_backward : ndarray of complex
        The engine's reciprocating phasors per order (N, N m), for ``orders``.
    orders : sequence of int
        The orders of those phasors.
    cancel : iterable of int, optional
        Orders the proposal cancels (default 1 and 2, as far as they are among ``orders``).
    strategy : {'two-plane', 'per-throw'}
        Counterweights at the two crank ends (the lightest answer for the free couple), or
        one for each throw (each throw balanced in itself, which also unloads the main
        bearings).
    balance_factor : float or BalanceFactor, optional
        The reciprocating mass put on the crank, instead of the forward share of the first
        order (singles and twins): a float is a share of each cylinder's reciprocating mass
        [1], a :class:`~balance.core.balance_factor.BalanceFactor` says its convention.
    counterweight_radius : float, optional
        Radius of the counterweights' centres of gravity [m]; default the mean crank radius.
    fixed_shafts : sequence of ShaftPosition, optional
        The shafts the design has room for (the layout's ``balance: shafts:``): the proposal
        then uses these speed ratios only, finds their unbalances, phases and planes, keeps
        every coordinate given, and says in its notes what they leave.  Without them, one
        shaft per order and sense that needs one, with its axis at the default place
        (:func:`default_axes`): 2 r from the crank axis, below it; a single one straight
        below, the two of a pair of one order at ``x = -r`` (forward) and ``x = +r``
        (backward), ``y = -sqrt(3) r``.
    cancel_roll : bool
        Place the shafts of each order (the coordinates not given) so that the roll of that
        order, the engine's and the shafts' together, is zero (:func:`place_for_roll`);
        needs ``roll``.  Where that cannot be done, the notes say why.
    roll : ndarray of complex, optional
        The engine's roll phasors for ``orders`` [N m]; with them the notes also say where
        the shafts make the roll of an order larger than the engine's own.

    Returns
    -------
    Proposal
    """
    if strategy not in STRATEGIES:
        raise AnalysisError(f"unknown strategy {strategy!r}; valid: {', '.join(STRATEGIES)}")
    ks = [int(k) for k in np.asarray(orders).ravel()]
    wanted = tuple(sorted({int(k) for k in (cancel if cancel is not None else DEFAULT_ORDERS)}))
    if any(k < 1 for k in wanted):
        raise AnalysisError("orders to cancel start at 1")
    w2 = float(speed_squared(layout.speed))
    r_mean = mean(layout.crank_radius)
    radius = float(counterweight_radius) if counterweight_radius is not None else r_mean
    if not (math.isfinite(radius) and radius > 0):
        raise AnalysisError("counterweight radius must be a positive length")
    z = layout.z
    z_ref = layout.reference_z
    z_min, z_max = float(z.min()), float(z.max())
    lever = z - z_ref
    n = layout.n_cylinders
    factor = (
        BalanceFactor(float(balance_factor))
        if isinstance(balance_factor, int | float)
        else balance_factor
    )
    rods = rods_per_pin(layout) if factor is not None else None  # only a factor needs them
    equivalents = (
        FactorEquivalents.of(factor, rods) if factor is not None and rods is not None else None
    )

    ff = {k: complex(force_forward[i]) for i, k in enumerate(ks)}
    fb = {k: complex(force_backward[i]) for i, k in enumerate(ks)}
    mf = {k: complex(moment_forward[i]) for i, k in enumerate(ks)}
    mb = {k: complex(moment_backward[i]) for i, k in enumerate(ks)}
    missing = [k for k in wanted if k not in ff]
    if missing:
        raise AnalysisError(
            f"orders {missing} are to be cancelled but were not analysed; include them in orders"
        )

    counterweights: list[Counterweight] = []
    if 1 in wanted:
        shares = cylinder_shares(factor, rods) if factor is not None and rods is not None else None
        targets = _counterweight_targets(layout, first_order, shares)
        scale_f = float(np.sum(np.abs(targets)))
        scale_m = float(np.sum(np.abs(targets * lever)))
        if strategy == "two-plane":
            force = zero_below(complex(targets.sum()), scale_f, n)
            moment = zero_below(complex((targets * lever).sum()), scale_m, n)
            for plane_z, value in cancelling_planes(force, moment, z_ref, z_min, z_max):
                counterweights.append(Counterweight(plane_z, value, radius))
        else:
            groups = crank_pins(layout)
            throw_planes = group_least(z, groups)
            # listed along the crank (z), throws in one plane by their angle
            for g in np.lexsort((np.arange(throw_planes.size), throw_planes)):
                plane_z = throw_planes[g]
                members = groups == g
                value = complex(targets[members].sum())
                value = zero_below(value, float(np.abs(targets[members]).sum()), 2)
                if value != 0:
                    counterweights.append(Counterweight(float(plane_z), -value, radius))
        # what the counterweights take off the forward first order of the reciprocating part
        cw_force = sum((c.unbalance for c in counterweights), 0j) * w2
        cw_moment = sum(((c.z - z_ref) * c.unbalance for c in counterweights), 0j) * w2
        rot = layout.rotating_mass * layout.crank_radius * w2 * np.exp(1j * layout.throw)
        ff[1] = ff[1] + complex(rot.sum()) + cw_force
        mf[1] = mf[1] + complex((rot * lever).sum()) + cw_moment
        f_scale = float(
            np.sum(np.abs(rot)) + np.sum(layout.reciprocating_mass * layout.crank_radius) * w2
        )
        ff[1] = zero_below(ff[1], f_scale + abs(cw_force), n + 2)
        mf[1] = zero_below(mf[1], f_scale * (float(np.abs(lever).max()) + 1e-300), n + 2)

    return completed_proposal(
        layout,
        counterweights,
        (ks, wanted, (ff, fb, mf, mb), roll),
        strategy=strategy,
        radius=radius,
        equivalents=equivalents,
        fixed_shafts=fixed_shafts,
        cancel_roll=cancel_roll,
        mean_radius=r_mean,
    )


def completed_proposal(
    layout: Engine,
    counterweights: Sequence[Counterweight],
    left: tuple[Sequence[int], Sequence[int], ByOrder, ComplexArray | None],
    *,
    strategy: str,
    radius: float,
    equivalents: FactorEquivalents | None,
    fixed_shafts: Sequence[ShaftPosition] | None,
    cancel_roll: bool,
    counterweight_senses: tuple[int, ...] = (1,),
    mean_radius: float | None = None,
) -> Proposal:
    """The proposal from its counterweights: the shafts for what they leave and the notes
    (:func:`balance_shafts`), the tail of :func:`propose` and of
    :func:`balance.core.counterweights.propose_geared`.

    Parameters
    ----------
    layout : Engine
        The engine.
    counterweights : sequence of Counterweight
        The counterweights proposed.
    left : tuple
        ``(ks, wanted, phasors, roll)`` as :func:`balance_shafts` takes them (the phasors
        with the counterweights' part in the first order [N, N m], the roll [N m] or None).
    strategy, radius, equivalents
        The counterweights' strategy, radius [m] and balance factor (or None).
    fixed_shafts, cancel_roll, counterweight_senses, mean_radius
        As :func:`balance_shafts`.

    Returns
    -------
    Proposal
    """
    ks, wanted, phasors, roll = left
    shafts, notes = balance_shafts(
        layout,
        ks,
        wanted,
        phasors,
        fixed_shafts=fixed_shafts,
        cancel_roll=cancel_roll,
        roll=roll,
        counterweight_senses=counterweight_senses,
        mean_radius=mean_radius,
    )
    return Proposal(
        counterweights=tuple(counterweights),
        shafts=tuple(shafts),
        strategy=strategy,
        orders=tuple(wanted),
        balance_factor=equivalents.each_cylinder if equivalents is not None else None,
        counterweight_radius=radius,
        cancel_roll=cancel_roll,
        notes=tuple(notes),
        factor=equivalents,
    )


def balance_shafts(
    layout: Engine,
    ks: Sequence[int],
    wanted: Sequence[int],
    phasors: ByOrder,
    *,
    fixed_shafts: Sequence[ShaftPosition] | None = None,
    cancel_roll: bool = False,
    roll: ComplexArray | None = None,
    counterweight_senses: tuple[int, ...] = (1,),
    mean_radius: float | None = None,
) -> tuple[list[BalanceShaft], list[str]]:
    """The balance shafts for what the counterweights leave, and the notes on them.

    Parameters
    ----------
    layout : Engine
        The engine (its speed, crank radii, ``z`` and ``reference_z``).
    ks : sequence of int
        The orders of ``phasors`` and ``roll``.
    wanted : sequence of int
        The orders to cancel.
    phasors : tuple of dict
        Force forward, force backward, moment forward, moment backward per order [N, N m],
        with the counterweights' part already in the first order (a forward first order is
        always the counterweights').
    fixed_shafts, cancel_roll, roll
        As :func:`propose`.
    counterweight_senses : tuple of int
        The senses of the first order that belong to the counterweights (no shaft is
        proposed for them): forward, and backward too where crank axes counter-rotate.
    mean_radius : float, optional
        The mean crank radius [m], where the caller has it (default: the engine's).

    Returns
    -------
    shafts : list of BalanceShaft
        The shafts, one per order and sense that needs one.
    notes : list of str
        What the shafts leave and what they do to the roll.
    """
    ff, fb, mf, mb = phasors
    w2 = float(speed_squared(layout.speed))
    r_mean = mean(layout.crank_radius) if mean_radius is None else mean_radius
    z_ref = layout.reference_z
    z_range: tuple[float, float] | None = None  # the crank's ends, once a shaft needs them
    notes: list[str] = []
    shafts: list[BalanceShaft] = []
    given = {f.speed_ratio: f for f in fixed_shafts} if fixed_shafts is not None else None
    carried: set[int] = set()
    for k in wanted:
        for sense, force, moment in ((+1, ff[k], mf[k]), (-1, fb[k], mb[k])):
            if k == 1 and sense in counterweight_senses:
                continue  # forward first order belongs to the counterweights
            if force == 0 and moment == 0:
                continue
            speed_ratio = sense * k
            spec = given.get(speed_ratio) if given is not None else None
            if given is not None and spec is None:
                other = (fb[k], mb[k]) if sense > 0 else (ff[k], mf[k])
                notes.append(_left_note(k, sense, force, moment, other != (0j, 0j) and k > 1))
                continue
            if z_range is None:
                z_range = (float(layout.z.min()), float(layout.z.max()))
            planes = cancelling_planes(force, moment, z_ref, *z_range)
            unbalances = tuple((pz, v / (k * k * w2)) for pz, v in planes)
            x, y = _default_position(k, sense, ff, fb, mf, mb, r_mean)
            x_from = y_from = "default"
            if spec is not None:
                carried.add(speed_ratio)
                if spec.x is not None:
                    x, x_from = spec.x, "layout"
                if spec.y is not None:
                    y, y_from = spec.y, "layout"
            shafts.append(BalanceShaft(speed_ratio, float(x), float(y), unbalances, x_from, y_from))
    for spec in fixed_shafts or ():
        if spec.speed_ratio not in carried:
            notes.append(_idle_note(spec.speed_ratio, wanted))

    shafts, roll_notes = place_shafts(
        layout, shafts, roll, ks, cancel_roll=cancel_roll, mean_radius=r_mean
    )
    return shafts, notes + roll_notes


def _default_position(
    k: int,
    sense: int,
    ff: dict[int, complex],
    fb: dict[int, complex],
    mf: dict[int, complex],
    mb: dict[int, complex],
    r: float,
) -> tuple[float, float]:
    pair = (ff[k] != 0 or mf[k] != 0) and (fb[k] != 0 or mb[k] != 0) and k > 1
    return default_axes(r, sense if pair else 0)


def _left_note(k: int, sense: int, force: complex, moment: complex, line: bool) -> str:
    """Note for an order and sense that needs a shaft the layout's ``shafts`` does not give."""
    part = "forward" if sense > 0 else "backward"
    text = (
        f"order {k}: the {part} part is left (force {abs(force):.4g} N, moment "
        f"{abs(moment):.4g} N m): balance.shafts has no shaft at {sense * k:+d}"
    )
    if line:
        text += f" (a force along a line needs a shaft at +{k} and one at -{k})"
    return text


def _idle_note(speed_ratio: int, wanted: Sequence[int]) -> str:
    """Note for a shaft of the layout's ``shafts`` that has nothing to carry."""
    k = abs(speed_ratio)
    head = f"the shaft at {speed_ratio:+d} in balance.shafts carries nothing and is left out"
    if speed_ratio == 1:
        return head + ": the counterweights on the crank take the forward first order"
    if k not in wanted:
        listed = ", ".join(map(str, wanted))
        return head + f": order {k} is not among the orders to cancel ({listed})"
    part = "forward" if speed_ratio > 0 else "backward"
    return head + f": the engine has no {part} order-{k} force or moment to cancel"
