"""Several crankshafts against a brute-force simulation that shares nothing with the package.

Every body of every crankshaft is placed in the engine frame at N crank angles from the
geometry alone (docs/several-crankshafts.md): the crank pin at
``alpha = phase + sigma (theta + throw)`` on its axis, the piston pin on the bore line
(offset towards the side the pin moves to after TDC), the rod as its two masses plus a
massless body of inertia ``conrod_inertia_correction`` turning with the rod.  Velocities
and accelerations are spectral derivatives of the positions; forces are ``-sum m a``,
the roll is ``-dLambda/dt - sigma_o sum_s M_s`` with ``Lambda`` the angular momentum of
every body about the frame's z axis, and each shaft's torque ``M_s`` comes from energy:
``M_s omega = -d(kinetic energy of its pistons and rods)/dt``.  Each is transformed into
phasors and compared with every rung of the model ladder (docs/validation.md,
"Several crankshafts").
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import pytest

from balance.api import Engine, compute_result
from balance.core.engine import Links
from tests.geared_engines import cylinders, with_crankshafts

N = 512  # crank angles per revolution


def _unit(angle: Any) -> Any:
    """Engine-frame unit vector at an angle from +y towards +x, as (x, y)."""
    return np.stack([np.sin(angle), np.cos(angle)])


def _spectral_derivative(values: Any, omega: float) -> Any:
    """d/dt of periodic samples over one revolution (last axis), at crank speed omega."""
    k = np.fft.fftfreq(values.shape[-1], 1.0 / values.shape[-1])
    k[values.shape[-1] // 2] = 0.0  # the Nyquist term of a real signal
    return np.real(np.fft.ifft(1j * k * omega * np.fft.fft(values, axis=-1), axis=-1))


@dataclass
class Bodies:
    """Per cylinder over the crank angles: piston pin and crank pin positions (2, N) [m],
    the rod angle [rad], the cylinder's shaft."""

    piston: list[Any]
    pin: list[Any]
    rod_angle: list[Any]


def place(engine: Engine, theta: Any) -> Bodies:
    """Every body of every cylinder from the geometry.  A link rod's lower end is its link
    pin on its master's rod, ``pin_radius`` from the crank pin at ``pin_angle`` from the
    master rod's centre line (engine-frame sense); there its cylinder's rotating mass sits
    (the test engines' link cylinders have no share of a crank unbalance)."""
    shafts = engine.crankshafts
    assert shafts is not None
    links = engine.links
    n = engine.n_cylinders
    pistons, pins, angles = [None] * n, [None] * n, [None] * n
    linked = [links is not None and links.master[i] >= 0 for i in range(n)]
    # masters and plain rods first: a link rod hangs on its master's
    for i in sorted(range(n), key=lambda i: linked[i]):
        s = int(shafts.of_cylinder[i])
        sigma = float(shafts.rotation[s])
        axis = np.array([shafts.x[s], shafts.y[s]])[:, None]
        r, length, e = engine.crank_radius[i], engine.conrod_length[i], engine.offset[i]
        alpha = shafts.phase[s] + sigma * (theta + engine.throw[i])
        c = r * _unit(alpha)  # crank pin from the axis
        if linked[i]:
            assert links is not None
            m = int(links.master[i])
            c = c + links.pin_radius[i] * _unit(angles[m] + links.pin_angle[i])
        u = _unit(engine.bank[i])  # along the bore, crank to head
        w = _unit(engine.bank[i] + sigma * math.pi / 2)  # the offset's side
        c_u, c_w = u @ c, w @ c
        s_along = c_u + np.sqrt(length**2 - (e - c_w) ** 2)
        p = e * w[:, None] + s_along[None, :] * u[:, None]
        pistons[i] = axis + p
        pins[i] = axis + c
        d = p - c
        angles[i] = np.unwrap(np.arctan2(d[0], d[1]))
    return Bodies(pistons, pins, angles)


def _cross(q: Any, v: Any) -> Any:
    """y v_x - x v_y: the moment about z of v at q, positive in crankshaft 1's sense."""
    return q[1] * v[0] - q[0] * v[1]


def _forward_backward(signal: Any, orders: Any) -> tuple[Any, Any]:
    spectrum = np.fft.fft(signal) / signal.size
    return spectrum[orders], spectrum[-orders]


