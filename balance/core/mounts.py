r"""The engine on its mounts: a rigid body with six degrees of freedom on linear mounts.

The powertrain is a rigid body of mass :math:`m`, centre of gravity :math:`\mathbf{c}` and
inertia tensor :math:`\mathbf{J}` about the CG, carried by point mounts that are linear
springs (and optional viscous dampers) along three perpendicular axes of their own.  The
motion is small about static equilibrium.  Its coordinates are the *CG coordinates*

.. math::

    \mathbf{q} = (u_x, u_y, u_z, \theta_x, \theta_y, \theta_z)

: the translations of the CG [m] and the small rotations [rad] about axes through the CG parallel
to the engine frame, right-handed about :math:`+x, +y, +z` (:math:`\hat{x} \times \hat{y} =
\hat{z}`).  The crank turns from :math:`+y` towards :math:`+x` (docs/conventions.md, "Frame and
angles"): that is a *negative* rotation about :math:`+z`, so a roll torque that is positive "in the
direction of rotation" is a torque about :math:`-z`.

Equations of motion (Harris & Piersol 2002, ch. 3):

.. math::

    \mathbf{M}\ddot{\mathbf{q}} + \mathbf{C}\dot{\mathbf{q}} + \mathbf{K}\mathbf{q}
    = \mathbf{f}(t),\qquad
    \mathbf{M} = \begin{pmatrix} m\mathbf{I} & 0 \\ 0 & \mathbf{J} \end{pmatrix},\qquad
    \mathbf{K} = \sum_i \mathbf{T}_i^{\mathsf T} \mathbf{K}_i \mathbf{T}_i,

where :math:`\mathbf{T}_i = [\,\mathbf{I} \mid -[\mathbf{r}_i]_\times]` gives the
displacement :math:`\mathbf{u} + \boldsymbol{\theta} \times \mathbf{r}_i` of mount
:math:`i` at :math:`\mathbf{r}_i` from the CG, and
:math:`\mathbf{K}_i = \mathbf{A}_i^{\mathsf T}\operatorname{diag}(k_1, k_2, k_3)\mathbf{A}_i`
is its stiffness in the engine frame (rows of :math:`\mathbf{A}_i`: the mount's axes);
:math:`\mathbf{C}` likewise from the dampings.  :math:`\mathbf{f}` holds the forces on the
body and their moments about the CG.

Harmonic quantities are complex amplitudes: :math:`x(t) = \mathrm{Re}(\hat{x}\, e^{i\Omega t})`,
with the crank angle :math:`\theta = \omega t` and :math:`\Omega = k\omega` for order :math:`k`.  A
component :math:`a\cos k\theta + b\sin k\theta` has :math:`\hat{x} = a - ib`, and its amplitude
(docs/conventions.md, "The engine on its mounts": the :math:`a` of :math:`a\cos(k\theta +
\text{phase})`) is :math:`|\hat{x}|`.

Every function takes numpy arrays in SI units; leading axes broadcast (a speed sweep over
all orders is one batched linear solve).  The core assumes valid input:
:mod:`balance.io.mounts_section` checks a ``mounts:`` section before building a
:class:`MountSystem`.

.. rubric:: References

C. M. Harris and A. G. Piersol (eds.), *Harris' Shock and Vibration Handbook*, 5th ed.,
McGraw-Hill, 2002, ch. 3 (H. Himelblau and S. Rubin, "Vibration of a resiliently supported
rigid body"): equations of motion in CG coordinates, the stiffness matrix of a set of
resilient supports, decoupled modes of symmetric systems.  F. F. Timpner, "Design
considerations in engine mounting", SAE Technical Paper 650093, 1965: the engine as a rigid
body on mounts, the torque-roll axis, decoupling.  T. Jeong and R. Singh, "Analytical
methods of decoupling the automotive engine torque roll axis", *Journal of Sound and
Vibration* 234(1), 2000, pp. 85-114: the torque-roll axis as the direction
:math:`\mathbf{J}^{-1}\hat{\mathbf{e}}` of the free body's rotation under a torque about the
crank axis, and the conditions for a mount system to decouple it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "COORDINATES",
    "Modes",
    "MountPoint",
    "MountSystem",
    "MountsResult",
    "assemble",
    "axis_distances",
    "crank_loads",
    "crossings",
    "damping_matrix",
    "elastic_axis_offsets",
    "harmonic_response",
    "inertia_tensor",
    "mass_matrix",
    "mount_forces",
    "mount_matrices",
    "mount_response",
    "normal_modes",
    "order_frequencies",
    "peak_force",
    "point_motion",
    "point_transfer",
    "speed_sweep",
    "stiffness_matrix",
    "torque_roll_axis",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Names of the six CG coordinates, in order.
COORDINATES = ("x", "y", "z", "rx", "ry", "rz")


def _frozen(value: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    array = np.array(value, dtype=np.float64).reshape(shape)
    array.flags.writeable = False
    return array


@dataclass(frozen=True, eq=False)
class MountPoint:
    """One mount: a linear spring (and viscous damper) along three perpendicular axes.

    Attributes
    ----------
    position : ndarray, shape (3,)
        Elastic centre of the mount in the engine frame [m].
    stiffness : ndarray, shape (3,)
        Stiffness along the mount's axes 1, 2, 3 [N/m], each >= 0.
    damping : ndarray, shape (3,)
        Viscous damping along the mount's axes 1, 2, 3 [N s/m], each >= 0 (default 0).
    axes : ndarray, shape (3, 3)
        Rotation matrix whose rows are the mount's axes 1, 2, 3 in the engine frame
        (orthonormal, right-handed; default: the engine axes).  An engine-frame vector
        ``v`` has the mount-axis components ``axes @ v``.
    """

    position: FloatArray
    stiffness: FloatArray
    damping: FloatArray = field(default_factory=lambda: np.zeros(3))
    axes: FloatArray = field(default_factory=lambda: np.eye(3))

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", _frozen(self.position, (3,)))
        object.__setattr__(self, "stiffness", _frozen(self.stiffness, (3,)))
        object.__setattr__(self, "damping", _frozen(self.damping, (3,)))
        object.__setattr__(self, "axes", _frozen(self.axes, (3, 3)))


@dataclass(frozen=True, eq=False)
class MountSystem:
    """The powertrain as a rigid body and the mounts that carry it (SI units).

    Attributes
    ----------
    mass : float
        Mass of everything the mounts carry [kg], > 0.
    cg : ndarray, shape (3,)
        Centre of gravity in the engine frame [m].
    inertia : ndarray, shape (3, 3)
        Inertia tensor about the CG in engine axes [kg m^2], symmetric positive definite,
        with the products of inertia on the off-diagonal as
        :math:`J_{xy} = -\\int x y \\,dm`
        (docs/conventions.md, "The engine on its mounts").
    points : tuple of MountPoint
        The mounts, at least one.
    """

    mass: float
    cg: FloatArray
    inertia: FloatArray
    points: tuple[MountPoint, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", float(self.mass))
        object.__setattr__(self, "cg", _frozen(self.cg, (3,)))
        object.__setattr__(self, "inertia", _frozen(self.inertia, (3, 3)))
        object.__setattr__(self, "points", tuple(self.points))

    @property
    def n_mounts(self) -> int:
        """Number of mounts."""
        return len(self.points)

    @property
    def positions(self) -> FloatArray:
        """Mount positions in the engine frame [m], shape ``(n, 3)``."""
        return np.array([p.position for p in self.points]).reshape(-1, 3)

    @property
    def offsets(self) -> FloatArray:
        """Mount positions relative to the CG [m], shape ``(n, 3)``."""
        return self.positions - self.cg

    @property
    def mount_stiffness(self) -> FloatArray:
        """Each mount's stiffness matrix in the engine frame [N/m], shape ``(n, 3, 3)``."""
        return mount_matrices(self._axes(), np.array([p.stiffness for p in self.points]))

    @property
    def mount_damping(self) -> FloatArray:
        """Each mount's damping matrix in the engine frame [N s/m], shape ``(n, 3, 3)``."""
        return mount_matrices(self._axes(), np.array([p.damping for p in self.points]))

    def _axes(self) -> FloatArray:
        return np.array([p.axes for p in self.points]).reshape(-1, 3, 3)


