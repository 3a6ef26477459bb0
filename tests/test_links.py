"""Articulated (master-and-link) rods: kinematics against mpmath, the whole engine against a
Newton–Euler solution of the rigid bodies, the limit of a vanishing pin radius, invariances,
the model ladder's bounds, dead centres, the ``cylinders`` list, studies and bad input."""

from __future__ import annotations

import dataclasses
import json
import math
import textwrap

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from oracles import block_force_newton_euler, crank_torque_newton_euler, crank_train_newton_euler
from typer.testing import CliRunner

from balance.api import analyse, load_layout
from balance.cli import app
from balance.core import bearings as bb
from balance.core import sampled as td
from balance.core.analysis import compute, compute_phasors
from balance.core.cylinders import dead_centres, engine_dead_centres
from balance.core.engine import Engine, Links
from balance.core.errors import InputError, LayoutError
from balance.core.kinematics import normalised_slider
from balance.core.links import (
    link_dead_centres,
    link_geometry,
    link_motion,
    link_reach,
)
from balance.core.result import Request
from balance.core.torque import compute_torque
from balance.io.layout_file import expand_layout, layout_from_text
from balance.io.request import build_request
from balance.studies.sweep import sweep, variant
from balance.views.json import to_dict

ORDERS = np.arange(1, 9)

# A small engine with every term switched on: master and link bores offset, link pins
# off the bank difference, every rod with its own inertia, a crank unbalance.
TWISTED = """\
name: twisted W3 with link rods
speed: 3000 rpm
geometry: {stroke: 100 mm, conrod_length: 210 mm, offset: 3 mm, bore: 90 mm}
masses: {piston_group: 0.9 kg, conrod: 1.6 kg, conrod_cg_to_big_end: 55 mm,
         conrod_inertia: 0.011 kg m^2, crank_unbalance: 0.4 kg}
cylinders:
  - {throw: 20 deg, bank: -50 deg, z: 0 mm}
  - {throw: 20 deg, bank: 10 deg, z: 0 mm, offset: -4 mm, conrod: 0.6 kg,
     conrod_cg_to_big_end: 60 mm, conrod_inertia: 3.1e-3 kg m^2,
     link: {master: 1, pin_radius: 45 mm, pin_angle: 66 deg, length: 168 mm}}
  - {throw: 20 deg, bank: 75 deg, z: 0 mm, conrod: 0.5 kg, conrod_cg_to_big_end: 62 mm,
     conrod_inertia: 2.2e-3 kg m^2,
     link: {master: 1, pin_radius: 40 mm, pin_angle: 118 deg, length: 172 mm}}
  - {throw: 200 deg, bank: -50 deg, z: 90 mm}
  - {throw: 200 deg, bank: 10 deg, z: 90 mm, conrod: 0.6 kg, conrod_cg_to_big_end: 60 mm,
     conrod_inertia: 3.1e-3 kg m^2,
     link: {master: 4, pin_radius: 45 mm, pin_angle: 60 deg, length: 168 mm}}
firing_order: [1, 2, 3, 4, 5]
"""
GAS = "gas:\n  model: {compression_ratio: 8.5, peak_pressure: 60 bar}\n"


def twisted(gas: bool = False) -> Engine:
    return layout_from_text(TWISTED + (GAS if gas else ""))


def _scale(engine: Engine) -> float:
    """m_rec r w^2 of the largest cylinder."""
    return float(np.max(engine.reciprocating_mass * engine.crank_radius) * engine.speed**2)


# --------------------------------------------------------------------------- kinematics

GEOMETRIES = [
    # lambda_m, eps_m, kappa, delta, shift, lambda_j, eps_j
    (0.26, 0.0, 0.8, 0.0, math.radians(40), 0.33, 0.0),  # a radial's link
    (0.28, 0.03, 0.69, math.radians(10.17), math.radians(60), 0.35, 0.0),  # the V-2's
    (0.35, -0.05, 1.1, -0.4, 2.2, 0.3, 0.06),  # everything at once
]


def _mp_position(params: tuple[float, ...]) -> object:
    lam_m, eps_m, kappa, delta, shift, lam, eps = (mpmath.mpf(p) for p in params)

    def s(beta: object) -> object:
        gamma = mpmath.asin(lam_m * (mpmath.sin(beta + shift) - eps_m))
        pin_y = mpmath.cos(beta) + kappa * mpmath.cos(delta - gamma)
        pin_x = mpmath.sin(beta) + kappa * mpmath.sin(delta - gamma)
        return pin_y + mpmath.sqrt(1 - (lam * (pin_x - eps)) ** 2) / lam

    return s


