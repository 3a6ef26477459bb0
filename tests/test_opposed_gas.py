"""Gas forces on opposed pistons (docs/several-crankshafts.md, "Opposed pistons").

One pressure per bore acts on both pistons, read from the bore's smallest volume; each
piston's push drives its own shaft; there is no head, so the gas puts no force on the block.
The checks place the piston pins from the geometry alone (tests/test_geared_brute_force.py's
``place``) and form the bore's volume and each piston's work from them.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from balance.api import compute_result
from balance.cli import app
from balance.core.errors import InputError
from balance.io.layout_reader import layout_from_text
from tests.test_geared_brute_force import place

HEAD = """\
name: {name}
speed: 2200 rpm
cycle: {cycle}
geometry: {{bore: 105 mm, stroke: 160 mm, conrod_length: 350 mm}}
masses: {{piston_group: 3 kg, conrod: 2 kg, conrod_cg_to_big_end: 100 mm,
         crank_unbalance: 1.5 kg}}
"""
GAS = """\
gas:
  model: {compression_ratio: 17, peak_pressure: 90 bar, intake_pressure: 1.3 bar}
  crankcase_pressure: 1 bar
"""
JUMO = """\
crankshafts:
  - {name: intake}
  - {name: exhaust, y: 945 mm, phase: 191 deg}   # 180 + an 11 deg exhaust lead
crank:
  throws: [0, 120, 240, 180, 300, 60]
  spacing: 160 mm
  opposed: [intake, exhaust]
"""
# a Deltic-like triangle: three shafts, one turning the other way, offsets on one bank
DELTIC = """\
crankshafts:
  - {name: A, x: -500 mm}
  - {name: B, x: 500 mm, phase: 200 deg}
  - {name: C, y: 866.0254037844386 mm, rotation: opposite, phase: 270 deg}
output: {rotation: opposite}
crank:
  - {throws: [0, 120, 240], spacing: 200 mm, opposed: [A, B]}
  - {throws: [0, 120, 240], spacing: 200 mm, opposed: [B, C]}
  - {throws: [0, 120, 240], spacing: 200 mm, opposed: [C, A]}
