r"""Brute-force computation in the crank-angle domain.

Independent of the phasor algebra: the forces, moments and roll torque are sampled over a
revolution from the geometry of every cylinder, summed as vectors in the engine frame, and
their harmonics taken by FFT.  The tests check every analytic shortcut of the package
against these functions (and against the references only they use, in ``tests/oracles.py``:
the torque and forces on the crank, the whole block force, the proposal's masses).

The roll torque is found here by the Newton–Euler equations of piston and rigid conrod
(mass, centre of gravity, moment of inertia) at each crank angle, solved for the force of
the cylinder wall; its moment about the crank axis is what the block receives.  This does
not use the energy argument by which :func:`balance.core.kinematics.roll_coefficients` is
derived.

Articulated rods (:mod:`balance.core.links`) are brute-forced the same way, independently of
that module: the rods' angles come from the loop-closure constraints (a rod from a moving
point to a slider on a bore), their rates and accelerations from the differentiated
constraints (the velocity and acceleration analysis of a linkage), and each master with its
link rods and pistons is one rigid-body system whose pin forces and wall forces are the
unknowns of one linear solve per crank angle (:func:`articulated_newton_euler`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import crank_train
from balance.core.engine import Engine
from balance.core.kinematics import (
    conrod_angle_derivatives,
    normalised_slider,
    offset_ratio,
    rod_ratio,
)
from balance.core.speed import speed_squared

__all__ = [
    "ArticulatedSolution",
    "articulated_newton_euler",
    "crank_angles",
    "link_pin_force_samples",
    "link_piston_acceleration_at",
    "phasors_from_samples",
    "reciprocating_force_samples",
    "reciprocating_samples",
    "roll_newton_euler",
    "roll_phasors_from_samples",
    "rotating_force_samples",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


def crank_angles(samples: int) -> FloatArray:
    r"""Equally spaced crank angles over one revolution.

    Parameters
    ----------
    samples : int
        Number of angles.

    Returns
    -------
    ndarray
        :math:`2\pi i/N`, :math:`i = 0 \dots N-1` [rad].
    """
    return 2.0 * np.pi * np.arange(samples) / samples


def reciprocating_force_samples(
    layout: Engine, theta: ArrayLike, lever: bool = False
) -> ComplexArray:
    r"""Reciprocating inertia force (or moment) on the block at each crank angle.

    Parameters
    ----------
    layout : Engine
        The engine (its masses, geometry and speed).
    theta : array_like
        Crank angles [rad], shape (angles,).
    lever : bool
        Return the moment instead of the force.

    Returns
    -------
    ndarray of complex
        :math:`\sum_i -m_{rec,i}\, \omega^2 s_i''(\beta_i)\, e^{i\psi_i}` [N] (times
        :math:`z_i - z_{ref}` [N m] with ``lever=True``), one value per crank angle; with
        link rods also each link-pin mass' inertia relative to its crank pin
        (:func:`link_pin_force_samples`).  Both at once: :func:`reciprocating_samples`.
    """
    force, moment = reciprocating_samples(layout, theta)
    return moment if lever else force


def rotating_force_samples(layout: Engine, theta: ArrayLike, lever: bool = False) -> ComplexArray:
    """Centrifugal force (or moment) of the rotating masses at each crank angle.

    Parameters
    ----------
    layout : Engine
        The engine.
    theta : array_like
        Crank angles [rad], shape (angles,).
    lever : bool
        Return the moment about ``reference_z`` instead of the force.

    Returns
    -------
    ndarray of complex
        One value per crank angle [N, or N m with ``lever``].
    """
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

    Parameters
    ----------
    samples : array_like of complex
        :math:`Q` at :func:`crank_angles`, angles on the last axis (any unit).
    orders : array_like of int
        The orders k.

    Returns
    -------
    forward, backward : ndarray of complex
        :math:`P_k^{+}` and :math:`P_k^{-}`, in the unit of ``samples``.
    """
    q = np.asarray(samples, dtype=np.complex128)
    n = q.shape[-1]
    spectrum = np.fft.fft(q, axis=-1) / n
    ks = np.asarray(orders, dtype=np.intp)
    return spectrum[..., ks % n], spectrum[..., (-ks) % n]


