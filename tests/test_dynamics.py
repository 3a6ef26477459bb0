"""The variable-speed rung: the crank train's own motion (balance.core.crank_motion,
balance.core.dynamics, balance.views.dynamics; docs/dynamics.md).

Validation: two textbook flywheel examples (energy method, exact periodic fluctuation and
sizing), the kinetic energy of every moving body sampled by brute force against
:math:`\\tfrac12 J(\\theta)\\omega^2`, the energy balance of the steady state, the mean of the
roll, the coasting crank without gas, an independent Runge-Kutta integration converging to
the same orbit, and the constant-speed limit (the phasors of docs/conventions.md).
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import balance
from balance.core.analysis import compute
from balance.core.crank_motion import (
    ConstantTorque,
    PowerLaw,
    Propeller,
    crank_train,
    orders_in_time,
    periodic_integral,
    periodic_motion,
    time_over_cycle,
)
from balance.core.dynamics import dynamics_part, size_flywheel
from balance.core.errors import AnalysisError, InputError
from balance.core.result import Request
from balance.core.speed import rpm_to_rad_per_s
from balance.core.speed_model import (
    ConstantLoad,
    Flywheel,
    MeanLoad,
    PowerLawLoad,
    PropellerLoad,
    constant_speed_bound,
    constant_speed_warning,
    settings_of,
)
from balance.io.layout_file import layout_from_dict

ORDERS = np.arange(1, 9)
REQUEST = Request.of(range(1, 9))
RPM = 30.0 / math.pi

#: A master with two link rods (offsets, every rod with its own inertia, crank unbalance)
#: and a plain cylinder on a second throw.
LINK_LAYOUT = {
    "name": "test link engine",
    "speed": "2000 rpm",
    "geometry": {"stroke": "120 mm", "conrod_length": "240 mm", "offset": "3 mm"},
    "masses": {
        "piston_group": "0.9 kg",
        "conrod": "2.2 kg",
        "conrod_cg_to_big_end": "50 mm",
        "conrod_inertia": "0.02 kg m^2",
        "crank_unbalance": "1.1 kg",
    },
    "cylinders": [
        {"throw": "0 deg", "bank": "0 deg", "z": "0 mm"},
        {"throw": "0 deg", "bank": "60 deg", "z": "0 mm", "conrod": "0.7 kg",
         "conrod_cg_to_big_end": "70 mm", "conrod_inertia": "4e-3 kg m^2", "offset": "-2 mm",
         "link": {"master": 1, "pin_radius": "50 mm", "pin_angle": "62 deg", "length": "190 mm"}},
        {"throw": "0 deg", "bank": "-60 deg", "z": "0 mm", "conrod": "0.6 kg",
         "conrod_cg_to_big_end": "60 mm", "conrod_inertia": "3e-3 kg m^2",
         "link": {"master": 1, "pin_radius": "55 mm", "pin_angle": "-58 deg", "length": "185 mm"}},
        {"throw": "180 deg", "bank": "0 deg", "z": "100 mm"},
    ],
}  # fmt: skip


def _single_with_gas(speed: str = "1000 rpm", heat: str = "0.25 kJ", **gas: object) -> dict:
    """The built-in single (KTM 690 geometry and masses) with the parametric gas model: a
    part load (0.45 bar intake, 0.25 kJ per cycle) at 1000 rpm is an idle of sorts."""
    model = {
        "compression_ratio": 12.7,
        "intake_pressure": "0.45 bar",
        "exhaust_pressure": "1.05 bar",
        "heat_released": heat,
        **gas,
    }
    return {
        "name": "single with gas",
        "speed": speed,
        "cycle": "four-stroke",
        "geometry": {"bore": "102 mm", "stroke": "84.5 mm", "conrod_length": "146 mm"},
        "masses": {
            "piston_group": "0.53 kg",
            "conrod": "0.50 kg",
            "conrod_cg_to_big_end": "44 mm",
            "conrod_inertia": "1.8e-3 kg m^2",
            "crank_unbalance": "0.35 kg",
        },
        "crank": {"throws": [0]},
        "firing_order": [1],
        "gas": {"model": model, "crankcase_pressure": "1 bar"},
        "flywheel": {"inertia": "0.06 kg m^2"},
    }


@pytest.fixture(scope="module")
def inline4_gas():
    engine = balance.load_layout("inline-4-gas")
    return engine, compute(engine, REQUEST)


@pytest.fixture(scope="module")
def single_idle():
    engine = layout_from_dict(_single_with_gas())
    return engine, compute(engine, REQUEST)


def _dynamics(engine, result=None, **options):
    result = compute(engine, REQUEST) if result is None else result
    return dynamics_part(engine, REQUEST, result, **{"speed_model": "dynamic", **options})


# --------------------------------------------------------------------------- textbook


def test_three_crank_engine_constant_resisting_torque():
    """Khurmi and Gupta, *Theory of Machines*, S. Chand 2005, ch. 16, Example 16.13: a
    three-crank engine's turning moment is (5000 + 1500 sin 3θ) N m, the flywheel has
    1000 kg m^2 and the mean speed is 300 rpm; with a constant resisting torque the power is
    157.1 kW and the total fluctuation of speed 0.1 % (the energy method: the largest
    fluctuation of energy is the area of one loop, 1000 N m, over I ω^2).  The exact periodic
    solution keeps the mean speed, its kinetic energy swings by exactly those 1000 J, and its
    fluctuation is the energy method's to O(δ^2)."""
    n = 720
    theta = 2 * math.pi * np.arange(n) / n
    torque = 5000.0 + 1500.0 * np.sin(3 * theta)
    inertia = np.full(n, 1000.0)
    w = rpm_to_rad_per_s(300.0)
    motion = periodic_motion(inertia, np.zeros(n), torque, 2 * math.pi, ConstantTorque(5000.0), w)
    assert round(5000.0 * w / 1e3, 1) == 157.1  # the book's power [kW]
    swing = 0.5 * 1000.0 * (motion.speed.max() ** 2 - motion.speed.min() ** 2)
    assert swing == pytest.approx(1000.0, rel=1e-12)  # the loop's area, exactly
    estimate = 1000.0 / (1000.0 * w * w)
    assert round(100 * estimate, 1) == 0.1  # the book's 0.1 %
    assert motion.speed_fluctuation == pytest.approx(estimate, rel=1e-6)
    assert motion.mean_speed == pytest.approx(w, rel=1e-14)
    # the speed is highest where the loop of excess energy ends (theta = 60 deg)
    assert abs(math.degrees(theta[np.argmax(motion.speed)]) - 60.0) < 1.0


