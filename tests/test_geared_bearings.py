"""Crank-pin and main-bearing loads with several crankshafts (docs/several-crankshafts.md,
"Bearing loads"): each shaft's loads are those of its own cylinders as a one-crank engine,
mirrored for a counter-rotating shaft; the mapping form of ``bearings.mains``; a brute-force
check of one counter-rotating shaft from the bodies' accelerations."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from balance.api import compute_result
from balance.cli import app
from tests.geared_engines import cylinders, with_crankshafts

runner = CliRunner()

TWIN = """\
name: twin-crank twin
speed: 7500 rpm
geometry: {{bore: 90 mm, stroke: 68 mm, conrod_length: 125 mm}}
masses: {{reciprocating: 0.51 kg, rotating: 0.27 kg}}
crankshafts:
  - {{name: left, x: -50 mm}}
  - {{name: right, x: {x}, y: {y}, rotation: {rotation}, phase: {phase} deg}}
cylinders:
  - {{crankshaft: left, throw: 0 deg, bank: 0 deg, z: 0 mm}}
  - {{crankshaft: right, throw: {throw} deg, bank: {bank} deg, z: 10 mm}}
bearings:
  mains: {{left: [-40 mm, 40 mm], right: [-30 mm, 50 mm]}}
"""

SINGLE = """\
name: one cylinder
speed: 7500 rpm
geometry: {{bore: 90 mm, stroke: 68 mm, conrod_length: 125 mm}}
masses: {{reciprocating: 0.51 kg, rotating: 0.27 kg}}
cylinders:
  - {{throw: {throw} deg, bank: {bank} deg, z: {z} mm}}
bearings:
  mains: [{mains}]
"""


def _write(tmp_path: Path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def _twin(tmp_path: Path, rotation: str, *, phase=0.0, throw=0.0, bank=0.0, x="50 mm", y="0 mm"):
    text = TWIN.format(rotation=rotation, phase=phase, throw=throw, bank=bank, x=x, y=y)
    return compute_result(_write(tmp_path, "twin.yaml", text), bearings=True).part("bearings")


def _single(tmp_path: Path, throw: float, bank: float, z: float, mains: str):
    text = SINGLE.format(throw=throw, bank=bank, z=z, mains=mains)
    return compute_result(_write(tmp_path, "single.yaml", text), bearings=True).part("bearings")


def _close(actual, expected, rel=1e-12):
    actual, expected = np.asarray(actual), np.asarray(expected)
    scale = float(np.max(np.abs(expected)))
    assert np.max(np.abs(actual - expected)) <= rel * scale


def _shaft(b, k):
    """Shaft ``k``'s pin and main curves and statistics (0-based shaft)."""
    pins, mains = b.pin_axis == k, b.main_axis == k
    return {
        "pin": b.pin_load[pins],
        "main": b.main_load[mains],
        "moment": b.internal_moment[mains],
        "pin_max": b.pin_max[pins],
        "pin_mean": b.pin_mean[pins],
        "main_max": b.main_max[mains],
        "main_mean": b.main_mean[mains],
        "moment_max": b.moment_max[mains],
        "main_z": b.main_z[mains],
    }


def _same(shaft, alone, turn=None):
    """Equal statistics; curves equal, or ``turn(curve)`` of the one cylinder's."""
    one = alone.loads
    for key, ref in (
        ("pin_max", one.pin_max),
        ("pin_mean", one.pin_mean),
        ("main_max", one.main_max),
        ("main_mean", one.main_mean),
        ("moment_max", one.moment_max),
    ):
        _close(shaft[key], ref)
    turn = turn or (lambda c: c)
    _close(shaft["pin"], turn(one.pin_load))
    _close(shaft["main"], turn(one.main_load))
    _close(shaft["moment"], turn(one.internal_moment))


@pytest.mark.parametrize("phase", [0.0, 40.0])
def test_co_rotating_shafts_loads_are_each_cylinders_alone(tmp_path, phase):
    b = _twin(tmp_path, "same", phase=phase, throw=25.0, bank=15.0).loads
    assert b.axis_names == ("left", "right")
    _same(_shaft(b, 0), _single(tmp_path, 0.0, 0.0, 0.0, "-40 mm, 40 mm"))
    # co-rotating with phase: the cylinder turned by the phase, the same forces
    alone = _single(tmp_path, 25.0 + phase, 15.0, 10.0, "-30 mm, 50 mm")
    _same(_shaft(b, 1), alone)
    np.testing.assert_array_equal(_shaft(b, 1)["main_z"], [-0.03, 0.05])


