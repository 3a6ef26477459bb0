"""The crank train's loads on the engine on its mounts, from an analysis.

:func:`order_loads` gathers, per order, what :func:`balance.core.mounts.crank_loads`
needs from a :class:`~balance.core.result.Result`: the free force and moment phasors
(reciprocating, plus the rotating ones at order 1; with the proposal, the residual phasors
that add every proposed mass) and the roll torque (with the gas torque's reaction when the
engine has gas forces, whose orders may be halves).  :func:`mounts_of` solves the response
(``CONTRACT`` §7).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from balance.core.errors import InputError
from balance.core.mounts import MountsResult, MountSystem, mount_response
from balance.core.result import Result

__all__ = ["OrderLoads", "mounts_of", "order_loads"]

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]

#: (orders, force forward, force backward, moment forward, moment backward, roll)
OrderLoads = tuple[FloatArray, ComplexArray, ComplexArray, ComplexArray, ComplexArray, ComplexArray]


def order_loads(result: Result, with_proposal: bool = False) -> OrderLoads:
    """Phasors per order of everything the crank train puts on the block [N, N m].

    Parameters
    ----------
    result : Result
        An analysis with moments and roll (and a proposal, for ``with_proposal``).
    with_proposal : bool
        Use the residual phasors (every proposed counterweight and shaft added).

    Returns
    -------
    OrderLoads
        The orders (the union of the force orders and the roll orders, ascending) and
        the phasors on them (zero where an order has no such term).

    Raises
    ------
    InputError
        Without the moments or the roll, or without a proposal for ``with_proposal``.
    """
    p = result.phasors
    if not result.has_moments or result.roll is None:
        raise InputError(
            "the response on the mounts needs the free moments and the roll "
            "(do not give --no-moments or --no-roll with mounts)"
        )
    force_orders = np.asarray(p.orders, dtype=np.float64)
    first = (force_orders == 1).astype(np.float64)
    if with_proposal:
        b = result.balanced
        if b is None or result.residual_roll is None:
            raise InputError(
                "--with-proposal: there is no proposal to put on the mounts "
                "(do not give --no-proposal with --with-proposal)"
            )
        ff, fb, mf, mb = b.force_forward, b.force_backward, b.moment_forward, b.moment_backward
        roll = result.residual_roll
    else:
        ff = p.force_forward + first * p.rotating_force
        fb = p.force_backward
        mf = p.moment_forward + first * p.rotating_moment
        mb = p.moment_backward
        roll = result.roll
    roll_orders = np.asarray(result.roll_orders, dtype=np.float64)
    orders = np.union1d(force_orders, roll_orders)
    at_force = np.searchsorted(orders, force_orders)
    at_roll = np.searchsorted(orders, roll_orders)

    def spread(values: ComplexArray, at: NDArray[np.intp]) -> ComplexArray:
        out = np.zeros(orders.size, dtype=np.complex128)
        out[at] = np.asarray(values, dtype=np.complex128)
        return out

    return (
        orders,
        spread(ff, at_force),
        spread(fb, at_force),
        spread(mf, at_force),
        spread(mb, at_force),
        spread(roll, at_roll),
    )


def require_mounts(system: MountSystem | None, name: str) -> MountSystem:
    """The engine's mount system, or an :class:`InputError` that says how to give one."""
    if system is None:
        raise InputError(
            f"layout '{name}' has no mounts: section (asked by --on-mounts or balance mounts); "
            "add one or give --mounts FILE"
        )
    return system


def mounts_of(result: Result, with_proposal: bool = False) -> MountsResult:
    """The response of the analysed engine on its mounts at the analysis speed.

    Parameters
    ----------
    result : Result
        An analysis of an engine with a mount system (:attr:`Engine.mounts`).
    with_proposal : bool
        Load the mounts with the residual (the proposal added).

    Returns
    -------
    MountsResult
    """
    engine = result.engine
    system = require_mounts(engine.mounts, engine.name)
    orders, ff, fb, mf, mb, roll = order_loads(result, with_proposal)
    return mount_response(
        system,
        engine.speed,
        orders,
        engine.reference_z,
        ff,
        fb,
        mf,
        mb,
        roll,
        with_proposal=with_proposal,
        gas_roll=gas_roll(result, orders),
    )


def gas_roll(result: Result, orders: FloatArray) -> ComplexArray | None:
    """The gas torque's reaction in the roll, per order of ``orders`` [N m] (None without
    gas): the roll with gas forces less the inertia roll on the integer orders."""
    if result.torque is None or result.roll is None:
        return None
    total = np.zeros(orders.size, dtype=np.complex128)
    total[np.searchsorted(orders, result.roll_orders)] = result.roll
    p = result.phasors
    at = np.searchsorted(orders, np.asarray(p.orders, dtype=np.float64))
    total[at] -= p.roll
    return total