def test_flywheel_sized_for_a_total_fluctuation_of_one_percent():
    """Khurmi and Gupta 2005, Example 16.11: T = (20 000 + 9500 sin 2θ − 5700 cos 2θ) N m
    at 180 rpm, total fluctuation ±0.5 %: power 377 kW, largest fluctuation of energy
    11 078 N m, flywheel 3121 kg m^2 (the book divides by ω^2 C_s rounded to 3.55; unrounded
    11 078.8/(ω^2 0.01) = 3118.1), angular acceleration 3.044 rad/s^2 at θ = 45 deg.  The
    exact sizing (the steady state's δ is 1 %) agrees with the energy method to O(δ^2)."""
    n = 720
    theta = 2 * math.pi * np.arange(n) / n
    torque = 20000.0 + 9500.0 * np.sin(2 * theta) - 5700.0 * np.cos(2 * theta)
    w = rpm_to_rad_per_s(180.0)
    zero = np.zeros(n)
    load = ConstantTorque(20000.0)
    inertia = size_flywheel(zero, zero, torque, load, w, 2 * math.pi, 0.01)
    assert round(20000.0 * w / 1e3) == 377
    energy = math.hypot(9500.0, 5700.0)
    assert round(energy) == 11079  # the book's 11 078 (truncated)
    assert inertia == pytest.approx(energy / (w * w * 0.01), rel=1e-4)
    assert inertia == pytest.approx(3121.0, rel=1.5e-3)
    motion = periodic_motion(np.full(n, inertia), zero, torque, 2 * math.pi, load, w)
    assert motion.speed_fluctuation == pytest.approx(0.01, rel=1e-10)
    accel = motion.acceleration[n // 8]  # theta = 45 deg
    assert accel == pytest.approx(9500.0 / inertia, rel=1e-12)
    assert accel == pytest.approx(3.044, rel=1.5e-3)  # the book's, with its 3121 kg m^2


# --------------------------------------------------------------------------- J(theta)


def _rod_to_bore(end, length, bank, offset):
    """Angle of a rod from its lower end ``end`` (complex y + ix) to a piston pin on the bore
    of direction ``bank`` offset by ``offset``, and the pin: written here from the geometry,
    independently of the package."""
    across = (end * np.exp(-1j * bank)).imag
    angle = bank + np.arcsin((offset - across) / length)
    return angle, end + length * np.exp(1j * angle)


def _bodies(engine, theta):
    """Every moving body of an engine with masses by part at crank angles ``theta``: a list
    of (mass, place, inertia, angle), each place and angle an array over ``theta``."""
    parts = engine.mass_parts
    links = engine.links
    out = []
    rod_angle = {}
    for i in range(engine.n_cylinders):
        r = engine.crank_radius[i]
        crank = r * np.exp(1j * (theta + engine.throw[i]))
        master = -1 if links is None else int(links.master[i])
        if master < 0:
            lower = crank
        else:  # the link pin on the master rod
            lower = crank + links.pin_radius[i] * np.exp(
                1j * (rod_angle[master] + links.pin_angle[i])
            )
        angle, pin = _rod_to_bore(lower, engine.conrod_length[i], engine.bank[i], engine.offset[i])
        rod_angle[i] = angle
        a, m_c = parts.conrod_cg_to_big_end[i], parts.conrod[i]
        inertia = parts.conrod_inertia[i]
        if math.isnan(inertia):
            inertia = m_c * a * (engine.conrod_length[i] - a)
        out.append((parts.piston_group[i], pin, 0.0, angle))
        out.append((m_c, lower + a * np.exp(1j * angle), inertia, angle))
        unbalance = np.nan_to_num(parts.crank_unbalance[i]) / parts.rods_per_throw[i]
        out.append((unbalance, crank, 0.0, angle))
    return out


def _derivative(f, theta, h=1e-4):
    return (-f(theta + 2 * h) + 8 * f(theta + h) - 8 * f(theta - h) + f(theta - 2 * h)) / (12 * h)


@pytest.mark.parametrize(
    "name", ["single", "inline-4-gas", "v8-crossplane-gas", "radial-9", "links"]
)
def test_kinetic_energy_of_every_body_is_half_j_omega_squared(name):
    """Brute force: each body's velocity by differencing its place (fourth-order central
    differences), the true rod (its mass at its centre of gravity, its own inertia), the
    crank unbalance on the pin: 2 T/ω^2 = J(θ) - J_f to 1e-10."""
    engine = layout_from_dict(LINK_LAYOUT) if name == "links" else balance.load_layout(name)
    theta_deg = np.linspace(0.0, 360.0, 73)
    theta = np.radians(theta_deg)
    total = np.zeros(theta.size)
    for k in range(3 * engine.n_cylinders):

        def place(t, k=k):
            return _bodies(engine, t)[k][1]

        def angle(t, k=k):
            return _bodies(engine, t)[k][3]

        mass, _, inertia, _ = _bodies(engine, theta[:1])[k]
        total += mass * np.abs(_derivative(place, theta)) ** 2
        total += inertia * _derivative(angle, theta) ** 2
    train = crank_train(engine, theta_deg)
    np.testing.assert_allclose(train.inertia, total, rtol=1e-10)  # measured 1.4e-11
    # and its slope is the derivative of J
    slope = _derivative(lambda t: crank_train(engine, np.degrees(t)).inertia, theta)
    np.testing.assert_allclose(train.inertia_slope, slope, atol=1e-8 * total.max())


# --------------------------------------------------------------------------- steady state


@pytest.mark.parametrize("load", [MeanLoad(), PropellerLoad(), PowerLawLoad(180.0, 700.0, 1.7)])
def test_the_steady_state_balances_the_cycle_work(inline4_gas, load):
    """Over the periodic steady state the load absorbs the cycle's work,
    ∮(Q − T_L) dθ = 0; the kinetic energy ½ J ω^2 changes by the integral of Q − T_L; the
    acceleration is that of the equation of motion; the time-mean speed is the layout's."""
    engine, result = inline4_gas
    part = _dynamics(engine, result, load=load, flywheel=Flywheel(0.05)).part("dynamics")
    motion, q = part.motion, part.gas_torque
    assert abs(np.mean(q - motion.load_torque)) <= 1e-12 * np.max(np.abs(q))
    energy = 0.5 * part.inertia * motion.speed**2
    cycle = 4 * math.pi
    _, work = periodic_integral(q - motion.load_torque, cycle)
    np.testing.assert_allclose(energy - energy[0], work, atol=1e-10 * energy.max())
    train = crank_train(engine, part.crank_angle)
    lhs = part.inertia * motion.acceleration + 0.5 * train.inertia_slope * motion.speed**2
    np.testing.assert_allclose(lhs, q - motion.load_torque, atol=1e-9 * np.abs(q).max())
    if not isinstance(load, PowerLawLoad):
        assert part.mean_speed == pytest.approx(engine.speed, rel=1e-13)
    assert motion.period == pytest.approx(cycle / part.mean_speed, rel=1e-14)


def test_the_mean_roll_is_minus_the_mean_torque(inline4_gas):
    """The roll over the cycle (docs/dynamics.md) averages in time to minus the load torque
    (the angular momentum of the bodies returns each cycle), which for the mean load is
    minus the mean torque."""
    engine, result = inline4_gas
    part = _dynamics(engine, result, flywheel=Flywheel(0.02)).part("dynamics")
    m = part.motion
    train = crank_train(engine, part.crank_angle)
    roll = train.inertia_roll(m.speed, m.acceleration) - part.gas_torque
    weight = (4 * math.pi / m.speed.size) / m.speed / m.period
    assert np.sum(weight * roll) == pytest.approx(-part.load_torque, rel=1e-12)
    assert part.load_torque == pytest.approx(result.part("torque").mean, rel=1e-12)


@pytest.mark.parametrize("name", ["single", "inline-4", "v8-crossplane", "radial-9", "w12"])
def test_without_gas_the_crank_coasts(name):
    """No gas: the kinetic energy is constant, ω(θ) = ω_0 √(J(0)/J(θ)), with the time-mean
    speed the layout's."""
    engine = balance.load_layout(name)
    part = _dynamics(engine, flywheel=Flywheel(0.01)).part("dynamics")
    w = part.motion.speed
    np.testing.assert_allclose(w, w[0] * np.sqrt(part.inertia[0] / part.inertia), rtol=1e-13)
    assert part.mean_speed == pytest.approx(engine.speed, rel=1e-13)
    assert part.load_torque == 0.0 and np.all(part.gas_torque == 0.0)


def _rk4_cycle(theta_deg, inertia, slope, torque, load_at, speed, time, cycles):
    """Runge-Kutta of order 4 in the crank angle, of dω/dθ = (Q − T_L − ½J'ω²)/(Jω) and
    dt/dθ = 1/ω, with steps of two grid intervals (the grid's odd angles are the
    midpoints); returns ω and t at the even angles of the last cycle."""
    n = theta_deg.size
    h = 2 * math.radians(theta_deg[1] - theta_deg[0])
    J, dJ, Q = inertia.tolist(), slope.tolist(), torque.tolist()

    def f(j, w):
        return (Q[j] - load_at(w) - 0.5 * dJ[j] * w * w) / (J[j] * w)

    w, t = speed, time
    for _ in range(cycles):
        ws, ts = [], []
        for j in range(0, n, 2):
            ws.append(w)
            ts.append(t)
            k1 = f(j, w)
            k2 = f(j + 1, w + 0.5 * h * k1)
            k3 = f(j + 1, w + 0.5 * h * k2)
            k4 = f((j + 2) % n, w + h * k3)
            l1, l2, l3, l4 = 1 / w, 1 / (w + 0.5 * h * k1), 1 / (w + 0.5 * h * k2), 1 / (w + h * k3)
            w += h * (k1 + 2 * k2 + 2 * k3 + k4) / 6
            t += h * (l1 + 2 * l2 + 2 * l3 + l4) / 6
    return np.array(ws), np.array(ts), t


def _smooth_torque(theta):
    """A single's torque of sorts over a four-stroke cycle [N m] (smooth, so that the
    Runge-Kutta integration keeps its order)."""
    return (
        40.0
        + 60.0 * np.sin(theta / 2 + 0.4)
        + 45.0 * np.sin(theta + 1.1)
        + 30.0 * np.sin(1.5 * theta + 0.2)
        + 20.0 * np.sin(2 * theta)
    )


def test_runge_kutta_from_constant_speed_converges_to_the_periodic_orbit():
    """An independent time integration of the same equation (the single's J(θ), a smooth
    torque, a power-law load of exponent 4), started at constant speed, settles within 1e-10
    on the orbit the steady-state solver gives, with the same mean speed."""
    engine = balance.load_layout("single")
    n = 2880
    theta_deg = 720.0 * np.arange(n) / n
    train = crank_train(engine, theta_deg)
    inertia = train.inertia + 0.1
    torque = _smooth_torque(np.radians(theta_deg))
    law = PowerLaw(40.0, rpm_to_rad_per_s(1000.0), 4.0)
    motion = periodic_motion(inertia, train.inertia_slope, torque, 4 * math.pi, law)
    assert 0.05 < motion.speed_fluctuation < 0.3
    w, t, end = _rk4_cycle(
        theta_deg, inertia, train.inertia_slope, torque,
        lambda s: float(law.at(np.array(s))), law.speed, 0.0, 24,
    )  # fmt: skip
    np.testing.assert_allclose(w, motion.speed[::2], rtol=1e-10)  # measured 6.5e-13
    assert (4 * math.pi) / (end - t[0]) == pytest.approx(motion.mean_speed, rel=1e-11)


def test_runge_kutta_keeps_the_mean_load_orbit():
    """Under the mean load every orbit is periodic; started on the solver's, one cycle of
    the independent integration returns to it, in the cycle time the mean speed gives."""
    engine = balance.load_layout("single")
    n = 2880
    theta_deg = 720.0 * np.arange(n) / n
    train = crank_train(engine, theta_deg)
    inertia = train.inertia + 0.1
    torque = _smooth_torque(np.radians(theta_deg))
    speed = rpm_to_rad_per_s(1000.0)
    load = ConstantTorque(float(np.mean(torque)))
    motion = periodic_motion(inertia, train.inertia_slope, torque, 4 * math.pi, load, speed)
    w, t, end = _rk4_cycle(
        theta_deg, inertia, train.inertia_slope, torque,
        lambda s: load.torque, float(motion.speed[0]), 0.0, 1,
    )  # fmt: skip
    np.testing.assert_allclose(w, motion.speed[::2], rtol=1e-10)  # measured 1.0e-12
    np.testing.assert_allclose(t, motion.time[::2], rtol=1e-10, atol=1e-14)
    assert end == pytest.approx(motion.period, rel=1e-11)


# --------------------------------------------------------------------------- the constant limit


@pytest.mark.parametrize(
    "name",
    ["single", "inline-4", "inline-4-gas", "v8-crossplane-gas", "vr6", "w12", "boxer-2",
     "radial-9", "v12-60-articulated", "links"],
)  # fmt: skip
def test_constant_speed_bundle_is_the_phasors_of_the_analysis(name):
    """At the constant mean speed the whole free force, moment and roll of the sampled
    bodies are the analysis' phasors (docs/conventions.md) at every whole order, its roll
    with the gas (half orders) too, and half orders of the inertia forces are zero."""
    engine = layout_from_dict(LINK_LAYOUT) if name == "links" else balance.load_layout(name)
    result = compute(engine, REQUEST)
    flywheel = None if engine.gas is not None else Flywheel(0.05)
    part = _dynamics(engine, result, flywheel=flywheel).part("dynamics")
    free = result.phasors.free()
    whole = np.isin(part.orders, ORDERS)
    scale = result.reference_force
    c = part.constant
    np.testing.assert_allclose(c.force_forward[whole], free.force_forward, atol=1e-12 * scale)
    np.testing.assert_allclose(c.force_backward[whole], free.force_backward, atol=1e-12 * scale)
    assert np.all(c.force_forward[~whole] == 0) and np.all(c.force_backward[~whole] == 0)
    lever = max(float(np.ptp(engine.z)), 0.1)
    np.testing.assert_allclose(
        c.moment_forward[whole], free.moment_forward, atol=1e-12 * scale * lever
    )
    if engine.gas is not None:
        np.testing.assert_allclose(c.roll, result.roll, atol=1e-12 * np.abs(result.roll).max())
    else:
        np.testing.assert_allclose(c.roll[whole], result.roll, atol=1e-12 * result.reference_roll)


def test_at_constant_inertia_the_dynamic_phasors_are_the_constant_ones():
    """A crank train whose J does not change (rotating masses only) coasts at constant
    speed without gas: its dynamic phasors are the constant-speed ones exactly."""
    engine = balance.load_layout("v8-crossplane")
    n = engine.n_cylinders
    flat = replace(
        engine,
        reciprocating_mass=np.zeros(n),
        conrod_inertia_correction=np.zeros(n),
    )
    result = compute(flat, REQUEST)
    part = _dynamics(flat, result, flywheel=Flywheel(0.0)).part("dynamics")
    assert part.speed_fluctuation == 0.0 and np.all(part.motion.acceleration == 0.0)
    free = result.phasors.free()
    whole = np.isin(part.orders, ORDERS)
    scale = float(np.abs(free.force_forward).max())
    np.testing.assert_allclose(
        part.dynamic.force_forward[whole], free.force_forward, atol=1e-13 * scale
    )
    assert np.all(part.difference("force") <= 1e-12 * scale)


def test_a_heavy_flywheel_tends_to_the_constant_speed_answer():
    """Without gas the speed varies as 1/J_f: the difference from the constant-speed
    phasors falls in proportion (a hundred times the flywheel, a hundredth the
    difference)."""
    engine = balance.load_layout("inline-4")
    result = compute(engine, REQUEST)
    diffs = []
    for inertia in (1.0, 100.0):
        part = _dynamics(engine, result, flywheel=Flywheel(inertia)).part("dynamics")
        diffs.append(float(part.difference("force").max()))
    assert diffs[1] == pytest.approx(diffs[0] / 100.0, rel=0.02)
    assert diffs[1] < 1e-4 * result.reference_force


# --------------------------------------------------------------------------- properties


def _band_limited(draw, n, scale, terms=4):
    theta = 4 * math.pi * np.arange(n) / n
    values = np.full(n, 0.0)
    for k in range(1, terms + 1):
        amp = draw(st.floats(0.0, scale / k))
        phase = draw(st.floats(0.0, 2 * math.pi))
        values += amp * np.cos(k * theta / 2 + phase)
    return values


@st.composite
def problems(draw):
    """A periodic problem over a four-stroke cycle: J > 0 and Q band-limited, a speed."""
    n = 256
    j0 = draw(st.floats(0.02, 2.0))
    inertia = j0 * (1.0 + _band_limited(draw, n, 0.3))
    mean = draw(st.floats(10.0, 500.0))
    torque = mean + _band_limited(draw, n, 3.0 * mean)
    speed = draw(st.floats(50.0, 900.0))
    # keep the crank turning: the energy swing well below the kinetic energy
    _, work = periodic_integral(torque - mean, 4 * math.pi)
    inertia = inertia * max(1.0, 4.0 * float(np.ptp(work)) / (0.5 * j0 * 0.7 * speed * speed))
    return inertia, torque, speed


def _slope(inertia):
    n = inertia.size
    spectrum = np.fft.rfft(inertia)
    m = np.arange(spectrum.size) * 0.5
    return np.fft.irfft(1j * m * spectrum, n=n)


@settings(max_examples=25, deadline=None)
@given(problem=problems(), scale=st.floats(0.01, 100.0))
def test_scaling_inertia_and_torques_keeps_the_motion(problem, scale):
    inertia, torque, speed = problem
    slope = _slope(inertia)
    for load in (ConstantTorque(float(np.mean(torque))), Propeller()):
        a = periodic_motion(inertia, slope, torque, 4 * math.pi, load, speed)
        scaled_load = (
            ConstantTorque(scale * load.torque) if isinstance(load, ConstantTorque) else load
        )
        b = periodic_motion(
            scale * inertia, scale * slope, scale * torque, 4 * math.pi, scaled_load, speed
        )
        np.testing.assert_allclose(b.speed, a.speed, rtol=1e-10)
        assert a.mean_speed == pytest.approx(speed, rel=1e-12)


@settings(max_examples=25, deadline=None)
@given(problem=problems(), shift=st.integers(0, 255))
def test_moving_the_crank_angle_origin_moves_the_motion(problem, shift):
    inertia, torque, speed = problem
    slope = _slope(inertia)
    load = Propeller()
    a = periodic_motion(inertia, slope, torque, 4 * math.pi, load, speed)
    b = periodic_motion(
        np.roll(inertia, -shift), np.roll(slope, -shift), np.roll(torque, -shift),
        4 * math.pi, load, speed,
    )  # fmt: skip
    np.testing.assert_allclose(b.speed, np.roll(a.speed, -shift), rtol=1e-10)
    assert b.coefficient == pytest.approx(a.coefficient, rel=1e-10)


@settings(max_examples=25, deadline=None)
@given(problem=problems())
def test_a_square_power_law_is_the_propeller(problem):
    inertia, torque, speed = problem
    slope = _slope(inertia)
    prop = periodic_motion(inertia, slope, torque, 4 * math.pi, Propeller(), speed)
    c = prop.coefficient
    law = periodic_motion(
        inertia, slope, torque, 4 * math.pi, PowerLaw(c * speed * speed, speed, 2.0)
    )
    # both paths end in the closed-form periodic solve, whose rounding reaches 1e-10 of the
    # energy where exp of the load's periodic integral spans decades (hypothesis found a
    # cycle at 1.05e-10; crank_motion.NEWTON_FLOOR)
    np.testing.assert_allclose(law.speed, prop.speed, rtol=1e-9)
    assert law.mean_speed == pytest.approx(speed, rel=1e-9)


@settings(max_examples=20, deadline=None)
@given(problem=problems(), extra=st.floats(0.1, 10.0))
def test_the_fluctuation_falls_as_the_flywheel_grows(problem, extra):
    inertia, torque, speed = problem
    slope = _slope(inertia)
    load = ConstantTorque(float(np.mean(torque)))
    a = periodic_motion(inertia, slope, torque, 4 * math.pi, load, speed)
    b = periodic_motion(inertia + extra * inertia.mean(), slope, torque, 4 * math.pi, load, speed)
    assert b.speed_fluctuation <= a.speed_fluctuation
    if a.speed_fluctuation > 1e-9:
        assert b.speed_fluctuation < a.speed_fluctuation


@settings(max_examples=20, deadline=None)
@given(speed=st.floats(20.0, 2000.0))
def test_without_gas_the_motion_scales_with_the_speed(speed):
    """Coasting, ω/ω_mean depends on J(θ) alone; the force phasors grow as ω^2."""
    engine = balance.load_layout("inline-3")
    base = _dynamics(engine, flywheel=Flywheel(0.02)).part("dynamics")
    fast = _dynamics(engine.with_speed(speed), flywheel=Flywheel(0.02)).part("dynamics")
    ratio = speed / engine.speed
    np.testing.assert_allclose(fast.motion.speed, ratio * base.motion.speed, rtol=1e-12)
    np.testing.assert_allclose(
        fast.dynamic.force_forward,
        ratio**2 * base.dynamic.force_forward,
        atol=1e-11 * ratio**2 * np.abs(base.dynamic.force_forward).max(),
    )


# --------------------------------------------------------------------------- orders in time


def test_orders_in_time_take_the_time_series():
    """A signal that is a pure order k in time, F = e^{ik θ̄(t)}, gives P_k^+ = 1 and
    nothing else, whatever the speed does over the cycle."""
    n = 1440
    theta = 4 * math.pi * np.arange(n) / n
    speed = 100.0 * (1.0 + 0.2 * np.sin(theta) + 0.1 * np.cos(1.5 * theta + 0.3))
    time, period = time_over_cycle(speed, 4 * math.pi)
    mean = 4 * math.pi / period
    weight = (4 * math.pi / n) / speed / period
    offset = np.sum(weight * (theta - mean * time))
    mean_angle = mean * time + offset
    ks = np.arange(1, 9) / 2
    forward, backward = orders_in_time(
        np.exp(1.5j * mean_angle), speed, time, period, ks, 4 * math.pi
    )
    expected = np.where(ks == 1.5, 1.0, 0.0)
    np.testing.assert_allclose(forward, expected, atol=1e-12)
    np.testing.assert_allclose(backward, 0.0, atol=1e-12)


# --------------------------------------------------------------------------- sizing, bound


def test_flywheel_sized_for_an_exact_fluctuation():
    """v8-crossplane-gas asks for 1 %: the steady state with the sized J_f has δ = 1 %
    exactly, and J_f is near the constant-speed estimate."""
    engine = balance.load_layout("v8-crossplane-gas")
    part = _dynamics(engine).part("dynamics")
    assert part.flywheel_sized
    assert part.speed_fluctuation == pytest.approx(0.01, rel=1e-9)
    assert part.speed_fluctuation_constant_speed == pytest.approx(0.01, rel=0.01)
    estimate = part.excess_work / (0.01 * part.mean_speed**2) - float(
        np.mean(part.inertia - part.flywheel_inertia)
    )
    assert part.flywheel_inertia == pytest.approx(estimate, rel=0.01)


@pytest.mark.parametrize(
    "name,flywheel,rpm",
    [("inline-4-gas", 0.12, 7000), ("inline-4-gas", 0.03, 2000), ("v8-crossplane-gas", 0.05, 1500),
     ("single-idle", 0.06, 1000), ("single-idle", 0.03, 1500), ("single-rated", 0.06, 7500)],
)  # fmt: skip
def test_the_constant_speed_bound_holds(name, flywheel, rpm):
    """The constant rung's bound on its own force error (from constant-speed data alone)
    is not exceeded by the measured difference over the cycle."""
    if name.startswith("single"):
        heat = "0.25 kJ" if name == "single-idle" else "1.1 kJ"
        intake = "0.45 bar" if name == "single-idle" else "1.0 bar"
        engine = layout_from_dict(_single_with_gas(f"{rpm} rpm", heat, intake_pressure=intake))
    else:
        engine = balance.load_layout(name).with_speed(rpm_to_rad_per_s(rpm))
    wheel = Flywheel(flywheel)
    result = compute(engine, REQUEST)
    part = dynamics_part(engine, REQUEST, result, speed_model="dynamic", flywheel=wheel)
    part = part.part("dynamics")
    bound = constant_speed_bound(engine, result.part("torque"), wheel)
    measured = float(np.max(np.abs(part.force - part.force_constant)))
    assert measured <= bound.force
    assert 0.0 < bound.ratio < math.inf


def test_the_constant_speed_warning(single_idle):
    engine, result = single_idle
    torque = result.part("torque")
    light = constant_speed_warning(engine, torque, Flywheel(0.005))
    assert light is not None and light.rule == "constant_speed_bound"
    assert "dynamic" in light.message and "% of sum(m r w^2)" in light.message
    assert constant_speed_warning(engine, torque, Flywheel(50.0)) is None
    bare = replace(engine, gas=replace(engine.gas, flywheel_inertia=None))
    assert (
        constant_speed_bound(bare, torque) is None and constant_speed_warning(bare, torque) is None
    )


# --------------------------------------------------------------------------- refusals, warnings


def test_refused_without_a_flywheel():
    engine = balance.load_layout("inline-4")
    with pytest.raises(AnalysisError, match="flywheel"):
        _dynamics(engine)
    with pytest.raises(AnalysisError, match="flywheel"):
        settings_of(engine)


def test_a_constant_load_must_be_the_mean_torque(inline4_gas):
    engine, result = inline4_gas
    mean = result.part("torque").mean
    with pytest.raises(
        AnalysisError,
        match=r"the engine stalls: its mean torque at 7000 rpm is 210 N m, the load 300 N m; "
        r"the speed falls to zero",
    ):
        _dynamics(engine, result, load=ConstantLoad(300.0))
    with pytest.raises(
        AnalysisError,
        match=r"no steady state: the engine accelerates \(mean torque 210 N m > load 30 N m\)",
    ):
        _dynamics(engine, result, load=ConstantLoad(30.0))
    ok = _dynamics(engine, result, load=ConstantLoad(mean * (1 + 1e-7))).part("dynamics")
    same = _dynamics(engine, result).part("dynamics")
    np.testing.assert_array_equal(ok.motion.speed, same.motion.speed)


def test_a_motored_engine_cannot_drive_a_load():
    engine = layout_from_dict(_single_with_gas(heat="0.001 kJ"))  # motored, in effect
    for load in (PropellerLoad(), PowerLawLoad(10.0, 100.0, 2.0)):
        with pytest.raises(
            AnalysisError, match=r"the engine cannot drive the load: its mean torque is -\d"
        ):
            _dynamics(engine, load=load)
    assert (
        _dynamics(engine).part("dynamics").load_torque < 0.0
    )  # the mean load: it coasts down and back


def test_without_gas_only_the_mean_load():
    engine = balance.load_layout("inline-4")
    for load in (PropellerLoad(), ConstantLoad(5.0), PowerLawLoad(1.0, 100.0, 2.0)):
        with pytest.raises(AnalysisError, match="no gas torque: the speed falls to zero"):
            _dynamics(engine, load=load, flywheel=Flywheel(0.1))
    _dynamics(engine, load=ConstantLoad(0.0), flywheel=Flywheel(0.1))


def test_sizing_refused_when_the_masses_alone_do():
    """v8-crossplane-gas without a flywheel varies by 8.7 %: asking for 20 % is refused."""
    engine = balance.load_layout("v8-crossplane-gas")
    with pytest.raises(
        AnalysisError, match=r"a speed fluctuation of 20 % needs no flywheel: .* varies by 8\.68 %"
    ):
        _dynamics(engine, flywheel=Flywheel(speed_fluctuation=0.2))


def test_a_power_law_needs_positive_values():
    with pytest.raises(InputError, match="exponent"):
        PowerLawLoad(10.0, 100.0, 0.0)
    with pytest.raises(InputError, match="torque"):
        PowerLawLoad(-1.0, 100.0, 2.0)


def test_warnings_near_stalling(single_idle):
    engine, result = single_idle
    out = _dynamics(engine, result, flywheel=Flywheel(0.004))
    part = out.part("dynamics")
    rules = {w.rule for w in part.warnings}
    assert part.speed_fluctuation > 0.2 and "speed_fluctuation" in rules
    assert all(w in out.warnings for w in part.warnings)
    text = next(w.message for w in part.warnings if w.rule == "speed_fluctuation")
    assert (
        text.startswith("the crank speed varies by") and "rpm): the engine is near stalling" in text
    )
    if part.speed_min < 0.5 * part.mean_speed:
        assert "lowest_speed" in rules
    calm = _dynamics(engine, result, flywheel=Flywheel(1.0)).part("dynamics")
    assert calm.warnings == ()


def test_a_power_law_far_from_the_trace_speed_is_warned(inline4_gas):
    engine, result = inline4_gas
    part = _dynamics(engine, result, load=PowerLawLoad(10.0, 100.0, 1.0)).part("dynamics")
    assert part.mean_speed > 2 * engine.speed
    (warning,) = [w for w in part.warnings if w.rule == "load_speed"]
    assert "times the layout's speed" in warning.message


def test_the_lowest_speed_warning():
    engine = layout_from_dict(_single_with_gas(heat="0.45 kJ", intake_pressure="0.8 bar"))
    part = _dynamics(engine, flywheel=Flywheel(0.0)).part("dynamics")
    assert part.speed_min < 0.5 * part.mean_speed
    assert "lowest_speed" in {w.rule for w in part.warnings}


# --------------------------------------------------------------------------- views


def test_json_block_has_the_documented_shape(inline4_gas):
    from balance.views.dynamics import json_block

    engine, result = inline4_gas
    out = _dynamics(engine, result, load=PropellerLoad())
    block = json_block(out)["dynamics"]
    json.dumps(block, allow_nan=False)
    assert list(block) == [
        "speed_model", "load", "mean_speed_rpm", "speed_min_rpm", "speed_max_rpm",
        "speed_fluctuation", "speed_fluctuation_constant_speed", "inertia_kgm2",
        "flywheel_inertia_kgm2", "samples", "force", "moment", "roll", "largest_difference",
    ]  # fmt: skip
    assert block["speed_model"] == "dynamic" and block["mean_speed_rpm"] == 7000.0
    assert set(block["load"]) == {"kind", "coefficient_Nms2"}
    assert block["speed_min_rpm"] < 7000.0 < block["speed_max_rpm"]
    assert list(block["samples"]) == [
        "crank_angle_deg",
        "speed_rpm",
        "acceleration_rad_s2",
        "time_s",
    ]
    assert block["samples"]["crank_angle_deg"] == list(map(float, range(720)))
    assert [e["order"] for e in block["force"]] == [
        k / 2 if k % 2 else k // 2 for k in range(1, 17)
    ]
    entry = block["force"][3]
    assert set(entry) == {
        "order",
        "forward",
        "backward",
        "peak",
        "peak_constant_speed",
        "difference",
    }
    assert set(block["roll"][0]) == {
        "order",
        "amplitude",
        "phase_deg",
        "amplitude_constant_speed",
        "difference",
    }
    # an even-firing inline-4 has no half orders, the dynamic model included
    assert all(e["peak"] == 0.0 for e in block["force"] if isinstance(e["order"], float))
    assert all(e["amplitude"] == 0.0 for e in block["roll"] if isinstance(e["order"], float))
    assert set(block["largest_difference"]) == {"force", "moment", "roll"}
    law = json_block(_dynamics(engine, result, load=PowerLawLoad(150.0, 600.0, 2.0)))["dynamics"]
    assert law["load"]["kind"] == "power_law" and law["load"]["at_rpm"] == pytest.approx(600 * RPM)


def test_two_stroke_orders_are_whole():
    data = _single_with_gas()
    data["cycle"] = "two-stroke"
    engine = layout_from_dict(data)
    part = _dynamics(engine).part("dynamics")
    np.testing.assert_array_equal(part.orders, ORDERS)
    assert part.cycle_deg == 360.0 and part.samples()["crank_angle"].size == 360


@pytest.fixture
def registered():
    """The section in the registries, for the writers that loop over them."""
    from balance.core import sections
    from balance.views import sections as views

    assert sections.section("dynamics").part == "balance.core.dynamics:dynamics_part"
    assert views.VIEWS["dynamics"] == "balance.views.dynamics"


def test_the_section_through_the_writers(registered, inline4_gas):
    from balance.views.dataset import build_dataset
    from balance.views.json import to_dict
    from balance.views.report import render_report

    engine, _ = inline4_gas
    request = REQUEST.with_sections(dynamics={"speed_model": "dynamic", "flywheel": Flywheel(0.03)})
    result = compute(engine, request)
    assert "dynamics" in result.parts
    ds = build_dataset(result)
    for name, var in ds.data_vars.items():
        if name.startswith("dynamics_"):
            assert var.attrs["units"] is not None and var.attrs["long_name"]
    assert ds.sizes["cycle_angle"] == 720 and ds.sizes["dynamics_order"] == 16
    assert ds["dynamics_speed_fluctuation"].item() == pytest.approx(
        result.part("dynamics").speed_fluctuation
    )
    assert ds.attrs["dynamics_load_kind"] == "mean"
    assert to_dict(result)["dynamics"]["speed_model"] == "dynamic"
    html = render_report(result, figures=False)
    assert "Variable crank speed" in html


def test_tables_plots_and_report(inline4_gas):
    from rich.console import Console

    from balance.views import dynamics as views

    engine, result = inline4_gas
    out = _dynamics(engine, result, flywheel=Flywheel(0.03), load=PowerLawLoad(200.0, 700.0, 2.0))
    console = Console(width=100, record=True)
    for table in views.tables(out):
        console.print(table)
    text = console.export_text()
    assert "power law" in text and "Roll torque per order" in text
    for kind, draw in views.PLOTS.items():
        fig = draw(out)
        assert fig.axes, kind
        note = draw(result)  # without the part: a note
        assert "no variable-speed analysis" in note.axes[0].texts[0].get_text()
    from balance.views.report import escape, html_table  # noqa: F401  (the report's helpers)

    html = views.report_section(out, figures=False)
    assert "<table>" in html and "periodic steady state" in html


def test_without_moments_and_roll_the_block_has_the_force_only(inline4_gas):
    from balance.views.dynamics import json_block

    engine, _ = inline4_gas
    request = Request.of(range(1, 5), moments=False, roll=False)
    result = compute(engine, request)
    part = dynamics_part(engine, request, result, speed_model="dynamic").part("dynamics")
    assert not part.has("moment") and not part.has("roll") and part.has("force")
    block = json_block(result.with_part("dynamics", part))["dynamics"]
    assert "moment" not in block and "roll" not in block
    assert set(block["largest_difference"]) == {"force"}
    assert [e["order"] for e in block["force"]] == [0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4]


@pytest.mark.parametrize("load", [PropellerLoad(), PowerLawLoad(600.0, 400.0, 1.5)])
def test_sizing_under_a_speed_dependent_load(load):
    """The flywheel is sized for the exact fluctuation whatever the load."""
    engine = balance.load_layout("v8-crossplane-gas")
    part = _dynamics(engine, load=load).part("dynamics")
    assert part.flywheel_sized
    assert part.speed_fluctuation == pytest.approx(0.01, rel=1e-9)


def test_the_power_law_stops_at_the_rounding_floor():
    """A cycle that hypothesis found (J = 0.03125 (1 + 0.25 cos θ/2) kg m², Q = 168 +
    cos θ/2 + 2 cos(2θ + 1) N m, a square law through 50 rad/s, as sampled in
    ``tests/data/power_law_rounding_floor.npz``): Newton's steps on the power law's
    steady state fall to 1e-14 to 2.5e-14 of the energy and stay there, the rounding of the
    closed-form linear solve, so the old test "below 1e-14" never passed and the analysis
    was refused.  It now stops there, and agrees with the propeller's exact solution."""
    data = np.load(Path(__file__).parent / "data" / "power_law_rounding_floor.npz")
    inertia, torque = data["inertia"], data["torque"]
    slope = _slope(inertia)
    law = periodic_motion(
        inertia, slope, torque, 4 * math.pi, PowerLaw(float(data["load_torque"]), 50.0, 2.0)
    )
    prop = periodic_motion(inertia, slope, torque, 4 * math.pi, Propeller(), 50.0)
    np.testing.assert_allclose(law.speed, prop.speed, rtol=1e-10)
    assert law.mean_speed == pytest.approx(50.0, rel=1e-10)
