"""Crank-pin and main-bearing loads, internal moments (balance.core.bearings, issue 15)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_phasors import random_layouts

from balance.core import _numerics
from balance.core import bearings as bb
from balance.core.torque import compute_torque
from balance.io.bearings_section import BearingsSpec, main_positions
from balance.io.layout_file import layout_from_dict, load_layout
from balance.io.problems import FieldProblem

# --------------------------------------------------------------------------- helpers


def by_part(
    throws: list[float],
    banks: list[float] | None = None,
    *,
    offset: float = 0.0,
    inertia: float | None = 1.7e-3,
    unbalance: float = 0.3,
    speed: str = "6500 rpm",
) -> Any:
    """A by-part engine (piston group, rigid rod with CG and inertia, crank unbalance)."""
    masses: dict[str, Any] = {
        "piston_group": "0.42 kg",
        "conrod": "0.55 kg",
        "conrod_cg_to_big_end": "38 mm",
        "crank_unbalance": f"{unbalance} kg",
    }
    if inertia is not None:
        masses["conrod_inertia"] = f"{inertia} kg m^2"
    crank: dict[str, Any] = {"throws": throws, "spacing": "91 mm"}
    if banks is not None:
        crank["banks"] = banks
    return layout_from_dict(
        {
            "name": "by part",
            "speed": speed,
            "geometry": {"stroke": "86 mm", "conrod_length": "143 mm", "offset": f"{offset} mm"},
            "masses": masses,
            "crank": crank,
        }
    )


def lumped_single(rec: float = 0.6, rot: float = 0.4) -> Any:
    return layout_from_dict(
        {
            "name": "single",
            "speed": "6000 rpm",
            "geometry": {"stroke": "86 mm", "conrod_length": "143 mm"},
            "masses": {"reciprocating": f"{rec} kg", "rotating": f"{rot} kg"},
            "cylinders": [{"throw": 0, "bank": 0, "z": "0 mm"}],
        }
    )


def rigid_body_pin_forces(engine: Any, theta: np.ndarray, gas: np.ndarray | None) -> np.ndarray:
    """Force of each big end on its pin, engine frame, from the rigid bodies (independent).

    Per cylinder and angle, in the cylinder's frame (X across the bore towards where the pin
    goes after TDC, Y along the bore), the unknowns are the force of the rod on the piston
    (Rx, Ry), the force of the pin on the rod (Cx, Cy) and the wall force on the piston N:

        piston:      m_p a_P = -(Rx, Ry) + (N, -G)
        rod:         m_c a_G = (Rx, Ry) + (Cx, Cy)
        rod, about G: I_G alpha = (P - G) x (Rx, Ry) + (C - G) x (Cx, Cy)

    solved as a 5x5 linear system.  Kinematics from the loop closure l sin(g) = r sin(b) - e,
    s = r cos(b) + l cos(g), differentiated twice by hand here (not balance.core.kinematics).
    """
    parts = engine.mass_parts
    w = engine.speed
    out = np.zeros((engine.n_cylinders, theta.size), dtype=complex)
    for i in range(engine.n_cylinders):
        r, ell, e = engine.crank_radius[i], engine.conrod_length[i], engine.offset[i]
        m_p, m_c, a = parts.piston_group[i], parts.conrod[i], parts.conrod_cg_to_big_end[i]
        i_g = parts.conrod_inertia[i]
        if np.isnan(i_g):
            i_g = m_c * a * (ell - a)
        b = theta + engine.throw[i] - engine.bank[i]
        g = np.arcsin((r * np.sin(b) - e) / ell)
        g1 = r * np.cos(b) / (ell * np.cos(g))
        g2 = (-r * np.sin(b) + ell * np.sin(g) * g1**2) / (ell * np.cos(g))
        s = r * np.cos(b) + ell * np.cos(g)
        s2 = -r * np.cos(b) - ell * np.cos(g) * g1**2 - ell * np.sin(g) * g2
        cx, cy = r * np.sin(b), r * np.cos(b)
        px, py = e + 0 * b, s
        a_c = (-(w**2) * cx, -(w**2) * cy)
        a_p = (0 * b, w**2 * s2)
        f = a / ell
        gx, gy = cx + f * (px - cx), cy + f * (py - cy)
        agx, agy = a_c[0] + f * (a_p[0] - a_c[0]), a_c[1] + f * (a_p[1] - a_c[1])
        alpha = w**2 * g2  # the rod's direction C->P is at pi/2 + g (counter-clockwise)
        gas_i = np.zeros_like(b) if gas is None else gas[i]
        for j in range(b.size):
            # unknowns: Rx, Ry, Cx, Cy, N
            m = np.array(
                [
                    [-1, 0, 0, 0, 1],
                    [0, -1, 0, 0, 0],
                    [1, 0, 1, 0, 0],
                    [0, 1, 0, 1, 0],
                    [
                        -(py[j] - gy[j]),
                        px[j] - gx[j],
                        -(cy[j] - gy[j]),
                        cx[j] - gx[j],
                        0,
                    ],
                ],
                dtype=float,
            )
            rhs = np.array(
                [
                    m_p * a_p[0][j],
                    m_p * a_p[1][j] + gas_i[j],
                    m_c * agx[j],
                    m_c * agy[j],
                    i_g * alpha[j],
                ]
            )
            _, _, c_x, c_y, _ = np.linalg.solve(m, rhs)
            fx, fy = -c_x, -c_y  # the rod on the pin
            out[i, j] = (fy + 1j * fx) * np.exp(1j * engine.bank[i])
    return out


def dense_stats(f: Any, period: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Brute force: mean of |F| on n uniform points (the trapezoidal rule); max of the
    samples, resampled three times around each row's best on 401 points spanning four of
    the previous spacings (the last spacing is 1e-6 of the first)."""
    theta = period * np.arange(n) / n
    chunks = [np.abs(f(theta[k : k + 2**16])) for k in range(0, n, 2**16)]
    values = np.concatenate(chunks, axis=1)
    mean = values.mean(axis=1)
    rows = np.arange(values.shape[0])
    best, top = theta[np.argmax(values, axis=1)], values.max(axis=1)
    h = period / n
    for _ in range(3):
        local = best[:, None] + np.linspace(-2 * h, 2 * h, 401)[None, :]
        # every row at its own window: all rows at all windows, keep each row's own
        near = np.abs(f(local.ravel())).reshape(rows.size, rows.size, -1)[rows, rows]
        best, top = local[rows, np.argmax(near, axis=1)], np.maximum(top, near.max(axis=1))
        h = 4 * h / 400
    return top, mean


