"""The crank train's loads on the engine on its mounts, from an analysis.

:func:`order_loads` gathers, per order, what :func:`balance.core.mounts.crank_loads`
needs from a :class:`~balance.core.result.Result`: the free force and moment phasors
(reciprocating, plus the rotating ones at order 1; with the proposal, the residual phasors
that add every proposed mass) and the roll torque (with the gas torque's reaction when the
engine has gas forces, whose orders may be halves).  :func:`mounts_of` solves the response
(docs/conventions.md, "The engine on its mounts").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.catalogue import Compared, Output
from balance.core.errors import InputError
from balance.core.mounts import (
    COORDINATES,
    MountsResult,
    MountSystem,
    mount_response,
    speed_sweep,
)
from balance.core.result import Result

__all__ = [
    "FIGURE_SPEEDS",
    "OUTPUTS",
    "MountsPart",
    "figure_speeds",
    "mounts_of",
    "mounts_part",
    "order_loads",
]

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
    if not result.has_moments or result.roll is None:
        raise InputError(
            "the response on the mounts needs the free moments and the roll: "
            "analyse with both to put the engine on its mounts"
        )
    force_orders = np.asarray(result.phasors.orders, dtype=np.float64)
    if with_proposal:
        proposal = result.part("proposal")
        if proposal is None:
            raise InputError(
                "the mounts loaded with the proposal need a proposal: "
                "analyse with the proposal to put it on the mounts"
            )
        loads, roll = proposal.residual, proposal.residual_roll
    else:
        loads, roll = result.phasors.free(), result.roll
    ff, fb = loads.force_forward, loads.force_backward
    mf, mb = loads.moment_forward, loads.moment_backward
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
            f"layout '{name}' has no mounts: section, so the engine on its mounts cannot "
            "be computed; add one (docs/mounts.md) or give a mounts file"
        )
    return system


def mounts_of(result: Result, with_proposal: bool = False) -> MountsResult:
    """The response of the analysed engine on its mounts at the analysis speed.

    Parameters
    ----------
    result : Result
        An analysis of an engine with a mount system (its ``mounts`` section,
        :meth:`balance.core.engine.Engine.section`).
    with_proposal : bool
        Load the mounts with the residual (the proposal added).

    Returns
    -------
    MountsResult
    """
    engine = result.engine
    system = require_mounts(engine.section("mounts"), engine.name)
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
    if result.part("torque") is None or result.roll is None:
        return None
    total = np.zeros(orders.size, dtype=np.complex128)
    total[np.searchsorted(orders, result.roll_orders)] = result.roll
    p = result.phasors
    at = np.searchsorted(orders, np.asarray(p.orders, dtype=np.float64))
    assert p.roll is not None  # the roll was asked for, so was its inertia part
    total[at] -= p.roll
    return total


# --------------------------------------------------------------------------- the section


@dataclass(frozen=True)
class MountsPart:
    """The ``mounts`` section's part of a result.

    Attributes
    ----------
    response : MountsResult
        Modes and the response per order at the analysis speed.
    sweep : MountsResult or None
        The same response over the speeds asked for (:func:`balance.core.mounts.speed_sweep`),
        None when none were asked.
    """

    response: MountsResult
    sweep: MountsResult | None = None


#: The speeds of the mount-force figure, as fractions of the analysis speed, and their
#: number: 0.15 to 1.3 times, 231 speeds.
FIGURE_SPEEDS = (0.15, 1.3, 231)


def figure_speeds(speed: float) -> FloatArray:
    """The speeds the mount-force figure draws for an analysis at ``speed``.

    Parameters
    ----------
    speed : float
        The analysis's crank speed [rad/s].

    Returns
    -------
    ndarray
        The speeds of :data:`FIGURE_SPEEDS` [rad/s].
    """
    low, high, count = FIGURE_SPEEDS
    return np.linspace(low * speed, high * speed, count)


def mounts_part(
    engine: Any,
    request: Any,
    result: Result,
    *,
    with_proposal: bool = False,
    speeds: ArrayLike | str | None = None,
) -> Result:
    """The ``mounts`` section (:mod:`balance.core.sections`): the engine's response on its
    mounts (:func:`mounts_of`), and over a range of speeds when asked.

    Parameters
    ----------
    engine : Engine
        The analysed engine (its ``mounts:`` section).
    request : Request
        The request.
    result : Result
        The result so far (its phasors and roll, and its proposal part).
    with_proposal : bool
        Load the mounts with the residual (the proposal added) instead of the free forces.
    speeds : array_like or str, optional
        Crank speeds [rad/s] of a speed sweep; ``"figure"`` for those of the mount-force figure
        (:func:`figure_speeds`).

    Returns
    -------
    Result
        ``result`` with the ``mounts`` part added.
    """
    response = mounts_of(result, with_proposal)
    sweep = None
    if isinstance(speeds, str):
        speeds = figure_speeds(float(result.engine.speed))
    if speeds is not None:
        sweep = speed_sweep(response, np.asarray(speeds, dtype=np.float64))
    return result.with_part("mounts", MountsPart(response, sweep))


def _response(result: Any) -> MountsResult:
    part: MountsPart = result.part("mounts")
    return part.response


def _output(
    name: str, dims: tuple[str, ...], units: str, long_name: str, get: Any, **options: Any
) -> Output:
    return Output(name, dims, units, long_name, lambda r: get(_response(r)), **options)


def _coordinate(name: str, long_name: str, get: Any) -> Output:
    return Output(name, (name,), "1", long_name, lambda r: get(_response(r)), kind="coord")


#: The outputs of the ``mounts`` section.
OUTPUTS: tuple[Output, ...] = (
    _output(
        "mount_mode_frequency",
        ("mount_mode",),
        "Hz",
        "undamped rigid-body mode frequency on the mounts",
        lambda m: m.modes.frequency,
    ),
    _output(
        "mount_mode_energy_share",
        ("mount_mode", "mount_coordinate"),
        "1",
        "share of the mode's kinetic energy per CG coordinate",
        lambda m: m.modes.energy_share,
    ),
    _output(
        "mount_cg_translation",
        ("mount_order", "axis"),
        "m",
        "amplitude of the CG translation",
        lambda m: m.translation,
    ),
    _output(
        "mount_rotation",
        ("mount_order", "axis"),
        "rad",
        "amplitude of the rotation about axes through the CG",
        lambda m: m.rotation,
    ),
    _output(
        "mount_force",
        ("mount_order", "mount", "axis"),
        "N",
        "amplitude of the force each mount passes on, engine axes",
        lambda m: m.force_amplitude,
    ),
    _output(
        "mount_force_peak",
        ("mount_order", "mount"),
        "N",
        "largest magnitude of each mount's force over a cycle",
        lambda m: m.force_peak,
    ),
    _output(
        "mount_force_max",
        (),
        "N",
        "largest force of any mount and order at the analysis speed",
        lambda m: float(np.max(m.largest_force)),
        compare=Compared(
            "mount F max [N]",
            "largest mount force",
            "largest mount force of any order at the layout's speed (NaN without mounts)",
        ),
    ),
    _output(
        "torque_roll_axis",
        ("axis",),
        "1",
        "direction of the torque-roll axis through the CG",
        lambda m: m.roll_axis,
    ),
    _output(
        "mount_distance_to_torque_roll_axis",
        ("mount",),
        "m",
        "distance of each mount from the torque-roll axis",
        lambda m: m.axis_distance,
    ),
    _coordinate("mount_mode", "rigid-body mode number", lambda m: np.arange(1, 7)),
    _coordinate("mount_coordinate", "CG coordinate", lambda m: list(COORDINATES)),
    _coordinate("mount_order", "order of the mount response", lambda m: np.asarray(m.orders)),
    _coordinate("mount", "mount number", lambda m: np.arange(1, m.system.n_mounts + 1)),
    _coordinate("axis", "engine axis", lambda m: ["x", "y", "z"]),
)