@pytest.mark.parametrize(("phase", "bank"), [(0.0, 0.0), (40.0, 20.0)])
def test_counter_rotating_shafts_loads_are_the_mirror_of_the_cylinder_alone(tmp_path, phase, bank):
    """The counter-rotating cylinder is the mirror image, across its bore line, of the
    forward cylinder with throw ``throw - phase + 2 bank``: equal magnitudes, every force
    reflected across the bore line (F -> e^{2i bank} conj(F) in y + ix)."""
    throw = 25.0
    b = _twin(tmp_path, "opposite", phase=phase, throw=throw, bank=bank).loads
    alone = _single(tmp_path, throw - phase + 2.0 * bank, bank, 10.0, "-30 mm, 50 mm")
    b_rad = math.radians(bank)
    _same(_shaft(b, 1), alone, lambda c: np.exp(2j * b_rad) * np.conj(c))
    _same(_shaft(b, 0), _single(tmp_path, 0.0, 0.0, 0.0, "-40 mm, 40 mm"))


def test_the_built_in_twin_cranks_are_mirror_images(tmp_path):
    """twin-crank-2: the right crank's loads are the left one's reflected across y,
    with the proposal's counterweights too (each crank its own, mirrored)."""
    b = compute_result("twin-crank-2", bearings=True).part("bearings").loads
    left, right = b.main_axis == 0, b.main_axis == 1
    _close(b.main_load_with_proposal[right], np.conj(b.main_load_with_proposal[left]))
    _close(b.pin_load[b.pin_axis == 1], np.conj(b.pin_load[b.pin_axis == 0]))
    # the counterweights lower the largest main load (each takes 100 % of one piston)
    assert np.all(b.main_max_with_proposal < 0.6 * b.main_max)


def test_a_moved_shaft_has_the_same_loads(tmp_path):
    """Loads are relative to the shaft's own axis."""
    here = _twin(tmp_path, "opposite", phase=30.0, throw=10.0, bank=5.0).loads
    there = _twin(
        tmp_path, "opposite", phase=30.0, throw=10.0, bank=5.0, x="310 mm", y="-170 mm"
    ).loads
    for name in ("pin_load", "main_load", "internal_moment", "main_max", "pin_max"):
        np.testing.assert_array_equal(getattr(there, name), getattr(here, name))


# --------------------------------------------------------------------- brute force


def _unit(angle):
    """Engine-frame unit vector at an angle from +y towards +x, as (x, y)."""
    return np.stack([np.sin(angle), np.cos(angle)])


