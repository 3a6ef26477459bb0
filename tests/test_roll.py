"""Roll torque: the energy-derived phasors against a Newton-Euler solution."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from helpers import engine
from hypothesis import given
from hypothesis import strategies as st
from test_phasors import random_layouts

from balance.api import analyse
from balance.core import sampled as td
from balance.core.analysis import compute_phasors

ORDERS = np.arange(1, 9)


def _roll_scale(layout) -> float:
    return float(
        np.max(layout.reciprocating_mass * layout.crank_radius**2) * layout.speed**2
        + np.max(np.abs(layout.conrod_inertia_correction)) * layout.speed**2
    )


@given(layout=random_layouts())
def test_roll_equals_newton_euler(layout):
    """The roll phasors (from the balance of angular momentum, with offset and the conrod
    inertia correction) equal the FFT of the block torque found by solving piston and rigid
    rod by Newton-Euler at each crank angle, to 1e-9 of m_rec r^2 w^2."""
    result = compute_phasors(layout, ORDERS)
    theta = td.crank_angles(1024)
    sampled = td.roll_phasors_from_samples(td.roll_newton_euler(layout, theta), ORDERS)
    np.testing.assert_allclose(
        result.phasors.roll, sampled, rtol=0, atol=1e-9 * _roll_scale(layout)
    )


@given(
    layout=random_layouts(max_cylinders=4), share=st.floats(0.05, 0.95), cg=st.floats(0.05, 0.95)
)
def test_roll_depends_only_on_the_statically_equivalent_masses(layout, share, cg):
    """Any rod with the same reciprocating mass and inertia correction gives the same roll."""
    theta = td.crank_angles(256)
    a = td.roll_newton_euler(layout, theta)
    b = td.roll_newton_euler(layout, theta, small_end_share=share, cg_fraction=cg)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * _roll_scale(layout))


def test_inline4_second_order_roll_textbook():
    """Inline-4 with two-mass rods: the roll is of even orders only; order 2 is
    2 m_rec r^2 w^2 to first order in lambda (Taylor vol. 2, inertia torque of four pistons
    in phase, each (1/2) m r^2 w^2 sin 2 beta)."""
    layout = engine([0, 180, 180, 0], stroke=2e-5, conrod_length=1.0)  # lambda = 1e-5
    ds = analyse(layout)
    norm = ds.roll_amplitude_normalised
    assert float(norm.sel(roll_order=2)) == pytest.approx(2.0, rel=1e-4)
    for k in (1, 3, 5, 7):
        assert float(norm.sel(roll_order=k)) == 0.0


def test_roll_with_conrod_inertia_differs_and_is_checked():
    layout = engine([0, 180, 180, 0])
    heavy = dataclasses.replace(layout, conrod_inertia_correction=np.full(4, -2e-3))
    a = compute_phasors(layout, ORDERS).phasors.roll
    b = compute_phasors(heavy, ORDERS).phasors.roll
    assert np.abs(b - a).max() > 1.0  # N m: the correction matters
    theta = td.crank_angles(512)
    sampled = td.roll_phasors_from_samples(td.roll_newton_euler(heavy, theta), ORDERS)
    np.testing.assert_allclose(b, sampled, atol=1e-9 * _roll_scale(heavy))


def test_inline6_roll_orders_are_multiples_of_three():
    ds = analyse(engine([0, 240, 120, 120, 240, 0]), orders=12)
    amp = ds.roll_amplitude
    for k in range(1, 13):
        if k % 3:
            assert float(amp.sel(roll_order=k)) == 0.0
        else:
            assert float(amp.sel(roll_order=k)) > 0.0
