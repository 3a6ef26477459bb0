"""Brute-force references that only the tests use: the Newton–Euler solution of piston and
rigid conrod read as the torque on the crank, the wall and rod forces and the force on each
crank pin; the whole force and moment on the block; the forces and roll of a proposal's
counterweights and balance shafts, sampled over crank angles.

They check the package's closed forms (:mod:`balance.core.torque`,
:mod:`balance.core.bearings`, the phasor sums) and share none of them: the plain cylinders'
rigid-body solution and the master-and-link groups' linear solve are those of
:mod:`balance.core.sampled`, which the ``time`` model also uses for its roll.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.balancing import Proposal
from balance.core.engine import Engine
from balance.core.kinematics import normalised_slider, offset_ratio, rod_ratio
from balance.core.sampled import (
    _newton_euler,
    _plain_mask,
    articulated_newton_euler,
)
from balance.core.speed import speed_squared

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


def crank_torque_newton_euler(
    layout: Engine,
    theta: ArrayLike,
    gas_force: ArrayLike | None = None,
    small_end_share: float = 1.0 / 3.0,
    cg_fraction: float = 0.3,
) -> FloatArray:
    r"""Torque the conrods put on the crankshaft [N m], from the same Newton–Euler solution.

    Parameters are those of :func:`balance.core.sampled.roll_newton_euler`.

    Returns
    -------
    ndarray
        Torque about the crank axis on the crankshaft, positive in the direction of rotation,
        one value per crank angle (the engine torque at constant speed).

    Notes
    -----
    The rod pushes the crank pin :math:`C` with :math:`-F_{CR} = -(m_c a_G + F_{RP})`,
    :math:`F_{RP} = m_p a_P + (0, G) - (N, 0)`; its moment in the direction of rotation is
    :math:`C_Y F_X - C_X F_Y`.
    """
    cylinders = _newton_euler(layout, theta, small_end_share, cg_fraction, gas_force)
    C, pin_force = cylinders.crank, cylinders.on_pin
    torque = C.imag * pin_force.real - C.real * pin_force.imag
    if layout.has_links:
        solution = articulated_newton_euler(layout, theta, small_end_share, cg_fraction, gas_force)
        plain = _plain_mask(layout)
        return np.asarray(
            np.where(plain, torque, 0.0).sum(axis=1) + solution.crank_torque, dtype=np.float64
        )
    return np.asarray(torque.sum(axis=1), dtype=np.float64)


@dataclass(frozen=True)
class CrankTrainForces:
    r"""Forces of the Newton–Euler solution per cylinder, shape (angles, cylinders).

    Attributes
    ----------
    wall : ndarray
        Force of the wall on each piston across its bore, along +X of its frame (towards
        where the pin goes after TDC) [N].
    rod_force : ndarray
        Each rod's force at its piston pin along the rod, compression positive [N].
    pin_force : ndarray of complex
        Force of each rod on its crank pin [N], engine frame :math:`y + \mathrm{i}x`: a
        master's is its master rod's, carrying its link rods, and a link cylinder's is 0.
    """

    wall: FloatArray
    rod_force: FloatArray
    pin_force: ComplexArray


def crank_train_newton_euler(
    layout: Engine,
    theta: ArrayLike,
    gas_force: ArrayLike | None = None,
    small_end_share: float = 1.0 / 3.0,
    cg_fraction: float = 0.3,
) -> CrankTrainForces:
    r"""Wall force, rod force and force on the crank pin of every cylinder, from the same
    Newton–Euler solution as :func:`balance.core.sampled.roll_newton_euler`
    (parameters as there).

    Notes
    -----
    The rod's force on the crank pin includes the inertia of the rod's own mass (its big-end
    share turns with the pin: :math:`m_\mathrm{big}\omega^2 r` outwards); the rod force is
    the axial part of the force between rod and piston, so it depends on the rod's
    small-end share unless ``small_end_share`` is 0 (the rod is then a massless body of
    inertia :math:`\Delta I`, the whole reciprocating mass at the piston pin).
    """
    th = np.asarray(theta, dtype=np.float64)
    cylinders = _newton_euler(layout, th, small_end_share, cg_fraction, gas_force)
    turn = np.exp(1j * layout.bank)

    def engine_frame(v: ComplexArray) -> ComplexArray:  # X + iY of a cylinder -> y + ix
        return np.asarray(1j * np.conj(v) * turn)

    wall = np.array(cylinders.wall, dtype=np.float64)
    along = cylinders.rod / np.abs(cylinders.rod)
    rod_force = np.real(-cylinders.on_piston * np.conj(along))
    pin_force = engine_frame(cylinders.on_pin)
    if layout.has_links:
        solution = articulated_newton_euler(layout, th, small_end_share, cg_fraction, gas_force)
        grouped = ~_plain_mask(layout)
        wall[:, grouped] = solution.wall.T[:, grouped]
        rod_force[:, grouped] = solution.rod_force.T[:, grouped]
        pin_force[:, grouped] = 0.0
        pin_force[:, solution.masters] = solution.pin_force.T
    return CrankTrainForces(wall, rod_force, pin_force)


def proposal_force_samples(
    proposal: Proposal, layout: Engine, theta: ArrayLike, lever: bool = False
) -> ComplexArray:
    r"""Force (or moment) of every proposed mass at each crank angle [N, N m].

    A counterweight :math:`U = mRe^{i\alpha}` at crank angle :math:`\theta` pulls with
    :math:`U\omega^2 e^{i\theta}`; an eccentric on a shaft at :math:`s\omega` with
    :math:`mRe^{i\alpha}` sits at :math:`\alpha + s\theta` and pulls with
    :math:`U (s\omega)^2 e^{is\theta}`.
    """
    th = np.asarray(theta, dtype=np.float64)
    w = layout.speed
    total = np.zeros(th.shape, dtype=np.complex128)
    for cw in proposal.counterweights:
        arm = (cw.z - layout.reference_z) if lever else 1.0
        total += arm * cw.unbalance * w**2 * np.exp(1j * th)
    for shaft in proposal.shafts:
        s = shaft.speed_ratio
        for z, u in shaft.planes:
            arm = (z - layout.reference_z) if lever else 1.0
            total += arm * u * (s * w) ** 2 * np.exp(1j * s * th)
    return total


def proposal_roll_samples(proposal: Proposal, layout: Engine, theta: ArrayLike) -> FloatArray:
    """Torque about the crank axis of the shafts' eccentric forces [N m] (rotation sense).

    A force :math:`(F_x, F_y)` at :math:`(x, y)` turns the block by :math:`yF_x - xF_y`.
    """
    th = np.asarray(theta, dtype=np.float64)
    w = layout.speed
    total = np.zeros(th.shape)
    for shaft in proposal.shafts:
        s = shaft.speed_ratio
        force = sum(u for _, u in shaft.planes) * (s * w) ** 2 * np.exp(1j * s * th)
        f_y, f_x = force.real, force.imag
        total += shaft.y * f_x - shaft.x * f_y
    return total


def block_force_newton_euler(
    layout: Engine,
    theta: ArrayLike,
    small_end_share: float = 1.0 / 3.0,
    cg_fraction: float = 0.3,
) -> tuple[ComplexArray, ComplexArray]:
    r"""Whole force and moment on the block [N, N m] (reciprocating and rotating), inertia
    only: plain cylinders by :math:`-\sum m a` of their two-mass models, master-and-link
    groups by :func:`balance.core.sampled.articulated_newton_euler`."""
    th = np.asarray(theta, dtype=np.float64)
    beta = th[:, None] + layout.throw - layout.bank
    r = layout.crank_radius
    w2 = speed_squared(layout.speed)
    _, _, d2s = normalised_slider(
        beta, rod_ratio(r, layout.conrod_length), offset_ratio(layout.offset, r)
    )
    each = -layout.reciprocating_mass * w2 * r * d2s * np.exp(1j * layout.bank)
    each = each + layout.rotating_mass * r * w2 * np.exp(1j * (th[:, None] + layout.throw))
    lever = layout.z - layout.reference_z
    if not layout.has_links:
        return (
            np.asarray(each.sum(axis=1), dtype=np.complex128),
            np.asarray((each * lever).sum(axis=1), dtype=np.complex128),
        )
    each = np.where(_plain_mask(layout), each, 0.0)
    solution = articulated_newton_euler(layout, th, small_end_share, cg_fraction)
    return (
        np.asarray(each.sum(axis=1) + solution.block_force, dtype=np.complex128),
        np.asarray((each * lever).sum(axis=1) + solution.block_moment, dtype=np.complex128),
    )
