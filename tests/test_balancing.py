"""Balancing proposals: checked by adding the proposed masses in the crank-angle domain."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from helpers import engine
from hypothesis import example, given
from hypothesis import strategies as st
from oracles import proposal_force_samples, proposal_roll_samples
from test_geared_brute_force import _with_proposal
from test_phasors import random_layouts

import balance
from balance.api import Engine, analyse, load_layout
from balance.core import kinematics as kin
from balance.core import sampled as td
from balance.core.analysis import compute_phasors
from balance.core.factor_study import balance_factor_study, optimal_balance_factor
from balance.core.proposal import balance_engine

ORDERS = np.arange(1, 9)


def _units(layout: Engine) -> tuple[float, float]:
    """Tolerance units: m_rec r w^2 (largest cylinder) and that times the pitch (or the
    crank's axial span, or the stroke for single-plane engines)."""
    f1 = float(np.max(layout.reciprocating_mass * layout.crank_radius) * layout.speed**2)
    span = float(np.ptp(layout.z))
    pitch = layout.pitch if math.isfinite(layout.pitch) else (span or 2 * layout.crank_radius[0])
    return f1, f1 * pitch


def _time_domain_residual(layout: Engine, proposal) -> dict[str, np.ndarray]:
    """Forward/backward phasors of the whole free force and moment with every proposed mass,
    from sampled vector sums (independent of the phasor algebra)."""
    theta = td.crank_angles(1024)
    force = (
        td.reciprocating_force_samples(layout, theta)
        + td.rotating_force_samples(layout, theta)
        + proposal_force_samples(proposal, layout, theta)
    )
    moment = (
        td.reciprocating_force_samples(layout, theta, lever=True)
        + td.rotating_force_samples(layout, theta, lever=True)
        + proposal_force_samples(proposal, layout, theta, lever=True)
    )
    ff, fb = td.phasors_from_samples(force, ORDERS)
    mf, mb = td.phasors_from_samples(moment, ORDERS)
    return {"ff": ff, "fb": fb, "mf": mf, "mb": mb}


def _brute_force_residual(layout: Engine, proposal) -> dict[str, np.ndarray]:
    """Several crankshafts: the phasors of the bodies of the brute force with every proposed
    mass as a point mass on its axis (test_geared_brute_force.py, which shares nothing with
    the package)."""
    out = _with_proposal(layout, proposal, ORDERS)
    (ff, fb), (mf, mb) = out["force"], out["moment"]
    return {"ff": ff, "fb": fb, "mf": mf, "mb": mb}


@pytest.mark.parametrize("strategy", ["two-plane", "per-throw"])
@pytest.mark.parametrize("name", balance.builtin_layout_names())
def test_every_builtin_proposal_cancels_what_it_sets_out_to(name, strategy):
    """Issue 3: orders 1 and 2 (forward and backward, force and moment) vanish in the
    residual to 1e-9 of m_rec r w^2 (forces) and m_rec r w^2 a (moments), by time domain;
    with several crankshafts by the brute force's bodies (issue 25)."""
    layout = load_layout(name)
    result = compute_phasors(layout, ORDERS)
    balanced = balance_engine(layout, result, strategy=strategy, cancel=[1, 2])
    reference = _brute_force_residual if layout.geared else _time_domain_residual
    residual = reference(layout, balanced.proposal)
    f_unit, m_unit = _units(layout)
    for k in (1, 2):
        i = k - 1
        assert abs(residual["ff"][i]) <= 1e-9 * f_unit, (k, "forward force")
        assert abs(residual["fb"][i]) <= 1e-9 * f_unit, (k, "backward force")
        assert abs(residual["mf"][i]) <= 1e-9 * m_unit, (k, "forward moment")
        assert abs(residual["mb"][i]) <= 1e-9 * m_unit, (k, "backward moment")
    # and the reported residual agrees with the time domain for every order
    for key, mine in (
        ("ff", balanced.residual.force_forward),
        ("fb", balanced.residual.force_backward),
        ("mf", balanced.residual.moment_forward),
        ("mb", balanced.residual.moment_backward),
    ):
        unit = f_unit if key[0] == "f" else m_unit
        np.testing.assert_allclose(mine, residual[key], rtol=0, atol=1e-9 * unit)


def _one_plane(n: int, reference_z: float) -> Engine:
    """``n`` cylinders evenly spaced on one crank plane z = 0, moments about ``reference_z``."""
    radius = np.full(n, 0.043)
    return Engine(
        name="random",
        speed=200.0,
        throw=np.radians(np.arange(n) * 360.0 / n),
        bank=np.zeros(n),
        z=np.zeros(n),
        crank_radius=radius,
        conrod_length=radius / 0.3,
        offset=np.zeros(n),
        reciprocating_mass=np.full(n, 0.5),
        rotating_mass=np.full(n, 0.2),
        conrod_inertia_correction=np.zeros(n),
        reference_z=reference_z,
        pitch=0.1,
    )


def _pins_2e_17_apart() -> Engine:
    """Three cylinders on one throw, the third pin 2.1e-17 m from the others (hypothesis)."""
    n = 3
    return Engine(
        name="random",
        speed=10.0,
        throw=np.zeros(n),
        bank=np.zeros(n),
        z=np.array([0.0, 0.0, 2.08093905e-17]),
        crank_radius=np.full(n, 0.0625),
        conrod_length=np.full(n, 0.125),
        offset=np.zeros(n),
        reciprocating_mass=np.ones(n),
        rotating_mass=np.zeros(n),
        conrod_inertia_correction=np.zeros(n),
        reference_z=0.0,
        pitch=0.1,
    )


# Moments about a subnormal reference_z (hypothesis found 2.2e-311 m): lever arms of
# 2.2e-311 m give terms of 1e-313 N m per unit of omega^2, where floating point rounds by
# absolute units of 4.9e-324, not relative ones.  With all cylinders in one plane the
# forces of orders 1 and 2 cancel and the moments about reference_z must too; their
# rounding (one subnormal unit) was taken for a couple that one plane cannot cancel
# (AnalysisError) until cancel_to_zero counted the subnormal spacing.  The tolerance's
# floor (1e-12 m of lever, below) keeps the check on the scale of the forces and lengths
# of the engine, not of 1e-9 of a subnormal number.
@example(layout=_one_plane(3, 2.2e-311), per_throw=False)
@example(layout=_one_plane(3, 2.2e-311), per_throw=True)
@example(layout=_one_plane(2, 2.2e-311), per_throw=False)
@example(layout=_one_plane(1, -2.2e-311), per_throw=True)
@example(layout=_pins_2e_17_apart(), per_throw=True)
@given(layout=random_layouts(max_cylinders=8), per_throw=st.booleans())
def test_random_layout_proposals_cancel_orders_one_to_three(layout, per_throw):
    result = compute_phasors(layout, ORDERS)
    strategy = "per-throw" if per_throw else "two-plane"
    balanced = balance_engine(layout, result, strategy=strategy, cancel=[1, 2, 3])
    residual = _time_domain_residual(layout, balanced.proposal)
    f1 = float(np.max(layout.reciprocating_mass * layout.crank_radius) * layout.speed**2)
    f1 += float(np.sum(layout.rotating_mass * layout.crank_radius) * layout.speed**2)
    # lever arms are resolved to 1e-12 m: pins closer than that share a throw (crank_pins),
    # so a per-throw counterweight may sit up to 1e-12 m from a pin's plane, and leave the
    # couple of its throw's force (at most every cylinder's) over that distance: hypothesis
    # found pins at 0 and 2.1e-17 m whose counterweight at 0 leaves 6.5e-17 N m, against
    # 1e-9 of a moment scale of 6.25e-12 N m
    lever = float(np.ptp(layout.z)) + float(np.max(np.abs(layout.z - layout.reference_z)))
    m1 = f1 * (lever + 1e-12)
    planes = 1e-12 * f1 * layout.z.size if per_throw else 0.0
    for i in range(3):
        for key in ("ff", "fb"):
            assert abs(residual[key][i]) <= 1e-9 * f1
        for key in ("mf", "mb"):
            assert abs(residual[key][i]) <= 1e-9 * m1 + planes


def test_per_throw_counterweight_plane_does_not_depend_on_numbering():
    """Rods within 1e-12 m of one plane share a throw; its counterweight sits at the least of
    their planes (it took the first cylinder's, so renumbering moved it by 3.7e-13 m)."""
    base = load_layout("inline-4")
    layout = dataclasses.replace(
        base,
        z=np.array([3.74524841e-13, 0.0, 0.0, 0.0]),
        throw=np.zeros(4),
        reference_z=0.0,
        mass_parts=None,
    )
    planes = []
    for order in ([0, 1, 2, 3], [3, 2, 1, 0]):
        each = layout.reordered(np.asarray(order))
        proposal = balance_engine(
            each, compute_phasors(each, ORDERS), strategy="per-throw", cancel=[1]
        ).proposal
        planes.append([c.z for c in proposal.counterweights])
    assert planes[0] == planes[1] == [0.0]


# --- textbook cases ----------------------------------------------------------------------


def test_inline4_lanchester_pair():
    """Two shafts, +2w and -2w, each with the unbalance A2 m_rec r / 2 (m_rec per
    cylinder): each cancels half of the 4 A2 m_rec r w^2 second-order force at (2w)^2."""
    layout = engine([0, 180, 180, 0])
    result = compute_phasors(layout, ORDERS)
    proposal = balance_engine(layout, result).proposal
    assert proposal.counterweights == ()
    assert sorted(s.speed_ratio for s in proposal.shafts) == [-2, 2]
    lam = 0.043 / 0.143
    a2 = float(kin.series_coefficients_centred(lam, 40, 2))
    for shaft in proposal.shafts:
        assert len(shaft.planes) == 1
        assert abs(shaft.total_unbalance) == pytest.approx(a2 * 0.6 * 0.043 / 2, rel=1e-12)
        # the force of one shaft: half the engine's second-order force
        force = abs(shaft.total_unbalance) * (2 * layout.speed) ** 2
        assert force == pytest.approx(0.5 * 4 * a2 * 0.6 * 0.043 * layout.speed**2, rel=1e-12)
        assert shaft.planes[0][0] == pytest.approx(layout.reference_z)  # no couple


def test_crossplane_v8_end_counterweights_only():
    layout = engine([0, 90, 270, 180], banks=[-45, 45])
    proposal = balance_engine(layout, compute_phasors(layout, ORDERS)).proposal
    assert proposal.shafts == ()
    assert len(proposal.counterweights) == 2
    zs = sorted(c.z for c in proposal.counterweights)
    assert zs == pytest.approx([0.0, 0.27])


def test_inline3_counterweights_and_one_backward_shaft():
    layout = engine([0, 240, 120])
    proposal = balance_engine(layout, compute_phasors(layout, ORDERS), cancel=[1]).proposal
    assert len(proposal.counterweights) == 2
    assert [s.speed_ratio for s in proposal.shafts] == [-1]
    shaft = proposal.shafts[0]
    assert len(shaft.planes) == 2
    assert abs(shaft.total_unbalance) == pytest.approx(0.0, abs=1e-15)  # a pure couple


def test_ninety_degree_v_twin_full_reciprocating_mass_on_the_crank():
    """90-degree V-twin on one pin: a counterweight of both rods' rotating mass plus 100 %
    of one cylinder's reciprocating mass cancels the whole first order; no shaft."""
    layout = engine([0], banks=[-45, 45], spacing=0.0, reciprocating=0.5, rotating=0.3)
    ds = analyse(layout, cancel=[1])
    assert ds.sizes["counterweight"] == 1 and ds.sizes["shaft"] == 0
    mass = float(ds.counterweight_mass[0])
    assert mass == pytest.approx(2 * 0.3 + 1.0 * 0.5, rel=1e-12)
    assert float(ds.counterweight_angle[0]) == pytest.approx(180.0)
    assert float(ds.residual_force_peak.sel(order=1)) == 0.0


@pytest.mark.parametrize("name", ["inline-6", "v12-60", "boxer-6"])
def test_nothing_to_cancel_gets_no_proposal(name):
    ds = analyse(load_layout(name))
    assert ds.sizes["counterweight"] == 0
    assert ds.sizes["shaft"] == 0


@given(layout=random_layouts(max_cylinders=6), seed=st.integers(0, 2**32 - 1))
def test_proposal_invariant_to_cylinder_numbering(layout, seed):
    order = np.random.default_rng(seed).permutation(layout.n_cylinders)
    a = balance_engine(layout, compute_phasors(layout, ORDERS)).proposal
    renumbered = layout.reordered(order)
    b = balance_engine(renumbered, compute_phasors(renumbered, ORDERS)).proposal
    f_unit = float(np.sum((layout.reciprocating_mass + layout.rotating_mass) * layout.crank_radius))
    # two-plane masses are moment / plane spacing: rounding grows with lever / spacing (a
    # random layout may put its crank ends 0.1 um apart about a reference 0.15 m away)
    span = float(np.ptp(layout.z))
    lever = float(np.max(np.abs(layout.z - layout.reference_z)))
    f_unit *= max(1.0, lever / span) if span > 0 else 1.0

    def key(values):
        return sorted((round(z, 9), round(u.real, 9), round(u.imag, 9)) for z, u in values)

    cw_a = [(c.z, c.unbalance) for c in a.counterweights]
    cw_b = [(c.z, c.unbalance) for c in b.counterweights]
    assert len(cw_a) == len(cw_b)
    for (za, ua), (zb, ub) in zip(
        sorted(cw_a, key=lambda t: t[0]), sorted(cw_b, key=lambda t: t[0]), strict=True
    ):
        assert za == pytest.approx(zb)
        assert abs(ua - ub) <= 1e-12 * f_unit
    assert sorted(s.speed_ratio for s in a.shafts) == sorted(s.speed_ratio for s in b.shafts)
    for sa in a.shafts:
        sb = next(s for s in b.shafts if s.speed_ratio == sa.speed_ratio)
        assert len(sa.planes) == len(sb.planes)
        for (za, ua), (zb, ub) in zip(sa.planes, sb.planes, strict=True):
            assert za == pytest.approx(zb)
            assert abs(ua - ub) <= 1e-12 * f_unit


# --- balance factor -----------------------------------------------------------------------


def test_single_balance_factor_study():
    """A single: 0 % leaves the whole first order vertical, 100 % moves it all to the
    horizontal, 50 % makes a circle of half the size; the best factor is 50 %."""
    layout = engine([0], spacing=0.0)  # no offset: G1 = 1 exactly, whatever lambda
    f1 = 0.6 * 0.043 * layout.speed**2
    g1 = np.ones(1, dtype=np.complex128)
    study = balance_factor_study(layout, g1, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(study["vertical_peak"], [f1, f1 / 2, 0.0], atol=1e-9 * f1)
    np.testing.assert_allclose(study["horizontal_peak"], [0.0, f1 / 2, f1], atol=1e-9 * f1)
    assert optimal_balance_factor(layout, g1) == pytest.approx(0.5, abs=1e-9)


def test_balance_factor_in_the_proposal_leaves_the_rest_as_residual():
    layout = engine([0], spacing=0.0)
    ds = analyse(layout, cancel=[1], balance_factor=0.7)
    g1 = 1.0  # no offset
    f1 = 0.6 * 0.043 * layout.speed**2
    # counterweight: rotating + 70 % of the reciprocating mass
    assert float(ds.counterweight_mass[0]) == pytest.approx(0.4 + 0.7 * 0.6, rel=1e-12)
    # forward first order left: (1/2 - 0.7) F1 (the backward half is cancelled by a shaft)
    fwd = float(ds.residual_force_magnitude.sel(order=1, rotation="forward"))
    assert fwd == pytest.approx(abs(0.5 * g1 - 0.7) * f1, rel=1e-12)
    assert float(ds.residual_force_magnitude.sel(order=1, rotation="backward")) == 0.0


def test_factor_study_dataset_for_a_twin():
    ds = balance.analyse("inline-2-360", factor_study=True)
    assert float(ds.optimal_balance_factor) == pytest.approx(0.5, abs=1e-6)
    for name in ("study_vertical_peak", "study_horizontal_peak", "study_moment_peak"):
        assert ds[name].attrs["units"]


# --- roll ------------------------------------------------------------------------------------


def test_lanchester_pair_placed_to_cancel_second_order_roll():
    """A Lanchester pair at two heights also cancels the inline-4's 2nd-order roll (checked
    with the Newton-Euler roll of the engine and the shafts' sampled torque)."""
    layout = load_layout("inline-4")
    result = compute_phasors(layout, ORDERS)
    balanced = balance_engine(layout, result, cancel_roll=True)
    k2 = 1  # index of order 2
    assert balanced.residual.roll[k2] == 0.0
    theta = td.crank_angles(1024)
    torque = td.roll_newton_euler(layout, theta) + proposal_roll_samples(
        balanced.proposal, layout, theta
    )
    sampled = td.roll_phasors_from_samples(torque, ORDERS)
    scale = float(np.max(layout.reciprocating_mass * layout.crank_radius**2) * layout.speed**2)
    assert abs(sampled[k2]) <= 1e-9 * scale
    # the forces are still cancelled
    residual = _time_domain_residual(layout, balanced.proposal)
    f_unit, _ = _units(layout)
    assert abs(residual["ff"][k2]) <= 1e-9 * f_unit and abs(residual["fb"][k2]) <= 1e-9 * f_unit
    # the shafts sit at different heights: that is what makes the roll couple
    ys = sorted(s.y for s in balanced.proposal.shafts)
    assert ys[1] - ys[0] > 0.05


def test_shaft_roll_is_reported_and_checked_in_the_time_domain():
    layout = load_layout("single")
    result = compute_phasors(layout, ORDERS)
    balanced = balance_engine(layout, result)
    theta = td.crank_angles(1024)
    torque = td.roll_newton_euler(layout, theta) + proposal_roll_samples(
        balanced.proposal, layout, theta
    )
    sampled = td.roll_phasors_from_samples(torque, ORDERS)
    scale = float(np.max(layout.reciprocating_mass * layout.crank_radius**2) * layout.speed**2)
    np.testing.assert_allclose(balanced.residual.roll, sampled, rtol=0, atol=1e-9 * scale)
    assert (
        abs(balanced.residual.roll[0]) > 0
    )  # a single -w shaft off the crank axis rocks the block