def roll_phasors_from_samples(samples: ArrayLike, orders: ArrayLike) -> ComplexArray:
    r"""Phasors :math:`R_k` of a real torque :math:`\sum_k \mathrm{Re}(R_k e^{ik\theta})`.

    Parameters
    ----------
    samples : array_like
        The torque at :func:`crank_angles` [N m], angles on the last axis.
    orders : array_like of int
        The orders k.

    Returns
    -------
    ndarray of complex
        :math:`R_k` [N m].
    """
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
    cylinders = _newton_euler(layout, theta, small_end_share, cg_fraction, gas_force)
    torque = -cylinders.s * cylinders.wall - cylinders.offset * cylinders.gas
    if layout.has_links:
        solution = articulated_newton_euler(layout, theta, small_end_share, cg_fraction, gas_force)
        plain = _plain_mask(layout)
        return np.asarray(
            np.where(plain, torque, 0.0).sum(axis=1) + solution.roll, dtype=np.float64
        )
    return np.asarray(torque.sum(axis=1), dtype=np.float64)


@dataclass(frozen=True)
class _PlainSolution:
    """The Newton–Euler solution of plain cylinders, shape (angles, cylinders); vectors in
    each cylinder's frame as X + iY."""

    wall: FloatArray  # N, the wall's force on the piston along +X
    on_pin: ComplexArray  # force of the rod on the crank pin
    crank: ComplexArray  # crank pin C
    s: FloatArray
    offset: FloatArray
    gas: FloatArray
    on_piston: ComplexArray  # force of the rod on the piston pin
    rod: ComplexArray  # C - P


def _newton_euler(
    layout: Engine,
    theta: ArrayLike,
    small_end_share: float,
    cg_fraction: float,
    gas_force: ArrayLike | None,
) -> _PlainSolution:
    """Wall force N, the rod's forces on crank pin and piston pin, pin position, s, e and G
    per cylinder."""
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
    return _PlainSolution(N, on_pin, C, s, offset, gas, Q - N, d)


# --------------------------------------------------------------------------- articulated rods


def _plain_mask(layout: Engine) -> NDArray[np.bool_]:
    """Cylinders (on the last axis) whose rod is neither a master nor a link rod."""
    assert layout.links is not None
    grouped = np.zeros(layout.n_cylinders, dtype=bool)
    grouped[layout.links.link_indices] = True
    grouped[layout.links.masters] = True
    return np.asarray(~grouped)


@dataclass(frozen=True)
class _Rod:
    """A rod from a moving point to a piston pin sliding on a bore, over crank angles.

    ``angle`` is the direction of the rod from its lower end to the piston pin, from +y in
    the direction of rotation; derivatives with respect to the crank angle.  Points are
    complex ``y + ix`` in the engine frame.
    """

    angle: FloatArray
    dangle: FloatArray
    d2angle: FloatArray
    piston: ComplexArray
    dpiston: ComplexArray
    d2piston: ComplexArray


