"""The engine on its mounts (balance.core.mounts): modes, loads, response, torque-roll axis.

Closed forms: the decoupled modes of a rigid body on four identical mounts placed
symmetrically about its CG (Harris' Shock and Vibration Handbook, 5th ed., 2002, ch. 3):
each mode moves one coordinate, at :math:`\\sqrt{\\sum k / m}` for a translation and
:math:`\\sqrt{\\sum k d^2 / I}` for a rotation.  Brute force: a fixed-step RK4 integration of
the same six equations of motion, with the loads built from the CONTRACT's definitions
(not from :func:`crank_loads`), to steady state.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from balance.core import mounts as mt

# ---------------------------------------------------------------------------------------
# helpers


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix (Rodrigues) turning vectors by ``angle`` about ``axis``."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def matrices(system: mt.MountSystem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return (
        mt.mass_matrix(system.mass, system.inertia),
        mt.stiffness_matrix(system),
        mt.damping_matrix(system),
    )


def symmetric_system(cg: tuple[float, float, float] = (0.01, 0.06, 0.14)) -> mt.MountSystem:
    """Four identical mounts at (±dx, 0, ±dz) from the CG; diagonal inertia."""
    dx, dz = 0.22, 0.18
    k = (2.5e5, 4.0e5, 1.5e5)
    c = np.asarray(cg)
    points = tuple(
        mt.MountPoint(position=c + np.array([sx * dx, 0.0, sz * dz]), stiffness=k)
        for sx in (-1, 1)
        for sz in (-1, 1)
    )
    return mt.MountSystem(mass=160.0, cg=c, inertia=mt.inertia_tensor(7.5, 9.0, 4.0), points=points)


def general_system() -> mt.MountSystem:
    """Four different, tilted, damped mounts; an inertia tensor with products."""
    inertia = mt.inertia_tensor(7.5, 9.0, 4.0, xy=0.4, xz=-0.8, yz=0.3)
    points = (
        mt.MountPoint(
            position=(-0.22, -0.12, 0.0),
            stiffness=(2.5e5, 4.0e5, 1.5e5),
            damping=(0.02 * 2.5e5, 0.015 * 4.0e5, 0.03 * 1.5e5),
            axes=rotation((1, 0.3, 0.2), 0.5),
        ),
        mt.MountPoint(
            position=(0.25, -0.10, 0.02),
            stiffness=(2.0e5, 3.5e5, 1.8e5),
            damping=(0.025 * 2.0e5, 0.02 * 3.5e5, 0.02 * 1.8e5),
            axes=rotation((0, 0, 1), -0.6),
        ),
        mt.MountPoint(
            position=(-0.05, 0.15, 0.34),
            stiffness=(1.2e5, 2.2e5, 1.0e5),
            damping=(0.03 * 1.2e5, 0.02 * 2.2e5, 0.025 * 1.0e5),
        ),
        mt.MountPoint(
            position=(0.08, -0.16, 0.30),
            stiffness=(1.5e5, 1.5e5, 1.5e5),
            damping=(0.02 * 1.5e5, 0.02 * 1.5e5, 0.02 * 1.5e5),
            axes=rotation((0.2, 1, -0.4), 1.1),
        ),
    )
    return mt.MountSystem(mass=160.0, cg=(0.01, 0.06, 0.14), inertia=inertia, points=points)


# ---------------------------------------------------------------------------------------
# mount matrices


@given(
    st.tuples(*(st.floats(-1, 1) for _ in range(3))).filter(lambda v: np.linalg.norm(v) > 1e-3),
    st.floats(-math.pi, math.pi),
    st.floats(1e3, 1e7),
)
def test_rotating_an_isotropic_mount_changes_nothing(axis, angle, k):
    turned = mt.mount_matrices(rotation(np.array(axis), angle), (k, k, k))
    np.testing.assert_allclose(turned, k * np.eye(3), rtol=0, atol=1e-12 * k)


def test_mount_axes_are_rows_in_the_engine_frame():
    # axis 1 along engine +y, axis 2 along engine -x: stiffness k1 acts along y
    axes = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    k = mt.mount_matrices(axes, (1.0, 2.0, 3.0))
    np.testing.assert_allclose(k, np.diag([2.0, 1.0, 3.0]), atol=1e-15)


def test_stiffness_matrix_is_symmetric_and_holds_forces():
    system = general_system()
    _, k, c = matrices(system)
    np.testing.assert_allclose(k, k.T, rtol=0, atol=1e-9 * np.abs(k).max())
    np.testing.assert_allclose(c, c.T, rtol=0, atol=1e-9 * np.abs(c).max())
    assert np.all(np.linalg.eigvalsh(k) > 0)


# ---------------------------------------------------------------------------------------
# modes


def test_symmetric_mounts_give_closed_form_modes():
    system = symmetric_system()
    modes = mt.normal_modes(*matrices(system)[:2])
    kx, ky, kz = 4 * 2.5e5, 4 * 4.0e5, 4 * 1.5e5  # Σk along x, y, z
    dx, dz = 0.22, 0.18
    m = 160.0
    ixx, iyy, izz = 7.5, 9.0, 4.0
    expected = {
        "x": math.sqrt(kx / m),  # lateral
        "y": math.sqrt(ky / m),  # bounce
        "z": math.sqrt(kz / m),  # fore-aft
        "rx": math.sqrt(ky * dz**2 / ixx),  # pitch: Σ k_y dz²
        "ry": math.sqrt((kx * dz**2 + kz * dx**2) / iyy),  # yaw
        "rz": math.sqrt(ky * dx**2 / izz),  # roll: Σ k_y dx²
    }
    freqs = sorted(w / (2 * math.pi) for w in expected.values())
    assert len({round(f, 6) for f in freqs}) == 6  # distinct, so each mode is one coordinate
    np.testing.assert_allclose(modes.frequency, freqs, rtol=1e-12)
    for j in range(6):
        share = modes.energy_share[j]
        coordinate = int(np.argmax(share))
        np.testing.assert_allclose(share, np.eye(6)[coordinate], atol=1e-12)
        name = mt.COORDINATES[coordinate]
        assert modes.frequency[j] == pytest.approx(expected[name] / (2 * math.pi), rel=1e-12)
        assert modes.shapes[coordinate, j] > 0


def test_energy_shares_sum_to_one_and_shapes_are_mass_normalised():
    system = general_system()
    m, k, _ = matrices(system)
    modes = mt.normal_modes(m, k)
    np.testing.assert_allclose(modes.energy_share.sum(axis=-1), 1.0, atol=1e-12)
    phi = modes.shapes
    np.testing.assert_allclose(phi.T @ m @ phi, np.eye(6), atol=1e-10)
    omega2 = (2 * math.pi * modes.frequency) ** 2
    np.testing.assert_allclose(phi.T @ k @ phi, np.diag(omega2), atol=1e-8 * omega2.max())
    assert np.all(np.diff(modes.frequency) >= 0)


def test_modes_broadcast_over_leading_axes():
    system = general_system()
    m, k, _ = matrices(system)
    one = mt.normal_modes(m, k)
    many = mt.normal_modes(np.stack([m, m]), np.stack([k, 2 * k]))
    np.testing.assert_allclose(many.frequency[0], one.frequency, rtol=1e-12)
    np.testing.assert_allclose(many.frequency[1], math.sqrt(2) * one.frequency, rtol=1e-12)


unit_vectors = st.tuples(*(st.floats(-1, 1) for _ in range(3))).filter(
    lambda v: np.linalg.norm(v) > 1e-2
)


@given(unit_vectors, st.floats(-math.pi, math.pi))
def test_modes_do_not_depend_on_the_orientation_of_the_coordinates(axis, angle):
    """Turning the whole system (mounts, their axes, inertia) about the CG changes no
    frequency, nor the split of each mode's energy between translation and rotation."""
    system = general_system()
    q = rotation(np.array(axis), angle)
    turned = mt.MountSystem(
        mass=system.mass,
        cg=system.cg,
        inertia=q @ system.inertia @ q.T,
        points=tuple(
            mt.MountPoint(
                position=system.cg + q @ (p.position - system.cg),
                stiffness=p.stiffness,
                damping=p.damping,
                axes=p.axes @ q.T,
            )
            for p in system.points
        ),
    )
    before = mt.normal_modes(*matrices(system)[:2])
    after = mt.normal_modes(*matrices(turned)[:2])
    np.testing.assert_allclose(after.frequency, before.frequency, rtol=1e-10)
    translation = before.energy_share[:, :3].sum(axis=-1)
    np.testing.assert_allclose(after.energy_share[:, :3].sum(axis=-1), translation, atol=1e-9)