@dataclass(frozen=True)
class Modes:
    """Undamped rigid-body modes of a mount system, ascending in frequency.

    Attributes
    ----------
    frequency : ndarray, shape (..., 6)
        Natural frequencies [Hz], ascending.
    shapes : ndarray, shape (..., 6, 6)
        Mode shapes in CG coordinates, ``shapes[..., :, j]`` for mode ``j`` ([m] and [rad]
        per unit modal coordinate), mass-normalised (:math:`\\phi^{\\mathsf T} M \\phi = 1`),
        signed so that the coordinate with the largest energy
        share is positive.
    energy_share : ndarray, shape (..., 6, 6)
        ``energy_share[..., j, c]``: the share of mode ``j``'s kinetic energy in
        coordinate ``c`` (:data:`COORDINATES`), :math:`\\phi_c (M\\phi)_c /
        \\phi^{\\mathsf T} M \\phi` [1]; each mode's shares sum to 1.  With products of
        inertia a rotational share may be slightly negative (the cross terms are split
        between the two coordinates).
    """

    frequency: FloatArray
    shapes: FloatArray
    energy_share: FloatArray


# ---------------------------------------------------------------------------------------
# matrices


def inertia_tensor(
    xx: ArrayLike,
    yy: ArrayLike,
    zz: ArrayLike,
    xy: ArrayLike = 0.0,
    xz: ArrayLike = 0.0,
    yz: ArrayLike = 0.0,
) -> FloatArray:
    r"""The inertia tensor from its six entries.

    Parameters
    ----------
    xx, yy, zz : array_like
        Moments of inertia about the axes through the CG [kg m^2].
    xy, xz, yz : array_like, optional
        Products of inertia as tensor entries, :math:`J_{xy} = -\int x y\,dm` [kg m^2].

    Returns
    -------
    ndarray, shape (..., 3, 3)
        :math:`\begin{pmatrix} J_{xx} & J_{xy} & J_{xz} \\ J_{xy} & J_{yy} & J_{yz} \\
        J_{xz} & J_{yz} & J_{zz}\end{pmatrix}` [kg m^2].
    """
    e = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (xx, yy, zz, xy, xz, yz)))
    rows = [[e[0], e[3], e[4]], [e[3], e[1], e[5]], [e[4], e[5], e[2]]]
    return np.moveaxis(np.array(rows, dtype=np.float64), (0, 1), (-2, -1))


