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

Everything here is plain numpy over the cylinder table; :func:`propose` returns a
:class:`Proposal` and :func:`proposal_phasors` the phasors of its masses, from which the
residual is formed.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from balance.core.engine import Engine
from balance.core.errors import AnalysisError
from balance.core.phasors import CANCELLATION_FACTOR
from balance.core.speed import speed_squared

__all__ = [
    "DEFAULT_ORDERS",
    "STRATEGIES",
    "BalanceShaft",
    "Counterweight",
    "Proposal",
    "ProposalPhasors",
    "balance_factor_study",
    "counterweight_targets",
    "optimal_balance_factor",
    "proposal_phasors",
    "propose",
    "shaft_roll_phasors",
    "throw_groups",
]

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]

DEFAULT_ORDERS = (1, 2)
STRATEGIES = ("two-plane", "per-throw")
_EPS = float(np.finfo(np.float64).eps)


@dataclass(frozen=True)
class Counterweight:
    """A mass on the crankshaft, turning with it.

    Attributes
    ----------
    z : float
        Axial plane [m].
    unbalance : complex
        :math:`m R e^{i\alpha}` [kg m], the angle measured at crank angle 0 from +y in the
        direction of rotation.
    radius : float
        Radius of the mass's centre of gravity [m].
    """

    z: float
    unbalance: complex
    radius: float

    @property
    def mass(self) -> float:
        """Mass at :attr:`radius` [kg]."""
        return abs(self.unbalance) / self.radius

    @property
    def angle_deg(self) -> float:
        """Angle at crank angle 0 [deg], in [0, 360)."""
        return _deg(self.unbalance)


@dataclass(frozen=True)
class BalanceShaft:
    """A shaft turning at ``speed_ratio`` times crank speed with eccentric masses.

    Attributes
    ----------
    speed_ratio : int
        Shaft speed over crank speed; negative turns against the crank.
    x, y : float
        Position of the shaft axis in the transverse plane [m] (for roll).
    planes : tuple of (float, complex)
        ``(z, unbalance)`` of each eccentric: plane [m] and :math:`m e\\, e^{i\alpha}` [kg m];
        the mass sits at :math:`\alpha + s\theta`.
    """

    speed_ratio: int
    x: float
    y: float
    planes: tuple[tuple[float, complex], ...]

    @property
    def total_unbalance(self) -> complex:
        """Sum of the planes' unbalances [kg m] (what the shaft's force depends on)."""
        return complex(sum(u for _, u in self.planes))


@dataclass(frozen=True)
class Proposal:
    """A balancing proposal and the choices behind it."""

    counterweights: tuple[Counterweight, ...]
    shafts: tuple[BalanceShaft, ...]
    strategy: str
    orders: tuple[int, ...]
    balance_factor: float | None
    counterweight_radius: float
    cancel_roll: bool = False
    notes: tuple[str, ...] = field(default=())

    @property
    def is_empty(self) -> bool:
        """True when nothing is proposed."""
        return not self.counterweights and not self.shafts


@dataclass(frozen=True)
class ProposalPhasors:
    """Phasors of the proposed masses, per order (same layout as the analysis)."""

    force_forward: ComplexArray
    force_backward: ComplexArray
    moment_forward: ComplexArray
    moment_backward: ComplexArray
    roll: ComplexArray


def _deg(z: complex) -> float:
    value = math.degrees(math.atan2(z.imag, z.real)) % 360.0
    value = round(value, 9)
    return 0.0 if value >= 360.0 or abs(z) == 0 else value + 0.0


def throw_groups(layout: Engine) -> NDArray[np.intp]:
    """Index of the crank throw (and rod plane) each cylinder's pin belongs to.

    Rods whose pins are at the same angle and the same axial position share a throw;
    split pins and staggered rods are separate planes.
    """
    keys = np.round(np.mod(np.degrees(layout.throw), 360.0), 9) % 360.0
    z = np.round(layout.z, 12)
    pairs = np.stack([keys, z], axis=-1)
    _, inverse = np.unique(pairs, axis=0, return_inverse=True)
    return np.asarray(inverse.ravel(), dtype=np.intp)


