"""The torsion section through the front doors: the built-in layouts with a ``torsion:``
section, ``balance torsion``, ``balance analyse --torsion``, the plots and the report, the
API and the Dataset, the layout file's round trip, and the refusals with their file, line
and field (docs/torsion.md, docs/cli.md)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import balance
from balance.cli import app
from balance.io.layout_file import expand_layout, load_layout

runner = CliRunner()

DIESEL = "inline-6-diesel-torsion"

#: The nine-mass table of the MWM six of Mendes, Meirelles and Zampieri, Proc. IMechE Part K
#: 222 (2008) 155, Fig. 4, as transcribed in the openTorsion ICE example: inertias [kg m^2]
#: from the pulley to the flywheel and the stiffnesses of the eight sections [N m/rad].
MENDES_INERTIA = [0.0170, 0.0090, 0.0467, 0.0327, 0.0467, 0.0467, 0.0327, 0.0487, 2.0750]
MENDES_STIFFNESS = [1.106e6, 1.631e6, 1.253e6, 1.253e6, 1.678e6, 1.253e6, 1.253e6, 1.976e6]


def run(*args: str):
    return runner.invoke(app, list(args))


def holzer_residual(inertia: list[float], stiffness: list[float], omega: float) -> float:
    """Holzer's method (Den Hartog, *Mechanical Vibrations*, 4th ed. 1956, §4.4): the torque
    left over at the end of a free-free chain swinging at ``omega`` with mass 1 at unit
    amplitude, divided by the sum of the inertia torques' sizes; zero at a natural
    frequency.  A marching scheme, independent of the eigensolver of the program."""
    angle, torque, size = 1.0, 0.0, 0.0
    for i, j in enumerate(inertia):
        torque += j * omega**2 * angle
        size += abs(j * omega**2 * angle)
        if i < len(stiffness):
            angle -= torque / stiffness[i]
    return torque / size


def test_the_diesel_frequencies_are_holzers():
    """Every natural frequency of ``balance torsion`` of the MWM six is a root of Holzer's
    residual of the published table, found by bisection to 1e-10, and none is missed: the
    residual (continuous in the frequency) changes sign once at each and nowhere else."""
    from scipy.optimize import brentq

    out = run("torsion", DIESEL, "-f", "json")
    assert out.exit_code == 0, out.output
    freqs = [m["frequency_Hz"] for m in json.loads(out.stdout)["modes"]]
    assert len(freqs) == 8
    assert freqs[0] == pytest.approx(216.58, abs=0.01)

    def residual(f: float) -> float:
        return holzer_residual(MENDES_INERTIA, MENDES_STIFFNESS, 2 * math.pi * f)

    grid = np.linspace(1.0, 1.2 * freqs[-1], 20_000)
    values = np.array([residual(f) for f in grid])
    brackets = np.flatnonzero(np.sign(values[1:]) != np.sign(values[:-1]))
    roots = [brentq(residual, grid[i], grid[i + 1], xtol=1e-12, rtol=1e-13) for i in brackets]
    np.testing.assert_allclose(roots, freqs, rtol=1e-10)


def test_torsion_command_json_follows_the_schema():
    out = run(
        "torsion", DIESEL, "-f", "json", "--speed", "1000rpm:3000rpm:41", "--orders", "3,4.5,6"
    )
    assert out.exit_code == 0, out.output
    doc = json.loads(out.stdout)
    assert doc["schema"] == "balance.torsion/1"
    assert doc["cycle"] == "four-stroke"
    assert doc["speed_rpm"][0] == pytest.approx(1000.0) and doc["speed_rpm"][-1] == pytest.approx(
        3000.0
    )
    assert len(doc["speed_rpm"]) == 41
    assert doc["orders"] == [3.0, 4.5, 6.0]
    assert [m["name"] for m in doc["masses"]][:3] == ["pulley", "gear train", "throw 1"]
    assert [m["cylinders"] for m in doc["masses"]][2:8] == [[c] for c in range(1, 7)]
    assert [s["between"] for s in doc["sections"]] == [[i, i + 1] for i in range(1, 9)]
    assert doc["dampers"] == []
    # the gas part is there (the layout has gas:), the inertia part at the layout's speed
    cyl = doc["excitation"]["cylinders"][0]
    assert doc["excitation"]["reference_speed_rpm"] == pytest.approx(2500.0)
    assert {"gas", "inertia", "tangential_pressure_bar"} <= set(cyl["orders"][0])
    # every resonance in the range, at exactly its speed 60 f / k
    freqs = {m["mode"]: m["frequency_Hz"] for m in doc["modes"]}
    for r in doc["resonances"]:
        assert r["speed_rpm"] == pytest.approx(60 * freqs[r["mode"]] / r["order"], rel=1e-9)
        assert 1000.0 <= r["speed_rpm"] <= 3000.0
    assert {(r["mode"], r["order"]) for r in doc["resonances"]} == {(1, 6.0), (1, 4.5)}
    sections = doc["response"]["sections"]
    assert len(sections) == 8 and sections[0]["stress_MPa"] is None
    assert len(sections[7]["torque_Nm"]["synthesis"]) == 41
    assert len(doc["response"]["free_end_deg"]["amplitude"]) == 3


def test_torsion_command_table_and_csv():
    table = run("torsion", DIESEL)
    assert table.exit_code == 0, table.output
    assert "Campbell" not in table.stdout
    assert "216.6" in table.stdout and "Resonances in the speed range" in table.stdout
    csv = run("torsion", DIESEL, "-f", "csv", "--speed", "600rpm,1200rpm,2166rpm")
    assert csv.exit_code == 0, csv.output
    rows = csv.stdout.strip().splitlines()
    assert len(rows) == 4  # header and one row per speed
    header = rows[0].split(",")
    assert header[0].startswith("speed") and len(header) == 1 + 1 + 8  # free end, 8 sections
    assert float(rows[3].split(",")[0]) == pytest.approx(2166.0)


def test_campbell_plot_file_and_force(tmp_path: Path):
    target = tmp_path / "campbell.svg"
    first = run("torsion", DIESEL, "-o", str(target), "-q")
    assert first.exit_code == 0, first.output
    assert target.read_text().lstrip().startswith("<?xml")
    again = run("torsion", DIESEL, "-o", str(target), "-q")
    assert again.exit_code == 2 and "--force" in again.output
    assert run("torsion", DIESEL, "-o", str(target), "--force", "-q").exit_code == 0


def test_analyse_gains_the_block_at_one_speed():
    out = run("analyse", DIESEL, "-f", "json", "--speed", "2166rpm")
    assert out.exit_code == 0, out.output
    doc = json.loads(out.stdout)
    block = doc["torsion"]
    assert "schema" not in block
    assert block["speed_rpm"] == [pytest.approx(2166.0)]
    assert block["resonances"] == []
    full = json.loads(run("torsion", DIESEL, "-f", "json", "--speed", "2166rpm").stdout)
    np.testing.assert_allclose(
        block["response"]["free_end_deg"]["synthesis"],
        full["response"]["free_end_deg"]["synthesis"],
        rtol=1e-12,
    )
    # asked with the flag of a layout that has the section: the same
    flagged = json.loads(run("analyse", DIESEL, "-f", "json", "--torsion").stdout)
    assert flagged["torsion"]["modes"] == block["modes"]


def test_refused_without_a_torsion_section():
    for args in (("analyse", "inline-4", "--torsion"), ("torsion", "inline-4")):
        out = run(*args)
        assert out.exit_code == 2
        line = out.output.strip()
        assert "\n" not in line and "Traceback" not in line
        assert "inline-4" in line and "torsion:" in line


@pytest.mark.parametrize(
    ("option", "value", "says"),
    [
        ("--speed", "0rpm:3000rpm:10", "speed"),
        ("--orders", "0.3", "0.5"),
        ("--orders", "0-2", "positive"),
        ("--orders", "1,1.25", "0.5"),
    ],
)
def test_bad_options_are_one_line(option: str, value: str, says: str):
    out = run("torsion", DIESEL, option, value)
    assert out.exit_code == 2, out.output
    message = out.output.strip()
    assert "\n" not in message and "Traceback" not in message
    assert option in message and says in message


TWO_STROKE = """\
name: Two-stroke twin with a torsion table
speed: 3000 rpm
cycle: two-stroke
geometry: {stroke: 60 mm, conrod_length: 120 mm}
masses: {reciprocating: 0.3 kg, rotating: 0.3 kg}
crank: {throws: [0, 180], spacing: 80 mm}
torsion:
  masses:
    - {name: throw 1, cylinders: [1], inertia: 0.002 kg m^2,
       shaft: {stiffness: 2.0e5 N m/rad}}
    - {name: throw 2, cylinders: [2], inertia: 0.002 kg m^2,
       shaft: {stiffness: 5.0e4 N m/rad}}
    - {name: flywheel, inertia: 0.05 kg m^2}
  loss_factor: 2 %