def _second_derivative(values, omega):
    n = values.shape[-1]
    k = np.fft.fftfreq(n, 1.0 / n)
    k[n // 2] = 0.0
    return np.real(np.fft.ifft(-((k * omega) ** 2) * np.fft.fft(values, axis=-1), axis=-1))


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def test_counter_rotating_shaft_loads_match_the_brute_force_bodies():
    """One counter-rotating shaft with two cylinders (offsets, banks, rod inertia) and the
    proposal's counterweights: each big end's force from the piston's and the rod's
    accelerations at 360 sampled angles, the mains by lever shares."""
    base = cylinders([0.0, 90.0, 200.0], [0.0, 20.0, -35.0], [0.0, 0.0, 0.06])
    base = replace_arrays(
        base,
        offset=np.array([0.0, 0.004, -0.003]),
        conrod_inertia_correction=np.array([0.0, 2e-4, -1e-4]),
        rotating_mass=np.array([0.4, 0.3, 0.5]),
    )
    engine = with_crankshafts(
        base, [0, 1, 1], x=[0.0, 0.12], y=[0.0, 0.03], rotation=[1.0, -1.0], phase_deg=[0, 37]
    )
    mains = (-0.04, 0.03, 0.1)
    engine = engine.with_section("bearings", {"shaft2": mains})
    result = compute_result(engine, bearings=True)
    b = result.part("bearings").loads
    proposal = result.part("proposal").proposal
    theta = b.theta
    assert theta.size == 360
    omega = engine.speed
    shafts = engine.crankshafts
    s, sigma = 1, -1.0
    axis = np.array([shafts.x[s], shafts.y[s]])[:, None]
    pins = []
    for i in (1, 2):
        r, length, e = engine.crank_radius[i], engine.conrod_length[i], engine.offset[i]
        alpha = shafts.phase[s] + sigma * (theta + engine.throw[i])
        c = r * _unit(alpha)
        u = _unit(engine.bank[i])
        w = _unit(engine.bank[i] + sigma * math.pi / 2)
        s_along = u @ c + np.sqrt(length**2 - (e - w @ c) ** 2)
        p = e * w[:, None] + s_along[None, :] * u[:, None]
        a_p = _second_derivative(axis + p, omega)
        a_c = _second_derivative(axis + c, omega)
        d = p - c
        phi = np.unwrap(np.arctan2(d[1], d[0]))  # rod angle, counter-clockwise in (x, y)
        phi_dd = _second_derivative(phi, omega)
        # piston: m a_P = F_RP + N n; along the bore F_RP.u = m a_P.u;
        # massless rod of inertia dI about C: dI phi'' = d x (-F_RP)
        m = engine.reciprocating_mass[i]
        f_u = m * (u @ a_p)
        n = np.array([u[1], -u[0]])
        f_n = (-engine.conrod_inertia_correction[i] * phi_dd - _cross(d, u[:, None]) * f_u) / (
            _cross(d, n[:, None])
        )
        f_rp = u[:, None] * f_u + n[:, None] * f_n
        force = -f_rp - engine.rotating_mass[i] * a_c
        pins.append(force[1] + 1j * force[0])
    on_shaft = b.pin_axis == 1
    _close(b.pin_load[on_shaft], np.array(pins), rel=1e-9)
    # mains: the lever rule on the two pins and the shaft's counterweights
    loads = [(engine.z[1], pins[0]), (engine.z[2], pins[1])]
    weights = [cw for cw in proposal.counterweights if cw.axis == "shaft2"]
    assert weights
    for cw in weights:  # turning backward with the shaft
        loads.append((cw.z, omega**2 * cw.unbalance * np.exp(-1j * theta)))
    expected = np.zeros((len(mains), theta.size), dtype=complex)
    for z, f in loads:
        j = min(max(np.searchsorted(mains, z, side="right") - 1, 0), len(mains) - 2)
        za, zb = mains[j], mains[j + 1]
        expected[j] += (zb - z) / (zb - za) * f
        expected[j + 1] += (z - za) / (zb - za) * f
    np.testing.assert_array_equal(b.main_z[b.main_axis == 1], mains)
    _close(b.main_load_with_proposal[b.main_axis == 1], expected, rel=1e-9)


def replace_arrays(engine, **arrays):
    from dataclasses import replace

    return replace(engine, **arrays)


# ------------------------------------------------------------------ reading and CLI


def test_cli_json_names_each_entrys_crankshaft_and_the_gear_note(tmp_path):
    text = TWIN.format(rotation="opposite", phase=0, throw=0, bank=0, x="50 mm", y="0 mm")
    out = runner.invoke(app, ["analyse", _write(tmp_path, "t.yaml", text), "--format", "json"])
    assert out.exit_code == 0, out.output
    block = json.loads(out.stdout)["bearings"]
    assert [p["crankshaft"] for p in block["crank_pins"]] == ["left", "right"]
    assert [m["crankshaft"] for m in block["mains"]] == ["left", "left", "right", "right"]
    assert [m["z_m"] for m in block["mains"]] == [-0.04, 0.04, -0.03, 0.05]
    assert [m["crankshaft"] for m in block["internal_moment"]] == [
        "left",
        "left",
        "right",
        "right",
    ]
    assert "gear mesh forces are not in the main-bearing loads" in block["note"]
    table = runner.invoke(app, ["analyse", _write(tmp_path, "t.yaml", text), "--bearings"])
    assert "gear mesh forces are not in the main-bearing loads" in " ".join(table.stdout.split())


def test_a_list_is_crankshaft_ones_and_the_others_get_their_default_mains(tmp_path):
    text = TWIN.format(rotation="opposite", phase=0, throw=0, bank=0, x="50 mm", y="0 mm")
    text = text.replace("{left: [-40 mm, 40 mm], right: [-30 mm, 50 mm]}", "[-40 mm, 40 mm]")
    b = compute_result(_write(tmp_path, "t.yaml", text), bearings=True).part("bearings").loads
    np.testing.assert_array_equal(b.main_z[b.main_axis == 0], [-0.04, 0.04])
    # one throw, no pitch: one stroke either side of its plane (as one crankshaft)
    np.testing.assert_allclose(b.main_z[b.main_axis == 1], [0.01 - 0.068, 0.01 + 0.068])


def test_an_unknown_crankshaft_name_in_mains_is_refused_in_one_line(tmp_path):
    text = TWIN.format(rotation="opposite", phase=0, throw=0, bank=0, x="50 mm", y="0 mm")
    path = _write(tmp_path, "t.yaml", text.replace("right: [-30", "rihgt: [-30"))
    out = runner.invoke(app, ["analyse", path])
    assert out.exit_code == 2
    message = out.output.strip()
    assert "\n" not in message
    assert f"{path}:12:" in message
    assert "bearings.mains.rihgt" in message
    assert "did you mean 'right'?" in message


def test_a_mapping_without_crankshafts_is_refused(tmp_path):
    text = SINGLE.format(throw=0, bank=0, z=0, mains="-40 mm, 40 mm").replace(
        "mains: [-40 mm, 40 mm]", "mains: {left: [-40 mm, 40 mm]}"
    )
    out = runner.invoke(app, ["analyse", _write(tmp_path, "s.yaml", text)])
    assert out.exit_code == 2
    assert "bearings.mains" in out.output and "give the mains as a list" in out.output


def test_a_main_in_a_pin_plane_names_the_engines_cylinder(tmp_path):
    text = TWIN.format(rotation="opposite", phase=0, throw=0, bank=0, x="50 mm", y="0 mm")
    path = _write(
        tmp_path, "t.yaml", text.replace("right: [-30 mm, 50 mm]", "right: [10 mm, 50 mm]")
    )
    out = runner.invoke(app, ["analyse", path])
    assert out.exit_code == 2
    assert "bearings.mains.right[1]" in out.output
    assert "crank pin of cylinder 2" in out.output