def mount_matrices(axes: ArrayLike, values: ArrayLike) -> FloatArray:
    r"""Stiffness (or damping) matrices of mounts in the engine frame.

    Parameters
    ----------
    axes : array_like, shape (..., 3, 3)
        Rows: the mount's axes 1, 2, 3 in the engine frame (orthonormal).
    values : array_like, shape (..., 3)
        Stiffness [N/m] (or damping [N s/m]) along each of those axes.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        :math:`\mathbf{A}^{\mathsf T}\operatorname{diag}(k)\mathbf{A}` [N/m or N s/m].

    Notes
    -----
    An isotropic mount (:math:`k_1 = k_2 = k_3 = k`) gives :math:`k\mathbf{I}` whatever its
    axes, because :math:`\mathbf{A}^{\mathsf T}\mathbf{A} = \mathbf{I}`.
    """
    a = np.asarray(axes, dtype=np.float64)
    k = np.asarray(values, dtype=np.float64)
    return np.asarray(np.einsum("...ki,...k,...kj->...ij", a, k, a), dtype=np.float64)


def point_transfer(offsets: ArrayLike) -> FloatArray:
    r"""Matrices giving the displacement of body points from the CG coordinates.

    Parameters
    ----------
    offsets : array_like, shape (..., 3)
        Points relative to the CG [m].

    Returns
    -------
    ndarray, shape (..., 3, 6)
        :math:`\mathbf{T} = [\,\mathbf{I} \mid -[\mathbf{r}]_\times]`, so that the point's
        displacement is :math:`\mathbf{T}\mathbf{q} = \mathbf{u} + \boldsymbol{\theta}
        \times \mathbf{r}` [m] (small rotations).
    """
    r = np.asarray(offsets, dtype=np.float64)
    x, y, z = r[..., 0], r[..., 1], r[..., 2]
    t = np.zeros((*r.shape[:-1], 3, 6))
    t[..., 0, 0] = t[..., 1, 1] = t[..., 2, 2] = 1.0
    # theta x r = -r x theta = -[r]x theta
    t[..., 0, 4], t[..., 0, 5] = z, -y
    t[..., 1, 3], t[..., 1, 5] = -z, x
    t[..., 2, 3], t[..., 2, 4] = y, -x
    return t


def assemble(offsets: ArrayLike, matrices: ArrayLike) -> FloatArray:
    r"""The 6×6 matrix of a set of point mounts in CG coordinates.

    Parameters
    ----------
    offsets : array_like, shape (n, 3)
        Mount positions relative to the CG [m].
    matrices : array_like, shape (n, 3, 3)
        Each mount's stiffness [N/m] (or damping [N s/m]) in the engine frame.

    Returns
    -------
    ndarray, shape (6, 6)
        :math:`\sum_i \mathbf{T}_i^{\mathsf T}\mathbf{K}_i\mathbf{T}_i`: [N/m], [N/rad],
        [N m/m] and [N m/rad] blocks (or the damping analogues).

    Notes
    -----
    The potential energy of the mounts is :math:`\tfrac12 \sum_i (\mathbf{T}_i\mathbf{q})^
    {\mathsf T} \mathbf{K}_i (\mathbf{T}_i \mathbf{q})`, whence the sum (Harris & Piersol
    2002, ch. 3).
    """
    t = point_transfer(offsets)
    k = np.asarray(matrices, dtype=np.float64)
    return np.asarray(np.einsum("nki,nkl,nlj->ij", t, k, t), dtype=np.float64)


def mass_matrix(mass: float, inertia: ArrayLike) -> FloatArray:
    r"""The 6×6 mass matrix in CG coordinates.

    Parameters
    ----------
    mass : float
        [kg].
    inertia : array_like, shape (3, 3)
        Inertia tensor about the CG [kg m^2].

    Returns
    -------
    ndarray, shape (6, 6)
        :math:`\operatorname{diag}(m\mathbf{I}, \mathbf{J})` [kg, kg m^2].
    """
    m = np.zeros((6, 6))
    m[:3, :3] = mass * np.eye(3)
    m[3:, 3:] = np.asarray(inertia, dtype=np.float64)
    return m


def stiffness_matrix(system: MountSystem) -> FloatArray:
    """The 6×6 stiffness matrix of a mount system in CG coordinates.

    Parameters
    ----------
    system : MountSystem
        The body and its mounts.

    Returns
    -------
    ndarray, shape (6, 6)
        :math:`K = \\sum_i T_i^{\\mathsf T} K_i T_i` [N/m, N/rad, N m/m, N m/rad]
        (:func:`assemble`).
    """
    return assemble(system.offsets, system.mount_stiffness)


def damping_matrix(system: MountSystem) -> FloatArray:
    """The 6×6 viscous damping matrix of a mount system in CG coordinates.

    Parameters
    ----------
    system : MountSystem
        The body and its mounts.

    Returns
    -------
    ndarray, shape (6, 6)
        :math:`C = \\sum_i T_i^{\\mathsf T} C_i T_i` [N s/m, N s/rad, N m s/m,
        N m s/rad] (:func:`assemble`); zero where no mount has damping.
    """
    return assemble(system.offsets, system.mount_damping)


# ---------------------------------------------------------------------------------------
# modes


