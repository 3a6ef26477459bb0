r"""Brute-force computation in the crank-angle domain.

Independent of the phasor algebra: the forces, moments and roll torque are sampled over a
revolution from the geometry of every cylinder, summed as vectors in the engine frame, and
their harmonics taken by FFT.  The tests check every analytic shortcut of the package
against these functions.

The roll torque is found here by the Newton–Euler equations of piston and rigid conrod
(mass, centre of gravity, moment of inertia) at each crank angle, solved for the force of
the cylinder wall; its moment about the crank axis is what the block receives.  This does
not use the energy argument by which :func:`balance.core.kinematics.roll_coefficients` is
derived.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.balancing import Proposal
from balance.core.engine import Engine
from balance.core.kinematics import (
    conrod_angle_derivatives,
    normalised_slider,
    offset_ratio,
    rod_ratio,
)
from balance.core.speed import speed_squared

__all__ = [
    "crank_angles",
    "crank_torque_newton_euler",
    "phasors_from_samples",
    "proposal_force_samples",
    "proposal_roll_samples",
    "reciprocating_force_samples",
    "roll_newton_euler",
    "roll_phasors_from_samples",
    "rotating_force_samples",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


def crank_angles(samples: int) -> FloatArray:
    """``samples`` equally spaced crank angles over one revolution [rad]."""
    return 2.0 * np.pi * np.arange(samples) / samples


def reciprocating_force_samples(
    layout: Engine, theta: ArrayLike, lever: bool = False
) -> ComplexArray:
    r"""Reciprocating inertia force (or moment) on the block at each crank angle.

    Returns
    -------
    ndarray of complex
        :math:`\sum_i -m_{rec,i}\, \omega^2 s_i''(\beta_i)\, e^{i\psi_i}` [N] (times
        :math:`z_i - z_{ref}` [N m] with ``lever=True``), one value per crank angle.
    """
    th = np.asarray(theta, dtype=np.float64)[:, None]
    beta = th + layout.throw - layout.bank
    r = layout.crank_radius
    _, _, d2s = normalised_slider(
        beta, rod_ratio(r, layout.conrod_length), offset_ratio(layout.offset, r)
    )
    w2 = speed_squared(layout.speed)
    force = -layout.reciprocating_mass * w2 * r * d2s * np.exp(1j * layout.bank)
    if lever:
        force = force * (layout.z - layout.reference_z)
    return np.asarray(force.sum(axis=1), dtype=np.complex128)


def rotating_force_samples(layout: Engine, theta: ArrayLike, lever: bool = False) -> ComplexArray:
    """Centrifugal force (or moment) of the rotating masses at each crank angle [N, N m]."""
    th = np.asarray(theta, dtype=np.float64)[:, None]
    force = (
        layout.rotating_mass
        * layout.crank_radius
        * speed_squared(layout.speed)
        * np.exp(1j * (th + layout.throw))
    )
    if lever:
        force = force * (layout.z - layout.reference_z)
    return np.asarray(force.sum(axis=1), dtype=np.complex128)


def phasors_from_samples(
    samples: ArrayLike, orders: ArrayLike
) -> tuple[ComplexArray, ComplexArray]:
    r"""Forward and backward phasors of a complex signal sampled over one revolution.

    For :math:`Q(\theta) = \sum_k P_k^{+}e^{ik\theta} + P_k^{-}e^{-ik\theta}` sampled at
    :func:`crank_angles`, :math:`P_k^{+}` is FFT bin :math:`k` and :math:`P_k^{-}` bin
    :math:`-k`, divided by the number of samples.
    """
    q = np.asarray(samples, dtype=np.complex128)
    n = q.shape[-1]
    spectrum = np.fft.fft(q, axis=-1) / n
    ks = np.asarray(orders, dtype=np.intp)
    return spectrum[..., ks % n], spectrum[..., (-ks) % n]


def roll_phasors_from_samples(samples: ArrayLike, orders: ArrayLike) -> ComplexArray:
    r"""Phasors :math:`R_k` of a real torque :math:`\sum_k \mathrm{Re}(R_k e^{ik\theta})`."""
    t = np.asarray(samples, dtype=np.float64)
    n = t.shape[-1]
    spectrum = np.fft.fft(t, axis=-1) / n
    return 2.0 * spectrum[..., np.asarray(orders, dtype=np.intp) % n]


def _cross(a: ComplexArray, b: ComplexArray) -> FloatArray:
    """z-component of the cross product of 2-D vectors stored as X + iY (math orientation)."""
    return np.asarray(a.real * b.imag - a.imag * b.real)


def roll_newton_euler(
    layout: Engine,
    theta: ArrayLike,
    small_end_share: float = 1.0 / 3.0,
    cg_fraction: float = 0.3,
    gas_force: ArrayLike | None = None,
) -> FloatArray:
    r"""Roll torque on the block from the Newton–Euler equations of piston and rigid rod.

    Parameters
    ----------
    layout : Engine
        The engine (inertia only, constant crank speed).
    theta : array_like
        Crank angles [rad].
    small_end_share : float
        Share of each cylinder's reciprocating mass that is the conrod's small-end share;
        the rest is the piston.  The rod is then a rigid body with its centre of gravity
        ``cg_fraction`` of its length from the big end and the moment of inertia that gives
        the layout's ``conrod_inertia_correction``.  The result must not depend on this
        choice (static equivalence).
    cg_fraction : float
        Centre of gravity of the rod from the big end, as a fraction of its length.
    gas_force : array_like, optional
        Gas force :math:`G` on each piston towards the crank [N], shape (angles, cylinders);
        the same force pushes the head away from the crank along the bore axis.

    Returns
    -------
    ndarray
        Torque about the crank axis received by the block [N m], positive in the direction
        of rotation, one value per crank angle.

    Notes
    -----
    In each cylinder's frame (X across the bore towards where the pin goes after TDC,
    Y along the bore; vectors as X + iY) with crank pin C, piston pin P, rod centre of
    gravity G, the rod turning at :math:`\ddot\vartheta = \omega^2\gamma''`:

    .. math::

        m_p a_P &= F_{RP} + (N, 0) \\
        m_c a_G &= F_{CR} - F_{RP} \\
        I_G \ddot\vartheta &= (P-G)\times(-F_{RP}) + (C-G)\times F_{CR}

    which give :math:`N = [I_G\ddot\vartheta - d\times m_p a_P - (C-G)\times m_c a_G]/d_Y`
    with :math:`d = C - P`.  The wall pushes the block with :math:`(-N, 0)` at P, whose
    moment about the crank axis in the direction of rotation is :math:`-s N`.  A gas force
    :math:`G` adds :math:`(0, -G)` on the piston (:math:`m_p a_P` becomes
    :math:`m_p a_P + (0, G)` above) and :math:`(0, G)` on the head at :math:`x = e`, whose
    moment is :math:`-eG`.
    """
    wall, _, _, s, e, gas = _newton_euler(layout, theta, small_end_share, cg_fraction, gas_force)
    torque = -s * wall - e * gas
    return np.asarray(torque.sum(axis=1), dtype=np.float64)


def crank_torque_newton_euler(
    layout: Engine,
    theta: ArrayLike,
    gas_force: ArrayLike | None = None,
    small_end_share: float = 1.0 / 3.0,
    cg_fraction: float = 0.3,
) -> FloatArray:
    r"""Torque the conrods put on the crankshaft [N m], from the same Newton–Euler solution.

    Parameters are those of :func:`roll_newton_euler`.

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
    _, pin_force, C, _, _, _ = _newton_euler(layout, theta, small_end_share, cg_fraction, gas_force)
    torque = C.imag * pin_force.real - C.real * pin_force.imag
    return np.asarray(torque.sum(axis=1), dtype=np.float64)