@given(st.permutations(range(4)))
def test_renumbering_the_mounts_changes_nothing(order):
    system = general_system()
    renumbered = mt.MountSystem(
        mass=system.mass,
        cg=system.cg,
        inertia=system.inertia,
        points=tuple(system.points[i] for i in order),
    )
    k0, k1 = mt.stiffness_matrix(system), mt.stiffness_matrix(renumbered)
    np.testing.assert_allclose(k1, k0, rtol=0, atol=1e-9 * np.abs(k0).max())
    f0 = mt.normal_modes(*matrices(system)[:2]).frequency
    f1 = mt.normal_modes(*matrices(renumbered)[:2]).frequency
    np.testing.assert_allclose(f1, f0, rtol=1e-12)


# ---------------------------------------------------------------------------------------
# loads: signs and frames


def real_load(load: np.ndarray, k: float, theta: float) -> np.ndarray:
    return np.real(load * np.exp(1j * k * theta))


def test_forward_force_turns_with_the_crank_from_plus_y_to_plus_x():
    cg = np.zeros(3)
    load = mt.crank_loads(0.0, cg, force_forward=1.0)
    np.testing.assert_allclose(real_load(load, 1, 0.0), [0, 1, 0, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(real_load(load, 1, math.pi / 2), [1, 0, 0, 0, 0, 0], atol=1e-15)
    back = mt.crank_loads(0.0, cg, force_backward=1.0)
    np.testing.assert_allclose(real_load(back, 1, math.pi / 2), [-1, 0, 0, 0, 0, 0], atol=1e-15)
    # equal phasors: a line along y (an inline engine's reciprocating force)
    line = mt.crank_loads(0.0, cg, force_forward=0.5, force_backward=0.5)
    for theta in np.linspace(0, 2 * math.pi, 7):
        assert real_load(line, 1, theta)[0] == pytest.approx(0.0, abs=1e-15)


def test_moment_phasor_is_the_force_moved_along_the_crank_axis():
    """A force P acting at z_ref + d equals P at z_ref with the moment phasor d·P."""
    cg = np.array([0.02, 0.07, 0.11])
    p_f, p_b, d = 3.0 - 2.0j, -1.0 + 0.5j, 0.09
    moved = mt.crank_loads(0.2 + d, cg, force_forward=p_f, force_backward=p_b)
    with_moment = mt.crank_loads(
        0.2,
        cg,
        force_forward=p_f,
        force_backward=p_b,
        moment_forward=d * p_f,
        moment_backward=d * p_b,
    )
    np.testing.assert_allclose(with_moment, moved, atol=1e-14)


def test_positive_roll_turns_the_block_with_the_crank():
    """The crank turns from +y towards +x, a negative rotation about +z: a positive roll
    torque (in the direction of rotation) is -z, and statically moves the top of the
    engine towards +x."""
    system = symmetric_system(cg=(0.0, 0.0, 0.0))
    m, k, c = matrices(system)
    load = mt.crank_loads(0.0, system.cg, roll=100.0)
    np.testing.assert_allclose(load, [0, 0, 0, 0, 0, -100.0], atol=1e-15)
    static = mt.harmonic_response(m, k, c, 0.0, load).real
    assert static[5] < 0
    top = mt.point_motion(np.array([[0.0, 0.3, 0.0]]), static)[0]
    assert top[0] > 0


def test_force_on_the_crank_axis_has_a_moment_about_the_cg():
    cg = np.array([0.0, 0.1, 0.0])  # CG 0.1 m above the crank axis
    load = mt.crank_loads(0.0, cg, force_forward=1.0)
    f = real_load(load, 1, math.pi / 2)  # force +x, applied 0.1 m below the CG
    np.testing.assert_allclose(f, [1, 0, 0, 0, 0, 0.1], atol=1e-15)  # (-0.1 ŷ) × x̂ = +0.1 ẑ


# ---------------------------------------------------------------------------------------
# response


def test_mount_forces_balance_the_loads():
    """Dynamic equilibrium: f = -Ω² M q + Σ T_iᵀ F_i (and Σ F_i = f at Ω = 0)."""
    system = general_system()
    m, k, c = matrices(system)
    omega = np.array([0.0, 40.0, 150.0])
    load = mt.crank_loads(
        0.15,
        system.cg,
        force_forward=200.0,
        force_backward=80 - 30j,
        moment_forward=5 + 1j,
        roll=30.0,
    )
    q = mt.harmonic_response(m, k, c, omega, load)
    forces = mt.mount_forces(system, q, omega)
    t = mt.point_transfer(system.offsets)
    reaction = np.einsum("nij,...ni->...j", t, forces)
    inertia = -(omega[:, None] ** 2) * (q @ m.T)
    np.testing.assert_allclose(inertia + reaction, np.broadcast_to(load, q.shape), atol=1e-9)
    np.testing.assert_allclose(forces[0].sum(axis=0), load[:3], atol=1e-9)


def test_batched_solve_equals_one_solve_per_frequency():
    system = general_system()
    m, k, c = matrices(system)
    speeds = np.linspace(80, 800, 5)
    orders = np.array([1.0, 2.0, 0.5])
    omega = mt.order_frequencies(speeds, orders)
    rng = np.random.default_rng(5)
    phasor = rng.normal(size=(5, 3)) + 1j * rng.normal(size=(5, 3))
    load = mt.crank_loads(0.1, system.cg, force_forward=phasor, roll=2 * phasor)
    batched = mt.harmonic_response(m, k, c, omega, load)
    assert batched.shape == (5, 3, 6)
    for s in range(5):
        for j in range(3):
            w = omega[s, j]
            one = np.linalg.solve(k - w**2 * m + 1j * w * c, load[s, j])
            np.testing.assert_allclose(batched[s, j], one, rtol=1e-12)


def _time_domain_loads(
    t: np.ndarray,
    speed: float,
    order: float,
    z_ref: float,
    cg: np.ndarray,
    p_f: complex,
    p_b: complex,
    q_f: complex,
    q_b: complex,
    roll: complex,
) -> np.ndarray:
    """Real loads over time straight from CONTRACT §1–2 (independent of crank_loads)."""
    theta = speed * t
    turn = np.exp(1j * order * theta)
    force_c = p_f * turn + p_b / turn  # y + i x
    moment_c = q_f * turn + q_b / turn  # Σ dz F, drawn like a force
    fx, fy = force_c.imag, force_c.real
    mx, my = -moment_c.real, moment_c.imag  # pitch -Σ dz F_y, yaw Σ dz F_x
    torque = np.real(roll * turn)  # on the block, positive with the crank: -z
    force = np.stack([fx, fy, np.zeros_like(fx)], axis=-1)
    lever = np.array([0.0, 0.0, z_ref]) - cg
    moment = np.stack([mx, my, -torque], axis=-1) + np.cross(lever, force)
    return np.concatenate([force, moment], axis=-1)


def test_frequency_domain_response_matches_time_integration():
    system = general_system()
    m, k, c = matrices(system)
    speed, order = 2 * math.pi * 6.5, 2.0  # 390 rpm, second order: 13 Hz
    omega = speed * order
    z_ref = 0.17
    args = dict(p_f=350 + 120j, p_b=-90 + 260j, q_f=12 - 30j, q_b=8 + 5j, roll=-45 + 70j)

    # RK4 on y = (q, v): y' = A y + g(t)
    minv = np.linalg.inv(m)
    a = np.zeros((12, 12))
    a[:6, 6:] = np.eye(6)
    a[6:, :6] = -minv @ k
    a[6:, 6:] = -minv @ c
    period = 2 * math.pi / omega
    per_period = 400
    h = period / per_period
    settle, measure = 45, 10  # periods (3.5 s, then 0.77 s)
    steps = (settle + measure) * per_period
    times = h * np.arange(2 * steps + 1) / 2
    g = np.zeros((times.size, 12))
    g[:, 6:] = _time_domain_loads(times, speed, order, z_ref, system.cg, **args) @ minv.T
    y = np.zeros(12)
    history = np.empty((measure * per_period, 6))
    start = settle * per_period
    for n in range(steps):
        if n >= start:
            history[n - start] = y[:6]
        k1 = a @ y + g[2 * n]
        k2 = a @ (y + 0.5 * h * k1) + g[2 * n + 1]
        k3 = a @ (y + 0.5 * h * k2) + g[2 * n + 1]
        k4 = a @ (y + h * k3) + g[2 * n + 2]
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    tm = times[0 : 2 * steps : 2][start:]
    # complex amplitude by projection over whole periods: q = Re(X e^{iΩt})
    x_time = 2 * np.mean(history * np.exp(-1j * omega * tm)[:, None], axis=0)

    load = mt.crank_loads(
        z_ref,
        system.cg,
        force_forward=args["p_f"],
        force_backward=args["p_b"],
        moment_forward=args["q_f"],
        moment_backward=args["q_b"],
        roll=args["roll"],
    )
    x_freq = mt.harmonic_response(m, k, c, omega, load)
    # the crank angle is theta = speed * t, so e^{ikθ} = e^{iΩt}: the same amplitudes
    translation = np.abs(x_freq[:3]).max()
    rotation_ = np.abs(x_freq[3:]).max()
    scale = np.r_[np.full(3, translation), np.full(3, rotation_)]
    assert np.all(np.abs(x_freq) > 1e-3 * scale)  # every coordinate moves
    np.testing.assert_allclose(np.abs(x_time), np.abs(x_freq), rtol=1e-6)
    assert np.all(np.abs(x_time - x_freq) <= 1e-6 * np.abs(x_freq))

    # mount forces from the time-domain motion through the mounts' springs and dampers
    f_freq = mt.mount_forces(system, x_freq, omega)
    d_time = mt.point_motion(system.offsets, x_time)
    f_time = np.einsum(
        "nij,nj->ni", system.mount_stiffness + 1j * omega * system.mount_damping, d_time
    )
    np.testing.assert_allclose(np.abs(f_time), np.abs(f_freq), rtol=1e-6)


# ---------------------------------------------------------------------------------------
# torque-roll axis


TILTED = mt.inertia_tensor(7.5, 9.0, 4.0, xy=0.5, xz=-1.5, yz=0.9)  # TRA 13° off z


def test_torque_roll_axis_is_the_free_body_rotation_under_a_roll_torque():
    a = mt.torque_roll_axis(TILTED)
    assert np.linalg.norm(a) == pytest.approx(1.0)
    moment = TILTED @ a
    np.testing.assert_allclose(np.cross(moment, [0, 0, 1]), 0, atol=1e-14)
    assert a[2] > 0
    assert a[2] < math.cos(math.radians(10))  # tilted: the crank axis is not principal
    np.testing.assert_allclose(mt.torque_roll_axis(np.diag([1.0, 2.0, 3.0])), [0, 0, 1])


def tra_mounted_system() -> mt.MountSystem:
    """Mounts centred on the torque-roll axis a = J⁻¹e_z / |J⁻¹e_z| (through the CG).

    The mounts' rotational stiffness about the CG is S = Σ k (|r|² I − r rᵀ) for
    isotropic mounts at r from the CG.  Take S = λJ + β(I − a aᵀ): then S a = λ J a ∥ e_z,
    so turning about the TRA needs only a torque about the crank axis, while S is not
    proportional to J (the other rotational modes differ from the roll mode).  S is
    realised by pairs of isotropic mounts at ±s_i u_i, where u_i, p_i are the eigenvectors
    and eigenvalues of P = tr(S)/2 I − S (positive definite) and 2 k_i s_i² = p_i; pairs
    put the mounts' centroid at the CG, so translation and rotation are uncoupled.
    """
    cg = np.array([0.01, 0.06, 0.14])
    a = mt.torque_roll_axis(TILTED)
    s = 2.0e4 * TILTED + 3.0e4 * (np.eye(3) - np.outer(a, a))
    p, u = np.linalg.eigh(np.trace(s) / 2 * np.eye(3) - s)
    assert np.all(p > 0)
    distances = np.array([0.20, 0.16, 0.24])
    stiffness = p / (2 * distances**2)
    points = []
    for i in range(3):
        for sign in (-1, 1):
            kk = stiffness[i]
            points.append(
                mt.MountPoint(
                    position=cg + sign * distances[i] * u[:, i],
                    stiffness=(kk, kk, kk),
                    damping=(0.01 * kk,) * 3,
                    axes=rotation((1, 2, 3), 0.4 * i),
                )
            )
    return mt.MountSystem(mass=160.0, cg=cg, inertia=TILTED, points=tuple(points))


def test_pure_roll_torque_on_mounts_centred_on_the_tra_turns_the_engine_about_it():
    system = tra_mounted_system()
    m, k, c = matrices(system)
    a = mt.torque_roll_axis(system.inertia)
    modes = mt.normal_modes(m, k)
    turning = modes.energy_share[:, 3:].sum(axis=-1) > 0.5
    rotational, translational = modes.frequency[turning], modes.frequency[~turning]
    assert rotational.size == 3 and np.all(np.diff(rotational) > 0.05)  # distinct modes
    assert np.abs(rotational[:, None] - translational).min() > 0.05
    roll_mode = 2 * math.pi * modes.frequency[np.argmax(modes.energy_share[:, 5])]
    omega = np.array([0.0, 20.0, roll_mode, 300.0])
    load = mt.crank_loads(system.cg[2], system.cg, roll=np.full(omega.shape, 50.0 + 20j))
    q = mt.harmonic_response(m, k, c, omega, load)
    for row in q:
        spin = row[3:]
        size = np.linalg.norm(spin)
        assert size > 0
        np.testing.assert_allclose(row[:3], 0, atol=1e-12 * size)  # the CG does not move
        np.testing.assert_allclose(np.cross(spin, a), 0, atol=1e-12 * size)  # about a
    # the TRA is a mode shape, and the other rotational modes are not about it
    along = np.abs(modes.shapes[3:].T @ a) / np.linalg.norm(modes.shapes, axis=0)
    assert along.max() == pytest.approx(1.0, abs=1e-9)
    assert np.sort(along)[-2] < 0.9
    # a roll torque on a system not centred on the TRA also moves the CG
    other = general_system()
    mo, ko, co = matrices(other)
    moved = mt.harmonic_response(mo, ko, co, 20.0, mt.crank_loads(0.0, other.cg, roll=50.0))
    assert np.linalg.norm(moved[:3]) > 1e-3 * np.linalg.norm(moved[3:])


def test_distances_from_the_torque_roll_axis():
    system = symmetric_system(cg=(0.0, 0.0, 0.0))
    a = mt.torque_roll_axis(system.inertia)
    np.testing.assert_allclose(a, [0, 0, 1])
    np.testing.assert_allclose(mt.axis_distances(system.positions, system.cg, a), 0.22)
    offsets = mt.elastic_axis_offsets(system, system.cg, a)
    # axis 1 (x) of each mount passes through the TRA; axis 2 (y) misses it by dx;
    # axis 3 (z) is parallel to it, dx away
    np.testing.assert_allclose(offsets[:, 0], 0.0, atol=1e-15)
    np.testing.assert_allclose(offsets[:, 1], 0.22)
    np.testing.assert_allclose(offsets[:, 2], 0.22)