def counterweight_targets(
    layout: Engine, first_order: ComplexArray, balance_factor: float | None = None
) -> ComplexArray:
    r"""Per-cylinder unbalance the counterweights set out to cancel [kg m].

    Parameters
    ----------
    layout : Engine
    first_order : ndarray of complex
        :math:`G_1` of each cylinder's :math:`-s''/r` (1 without offset).
    balance_factor : float, optional
        Share of each cylinder's reciprocating mass to put on the crank.  Without it, the
        forward share of the first-order reciprocating phasor, :math:`G_1/2` (50 % of the
        reciprocating mass for an unoffset cylinder; for rods on a common pin the vector
        sum turns this into the classical results, e.g. 100 % of one rod for a 90° V-twin).

    Returns
    -------
    ndarray of complex
        :math:`(m_{rot} r + \text{share}\cdot m_{rec} r)\, e^{i\varphi}` per cylinder.
    """
    r = layout.crank_radius
    if balance_factor is None:
        share = 0.5 * np.asarray(first_order, dtype=np.complex128)
    else:
        share = np.full(layout.n_cylinders, float(balance_factor), dtype=np.complex128)
    return np.asarray(
        (layout.rotating_mass * r + share * layout.reciprocating_mass * r)
        * np.exp(1j * layout.throw),
        dtype=np.complex128,
    )


def _zero_below(value: complex, scale: float, n_terms: int) -> complex:
    return 0j if abs(value) <= CANCELLATION_FACTOR * max(n_terms, 1) * _EPS * scale else value


