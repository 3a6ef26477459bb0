r"""Counterweights on several crank axes, and the phasors of a proposal's masses.

A counterweight turns with its crank axis (docs/several-crankshafts.md): at
:math:`\alpha_0 + \sigma_s\theta` from the engine-frame position :math:`\alpha_0` it has at
crank angle 0, so that on a counter-rotating axis its centrifugal force is a *backward*
first order, :math:`U\omega^2 e^{-i\theta}` with :math:`U = m R e^{i\alpha_0}`.
:func:`propose_geared` proposes counterweights for an engine with several crank axes:

- without a balance factor, the engine's forward first-order force and moment are cancelled
  by counterweights on the axes turning with crankshaft 1 and the backward ones by
  counterweights on the counter-rotating axes; each axis takes its own cylinders' part of
  its sense (their rotating masses and that half of their reciprocating first order), and
  the other sense's cylinders' part of it is shared equally among the axes of that sense;
- with a balance factor, each cylinder's rotating mass and that share of its reciprocating
  mass is balanced on its own axis, opposite its crank pin, as for one crank;
- ``two-plane`` puts each axis's counterweights at its own end planes (reaching as far as
  the planes of the other sense's cylinders whose part it shares, so that a one-throw axis
  can take a couple), ``per-throw`` one at each of its throws (a shared part joins the throw
  in its plane, or has a counterweight of its own).

What they leave, and every other order, goes to balance shafts as for one crank
(:func:`balance.core.balancing.balance_shafts`).  :func:`proposal_phasors` gives the phasors
of every proposed mass, with the moment about ``z`` of counterweights on displaced axes in
the roll (:func:`counterweight_moment_z`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from balance.core._numerics import mean
from balance.core.balance_factor import BalanceFactor, FactorEquivalents, cylinder_shares
from balance.core.balancing import (
    DEFAULT_ORDERS,
    STRATEGIES,
    Counterweight,
    Proposal,
    cancelling_planes,
    completed_proposal,
    zero_below,
)
from balance.core.engine import Engine, ShaftPosition
from balance.core.errors import AnalysisError
from balance.core.phasors import Phasors
from balance.core.shafts import shaft_roll_phasors
from balance.core.speed import speed_squared
from balance.core.throws import crank_throws, pin_keys, rods_per_throw

__all__ = [
    "axis_rods_per_pin",
    "counterweight_moment_z",
    "proposal_phasors",
    "propose_geared",
]

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]


def counterweight_moment_z(counterweight: Counterweight, w2: float) -> complex:
    r"""The first-order moment about the frame's ``z`` axis of a counterweight's force on
    its displaced crank axis, in the roll's convention (docs/several-crankshafts.md).

    Parameters
    ----------
    counterweight : Counterweight
        The counterweight.
    w2 : float
        :math:`\omega^2` [rad²/s²].

    Returns
    -------
    complex
        :math:`Z` with :math:`y F_x - x F_y = \mathrm{Re}(Z e^{i\theta})` [N m].
    """
    p = complex(counterweight.y, counterweight.x)
    force = counterweight.unbalance * w2
    if counterweight.sense > 0:
        return complex(-1j * p.conjugate() * force)
    return complex(1j * p * force.conjugate())


def proposal_phasors(
    proposal: Proposal, layout: Engine, orders: Sequence[int] | NDArray[np.integer]
) -> Phasors:
    """Forward and backward phasors of every proposed mass, and their roll, per order.

    Parameters
    ----------
    proposal : Proposal
        The counterweights and shafts.
    layout : Engine
        The engine (its speed and ``reference_z``).
    orders : sequence of int
        The orders.

    Returns
    -------
    Phasors
        Force and moment [N, N m] and roll [N m] per order (no rotating part of its own):
        a counterweight on a counter-rotating axis in the backward first order, one on a
        displaced axis with its moment about ``z`` in the roll.
    """
    ks = np.asarray(orders, dtype=np.intp)
    ks = ks if ks.ndim == 1 else ks.ravel()  # the orders given, the sum's orders (Phasors.__add__)
    w2 = float(speed_squared(layout.speed))
    z_ref = layout.reference_z
    zeros = np.zeros(ks.size, dtype=np.complex128)
    ff, fb, mf, mb = zeros.copy(), zeros.copy(), zeros.copy(), zeros.copy()
    first = ks == 1
    # a counterweight off the crank axis has a moment about z: the roll's first order
    displaced = any(cw.x != 0.0 or cw.y != 0.0 for cw in proposal.counterweights)
    roll_z = zeros.copy() if displaced else zeros
    for cw in proposal.counterweights:
        force = cw.unbalance * w2
        if cw.sense > 0:
            ff[first] += force
            mf[first] += (cw.z - z_ref) * force
        else:
            fb[first] += force
            mb[first] += (cw.z - z_ref) * force
        if displaced:
            roll_z[first] += counterweight_moment_z(cw, w2)
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
    if displaced:
        roll = roll + roll_z
    return Phasors(ks, ff, fb, mf, mb, roll=roll)


def axis_rods_per_pin(layout: Engine) -> FloatArray:
    """How many rods share each cylinder's crank pin, pins of different crank axes apart
    (:func:`balance.core.throws.rods_per_pin` axis by axis).

    Parameters
    ----------
    layout : Engine
        The engine.

    Returns
    -------
    ndarray
        Per cylinder, the number of rods on its pin [1].
    """
    axis = layout.axis_table().axis.astype(np.float64)
    keys = np.stack([crank_throws(layout), pin_keys(layout.throw, layout.z)[:, 0], axis], axis=-1)
    _, inverse = np.unique(keys, axis=0, return_inverse=True)
    return rods_per_throw(inverse.ravel())


def _targets(
    layout: Engine,
    first_order: ComplexArray,
    shares: FloatArray | None,
    link_pins: tuple[ComplexArray, ComplexArray] | None = None,
) -> list[tuple[int, float, complex, Any]]:
    """What the counterweights set out to cancel, as ``(axis, z, unbalance, key)`` [kg m]:
    the key groups the terms of one throw (``per-throw``); ``link_pins`` adds each link
    pin's first order (forward, backward [N])."""
    table = layout.axis_table()
    r = layout.crank_radius
    angle = table.axis_phase + table.sense * layout.throw  # engine frame at theta = 0
    rotating = layout.rotating_mass * r * np.exp(1j * angle)
    pins = pin_keys(layout.throw, layout.z)
    out: list[tuple[int, float, complex, Any]] = []
    if shares is not None:
        own = rotating + shares * layout.reciprocating_mass * r * np.exp(1j * angle)
        for i in range(layout.n_cylinders):
            key = ("pin", int(table.axis[i]), *pins[i])
            out.append((int(table.axis[i]), float(layout.z[i]), complex(own[i]), key))
        return out
    g1 = np.asarray(first_order, dtype=np.complex128)
    phi = layout.forward_throw()
    half = 0.5 * layout.reciprocating_mass * r
    forward = half * g1 * np.exp(1j * phi)
    backward = half * np.conj(g1) * np.exp(1j * (2.0 * layout.bank - phi))
    if link_pins is not None:
        w2 = speed_squared(layout.speed)
        forward, backward = forward + link_pins[0] / w2, backward + link_pins[1] / w2
    for i in range(layout.n_cylinders):
        s = int(table.axis[i])
        ahead = table.sense[i] > 0
        mine, other = (forward[i], backward[i]) if ahead else (backward[i], forward[i])
        key = ("pin", s, *pins[i])
        out.append((s, float(layout.z[i]), complex(rotating[i] + mine), key))
        sharing = np.flatnonzero(table.rotation == -table.sense[i])
        for t in sharing:
            plane = ("plane", int(t), round(float(layout.z[i]), 12))
            out.append((int(t), float(layout.z[i]), complex(other / sharing.size), plane))
    return out


