"""The engine on its mounts through the analysis: loads from a Result, speed sweeps, views.

Through the command line: the ``mounts`` JSON block of CONTRACT §7, the tables, ``--mounts
FILE``, the errors, the ``balance mounts`` sweep and its crossings, the ``compare`` column,
the Dataset variables, the figure and the report section.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from balance.cli import app
from balance.core import mounts as mt
from balance.core.analysis import compute
from balance.core.mount_loads import mounts_of, order_loads
from balance.core.result import Request
from balance.io.layout_file import builtin_layout_path, load_layout
from balance.io.mounts_section import mounts_from_text
from balance.io.request import build_request

runner = CliRunner()

MOUNTS = """\
mass: 150 kg
cg: [-40 mm, 60 mm, 230 mm]
inertia: {xx: 6.0 kg m^2, yy: 5.1 kg m^2, zz: 4.4 kg m^2, xz: 0.3 kg m^2}
points:
  - {position: [0 mm, 250 mm, -80 mm], stiffness: [120 N/mm, 250 N/mm, 150 N/mm],
     damping: [250 N s/m, 400 N s/m, 250 N s/m]}
  - {position: [-40 mm, 200 mm, 560 mm], stiffness: [120 N/mm, 250 N/mm, 150 N/mm]}
  - {position: [250 mm, -150 mm, 250 mm], stiffness: [300 N/mm, 40 N/mm, 40 N/mm]}
  - {position: [-300 mm, -150 mm, 250 mm], stiffness: [300 N/mm, 40 N/mm, 40 N/mm]}