def _planes_for(
    force: complex, moment: complex, z_ref: float, z_min: float, z_max: float
) -> tuple[tuple[float, complex], ...]:
    r"""Unbalance-like plane values that put ``-force`` and ``-moment`` (about z_ref).

    Returns ``(z, value)`` pairs such that :math:`\\sum v = -F` and
    :math:`\\sum (z - z_{ref}) v = -M`: one plane where the pair is a single force along
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
    # v_a + v_b = -F ; a v_a + b v_b = -M
    v_b = (-moment + a * force) / (b - a)
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
    balance_factor: float | None = None,
    counterweight_radius: float | None = None,
    shaft_positions: Sequence[tuple[float, float]] | None = None,
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
    balance_factor : float, optional
        Share of each cylinder's reciprocating mass put on the crank, instead of the
        forward share of the first order (singles and twins).
    counterweight_radius : float, optional
        Radius of the counterweights' centres of gravity [m]; default the mean crank radius.
    shaft_positions : sequence of (x, y), optional
        Shaft axes in the transverse plane [m], in the order the shafts are proposed;
        default: below the crank at ``y = -2 r``, pairs of the same order at
        ``x = -2 r`` (forward) and ``x = +2 r`` (backward).
    cancel_roll : bool
        For a pair of shafts of the same order (a Lanchester pair), move their axes (the
        least from the given positions) so that they also cancel the engine's roll of that
        order; needs ``roll``.
    roll : ndarray of complex, optional
        The engine's roll phasors for ``orders``.

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
    r_mean = float(np.mean(layout.crank_radius))
    radius = float(counterweight_radius) if counterweight_radius is not None else r_mean
    if not (math.isfinite(radius) and radius > 0):
        raise AnalysisError("counterweight radius must be a positive length")
    z = layout.z
    z_ref = layout.reference_z
    z_min, z_max = float(z.min()), float(z.max())
    lever = z - z_ref
    n = layout.n_cylinders
    notes: list[str] = []

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
        targets = counterweight_targets(layout, first_order, balance_factor)
        scale_f = float(np.sum(np.abs(targets)))
        scale_m = float(np.sum(np.abs(targets * lever)))
        if strategy == "two-plane":
            force = _zero_below(complex(targets.sum()), scale_f, n)
            moment = _zero_below(complex((targets * lever).sum()), scale_m, n)
            for plane_z, value in _planes_for(force, moment, z_ref, z_min, z_max):
                counterweights.append(Counterweight(plane_z, value, radius))
        else:
            groups = throw_groups(layout)
            for g in range(int(groups.max()) + 1):
                members = groups == g
                value = complex(targets[members].sum())
                value = _zero_below(value, float(np.abs(targets[members]).sum()), 2)
                if value != 0:
                    counterweights.append(Counterweight(float(z[members][0]), -value, radius))
        # what the counterweights take off the forward first order of the reciprocating part
        cw_force = sum((c.unbalance for c in counterweights), 0j) * w2
        cw_moment = sum(((c.z - z_ref) * c.unbalance for c in counterweights), 0j) * w2
        rot = layout.rotating_mass * layout.crank_radius * w2 * np.exp(1j * layout.throw)
        ff[1] = ff[1] + complex(rot.sum()) + cw_force
        mf[1] = mf[1] + complex((rot * lever).sum()) + cw_moment
        f_scale = float(
            np.sum(np.abs(rot)) + np.sum(layout.reciprocating_mass * layout.crank_radius) * w2
        )
        ff[1] = _zero_below(ff[1], f_scale + abs(cw_force), n + 2)
        mf[1] = _zero_below(mf[1], f_scale * (float(np.abs(lever).max()) + 1e-300), n + 2)
        if balance_factor is not None:
            notes.append(
                f"balance factor {balance_factor:.0%}: the rest of the forward first order "
                "is left as a residual"
            )

    shafts: list[BalanceShaft] = []
    positions = list(shaft_positions or [])
    for k in wanted:
        for sense, force, moment in ((+1, ff[k], mf[k]), (-1, fb[k], mb[k])):
            if k == 1 and sense > 0:
                continue  # forward first order belongs to the counterweights
            if force == 0 and moment == 0:
                continue
            speed_ratio = sense * k
            planes = _planes_for(force, moment, z_ref, z_min, z_max)
            unbalances = tuple((pz, v / (k * k * w2)) for pz, v in planes)
            if positions:
                x, y = positions.pop(0)
            else:
                x, y = _default_position(k, sense, ff, fb, mf, mb, r_mean)
            shafts.append(BalanceShaft(speed_ratio, float(x), float(y), unbalances))

    if cancel_roll:
        if roll is None:
            raise AnalysisError("cancelling roll needs the engine's roll phasors")
        shafts = _place_for_roll(shafts, {k: complex(roll[i]) for i, k in enumerate(ks)}, w2, notes)

    return Proposal(
        counterweights=tuple(counterweights),
        shafts=tuple(shafts),
        strategy=strategy,
        orders=wanted,
        balance_factor=balance_factor,
        counterweight_radius=radius,
        cancel_roll=cancel_roll,
        notes=tuple(notes),
    )


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
    x = (-2.0 * r if sense > 0 else 2.0 * r) if pair else 0.0
    return x, -2.0 * r


def shaft_roll_phasors(
    shafts: Sequence[BalanceShaft], speed: float, orders: Sequence[int] | NDArray[np.integer]
) -> ComplexArray:
    r"""Roll torque phasors that the shafts' eccentric forces put on the block.

    A shaft at :math:`p = y + ix` with force :math:`F(\theta) = P e^{is\theta}` gives the
    torque :math:`\mathrm{Im}(\bar p F)` about the crank axis (positive in the direction of
    rotation): :math:`R = -i\bar p P` for s > 0, :math:`R = i p \bar P` for s < 0.  At
    constant speed the shaft's drive carries no torque.
    """
    ks = np.asarray(orders, dtype=np.intp).ravel()
    out = np.zeros(ks.size, dtype=np.complex128)
    for shaft in shafts:
        s = shaft.speed_ratio
        p = complex(shaft.y, shaft.x)
        P = shaft.total_unbalance * s * s * float(speed_squared(speed))
        R = -1j * p.conjugate() * P if s > 0 else 1j * p * P.conjugate()
        out[ks == abs(s)] += R
    return out


def _place_for_roll(
    shafts: list[BalanceShaft], roll: dict[int, complex], w2: float, notes: list[str]
) -> list[BalanceShaft]:
    """Move pairs of same-order shafts so that their forces also cancel the roll."""
    result = list(shafts)
    by_order: dict[int, list[int]] = {}
    for i, shaft in enumerate(result):
        by_order.setdefault(abs(shaft.speed_ratio), []).append(i)
    for k, idx in by_order.items():
        target = roll.get(k, 0j)
        if len(idx) != 2 or target == 0:
            continue
        a, b = (result[i] for i in idx)
        # roll of the pair is linear in (x_a, y_a, x_b, y_b): R = sum c_j q_j
        cols = []
        for shaft in (a, b):
            s = shaft.speed_ratio
            P = shaft.total_unbalance * s * s * w2
            if s > 0:  # R = -i conj(p) P, p = y + i x
                cols += [-1j * (-1j) * P, -1j * P]  # d/dx, d/dy
            else:  # R = i p conj(P)
                cols += [1j * 1j * P.conjugate(), 1j * P.conjugate()]
        current = shaft_roll_phasors([a, b], math.sqrt(w2), [k])[0]
        need = -target - current
        A = np.array([[c.real for c in cols], [c.imag for c in cols]])
        rhs = np.array([need.real, need.imag])
        step, *_ = np.linalg.lstsq(A, rhs, rcond=None)
        if np.linalg.norm(A @ step - rhs) > 1e-9 * (abs(target) + 1e-300):
            notes.append(f"order {k}: the shaft pair cannot cancel the roll")
            continue
        moved = []
        for j, shaft in enumerate((a, b)):
            moved.append(
                BalanceShaft(
                    shaft.speed_ratio,
                    shaft.x + float(step[2 * j]),
                    shaft.y + float(step[2 * j + 1]),
                    shaft.planes,
                )
            )
        result[idx[0]], result[idx[1]] = moved
        notes.append(f"order {k}: shaft axes placed to cancel the order-{k} roll as well")
    return result


def proposal_phasors(
    proposal: Proposal, layout: Engine, orders: Sequence[int] | NDArray[np.integer]
) -> ProposalPhasors:
    """Forward and backward phasors of every proposed mass, and their roll, per order."""
    ks = np.asarray(orders, dtype=np.intp).ravel()
    w2 = float(speed_squared(layout.speed))
    z_ref = layout.reference_z
    zeros = np.zeros(ks.size, dtype=np.complex128)
    ff, fb, mf, mb = zeros.copy(), zeros.copy(), zeros.copy(), zeros.copy()
    first = ks == 1
    for cw in proposal.counterweights:
        ff[first] += cw.unbalance * w2
        mf[first] += (cw.z - z_ref) * cw.unbalance * w2
    for shaft in proposal.shafts:
        s = shaft.speed_ratio
        at = ks == abs(s)
        for plane_z, u in shaft.planes:
            force = u * s * s * w2
            if s > 0:
                ff[at] += force
                mf[at] += (plane_z - z_ref) * force
            else:
                fb[at] += force
                mb[at] += (plane_z - z_ref) * force
    roll = shaft_roll_phasors(proposal.shafts, layout.speed, ks)
    return ProposalPhasors(ff, fb, mf, mb, roll)


def _residual_first_order(
    layout: Engine,
    first_order: ComplexArray,
    factor: float,
    pin_first_order: tuple[ComplexArray, ComplexArray] | None = None,
) -> tuple[complex, complex, complex]:
    """Free first-order force phasors (forward, backward) and moment peak after counterweights
    carrying rotating mass plus ``factor`` of the reciprocating mass, per-throw; link pins'
    relative motion (``pin_first_order``: forward and backward per cylinder [N]) added."""
    w2 = float(speed_squared(layout.speed))
    r = layout.crank_radius
    c1 = 0.5 * np.asarray(first_order, dtype=np.complex128)
    rec = layout.reciprocating_mass * r * w2
    along = np.exp(1j * layout.bank)
    turn = np.exp(1j * (layout.throw - layout.bank))
    fwd_terms = rec * c1 * turn * along - factor * rec * np.exp(1j * layout.throw)
    bwd_terms = rec * np.conj(c1) * np.conj(turn) * along
    if pin_first_order is not None:
        fwd_terms = fwd_terms + pin_first_order[0]
        bwd_terms = bwd_terms + pin_first_order[1]
    lever = layout.z - layout.reference_z
    moment_peak = abs(complex((fwd_terms * lever).sum())) + abs(complex((bwd_terms * lever).sum()))
    return complex(fwd_terms.sum()), complex(bwd_terms.sum()), complex(moment_peak)


def balance_factor_study(
    layout: Engine,
    first_order: ComplexArray,
    factors: Sequence[float] | FloatArray,
    pin_first_order: tuple[ComplexArray, ComplexArray] | None = None,
) -> dict[str, FloatArray]:
    r"""Residual first-order force against balance factor.

    The rotating masses are balanced in full; ``factor`` of each cylinder's reciprocating
    mass is added to the crank.  The residual first-order force traces an ellipse; its
    vertical (y) and horizontal (x) peaks are

    .. math:: |P^{+} + \bar P^{-}| \quad\text{and}\quad |P^{+} - \bar P^{-}|

    Returns
    -------
    dict of ndarray
        ``factor`` [1], ``vertical_peak`` [N], ``horizontal_peak`` [N], ``moment_peak``
        [N m] (first order).
    """
    f = np.asarray(factors, dtype=np.float64).ravel()
    vertical = np.empty(f.size)
    horizontal = np.empty(f.size)
    moment = np.empty(f.size)
    for i, factor in enumerate(f):
        fwd, bwd, mpk = _residual_first_order(layout, first_order, float(factor), pin_first_order)
        vertical[i] = abs(fwd + bwd.conjugate())
        horizontal[i] = abs(fwd - bwd.conjugate())
        moment[i] = mpk.real
    return {
        "factor": f,
        "vertical_peak": vertical,
        "horizontal_peak": horizontal,
        "moment_peak": moment,
    }


def optimal_balance_factor(
    layout: Engine,
    first_order: ComplexArray,
    pin_first_order: tuple[ComplexArray, ComplexArray] | None = None,
) -> float:
    """Balance factor in [0, 1] that minimises the larger of the vertical and horizontal
    first-order residual peaks (ternary search: the larger of two convex functions is
    convex)."""

    def worst(factor: float) -> float:
        study = balance_factor_study(layout, first_order, [factor], pin_first_order)
        return float(max(study["vertical_peak"][0], study["horizontal_peak"][0]))

    lo, hi = 0.0, 1.0
    for _ in range(200):
        m1, m2 = lo + (hi - lo) / 3, hi - (hi - lo) / 3
        if worst(m1) <= worst(m2):
            hi = m2
        else:
            lo = m1
    return 0.5 * (lo + hi)