def _placed(
    layout: Engine, targets: list[tuple[int, float, complex, Any]], strategy: str, radius: float
) -> list[Counterweight]:
    """The counterweights that cancel ``targets`` on each axis."""
    table = layout.axis_table()
    z_ref = layout.reference_z
    out: list[Counterweight] = []
    for s, name in enumerate(table.names):
        mine = [t for t in targets if t[0] == s]

        def weight(z: float, value: complex, s: int = s, name: str = name) -> Counterweight:
            sense = int(table.rotation[s])
            x, y = float(table.x[s]), float(table.y[s])
            return Counterweight(z, value, radius, sense, x, y, name)

        if strategy == "two-plane":
            # its own end planes, reaching as far as the planes of the shares it takes
            on = table.axis == s
            planes = [*layout.z[on], *(z for _, z, _, _ in mine)]
            z_min, z_max = float(min(planes)), float(max(planes))
            values = np.array([v for _, _, v, _ in mine], dtype=np.complex128)
            lever = np.array([z - z_ref for _, z, _, _ in mine])
            n = len(mine)
            force = zero_below(complex(values.sum()), float(np.abs(values).sum()), n)
            moment = zero_below(
                complex((values * lever).sum()), float(np.abs(values * lever).sum()), n
            )
            out.extend(
                weight(pz, v) for pz, v in cancelling_planes(force, moment, z_ref, z_min, z_max)
            )
            continue
        groups: dict[Any, list[tuple[float, complex]]] = {}
        for _, z, value, key in mine:
            groups.setdefault(key, []).append((z, value))
        # a share of the other sense in the plane of one throw of this axis joins it
        for key in [k for k in groups if k[0] == "plane"]:
            throws = [k for k in groups if k[0] == "pin" and round(k[3], 12) == key[2]]
            if len(throws) == 1:
                groups[throws[0]].extend(groups.pop(key))
        listed = sorted(groups.values(), key=lambda g: min(z for z, _ in g))
        for members in listed:
            value = complex(sum(v for _, v in members))
            value = zero_below(value, sum(abs(v) for _, v in members), len(members) + 1)
            if value != 0:
                out.append(weight(min(z for z, _ in members), -value))
    return out


