"""Free forces and moments: literature values, brute force and invariances."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from helpers import engine
from hypothesis import given
from hypothesis import strategies as st

from balance.api import Engine, analyse, load_layout
from balance.core import kinematics as kin
from balance.core import sampled as td
from balance.core.analysis import compute_phasors

ORDERS = np.arange(1, 9)


def f1(layout: Engine) -> float:
    return float(layout.reciprocating_mass[0] * layout.crank_radius[0] * layout.speed**2)


# --- literature values (Taylor 1985, vol. 2, ch. 8; Kolchin and Demidov 1984) ------------


def test_inline4_flat_crank_second_order_force_only():
    """Inline-4, flat crank: 2nd-order force 4 A2 F1 (textbook 4 lambda F1), nothing else
    in orders 1-3; no free moments at all (mirror-symmetric crank)."""
    layout = engine([0, 180, 180, 0])
    lam = 0.043 / 0.143
    ds = analyse(layout)
    a2 = float(kin.series_coefficients_centred(lam, 30, 2))
    peak = ds.reciprocating_force_peak_normalised
    assert float(peak.sel(order=2)) == pytest.approx(4 * a2, rel=1e-12)
    # forward and backward halves: the force is a straight line (vertical)
    mags = ds.reciprocating_force_magnitude.sel(order=2) / f1(layout)
    np.testing.assert_allclose(mags, [2 * a2, 2 * a2], rtol=1e-12)
    assert float(peak.sel(order=1)) == 0.0 and float(peak.sel(order=3)) == 0.0
    assert float(ds.reciprocating_moment_peak.max()) == 0.0
    assert float(ds.rotating_force_magnitude) == 0.0
    assert float(ds.rotating_moment_magnitude) == 0.0
    textbook = analyse(layout, model="textbook")
    assert float(textbook.reciprocating_force_peak_normalised.sel(order=2)) == pytest.approx(
        4 * lam, rel=1e-12
    )


def test_inline3_couples():
    """Inline-3 (120 deg throws): no free forces of orders 1 and 2; 1st-order couple
    sqrt(3) F1 a, 2nd-order couple sqrt(3) A2 F1 a, split equally forward and backward."""
    layout = engine([0, 240, 120])
    lam = 0.043 / 0.143
    a2 = float(kin.series_coefficients_centred(lam, 30, 2))
    ds = analyse(layout)
    assert float(ds.reciprocating_force_peak.sel(order=1)) == 0.0
    assert float(ds.reciprocating_force_peak.sel(order=2)) == 0.0
    moment = ds.reciprocating_moment_peak_normalised
    assert float(moment.sel(order=1)) == pytest.approx(math.sqrt(3), rel=1e-12)
    assert float(moment.sel(order=2)) == pytest.approx(math.sqrt(3) * a2, rel=1e-12)
    halves = ds.reciprocating_moment_normalised.sel(order=1)
    np.testing.assert_allclose(halves, [math.sqrt(3) / 2] * 2, rtol=1e-12)
    # the rotating couple: sqrt(3) m_rot r w^2 a, forward
    m_rot = float(layout.rotating_mass[0] * layout.crank_radius[0] * layout.speed**2)
    assert float(ds.rotating_moment_magnitude) == pytest.approx(math.sqrt(3) * m_rot * 0.09)


def test_inline6_is_free_of_first_and_second_order():
    ds = analyse(engine([0, 240, 120, 120, 240, 0]), orders=12)
    for k in (1, 2, 3, 4, 5):
        assert float(ds.reciprocating_force_peak.sel(order=k)) == 0.0
    assert float(ds.reciprocating_moment_peak.max()) == 0.0  # mirror-symmetric
    assert float(ds.reciprocating_force_peak.sel(order=6)) > 0.0  # orders 6, 12 remain
    assert float(ds.rotating_force_magnitude) == 0.0 and float(ds.rotating_moment_magnitude) == 0.0


def test_crossplane_v8_first_order_couple_forward_only():
    """90-degree V8, cross-plane crank 0-90-270-180: 1st-order couple sqrt(10) F1 a turning
    forwards only (so a counterweight cancels it); no free forces of orders 1 and 2; no
    2nd-order couple."""
    layout = engine([0, 90, 270, 180], banks=[-45, 45])
    ds = analyse(layout)
    m = ds.reciprocating_moment_normalised.sel(order=1)
    assert float(m.sel(rotation="forward")) == pytest.approx(math.sqrt(10), rel=1e-12)
    assert float(m.sel(rotation="backward")) == 0.0
    assert float(ds.reciprocating_force_peak.sel(order=1)) == 0.0
    assert float(ds.reciprocating_force_peak.sel(order=2)) == 0.0
    assert float(ds.reciprocating_moment_peak.sel(order=2)) == 0.0


def test_flatplane_v8_second_order_force_horizontal():
    """Flat-plane V8 = two inline-4s at 90 deg: 2nd-order forces of sqrt(2) * 4 A2 F1,
    horizontal."""
    layout = engine([0, 180, 180, 0], banks=[-45, 45])
    lam = 0.043 / 0.143
    a2 = float(kin.series_coefficients_centred(lam, 30, 2))
    ds = analyse(layout, orders=2)
    assert float(ds.reciprocating_force_peak_normalised.sel(order=2)) == pytest.approx(
        math.sqrt(2) * 4 * a2, rel=1e-12
    )
    # the two phasors are equal in size with phases whose mean is 90 deg: a line along x
    phases = ds.reciprocating_force_phase.sel(order=2).values
    assert math.cos(math.radians(phases.sum() / 2)) == pytest.approx(0.0, abs=1e-12)


def test_ninety_degree_v_twin_first_order_is_a_circle():
    """90-degree V-twin on one pin: the 1st-order reciprocating force is a constant
    F1 turning forwards (a counterweight of the whole reciprocating mass cancels it)."""
    ds = analyse(engine([0], banks=[-45, 45], spacing=0.0))
    m = ds.reciprocating_force_normalised.sel(order=1)
    assert float(m.sel(rotation="forward")) == pytest.approx(1.0, rel=1e-12)
    assert float(m.sel(rotation="backward")) == 0.0


@pytest.mark.parametrize("name", ["inline-3", "inline-4", "inline-6", "v8-crossplane"])
def test_builtin_layouts_show_the_textbook_coefficients(name):
    layout = load_layout(name)
    ds = analyse(layout)
    lam = float(layout.crank_radius[0] / layout.conrod_length[0])
    a2 = float(kin.series_coefficients_centred(lam, 30, 2))
    force = ds.reciprocating_force_peak_normalised
    moment = ds.reciprocating_moment_peak_normalised
    expected = {
        "inline-3": (0, 0, math.sqrt(3), math.sqrt(3) * a2),
        "inline-4": (0, 4 * a2, 0, 0),
        "inline-6": (0, 0, 0, 0),
        "v8-crossplane": (0, 0, math.sqrt(10), 0),
    }[name]
    got = (
        float(force.sel(order=1)),
        float(force.sel(order=2)),
        float(moment.sel(order=1)),
        float(moment.sel(order=2)),
    )
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-12)


# --- brute force: sampled forces and their FFT -----------------------------------------


@st.composite
def random_layouts(draw, max_cylinders: int = 10) -> Engine:
    n = draw(st.integers(1, max_cylinders))
    angles = st.floats(-360, 360, allow_nan=False)
    lam = draw(st.lists(st.floats(0.02, 0.5), min_size=n, max_size=n))
    radius = np.asarray(draw(st.lists(st.floats(0.01, 0.1), min_size=n, max_size=n)))
    share = np.asarray(draw(st.lists(st.floats(-0.9, 0.9), min_size=n, max_size=n)))
    length = radius / np.asarray(lam)
    offset = share * (length - radius)
    return Engine(
        name="random",
        speed=draw(st.floats(10.0, 2000.0)),
        throw=np.radians(draw(st.lists(angles, min_size=n, max_size=n))),
        bank=np.radians(draw(st.lists(angles, min_size=n, max_size=n))),
        z=np.asarray(draw(st.lists(st.floats(-0.5, 0.5), min_size=n, max_size=n))),
        crank_radius=radius,
        conrod_length=length,
        offset=offset,
        reciprocating_mass=np.asarray(draw(st.lists(st.floats(0.05, 3.0), min_size=n, max_size=n))),
        rotating_mass=np.asarray(draw(st.lists(st.floats(0.0, 3.0), min_size=n, max_size=n))),
        conrod_inertia_correction=np.asarray(
            draw(st.lists(st.floats(-5e-3, 5e-3), min_size=n, max_size=n))
        ),
        reference_z=draw(st.floats(-0.2, 0.2)),
        pitch=0.1,
    )


def _scale(layout: Engine) -> float:
    """m_rec r w^2 of the largest cylinder (the tolerance unit of the issue)."""
    return float(np.max(layout.reciprocating_mass * layout.crank_radius) * layout.speed**2)


@given(layout=random_layouts())
def test_phasors_equal_fft_of_sampled_forces(layout):
    """Issue 2: for random layouts (throws, banks, z, offsets, lambda up to 0.5) the phasors
    from the analysis equal those of the sampled exact force, to 1e-9 of m_rec r w^2."""
    result = compute_phasors(layout, ORDERS)
    theta = td.crank_angles(1024)
    scale = _scale(layout)
    fwd, bwd = td.phasors_from_samples(td.reciprocating_force_samples(layout, theta), ORDERS)
    np.testing.assert_allclose(result.phasors.force_forward, fwd, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(result.phasors.force_backward, bwd, rtol=0, atol=1e-9 * scale)
    fwd, bwd = td.phasors_from_samples(td.reciprocating_force_samples(layout, theta, True), ORDERS)
    np.testing.assert_allclose(result.phasors.moment_forward, fwd, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(result.phasors.moment_backward, bwd, rtol=0, atol=1e-9 * scale)
    rot_scale = float(np.sum(layout.rotating_mass * layout.crank_radius) * layout.speed**2) + 1e-300
    fwd, bwd = td.phasors_from_samples(td.rotating_force_samples(layout, theta), [1])
    assert abs(result.phasors.rotating_force - fwd[0]) <= 1e-12 * rot_scale
    assert abs(bwd[0]) <= 1e-12 * rot_scale
    fwd, _ = td.phasors_from_samples(td.rotating_force_samples(layout, theta, True), [1])
    assert abs(result.phasors.rotating_moment - fwd[0]) <= 1e-12 * rot_scale


@given(layout=random_layouts())
def test_sum_of_phasors_rebuilds_the_force_at_any_angle(layout):
    """The phasors, evaluated at crank angles off the FFT grid, give back the sampled force
    (with enough orders for the geometry)."""
    # the series converges like exp(-a k), a = acosh(1/lambda - |e|/r): the branch point
    # of the conrod term; take enough orders for the truncation to fall below 1e-12
    lam = layout.crank_radius / layout.conrod_length
    a = float(np.min(np.arccosh(1 / lam - np.abs(layout.offset / layout.crank_radius))))
    result = compute_phasors(layout, min(int(np.ceil(36 / a)) + 20, 3000))
    theta = np.array([0.123, 1.0, 2.5, 4.4, 6.0])
    k = result.phasors.orders[None, :]
    rebuilt = (
        result.phasors.force_forward[None, :] * np.exp(1j * k * theta[:, None])
        + result.phasors.force_backward[None, :] * np.exp(-1j * k * theta[:, None])
    ).sum(axis=1)
    direct = td.reciprocating_force_samples(layout, theta)
    np.testing.assert_allclose(rebuilt, direct, rtol=0, atol=1e-9 * _scale(layout))


# --- invariances -----------------------------------------------------------------------


@given(layout=random_layouts(), shift=st.floats(-720, 720))
def test_crank_angle_origin_changes_phases_only(layout, shift):
    """Turning every throw by delta is the same engine seen at another crank angle: each
    order-k phasor is multiplied by exp(i k delta) forwards and exp(-i k delta) backwards."""
    delta = math.radians(shift)
    turned = dataclasses.replace(layout, throw=layout.throw + delta)
    a = compute_phasors(layout, ORDERS)
    b = compute_phasors(turned, ORDERS)
    tol = 1e-12 * _scale(layout)
    np.testing.assert_allclose(
        b.phasors.force_forward, a.phasors.force_forward * np.exp(1j * ORDERS * delta), atol=tol
    )
    np.testing.assert_allclose(
        b.phasors.force_backward, a.phasors.force_backward * np.exp(-1j * ORDERS * delta), atol=tol
    )
    np.testing.assert_allclose(
        np.abs(b.phasors.moment_forward), np.abs(a.phasors.moment_forward), atol=tol
    )
    np.testing.assert_allclose(np.abs(b.phasors.roll), np.abs(a.phasors.roll), atol=tol)


@given(layout=random_layouts(), seed=st.integers(0, 2**32 - 1))
def test_renumbering_cylinders_changes_nothing(layout, seed):
    order = np.random.default_rng(seed).permutation(layout.n_cylinders)
    a = compute_phasors(layout, ORDERS)
    b = compute_phasors(layout.reordered(order), ORDERS)
    tol = 1e-12 * _scale(layout)
    for name in ("force_forward", "force_backward", "moment_forward", "moment_backward", "roll"):
        np.testing.assert_allclose(getattr(b.phasors, name), getattr(a.phasors, name), atol=tol)


@given(
    layout=random_layouts(), speed_factor=st.floats(0.01, 100), mass_factor=st.floats(0.001, 1000)
)
def test_forces_scale_with_speed_squared_and_mass(layout, speed_factor, mass_factor):
    scaled = dataclasses.replace(
        layout,
        speed=layout.speed * speed_factor,
        reciprocating_mass=layout.reciprocating_mass * mass_factor,
        rotating_mass=layout.rotating_mass * mass_factor,
        conrod_inertia_correction=layout.conrod_inertia_correction * mass_factor,
    )
    a = compute_phasors(layout, ORDERS)
    b = compute_phasors(scaled, ORDERS)
    factor = speed_factor**2 * mass_factor
    tol = 1e-11 * _scale(layout) * factor
    np.testing.assert_allclose(b.phasors.force_forward, a.phasors.force_forward * factor, atol=tol)
    np.testing.assert_allclose(
        b.phasors.moment_backward, a.phasors.moment_backward * factor, atol=tol
    )
    np.testing.assert_allclose(b.phasors.roll, a.phasors.roll * factor, atol=tol * 0.1)
    assert abs(b.phasors.rotating_force - a.phasors.rotating_force * factor) <= tol + 1e-12 * abs(
        b.phasors.rotating_force
    )


@given(
    half=st.lists(
        st.tuples(st.floats(0, 360), st.floats(-60, 60), st.floats(0.01, 0.4)),
        min_size=1,
        max_size=5,
    ),
)
def test_mirror_symmetric_crank_has_no_free_moments(half):
    """A crank that is its own mirror image about the mid plane (cylinder at +z matched by
    an identical one at -z) has no free moments of any order."""
    throws = [t for t, _, _ in half] * 2
    banks = [b for _, b, _ in half] * 2
    z = [zz for _, _, zz in half] + [-zz for _, _, zz in half]
    n = len(throws)
    layout = Engine(
        name="mirror",
        speed=600.0,
        throw=np.radians(throws),
        bank=np.radians(banks),
        z=np.asarray(z),
        crank_radius=np.full(n, 0.04),
        conrod_length=np.full(n, 0.14),
        offset=np.full(n, 0.003),
        reciprocating_mass=np.full(n, 0.5),
        rotating_mass=np.full(n, 0.4),
        conrod_inertia_correction=np.zeros(n),
        reference_z=0.0,
        pitch=0.1,
    )
    result = compute_phasors(layout, ORDERS)
    assert np.all(result.phasors.moment_forward == 0) and np.all(
        result.phasors.moment_backward == 0
    )
    assert result.phasors.rotating_moment == 0


def test_exact_cancellation_is_reported_as_zero_not_noise():
    ds = analyse(engine([0, 240, 120, 120, 240, 0], speed="1000000 rpm"))
    # terms of 1e9 N cancel; the sum must be 0.0 exactly, not 1e-7 N of rounding
    assert float(ds.reciprocating_force_peak.sel(order=1)) == 0.0
    assert float(ds.reciprocating_force_phase.sel(order=1, rotation="forward")) == 0.0


@pytest.mark.parametrize("shape", [(12, 1), (12, 8), (3, 5, 12, 8), (7, 4, 2), (1, 3)])
def test_both_ways_of_summing_over_cylinders_give_the_same_bits(shape, monkeypatch):
    """One running-sum call (one engine) and the per-cylinder loop (a sweep's chunk) add
    in the same order; a sweep equals analyse bit for bit only if they agree exactly."""
    from balance.core import phasors

    rng = np.random.default_rng(sum(shape))
    values = rng.normal(size=shape) * 10.0 ** rng.uniform(-8, 8, size=shape)
    weight = rng.normal(size=(*shape[:-1], 1))
    terms = values + 1j * rng.normal(size=shape)
    small = (phasors._dot_over_cylinders(weight, values), phasors.sum_over_cylinders(terms))
    monkeypatch.setattr(phasors, "_SMALL", 0)
    large = (phasors._dot_over_cylinders(weight, values), phasors.sum_over_cylinders(terms))
    for a, b in zip(small, large, strict=True):
        assert np.array_equal(a, b)
    # and it is the sum in cylinder order, not numpy.sum's pairwise order
    expected = terms[..., 0, :].copy()
    for i in range(1, shape[-2]):
        expected = expected + terms[..., i, :]
    assert np.array_equal(large[1], expected)