def _real_phasors(signal: Any, orders: Any) -> Any:
    return 2.0 * np.fft.fft(signal)[orders] / signal.size


def brute_force(engine: Engine, orders: Any) -> dict[str, Any]:
    """Phasors of the whole engine and of each shaft, from the bodies."""
    shafts = engine.crankshafts
    assert shafts is not None
    w = engine.speed
    theta = 2.0 * np.pi * np.arange(N) / N
    bodies = place(engine, theta)
    n_shafts = shafts.count
    force = np.zeros((n_shafts, 2, N))
    moment = np.zeros((2, N))
    spin = np.zeros(N)  # angular momentum about the frame's z
    own_spin = np.zeros((n_shafts, N))
    energy = np.zeros((n_shafts, N))
    lever = engine.z - engine.reference_z
    for i in range(engine.n_cylinders):
        s = int(shafts.of_cylinder[i])
        axis = np.array([shafts.x[s], shafts.y[s]])[:, None]
        for mass, q in (
            (engine.reciprocating_mass[i], bodies.piston[i]),
            (engine.rotating_mass[i], bodies.pin[i]),
        ):
            v = _spectral_derivative(q, w)
            a = _spectral_derivative(v, w)
            force[s] -= mass * a
            moment -= lever[i] * mass * a
            spin += mass * _cross(q, v)
            own_spin[s] += mass * _cross(q - axis, v)
            energy[s] += 0.5 * mass * np.sum(v * v, axis=0)
        # the rod's inertia beyond its two masses, turning with the rod (crankshaft 1's sense)
        rate = _spectral_derivative(bodies.rod_angle[i], w)
        spin += engine.conrod_inertia_correction[i] * rate
        own_spin[s] += engine.conrod_inertia_correction[i] * rate
        energy[s] += 0.5 * engine.conrod_inertia_correction[i] * rate**2
    torque = -_spectral_derivative(energy, w) / w  # M_s, own sense (the crank turns at w)
    sigma = shafts.rotation
    roll = -_spectral_derivative(spin, w) - shafts.output_rotation * torque.sum(axis=0)
    own_roll = -_spectral_derivative(own_spin, w) - sigma[:, None] * torque
    as_complex = force[:, 1] + 1j * force[:, 0]  # y + i x
    moment_z = sum(_cross(np.array([shafts.x[s], shafts.y[s]]), force[s]) for s in range(n_shafts))
    total = as_complex.sum(axis=0)
    return {
        "force": _forward_backward(total, orders),
        "moment": _forward_backward(moment[1] + 1j * moment[0], orders),
        "shaft_force": [_forward_backward(as_complex[s], orders) for s in range(n_shafts)],
        "roll": _real_phasors(roll, orders),
        "own_roll": np.stack([_real_phasors(own_roll[s], orders) for s in range(n_shafts)]),
        "torque": np.stack([_real_phasors(torque[s], orders) for s in range(n_shafts)]),
        "moment_z": _real_phasors(moment_z, orders),
    }


def counter_rotating_pair(output: float) -> Engine:
    """Two cranks, the second counter-rotating, displaced, with offsets, a rod inertia
    correction and phases."""
    base = cylinders([0.0, 90.0, 30.0], [10.0, -25.0, 50.0], [0.0, 0.05, 0.1])
    base = replace(
        base,
        offset=np.array([0.004, -0.003, 0.002]),
        conrod_inertia_correction=np.array([2e-4, -1e-4, 3e-4]),
        rotating_mass=np.array([0.4, -0.3, 0.2]),
    )
    return with_crankshafts(
        base,
        [0, 1, 1],
        x=[-0.05, 0.06],
        y=[0.01, -0.02],
        rotation=[1.0, -1.0],
        phase_deg=[0.0, 37.0],
        output=output,
    )