"""


def engine(body: str, *, cycle: str = "two-stroke", gas: str = GAS):
    return layout_from_text(HEAD.format(name="opposed", cycle=cycle) + body + gas, "f.yaml")


def bore_geometry(eng, theta_deg):
    """Per cylinder: its pin's distance from its own axis along its bore [m]; per bore: the
    distance between the two piston pins [m], over ``theta_deg``."""
    bodies = place(eng, np.radians(theta_deg))
    shafts = eng.crankshafts
    own = []
    for i in range(eng.n_cylinders):
        s = int(shafts.of_cylinder[i])
        axis = np.array([shafts.x[s], shafts.y[s]])[:, None]
        u = np.array([math.sin(eng.bank[i]), math.cos(eng.bank[i])])
        own.append(u @ (bodies.piston[i] - axis))
    pairs = [(i, int(j)) for i, j in enumerate(shafts.opposed) if j > i]
    gap = {p: np.linalg.norm(bodies.piston[p[0]] - bodies.piston[p[1]], axis=0) for p in pairs}
    return np.array(own), gap


def derivative(values, samples):
    """d/d(theta) [per rad] of periodic samples over one revolution (spectral)."""
    k = np.fft.fftfreq(samples, 1.0 / samples)
    k[samples // 2] = 0.0
    return np.real(np.fft.ifft(1j * k * np.fft.fft(values, axis=-1), axis=-1))


@pytest.mark.parametrize("body", [JUMO, DELTIC], ids=["jumo", "deltic"])
def test_mean_torque_is_the_closed_integral_of_p_dv_over_two_pi(body):
    """The output's mean torque (the shafts' sum in their own senses) equals
    sum over bores of (closed integral of p dV) / 2 pi, V from the distance between the two
    piston pins placed from the geometry, to 1e-9; each shaft's mean torque is the work of
    its own pistons, sum of (p - p0) A (-ds/d theta) over the cycle, to 1e-9."""
    eng = engine(body)
    result = compute_result(eng, proposal=False)
    torque = result.part("torque")
    theta = torque.crank_angle
    samples = theta.size
    assert samples == 1440  # a two-stroke cycle, every 0.25 deg
    own, gap = bore_geometry(eng, theta)
    area = math.pi / 4.0 * 0.105**2
    work = 0.0
    for (i, j), d in gap.items():
        np.testing.assert_array_equal(torque.pressure[i], torque.pressure[j])
        work += np.mean(torque.pressure[i] * area * derivative(d, samples)) * 2.0 * math.pi
    assert torque.mean == pytest.approx(work / (2.0 * math.pi), rel=1e-9)
    assert torque.mean > 0.0
    push = (torque.pressure - 1.0e5) * area * -derivative(own, samples)
    shafts = result.shafts
    for s, members in enumerate(shafts.members):
        assert shafts.torque_mean[s] == pytest.approx(np.mean(push[members].sum(axis=0)), rel=1e-9)
    assert float(np.sum(shafts.torque_mean)) == pytest.approx(torque.mean, rel=1e-12)


def test_the_bore_fires_at_its_smallest_volume_between_the_two_inner_dead_centres():
    """Both pistons of a bore start their cycle where the pins are closest (found on a
    0.001 deg grid from the geometry), which with the 11 deg exhaust lead lies between the
    two pistons' inner dead centres, about 5.5 deg after the exhaust piston's."""
    eng = engine(JUMO)
    result = compute_result(eng, proposal=False)
    tdc = result.part("torque").firing_tdc
    for i in range(0, 12, 2):
        assert tdc[i] == tdc[i + 1]
        fine = tdc[i] + np.arange(-2000, 2001) * 1e-3
        _, gap = bore_geometry(eng, fine)
        assert abs(fine[int(np.argmin(gap[(i, i + 1)]))] - tdc[i]) <= 1e-3
        # intake piston i's inner dead centre (no offset): its own crank at its TDC
        lag = (tdc[i] - (np.degrees(eng.bank[i] - eng.throw[i]) % 360.0)) % 360.0
        assert lag == pytest.approx(360.0 - 5.5, abs=0.3)


@pytest.mark.parametrize("body", [JUMO, DELTIC], ids=["jumo", "deltic"])
def test_the_gas_puts_no_free_force_on_the_block(body):
    """The force, its moment and the moment about z with gas equal those without (to
    rounding): the two pistons' pushes reach the two axes along one bore line and cancel.
    The roll is the geared roll with the gas torque: its mean is -sigma_o times the mean
    torque, the orders of a two-stroke are whole (no half orders), and it is the sum of the
    shafts' own rolls, the moment about z and the gear couple."""
    eng = engine(body)
    with_gas = compute_result(eng, proposal=False)
    without = compute_result(replace(eng, gas=None), proposal=False)
    a, b = with_gas.phasors, without.phasors
    scale = float(np.max(np.abs(b.free().force_forward))) + float(np.max(np.abs(b.roll)))
    for name in ("force_forward", "force_backward", "moment_forward", "moment_backward"):
        np.testing.assert_allclose(
            getattr(a.free(), name), getattr(b.free(), name), rtol=0, atol=1e-12 * scale
        )
    np.testing.assert_allclose(
        with_gas.shafts.moment_z_reciprocating,
        without.shafts.moment_z_reciprocating,
        rtol=0,
        atol=1e-12 * scale,
    )
    torque = with_gas.part("torque")
    assert np.all(torque.roll_orders == np.round(torque.roll_orders))
    sigma_o = eng.axis_table().output_sense
    assert np.mean(torque.roll_torque) == pytest.approx(-sigma_o * torque.mean, rel=1e-9)
    shafts = with_gas.shafts
    parts = (
        shafts.force.roll.sum(axis=0)
        + shafts.moment_z_reciprocating
        + shafts.moment_z_rotating
        + shafts.gear_couple
    )
    np.testing.assert_allclose(with_gas.roll, parts, rtol=0, atol=1e-9 * np.max(np.abs(parts)))
    # the gas matters: the roll's sixth order (the bores fire every 60 or 120 deg) with gas
    # is not the inertia roll's
    six = int(np.flatnonzero(torque.roll_orders == 6.0)[0])
    assert abs(with_gas.roll[six] - without.roll[six]) > 100.0


def test_each_piston_drives_its_own_shaft():
    """The intake and exhaust shafts of the Jumo-like engine: the exhaust shaft, whose
    pistons lead by 11 deg and take the expansion earlier, delivers more; each shaft's gas
    torque is the same for each of its six pistons shifted by the firing interval."""
    result = compute_result(engine(JUMO), proposal=False)
    means = result.shafts.torque_mean
    assert means[1] > means[0] > 0.0
    cyl = result.part("torque").cylinder_torque
    # cylinders 1 and 3 (intake, throws 0 and 120): 3 is 120 deg ahead (0.25 deg steps)
    np.testing.assert_allclose(cyl[2], np.roll(cyl[0], -4 * 120), rtol=0, atol=1e-6 * 1e3)