def _rod_on_bore(
    end: ComplexArray,
    dend: ComplexArray,
    d2end: ComplexArray,
    length: ArrayLike,
    bank: ArrayLike,
    offset: ArrayLike,
) -> _Rod:
    r"""Solve the loop-closure constraint of a rod of ``length`` from the point ``end`` (with
    its first and second derivatives) to a piston pin on the bore of direction ``bank`` and
    offset ``offset``.

    The constraint :math:`\operatorname{Im}(P e^{-i\psi}) = e` with :math:`P = A +
    l e^{i\vartheta}` gives :math:`\sin(\vartheta - \psi) = (e - A_X)/l` (the rod points
    away from the crank), and differentiated once and twice
    :math:`A_X' + l\cos(\vartheta-\psi)\vartheta' = 0`,
    :math:`A_X'' + l\cos(\vartheta-\psi)\vartheta'' - l\sin(\vartheta-\psi)\vartheta'^2
    = 0` (:math:`A_X` across the bore).
    """
    psi = np.asarray(bank, dtype=np.float64)
    ell = np.asarray(length, dtype=np.float64)
    turn = np.exp(-1j * psi)
    across, dacross, d2across = (end * turn).imag, (dend * turn).imag, (d2end * turn).imag
    sin_rel = (np.asarray(offset, dtype=np.float64) - across) / ell
    cos_rel = np.sqrt(1.0 - sin_rel**2)
    angle = psi + np.arcsin(sin_rel)
    dangle = -dacross / (ell * cos_rel)
    d2angle = (ell * sin_rel * dangle**2 - d2across) / (ell * cos_rel)
    direction = np.exp(1j * angle)
    piston = end + ell * direction
    dpiston = dend + 1j * ell * dangle * direction
    d2piston = d2end + ell * direction * (1j * d2angle - dangle**2)
    return _Rod(angle, dangle, d2angle, piston, dpiston, d2piston)


@dataclass(frozen=True)
class _Group:
    """The kinematics of one master with its link rods, over crank angles (engine frame)."""

    master: int
    links: NDArray[np.intp]
    crank: ComplexArray
    master_rod: _Rod
    link_pin: ComplexArray  # (links, angles)
    dlink_pin: ComplexArray
    d2link_pin: ComplexArray
    link_rods: _Rod  # arrays (links, angles)


def _articulated_kinematics(layout: Engine, theta: ArrayLike) -> list[_Group]:
    r"""The kinematics of every master with its link rods (see :func:`_rod_on_bore`).

    The link pin of link rod j is :math:`L = C + \rho e^{i(\vartheta_m + \alpha)}` on the
    master rod (angle :math:`\vartheta_m`); its derivatives follow from the master rod's.
    """
    assert layout.links is not None
    th = np.asarray(theta, dtype=np.float64)
    links = layout.links
    groups = []
    for m in links.masters.tolist():
        js = np.flatnonzero(links.master == m).astype(np.intp)
        r = layout.crank_radius[m]
        crank = r * np.exp(1j * (th + layout.throw[m]))
        master = _rod_on_bore(
            crank,
            1j * crank,
            -crank,
            layout.conrod_length[m],
            layout.bank[m],
            layout.offset[m],
        )
        rho = links.pin_radius[js][:, None]
        direction = np.exp(1j * (master.angle[None, :] + links.pin_angle[js][:, None]))
        pin = crank[None, :] + rho * direction
        dpin = 1j * crank[None, :] + 1j * rho * master.dangle[None, :] * direction
        d2pin = -crank[None, :] + rho * direction * (
            1j * master.d2angle[None, :] - master.dangle[None, :] ** 2
        )
        rods = _rod_on_bore(
            pin,
            dpin,
            d2pin,
            layout.conrod_length[js][:, None],
            layout.bank[js][:, None],
            layout.offset[js][:, None],
        )
        groups.append(_Group(m, js, crank, master, pin, dpin, d2pin, rods))
    return groups


def _pin_shares(layout: Engine, every: bool = False) -> FloatArray:
    """Link rods' link-pin shares [kg] per cylinder (rotating mass less the crank's share);
    with ``every``, every rod's share at its lower end."""
    share: FloatArray | float = 0.0
    parts = layout.mass_parts
    if parts is not None:
        share = np.nan_to_num(parts.crank_unbalance) / parts.rods_per_throw
    assert layout.links is not None
    rod = np.asarray(layout.rotating_mass - share, dtype=np.float64)
    if every:
        return rod
    return np.asarray(np.where(layout.links.master >= 0, rod, 0.0), dtype=np.float64)


