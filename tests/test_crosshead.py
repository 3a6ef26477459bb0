"""Crosshead engines: the slider's mass parts, the guide forces and MAN B&W's guide-force
moments (docs/crossheads.md), checked against sums over one cylinder, the roll, and a
brute-force Newton–Euler solution of the rod by finite differences."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import balance
from balance.cli import app
from balance.core.analysis import compute
from balance.io.layout_file import layout_from_text
from balance.io.request import build_request

runner = CliRunner()

#: A six-cylinder crosshead two-stroke firing 1-5-3-4-2-6 (even 60°): cylinder i is at TDC at
#: theta = -throw_i, so throws 0, 120, 240, 180, 300, 60 (about an S60MC-C's size).
SIX = """\
name: crosshead six
speed: 105 rpm
cycle: two-stroke
geometry: {{stroke: 2400 mm, conrod_length: 2460 mm, bore: 600 mm, offset: {offset}}}
masses:
  piston_group: 2200 kg
  piston_rod: 1500 kg
  crosshead: 2600 kg
  conrod: 3600 kg
  conrod_cg_to_big_end: 900 mm
  {inertia}
crank: {{throws: [0, 120, 240, 180, 300, 60], spacing: 1020 mm}}
firing_order: [1, 5, 3, 4, 2, 6]
{gas}
"""

ONE = SIX.replace("[0, 120, 240, 180, 300, 60]", "[0]").replace(
    "firing_order: [1, 5, 3, 4, 2, 6]", ""
)

GAS = "gas: {model: {compression_ratio: 18, peak_pressure: 150 bar}, bore: 600 mm}"


def _six(offset: str = "0 mm", inertia: str = "", gas: str = "", text: str = SIX):
    return layout_from_text(text.format(offset=offset, inertia=inertia, gas=gas))


def _result(engine, orders: str = "1-18"):
    return compute(engine, build_request(engine, orders))


def _guide(engine, orders: str = "1-18"):
    return _result(engine, orders).part("guide_forces")


def test_the_slider_is_piston_group_rod_and_crosshead():
    engine = _six()
    a, length = 0.9, 2.46
    assert engine.reciprocating_mass == pytest.approx(2200 + 1500 + 2600 + 3600 * a / length)
    assert np.asarray(engine.section("crossheads")).tolist() == [True] * 6


def test_h_type_of_an_even_six_is_only_orders_6_12_18_and_six_times_one_cylinder_s():
    six, one = _guide(_six()), _guide(_six(text=ONE))
    k = six.orders
    single = np.abs(one.h_type)
    for i, order in enumerate(k):
        if order % 6 == 0:
            # to rounding of the largest term (order 18 is 1e-7 of order 6)
            assert abs(six.h_type[i]) == pytest.approx(
                6 * single[i], rel=1e-12, abs=1e-12 * 6 * single.max()
            )
        else:  # zero to rounding, relative to one cylinder's order
            assert abs(six.h_type[i]) <= 1e-12 * max(single[i], single[5])
    assert abs(six.h_type[5]) > 0


def test_h_type_is_the_roll_without_offset_and_gas():
    engine = _six(inertia="conrod_inertia: 2900 kg m^2")
    result = _result(engine)
    guide = result.part("guide_forces")
    scale = np.max(np.abs(result.roll))
    assert np.allclose(guide.h_type, result.roll, rtol=0, atol=1e-12 * scale)


def test_h_type_is_the_roll_with_gas_without_offset():
    """Gas on the head acts along the bore through the crank axis: no moment, so the roll
    is still the guide forces' couples."""
    engine = _six(gas=GAS)
    result = _result(engine)
    guide = result.part("guide_forces")
    assert guide.with_gas
    scale = np.max(np.abs(result.roll))
    assert np.allclose(guide.h_type, result.roll, rtol=0, atol=1e-9 * scale)


def test_second_order_free_moment_is_root_12_pitch_times_one_cylinder_s_force():
    six, one = _result(_six()), _result(_six(text=ONE))
    force = one.phasors.peak("force")[1]
    moment = six.phasors.peak("moment")[1]
    assert moment == pytest.approx(math.sqrt(12) * 1.02 * force, rel=1e-12)


def test_x_type_is_the_direct_sum_over_cylinders():
    engine = _six(inertia="conrod_inertia: 2900 kg m^2")
    six, one = _guide(engine), _guide(_six(inertia="conrod_inertia: 2900 kg m^2", text=ONE))
    throws = np.radians([0, 120, 240, 180, 300, 60])
    lever = (np.arange(6) * 1.02 - 2.55) / 2.46
    k = six.orders[:, None]
    direct = np.sum(one.h_type[:, None] * np.exp(1j * k * throws) * lever, axis=1)
    scale = np.max(np.abs(one.h_type)) * np.sum(np.abs(lever))
    assert np.allclose(six.x_type, direct, rtol=0, atol=1e-12 * scale)
    assert abs(six.x_type[1]) > 0.1 * scale  # the second order: a real X-type moment


