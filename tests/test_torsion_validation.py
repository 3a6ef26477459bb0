"""The torsional model against published results and independent computations.

Each test names its source.  The model is that of docs/torsion.md,
``M q'' + C q' + (K + i eta K_s) q = T``, solved exactly per order
(:mod:`balance.core.torsion_response`); the inertia of the moving parts and the excitation
come from :mod:`balance.core.torsion_excitation`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from torsion_trains import analysed, chain, inline4_train, with_train

from balance.core import torsion_excitation as tx
from balance.core import torsion_response as td
from balance.core.torque import compute_torque
from balance.io.layout_file import layout_from_dict, load_layout

#: "Ground": an inertia this many times the main one stands still to about its inverse.
GROUND = 1e12


def _absorber(mu: float, f: float, zeta: float):
    """Den Hartog's main system with an absorber, as a torsional chain: the main inertia
    J = 1 on a shaft k = 1 to the ground (a very large inertia), and a ring mu J on a
    coupling tuned to f times the main system's frequency, damping zeta = c / (2 m Omega_n)
    (m the ring's inertia)."""
    j_main, k_main = 1.0, 1.0
    omega_n = math.sqrt(k_main / j_main)
    j_ring = mu * j_main
    k_ring = j_ring * (f * omega_n) ** 2
    c_ring = 2.0 * zeta * j_ring * omega_n
    return td.assemble(
        [j_main, GROUND * j_main],
        [k_main],
        [0.0],
        [0.0, 0.0],
        [0],
        [j_ring],
        [k_ring],
        [c_ring],
    )


def _main_amplitude(matrices: td.TrainMatrices, g) -> np.ndarray:
    """|x_1| / x_st of the main inertia for a unit torque on it at g = w / Omega_n."""
    g = np.asarray(g, dtype=float)
    force = np.zeros((*g.shape, matrices.size), dtype=complex)
    force[..., 0] = 1.0
    q = td.harmonic_response(matrices, g, force)
    return np.abs(q[..., 0] - q[..., 1])  # relative to the ground, per x_st = T / k = 1


# --------------------------------------------------------------------------- Den Hartog


@pytest.mark.parametrize("mu", [0.05, 0.1, 0.25])
@pytest.mark.parametrize("f", [0.8, 1.0])
def test_tuned_damper_fixed_points(mu, f):
    """Den Hartog, *Mechanical Vibrations*, 4th ed., McGraw-Hill 1956, §3.3 (the damped
    vibration absorber): every response curve of the main mass, whatever the absorber's
    damping, passes through two fixed points, at the roots g^2 of

        g^4 - 2 g^2 (1 + f^2 + mu f^2) / (2 + mu) + 2 f^2 / (2 + mu) = 0,

    at the height of the undamped-coupled (c = infinity) curve, x1 / x_st =
    1 / |1 - (1 + mu) g^2|."""
    a = 2.0 * (1.0 + f * f + mu * f * f) / (2.0 + mu)
    b = 2.0 * f * f / (2.0 + mu)
    roots = np.sqrt(np.array([a / 2 - math.sqrt(a * a / 4 - b), a / 2 + math.sqrt(a * a / 4 - b)]))
    expected = 1.0 / np.abs(1.0 - (1.0 + mu) * roots**2)
    for zeta in (0.02, 0.1, 0.3, 1.0, 5.0):
        found = _main_amplitude(_absorber(mu, f, zeta), roots)
        np.testing.assert_allclose(found, expected, rtol=1e-9)


@pytest.mark.parametrize("mu", [0.05, 0.1, 0.25])
def test_tuned_damper_equal_peaks(mu):
    """Den Hartog 1956, §3.3: tuned to f = 1 / (1 + mu), both fixed points lie at
    x1 / x_st = sqrt(1 + 2 / mu); with the damping zeta^2 = 3 mu / (8 (1 + mu)^3)
    (c_c = 2 m Omega_n, m the absorber's mass) the curve is nearly flat there: its peak is
    within 1 % above sqrt(1 + 2 / mu) (Den Hartog's optimum is approximate; the exact
    equal-peak optimum lies slightly off)."""
    f = 1.0 / (1.0 + mu)
    height = math.sqrt(1.0 + 2.0 / mu)
    a = 2.0 * (1.0 + f * f + mu * f * f) / (2.0 + mu)
    b = 2.0 * f * f / (2.0 + mu)
    roots = np.sqrt([a / 2 - math.sqrt(a * a / 4 - b), a / 2 + math.sqrt(a * a / 4 - b)])
    for zeta in (0.05, 0.5):
        np.testing.assert_allclose(
            _main_amplitude(_absorber(mu, f, zeta), roots), height, rtol=1e-9
        )
    zeta = math.sqrt(3.0 * mu / (8.0 * (1.0 + mu) ** 3))
    g = np.linspace(0.5, 1.5, 20001)
    peak = float(np.max(_main_amplitude(_absorber(mu, f, zeta), g)))
    assert height <= peak <= 1.01 * height


@pytest.mark.parametrize("mu", [0.05, 0.2, 1.0])
def test_untuned_viscous_damper_fixed_point(mu):
    """Den Hartog 1956, §3.4 (the untuned viscous, or Lanchester, damper): the ring on a
    viscous coupling only; every curve passes through one fixed point at
    g^2 = 2 / (2 + mu), of height x1 / x_st = 1 + 2 / mu; with the optimum damping
    (c / c_c)^2 = 1 / (2 (1 + mu)(2 + mu)), c_c = 2 m Omega_n, the curve is horizontal there,
    so that the fixed point is the peak."""
    g_p = math.sqrt(2.0 / (2.0 + mu))
    height = 1.0 + 2.0 / mu
    for zeta in (0.01, 0.1, 0.5, 3.0):
        found = _main_amplitude(_absorber(mu, 0.0, zeta), [g_p])
        np.testing.assert_allclose(found, height, rtol=1e-9)
    zeta = 1.0 / math.sqrt(2.0 * (1.0 + mu) * (2.0 + mu))
    g = np.linspace(0.2, 2.0, 180001)
    curve = _main_amplitude(_absorber(mu, 0.0, zeta), g)
    np.testing.assert_allclose(float(curve.max()), height, rtol=1e-6)
    assert abs(float(g[np.argmax(curve)]) - g_p) < 2e-3


def test_three_rotor_frequency_equation(rng):
    """Three inertias on two shafts, free at both ends (Thomson, *Theory of Vibration with
    Applications*, ch. "Multi-degree of freedom systems", the three-disc torsional system;
    Den Hartog 1956, ch. 4): the non-zero natural frequencies are the roots of

        J1 J2 J3 w^4 - [k1 J3 (J1 + J2) + k2 J1 (J2 + J3)] w^2 + k1 k2 (J1 + J2 + J3) = 0.
    """
    for _ in range(20):
        j1, j2, j3 = rng.uniform(0.01, 2.0, 3)
        k1, k2 = rng.uniform(1e3, 1e6, 2)
        a = j1 * j2 * j3
        b = k1 * j3 * (j1 + j2) + k2 * j1 * (j2 + j3)
        c = k1 * k2 * (j1 + j2 + j3)
        w2 = np.sort(np.roots([a, -b, c]).real)
        expected = np.sqrt(w2) / (2 * math.pi)
        train = chain([j1, j2, j3], [k1, k2])
        frequency, shape = td.normal_modes(td.assemble([j1, j2, j3], [k1, k2], [0, 0], [0, 0, 0]))
        np.testing.assert_allclose(frequency, expected, rtol=1e-10)
        # shapes: +1 at mass 1; the Holzer residual torque beyond mass 3 is zero
        np.testing.assert_allclose(shape[:, 0], 1.0)
        w2f = (2 * math.pi * frequency) ** 2
        inertia = np.array([j1, j2, j3])
        np.testing.assert_allclose(
            np.sum(inertia * shape, axis=1) * w2f,
            0.0,
            atol=1e-9 * float(np.max(inertia * w2f[:, None])),
        )
        assert train.n_masses == 3


# --------------------------------------------------------------------------- energy


def _random_system(rng, n: int, tuned: bool = True) -> td.TrainMatrices:
    j = rng.uniform(0.001, 0.5, n)
    k = rng.uniform(1e4, 2e6, n - 1)
    c_sec = rng.uniform(0.0, 3.0, n - 1)
    c_abs = rng.uniform(0.0, 1.0, n)
    at = [0, int(rng.integers(0, n))]
    k_ring = [rng.uniform(1e4, 1e5) if tuned else 0.0, 0.0]
    return td.assemble(
        j,
        k,
        c_sec,
        c_abs,
        at,
        rng.uniform(0.002, 0.02, 2),
        k_ring,
        rng.uniform(1.0, 20.0, 2),
        loss_factor=float(rng.uniform(0.0, 0.05)),
    )


def test_energy_balance_per_order(rng):
    """The mean power the excitation puts in at each order, Re(F . conj(i w Q)) / 2, equals
    the power dissipated, w^2 Q^H C Q / 2 + w eta Q^H K_s Q / 2 (the viscous and the
    hysteretic damping); Den Hartog 1956, ch. 2 (work per cycle of viscous and
    hysteretic damping)."""
    for _ in range(10):
        m = _random_system(rng, int(rng.integers(2, 10)))
        w = rng.uniform(20.0, 5000.0, 50)
        f = rng.standard_normal((50, m.size)) + 1j * rng.standard_normal((50, m.size))
        f[:, m.rings] = 0.0
        q = td.harmonic_response(m, w, f)
        power_in = 0.5 * np.real(np.sum(f * np.conj(1j * w[:, None] * q), axis=1))
        viscous = 0.5 * w**2 * np.real(np.einsum("si,ij,sj->s", np.conj(q), m.damping, q))
        hysteretic = (
            0.5
            * w
            * m.loss_factor
            * np.real(np.einsum("si,ij,sj->s", np.conj(q), m.section_stiffness, q))
        )
        np.testing.assert_allclose(power_in, viscous + hysteretic, rtol=1e-9)
        assert np.all(power_in >= 0)


def test_damper_power_is_its_share_of_the_dissipation():
    """The damper power reported, (k Omega)^2 c |Q_hub - Q_ring|^2 / 2, is the coupling's
    term of the dissipation of the energy balance; at every order and speed of an engine's
    response it is at most the power the excitation puts in."""
    engine = with_train("inline-4-gas", inline4_train())
    result = analysed(engine, speeds=np.linspace(100.0, 700.0, 7))
    t = result.part("torsion")
    from balance.core.torsion import train_matrices

    m = train_matrices(t.train, t.inertias)
    forces = t.excitation.at_crank(t.speeds)  # (S, K, c)
    to_mass = np.zeros((forces.shape[-1], m.size))
    to_mass[np.arange(forces.shape[-1]), t.cylinder_mass] = 1.0
    f = forces @ to_mass
    w = np.outer(t.speeds, t.orders)
    q = td.harmonic_response(m, w, f)
    damper = t.train.dampers[0]
    expected = 0.5 * w**2 * damper.damping * np.abs(q[..., damper.at - 1] - q[..., m.n_masses]) ** 2
    np.testing.assert_allclose(t.damper_power[0], expected.T, rtol=1e-12, atol=1e-300)
    power_in = 0.5 * np.real(np.sum(f * np.conj(1j * w[..., None] * q), axis=-1))
    assert np.all(t.damper_power[0] <= power_in.T * (1 + 1e-9) + 1e-300)
    np.testing.assert_allclose(np.abs(q[..., 0]).T, np.abs(t.free_end), rtol=1e-12)


# --------------------------------------------------------------------------- time domain


def _integrate(m: td.TrainMatrices, torque, q0, v0, t_end: float, t_eval):
    scipy = pytest.importorskip("scipy.integrate")
    minv = 1.0 / np.diag(m.mass)

    def rhs(t, y):
        q, v = y[: m.size], y[m.size :]
        a = minv * (torque(t) - m.damping @ v - m.stiffness @ q)
        return np.concatenate([v, a])

    sol = scipy.solve_ivp(
        rhs,
        (0.0, t_end),
        np.concatenate([q0, v0]),
        method="DOP853",
        rtol=1e-11,
        atol=1e-14,
        t_eval=t_eval,
    )
    assert sol.success
    return sol.y[: m.size]


def test_time_domain_from_rest_reaches_the_steady_state(rng):
    """Integrating M q'' + C q' + K q = sum_k Re(F_k e^{i k W t}) from rest (scipy's DOP853,
    an explicit Runge-Kutta method of order 8; every mass damped to the block, so that the
    transient dies away and the rigid-body rotation comes to rest at a constant angle) ends
    on the steady state solved per order, and its half range is the synthesis."""
    n = 4
    m = td.assemble(
        [0.02, 0.01, 0.015, 0.05],
        [2e4, 3e4, 1e4],
        [0.5, 0.5, 0.5],
        [0.8, 0.4, 0.6, 2.0],
        [0],
        [0.004],
        [2e3],
        [0.3],
    )
    big_w = 60.0
    orders = np.array([0.5, 1.0, 1.5, 3.0])
    f = rng.standard_normal((orders.size, m.size)) + 1j * rng.standard_normal((orders.size, m.size))
    f[:, m.rings] = 0.0
    q = td.harmonic_response(m, orders * big_w, f)  # (K, N)

    def torque(t):
        return np.real(np.exp(1j * orders * big_w * t) @ f)

    period = 4 * math.pi / big_w  # the cycle of the half orders
    decay = float(np.max(np.diag(m.mass) / np.maximum(np.diag(m.damping), 1e-300)))
    t_end = math.ceil(40 * decay / period) * period
    t_eval = t_end - period + period * np.arange(400) / 400
    y = _integrate(m, torque, np.zeros(m.size), np.zeros(m.size), t_end, t_eval)
    steady = np.real(np.exp(1j * np.outer(t_eval, orders * big_w)) @ q).T
    scale = float(np.max(np.abs(steady)))
    # the rigid-body rotation has no stiffness: where the transient leaves it is a constant
    # angle of every mass, the mean over the cycle (the steady state's is zero)
    offset = np.mean(y, axis=1)
    np.testing.assert_allclose(offset, offset[0], atol=1e-7 * scale)
    y = y - offset[0]
    np.testing.assert_allclose(y, steady, atol=1e-7 * scale)
    h = tx.harmonic_numbers(orders, "four-stroke")
    half = td.half_range(q[:, 0], h)
    assert abs(half - 0.5 * (y[0].max() - y[0].min())) < 1e-3 * half  # 400 samples
    dense = np.real(np.exp(1j * np.outer(np.linspace(0, period, 200001), orders * big_w)) @ q[:, 0])
    np.testing.assert_allclose(half, 0.5 * (dense.max() - dense.min()), rtol=1e-9)
    assert n == 4


def test_time_domain_engine_response_is_a_solution():
    """The steady state of an engine at one speed (the inline-4 with gas and its train,
    viscous damping only) satisfies the equations of motion: integrated over two cycles
    from its own state at crank angle 0 by scipy's DOP853, with the cylinders' torques
    synthesised from every order reported, it stays on the free-end angle and the section
    torques of the result."""
    train = inline4_train(loss_factor=0.0)
    engine = with_train("inline-4-gas", train)
    speed = 400.0
    result = analysed(engine, speeds=[speed])
    t = result.part("torsion")
    from balance.core.torsion import train_matrices

    m = train_matrices(t.train, t.inertias)
    forces = t.excitation.at_crank([speed])[0]  # (K, c)
    to_mass = np.zeros((forces.shape[-1], m.size))
    to_mass[np.arange(forces.shape[-1]), t.cylinder_mass] = 1.0
    f = forces @ to_mass
    w = t.orders * speed
    q = td.harmonic_response(m, w, f)

    def torque(time):
        return np.real(np.exp(1j * w * time) @ f)

    period = 4 * math.pi / speed
    t_eval = np.linspace(0.0, 2 * period, 40001)
    y = _integrate(
        m,
        torque,
        np.real(q.sum(axis=0)),
        np.real((1j * w[:, None] * q).sum(axis=0)),
        2 * period,
        t_eval,
    )
    free_end = np.real(np.exp(1j * np.outer(t_eval, w)) @ t.free_end[:, 0])
    np.testing.assert_allclose(y[0], free_end, atol=1e-7 * float(np.max(np.abs(free_end))))
    k_sec = np.array([s.stiffness for s in t.train.sections])
    n = t.train.n_masses
    torques = k_sec[:, None] * (y[: n - 1] - y[1:n])
    synth = np.real(np.exp(1j * np.outer(t_eval, w)) @ t.section_torque[:, :, 0].T).T
    scale = float(np.max(np.abs(synth)))
    np.testing.assert_allclose(torques, synth, atol=1e-6 * scale)
    half = 0.5 * (torques.max(axis=1) - torques.min(axis=1))
    # sampled every 0.036 deg: below the synthesis by at most about (pi 24 / 20000)^2 / 2
    np.testing.assert_allclose(half, t.section_torque_synthesis[:, 0], rtol=2e-5)
    assert np.all(half <= t.section_torque_synthesis[:, 0] * (1 + 1e-9))


# --------------------------------------------------------------------------- inertia


def _brute_force_inertia(engine, cylinder: int, samples: int = 4096) -> float:
    """Twice the mean kinetic energy of a cylinder's piston group and rod per omega^2, from
    their positions alone: the piston pin on its bore, the rod a rigid body with its CG at
    ``conrod_cg_to_big_end`` from the big end and its own inertia about its CG; velocities
    by exact differentiation of the sampled periodic positions (FFT)."""
    parts = engine.mass_parts
    i = cylinder
    r, length, e = engine.crank_radius[i], engine.conrod_length[i], engine.offset[i]
    beta = 2 * math.pi * np.arange(samples) / samples
    big_end = r * np.cos(beta) + 1j * r * np.sin(beta)  # along the bore (real), across (imag)
    pin_x = np.full(samples, e)
    pin_y = r * np.cos(beta) + np.sqrt(length**2 - (r * np.sin(beta) - e) ** 2)
    pin = pin_y + 1j * pin_x
    a = parts.conrod_cg_to_big_end[i]
    cg = big_end + (a / length) * (pin - big_end)
    angle = np.angle(pin - big_end)

    def d(values):
        spectrum = np.fft.fft(values)
        k = np.fft.fftfreq(samples, 1.0 / samples)
        k[samples // 2] = 0.0
        return np.fft.ifft(1j * k * spectrum)

    inertia = parts.conrod_inertia[i]
    inertia = 0.0 if math.isnan(inertia) else inertia
    energy2 = (
        parts.piston_group[i] * np.abs(d(pin)) ** 2
        + parts.conrod[i] * np.abs(d(cg)) ** 2
        + inertia * np.real(d(angle)) ** 2
    )
    return float(np.mean(energy2))


@pytest.mark.parametrize("offset", ["0 mm", "4 mm", "-9 mm"])
def test_moving_parts_inertia_is_the_mean_kinetic_energy(offset):
    """Wilson, *Practical Solution of Torsional Vibration Problems*, vol. 1, 1956 (the
    equivalent inertia of the reciprocating parts: the mean kinetic energy over a
    revolution); here against the kinetic energy of the piston and the rigid rod sampled by
    brute force, with offsets."""
    data = {
        "name": "single",
        "speed": "3000 rpm",
        "geometry": {"stroke": "86 mm", "conrod_length": "139 mm", "offset": offset},
        "masses": {
            "piston_group": "0.40 kg",
            "conrod": "0.47 kg",
            "conrod_cg_to_big_end": "40 mm",
            "conrod_inertia": "1.5e-3 kg m^2",
            "crank_unbalance": "0.40 kg",
        },
        "cylinders": [{"throw": "0 deg", "bank": "0 deg", "z": "0 mm"}],
    }
    engine = layout_from_dict(data)
    found = float(tx.moving_parts_inertia(engine)[0])
    np.testing.assert_allclose(found, _brute_force_inertia(engine, 0), rtol=1e-12)


def test_moving_parts_inertia_series():
    """Without offset the mean inertia is m_big r^2 + m_rec r^2 (1/2 + lam^2/8 + lam^4/16
    + ...) + dI (lam^2/2 + lam^4/8 + ...) (docs/torsion.md); the first terms agree to the
    next power of lambda."""
    engine = load_layout("inline-4-gas")
    parts = engine.mass_parts
    r, length = engine.crank_radius[0], engine.conrod_length[0]
    lam = r / length
    m_big = parts.conrod[0] * (1 - parts.conrod_cg_to_big_end[0] / length)
    series = (
        m_big * r**2
        + engine.reciprocating_mass[0] * r**2 * (0.5 + lam**2 / 8 + lam**4 / 16 + 5 * lam**6 / 128)
        + engine.conrod_inertia_correction[0] * (lam**2 / 2 + lam**4 / 8 + lam**6 / 16)
    )
    found = float(tx.moving_parts_inertia(engine)[0])
    assert abs(found - series) < 2 * lam**8 * engine.reciprocating_mass[0] * r**2


@pytest.mark.parametrize(
    "layout", ["inline-4-gas", "v8-crossplane-gas", "v12-60-articulated", "radial-5"]
)
def test_inertia_torque_is_the_rate_of_kinetic_energy(layout):
    """The moving parts' torque on the crank pin (balance.core.torque.compute_torque with no
    gas force, link rods included) is -w^2/2 dJ/dtheta of the instantaneous inertia whose
    mean is added to a crank_inertia mass: the excitation and the inertia are one
    kinetic energy (Wilson 1956; Den Hartog 1956, ch. 5)."""
    engine = load_layout(layout)
    firing = tx.place_firing_tdc(engine)
    if isinstance(firing, str):
        firing = np.zeros(engine.n_cylinders)
    from dataclasses import replace

    bare = compute_torque(
        replace(engine, gas=tx._null_gas(engine, firing)), np.ones(1, dtype=np.intp)
    )
    theta = np.radians(bare.crank_angle)
    n = theta.size
    inertia = tx.instantaneous_inertia(engine, theta)
    k = np.fft.fftfreq(n, 1.0 / n) * (360.0 / (bare.cycle_deg))
    k[n // 2] = 0.0
    derivative = np.real(np.fft.ifft(1j * k * np.fft.fft(inertia, axis=1), axis=1))
    w2 = engine.speed**2
    expected = -0.5 * w2 * derivative
    scale = float(np.max(np.abs(bare.cylinder_torque)))
    np.testing.assert_allclose(bare.cylinder_torque, expected, atol=1e-9 * scale)


# --------------------------------------------------------------------------- vector sums


@pytest.mark.parametrize(
    ("layout", "majors"),
    [
        ("inline-6", [3.0, 6.0, 9.0, 12.0]),
        ("v8-crossplane-gas", [4.0, 8.0, 12.0]),
        ("inline-4-gas", [2.0, 4.0, 6.0, 8.0, 10.0, 12.0]),
    ],
)
def test_vector_sums_at_major_orders_are_plain_sums(layout, majors):
    """Nestorides, *A Handbook on Torsional Vibration*, 1958, and Wilson 1956: for an engine
    firing evenly z times a cycle, every cylinder is in phase at the major orders
    (multiples of z 360 / cycle), where the relative amplitude sum is the plain sum of the
    mode shape over the cylinders."""
    engine = load_layout(layout)
    n_cyl = engine.n_cylinders
    per_throw = 2 if layout.startswith("v8") else 1
    from balance.core.torsion import Shaft, TorsionMass, TorsionTrain

    masses = [TorsionMass("pulley", inertia=0.004, shaft=Shaft(1e6))]
    throws = n_cyl // per_throw
    order_of_z = np.argsort(engine.z, kind="stable")
    for t in range(throws):
        cyl = tuple(int(c) + 1 for c in order_of_z[t * per_throw : (t + 1) * per_throw])
        masses.append(
            TorsionMass(f"throw {t + 1}", crank_inertia=0.004, cylinders=cyl, shaft=Shaft(8e5))
        )
    masses.append(TorsionMass("flywheel", inertia=0.12, damping=1.0))
    train = TorsionTrain(tuple(masses))
    result = analysed(with_train(engine, train), speeds=[engine.speed])
    t = result.part("torsion")
    major = [float(k) for k, flag in zip(t.orders, t.major, strict=True) if flag]
    assert major == majors
    plain = np.abs(
        np.array([[np.sum(t.shapes[j, t.cylinder_mass]) for j in range(t.frequencies.size)]])
    )
    for k in majors:
        i = int(np.flatnonzero(t.orders == k)[0])
        np.testing.assert_allclose(t.vector_sums[:, i], plain[0], rtol=1e-9, atol=1e-12)


def test_the_diesels_synthesis_is_the_sampled_half_range():
    """The built-in MWM six over its 200 speeds: the synthesised half range of every
    section's torque and of the free-end angle is never below that of a sampling of the
    same series at 8192 points a cycle, and above it by no more than the sampling's step
    allows.  With two Newton steps only, an asymmetric extreme between two samples was
    under-refined: the synthesis fell 2.7e-4 short of the sampling."""
    engine = load_layout("inline-6-diesel-torsion")
    t = analysed(engine).part("torsion")
    h = np.rint(2 * np.asarray(t.orders)).astype(int)  # harmonics of the 720 deg cycle
    n = 1 << 13
    series = [
        (t.section_torque[j], t.section_torque_synthesis[j]) for j in range(len(t.section_torque))
    ]
    series.append((t.free_end, t.free_end_synthesis))
    for x, found in series:
        spectrum = np.zeros((x.shape[1], n // 2 + 1), dtype=np.complex128)
        spectrum[:, h] = x.T * (n / 2)
        f = np.fft.irfft(spectrum, n=n, axis=-1)
        sampled = 0.5 * (f.max(axis=1) - f.min(axis=1))
        slack = (2 * math.pi / n) ** 2 / 8 * (np.abs(x.T) @ (h * h).astype(float))
        assert np.all(found >= sampled * (1 - 1e-12))
        assert np.all(found <= sampled + slack + 1e-12 * sampled)