def link_pin_force_samples(layout: Engine, theta: ArrayLike) -> ComplexArray:
    r"""Inertia force of each link rod's link-pin share relative to its crank pin.

    :math:`-m\omega^2(L'' - C'')` per link cylinder, from the constraint kinematics.

    Parameters
    ----------
    layout : Engine
        An engine with link rods.
    theta : array_like
        Crank angles [rad], shape (angles,).

    Returns
    -------
    ndarray of complex
        Force [N], shape (link cylinders, angles), rows in cylinder order.
    """
    th = np.asarray(theta, dtype=np.float64)
    return _link_pin_forces(layout, _articulated_kinematics(layout, th), th.size)


def _link_rows(layout: Engine) -> dict[int, int]:
    """Row of each link cylinder in the (links, angles) arrays (cylinder order)."""
    assert layout.links is not None
    return {int(j): i for i, j in enumerate(layout.links.link_indices)}


def _link_pin_forces(layout: Engine, groups: list[_Group], n_t: int) -> ComplexArray:
    """:func:`link_pin_force_samples` from the groups' kinematics over ``n_t`` angles."""
    assert layout.links is not None
    out = np.zeros((layout.links.link_indices.size, n_t), dtype=np.complex128)
    row_of = _link_rows(layout)
    w2 = speed_squared(layout.speed)
    m_pin = _pin_shares(layout)
    for g in groups:
        for i, j in enumerate(g.links.tolist()):
            out[row_of[j]] = -m_pin[j] * w2 * (g.d2link_pin[i] + g.crank)
    return out


def _link_piston_rows(
    layout: Engine, groups: list[_Group], n_t: int, *, own_angles: bool = False
) -> FloatArray:
    """:math:`s''/r` of each link piston along its bore over ``n_t`` angles (rows: link
    cylinders in order) from the groups' kinematics; with ``own_angles`` the groups' angles
    are one block of ``n_t`` per link cylinder (in cylinder order), and each row is read
    from its own block."""
    row_of = _link_rows(layout)
    out = np.zeros((len(row_of), n_t))
    for g in groups:
        for i, j in enumerate(g.links.tolist()):
            row = row_of[j]
            start = row * n_t if own_angles else 0
            acc = g.link_rods.d2piston[i, start : start + n_t]
            out[row] = (acc * np.exp(-1j * layout.bank[j])).real / layout.crank_radius[j]
    return out


def _link_piston_acceleration(layout: Engine, theta: ArrayLike) -> FloatArray:
    """:math:`s''/r` of each link piston along its bore (rows: link cylinders in order), from
    the constraint kinematics, at the crank angles ``theta``."""
    th = np.asarray(theta, dtype=np.float64)
    return _link_piston_rows(layout, _articulated_kinematics(layout, th), th.size)


def link_piston_acceleration_at(layout: Engine, theta: ArrayLike) -> FloatArray:
    """:math:`s''/r` of each link piston along its bore, each link cylinder at its own crank
    angles, from the constraint kinematics.

    One pass of the kinematics over all rows' angles, each link cylinder then read at its own
    row's.

    Parameters
    ----------
    layout : Engine
        An engine with link rods.
    theta : array_like
        Crank angles [rad], shape (link cylinders, angles), rows in cylinder order.

    Returns
    -------
    ndarray
        :math:`s''/r` [1/rad^2], the shape of ``theta``.
    """
    th = np.asarray(theta, dtype=np.float64)
    groups = _articulated_kinematics(layout, th.reshape(-1))
    return _link_piston_rows(layout, groups, th.shape[-1], own_angles=True)