def deltic_like() -> Engine:
    """Three shafts at the corners of a triangle, the third counter-rotating; three
    bores along its sides, each with one piston on either end's shaft."""
    corners = [(0.0, 0.0), (0.5, 0.0), (0.25, 0.433)]
    pairs = [(0, 1), (1, 2), (2, 0)]
    throws, banks, z, of = [], [], [], []
    for j, (a, b) in enumerate(pairs):
        (xa, ya), (xb, yb) = corners[a], corners[b]
        toward = math.degrees(math.atan2(xb - xa, yb - ya))  # from +y towards +x
        throws += [120.0 * j, 120.0 * j]
        banks += [toward, toward + 180.0]
        z += [0.1 * j, 0.1 * j]
        of += [a, b]
    base = cylinders(throws, banks, z)
    base = replace(base, conrod_inertia_correction=np.full(6, 2e-4))
    return with_crankshafts(
        base,
        of,
        x=[c[0] for c in corners],
        y=[c[1] for c in corners],
        rotation=[1.0, 1.0, -1.0],
        phase_deg=[0.0, 180.0, 11.0],
    )


def h16_like() -> Engine:
    """Two flat-four crankshafts one above the other, geared, the lower one counter-rotating
    and 90 deg out of phase, the output turning with the upper one."""
    throws = [0.0, 180.0, 180.0, 0.0] * 2
    banks = [-90.0, 90.0, -90.0, 90.0] * 2
    z = [0.0, 0.05, 0.1, 0.15] * 2
    base = cylinders(throws, banks, z)
    return with_crankshafts(
        base,
        [0] * 4 + [1] * 4,
        x=[0.0, 0.0],
        y=[0.15, -0.15],
        rotation=[1.0, -1.0],
        phase_deg=[0.0, 90.0],
    )


def link_rods_on_three_shafts() -> Engine:
    """A 60 deg V-twin with a link rod on crankshaft 1; a W-3 (master at 10 deg, link rods
    at -40 and +65 deg with pin angles off the bank differences, offsets, rod inertias) on
    a displaced counter-rotating shaft with a phase; a V-twin with a link rod on a
    displaced co-rotating shaft with a phase."""
    base = cylinders(
        [0.0, 0.0, 40.0, 40.0, 40.0, 120.0, 120.0],
        [-30.0, 30.0, 10.0, -40.0, 65.0, -30.0, 30.0],
        [0.0, 0.0, 0.06, 0.06, 0.06, 0.12, 0.12],
    )
    base = replace(
        base,
        conrod_length=np.array([0.143, 0.11, 0.15, 0.12, 0.118, 0.143, 0.11]),
        offset=np.array([0.0, 0.002, 0.003, -0.002, 0.004, -0.001, 0.0]),
        conrod_inertia_correction=np.array([2e-4, 1e-4, -1e-4, 3e-4, 1.5e-4, 0.0, 2e-4]),
        reciprocating_mass=np.array([0.6, 0.5, 0.7, 0.45, 0.55, 0.6, 0.5]),
        # a link cylinder's rotating mass is its link rod's share at the link pin
        rotating_mass=np.array([0.4, 0.15, -0.2, 0.12, 0.18, 0.4, 0.15]),
        links=Links(
            master=np.array([-1, 0, -1, 2, 2, -1, 5], dtype=np.intp),
            pin_radius=np.array([0.0, 0.03, 0.0, 0.032, 0.028, 0.0, 0.025]),
            pin_angle=np.radians([0.0, 64.0, 0.0, -47.0, 58.0, 0.0, 60.0]),
        ),
    )
    return with_crankshafts(
        base,
        [0, 0, 1, 1, 1, 2, 2],
        x=[0.0, 0.21, -0.05],
        y=[0.0, -0.04, 0.23],
        rotation=[1.0, -1.0, 1.0],
        phase_deg=[0.0, 37.0, -22.0],
        output=-1.0,
    )


ENGINES = {
    "counter-rotating pair, output same": lambda: counter_rotating_pair(1.0),
    "counter-rotating pair, output opposite": lambda: counter_rotating_pair(-1.0),
    "Deltic-like triangle": deltic_like,
    "H16-like, 90 deg phase": h16_like,
    "link rods on three shafts": link_rods_on_three_shafts,
}


def _close(actual: Any, expected: Any, scale: float, rel: float) -> None:
    np.testing.assert_allclose(np.asarray(actual), np.asarray(expected), rtol=0, atol=rel * scale)


