"""The crank train's force balance (balance.core.crank_train) against the Newton-Euler
solution of piston and rigid rod (tests/oracles.py, which shares none of it) and against the
textbook forms without the rod's inertia correction."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from oracles import crank_torque_newton_euler, crank_train_newton_euler

from balance.core import crank_train as ct
from balance.core.kinematics import conrod_angle_derivatives, normalised_slider
from balance.io.layout_file import layout_from_dict


def _layout(seed: int) -> Any:
    """A by-part engine of random throws, banks, offset and rod inertia (Delta I != 0)."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 5))
    return layout_from_dict(
        {
            "name": f"random {seed}",
            "speed": f"{rng.uniform(1500, 8000):.0f} rpm",
            "geometry": {
                "stroke": f"{rng.uniform(60, 100):.1f} mm",
                "conrod_length": f"{rng.uniform(130, 180):.1f} mm",
                "offset": f"{rng.uniform(-6, 6):.2f} mm",
            },
            "masses": {
                "piston_group": f"{rng.uniform(0.3, 0.6):.3f} kg",
                "conrod": f"{rng.uniform(0.4, 0.7):.3f} kg",
                "conrod_cg_to_big_end": f"{rng.uniform(30, 50):.1f} mm",
                "conrod_inertia": f"{rng.uniform(1.0e-3, 3.0e-3):.5f} kg m^2",
            },
            "crank": {
                "throws": [float(t) for t in rng.uniform(0, 360, n).round(1)],
                "banks": [float(b) for b in rng.uniform(-60, 60, n).round(1)],
                "spacing": "90 mm",
            },
        }
    )


def _kernel(layout: Any, theta: np.ndarray, gas: np.ndarray) -> dict[str, np.ndarray]:
    """Every force of the kernel, shape (angles, cylinders), with ``gas`` (angles, cylinders)."""
    beta = theta[:, None] + layout.throw - layout.bank
    r, length = layout.crank_radius, layout.conrod_length
    lam, eps = r / length, layout.offset / r
    _, ds, d2s = normalised_slider(beta, lam, eps)
    dpsi, d2psi = conrod_angle_derivatives(beta, lam, eps)
    w2 = layout.speed**2
    delta_i = layout.conrod_inertia_correction
    sin_psi, cos_psi = ct.rod_direction(beta, lam, eps)
    piston = ct.piston_force(ct.reciprocating_force(layout.reciprocating_mass, w2, r, d2s), gas)
    couple = ct.couple_side_force(ct.rod_inertia_couple(delta_i, w2, d2psi), length, cos_psi)
    side = ct.side_thrust(piston, sin_psi, cos_psi, couple)
    return {
        "beta": beta,
        "piston": piston,
        "side": side,
        "side_moments": ct.side_thrust_moment_balance(
            piston, sin_psi, cos_psi, length, delta_i, w2, d2psi
        ),
        "rod": ct.rod_force(piston, side, sin_psi, cos_psi),
        "tangential": ct.tangential_force(piston, ds, delta_i, w2, dpsi, d2psi, r),
        "radial": ct.radial_force(piston, side, beta),
    }


@pytest.mark.parametrize("seed", range(6))
def test_kernel_equals_the_newton_euler_solution_of_piston_and_rigid_rod(seed):
    """At random crank angles, with random gas forces, offsets, banks and rod inertias: N (in
    both of its forms) and S against the rigid-body solution with the whole reciprocating
    mass at the piston pin (a massless rod of inertia Delta I); the torque on the crank
    sum(T r) for two splits of the rod; and the force on each crank pin, with the rod's
    big-end share turning with it, for a rigid rod of real mass: to 1e-10 of the largest."""
    layout = _layout(seed)
    rng = np.random.default_rng(100 + seed)
    theta = rng.uniform(0.0, 2.0 * np.pi, 157)
    gas = rng.uniform(-5e3, 6e4, (theta.size, layout.n_cylinders))
    k = _kernel(layout, theta, gas)
    massless = crank_train_newton_euler(layout, theta, gas, small_end_share=0.0)
    for got, want in (
        (k["side"], massless.wall),
        (k["side_moments"], massless.wall),
        (k["rod"], massless.rod_force),
    ):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * np.max(np.abs(want)))
    torque = (k["tangential"] * layout.crank_radius).sum(axis=1)
    for share, cg in ((1.0 / 3.0, 0.3), (0.45, 0.2)):
        want = crank_torque_newton_euler(layout, theta, gas, share, cg)
        np.testing.assert_allclose(torque, want, rtol=0, atol=1e-10 * np.max(np.abs(want)))
    # a rigid rod of real mass: its big-end share m_c - m_small turns with the pin
    share, cg = 1.0 / 3.0, 0.3
    rigid = crank_train_newton_euler(layout, theta, gas, share, cg)
    small = share * layout.reciprocating_mass
    centrifugal = (small / cg - small) * layout.speed**2 * layout.crank_radius
    got = ct.pin_force(k["piston"], k["side_moments"], centrifugal, k["beta"], layout.bank)
    scale = np.max(np.abs(rigid.pin_force))
    np.testing.assert_allclose(got, rigid.pin_force, rtol=0, atol=1e-10 * scale)


