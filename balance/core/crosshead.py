r"""Crosshead engines: the guide forces and MAN B&W's guide-force moments.

In a crosshead engine (the marine two-strokes) the piston rod ends in a crosshead that slides
in guides; the side thrust of the crank slider goes to the guide **at the crosshead pin**, at
the distance :math:`s(\beta)` of the pin from the crank axis.  A *crosshead cylinder* is one
whose layout gives a ``crosshead`` mass (or all, with ``crossheads: true``;
docs/crossheads.md).  Its inertia (the slider: piston group, piston rod and crosshead) is that
of a trunk-piston engine with the same reciprocating mass: forces, moments and the roll do
not change.  What this section adds:

* the guide force :math:`N_i(\theta)` of each crosshead cylinder: the force the guide takes
  from the crosshead along the cylinder's lateral direction :math:`\psi_i + 90°` (engine
  frame), from the rod's Newton–Euler equations (:mod:`balance.core.crank_train`'s
  :func:`~balance.core.crank_train.side_thrust`, whose :math:`N` is the guide's force on the
  crosshead, so :math:`N_i = -N`), with the gas force when the layout has ``gas:``;
* its moment about the crank axis, positive in the direction of rotation,
  :math:`H_i = s_i N_i` (the couple "guide force at the guide, reaction at the main
  bearing"; without offset and gas it is the cylinder's part of the roll);
* the guide-force moments as MAN B&W's project guides tabulate them (WinGD: lateral H-type
  and X-type):

  .. math::

      M_H(\theta) = \sum_i H_i(\theta), \qquad
      M_X(\theta) = \sum_i H_i(\theta)\,\frac{z_i - z_\mathrm{ref}}{L_i}

  with :math:`L_i` the conrod length ("the distance between crankshaft level and the middle
  position of the crosshead guide"), per order as amplitude and phase like the roll
  (:math:`\sum_k a_k\cos(k\theta + \varphi_k)`; half orders for a four-stroke with gas).

The forces are sampled over the working cycle on the torque's grid
(:data:`balance.core.torque.CYCLE_SAMPLES_PER_DEGREE`) and analysed into orders by the FFT.

.. rubric:: References

MAN Energy Solutions, *MAN B&W S60MC-C8.5-TII Project Guide* (and every MC/ME guide),
section 17.05 "Guide force moments" and table 17.07.01; WinGD, *Marine Installation
Manual*, "Lateral engine vibrations (rocking)"; Taylor, *The Internal Combustion Engine in
Theory and Practice*, vol. 2, MIT Press 1985, ch. 8 (the crank train's forces).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from balance.core import crank_train, phasors
from balance.core.catalogue import Output
from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.gas import cylinder_pressure, periodic_tables, piston_gas_force
from balance.core.kinematics import (
    conrod_angle_derivatives,
    normalised_slider,
    offset_ratio,
    rod_ratio,
)
from balance.core.speed import speed_squared
from balance.core.torque import CYCLE_SAMPLES_PER_DEGREE, engine_pressure_tables, roll_orders

__all__ = ["OUTPUTS", "GuideForces", "guide_force_part", "guide_forces"]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass(frozen=True)
class GuideForces:
    """The guide forces of a crosshead engine and MAN B&W's guide-force moments (SI).

    Attributes
    ----------
    crank_angle : ndarray
        :math:`\\theta` over the sampled cycle [deg].
    crossheads : ndarray of bool
        Which cylinders are crosshead cylinders.
    guide_force : ndarray
        :math:`N_i(\\theta)`, shape (cylinders, angles) [N], along each cylinder's lateral
        direction (bank + 90°); 0 for a trunk-piston cylinder.
    couple : ndarray
        :math:`H_i = s_i N_i`, shape (cylinders, angles) [N m].
    lever : ndarray
        :math:`L_i`, each cylinder's conrod length [m].
    orders : ndarray
        The orders of the moments (halves for a four-stroke with gas).
    h_type, x_type : ndarray of complex
        :math:`M_H`, :math:`M_X` per order: :math:`\\sum_k \\mathrm{Re}(c_k e^{ik\\theta})`
        [N m].
    maximum : ndarray
        The largest :math:`|N_i|` over the cycle [N]; NaN for a trunk-piston cylinder.
    with_gas : bool
        Whether the gas forces are in.
    """

    crank_angle: FloatArray
    crossheads: NDArray[np.bool_]
    guide_force: FloatArray
    couple: FloatArray
    lever: FloatArray
    orders: FloatArray
    h_type: ComplexArray
    x_type: ComplexArray
    maximum: FloatArray
    with_gas: bool


def guide_forces(engine: Engine, orders: NDArray[np.intp]) -> GuideForces:
    r"""The guide forces and guide-force moments of an engine with crosshead cylinders.

    Parameters
    ----------
    engine : Engine
        The engine; its section ``crossheads`` says which cylinders have a crosshead (all
        when it has none).
    orders : ndarray of int
        The analysis orders; the moments are given for :func:`balance.core.torque.roll_orders`
        with gas (halves for a four-stroke), for ``orders`` without.

    Returns
    -------
    GuideForces

    Raises
    ------
    InputError
        For link rods or several crankshafts, which this version does not combine with
        crossheads.

    Notes
    -----
    Per cylinder, on the torque's grid, the slider force :math:`P = P_g + m_{rec}\omega^2
    s''` and the rod's inertia couple give the guide's force on the crosshead
    :math:`N = P\tan\psi + M/(l\cos\psi)` (:func:`balance.core.crank_train.side_thrust`);
    the guide takes :math:`N_i = -N` along :math:`+X` (bank + 90°), at :math:`s` from the
    crank axis: :math:`H_i = s_i N_i`.  The orders are the FFT's bins of the cycle
    (:math:`c_k = 2\hat{x}_k`), sums that cancel by symmetry set to zero
    (:func:`balance.core.phasors.cancel_to_zero`).
    """
    if engine.has_links or engine.geared:
        raise InputError(
            f"{engine.name}: guide forces of crosshead cylinders with link rods or several "
            "crankshafts are not in this version"
        )
    mask = engine.section("crossheads")
    crossheads = (
        np.ones(engine.n_cylinders, dtype=bool) if mask is None else np.asarray(mask, dtype=bool)
    )
    gas = engine.gas
    cycle_deg = gas.cycle_deg if gas is not None else 360.0
    samples = round(cycle_deg * CYCLE_SAMPLES_PER_DEGREE)
    theta = cycle_deg * np.arange(samples) / samples
    throw_deg = np.degrees(engine.throw)[:, None]
    bank_deg = np.degrees(engine.bank)[:, None]
    beta = np.radians(np.mod(theta[None, :] + throw_deg - bank_deg, 360.0))
    r = engine.crank_radius[:, None]
    length = engine.conrod_length[:, None]
    lam = rod_ratio(r, length)
    eps = offset_ratio(engine.offset[:, None], r)
    w2 = float(speed_squared(engine.speed))
    s, _, d2s = normalised_slider(beta, lam, eps)
    sin_psi, cos_psi = crank_train.rod_direction(beta, lam, eps)
    _, d2g = conrod_angle_derivatives(beta, lam, eps)
    gas_force = None
    if gas is not None:
        pressure = cylinder_pressure(
            gas, periodic_tables(engine_pressure_tables(engine), cycle_deg), theta
        )
        gas_force = piston_gas_force(pressure, gas)
    inertia = crank_train.reciprocating_force(engine.reciprocating_mass[:, None], w2, r, d2s)
    piston = crank_train.piston_force(inertia, gas_force)
    couple_force = crank_train.couple_side_force(
        crank_train.rod_inertia_couple(engine.conrod_inertia_correction[:, None], w2, d2g),
        length,
        cos_psi,
    )
    # the kernel's N is the guide's force on the crosshead along +X; the guide takes -N
    guide = np.where(
        crossheads[:, None], -crank_train.side_thrust(piston, sin_psi, cos_psi, couple_force), 0.0
    )
    couple = s * r * guide
    lever = np.asarray(engine.conrod_length, dtype=np.float64)
    arm = (engine.z - engine.reference_z) / lever
    ks = roll_orders(orders, engine.cycle) if gas is not None else orders.astype(np.float64)
    bins = np.round(ks * cycle_deg / 360.0).astype(np.intp) % samples
    spectrum = np.fft.fft(couple, axis=-1) / samples  # per cylinder: H_i per order
    per_cylinder = 2.0 * spectrum[:, bins]
    n_terms = 8 * engine.n_cylinders * int(math.log2(samples))
    scale = float(np.sum(np.max(np.abs(couple), axis=1)))
    h_type = phasors.cancel_to_zero(per_cylinder.sum(axis=0), scale, n_terms)
    x_scale = float(np.sum(np.max(np.abs(couple), axis=1) * np.abs(arm)))
    x_type = phasors.cancel_to_zero((per_cylinder * arm[:, None]).sum(axis=0), x_scale, n_terms)
    maximum = np.where(crossheads, np.max(np.abs(guide), axis=1), math.nan)
    return GuideForces(
        crank_angle=theta,
        crossheads=crossheads,
        guide_force=guide,
        couple=couple,
        lever=lever,
        orders=ks,
        h_type=h_type,
        x_type=x_type,
        maximum=np.asarray(maximum, dtype=np.float64),
        with_gas=gas is not None,
    )


def guide_force_part(engine: Engine, request: Any, result: Any) -> Any:
    """The ``guide_forces`` section (:mod:`balance.core.sections`): :func:`guide_forces`.

    Parameters
    ----------
    engine : Engine
        The analysed engine.
    request : Request
        The request (the section takes no options).
    result : Result
        The result so far.

    Returns
    -------
    Result
        ``result`` with the ``guide_forces`` part added.
    """
    return result.with_part("guide_forces", guide_forces(engine, result.phasors.orders))


def _part(result: Any) -> GuideForces:
    part: GuideForces = result.part("guide_forces")
    return part


def _gas(result: Any) -> str:
    return ", gas forces included" if _part(result).with_gas else ", inertia only"


#: The outputs of the ``guide_forces`` section.
OUTPUTS: tuple[Output, ...] = (
    Output(
        "guide_force_moment_h_amplitude",
        ("guide_force_order",),
        "N m",
        lambda r: (
            "amplitude of the H-type guide-force moment sum of s_i N_i (MAN B&W)"
            f"{_gas(r)} (sum of a_k cos(k theta + phase_k))"
        ),
        lambda r: np.abs(_part(r).h_type),
    ),
    Output(
        "guide_force_moment_h_phase",
        ("guide_force_order",),
        "deg",
        "phase of the H-type guide-force moment, positive in the direction of rotation",
        lambda r: phasors.phase_deg(_part(r).h_type),
    ),
    Output(
        "guide_force_moment_x_amplitude",
        ("guide_force_order",),
        "N m",
        lambda r: (
            "amplitude of the X-type guide-force moment sum of s_i N_i (z_i - reference_z) / "
            f"L_i (MAN B&W){_gas(r)} (sum of a_k cos(k theta + phase_k))"
        ),
        lambda r: np.abs(_part(r).x_type),
    ),
    Output(
        "guide_force_moment_x_phase",
        ("guide_force_order",),
        "deg",
        "phase of the X-type guide-force moment, positive in the direction of rotation",
        lambda r: phasors.phase_deg(_part(r).x_type),
    ),
    Output(
        "guide_force_lever",
        ("cylinder",),
        "m",
        "L_i of the X-type moment: the conrod length (crank axis to mid-guide)",
        lambda r: _part(r).lever,
    ),
    Output(
        "guide_force_max",
        ("cylinder",),
        "N",
        "largest guide force of the crosshead on its guide over the cycle (NaN: no crosshead)",
        lambda r: _part(r).maximum,
    ),
    Output(
        "guide_force_order",
        ("guide_force_order",),
        "1",
        "harmonic order of the guide-force moments",
        lambda r: _part(r).orders,
        kind="coord",
    ),
)