def normal_modes(mass: ArrayLike, stiffness: ArrayLike) -> Modes:
    r"""Undamped modes: the generalised symmetric eigenproblem :math:`K\phi = \lambda M\phi`.

    Parameters
    ----------
    mass : array_like, shape (..., 6, 6)
        Mass matrix (symmetric positive definite).
    stiffness : array_like, shape (..., 6, 6)
        Stiffness matrix (symmetric positive semi-definite).

    Returns
    -------
    Modes
        Frequencies [Hz] ascending, mass-normalised shapes and kinetic-energy shares.

    Notes
    -----
    With the Cholesky factor :math:`M = LL^{\mathsf T}`, the symmetric matrix :math:`A = L^{-1} K
    L^{-\mathsf T}` has the eigenvalues :math:`\lambda_j = \omega_j^2` and eigenvectors
    :math:`\psi_j = L^{\mathsf T}\phi_j` (``numpy.linalg.eigh``). :math:`f_j = \sqrt{\lambda_j} /
    2\pi`; round-off negatives of a singular :math:`K` (a direction the mounts do not hold) give 0
    Hz.  Energy share of coordinate :math:`c` in mode :math:`j`: :math:`\phi_{c}(M\phi)_{c} /
    \phi^{\mathsf T}M\phi` (docs/conventions.md, "The engine on its mounts").  Within a repeated
    frequency the shapes are any basis of the eigenspace.
    """
    m = np.asarray(mass, dtype=np.float64)
    k = np.asarray(stiffness, dtype=np.float64)
    lower = np.linalg.cholesky(m)
    # A = L^-1 K L^-T, formed by two triangular solves (numpy's general solve)
    left = np.linalg.solve(lower, k)
    a = np.linalg.solve(lower, np.swapaxes(left, -1, -2))
    a = 0.5 * (a + np.swapaxes(a, -1, -2))
    lam, psi = np.linalg.eigh(a)
    phi = np.linalg.solve(np.swapaxes(lower, -1, -2), psi)
    m_phi = m @ phi
    energy = phi * m_phi  # [..., coordinate, mode]
    share = np.swapaxes(energy / np.sum(energy, axis=-2, keepdims=True), -1, -2)
    # sign: the coordinate with the largest share positive
    lead = np.argmax(share, axis=-1)  # [..., mode]
    sign = np.sign(np.take_along_axis(phi, lead[..., None, :], axis=-2))
    sign = np.where(sign == 0, 1.0, sign)
    phi = phi * sign
    frequency = np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * math.pi)
    return Modes(frequency=frequency, shapes=phi, energy_share=share)


# ---------------------------------------------------------------------------------------
# loads and response


def crank_loads(
    reference_z: float,
    cg: ArrayLike,
    force_forward: ArrayLike = 0.0,
    force_backward: ArrayLike = 0.0,
    moment_forward: ArrayLike = 0.0,
    moment_backward: ArrayLike = 0.0,
    roll: ArrayLike = 0.0,
) -> ComplexArray:
    r"""Complex amplitudes of the crank train's loads on the block, in CG coordinates.

    Parameters
    ----------
    reference_z : float
        Axial position of the point on the crank axis where the free forces act and about
        which the moment phasors are taken [m].
    cg : array_like, shape (3,)
        Centre of gravity [m].
    force_forward, force_backward : array_like of complex
        Force phasors :math:`P^{\pm}` of one order [N] (docs/conventions.md, "Phasors").
    moment_forward, moment_backward : array_like of complex
        Moment phasors :math:`\sum (z_i - z_{ref}) F_i` [N m], drawn like forces.
    roll : array_like of complex
        Roll phasor :math:`R` [N m]: the torque on the block about the crank axis is
        :math:`\mathrm{Re}(R e^{ik\theta})`, positive in the direction of rotation.

    Returns
    -------
    ndarray of complex, shape (..., 6)
        :math:`\hat{\mathbf{f}} = (\hat F_x, \hat F_y, \hat F_z, \hat M_x, \hat M_y,
        \hat M_z)` with :math:`\mathbf{f}(t) = \mathrm{Re}(\hat{\mathbf{f}} e^{ik\theta})`
        [N, N m]: forces, and moments about the CG.  The inputs broadcast (one entry per
        speed and order, say).

    Notes
    -----
    The transverse force is :math:`F_y + iF_x = P^{+}e^{ik\theta} + P^{-}e^{-ik\theta}`, so
    with :math:`\mathrm{Re}(P^{-}e^{-ik\theta}) = \mathrm{Re}(\overline{P^{-}}e^{ik\theta})`:

    .. math::

        \hat F_y = P^{+} + \overline{P^{-}},\qquad
        \hat F_x = -i\,(P^{+} - \overline{P^{-}}).

    The moment phasor :math:`Q` gives the couple :math:`M_x = -\mathrm{Re}\,Q`,
    :math:`M_y = \mathrm{Im}\,Q` (docs/conventions.md, "Moments"), so :math:`\hat M_x = -(Q^{+} +
    \overline{Q^{-}})` and :math:`\hat M_y = -i(Q^{+} - \overline{Q^{-}})`.  The crank turns
    from :math:`+y` towards :math:`+x`, a negative rotation about :math:`+z`
    (:math:`\hat{x}\times\hat{y} = \hat{z}`), so the roll torque about :math:`+z` is
    :math:`-\mathrm{Re}(Re^{ik\theta})`: :math:`\hat M_z = -R`.  The force acts at
    :math:`\mathbf{p}_0 = (0, 0, z_{ref})` on the crank axis; about the CG it adds the
    moment :math:`(\mathbf{p}_0 - \mathbf{c}) \times \hat{\mathbf{F}}`.
    """
    pf = np.asarray(force_forward, dtype=np.complex128)
    pb = np.conj(np.asarray(force_backward, dtype=np.complex128))
    qf = np.asarray(moment_forward, dtype=np.complex128)
    qb = np.conj(np.asarray(moment_backward, dtype=np.complex128))
    r = np.asarray(roll, dtype=np.complex128)
    pf, pb, qf, qb, r = np.broadcast_arrays(pf, pb, qf, qb, r)
    force = np.stack([-1j * (pf - pb), pf + pb, np.zeros_like(pf)], axis=-1)
    couple = np.stack([-(qf + qb), -1j * (qf - qb), -r], axis=-1)
    lever = np.array([0.0, 0.0, reference_z]) - np.asarray(cg, dtype=np.float64)
    moment = couple + np.cross(np.broadcast_to(lever, force.shape), force)
    return np.asarray(np.concatenate([force, moment], axis=-1), dtype=np.complex128)