@pytest.mark.parametrize("name", list(ENGINES))
@pytest.mark.parametrize("model", ["exact", "series", "textbook", "time"])
def test_every_rung_matches_the_brute_force_bodies(name, model):
    engine = ENGINES[name]()
    orders = np.arange(1, 7)
    expected = brute_force(engine, orders)
    result = compute_result(engine, 6, model=model, terms=6, proposal=False)
    free = result.phasors.free()
    w2 = engine.speed**2
    force_scale = float(np.sum(engine.reciprocating_mass * engine.crank_radius)) * w2
    torque_scale = float(np.sum(engine.reciprocating_mass * engine.crank_radius**2)) * w2
    # the force rungs are within their stated error bound; the roll and torque of every
    # phasor rung are exact Fourier series, the time rung's are sampled
    rel = 1e-9 if model in ("exact", "time") else 2.0 * result.model.error_bound + 1e-9
    _close(free.force_forward, expected["force"][0], force_scale, rel)
    _close(free.force_backward, expected["force"][1], force_scale, rel)
    _close(free.moment_forward, expected["moment"][0], force_scale * 0.2, rel)
    _close(free.moment_backward, expected["moment"][1], force_scale * 0.2, rel)
    part = result.part("crankshafts")
    shaft_free = part.force.free()
    for s, (fwd, bwd) in enumerate(expected["shaft_force"]):
        _close(shaft_free.force_forward[s], fwd, force_scale, rel)
        _close(shaft_free.force_backward[s], bwd, force_scale, rel)
    moment_z_scale = force_scale * 0.5
    _close(part.moment_z, expected["moment_z"], moment_z_scale, rel)
    _close(part.torque, expected["torque"], torque_scale, 1e-9)
    _close(part.force.roll, expected["own_roll"], torque_scale, 1e-9)
    _close(result.roll, expected["roll"], torque_scale + moment_z_scale, max(rel, 1e-9))


def test_the_brute_force_sees_what_it_checks():
    """The oracle is not blind: the H16's roll with the gear couple differs from the same
    engine with both shafts driven from outside (output sense of each its own) by far more
    than the tolerance, and a shaft's torque by energy equals minus its own roll without
    offset and rod inertia."""
    engine = h16_like()
    orders = np.arange(1, 7)
    expected = brute_force(engine, orders)
    scale = float(np.sum(engine.reciprocating_mass * engine.crank_radius**2)) * engine.speed**2
    driven_outside = expected["own_roll"].sum(axis=0) + expected["moment_z"]
    assert np.max(np.abs(expected["roll"] - driven_outside)) > 0.1 * scale
    np.testing.assert_allclose(
        expected["own_roll"],
        -engine.crankshafts.rotation[:, None] * expected["torque"],
        atol=1e-9 * scale,
    )


def _with_proposal(engine: Engine, proposal: Any, orders: Any) -> dict[str, Any]:
    """The brute force with the proposal's masses as point masses: each counterweight on its
    shaft's axis at ``angle_deg + sigma theta``, each balance-shaft eccentric (unit radius)
    on its axis at its angle + ``speed_ratio theta``."""
    shafts = engine.crankshafts
    assert shafts is not None
    out = brute_force(engine, orders)
    w = engine.speed
    theta = 2.0 * np.pi * np.arange(N) / N
    force = np.zeros((2, N))
    moment = np.zeros((2, N))
    spin = np.zeros(N)
    moment_z = np.zeros(N)
    bodies = []
    for c in proposal.counterweights:
        s = shafts.names.index(c.axis)
        axis = np.array([shafts.x[s], shafts.y[s]])
        angle = np.angle(c.unbalance)  # y + i x: from +y towards +x
        q = axis[:, None] + c.radius * _unit(angle + shafts.rotation[s] * theta)
        bodies.append((abs(c.unbalance) / c.radius, q, c.z, axis))
    for b in proposal.shafts:
        for plane_z, u in b.planes:
            q = np.array([b.x, b.y])[:, None] + _unit(np.angle(u) + b.speed_ratio * theta)
            bodies.append((abs(u), q, plane_z, None))
    for mass, q, plane_z, axis in bodies:
        v = _spectral_derivative(q, w)
        a = _spectral_derivative(v, w)
        force -= mass * a
        moment -= (plane_z - engine.reference_z) * mass * a
        spin += mass * _cross(q, v)
        if axis is not None:  # a counterweight's force acts on its crankshaft's axis
            moment_z += _cross(axis, -mass * a)
    total = force[1] + 1j * force[0]
    added = {
        "force": _forward_backward(total, orders),
        "moment": _forward_backward(moment[1] + 1j * moment[0], orders),
        "roll": _real_phasors(-_spectral_derivative(spin, w), orders),
        "moment_z": _real_phasors(moment_z, orders),
    }
    for key in ("force", "moment"):
        out[key] = tuple(a + b for a, b in zip(out[key], added[key], strict=True))
    for key in ("roll", "moment_z"):
        out[key] = out[key] + added[key]
    return out