# --------------------------------------------------------------------------- pin loads


@pytest.mark.parametrize(
    ("throws", "banks", "offset", "inertia"),
    [
        ([0, 180, 180, 0], None, 0.0, 1.7e-3),
        ([0, 90, 270, 180], [-45, 45], 0.0, 1.2e-3),
        ([0, 240, 120], [-30, 30], 4.0, 2.4e-3),
        ([0], None, -6.0, None),
    ],
)
def test_pin_loads_equal_rigid_body_newton_euler(throws, banks, offset, inertia):
    """Big-end forces (two-mass equivalent + inertia correction, closed form) equal the
    5x5 rigid-body solution of piston and rod with the rod's mass, CG and inertia, to
    1e-10 of the largest force, with offsets and V banks."""
    engine = by_part(throws, banks, offset=offset, inertia=inertia)
    theta = np.linspace(0.0, 2 * np.pi, 97, endpoint=False)
    got = bb.big_end_forces(engine, theta)
    want = rigid_body_pin_forces(engine, theta, None)
    scale = np.max(np.abs(want))
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * scale)


def test_pin_loads_with_gas_equal_rigid_body():
    """The same with the gas force of inline-4-gas on every piston."""
    engine = load_layout("inline-4-gas")
    theta = np.radians(np.linspace(0.0, 720.0, 181, endpoint=False))
    gas = bb.gas_forces(engine, theta)
    got = bb.big_end_forces(engine, theta, gas)
    want = rigid_body_pin_forces(engine, theta, gas)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * np.max(np.abs(want)))


def test_pin_load_sums_the_rods_of_a_pin():
    """A V8's crank pin carries both rods; the pin load is their sum."""
    engine = by_part([0, 90, 270, 180], [-45, 45])
    theta = np.linspace(0, 2 * np.pi, 32, endpoint=False)
    pins, _, _ = bb.loads_at(engine, theta)
    rods = bb.big_end_forces(engine, theta)
    group, _, cylinders = bb.pin_groups(engine)
    assert all(len(c) == 2 for c in cylinders)
    for g in range(pins.shape[0]):
        np.testing.assert_allclose(pins[g], rods[group == g].sum(axis=0), rtol=1e-14)