@pytest.mark.parametrize("seed", range(4))
def test_pin_force_along_and_across_the_throw_is_t_and_k(seed):
    """The force on the crank pin as a vector (pin_force) seen from the crank: across the
    throw T, the virtual-work form -P s'/r - Delta I w^2 psi' psi''/r; along it (outwards)
    -K plus the centrifugal force; to 1e-12 of the largest."""
    layout = _layout(seed)
    rng = np.random.default_rng(200 + seed)
    theta = rng.uniform(0.0, 2.0 * np.pi, 101)
    gas = rng.uniform(-5e3, 6e4, (theta.size, layout.n_cylinders))
    k = _kernel(layout, theta, gas)
    centrifugal = rng.uniform(0.0, 2e4, layout.n_cylinders)
    pin = ct.pin_force(k["piston"], k["side"], centrifugal, k["beta"], layout.bank)
    seen = pin * np.exp(-1j * (k["beta"] + layout.bank))
    scale = np.max(np.abs(pin))
    np.testing.assert_allclose(seen.imag, k["tangential"], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(seen.real, centrifugal - k["radial"], rtol=0, atol=1e-12 * scale)


def test_textbook_forces_without_the_rod_inertia_correction():
    """With Delta I = 0 and no offset, the textbook forms (Kolchin and Demidov, *Design of
    Automotive Engines*, Mir 1984, ch. 8-9; Taylor, *The Internal-Combustion Engine in
    Theory and Practice*, vol. 2, MIT Press 1985, ch. 8), sin(psi) = lambda sin(beta):
    N = P tan(psi), S = P/cos(psi), T = P sin(beta + psi)/cos(psi),
    K = P cos(beta + psi)/cos(psi); to 1e-13 of |P|."""
    rng = np.random.default_rng(7)
    beta = rng.uniform(0.0, 2.0 * np.pi, 2000)
    lam = rng.uniform(0.15, 0.4, beta.size)
    piston = rng.uniform(-3e4, 6e4, beta.size)
    psi = np.arcsin(lam * np.sin(beta))
    _, ds, _ = normalised_slider(beta, lam)
    dpsi, d2psi = conrod_angle_derivatives(beta, lam)
    sin_psi, cos_psi = ct.rod_direction(beta, lam)
    couple = ct.couple_side_force(ct.rod_inertia_couple(0.0, 1e6, d2psi), 0.15, cos_psi)
    side = ct.side_thrust(piston, sin_psi, cos_psi, couple)
    atol = 1e-13 * np.abs(piston) + 1e-300
    for got, want in (
        (side, piston * np.tan(psi)),
        (ct.rod_force(piston, side, sin_psi, cos_psi), piston / np.cos(psi)),
        (
            ct.tangential_force(piston, ds, 0.0, 1e6, dpsi, d2psi, 0.04),
            piston * np.sin(beta + psi) / np.cos(psi),
        ),
        (ct.radial_force(piston, side, beta), piston * np.cos(beta + psi) / np.cos(psi)),
    ):
        assert np.all(np.abs(got - want) <= 4 * atol)


def test_rod_inertia_couple_is_carried_at_the_piston_pin():
    """The rod's moment balance about its big end (module notes): the two forms of N agree
    to rounding, and the couple's share of N is -Delta I w^2 psi''/(l cos psi), whatever P."""
    rng = np.random.default_rng(11)
    beta = rng.uniform(0.0, 2.0 * np.pi, 500)
    lam, eps = 0.3, 0.05
    d2psi = conrod_angle_derivatives(beta, lam, eps)[1]
    sin_psi, cos_psi = ct.rod_direction(beta, lam, eps)
    length, delta_i, w2 = 0.15, 2e-3, 4e5
    for piston in (np.zeros(beta.size), rng.uniform(-3e4, 6e4, beta.size)):
        couple = ct.couple_side_force(ct.rod_inertia_couple(delta_i, w2, d2psi), length, cos_psi)
        tangent = ct.side_thrust(piston, sin_psi, cos_psi, couple)
        moments = ct.side_thrust_moment_balance(
            piston, sin_psi, cos_psi, length, delta_i, w2, d2psi
        )
        scale = np.max(np.abs(piston)) + np.max(np.abs(couple))
        np.testing.assert_allclose(tangent, moments, rtol=0, atol=1e-14 * scale)
        np.testing.assert_allclose(
            tangent - piston * sin_psi / cos_psi,
            -delta_i * w2 * d2psi / (length * cos_psi),
            rtol=0,
            atol=1e-14 * scale,
        )


def test_rod_point_inertia_is_minus_the_relative_acceleration():
    """A point rho e^{i(delta - psi)} from the big end (Y + iX): its acceleration relative to
    the big end, by a five-point finite difference in beta, is -rho e^{i delta} q(beta) with
    q = e^{-i psi}(psi'^2 + i psi'') from rod_point_inertia; to 1e-9."""
    lam, eps, rho, delta = 0.31, -0.04, 0.9, 0.7
    beta = np.linspace(0.0, 2.0 * np.pi, 37)

    def point(b: np.ndarray) -> np.ndarray:
        return rho * np.exp(1j * (delta - np.arcsin(lam * (np.sin(b) - eps))))

    h = 1e-3
    second = (
        -point(beta + 2 * h)
        + 16 * point(beta + h)
        - 30 * point(beta)
        + 16 * point(beta - h)
        - point(beta - 2 * h)
    ) / (12 * h**2)
    sin_psi, cos_psi = ct.rod_direction(beta, lam, eps)
    q_re, q_im = ct.rod_point_inertia(sin_psi, cos_psi, *conrod_angle_derivatives(beta, lam, eps))
    np.testing.assert_allclose(
        -second, rho * np.exp(1j * delta) * (q_re + 1j * q_im), rtol=0, atol=1e-9
    )


def test_hung_load_keeps_the_rod_in_balance():
    """A load -F_L on the rod at a point L: with the piston's push Delta N across the bore at
    the piston pin P = C + l e^{i(psi_b - psi)} and the rod's force on the crank pin
    (hung_load), the massless rod is in balance, forces and moments about C (Fearn 1927:
    the master rod carrying a link rod); and rod_on_piston is (P - iN) along and across the
    bore."""
    rng = np.random.default_rng(3)
    n = 50
    reaction = rng.normal(size=n) * 1e4 + 1j * rng.normal(size=n) * 1e4
    crank = 0.05 * np.exp(1j * rng.uniform(0, 2 * np.pi, n))
    point = crank + 0.04 * np.exp(1j * rng.uniform(0, 2 * np.pi, n))
    length, psi, bank = 0.16, rng.uniform(-0.3, 0.3, n), rng.uniform(-1.0, 1.0, n)
    side, on_pin = ct.hung_load(reaction, point, crank, length, np.cos(psi), bank)
    piston_pin = crank + length * np.exp(1j * (bank - psi))
    push = 1j * side * np.exp(1j * bank)  # the piston on the rod, +X of the bore
    # forces: -F_L + push - (the rod's force on the pin) = 0
    np.testing.assert_allclose(-reaction + push - on_pin, 0.0, atol=1e-10 * 1e4)
    moment = np.imag(np.conj(point - crank) * -reaction) + np.imag(
        np.conj(piston_pin - crank) * push
    )
    np.testing.assert_allclose(moment, 0.0, atol=1e-12 * 1e4)
    along = ct.rod_on_piston(3.0e4, 2.0e3, bank) * np.exp(-1j * bank)
    np.testing.assert_allclose(along, 3.0e4 - 2.0e3j, rtol=1e-15)