def order_frequencies(speed: ArrayLike, orders: ArrayLike) -> FloatArray:
    r"""Circular frequencies :math:`\Omega = k\omega` of each order at each speed.

    Parameters
    ----------
    speed : array_like, shape (S,)
        Crank speeds :math:`\omega` [rad/s].
    orders : array_like, shape (K,)
        Orders :math:`k` (halves allowed).

    Returns
    -------
    ndarray, shape (S, K)
        [rad/s].
    """
    w = np.asarray(speed, dtype=np.float64)
    k = np.asarray(orders, dtype=np.float64)
    return np.asarray(w[..., None] * k, dtype=np.float64)


def harmonic_response(
    mass: ArrayLike,
    stiffness: ArrayLike,
    damping: ArrayLike,
    frequency: ArrayLike,
    load: ArrayLike,
) -> ComplexArray:
    r"""Steady-state response to harmonic loads, all frequencies in one batched solve.

    Parameters
    ----------
    mass, stiffness, damping : array_like, shape (6, 6)
        :math:`M` [kg...], :math:`K` [N/m...], :math:`C` [N s/m...] in CG coordinates
        (leading axes broadcast with ``frequency``).
    frequency : array_like, shape (...)
        Circular frequency :math:`\Omega` of each load [rad/s], > 0 unless :math:`K` is
        non-singular.
    load : array_like of complex, shape (..., 6)
        Complex amplitudes :math:`\hat{\mathbf{f}}` [N, N m] (:func:`crank_loads`).

    Returns
    -------
    ndarray of complex, shape (..., 6)
        :math:`\hat{\mathbf{q}}` [m, rad], with :math:`\mathbf{q}(t) =
        \mathrm{Re}(\hat{\mathbf{q}}e^{i\Omega t})`; the amplitude of each coordinate is
        its magnitude.

    Notes
    -----
    Substituting :math:`\mathbf{q} = \mathrm{Re}(\hat{\mathbf{q}}e^{i\Omega t})` into
    :math:`M\ddot{\mathbf{q}} + C\dot{\mathbf{q}} + K\mathbf{q} = \mathrm{Re}(\hat{\mathbf{f}}
    e^{i\Omega t})` gives :math:`(K - \Omega^2 M + i\Omega C)\,\hat{\mathbf{q}} =
    \hat{\mathbf{f}}`, one 6×6 complex system per frequency, solved for all of them by one
    call of ``numpy.linalg.solve``.
    """
    w = np.asarray(frequency, dtype=np.float64)[..., None, None]
    m = np.asarray(mass, dtype=np.float64)
    k = np.asarray(stiffness, dtype=np.float64)
    c = np.asarray(damping, dtype=np.float64)
    complex_stiffness = k - w**2 * m + 1j * w * c
    f = np.asarray(load, dtype=np.complex128)
    batch = np.broadcast_shapes(complex_stiffness.shape[:-2], f.shape[:-1])
    complex_stiffness = np.broadcast_to(complex_stiffness, (*batch, 6, 6))
    f = np.broadcast_to(f, (*batch, 6))
    return np.asarray(np.linalg.solve(complex_stiffness, f[..., None])[..., 0], dtype=np.complex128)


def point_motion(offsets: ArrayLike, response: ArrayLike) -> ComplexArray:
    r"""Displacement of body points from a CG-coordinate response.

    Parameters
    ----------
    offsets : array_like, shape (n, 3)
        Points relative to the CG [m].
    response : array_like of complex, shape (..., 6)
        :math:`\hat{\mathbf{q}}` [m, rad].

    Returns
    -------
    ndarray of complex, shape (..., n, 3)
        :math:`\hat{\mathbf{d}}_i = \mathbf{T}_i\hat{\mathbf{q}} = \hat{\mathbf{u}} +
        \hat{\boldsymbol{\theta}} \times \mathbf{r}_i` in the engine frame [m].
    """
    t = point_transfer(offsets)
    q = np.asarray(response, dtype=np.complex128)
    return np.asarray(np.einsum("nij,...j->...ni", t, q), dtype=np.complex128)