@pytest.mark.parametrize("params", GEOMETRIES)
def test_link_piston_position_and_acceleration_against_mpmath(params):
    """The closed form's position, velocity and acceleration (per r) equal 40-digit mpmath
    derivatives of the geometry (link triangle from the master rod's angle) to 1e-12."""
    s = _mp_position(params)
    beta = np.array([0.0, 0.7, 1.9, 3.3, 5.1])
    motion = link_motion(beta, *params)
    with mpmath.workdps(40):
        want = np.array([[float(mpmath.diff(s, mpmath.mpf(b), n)) for b in beta] for n in range(3)])
    np.testing.assert_allclose(motion.s, want[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(motion.ds, want[1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(motion.d2s, want[2], rtol=0, atol=1e-12)


def test_link_pin_acceleration_against_mpmath():
    """The link pin's acceleration (what its mass puts on the block) against mpmath."""
    lam_m, eps_m, kappa, delta, shift = (mpmath.mpf(p) for p in GEOMETRIES[2][:5])

    def pin(beta: object, part: int) -> object:
        gamma = mpmath.asin(lam_m * (mpmath.sin(beta + shift) - eps_m))
        if part == 0:
            return mpmath.cos(beta) + kappa * mpmath.cos(delta - gamma)
        return mpmath.sin(beta) + kappa * mpmath.sin(delta - gamma)

    beta = np.array([0.3, 2.0, 4.6])
    motion = link_motion(beta, *GEOMETRIES[2])
    with mpmath.workdps(40):
        y = [float(mpmath.diff(lambda b: pin(b, 0), mpmath.mpf(b), 2)) for b in beta]
        x = [float(mpmath.diff(lambda b: pin(b, 1), mpmath.mpf(b), 2)) for b in beta]
    np.testing.assert_allclose(motion.d2pin_y, y, rtol=0, atol=1e-12)
    np.testing.assert_allclose(motion.d2pin_x, x, rtol=0, atol=1e-12)


def test_without_pin_radius_a_link_piston_is_a_plain_slider():
    beta = np.linspace(0.0, 2.0 * np.pi, 37)
    motion = link_motion(beta, 0.3, 0.02, 0.0, 0.9, 1.3, 0.27, -0.04)
    s, ds, d2s = normalised_slider(beta, 0.27, -0.04)
    np.testing.assert_allclose(motion.s, s, rtol=0, atol=4e-16 * 5)
    np.testing.assert_allclose(motion.ds, ds, rtol=0, atol=4e-16)
    np.testing.assert_allclose(motion.d2s, d2s, rtol=0, atol=4e-16)


# --------------------------------------------------------------------------- Newton–Euler


@pytest.mark.parametrize("name", ["twisted", "radial-9", "v12-60-articulated"])
def test_forces_moments_and_roll_equal_newton_euler_of_the_rigid_bodies(name):
    """The phasors (exact model) against the FFT of a Newton–Euler solution of every rigid
    body (pistons, master rods with their link pins, link rods), whose block force is the
    walls' and mains' and whose roll is the walls' moment, to 1e-10 of m_rec r w^2."""
    engine = twisted() if name == "twisted" else load_layout(name)
    result = compute_phasors(engine, ORDERS)
    theta = td.crank_angles(256)
    force, moment = block_force_newton_euler(engine, theta, small_end_share=0.25)
    f_fwd, f_bwd = td.phasors_from_samples(force, ORDERS)
    m_fwd, m_bwd = td.phasors_from_samples(moment, ORDERS)
    first = (ORDERS == 1).astype(float)
    tol = 1e-10 * _scale(engine)
    np.testing.assert_allclose(
        f_fwd, result.phasors.force_forward + first * result.phasors.rotating_force, atol=tol
    )
    np.testing.assert_allclose(f_bwd, result.phasors.force_backward, atol=tol)
    span = max(float(np.ptp(engine.z)), 0.1)
    np.testing.assert_allclose(
        m_fwd,
        result.phasors.moment_forward + first * result.phasors.rotating_moment,
        atol=tol * span,
    )
    np.testing.assert_allclose(m_bwd, result.phasors.moment_backward, atol=tol * span)
    roll = td.roll_phasors_from_samples(td.roll_newton_euler(engine, theta, 0.4, 0.2), ORDERS)
    np.testing.assert_allclose(
        roll, result.phasors.roll, atol=tol * float(np.max(engine.crank_radius))
    )


def test_newton_euler_does_not_depend_on_how_the_masses_are_split():
    """Static equivalence: pistons, rods and their centres of gravity chosen two ways give
    the same walls' roll and block force (the rods' inertias follow their corrections)."""
    engine = twisted()
    theta = td.crank_angles(64)
    a = td.articulated_newton_euler(engine, theta, 0.2, 0.4)
    b = td.articulated_newton_euler(engine, theta, 0.6, 0.15)
    scale = _scale(engine)
    np.testing.assert_allclose(a.roll, b.roll, atol=1e-11 * scale * 0.05)
    np.testing.assert_allclose(a.block_force, b.block_force, atol=1e-11 * scale)


def test_time_model_is_the_exact_model_for_link_engines():
    """The time model (constraint kinematics, Newton–Euler roll) against the exact model:
    phasors, each link piston's coefficients and each link pin's phasors."""
    engine = twisted()
    exact = compute_phasors(engine, ORDERS)
    sampled = compute_phasors(engine, ORDERS, model="time", samples=512)
    tol = 1e-10 * _scale(engine)
    for name in ("force_forward", "force_backward", "moment_forward", "moment_backward"):
        np.testing.assert_allclose(
            getattr(sampled.phasors, name), getattr(exact.phasors, name), atol=tol
        )
    np.testing.assert_allclose(sampled.phasors.roll, exact.phasors.roll, atol=tol * 0.05)
    np.testing.assert_allclose(sampled.coefficients, exact.coefficients, atol=1e-12)
    assert exact.link_pins.force_forward is not None and sampled.link_pins.force_forward is not None
    np.testing.assert_allclose(
        sampled.link_pins.force_forward, exact.link_pins.force_forward, atol=tol
    )


def test_pin_loads_equal_newton_euler_with_and_without_gas():
    """CONTRACT §6: the crank-pin load of a master-and-link throw is the master rod's big-end
    force; the closed form (two-mass rods and inertia corrections) against the rigid-body
    solution, over the four-stroke cycle with the gas forces, to 1e-12."""
    engine = twisted(gas=True)
    theta = np.linspace(0.0, 4.0 * np.pi, 91, endpoint=False)
    for gas in (None, bb.gas_forces(engine, theta)):
        got = bb.big_end_forces(engine, theta, gas)
        for share in (0.2, 0.5):
            solution = td.articulated_newton_euler(
                engine, theta, share, None, None if gas is None else gas.T
            )
            want = solution.pin_force
            np.testing.assert_allclose(got[[0, 3]], want, atol=1e-12 * np.abs(want).max())
        assert np.all(got[[1, 2, 4]] == 0.0)
    result = compute(twisted(), build_request(twisted(), bearings=True))
    assert result.part("bearings") is not None and result.part("bearings").loads.pin_cylinders == (
        (1, 2, 3),
        (4, 5),
    )
    assert np.all(result.part("bearings").loads.pin_max > 0)


def test_gas_torque_and_roll_equal_newton_euler():
    """With gas forces on every piston (the model's pressure over each link piston's own
    volume curve), the engine torque and the roll against the rigid-body solution with the
    rods' real inertias, for two splits of the rods, to 1e-10; and every cylinder's side
    thrust and rod force, each crank pin's tangential and radial force (the master's plus
    what its link rods pass through it) against the same solution."""
    engine = twisted(gas=True)
    assert np.all(engine.conrod_inertia_correction != 0.0)
    result = compute_torque(engine, ORDERS)
    theta = np.radians(result.crank_angle[::8])
    gas = result.gas_force[:, ::8].T
    roll = td.roll_newton_euler(engine, theta, gas_force=gas)
    scale = float(np.max(np.abs(result.roll_torque)))
    np.testing.assert_allclose(roll, result.roll_torque[::8], atol=1e-10 * scale)
    scale = float(np.max(np.abs(result.engine_torque)))
    for share, cg in ((0.3, 0.3), (0.45, 0.2)):
        torque = crank_torque_newton_euler(
            engine, theta, gas_force=gas, small_end_share=share, cg_fraction=cg
        )
        np.testing.assert_allclose(torque, result.engine_torque[::8], atol=1e-10 * scale)
    rigid = crank_train_newton_euler(engine, theta, gas, small_end_share=0.0)
    for got, want in ((rigid.wall, result.side_thrust), (rigid.rod_force, result.rod_force)):
        np.testing.assert_allclose(got.T, want[:, ::8], atol=1e-10 * np.max(np.abs(want)))
    rigid = crank_train_newton_euler(engine, theta, gas, 1.0 / 3.0, 0.3)
    assert engine.links is not None
    for m in engine.links.masters.tolist():
        on_pin = [m, *np.flatnonzero(engine.links.master == m)]
        force = rigid.pin_force[:, m] * np.exp(-1j * (theta + engine.throw[m]))
        small = engine.reciprocating_mass[m] / 3.0
        big_end = (small / 0.3 - small) * engine.crank_radius[m] * engine.speed**2
        for got, name in (
            (force.imag, "tangential_force"),
            (-force.real + big_end, "radial_force"),
        ):
            want = getattr(result, name)[on_pin][:, ::8].sum(axis=0)
            np.testing.assert_allclose(got, want, atol=1e-10 * np.max(np.abs(want)))
    # a link cylinder's torque is its tangential force times r: what its link rod passes
    # through the master rod to the pin, by virtual work
    np.testing.assert_allclose(
        result.cylinder_torque, result.tangential_force * engine.crank_radius[:, None], rtol=1e-15
    )


def test_a_link_cylinder_fires_at_its_actual_top_dead_centre():
    """Firing TDCs follow the firing order, every cylinder's at its actual TDC (not the
    nominal bank - throw): the link cylinders' and the offset masters' alike."""
    engine = twisted(gas=True)
    assert engine.gas is not None
    _, tdc = engine_dead_centres(engine)
    firing = engine.gas.firing_tdc
    np.testing.assert_allclose(np.mod(firing, 360.0), np.degrees(tdc), atol=1e-9)
    nominal = np.mod(np.degrees(engine.bank - engine.throw), 360.0)
    assert np.all(np.abs(np.mod(firing, 360.0) - nominal) > 0.1)
    # order 1-2-3-4-5: each fires after the one before, within one cycle
    assert np.all(np.diff(firing) > 0) and firing[-1] - firing[0] < 720.0


# --------------------------------------------------------------------------- limit


def _on_one_pin(rho: float, pin_angles: bool = True) -> tuple[Engine, Engine]:
    """A 5-cylinder radial with link rods of pin radius ``rho``, and the same engine with
    every rod (same length, mass, centre of gravity, inertia) on the crank pin."""
    head = textwrap.dedent(
        """\
        name: limit
        speed: 2000 rpm
        geometry: {stroke: 130 mm, conrod_length: 250 mm}
        masses: {piston_group: 1.0 kg, conrod: 2.2 kg, conrod_cg_to_big_end: 50 mm,
                 conrod_inertia: 0.012 kg m^2}
        cylinders:
          - {throw: 0 deg, bank: 0 deg, z: 0 mm}
        """
    )
    linked, plain = head, head
    for i in range(1, 5):
        bank = 72 * i
        rod = "conrod: 0.7 kg, conrod_cg_to_big_end: 80 mm, conrod_inertia: 4e-3 kg m^2"
        angle = bank if pin_angles else bank + 7
        linked += (
            f"  - {{throw: 0 deg, bank: {bank} deg, z: 0 mm, {rod}, link: {{master: 1, "
            f"pin_radius: {rho * 1e3!r} mm, pin_angle: {angle} deg, length: 200 mm}}}}\n"
        )
        plain += f"  - {{throw: 0 deg, bank: {bank} deg, z: 0 mm, {rod}, conrod_length: 200 mm}}\n"
    return layout_from_text(linked), layout_from_text(plain)


def test_vanishing_pin_radius_is_the_all_on_one_pin_engine():
    """pin_radius -> 0 with pin_angle = bank difference: the link engine is the engine with
    all rods on one pin, to rounding (forces, rotating forces, roll, strokes, TDCs); the
    difference grows linearly with the pin radius."""
    linked, plain = _on_one_pin(0.0)
    a, b = compute_phasors(linked, ORDERS), compute_phasors(plain, ORDERS)
    tol = 1e-13 * _scale(plain)
    for name in ("force_forward", "force_backward", "roll"):
        np.testing.assert_allclose(getattr(a.phasors, name), getattr(b.phasors, name), atol=tol)
    assert abs(a.phasors.rotating_force - b.phasors.rotating_force) <= tol
    stroke, tdc = engine_dead_centres(linked)
    np.testing.assert_allclose(stroke, 0.13, rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.degrees(tdc), [0, 72, 144, 216, 288], rtol=0, atol=1e-12)
    gaps = []
    for rho in (1e-7, 1e-6):
        small, _ = _on_one_pin(rho)
        gaps.append(
            np.max(
                np.abs(
                    compute_phasors(small, ORDERS).phasors.force_forward - b.phasors.force_forward
                )
            )
        )
    assert 8.0 < gaps[1] / gaps[0] < 12.0


# --------------------------------------------------------------------------- invariances


@st.composite
def link_engines(draw: st.DrawFn) -> Engine:
    """A master with one to three link rods, and a plain cylinder on another throw."""
    n_links = draw(st.integers(1, 3))
    n = n_links + 2
    r = draw(st.floats(0.03, 0.08))
    lam_m = draw(st.floats(0.15, 0.35))
    banks = [draw(st.floats(-180, 180)) for _ in range(n)]
    kappa = [draw(st.floats(0.0, 1.0)) for _ in range(n_links)]
    lam = [draw(st.floats(0.12, 0.3)) for _ in range(n_links)]
    master = np.full(n, -1, dtype=np.intp)
    master[1 : n_links + 1] = 0
    pin_radius = np.zeros(n)
    pin_radius[1 : n_links + 1] = np.asarray(kappa) * r
    pin_angle = np.zeros(n)
    pin_angle[1 : n_links + 1] = np.radians(
        np.asarray(banks[1 : n_links + 1]) - banks[0] + draw(st.floats(-15, 15))
    )
    length = np.full(n, r / lam_m)
    length[1 : n_links + 1] = r / np.asarray(lam)
    throw = np.zeros(n)
    throw[-1] = math.radians(draw(st.floats(0, 360)))
    z = np.zeros(n)
    z[-1] = 0.1
    return Engine(
        name="random links",
        speed=draw(st.floats(50.0, 800.0)),
        throw=throw,
        bank=np.radians(banks),
        z=z,
        crank_radius=np.full(n, r),
        conrod_length=length,
        offset=np.asarray([draw(st.floats(-0.004, 0.004)) for _ in range(n)]),
        reciprocating_mass=np.asarray([draw(st.floats(0.3, 2.0)) for _ in range(n)]),
        rotating_mass=np.asarray([draw(st.floats(0.1, 2.0)) for _ in range(n)]),
        conrod_inertia_correction=np.asarray([draw(st.floats(-2e-3, 2e-3)) for _ in range(n)]),
        reference_z=0.05,
        pitch=0.1,
        links=Links(master=master, pin_radius=pin_radius, pin_angle=pin_angle),
    )


@settings(max_examples=12, deadline=None)
@given(engine=link_engines(), shift=st.floats(-360, 360))
def test_crank_angle_origin_only_turns_the_phasors(engine, shift):
    delta = math.radians(shift)
    a = compute_phasors(engine, ORDERS)
    b = compute_phasors(dataclasses.replace(engine, throw=engine.throw + delta), ORDERS)
    tol = 1e-12 * _scale(engine)
    turn = np.exp(1j * ORDERS * delta)
    np.testing.assert_allclose(b.phasors.force_forward, a.phasors.force_forward * turn, atol=tol)
    np.testing.assert_allclose(b.phasors.force_backward, a.phasors.force_backward / turn, atol=tol)
    np.testing.assert_allclose(
        b.phasors.moment_backward, a.phasors.moment_backward / turn, atol=tol
    )
    np.testing.assert_allclose(b.phasors.roll, a.phasors.roll * turn, atol=tol * 0.1)


@settings(max_examples=12, deadline=None)
@given(engine=link_engines(), seed=st.integers(0, 2**32 - 1))
def test_renumbering_cylinders_keeps_every_master(engine, seed):
    order = np.random.default_rng(seed).permutation(engine.n_cylinders)
    renumbered = engine.reordered(order)
    assert renumbered.links is not None and engine.links is not None
    for new, old in enumerate(order):
        m_old, m_new = engine.links.master[old], renumbered.links.master[new]
        assert (m_old < 0 and m_new < 0) or order[m_new] == m_old
    a, b = compute_phasors(engine, ORDERS), compute_phasors(renumbered, ORDERS)
    tol = 1e-12 * _scale(engine)
    for name in ("force_forward", "force_backward", "moment_forward", "moment_backward", "roll"):
        np.testing.assert_allclose(getattr(b.phasors, name), getattr(a.phasors, name), atol=tol)
    sa, ta = engine_dead_centres(engine)
    sb, tb = engine_dead_centres(renumbered)
    np.testing.assert_allclose(sb, sa[order], rtol=1e-14)
    np.testing.assert_allclose(tb, ta[order], atol=1e-12)


# --------------------------------------------------------------------------- model ladder


def _measured_error(engine: Engine, model: str, **options: object) -> float:
    """Largest error of a model's coefficients per cylinder, in units of m_rec r w^2 per
    G_k (the bounds' units): |dG| plus, for link pins the model leaves out, 2|P|/(m r w^2)."""
    exact = compute_phasors(engine, ORDERS)
    got = compute_phasors(engine, ORDERS, model=model, **options)  # type: ignore[arg-type]
    error = np.abs(got.coefficients - exact.coefficients)
    unit = (engine.reciprocating_mass * engine.crank_radius * engine.speed**2)[:, None]
    assert exact.link_pins.force_forward is not None and exact.link_pins.force_backward is not None
    pin = got.link_pins.force_forward
    if pin is None:  # the model leaves the link pins' relative motion out
        error = (
            error
            + 2.0
            * np.maximum(
                np.abs(exact.link_pins.force_forward), np.abs(exact.link_pins.force_backward)
            )
            / unit
        )
    return float(error.max())


@pytest.mark.parametrize("name", ["twisted", "radial-9", "v12-60-articulated"])
def test_model_ladder_bounds_hold_for_link_engines(name):
    engine = twisted() if name == "twisted" else load_layout(name)
    for model, options in (
        ("textbook", {}),
        ("series", {"terms": 1}),
        ("series", {"terms": 4}),
        ("time", {"samples": 17}),  # aliasing well above rounding
        ("time", {"samples": 24}),
    ):
        bound = compute_phasors(engine, ORDERS, model=model, **options).model.error_bound
        measured = _measured_error(engine, model, **options)
        assert measured <= bound, (model, options, measured, bound)
    # the exact model against a fine time-domain reference
    reference = compute_phasors(engine, ORDERS, model="time", samples=4096)
    exact = compute_phasors(engine, ORDERS)
    gap = np.abs(exact.coefficients - reference.coefficients).max()
    assert gap <= exact.model.error_bound


def test_tolerance_picks_a_model_whose_bound_holds_for_links():
    engine = load_layout("radial-5")
    loose = compute(engine, Request(tolerance=10.0))
    assert loose.request.model == "textbook"
    assert _measured_error(engine, "textbook") <= loose.model.error_bound <= 10.0
    tight = compute(engine, Request(tolerance=1e-9))
    assert tight.request.model == "exact"


# --------------------------------------------------------------------------- dead centres


def test_dead_centres_of_plain_sliders_in_closed_form_and_by_newton():
    """The closed form (rod and crank in line) against the Newton search that link pistons
    use, run with a zero pin radius on offset plain sliders."""
    r, length, e = 0.05, np.array([0.15, 0.2, 0.12]), np.array([0.004, -0.01, 0.0])
    stroke, tdc = dead_centres(np.zeros(3), np.zeros(3), np.full(3, r), length, e)
    links = Links(np.array([-1, 0, 0]), np.zeros(3), np.zeros(3))
    geometry = link_geometry(np.full(3, r), length, e, np.zeros(3), links)
    top, s_top, s_bottom = link_dead_centres(geometry)
    np.testing.assert_allclose(r * (s_top - s_bottom), stroke[1:], rtol=1e-14)
    np.testing.assert_allclose(top, tdc[1:], atol=1e-13)
    assert stroke[2] == 2 * r and tdc[2] == 0.0


def test_link_dead_centres_are_the_extremes_of_the_piston():
    engine = load_layout("v12-60-articulated")
    stroke, tdc = engine_dead_centres(engine)
    theta = np.linspace(0.0, 2.0 * np.pi, 20001)
    j, motion = _motion(engine, theta)
    s = motion.s * engine.crank_radius[j][:, None]
    sampled = s.max(axis=1) - s.min(axis=1)  # can only fall short of the true extremes
    assert np.all(stroke[j] >= sampled) and np.all(stroke[j] - sampled <= 1e-8)
    _, at_top = _motion(engine, tdc)
    on_diagonal = at_top.ds[np.arange(j.size), j]
    np.testing.assert_allclose(on_diagonal, 0.0, atol=1e-14)
    # the published stroke of the V-2's articulated bank (en.wikipedia.org Kharkiv model
    # V-2): 186.7 mm, which the layout's estimated pin angle is chosen to give
    np.testing.assert_allclose(stroke[j], 0.1867, atol=5e-5)
    np.testing.assert_allclose(stroke[::2], 0.18, rtol=0, atol=1e-15)


def _motion(engine: Engine, theta: np.ndarray):
    """The link cylinders' indices and their LinkMotion at the crank angles (links, angles)."""
    from balance.core.links import engine_geometry

    geometry = engine_geometry(engine)
    j = geometry.cylinder
    beta = (
        np.asarray(theta, dtype=np.float64)[None, :] + (engine.throw[j] - engine.bank[j])[:, None]
    )
    return j, link_motion(beta, *geometry.columns())


def test_impossible_link_geometry_is_found():
    links = Links(np.array([-1, 0]), np.array([0.0, 0.06]), np.radians([0.0, 90.0]))
    geometry = link_geometry(
        np.full(2, 0.05), np.array([0.2, 0.045]), np.zeros(2), np.radians([0.0, 90.0]), links
    )
    assert link_reach(geometry)[0] >= 1.0


# --------------------------------------------------------------------------- results


def test_json_lists_every_cylinder_with_stroke_and_tdc():
    result = compute(load_layout("radial-9"), Request(orders=(1, 2)))
    data = json.loads(json.dumps(to_dict(result)))
    cylinders = data["cylinders"]
    assert [c["number"] for c in cylinders] == list(range(1, 10))
    assert cylinders[0] == {"number": 1, "stroke_m": 0.13, "tdc_crank_deg": 0.0}
    assert all(0.0 <= c["tdc_crank_deg"] < 360.0 for c in cylinders)
    assert all(c["stroke_m"] > 0.13 for c in cylinders[1:])
    assert cylinders[4]["link"] == {
        "master": 1,
        "pin_radius_m": pytest.approx(0.052, rel=1e-15),
        "pin_angle_deg": pytest.approx(160.0, abs=1e-12),
        "length_m": 0.198,
    }
    # offsets move a plain cylinder's TDC and stroke too
    plain = load_layout("inline-4")
    stroke, tdc = engine_dead_centres(dataclasses.replace(plain, offset=np.full(4, 0.003)))
    r, length, e = plain.crank_radius[0], plain.conrod_length[0], 0.003  # rod and crank in line
    want = math.sqrt((length + r) ** 2 - e**2) - math.sqrt((length - r) ** 2 - e**2)
    np.testing.assert_allclose(stroke, want, rtol=1e-15)
    assert want > 2 * r
    np.testing.assert_allclose(
        np.degrees(tdc[[0, 3]]), math.degrees(math.asin(e / (length + r))), rtol=1e-14
    )


def test_table_report_and_dataset_show_the_cylinders():
    from balance.views.cylinders import cylinders_table
    from balance.views.report import render_report

    result = compute(load_layout("radial-5"), Request(orders=(1, 2)))
    ds = analyse(load_layout("radial-5"), "1-2")
    np.testing.assert_array_equal(ds.cylinder_stroke.values, result.part("cylinders").stroke)
    assert ds.tdc_crank_angle.attrs["units"] == "deg"
    assert list(ds.link_master.values) == [0, 1, 1, 1, 1]
    from rich.console import Console

    console = Console(width=160, record=True)
    console.print(cylinders_table(result))
    text = console.export_text()
    rows = {
        cells[0]: cells
        for line in text.splitlines()
        if line.startswith("│")
        for cells in [[c.strip() for c in line.strip("│").split("│")]]
    }
    assert rows["2"] == ["2", "133.527", "74.3332", "link rod", "1", "58", "72", "197"]
    assert "master rod, 4 link(s)" in text
    html = render_report(result, figures=False)
    assert "actual stroke [mm]" in html and "on cylinder 1&#x27;s rod" in html


def test_expansion_shows_the_link_geometry_and_loads_back(tmp_path):
    path = tmp_path / "twisted.yaml"
    path.write_text(TWISTED)
    text = expand_layout(path)
    assert "link: {master: 1, pin_radius: 45 mm, pin_angle: 66 deg, length: 168 mm}" in text
    assert "#   cylinder 2: link rod on cylinder 1's rod; stroke" in text
    again = layout_from_text(text)
    original = load_layout(path)
    assert again.links is not None and original.links is not None
    np.testing.assert_array_equal(again.links.master, original.links.master)
    np.testing.assert_allclose(again.links.pin_angle, original.links.pin_angle, rtol=1e-15)
    for name in ("conrod_length", "reciprocating_mass", "rotating_mass", "offset"):
        np.testing.assert_allclose(getattr(again, name), getattr(original, name), rtol=1e-15)


def test_proposal_and_factor_study_take_the_link_pins_first_order():
    """The counterweights take the whole forward first order (link pins included); the
    balance-factor study's residual equals the phasors with the counterweight added."""
    from balance.core.factor_study import factor_study

    engine = load_layout("radial-5")
    result = compute(engine, Request())
    assert result.part("proposal") is not None
    assert result.part("proposal").residual.force_forward[0] == 0.0
    study = factor_study(engine, [0.0, 0.5])
    p = result.phasors
    w2 = engine.speed**2
    for i, factor in enumerate((0.0, 0.5)):
        cw = factor * np.sum(engine.reciprocating_mass * engine.crank_radius) * w2
        fwd = p.force_forward[0] - cw  # the rotating masses are balanced in full
        vertical = abs(fwd + np.conj(p.force_backward[0]))
        assert float(study.vertical_peak[i]) == pytest.approx(vertical, rel=1e-12)


# --------------------------------------------------------------------------- studies


def test_speed_and_mass_sweeps_equal_single_analyses_bit_for_bit():
    engine = load_layout("radial-5")
    vary = {"speed": "1000rpm,2500rpm", "cylinders[3].conrod": "0.6kg,0.8kg"}
    ds = sweep(engine, vary, "1-4")
    for i, j in np.ndindex(2, 2):
        at = ds.isel(speed=i, cylinder3_conrod=j)
        point = {"speed": float(at.speed), "cylinders[3].conrod": float(at.cylinder3_conrod)}
        ref = analyse(variant(engine, point), "1-4", proposal=False)
        for name in at.data_vars:
            assert np.array_equal(at[name].values, ref[name].values), name


@pytest.mark.parametrize(
    ("field", "why"),
    [
        ("conrod_length=200mm,220mm", "moves the link kinematics"),
        ("cylinders[2].bank=70deg,74deg", "moves the link kinematics"),
        ("masses.conrod=2kg,3kg", "vary cylinders[N].conrod instead"),
        ("cylinders[2].reciprocating=1kg,2kg", "given by part"),
    ],
)
def test_studies_refuse_what_they_cannot_do_exactly_on_link_engines(field, why):
    with pytest.raises(InputError) as info:
        sweep(load_layout("radial-5"), [field])
    text = str(info.value)
    assert text.startswith(field.split("=")[0] + ": cannot be varied on an engine with link rods")
    assert why in text and "\n" not in text


def test_mounts_take_the_link_engines_forces():
    """The mounts are loaded with the link engine's free forces (link pins included) and
    roll: the loads per order are the result's phasors."""
    from balance.core.mount_loads import order_loads

    engine = load_layout("radial-5").with_section(
        "mounts", load_layout("inline-4-mounts").section("mounts")
    )
    result = compute(engine, build_request(engine, mounts=True))
    assert result.part("mounts") is not None and result.roll is not None
    _, ff, fb, _, _, roll = order_loads(result)
    p = result.phasors
    np.testing.assert_array_equal(ff[1:8], p.force_forward[1:])
    np.testing.assert_array_equal(fb[:8], p.force_backward)
    np.testing.assert_array_equal(roll[:8], result.roll)
    assert ff[0] == p.force_forward[0] + p.rotating_force and abs(fb[0]) > 0


# --------------------------------------------------------------------------- bad input

BAD_BASE = """\
name: bad links
speed: 2000 rpm
geometry: {stroke: 100 mm, conrod_length: 200 mm}
masses: {piston_group: 1 kg, conrod: 2 kg, conrod_cg_to_big_end: 50 mm}
cylinders:
  - {throw: 0 deg, bank: 0 deg, z: 0 mm}
  - {throw: 0 deg, bank: 90 deg, z: 0 mm, conrod: 0.6 kg, conrod_cg_to_big_end: 40 mm,
     link: {master: 1, pin_radius: 40 mm, pin_angle: 90 deg, length: 160 mm}}
"""


@pytest.mark.parametrize(
    ("old", "new", "where", "message"),
    [
        ("master: 1,", "master: 3,", ":8:21: cylinders[2].link.master:", "master 3 is not a"),
        ("master: 1,", "master: 0,", ":8:21: cylinders[2].link.master:", "master is 0"),
        ("master: 1,", "master: 2,", ":8:21: cylinders[2].link.master:", "names itself"),
        ("master: 1,", "master: one,", ":8:21: cylinders[2].link.master:", "whole number"),
        (
            "{throw: 0 deg, bank: 90",
            "{throw: 10 deg, bank: 90",
            ":7:13: cylinders[2].throw:",
            "its throw is 10 deg, the master's 0 deg",
        ),
        (
            "bank: 90 deg, z: 0 mm",
            "bank: 90 deg, z: 5 mm",
            ":7:37: cylinders[2].z:",
            "its z is 5 mm",
        ),
        (
            "length: 160 mm",
            "length: 45 mm",
            ":8:70: cylinders[2].link.length:",
            "cannot reach its piston",
        ),
        (
            "z: 0 mm, conrod: 0.6 kg",
            "z: 0 mm, reciprocating: 1 kg, conrod: 0.6 kg",
            ":7:58: cylinders[2].reciprocating:",
            "lumped 'reciprocating' on link cylinder 2",
        ),
        (
            "conrod: 0.6 kg, conrod_cg",
            "conrod_length: 170 mm, conrod: 0.6 kg, conrod_cg",
            ":7:58: cylinders[2].conrod_length:",
            "'conrod_length' on link cylinder 2",
        ),
        ("conrod: 0.6 kg, ", "", ":7:5: cylinders[2].conrod:", "gives no 'conrod'"),
        (
            "pin_radius: 40 mm",
            "pin_radius: -4 mm",
            ":8:36: cylinders[2].link.pin_radius:",
            "pin_radius must be zero or more",
        ),
        (
            "length: 160 mm}",
            "lenght: 160 mm}",
            ":8:62: cylinders[2].link.lenght:",
            "unknown key 'lenght'",
        ),
    ],
)
def test_bad_link_entries_name_line_column_and_field(tmp_path, old, new, where, message):
    path = tmp_path / "bad.yaml"
    assert old in BAD_BASE
    path.write_text(BAD_BASE.replace(old, new, 1))
    with pytest.raises(LayoutError) as info:
        load_layout(path)
    text = str(info.value)
    assert text.startswith(f"{path}{where}"), text
    assert message in text


def test_a_master_that_hangs_on_another_rod_is_refused(tmp_path):
    text = BAD_BASE + (
        "  - {throw: 0 deg, bank: 180 deg, z: 0 mm, conrod: 0.6 kg, conrod_cg_to_big_end: 60 mm,\n"
        "     link: {master: 2, pin_radius: 40 mm, pin_angle: 180 deg, length: 160 mm}}\n"
    )
    with pytest.raises(LayoutError) as info:
        layout_from_text(text, "f.yaml")
    assert "f.yaml:10:21: cylinders[3].link.master: cylinder 2 is itself a link cylinder" in str(
        info.value
    )


def test_link_cylinders_need_masses_by_part(tmp_path):
    text = BAD_BASE.replace(
        "masses: {piston_group: 1 kg, conrod: 2 kg, conrod_cg_to_big_end: 50 mm}",
        "masses: {reciprocating: 1.5 kg, rotating: 1 kg}",
    )
    with pytest.raises(LayoutError) as info:
        layout_from_text(text, "f.yaml")
    assert (
        "f.yaml:8:12: cylinders[2].link: cylinder 2 has a link rod, but the engine's masses"
        in str(info.value)
    )


def test_cli_error_for_a_bad_link_is_one_line(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text(BAD_BASE.replace("master: 1,", "master: 7,"))
    result = CliRunner().invoke(app, ["analyse", str(path)])
    assert result.exit_code == 2
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "cylinders[2].link.master: master 7 is not a cylinder" in lines[0]


def test_idealised_radials_are_kept_for_teaching():
    for n in (3, 5, 7, 9):
        ideal = load_layout(f"radial-{n}-idealised")
        real = load_layout(f"radial-{n}")
        assert not ideal.has_links and real.has_links
        assert ideal.n_cylinders == real.n_cylinders == n