def _newton_euler_couple(beta, r, length, e, a, m_slider, m_rod, inertia, omega):
    r"""H = s N of one cylinder at crank angles ``beta`` [rad] by the rod's Newton–Euler
    equations, accelerations by central differences of the positions (no two-mass model).

    Cylinder frame X (where the pin goes after TDC), Y along the bore; angles and cross
    products counter-clockwise in (X, Y).  Slider: m_s a_P = -F + W (W the wall's force along
    X); rod: m_c a_G = F_C + F, I_G alpha = (C - G) x F_C + (P - G) x F, so
    (P - C) x F = I_G alpha - (C - G) x m_c a_G with F = (W, -m_s a_P,y).
    """
    h = 1e-3

    def positions(b):
        crank = np.stack([r * np.sin(b), r * np.cos(b)])
        slider = np.stack(
            [np.full_like(b, e), r * np.cos(b) + np.sqrt(length**2 - (r * np.sin(b) - e) ** 2)]
        )
        cg = crank + a / length * (slider - crank)
        d = slider - crank
        return crank, slider, cg, np.arctan2(d[1], d[0])

    def second(f):  # d2/dbeta2 by the five-point stencil, times omega^2
        values = [f(beta + j * h) for j in (-2, -1, 0, 1, 2)]
        return (
            omega**2
            * (-values[0] + 16 * values[1] - 30 * values[2] + 16 * values[3] - values[4])
            / (12 * h**2)
        )

    crank, slider, cg, _ = positions(beta)
    a_slider = second(lambda b: positions(b)[1])
    a_cg = second(lambda b: positions(b)[2])
    alpha = second(lambda b: np.unwrap(positions(b)[3]))
    d = slider - crank
    f_y = -m_slider * a_slider[1]
    arm = crank - cg
    rhs = inertia * alpha - (arm[0] * m_rod * a_cg[1] - arm[1] * m_rod * a_cg[0])
    wall = (d[0] * f_y - rhs) / d[1]
    return slider[1] * -wall  # the guide takes -W along X, at s from the crank axis


@pytest.mark.parametrize("offset", ["0 mm", "60 mm"])
def test_h_and_x_type_against_a_brute_force_newton_euler_solution(offset):
    engine = _six(offset=offset, inertia="conrod_inertia: 2900 kg m^2")
    guide = _guide(engine)
    samples = 720
    theta = 2 * np.pi * np.arange(samples) / samples
    omega = 105 * 2 * np.pi / 60
    couples = np.array(
        [
            _newton_euler_couple(
                theta + phi,
                1.2,
                2.46,
                float(offset.split()[0]) / 1e3,
                0.9,
                6300.0,
                3600.0,
                2900.0,
                omega,
            )
            for phi in np.radians([0, 120, 240, 180, 300, 60])
        ]
    )
    lever = (np.arange(6) * 1.02 - 2.55) / 2.46
    ks = np.arange(1, 19)
    h = 2 * np.fft.fft(couples.sum(axis=0))[ks] / samples
    x = 2 * np.fft.fft((couples * lever[:, None]).sum(axis=0))[ks] / samples
    scale = np.max(np.abs(couples))
    assert np.allclose(guide.h_type, h, rtol=0, atol=1e-7 * scale)
    assert np.allclose(guide.x_type, x, rtol=0, atol=1e-7 * scale)
    assert np.max(np.abs(guide.x_type)) > 0.1 * scale  # not a comparison of zeros


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "xh.yaml"
    path.write_text(text)
    return path


def test_json_table_csv_and_dataset_through_the_cli_and_the_api(tmp_path):
    path = _write(tmp_path, SIX.format(offset="0 mm", inertia="", gas=""))
    out = runner.invoke(app, ["analyse", str(path), "--format", "json", "--orders", "1-18"])
    assert out.exit_code == 0, out.stderr
    data = json.loads(out.stdout)
    moments = data["guide_force_moments"]
    assert [e["order"] for e in moments["H"]] == list(range(1, 19))
    assert set(moments["X"][0]) == {"order", "amplitude", "phase_deg"}
    assert moments["lever_m"] == [2.46] * 6
    h6 = moments["H"][5]["amplitude"]
    assert h6 == pytest.approx(max(abs(r["amplitude"]) for r in data["roll"]), rel=1e-12)
    for entry in data["cylinders"]:
        assert entry["guide_force_max_N"] > 0 and "stroke_m" in entry
    table = runner.invoke(app, ["analyse", str(path), "--orders", "1-8"])
    assert "Guide-force moments" in table.stdout
    csv = runner.invoke(app, ["analyse", str(path), "--format", "csv"])
    assert "guide_force_moment_x_amplitude [N m]" in csv.stdout.splitlines()[0]
    ds = balance.analyse(str(path), orders="1-18")
    assert ds["guide_force_moment_h_amplitude"].attrs["units"] == "N m"
    assert float(ds["guide_force_moment_h_amplitude"].sel(guide_force_order=6)) == pytest.approx(h6)
    assert "long_name" in ds["guide_force_moment_x_phase"].attrs
    off = balance.analyse(str(path), guide_forces=False)
    assert "guide_force_moment_h_amplitude" not in off