def mount_forces(system: MountSystem, response: ArrayLike, frequency: ArrayLike) -> ComplexArray:
    r"""Force each mount passes on (engine frame), from the response.

    Parameters
    ----------
    system : MountSystem
        The body and its mounts.
    response : array_like of complex, shape (..., 6)
        :math:`\hat{\mathbf{q}}` [m, rad] (:func:`harmonic_response`).
    frequency : array_like, shape (...)
        :math:`\Omega` of each response [rad/s].

    Returns
    -------
    ndarray of complex, shape (..., n, 3)
        :math:`\hat{\mathbf{F}}_i = (\mathbf{K}_i + i\Omega\mathbf{C}_i)\,\hat{\mathbf{d}}_i`
        [N]: the force the engine puts on mount ``i`` (and through it on the frame), in
        engine axes; the mount puts the opposite force on the engine.  The amplitude of
        each component is its magnitude.
    """
    d = point_motion(system.offsets, response)
    w = np.asarray(frequency, dtype=np.float64)[..., None, None]
    k = system.mount_stiffness
    c = system.mount_damping
    elastic = np.einsum("nij,...nj->...ni", k, d)
    viscous = np.einsum("nij,...nj->...ni", c, d)
    return np.asarray(elastic + 1j * w * viscous, dtype=np.complex128)


# ---------------------------------------------------------------------------------------
# torque-roll axis


def torque_roll_axis(inertia: ArrayLike, crank_axis: ArrayLike = (0.0, 0.0, 1.0)) -> FloatArray:
    r"""Direction of the torque-roll axis (TRA) through the CG.

    Parameters
    ----------
    inertia : array_like, shape (..., 3, 3)
        Inertia tensor about the CG [kg m^2].
    crank_axis : array_like, shape (3,), optional
        Direction of the torque [1] (default: the crank axis, +z).

    Returns
    -------
    ndarray, shape (..., 3)
        Unit vector :math:`\mathbf{a} = \mathbf{J}^{-1}\hat{\mathbf{e}} /
        |\mathbf{J}^{-1}\hat{\mathbf{e}}|`, signed so that :math:`\mathbf{a}\cdot
        \hat{\mathbf{e}} > 0`.

    Notes
    -----
    A free rigid body at rest loaded by a torque :math:`T\hat{\mathbf{e}}` starts to turn
    with :math:`\dot{\boldsymbol{\omega}} = T\mathbf{J}^{-1}\hat{\mathbf{e}}` about an axis
    through its CG: the torque-roll axis (Timpner 1965; Jeong & Singh 2000).  It is the
    crank axis only when that is a principal axis of :math:`\mathbf{J}`.
    """
    j = np.asarray(inertia, dtype=np.float64)
    e = np.broadcast_to(np.asarray(crank_axis, dtype=np.float64), (*j.shape[:-2], 3))
    a = np.linalg.solve(j, e[..., None])[..., 0]
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    sign = np.where(np.sum(a * e, axis=-1, keepdims=True) < 0, -1.0, 1.0)
    return np.asarray(a * sign, dtype=np.float64)


def axis_distances(points: ArrayLike, axis_point: ArrayLike, direction: ArrayLike) -> FloatArray:
    r"""Perpendicular distance of points from a line.

    Parameters
    ----------
    points : array_like, shape (..., 3)
        [m].
    axis_point : array_like, shape (3,)
        A point of the line [m] (the CG for the torque-roll axis).
    direction : array_like, shape (3,)
        Direction of the line (any length > 0).

    Returns
    -------
    ndarray, shape (...)
        :math:`|(\mathbf{p} - \mathbf{c}) \times \hat{\mathbf{a}}|` [m].
    """
    a = np.asarray(direction, dtype=np.float64)
    a = a / np.linalg.norm(a)
    rel = np.asarray(points, dtype=np.float64) - np.asarray(axis_point, dtype=np.float64)
    return np.asarray(np.linalg.norm(np.cross(rel, a), axis=-1), dtype=np.float64)


def elastic_axis_offsets(
    system: MountSystem, axis_point: ArrayLike, direction: ArrayLike
) -> FloatArray:
    r"""How far each mount's elastic axes pass from a line (the torque-roll axis, say).

    Parameters
    ----------
    system : MountSystem
        The body and its mounts.
    axis_point : array_like, shape (3,)
        A point of the line [m].
    direction : array_like, shape (3,)
        Its direction.

    Returns
    -------
    ndarray, shape (n, 3)
        For mount ``i`` and its axis ``j`` (1, 2, 3), the shortest distance [m] between
        the line through the mount's elastic centre along that axis and the given line.
        0 when the axis meets the line (a mount "focused" on the torque-roll axis).

    Notes
    -----
    For lines :math:`\mathbf{p} + s\hat{\mathbf{e}}` and :math:`\mathbf{c} + t\hat{\mathbf{a}}`
    with :math:`\mathbf{n} = \hat{\mathbf{e}}\times\hat{\mathbf{a}} \ne 0` the distance is
    :math:`|(\mathbf{p}-\mathbf{c})\cdot\mathbf{n}| / |\mathbf{n}|`; for parallel lines it
    is the perpendicular distance :math:`|(\mathbf{p}-\mathbf{c})\times\hat{\mathbf{a}}|`.
    """
    a = np.asarray(direction, dtype=np.float64)
    a = a / np.linalg.norm(a)
    rel = system.positions - np.asarray(axis_point, dtype=np.float64)  # (n, 3)
    axes = system._axes()  # (n, 3 axes, 3)
    n = np.cross(axes, a)  # (n, 3, 3)
    size = np.linalg.norm(n, axis=-1)
    parallel = size < 1e-12
    skew = np.abs(np.einsum("nk,njk->nj", rel, n)) / np.where(parallel, 1.0, size)
    perpendicular = np.linalg.norm(np.cross(rel, a), axis=-1)[:, None]
    return np.asarray(np.where(parallel, perpendicular, skew), dtype=np.float64)