def _newton_euler(
    layout: Engine,
    theta: ArrayLike,
    small_end_share: float,
    cg_fraction: float,
    gas_force: ArrayLike | None,
) -> tuple[FloatArray, ComplexArray, ComplexArray, FloatArray, FloatArray, FloatArray]:
    """Wall force N, force of the rod on the crank pin, pin position, s, e and G per cylinder."""
    th = np.asarray(theta, dtype=np.float64)[:, None]
    beta = th + layout.throw - layout.bank
    r = layout.crank_radius
    length = layout.conrod_length
    e = layout.offset
    w2 = speed_squared(layout.speed)
    lam = rod_ratio(r, length)
    eps = offset_ratio(e, r)
    s_n, _, d2s_n = normalised_slider(beta, lam, eps)
    _, d2g = conrod_angle_derivatives(beta, lam, eps)
    s = r * s_n
    small = small_end_share * layout.reciprocating_mass
    m_p = layout.reciprocating_mass - small
    cg = cg_fraction * length
    m_c = small * length / cg
    i_g = layout.conrod_inertia_correction + m_c * cg * (length - cg)

    C = r * (np.sin(beta) + 1j * np.cos(beta))
    P = e + 1j * s
    G = C + (cg / length) * (P - C)
    a_C = -w2 * C
    a_P = 1j * w2 * r * d2s_n
    a_G = a_C + (cg / length) * (a_P - a_C)
    alpha = w2 * d2g
    d = C - P
    gas = (
        np.zeros(np.broadcast_shapes(th.shape, r.shape))
        if gas_force is None
        else np.broadcast_to(np.asarray(gas_force, dtype=np.float64), (th.shape[0], r.size))
    )
    Q = m_p * a_P + 1j * gas
    N = (i_g * alpha - _cross(d, Q) - _cross(C - G, m_c * a_G)) / d.imag
    on_pin = -(m_c * a_G + Q - N)
    offset = np.broadcast_to(e, N.shape)
    return N, on_pin, C, s, offset, gas


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