def test_lumped_two_mass_model_same_mains():
    """Without conrod_inertia the by-part rod is its two-mass model: the lumped engine
    with the same reciprocating and rotating masses has the same main loads; its pin loads
    differ exactly by the crank unbalance's centrifugal force (inside its rotating mass)."""
    parts = by_part([0, 180, 180, 0], inertia=None)
    lumped = dataclasses.replace(parts, mass_parts=None)
    theta = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    p1, m1, t1 = bb.loads_at(parts, theta)
    p2, m2, t2 = bb.loads_at(lumped, theta)
    scale = np.max(np.abs(m1))
    np.testing.assert_allclose(m1, m2, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(t1, t2, rtol=0, atol=1e-12 * scale)
    u = parts.mass_parts.crank_unbalance[0] * parts.crank_radius[0] * parts.speed**2
    _, _, cylinders = bb.pin_groups(parts)
    for g, cyls in enumerate(cylinders):
        phi = parts.throw[cyls[0] - 1]
        np.testing.assert_allclose(
            p2[g] - p1[g], u * np.exp(1j * (theta + phi)), rtol=0, atol=1e-12 * scale
        )


# --------------------------------------------------------------------------- lever rule


def test_lever_rule_between_two_mains():
    """A throw a quarter of the way from main 1 to main 2: 3/4 and 1/4 of its load."""
    shares = bb.lever_shares([0.025], [0.0, 0.1])
    np.testing.assert_allclose(shares, [[0.75], [0.25]], rtol=1e-15)


def test_lever_rule_cantilever():
    """Throws beyond the outermost mains: the near main carries more than the load and the
    far main a negative share (it holds the shaft down)."""
    shares = bb.lever_shares([-0.05, 0.15], [0.0, 0.1])
    np.testing.assert_allclose(shares, [[1.5, -0.5], [-0.5, 1.5]], rtol=1e-14)
    shares = bb.lever_shares([-0.05], [0.0, 0.1, 0.2])
    np.testing.assert_allclose(shares[:, 0], [1.5, -0.5, 0.0], rtol=1e-14)


def test_lever_rule_only_neighbours_and_on_a_main():
    shares = bb.lever_shares([0.15, 0.1], [0.0, 0.1, 0.2, 0.3])
    np.testing.assert_allclose(shares[:, 0], [0, 0.5, 0.5, 0], atol=1e-15)
    np.testing.assert_allclose(shares[:, 1], [0, 1, 0, 0], atol=1e-15)


@given(
    z=st.lists(st.floats(-1.0, 1.0), min_size=1, max_size=8),
    gaps=st.lists(st.floats(0.01, 0.5), min_size=1, max_size=6),
    start=st.floats(-1.0, 0.5),
)
def test_lever_rule_statics(z, gaps, start):
    """Shares of every load sum to 1 (forces) and sum_m S z_m = z (moments)."""
    mains = start + np.concatenate([[0.0], np.cumsum(gaps)])
    shares = bb.lever_shares(z, mains)
    np.testing.assert_allclose(shares.sum(axis=0), 1.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(mains @ shares, z, rtol=0, atol=1e-12 * (1 + np.max(np.abs(z))))


def test_single_throw_between_mains_engine():
    """Single cylinder, mains at -50 mm and 150 mm: 3/4 and 1/4 of the throw load at every
    angle; internal moment at the far main = 0.15 m x throw load."""
    engine = lumped_single()
    theta = np.linspace(0, 2 * np.pi, 50, endpoint=False)
    pins, mains, moments = bb.loads_at(engine, theta, mains=[-0.05, 0.15])
    np.testing.assert_allclose(mains[0], 0.75 * pins[0], rtol=1e-14)
    np.testing.assert_allclose(mains[1], 0.25 * pins[0], rtol=1e-14)
    np.testing.assert_allclose(moments[0], 0.0)
    np.testing.assert_allclose(moments[1], 0.15 * pins[0], rtol=1e-14)


def test_default_mains():
    np.testing.assert_allclose(
        bb.default_mains([0, 0.09, 0.18, 0.27]), [-0.045, 0.045, 0.135, 0.225, 0.315]
    )
    np.testing.assert_allclose(bb.default_mains([0, 0, 0.1, 0.1]), [-0.05, 0.05, 0.15])
    np.testing.assert_allclose(bb.default_mains([0.0], pitch=0.09), [-0.045, 0.045])
    np.testing.assert_allclose(bb.default_mains([0.0], stroke=0.07), [-0.07, 0.07])


# --------------------------------------------------------------------------- balance factor


@pytest.mark.parametrize("factor", [0.0, 0.5, 1.0])
def test_single_cylinder_balance_factor(factor):
    """Single cylinder, counterweight (m_rot + f m_rec) r opposite the pin: the rotating
    force disappears from the mains, and the vertical first order of the total main load is
    (1 - f) m_rec r w^2 (a1 = 1 without offset): at 100 % it is zero, put wholly into the
    horizontal, which becomes -f m_rec r w^2 sin(theta) plus the wall force's first order."""
    engine = lumped_single()
    m_rec, m_rot = engine.reciprocating_mass[0], engine.rotating_mass[0]
    r, w2 = engine.crank_radius[0], engine.speed**2
    u = -(m_rot + factor * m_rec) * r
    n = 256
    theta = 2 * np.pi * np.arange(n) / n
    pins, mains, _ = bb.loads_at(engine, theta, counterweights=[(0.0, u)])
    total = mains.sum(axis=0)
    fy, fx = total.real, total.imag
    first_y = 2 * np.mean(fy * np.cos(theta))
    np.testing.assert_allclose(first_y, (1 - factor) * m_rec * r * w2, rtol=1e-12, atol=1e-9)
    # the wall force N (= fx without counterweight and rotating mass) is odd: sin terms only
    bare = pins[0] - m_rot * r * w2 * np.exp(1j * theta)
    first_x_wall = 2 * np.mean(bare.imag * np.sin(theta))
    first_x = 2 * np.mean(fx * np.sin(theta))
    np.testing.assert_allclose(first_x, first_x_wall - factor * m_rec * r * w2, rtol=1e-12)


def test_balance_factor_lowers_main_loads():
    """At 50 % the largest main load of a single is below that at 0 %; at 0 % it is the
    reciprocating force at TDC, m r w^2 (1 + lambda) with the two-mass model."""
    engine = lumped_single()
    m_rec, m_rot = engine.reciprocating_mass[0], engine.rotating_mass[0]
    r, w2 = engine.crank_radius[0], engine.speed**2
    lam = r / engine.conrod_length[0]
    res = {}
    for f in (0.0, 0.5, 1.0):
        cw = [(0.0, -(m_rot + f * m_rec) * r)]
        res[f] = bb.bearing_loads(engine, mains=[-0.05, 0.05], counterweights=cw)
    total0 = 2 * res[0.0].main_max[0]
    assert total0 == pytest.approx(m_rec * r * w2 * (1 + lam), rel=1e-12)
    assert res[0.5].main_max[0] < res[0.0].main_max[0]


# --------------------------------------------------------------------------- statistics


@pytest.mark.parametrize("name", ["inline-4", "v12-60", "v8-crossplane", "single"])
def test_max_and_mean_against_dense_sampling(name):
    """Refined max and integrated mean of every pin, main and moment equal a brute-force
    2^14-point sampling (plus local resampling of the max) to 1e-9 relative.

    2^14 points suffice: these loads are smooth, so the uniform rule converges
    geometrically; measured against the code's values, its means agree to 4e-16
    (inline-4: 8e-14) from 2^11 points on and its maxima to 2e-14 from 2^12, the same as
    with 2^18 or 2^20 points.  Sampling that a near-zero load needs is in
    :func:`test_near_zero_load_uses_graded_rule`."""
    engine = load_layout(name)
    cws = [(engine.z[0], 0.01 + 0.003j)]  # a counterweight, to break symmetries
    loads = bb.bearing_loads(engine, counterweights=cws)

    def f(t: np.ndarray) -> np.ndarray:
        return np.concatenate(bb.loads_at(engine, t, counterweights=cws), axis=0)

    dmax, dmean = dense_stats(f, 2 * np.pi, 2**14)
    got_max = np.concatenate([loads.pin_max, loads.main_max, loads.moment_max])
    got_mean = np.concatenate([loads.pin_mean, loads.main_mean, loads.moment_mean])
    scale = np.maximum(dmax, 1e-300)
    np.testing.assert_array_less(np.abs(got_max - dmax) / scale, 1e-9)
    np.testing.assert_array_less(np.abs(got_mean - dmean) / scale, 1e-9)
    assert np.all(got_max >= dmax * (1 - 1e-12))  # refined max is never below the samples


def test_near_zero_load_uses_graded_rule():
    """The V12's moment at the last main passes within 4e-5 of its maximum of zero, so the
    uniform rule on the code's first grid (1024 points) misses its mean by more than 1e-7;
    the graded rule's mean matches a 128 times denser sampling to 1e-9.

    2^17 points: near the zero :math:`|F|` is almost a kink, and the uniform rule converges
    only as :math:`h^2` there; measured against the code's mean, 2^15 points are off by
    4e-10, 2^17 by 4e-11, 2^19 by 1e-12 and 2^21 by 2e-16 (relative)."""
    engine = load_layout("v12-60")
    loads = bb.bearing_loads(engine)
    last = loads.moment_max.size - 1

    def f(t: np.ndarray) -> np.ndarray:
        return bb.loads_at(engine, t)[2][last:]

    n = 2**17
    theta = 2 * np.pi * np.arange(n) / n
    values = np.abs(np.concatenate([f(theta[k : k + 2**15]) for k in range(0, n, 2**15)], axis=1))
    assert np.min(values) < 4e-5 * loads.moment_max[last]
    coarse = np.mean(values[0, :: n // _numerics.START_GRID])
    assert abs(coarse - loads.moment_mean[last]) > 1e-7 * loads.moment_mean[last]
    assert loads.moment_mean[last] == pytest.approx(np.mean(values), rel=1e-9)


def test_gas_max_and_mean_against_dense_sampling():
    """With gas (two revolutions), against 2^18 points over 720 deg.

    With gas the loads have kinks (the trace is linear between its points), so the uniform
    rule converges only as :math:`h^2`: measured against the code's values its means are
    off by 1e-8 with 2^15 points, 4e-11 with 2^18 and 8e-12 with 2^20, its maxima by 4e-11
    from 2^18 on (relative)."""
    engine = load_layout("inline-4-gas")
    loads = bb.bearing_loads(engine)
    assert loads.gas and loads.cycle == pytest.approx(4 * np.pi)

    def f(t: np.ndarray) -> np.ndarray:
        pins, mains, _ = bb.loads_at(engine, t)
        return np.concatenate([pins, mains], axis=0)

    dmax, dmean = dense_stats(f, 4 * np.pi, 2**18)
    got_max = np.concatenate([loads.pin_max, loads.main_max])
    got_mean = np.concatenate([loads.pin_mean, loads.main_mean])
    np.testing.assert_allclose(got_max, dmax, rtol=1e-9)
    np.testing.assert_allclose(got_mean, dmean, rtol=1e-9)


def test_an_angle_gives_the_same_bits_alone_or_in_a_batch():
    """The gas statistics search each dip and peak one angle per quantity and compare with
    the values on the Gauss nodes, all evaluated many angles at once: a load at an angle
    must not depend on which other angles it is evaluated with (a matrix product would
    change its last bits with the number of columns)."""
    engine = load_layout("v8-crossplane-gas")
    theta = np.random.default_rng(3).uniform(0.0, 4 * np.pi, 67)
    cws = [(engine.z[0], 0.01 + 0.003j)]
    together = np.concatenate(bb.loads_at(engine, theta, counterweights=cws), axis=0)
    for j in (0, 1, 33, 66):
        alone = np.concatenate(bb.loads_at(engine, theta[j : j + 1], counterweights=cws), axis=0)
        assert np.array_equal(alone[:, 0], together[:, j])
    pair = np.concatenate(bb.loads_at(engine, theta[5:7], counterweights=cws), axis=0)
    assert np.array_equal(pair, together[:, 5:7])


def test_mean_converges_geometrically():
    """The trapezoidal mean of a smooth |F| converges geometrically: 64 points already
    agree with 4096 to 1e-9, 512 to rounding."""
    engine = load_layout("inline-4")

    def mean(n: int) -> np.ndarray:
        t = 2 * np.pi * np.arange(n) / n
        return np.abs(np.concatenate(bb.loads_at(engine, t)[:2])).mean(axis=1)

    ref = mean(4096)
    errors = [np.max(np.abs(mean(n) - ref) / ref) for n in (16, 32, 64, 128, 256, 512)]
    assert errors[2] < 1e-9 and errors[-1] < 1e-14
    assert errors[0] > errors[1] > errors[2]


# --------------------------------------------------------------------------- gas torque


def test_gas_mean_tangential_pin_force_times_r_is_mean_torque_per_cylinder():
    """Inline-4 with gas: the mean over the cycle of each pin's tangential force x r equals
    the mean engine torque of core.torque divided by the number of cylinders; at every angle
    the pin's tangential and radial force are core.torque's."""
    engine = load_layout("inline-4-gas")
    torque = compute_torque(engine, np.arange(1, 9))
    theta = np.radians(torque.crank_angle)
    gas = bb.gas_forces(engine, theta)
    np.testing.assert_allclose(gas, torque.gas_force, rtol=0, atol=1e-12 * np.max(gas))
    rods = bb.big_end_forces(engine, theta, gas)
    direction = 1j * np.exp(1j * (theta[None, :] + engine.throw[:, None]))  # rotation sense
    tangential = np.real(rods * np.conj(direction))
    mean_torque = (tangential * engine.crank_radius[:, None]).mean(axis=1)
    np.testing.assert_allclose(mean_torque, torque.mean / 4, rtol=1e-9)
    # and at every angle the pin's tangential and radial forces are core.torque's T and K
    # (both with the rod's inertia beyond its two-mass model, Delta I != 0), K less the
    # centrifugal force of the rod's big-end share
    assert np.all(engine.conrod_inertia_correction != 0.0)
    np.testing.assert_allclose(
        tangential * engine.crank_radius[:, None],
        torque.cylinder_torque,
        rtol=0,
        atol=1e-9 * np.max(np.abs(torque.cylinder_torque)),
    )
    big_end = (engine.rotating_mass - bb.crank_unbalance_share(engine)) * engine.speed**2
    radial = -np.real(rods * np.exp(-1j * (theta[None, :] + engine.throw[:, None])))
    np.testing.assert_allclose(
        radial + (big_end * engine.crank_radius)[:, None],
        torque.radial_force,
        rtol=0,
        atol=1e-9 * np.max(np.abs(torque.radial_force)),
    )


# --------------------------------------------------------------------------- invariances


def _rotated(engine: Any, delta: float) -> Any:
    return dataclasses.replace(engine, throw=engine.throw + delta)


@settings(max_examples=25, deadline=None)
@given(layout=random_layouts(max_cylinders=5), delta=st.floats(-np.pi, np.pi))
def test_crank_angle_origin(layout, delta):
    """Turning every throw by delta shifts the loads in crank angle: at theta the new engine
    is the old one at theta + delta; max and mean are unchanged."""
    theta = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    mains = bb.engine_default_mains(layout)
    a = bb.loads_at(layout, theta + delta, mains=mains)
    b = bb.loads_at(_rotated(layout, delta), theta, mains=mains)
    scale = max(np.max(np.abs(a[1])), 1e-300)
    np.testing.assert_allclose(b[1], a[1], rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(b[2], a[2], rtol=0, atol=1e-10 * scale * 10)
    la = bb.bearing_loads(layout, mains=mains)
    lb = bb.bearing_loads(_rotated(layout, delta), mains=mains)
    np.testing.assert_allclose(lb.main_max, la.main_max, rtol=1e-9, atol=1e-9 * scale)
    np.testing.assert_allclose(lb.main_mean, la.main_mean, rtol=1e-9, atol=1e-9 * scale)
    np.testing.assert_allclose(np.sort(lb.pin_max), np.sort(la.pin_max), rtol=1e-9)


@settings(max_examples=25, deadline=None)
@given(layout=random_layouts(max_cylinders=6), seed=st.integers(0, 2**31))
def test_cylinder_numbering(layout, seed):
    """Renumbering the cylinders changes no load (pins keyed by their plane and angle)."""
    perm = np.random.default_rng(seed).permutation(layout.n_cylinders)
    other = layout.reordered(perm)
    a, b = bb.bearing_loads(layout), bb.bearing_loads(other)
    np.testing.assert_allclose(b.main_z, a.main_z)
    np.testing.assert_allclose(b.main_max, a.main_max, rtol=1e-12)
    np.testing.assert_allclose(b.main_mean, a.main_mean, rtol=1e-12)
    np.testing.assert_allclose(b.moment_max, a.moment_max, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(b.pin_max, a.pin_max, rtol=1e-12)


def test_a_pin_whose_rods_differ_in_z_below_rounding_keeps_its_plane_when_renumbered():
    """Rods within 1e-12 m of one plane share a pin (``crank_pins``); the pin's plane is
    the least of theirs, not the last cylinder's.  Hypothesis found this numbering
    dependence (z = 0, 0, 0, 3.7e-13 m: main loads 18.75 N against 18.7499999998595 and
    18.75000000014045 N when cylinder 4 came last)."""
    z = np.array([0.0, 0.0, 0.0, 3.74524841e-13])
    layout = dataclasses.replace(
        load_layout("inline-4"), z=z, throw=np.zeros(4), reference_z=0.0, mass_parts=None
    )
    loads = [
        bb.bearing_loads(layout.reordered(np.asarray(p))) for p in ([0, 1, 2, 3], [3, 2, 1, 0])
    ]
    for each in loads:
        assert each.pin_z.tolist() == [0.0]
        assert each.main_max[0] == each.main_max[1]
    np.testing.assert_array_equal(loads[1].main_max, loads[0].main_max)
    np.testing.assert_array_equal(loads[1].pin_max, loads[0].pin_max)


def test_gas_needs_nothing_else_and_moments_stay_inertia_only():
    engine = load_layout("inline-4-gas")
    with_gas = bb.bearing_loads(engine)
    without = bb.bearing_loads(engine, gas=False)
    np.testing.assert_allclose(with_gas.moment_max, without.moment_max, rtol=1e-15)
    assert not np.allclose(with_gas.main_max, without.main_max)


def test_crank_frame():
    """At theta = 0 a force along the throw is real in the crank frame."""
    f = bb.crank_frame(np.array([2.0 * np.exp(1j * 0.3)]), np.array([0.1]), 0.2)
    np.testing.assert_allclose(f, [2.0], atol=1e-15)


# --------------------------------------------------------------------------- bearings section


def test_section_default_and_given():
    engine = load_layout("inline-4")
    np.testing.assert_allclose(main_positions(None, engine), bb.engine_default_mains(engine))
    np.testing.assert_allclose(
        main_positions(BearingsSpec.model_validate({}), engine), bb.engine_default_mains(engine)
    )
    spec = BearingsSpec.model_validate({"mains": ["-45 mm", "45 mm", "136 mm", "10 in"]})
    np.testing.assert_allclose(main_positions(spec, engine), [-0.045, 0.045, 0.136, 0.254])


@pytest.mark.parametrize(
    ("mains", "message", "at"),
    [
        (["45 mm"], "mains has 1 entry", ("mains",)),
        (["45 mm", "40 mm"], "main 2 at 40 mm is not after main 1 at 45 mm", ("mains", 1)),
        (["45 mm", "45 mm"], "is not after", ("mains", 1)),
    ],
)
def test_section_problems(mains, message, at):
    from pydantic import ValidationError

    with pytest.raises(ValidationError) as info:
        BearingsSpec.model_validate({"mains": mains})
    problem = info.value.errors()[0]["ctx"]["error"]
    assert isinstance(problem, FieldProblem)
    assert message in str(problem) and problem.at == at and problem.valid


def test_section_main_on_a_throw_plane():
    engine = load_layout("inline-4")
    spec = BearingsSpec.model_validate({"mains": ["-45 mm", "90 mm", "300 mm"]})
    with pytest.raises(FieldProblem) as info:
        main_positions(spec, engine)
    assert "main 2 at 90 mm is in the plane of the crank pin of cylinder 2" in str(info.value)
    assert info.value.at == ("mains", 1)


def test_section_unknown_key_and_units():
    from pydantic import ValidationError

    with pytest.raises(ValidationError):
        BearingsSpec.model_validate({"main": ["0 mm", "1 mm"]})
    with pytest.raises(ValidationError):
        BearingsSpec.model_validate({"mains": ["0 kg", "1 mm"]})