# ---------------------------------------------------------------------------------------
# the whole answer


def peak_force(forces: ArrayLike) -> FloatArray:
    r"""Largest magnitude over a cycle of harmonic force vectors.

    Parameters
    ----------
    forces : array_like of complex, shape (..., 3)
        Complex amplitudes :math:`\hat{\mathbf{F}}` [N] (:func:`mount_forces`).

    Returns
    -------
    ndarray, shape (...)
        :math:`\max_t |\mathrm{Re}(\hat{\mathbf{F}}e^{i\Omega t})| =
        \sqrt{(\hat{\mathbf{F}}^{\mathsf H}\hat{\mathbf{F}} +
        |\hat{\mathbf{F}}^{\mathsf T}\hat{\mathbf{F}}|)/2}` [N]: the semi-major axis of
        the ellipse the force vector draws (its components peak at different times).
    """
    f = np.asarray(forces, dtype=np.complex128)
    power = np.sum(np.abs(f) ** 2, axis=-1)
    square = np.abs(np.sum(f * f, axis=-1))
    return np.asarray(np.sqrt(0.5 * (power + square)), dtype=np.float64)


@dataclass(frozen=True, eq=False)
class MountsResult:
    """The engine on its mounts: modes and the steady-state response per order.

    Attributes
    ----------
    system : MountSystem
        The body and its mounts.
    modes : Modes
        The six undamped modes (:func:`normal_modes`).
    orders : ndarray, shape (K,)
        Orders of the response (halves for a four-stroke with gas forces).
    speed : ndarray, shape () or (S,)
        Crank speed [rad/s] (a speed sweep has one entry per speed).
    loads : ndarray of complex, shape (..., K, 6)
        Complex amplitudes of the loads on the block in CG coordinates [N, N m]
        (:func:`crank_loads`).
    response : ndarray of complex, shape (..., K, 6)
        CG translations [m] and rotations [rad] (:func:`harmonic_response`).
    forces : ndarray of complex, shape (..., K, n, 3)
        Force of each mount in engine axes [N] (:func:`mount_forces`).
    roll_axis : ndarray, shape (3,)
        Direction of the torque-roll axis through the CG (:func:`torque_roll_axis`).
    axis_distance : ndarray, shape (n,)
        Distance of each mount's elastic centre from the torque-roll axis [m].
    elastic_offsets : ndarray, shape (n, 3)
        Distance of each mount's elastic axes 1, 2, 3 from the torque-roll axis [m]
        (:func:`elastic_axis_offsets`).
    with_proposal : bool
        Whether the loads include the proposed counterweights and balance shafts.
    gas : bool
        Whether the roll torque includes the gas torque's reaction.
    gas_loads : ndarray of complex, shape (K, 6), or None
        The part of :attr:`loads` from the gas torque (which does not scale with speed);
        None without gas.
    """

    system: MountSystem
    modes: Modes
    orders: FloatArray
    speed: FloatArray
    loads: ComplexArray
    response: ComplexArray
    forces: ComplexArray
    roll_axis: FloatArray
    axis_distance: FloatArray
    elastic_offsets: FloatArray
    with_proposal: bool = False
    gas: bool = False
    gas_loads: ComplexArray | None = None

    @property
    def translation(self) -> FloatArray:
        """Amplitudes of the CG's x, y, z motion [m], shape ``(..., K, 3)``."""
        return np.asarray(np.abs(self.response[..., :3]), dtype=np.float64)

    @property
    def rotation(self) -> FloatArray:
        """Amplitudes of the rotations about x, y, z [rad], shape ``(..., K, 3)``."""
        return np.asarray(np.abs(self.response[..., 3:]), dtype=np.float64)

    @property
    def force_amplitude(self) -> FloatArray:
        """Amplitudes of each mount's force components [N], shape ``(..., K, n, 3)``."""
        return np.asarray(np.abs(self.forces), dtype=np.float64)

    @property
    def force_peak(self) -> FloatArray:
        """Largest magnitude of each mount's force over a cycle [N], ``(..., K, n)``
        (:func:`peak_force`)."""
        return peak_force(self.forces)

    @property
    def largest_force(self) -> FloatArray:
        """The largest :attr:`force_peak` of all mounts [N], shape ``(..., K)``."""
        return np.asarray(np.max(self.force_peak, axis=-1), dtype=np.float64)

    def mode_crossings(self) -> list[tuple[float, int, float]]:
        """Where the orders cross the modes within the result's speeds (:func:`crossings`
        from its lowest to its highest speed).

        Returns
        -------
        list of (order, mode, speed)
            Order :math:`k`, mode :math:`j` (0-based) and the crank speed [rad/s] at which
            the order excites the mode; ascending speed.
        """
        speeds = np.atleast_1d(self.speed)
        return crossings(
            self.modes.frequency, self.orders, float(speeds.min()), float(speeds.max())
        )