def test_a_trunk_piston_engine_has_no_guide_forces():
    out = runner.invoke(app, ["analyse", "inline-6", "--format", "json"])
    data = json.loads(out.stdout)
    assert "guide_force_moments" not in data
    assert all("guide_force_max_N" not in c for c in data["cylinders"])


LUMPED = """\
name: lumped crosshead
speed: 105 rpm
cycle: two-stroke
{flag}
geometry: {{stroke: 2400 mm, conrod_length: 2460 mm, bore: 600 mm}}
masses: {{reciprocating: 7600 kg, rotating: 2300 kg{extra}}}
crank: {{throws: [0, 120, 240, 180, 300, 60], spacing: 1020 mm}}
"""


def test_lumped_masses_with_crossheads_true_turn_the_section_on(tmp_path):
    engine = layout_from_text(LUMPED.format(flag="crossheads: true", extra=""))
    assert np.asarray(engine.section("crossheads")).all()
    assert _guide(engine).h_type[5] != 0
    plain = layout_from_text(LUMPED.format(flag="", extra=""))
    assert plain.section("crossheads") is None


@pytest.mark.parametrize("part", ["crosshead", "piston_rod"])
def test_a_slider_part_with_lumped_masses_is_refused_in_one_line(tmp_path, part):
    path = _write(tmp_path, LUMPED.format(flag="", extra=f", {part}: 2600 kg"))
    out = runner.invoke(app, ["analyse", str(path)])
    assert out.exit_code == 2
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, lines
    assert f"{path}:6:" in lines[0] and f"masses.{part}" in lines[0]
    assert "crossheads: true" in lines[0]


def test_a_sweep_of_the_crosshead_mass_moves_the_reciprocating_mass_like_the_piston_s():
    from balance.studies.sweep import sweep

    engine = _six(text=ONE)
    by_crosshead = sweep(engine, ["crosshead=2600kg,3600kg"], orders=[2])
    by_piston = sweep(engine, ["piston_group=2200kg,3200kg"], orders=[2])
    first = by_crosshead["reciprocating_force_peak"].values.ravel()
    assert first[1] > first[0] > 0
    assert np.allclose(first, by_piston["reciprocating_force_peak"].values.ravel(), rtol=1e-12)


def test_layout_expand_keeps_crossheads_true(tmp_path):
    path = _write(tmp_path, LUMPED.format(flag="crossheads: true", extra=""))
    out = runner.invoke(app, ["layout", "expand", str(path)])
    assert out.exit_code == 0, out.stderr
    assert "crossheads: true" in out.stdout
    again = _write(tmp_path, out.stdout)
    assert np.asarray(layout_from_text(again.read_text()).section("crossheads")).all()


def test_only_the_cylinders_that_give_a_crosshead_have_guide_forces():
    text = SIX.format(offset="0 mm", inertia="", gas="").replace("  crosshead: 2600 kg\n", "")
    text = text.replace(
        "crank: {throws: [0, 120, 240, 180, 300, 60], spacing: 1020 mm}",
        "cylinders:\n"
        + "".join(
            f"  - {{throw: {t}, z: {i * 1020} mm{', crosshead: 2600 kg' if i == 0 else ''}}}\n"
            for i, t in enumerate([0, 120, 240, 180, 300, 60])
        ),
    )
    engine = layout_from_text(text)
    guide = _guide(engine)
    assert guide.crossheads.tolist() == [True] + [False] * 5
    assert np.all(guide.guide_force[1:] == 0) and np.all(np.isnan(guide.maximum[1:]))
    one = _guide(_six(text=ONE))  # cylinder 1 alone, its own slider mass
    assert guide.maximum[0] == pytest.approx(one.maximum[0], rel=1e-12)
    # renumbered, the crosshead cylinder keeps its crosshead and its guide force
    order = [3, 0, 5, 1, 4, 2]
    moved = _guide(engine.reordered(order))
    assert moved.crossheads.tolist() == guide.crossheads[order].tolist()
    assert moved.maximum[1] == guide.maximum[0]
    assert np.all(np.isnan(np.delete(moved.maximum, 1)))


def test_a_four_stroke_with_gas_has_half_orders_and_its_h_type_is_the_roll():
    text = SIX.replace("cycle: two-stroke", "cycle: four-stroke")
    engine = _six(gas=GAS, text=text)
    result = _result(engine, "1-6")
    guide = result.part("guide_forces")
    assert guide.orders.tolist() == [k / 2 for k in range(1, 13)]
    assert guide.orders.tolist() == result.roll_orders.tolist()
    scale = np.max(np.abs(result.roll))
    assert np.allclose(guide.h_type, result.roll, rtol=0, atol=1e-9 * scale)
    assert abs(guide.h_type[0]) > 1e-3 * scale  # a half order is there