def reciprocating_samples(layout: Engine, theta: ArrayLike) -> tuple[ComplexArray, ComplexArray]:
    """:func:`reciprocating_force_samples` without and with the lever, from one pass of the
    kinematics.

    Parameters
    ----------
    layout : Engine
        The engine.
    theta : array_like
        Crank angles [rad], shape (angles,).

    Returns
    -------
    force, moment : ndarray of complex
        The force [N] and the moment about ``reference_z`` [N m] at each crank angle.
    """
    th = np.asarray(theta, dtype=np.float64)
    if layout.has_links:
        return _articulated_reciprocating(layout, th)
    beta = th[:, None] + layout.throw - layout.bank
    r = layout.crank_radius
    _, _, d2s = normalised_slider(
        beta, rod_ratio(r, layout.conrod_length), offset_ratio(layout.offset, r)
    )
    w2 = speed_squared(layout.speed)
    along = crank_train.reciprocating_force(
        layout.reciprocating_mass, w2, r, d2s
    )  # towards the crank
    force = -along * np.exp(1j * layout.bank)
    moment = force * (layout.z - layout.reference_z)
    return (
        np.asarray(force.sum(axis=1), dtype=np.complex128),
        np.asarray(moment.sum(axis=1), dtype=np.complex128),
    )


def _articulated_reciprocating(
    layout: Engine, theta: FloatArray
) -> tuple[ComplexArray, ComplexArray]:
    """Reciprocating force and moment samples of an engine with link rods."""
    assert layout.links is not None
    w2 = speed_squared(layout.speed)
    plain = layout.links.master < 0
    th = theta[:, None]
    beta = th + layout.throw - layout.bank
    r = layout.crank_radius
    _, _, d2s = normalised_slider(
        beta[:, plain],
        rod_ratio(r[plain], layout.conrod_length[plain]),
        offset_ratio(layout.offset[plain], r[plain]),
    )
    along = crank_train.reciprocating_force(layout.reciprocating_mass[plain], w2, r[plain], d2s)
    force = -along * np.exp(1j * layout.bank[plain])
    j = layout.links.link_indices
    groups = _articulated_kinematics(layout, theta)
    link_acc = _link_piston_rows(layout, groups, theta.size)  # (links, angles)
    m_j, r_j = layout.reciprocating_mass[j][:, None], r[j][:, None]
    pistons = (
        -crank_train.reciprocating_force(m_j, w2, r_j, link_acc)
        * np.exp(1j * layout.bank[j])[:, None]
    )
    each = pistons + _link_pin_forces(layout, groups, theta.size)

    def summed(arm: FloatArray) -> ComplexArray:
        total = (force * arm[plain]).sum(axis=1) + (each * arm[j][:, None]).sum(axis=0)
        return np.asarray(total, dtype=np.complex128)

    return summed(np.ones(layout.n_cylinders)), summed(layout.z - layout.reference_z)


@dataclass(frozen=True)
class ArticulatedSolution:
    r"""What the Newton–Euler solution of the master-and-link groups gives, over crank angles.

    Attributes
    ----------
    masters : ndarray of int
        The master cylinders (one group each).
    pin_force : ndarray of complex
        Force of each master rod on its crank pin [N], shape (groups, angles).
    wall : ndarray
        Normal force of the wall on each piston of the groups [N] (along the bore's +X),
        shape (cylinders, angles), 0 for the other cylinders.
    block_force, block_moment : ndarray of complex
        Force the groups put on the block (walls, mains and, with gas, heads) [N], and its
        moment :math:`\sum (z - z_{ref}) F` [N m].
    roll : ndarray
        Torque about the crank axis the block receives from the groups [N m].
    crank_torque : ndarray
        Torque the master rods put on the crankshaft [N m].
    rod_force : ndarray
        Each rod's force at its piston pin along the rod, compression positive [N], shape
        (cylinders, angles), 0 for the other cylinders.
    """

    masters: NDArray[np.intp]
    pin_force: ComplexArray
    wall: FloatArray
    block_force: ComplexArray
    block_moment: ComplexArray
    roll: FloatArray
    crank_torque: FloatArray
    rod_force: FloatArray