"""


def run(*args: str):
    return runner.invoke(app, list(args))


@pytest.fixture(scope="module")
def mounts_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("mounts") / "mounts.yaml"
    path.write_text(MOUNTS)
    return path


# ---------------------------------------------------------------------------------------
# loads and response from a Result


def test_loads_are_the_free_phasors_with_the_rotating_ones_at_order_1():
    engine = load_layout("single-mounts")
    result = compute(engine, build_request(engine, mounts=True))
    orders, ff, fb, mf, mb, roll = order_loads(result)
    p = result.phasors
    assert np.array_equal(orders, np.arange(1.0, 9.0))
    assert ff[0] == p.force_forward[0] + p.rotating_force
    assert np.array_equal(ff[1:], p.force_forward[1:])
    assert np.array_equal(fb, p.force_backward)
    assert mf[0] == p.moment_forward[0] + p.rotating_moment
    assert np.array_equal(roll, result.roll)
    m = result.part("mounts").response
    assert m is not None and not m.with_proposal and not m.gas
    load = mt.crank_loads(engine.reference_z, engine.section("mounts").cg, ff, fb, mf, mb, roll)
    assert np.allclose(m.loads, load, rtol=0, atol=1e-12 * np.abs(load).max())


def test_with_proposal_uses_the_residual():
    engine = load_layout("inline-4-mounts")
    result = compute(engine, build_request(engine, mounts=True, with_proposal=True))
    b = result.part("proposal").residual
    _, ff, fb, _, _, roll = order_loads(result, with_proposal=True)
    assert np.array_equal(ff, b.force_forward) and np.array_equal(fb, b.force_backward)
    assert np.array_equal(roll, result.part("proposal").residual_roll)
    bare = compute(engine, build_request(engine, mounts=True)).part("mounts").response
    # the second-order shafts take out the free force: the mounts see only the roll
    assert result.part("mounts").response.largest_force[1] < 0.8 * bare.largest_force[1]


def test_peak_force_is_the_largest_magnitude_over_a_cycle():
    rng = np.random.default_rng(3)
    f = rng.normal(size=(5, 3)) + 1j * rng.normal(size=(5, 3))
    t = np.linspace(0, 2 * np.pi, 20001)
    brute = np.linalg.norm(np.real(f[:, :, None] * np.exp(1j * t)), axis=1).max(axis=-1)
    assert np.allclose(mt.peak_force(f), brute, rtol=1e-6)


@pytest.mark.parametrize("layout", ["inline-4-mounts", "inline-4-gas"])
@pytest.mark.parametrize("with_proposal", [False, True])
def test_speed_sweep_equals_an_analysis_at_each_speed(layout, with_proposal):
    """Inertia loads scale with speed squared; the gas torque (one pressure trace) does
    not: the sweep from one analysis equals analyses at the other speeds."""
    engine = load_layout(layout)
    engine = engine.with_section("mounts", mounts_from_text(MOUNTS))
    request = build_request(engine, mounts=True, with_proposal=with_proposal)
    base = compute(engine, request).part("mounts").response
    speeds = np.array([0.4, 1.3]) * engine.speed
    sweep = mt.speed_sweep(base, speeds)
    assert sweep.forces.shape == (2, base.orders.size, 4, 3)
    assert sweep.gas == (layout == "inline-4-gas")
    for s, w in enumerate(speeds):
        one = compute(engine, dataclasses.replace(request, speed=float(w))).part("mounts").response
        scale = np.abs(one.forces).max()
        assert np.allclose(sweep.forces[s], one.forces, rtol=0, atol=1e-9 * scale)


def test_gas_roll_has_half_orders():
    engine = load_layout("inline-4-gas").with_section("mounts", mounts_from_text(MOUNTS))
    result = compute(engine, build_request(engine, mounts=True))
    m = result.part("mounts").response
    assert 0.5 in m.orders and 1.5 in m.orders and m.gas
    # evenly fired inline-4: the gas torque's reaction is at orders 2, 4, ... only
    half = [i for i, k in enumerate(m.orders) if not float(k).is_integer()]
    assert np.all(m.largest_force[half] < 1e-9 * m.largest_force.max())
    bare = (
        compute(engine, build_request(engine, mounts=True, torque=False)).part("mounts").response
    )  # no gas roll
    second = list(m.orders).index(2.0)
    assert abs(m.response[second, 5] - bare.response[1, 5]) > 0.1 * abs(bare.response[1, 5])


def test_crossings_are_at_60_f_over_k():
    system = mounts_from_text(MOUNTS)
    modes = mt.normal_modes(
        mt.mass_matrix(system.mass, system.inertia), mt.stiffness_matrix(system)
    )
    low, high = 800 * math.pi / 30, 8000 * math.pi / 30
    found = mt.crossings(modes.frequency, [0.5, 1, 2], low, high)
    assert found
    for k, j, w in found:
        assert w == pytest.approx(2 * math.pi * modes.frequency[j] / k)
        assert low <= w <= high
    expected = [
        (k, j)
        for k in (0.5, 1, 2)
        for j in range(6)
        if low <= 2 * math.pi * modes.frequency[j] / k <= high
    ]
    assert sorted((k, j) for k, j, _ in found) == sorted(expected)


def test_mounts_need_moments_roll_and_mounts():
    from balance.core.errors import InputError

    engine = load_layout("inline-4")
    with pytest.raises(InputError, match="no mounts: section"):
        compute(engine, build_request(engine, mounts=True))
    engine = load_layout("inline-4-mounts")
    with pytest.raises(InputError, match="moments and the roll"):
        compute(engine, build_request(engine, mounts=True, roll=False, proposal=False))
    with pytest.raises(InputError, match="loaded with the proposal need a proposal"):
        compute(engine, build_request(engine, mounts=True, with_proposal=True, proposal=False))
    assert compute(engine, Request()).part("mounts") is None  # only when asked


# ---------------------------------------------------------------------------------------
# the command line


def test_analyse_json_has_the_contract_mounts_block():
    result = run("analyse", "inline-4-mounts", "--on-mounts", "--format", "json")
    assert result.exit_code == 0, result.stderr
    block = json.loads(result.stdout)["mounts"]
    modes = block["modes"]
    assert len(modes) == 6
    freqs = [m["frequency_Hz"] for m in modes]
    assert freqs == sorted(freqs) and freqs[0] > 0
    for m in modes:
        assert set(m["energy_share"]) == {"x", "y", "z", "rx", "ry", "rz"}
        assert sum(m["energy_share"].values()) == pytest.approx(1.0)
    assert [r["order"] for r in block["response"]] == list(range(1, 9))
    for r in block["response"]:
        assert len(r["cg_translation_m"]) == 3 and len(r["rotation_rad"]) == 3
        assert len(r["mount_forces_N"]) == 4
        assert all(len(f) == 3 for f in r["mount_forces_N"])
    # inline-4: the free second-order force is what shakes the mounts
    second = block["response"][1]["mount_forces_N"]
    assert max(max(f) for f in second) > 1.0
    assert len(block["torque_roll_axis"]) == 3
    assert len(block["mounts"]) == 4
    # the layout's mounts: section asks for them, as a bearings: section does its loads
    plain = json.loads(run("analyse", "inline-4-mounts", "--format", "json").stdout)
    assert plain["mounts"] == block


def test_analyse_table_shows_modes_response_and_tra():
    result = run("analyse", "single-mounts", "--on-mounts", "--orders", "1-4")
    assert result.exit_code == 0, result.stderr
    out = result.stdout
    for text in (
        "Rigid-body modes on the mounts",
        "rz [%]",
        "Response on the mounts per order",
        "largest mount force [N]",
        "Torque-roll axis",
        "distance to TRA [mm]",
    ):
        assert text in out, text


def test_mounts_file_equals_the_section(mounts_file):
    section = builtin_layout_path("inline-4-mounts").read_text()
    start = section.index("\nmounts:") + 1
    body = "\n".join(line[2:] for line in section[start:].splitlines()[1:])
    path = mounts_file.parent / "same.yaml"
    path.write_text(body)
    a = json.loads(run("analyse", "inline-4-mounts", "--on-mounts", "-f", "json").stdout)
    b = run("analyse", "inline-4-mounts", "--mounts", str(path), "-f", "json")
    assert b.exit_code == 0, b.stderr
    assert json.loads(b.stdout)["mounts"] == a["mounts"]
    c = run("analyse", "inline-4", "--mounts", str(mounts_file), "-f", "json")
    assert c.exit_code == 0, c.stderr
    assert len(json.loads(c.stdout)["mounts"]["response"][0]["mount_forces_N"]) == 4


def test_errors_are_one_line_and_name_the_flag(tmp_path, mounts_file):
    r = run("analyse", "inline-4", "--on-mounts")
    assert r.exit_code == 2 and "no mounts: section" in r.stderr and "--mounts FILE" in r.stderr
    r = run("analyse", "inline-4", "--with-proposal")
    assert r.exit_code == 2 and "--with-proposal" in r.stderr
    r = run("analyse", "inline-4", "--mounts", str(tmp_path / "none.yaml"))
    assert r.exit_code == 2 and "no such file" in r.stderr
    r = run("analyse", "inline-4", "--mounts", str(mounts_file), "--no-roll")
    assert r.exit_code == 2 and "roll" in r.stderr
    bad = tmp_path / "bad.yaml"
    bad.write_text(MOUNTS.replace("[300 N/mm, 40 N/mm, 40 N/mm]}", "[300 N/mm, 40 N/mm, 40]}", 1))
    r = run("analyse", "inline-4", "--mounts", str(bad))
    assert r.exit_code == 2 and "bad.yaml:8:" in r.stderr, r.stderr
    assert "give a unit, e.g. '40 N/mm'" in r.stderr
    layout = tmp_path / "layout.yaml"
    text = builtin_layout_path("inline-4-mounts").read_text()
    layout.write_text(text.replace("  mass: 150 kg", "  mas: 150 kg"))
    r = run("analyse", str(layout), "--on-mounts")
    line = text.splitlines().index("  mass: 150 kg") + 1
    assert r.exit_code == 2 and f"layout.yaml:{line}:" in r.stderr and "mounts.mas" in r.stderr


def test_sweep_command_lists_the_crossings(tmp_path):
    r = run("mounts", "single-mounts", "--speed", "800rpm:8000rpm:200", "--format", "json")
    assert r.exit_code == 0, r.stderr
    data = json.loads(r.stdout)
    assert len(data["speed_rpm"]) == 200 and data["orders"] == list(range(1, 9))
    assert len(data["largest_mount_force_N"]) == 8
    assert all(len(row) == 200 for row in data["largest_mount_force_N"])
    freqs = [m["frequency_Hz"] for m in data["modes"]]
    assert {c["order"] for c in data["crossings"]} == {1, 2}
    for c in data["crossings"]:
        assert c["speed_rpm"] == pytest.approx(60 * freqs[c["mode"] - 1] / c["order"])
        assert 800 <= c["speed_rpm"] <= 8000
    # the inline-4's first order is zero: it loads no mount, so it crosses no mode (its
    # second order, the lowest it has, is above every mode from 800 rpm on)
    r = run("mounts", "inline-4-mounts", "--speed", "800rpm:8000rpm:200", "--format", "json")
    data = json.loads(r.stdout)
    assert max(data["largest_mount_force_N"][0]) == 0.0 and data["crossings"] == []
    table = run("mounts", "inline-4-mounts", "--speed", "800rpm:8000rpm:200")
    assert "No order that loads the mounts crosses a mode" in table.stdout
    table = run("mounts", "single-mounts", "--orders", "1-2", "--with-proposal")
    assert table.exit_code == 0, table.stderr
    assert "Orders crossing modes" in table.stdout and "with the proposal" in table.stdout
    csv = run("mounts", "single-mounts", "--speed", "1000rpm:2000rpm:3", "-f", "csv")
    assert csv.stdout.splitlines()[0].startswith("speed_rpm,order_1_N")
    assert len(csv.stdout.splitlines()) == 4
    png = tmp_path / "sweep.png"
    r = run("mounts", "single-mounts", "--speed", "1000rpm:8000rpm:50", "-o", str(png))
    assert r.exit_code == 0, r.stderr and png.read_bytes()[:4] == b"\x89PNG"
    r = run("mounts", "inline-4", "--speed", "1000rpm:2000rpm:3")
    assert r.exit_code == 2 and "no mounts: section" in r.stderr
    r = run("mounts", "inline-4-mounts", "--speed", "1000rpm:2000rpm:x")
    assert r.exit_code == 2


def test_sweep_with_gas_says_so(mounts_file):
    r = run("mounts", "inline-4-gas", "--mounts", str(mounts_file), "--speed", "1000rpm:3000rpm:5")
    assert r.exit_code == 0, r.stderr
    assert "gas torque is the same pressure trace" in " ".join(r.stdout.split())
    data = json.loads(
        run("mounts", "inline-4-gas", "--mounts", str(mounts_file), "-f", "json").stdout
    )
    assert data["gas"] and 0.5 in data["orders"]


def test_compare_column_of_the_largest_mount_force():
    r = run("compare", "inline-4", "inline-4-mounts", "--absolute", "-f", "csv")
    assert r.exit_code == 0, r.stderr
    head, plain, mounted = [line.split(",") for line in r.stdout.splitlines()[:3]]
    at = head.index("mount F max [N]")
    assert plain[at] == "-"
    engine = load_layout("inline-4-mounts")
    expected = compute(engine, build_request(engine, (1, 2, 3, 4), mounts=True))
    largest = expected.part("mounts").response.largest_force.max()
    assert float(mounted[at]) == pytest.approx(float(largest), rel=1e-3)
    r = run("compare", "inline-4", "inline-2-180", "-f", "csv")
    assert "mount F" not in r.stdout


@pytest.mark.xdist_group("sections_report")  # one worker builds the session fixture once
def test_dataset_netcdf_figure_and_report(tmp_path, sections_report):
    """The Dataset, its netCDF file, the mounts figure, and the report's mounts section
    (conftest.sections_report: the report of the inline-4 on its mounts, which also has
    the bearing loads; the section is the same code for any layout with mounts)."""
    from balance.views.dataset import build_dataset

    ds = build_dataset(
        compute(
            load_layout("inline-4-mounts"),
            build_request(load_layout("inline-4-mounts"), mounts=True),
        )
    )
    for name in (
        "mount_mode_frequency",
        "mount_mode_energy_share",
        "mount_cg_translation",
        "mount_rotation",
        "mount_force",
        "torque_roll_axis",
        "mount_distance_to_torque_roll_axis",
    ):
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs, name
    assert ds["mount_force"].dims == ("mount_order", "mount", "axis")
    target = tmp_path / "a.nc"
    r = run("analyse", "inline-4-mounts", "--on-mounts", "-f", "netcdf", "-o", str(target))
    assert r.exit_code == 0, r.stderr
    with xr.open_dataset(target) as back:
        assert back["mount_mode_frequency"].attrs["units"] == "Hz"
    r = run("plot", "inline-4-mounts", "-k", "mounts", "-o", str(tmp_path))
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "inline-4-mounts-mounts.png").exists()
    r, text = sections_report
    assert r.exit_code == 0, r.stderr
    assert 'id="mounts"' in text and "torque-roll axis" in text


def test_mounts_of_result_matches_compute():
    engine = load_layout("single-mounts")
    with_mounts = compute(engine, build_request(engine, mounts=True))
    again = mounts_of(compute(engine, Request()))
    assert np.array_equal(with_mounts.part("mounts").response.forces, again.forces)


def test_mode_crossings_of_a_sweep_are_those_within_its_speeds():
    """MountsResult.mode_crossings: :func:`balance.core.mounts.crossings` over the result's
    own speeds (what the sweep's JSON and figure show, read from the result)."""
    engine = load_layout("inline-4-mounts")
    result = compute(engine, build_request(engine, (1, 2, 4), mounts=True, figures=True))
    sweep = result.part("mounts").sweep
    speeds = np.asarray(sweep.speed)
    expected = mt.crossings(
        sweep.modes.frequency, sweep.orders, float(speeds.min()), float(speeds.max())
    )
    assert sweep.mode_crossings() == expected and expected
    assert all(speeds.min() <= w <= speeds.max() for _, _, w in expected)