def test_a_pressure_trace_is_read_from_the_bores_smallest_volume(tmp_path: Path):
    """With a trace, both pistons read it at theta - theta_0: the pressure row of every
    piston is the trace's, shifted by its bore's smallest-volume angle."""
    trace = tmp_path / "p.csv"
    angle = np.arange(-180.0, 180.0, 1.0)
    pressure = 1.0e5 + 80.0e5 * np.exp(-(((angle - 8.0) / 25.0) ** 2))
    trace.write_text(
        "crank_angle [deg],pressure [Pa]\n"
        + "".join(f"{a:g},{p:.6f}\n" for a, p in zip(angle, pressure, strict=True))
    )
    text = HEAD.format(name="trace", cycle="two-stroke") + JUMO + "gas: {pressure_trace: p.csv}\n"
    path = tmp_path / "jumo.yaml"
    path.write_text(text)
    from balance.io.layout_file import load_layout

    result = compute_result(load_layout(str(path)), proposal=False)
    torque = result.part("torque")
    for i in range(12):
        alpha = (torque.crank_angle - torque.firing_tdc[i]) % 360.0
        expected = np.interp(alpha, angle, pressure, period=360.0)
        np.testing.assert_allclose(torque.pressure[i], expected, rtol=1e-9)


def test_a_four_stroke_opposed_bore_with_gas_is_refused():
    four = replace(engine(JUMO), cycle="four-stroke")
    with pytest.raises(InputError) as caught:
        compute_result(four, proposal=False)
    assert "cycle: an opposed-piston bore with gas forces works a two-stroke" in str(caught.value)


def test_the_command_line_reports_the_torque_of_an_opposed_piston_engine(tmp_path: Path):
    path = tmp_path / "jumo.yaml"
    path.write_text(HEAD.format(name="Jumo-like", cycle="two-stroke") + JUMO + GAS)
    out = CliRunner().invoke(app, ["analyse", str(path), "--format", "json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    shafts = {s["name"]: s["torque_mean_Nm"] for s in data["crankshafts"]}
    assert shafts["intake"] + shafts["exhaust"] == pytest.approx(data["torque"]["mean_Nm"])
    assert data["torque"]["mean_Nm"] > 1000.0


def test_the_deltic_18_builtin_fires_every_20_degrees_and_shares_its_torque():
    """deltic-18: the triangle closes with a 20 deg exhaust lead in every bank, so the 18
    bores reach their smallest volumes evenly every 20 deg (each bore's two pistons at one
    angle), no crankshaft warning, and by the symmetry of the triangle each shaft takes a
    third of the torque (to 1e-9)."""
    from balance.io.layout_file import load_layout

    eng = load_layout("deltic-18")
    assert eng.arrangement_warnings() == []
    result = compute_result(eng, proposal=False)
    tdc = result.part("torque").firing_tdc
    bores = np.sort(tdc[0::2])
    np.testing.assert_array_equal(tdc[0::2], tdc[1::2])
    np.testing.assert_allclose(np.diff(bores), 20.0, rtol=0, atol=1e-9)
    means = result.shafts.torque_mean
    np.testing.assert_allclose(means, np.sum(means) / 3.0, rtol=1e-9)


def test_the_jumo_205_builtin_exhaust_shaft_takes_most_of_the_torque():
    """jumo-205: the exhaust shaft, 11 deg ahead, takes about 70 % of the indicated torque
    (Jumo 205: the upper shaft, the one that leads, delivered about three quarters of the
    power at the propeller, en.wikipedia.org Junkers Jumo 205; the rest of that figure is
    the auxiliaries the lower shaft drives, not modelled), and the mean torque, 2464 N m at
    2200 rpm, is an indicated 568 kW against the published 610 bhp (455 kW) brake."""
    from balance.io.layout_file import load_layout

    result = compute_result(load_layout("jumo-205"), proposal=False)
    intake, exhaust = result.shafts.torque_mean
    share = exhaust / (intake + exhaust)
    assert 0.65 < share < 0.75
    power = result.part("torque").mean * 2200 * 2 * math.pi / 60
    assert 455e3 / 0.85 < power < 455e3 / 0.75