@dataclass(frozen=True)
class _LinearSystem:
    """Real linear equations, one set per crank angle, written with complex numbers
    (``y + ix``): a complex equation is two rows, a complex unknown two columns."""

    A: FloatArray  # (angles, rows, columns)
    rhs: FloatArray  # (angles, rows)

    def put(self, row: int, col: int, z: ComplexArray | complex) -> None:
        """Coefficient ``z`` of the complex unknown at ``col`` in the complex equation at
        ``row``: ``z F`` has real part ``z_r F_y - z_i F_x`` and imaginary part
        ``z_i F_y + z_r F_x``."""
        zz = np.broadcast_to(np.asarray(z, dtype=np.complex128), self.A.shape[:1])
        self.A[:, row, col] += zz.real
        self.A[:, row, col + 1] -= zz.imag
        self.A[:, row + 1, col] += zz.imag
        self.A[:, row + 1, col + 1] += zz.real

    def put_real(self, row: int, col: int, z: ComplexArray | complex) -> None:
        """Complex coefficient of the real unknown at ``col`` (a normal force) at ``row``."""
        zz = np.broadcast_to(np.asarray(z, dtype=np.complex128), self.A.shape[:1])
        self.A[:, row, col] += zz.real
        self.A[:, row + 1, col] += zz.imag

    def put_moment(self, row: int, col: int, arm: ComplexArray, sign: float) -> None:
        r"""``sign * arm x F`` for the complex unknown F at ``col``, in the scalar equation at
        ``row``: :math:`\operatorname{Im}(\bar a F) = a_y F_x - a_x F_y`."""
        self.A[:, row, col] += -sign * arm.imag
        self.A[:, row, col + 1] += sign * arm.real

    def set_rhs(self, row: int, z: ComplexArray) -> None:
        """Right-hand side of the complex equation at ``row``."""
        self.rhs[:, row] = z.real
        self.rhs[:, row + 1] = z.imag