def propose_geared(
    layout: Engine,
    first_order: ComplexArray,
    picked: Phasors,
    *,
    cancel: Iterable[int] | None = None,
    strategy: str = "two-plane",
    balance_factor: float | BalanceFactor | None = None,
    counterweight_radius: float | None = None,
    fixed_shafts: Sequence[ShaftPosition] | None = None,
    cancel_roll: bool = False,
    link_pins: tuple[ComplexArray, ComplexArray] | None = None,
) -> Proposal:
    r"""Propose counterweights on each crank axis and balance shafts for an engine with
    several (:attr:`Engine.geared`).

    Parameters
    ----------
    layout : Engine
        The engine.
    first_order : ndarray of complex
        :math:`G_1` of each cylinder's :math:`-s''/r` at its own crank angle :math:`\beta`.
    picked : Phasors
        The engine's phasors at the orders to cancel (reciprocating force and moment, the
        rotating forward and backward phasors, the roll) [N, N m].
    cancel, strategy, balance_factor, counterweight_radius, fixed_shafts, cancel_roll
        As :func:`balance.core.balancing.propose`; the roll the shafts are placed for, and
        the notes speak of, is the engine's geared roll with the counterweights' moment
        about ``z``.
    link_pins : tuple of ndarray of complex, optional
        With link rods: each cylinder's link pin's first-order forward and backward phasors
        relative to its crank pin [N] (:attr:`balance.core.result.FreeForces.link_pins`),
        cancelled with the rest of its cylinder's first order.

    Returns
    -------
    Proposal
        Counterweights with their axis (:attr:`Counterweight.axis`, sense and position).
    """
    if strategy not in STRATEGIES:
        raise AnalysisError(f"unknown strategy {strategy!r}; valid: {', '.join(STRATEGIES)}")
    ks = [int(k) for k in np.asarray(picked.orders).ravel()]
    wanted = tuple(sorted({int(k) for k in (cancel if cancel is not None else DEFAULT_ORDERS)}))
    if any(k < 1 for k in wanted):
        raise AnalysisError("orders to cancel start at 1")
    missing = [k for k in wanted if k not in ks]
    if missing:
        raise AnalysisError(
            f"orders {missing} are to be cancelled but were not analysed; include them in orders"
        )
    w2 = float(speed_squared(layout.speed))
    r_mean = mean(layout.crank_radius)
    radius = float(counterweight_radius) if counterweight_radius is not None else r_mean
    if not (math.isfinite(radius) and radius > 0):
        raise AnalysisError("counterweight radius must be a positive length")
    factor = (
        BalanceFactor(float(balance_factor))
        if isinstance(balance_factor, int | float)
        else balance_factor
    )
    rods = axis_rods_per_pin(layout) if factor is not None else None
    equivalents = (
        FactorEquivalents.of(factor, rods) if factor is not None and rods is not None else None
    )
    assert picked.moment_forward is not None and picked.moment_backward is not None
    ff = {k: complex(picked.force_forward[i]) for i, k in enumerate(ks)}
    fb = {k: complex(picked.force_backward[i]) for i, k in enumerate(ks)}
    mf = {k: complex(picked.moment_forward[i]) for i, k in enumerate(ks)}
    mb = {k: complex(picked.moment_backward[i]) for i, k in enumerate(ks)}
    roll = None if picked.roll is None else np.array(picked.roll, dtype=np.complex128)
    counterweights: list[Counterweight] = []
    if 1 in wanted:
        shares = cylinder_shares(factor, rods) if factor is not None and rods is not None else None
        targets = _targets(layout, first_order, shares, link_pins)
        counterweights = _placed(layout, targets, strategy, radius)
        z_ref = layout.reference_z
        lever = layout.z - z_ref
        rotating = {
            "ff": picked.rotating_force,
            "fb": picked.rotating_force_backward,
            "mf": picked.rotating_moment,
            "mb": picked.rotating_moment_backward,
        }
        added = {key: complex(np.sum(v)) if v is not None else 0j for key, v in rotating.items()}
        for cw in counterweights:
            force = cw.unbalance * w2
            side = "f" if cw.sense > 0 else "b"
            added["f" + side] += force
            added["m" + side] += (cw.z - z_ref) * force
        f_scale = (
            float(
                np.sum((layout.rotating_mass + layout.reciprocating_mass) * layout.crank_radius)
                * w2
            )
            + sum(abs(cw.unbalance) for cw in counterweights) * w2
        )
        n = layout.n_cylinders + len(counterweights) + 2
        arm = float(np.abs(lever).max()) + max(
            (abs(cw.z - z_ref) for cw in counterweights), default=0.0
        )
        ff[1] = zero_below(ff[1] + added["ff"], f_scale, n)
        fb[1] = zero_below(fb[1] + added["fb"], f_scale, n)
        mf[1] = zero_below(mf[1] + added["mf"], f_scale * (arm + 1e-300), n)
        mb[1] = zero_below(mb[1] + added["mb"], f_scale * (arm + 1e-300), n)
        if roll is not None and counterweights:
            roll[ks.index(1)] += sum(counterweight_moment_z(cw, w2) for cw in counterweights)
    return completed_proposal(
        layout,
        counterweights,
        (ks, wanted, (ff, fb, mf, mb), roll),
        strategy=strategy,
        radius=radius,
        equivalents=equivalents,
        fixed_shafts=fixed_shafts,
        cancel_roll=cancel_roll,
        counterweight_senses=(1, -1) if np.any(layout.axis_table().rotation < 0) else (1,),
        mean_radius=r_mean,
    )