def mount_response(
    system: MountSystem,
    speed: ArrayLike,
    orders: ArrayLike,
    reference_z: float,
    force_forward: ArrayLike = 0.0,
    force_backward: ArrayLike = 0.0,
    moment_forward: ArrayLike = 0.0,
    moment_backward: ArrayLike = 0.0,
    roll: ArrayLike = 0.0,
    *,
    with_proposal: bool = False,
    gas_roll: ArrayLike | None = None,
) -> MountsResult:
    r"""Modes and steady-state response of a mount system to the crank train's loads.

    Parameters
    ----------
    system : MountSystem
        The body and its mounts.
    speed : array_like, shape () or (S,)
        Crank speed [rad/s].
    orders : array_like, shape (K,)
        Orders (halves allowed).
    reference_z : float
        Where the free forces act on the crank axis, and the moments' reference [m].
    force_forward, force_backward, moment_forward, moment_backward, roll : array_like
        Phasors per order [N, N m] (:func:`crank_loads`), shape ``(K,)`` or ``(S, K)``.
    with_proposal : bool
        Recorded on the result (whether the loads hold the proposal).
    gas_roll : array_like of complex, optional
        The part of ``roll`` that is the gas torque's reaction [N m] (kept apart so that a
        speed sweep scales only the inertia loads, :func:`speed_sweep`).

    Returns
    -------
    MountsResult

    Notes
    -----
    All speeds and orders are solved by one batched call of :func:`harmonic_response`.
    """
    w = np.asarray(speed, dtype=np.float64)
    ks = np.asarray(orders, dtype=np.float64)
    omega = order_frequencies(w, ks)
    loads = crank_loads(
        reference_z, system.cg, force_forward, force_backward, moment_forward, moment_backward, roll
    )
    m = mass_matrix(system.mass, system.inertia)
    k = stiffness_matrix(system)
    response = harmonic_response(m, k, damping_matrix(system), omega, loads)
    axis = torque_roll_axis(system.inertia)
    return MountsResult(
        system=system,
        modes=normal_modes(m, k),
        orders=ks,
        speed=w,
        loads=loads,
        response=response,
        forces=mount_forces(system, response, omega),
        roll_axis=axis,
        axis_distance=axis_distances(system.positions, system.cg, axis),
        elastic_offsets=elastic_axis_offsets(system, system.cg, axis),
        with_proposal=with_proposal,
        gas=gas_roll is not None,
        gas_loads=None
        if gas_roll is None
        else crank_loads(reference_z, system.cg, roll=np.asarray(gas_roll, dtype=np.complex128)),
    )


def speed_sweep(base: MountsResult, speeds: ArrayLike) -> MountsResult:
    r"""The response of :func:`mount_response` at other crank speeds, in one batched solve.

    Parameters
    ----------
    base : MountsResult
        A response at one speed :math:`\omega_0` (scalar :attr:`MountsResult.speed`).
    speeds : array_like, shape (S,)
        Crank speeds [rad/s].

    Returns
    -------
    MountsResult
        With ``speed`` of shape ``(S,)`` and loads, response and forces of shape
        ``(S, K, ...)``.

    Notes
    -----
    Every inertia load (free forces, moments, inertia roll, proposed masses) is
    proportional to :math:`\omega^2`, so :math:`\hat{\mathbf{f}}(\omega) =
    (\hat{\mathbf{f}}_0 - \hat{\mathbf{f}}_{gas})(\omega/\omega_0)^2 +
    \hat{\mathbf{f}}_{gas}`: the gas torque's reaction (one pressure trace at every
    speed) is kept as it is.
    """
    system = base.system
    w = np.asarray(speeds, dtype=np.float64)
    w0 = float(base.speed)
    gas = base.gas_loads if base.gas_loads is not None else np.zeros_like(base.loads)
    scale = (w / w0) ** 2
    loads = (base.loads - gas) * scale[..., None, None] + gas
    omega = order_frequencies(w, base.orders)
    m = mass_matrix(system.mass, system.inertia)
    response = harmonic_response(m, stiffness_matrix(system), damping_matrix(system), omega, loads)
    return replace(
        base,
        speed=w,
        loads=loads,
        response=response,
        forces=mount_forces(system, response, omega),
    )


def crossings(
    frequency: ArrayLike, orders: ArrayLike, low: float, high: float
) -> list[tuple[float, int, float]]:
    r"""Where the orders cross the modes within a speed range.

    Parameters
    ----------
    frequency : array_like, shape (6,)
        Mode frequencies [Hz].
    orders : array_like, shape (K,)
        Orders.
    low, high : float
        Speed range [rad/s].

    Returns
    -------
    list of (order, mode, speed)
        Order :math:`k` excites mode :math:`j` (0-based) at the crank speed
        :math:`\omega = 2\pi f_j / k` [rad/s] (:math:`60 f_j / k` rpm), for every pair whose
        speed lies in ``[low, high]``; ascending speed.
    """
    out = []
    for k in np.asarray(orders, dtype=np.float64):
        for j, f in enumerate(np.asarray(frequency, dtype=np.float64)):
            if k > 0 and f > 0:
                speed = 2.0 * math.pi * f / k
                if low <= speed <= high:
                    out.append((float(k), j, float(speed)))
    return sorted(out, key=lambda c: c[2])