def articulated_newton_euler(
    layout: Engine,
    theta: ArrayLike,
    small_end_share: float = 1.0 / 3.0,
    cg_fraction: float | None = 0.3,
    gas_force: ArrayLike | None = None,
) -> ArticulatedSolution:
    r"""Newton–Euler equations of every master with its link rods and pistons, solved.

    Parameters
    ----------
    layout : Engine
        An engine with link rods, constant crank speed.
    theta : array_like
        Crank angles [rad].
    small_end_share : float
        Share of each cylinder's reciprocating mass that is its rod's small-end share (the
        rest is the piston).  The master rod is then a rigid body with its centre of
        gravity ``cg_fraction`` of its length from the big end; a link rod one whose
        link-pin share is the cylinder's link-pin mass (its centre of gravity follows);
        each with the inertia that gives its ``conrod_inertia_correction``.  What is left
        of a cylinder's rotating mass turns with the crank pin.  Nothing may depend on
        these choices (static equivalence).
    cg_fraction : float or None
        Centre of gravity of each master rod from its big end, as a fraction of its length;
        None: where the rod's big-end share (its rotating mass less the crank's share of
        ``crank_unbalance``) puts it, so that ``pin_force`` is the real rod's (what
        :func:`balance.core.bearings.big_end_forces` computes).
    gas_force : array_like, optional
        Gas force on each piston towards the crank [N], shape (angles, cylinders); the same
        force pushes the head outwards.

    Returns
    -------
    ArticulatedSolution

    Notes
    -----
    Per group (master m, links j) and crank angle, with forces as complex numbers
    :math:`y + ix`, :math:`\times` the moment :math:`\operatorname{Im}(\bar a b)` in the
    direction of rotation, :math:`n = ie^{i\psi}` a bore's normal and :math:`b = e^{i\psi}`
    its axis:

    .. math::

        m_p a_{P_m} &= F_A + N_m n_m - G_m b_m &\text{(master piston)}\\
        M_m a_{G_m} &= -F_A + F_C - \textstyle\sum_j F_{B,j} &\text{(master rod)}\\
        I_m\ddot\vartheta_m &= (P_m - G_m)\times(-F_A) + (C - G_m)\times F_C
            + \textstyle\sum_j (L_j - G_m)\times(-F_{B,j}) \\
        M_j a_{G_j} &= F_{B,j} - F_{D,j}, \quad
        I_j\ddot\vartheta_j = (L_j - G_j)\times F_{B,j} + (P_j - G_j)\times(-F_{D,j})
            &\text{(link rod)}\\
        m_{p,j} a_{P_j} &= F_{D,j} + N_j n_j - G_j b_j &\text{(link piston)}

    :math:`5(1 + n_{links})` real equations for as many unknowns (:math:`F_A, N_m, F_C` and
    per link :math:`F_{B,j}, F_{D,j}, N_j`), solved at every angle.  The block receives
    :math:`-N n` at each piston pin, :math:`G b` at each head (moment :math:`-eG`) and,
    through the mains, :math:`-F_C` plus the centrifugal force of the masses left at the
    crank pin; the crankshaft the torque :math:`C \times (-F_C)`.
    """
    assert layout.links is not None
    th = np.asarray(theta, dtype=np.float64)
    n_t = th.size
    w2 = float(speed_squared(layout.speed))
    gas = (
        np.zeros((n_t, layout.n_cylinders))
        if gas_force is None
        else np.broadcast_to(np.asarray(gas_force, dtype=np.float64), (n_t, layout.n_cylinders))
    )
    m_pin = _pin_shares(layout)
    crank_share = np.asarray(layout.rotating_mass - _pin_shares(layout, every=True))
    groups = _articulated_kinematics(layout, th)
    wall = np.zeros((layout.n_cylinders, n_t))
    rod_force = np.zeros((layout.n_cylinders, n_t))
    pin_force = np.zeros((len(groups), n_t), dtype=np.complex128)
    block = np.zeros(n_t, dtype=np.complex128)
    block_moment = np.zeros(n_t, dtype=np.complex128)
    roll = np.zeros(n_t)
    crank_torque = np.zeros(n_t)
    for gi, g in enumerate(groups):
        m = g.master
        js = g.links
        n_l = js.size
        size = 5 * (1 + n_l)
        A = np.zeros((n_t, size, size))
        rhs = np.zeros((n_t, size))
        # unknown columns: F_A (y, x) 0-1, N_m 2, F_C (y, x) 3-4; link i: F_B 5+5i..,
        # F_D 7+5i.., N 9+5i
        small = small_end_share * layout.reciprocating_mass[m]
        m_p = layout.reciprocating_mass[m] - small
        length = layout.conrod_length[m]
        if cg_fraction is None:  # the rod's big-end share: its rotating mass less the crank's
            big = layout.rotating_mass[m] - crank_share[m]
            cg = length * small / (small + big)
        else:
            cg = cg_fraction * length
        M_m = small * length / cg
        I_m = layout.conrod_inertia_correction[m] + M_m * cg * (length - cg)
        rod = g.master_rod
        direction = np.exp(1j * rod.angle)
        G_m = g.crank + cg * direction
        a_G = w2 * (-g.crank + cg * direction * (1j * rod.d2angle - rod.dangle**2))
        a_P = w2 * rod.d2piston
        P_m = rod.piston
        n_m = 1j * np.exp(1j * layout.bank[m])
        b_m = np.exp(1j * layout.bank[m])

        system = _LinearSystem(A, rhs)
        put, put_real, put_moment, set_rhs = (
            system.put,
            system.put_real,
            system.put_moment,
            system.set_rhs,
        )

        # master piston (rows 0, 1)
        put(0, 0, 1.0)
        put_real(0, 2, n_m)
        set_rhs(0, m_p * a_P + gas[:, m] * b_m)
        # master rod force (rows 2, 3) and moment (row 4)
        put(2, 0, -1.0)
        put(2, 3, 1.0)
        set_rhs(2, M_m * a_G)
        put_moment(4, 0, P_m - G_m, -1.0)
        put_moment(4, 3, g.crank - G_m, 1.0)
        rhs[:, 4] = I_m * w2 * rod.d2angle
        link_rods = g.link_rods
        for i, j in enumerate(js.tolist()):
            base = 5 + 5 * i
            put(2, base, -1.0)
            put_moment(4, base, g.link_pin[i] - G_m, -1.0)
            small_j = small_end_share * layout.reciprocating_mass[j]
            m_pj = layout.reciprocating_mass[j] - small_j
            M_j = small_j + m_pin[j]
            l_j = layout.conrod_length[j]
            c_j = l_j * small_j / M_j
            I_j = layout.conrod_inertia_correction[j] + M_j * c_j * (l_j - c_j)
            dir_j = np.exp(1j * link_rods.angle[i])
            G_j = g.link_pin[i] + c_j * dir_j
            a_Gj = w2 * (
                g.d2link_pin[i]
                + c_j * dir_j * (1j * link_rods.d2angle[i] - link_rods.dangle[i] ** 2)
            )
            # link rod force (base, base+1), moment (base+2)
            put(base, base, 1.0)
            put(base, base + 2, -1.0)
            set_rhs(base, M_j * a_Gj)
            put_moment(base + 2, base, g.link_pin[i] - G_j, 1.0)
            put_moment(base + 2, base + 2, link_rods.piston[i] - G_j, -1.0)
            rhs[:, base + 2] = I_j * w2 * link_rods.d2angle[i]
            # link piston (base+3, base+4)
            n_j = 1j * np.exp(1j * layout.bank[j])
            b_j = np.exp(1j * layout.bank[j])
            put(base + 3, base + 2, 1.0)
            put_real(base + 3, base + 4, n_j)
            set_rhs(base + 3, m_pj * w2 * link_rods.d2piston[i] + gas[:, j] * b_j)
        x = np.linalg.solve(A, rhs[..., None])[..., 0]
        f_c = x[:, 3] + 1j * x[:, 4]
        pin_force[gi] = -f_c
        wall[m] = x[:, 2]
        # the rod pushes its piston with F; along the rod (piston to big end) the piston
        # pushes back with -F: compression is Re(F e^{-i angle})
        rod_force[m] = np.real((x[:, 0] + 1j * x[:, 1]) * np.exp(-1j * rod.angle))
        arm_m = layout.z[m] - layout.reference_z
        # mass left at the crank pin: the master's rotating mass less its rod's big-end
        # share, and each link cylinder's crank share
        left = layout.rotating_mass[m] - (M_m - small)
        forces = -x[:, 2] * n_m + gas[:, m] * b_m
        torque = np.imag(np.conj(P_m) * (-x[:, 2] * n_m)) - layout.offset[m] * gas[:, m]
        for i, j in enumerate(js.tolist()):
            base = 5 + 5 * i
            wall[j] = x[:, base + 4]
            f_d = x[:, base + 2] + 1j * x[:, base + 3]
            rod_force[j] = np.real(f_d * np.exp(-1j * link_rods.angle[i]))
            n_j = 1j * np.exp(1j * layout.bank[j])
            b_j = np.exp(1j * layout.bank[j])
            left = left + layout.rotating_mass[j] - m_pin[j]
            forces = forces - x[:, base + 4] * n_j + gas[:, j] * b_j
            torque = torque + np.imag(np.conj(link_rods.piston[i]) * (-x[:, base + 4] * n_j))
            torque = torque - layout.offset[j] * gas[:, j]
        forces = forces - f_c + left * w2 * g.crank
        block += forces
        block_moment += arm_m * forces
        roll += torque
        crank_torque += np.imag(np.conj(g.crank) * (-f_c))
    return ArticulatedSolution(
        masters=layout.links.masters,
        pin_force=pin_force,
        wall=wall,
        block_force=block,
        block_moment=block_moment,
        roll=roll,
        crank_torque=crank_torque,
        rod_force=rod_force,
    )