"""


def test_two_stroke_refuses_half_orders(tmp_path: Path):
    path = tmp_path / "two.yaml"
    path.write_text(TWO_STROKE)
    ok = run("torsion", str(path), "-f", "json", "--speed", "2000rpm")
    assert ok.exit_code == 0, ok.output
    assert json.loads(ok.stdout)["orders"] == [float(k) for k in range(1, 13)]
    half = run("torsion", str(path), "--orders", "1.5")
    assert half.exit_code == 2
    assert "--orders" in half.output and "two-stroke" in half.output


def test_a_bad_table_names_file_line_and_field(tmp_path: Path):
    src = expand_layout(DIESEL).replace("stiffness: 1631000 N m/rad", "stiffness: 0 N m/rad")
    path = tmp_path / "zero.yaml"
    path.write_text(src)
    out = run("torsion", str(path))
    assert out.exit_code == 2
    line = out.output.strip()
    row = next(i for i, t in enumerate(src.splitlines(), 1) if "stiffness: 0 N m/rad" in t)
    assert line.startswith(f"balance: {path}:{row}:")
    assert "torsion.masses[2].shaft.stiffness" in line and "positive stiffness" in line


@pytest.mark.parametrize("name", [DIESEL, "inline-4-cbr600rr-torsion"])
def test_expanded_layout_gives_the_same_torsion(tmp_path: Path, name: str):
    path = tmp_path / "expanded.yaml"
    path.write_text(expand_layout(name))
    here = json.loads(run("torsion", name, "-f", "json", "--speed", "3000rpm").stdout)
    there = json.loads(run("torsion", str(path), "-f", "json", "--speed", "3000rpm").stdout)
    for key in ("masses", "sections", "modes", "vector_sums"):
        assert here[key] == there[key], key
    # the response to rounding (the expanded file lists the cylinders one by one)
    for a, b in zip(here["response"]["sections"], there["response"]["sections"], strict=True):
        np.testing.assert_allclose(
            a["torque_Nm"]["amplitude"], b["torque_Nm"]["amplitude"], rtol=1e-12, atol=1e-12
        )


def test_the_motorcycle_crank_adds_the_moving_parts():
    """The CBR600RR throws are ``crank_inertia`` masses: the inertia used is the crank's own
    (P. Biedenkopf 2020) plus each cylinder's mean moving-parts inertia."""
    from balance.core.torsion_excitation import moving_parts_inertia

    engine = load_layout("inline-4-cbr600rr-torsion")
    doc = json.loads(run("torsion", "inline-4-cbr600rr-torsion", "-f", "json").stdout)
    crank = [1695.8e-6, 2159.5e-6, 1815.7e-6, 1260.2e-6]
    moving = moving_parts_inertia(engine)
    used = [m["inertia_kgm2"] for m in doc["masses"]]
    np.testing.assert_allclose(used[1:5], np.add(crank, moving), rtol=1e-12)
    assert used[0] == pytest.approx(19.9e-6) and used[5] == pytest.approx(15.4e-6)
    # the published stiffnesses in N m/deg, converted
    stiff = [s["stiffness_Nm_per_rad"] for s in doc["sections"]]
    np.testing.assert_allclose(stiff, np.degrees([3014, 2562, 2430, 2636, 2562]), rtol=1e-12)