@pytest.mark.parametrize("name", list(ENGINES))
@pytest.mark.parametrize("strategy", ["two-plane", "per-throw"])
@pytest.mark.parametrize("factor", [None, 0.6])
def test_the_proposals_residual_matches_the_brute_force_with_its_masses(name, strategy, factor):
    """Counterweights turn with their shaft (backward on a counter-rotating one) and act on
    its axis: the residual force, moment, roll and moment about z of the proposal are the
    bodies' with the counterweights and balance-shaft eccentrics as point masses."""
    engine = ENGINES[name]()
    orders = np.arange(1, 7)
    result = compute_result(
        engine, 6, model="exact", strategy=strategy, balance_factor=factor, cancel=[1, 2]
    )
    part = result.part("proposal")
    # (the H16-like flat fours balance themselves over each shaft: no two-plane weights)
    assert part.proposal.counterweights or name.startswith("H16")
    expected = _with_proposal(engine, part.proposal, orders)
    residual = part.residual
    w2 = engine.speed**2
    force_scale = float(np.sum(engine.reciprocating_mass * engine.crank_radius)) * w2
    torque_scale = float(np.sum(engine.reciprocating_mass * engine.crank_radius**2)) * w2
    _close(residual.force_forward, expected["force"][0], force_scale, 1e-9)
    _close(residual.force_backward, expected["force"][1], force_scale, 1e-9)
    _close(residual.moment_forward, expected["moment"][0], force_scale * 0.2, 1e-9)
    _close(residual.moment_backward, expected["moment"][1], force_scale * 0.2, 1e-9)
    _close(part.residual_moment_z, expected["moment_z"], force_scale * 0.5, 1e-9)
    _close(residual.roll, expected["roll"], torque_scale + force_scale * 0.5, 1e-9)
    if factor is None:  # the default cancels the whole first order with counterweights
        # (and a backward shaft where no shaft counter-rotates)
        assert abs(expected["force"][0][0]) < 1e-9 * force_scale
        assert abs(expected["force"][1][0]) < 1e-9 * force_scale
        assert abs(expected["moment"][0][0]) < 1e-9 * force_scale
        assert abs(expected["moment"][1][0]) < 1e-9 * force_scale


def test_the_brute_force_sees_the_link_rods():
    """The oracle is not blind to the link rods of a counter-rotating shaft: the link pins'
    angles taken the other way (what treating each cylinder as its own mirror image would
    do) or the link pins put on the crank pins change its force and torque by far more than
    the tolerance."""
    engine = link_rods_on_three_shafts()
    orders = np.arange(1, 7)
    expected = brute_force(engine, orders)
    links = engine.links
    on_b = engine.crankshafts.of_cylinder == 1
    flipped = replace(
        engine,
        links=replace(links, pin_angle=np.where(on_b, -links.pin_angle, links.pin_angle)),
    )
    on_pins = replace(engine, links=replace(links, pin_radius=np.zeros_like(links.pin_radius)))
    w2 = engine.speed**2
    force_scale = float(np.sum(engine.reciprocating_mass * engine.crank_radius)) * w2
    torque_scale = float(np.sum(engine.reciprocating_mass * engine.crank_radius**2)) * w2
    for other in (flipped, on_pins):
        got = brute_force(other, orders)
        assert np.max(np.abs(got["shaft_force"][1][0] - expected["shaft_force"][1][0])) > (
            1e-4 * force_scale
        )
        assert np.max(np.abs(got["torque"][1] - expected["torque"][1])) > 1e-4 * torque_scale