def test_api_and_dataset():
    result = balance.compute_result(DIESEL, torsion={"speeds": "sweep"})
    t = result.part("torsion")
    assert t.speeds.size == 200
    one = balance.compute_result(DIESEL).part("torsion")
    assert one.speeds.size == 1 and one.speeds[0] == pytest.approx(2500 * math.pi / 30)
    data = balance.analyse(DIESEL, torsion={"speeds": "sweep"})
    names = [v for v in data.data_vars if str(v).startswith("torsion_")]
    assert "torsion_mode_frequency" in names and "torsion_section_torque_synthesis" in names
    for v in names:
        assert data[v].attrs.get("units") is not None, v
        assert data[v].attrs.get("long_name"), v
    np.testing.assert_allclose(data["torsion_mode_frequency"].values, t.frequencies)
    off = balance.compute_result(DIESEL, torsion=False)
    assert off.part("torsion") is None


def test_plot_and_report_include_torsion(tmp_path: Path):
    out = run(
        "plot",
        DIESEL,
        "-k",
        "torsion-campbell",
        "-k",
        "torsion_response",
        "-o",
        str(tmp_path),
        "-q",
    )
    assert out.exit_code == 0, out.output
    assert {p.name for p in tmp_path.iterdir()} == {
        f"{DIESEL}-torsion_campbell.png",
        f"{DIESEL}-torsion_response.png",
    }
    report = tmp_path / "r.html"
    out = run("report", DIESEL, "-o", str(report), "-q")
    assert out.exit_code == 0, out.output
    html = report.read_text()
    assert "Torsional vibration of the crank train" in html
    assert html.count("<svg") >= 3


def test_undamped_table_warns_and_has_no_response(tmp_path: Path):
    src = "\n".join(
        line
        for line in expand_layout(DIESEL).splitlines()
        if "damping: 2 N m s/rad" not in line and "loss_factor" not in line
    )
    path = tmp_path / "undamped.yaml"
    path.write_text(src + "\n")
    out = run("torsion", str(path), "-f", "json", "--speed", "2000rpm")
    assert out.exit_code == 0, out.output
    doc = json.loads(out.stdout)
    assert doc["response"] is None
    assert [w["rule"] for w in doc["warnings"]] == ["torsion_damping"]
    assert "torsion_damping" in out.stderr or "damping" in out.stderr
    quiet = run("torsion", str(path), "-f", "json", "--speed", "2000rpm", "-q")
    assert quiet.stderr == ""
