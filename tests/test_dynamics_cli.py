"""The variable-speed rung through the front door, the layout file, the command line and the
writers: the speed model chosen, its refusals, the ladder's bound, and the constant-speed
estimate of the speed fluctuation (docs/dynamics.md)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

import balance
from balance.cli import app
from balance.core.crank_motion import crank_train
from balance.core.speed_model import Flywheel, constant_speed_bound
from balance.io.layout_file import expand_layout, load_layout
from tests.helpers import draw_only

runner = CliRunner()


def run(*args: str):
    return runner.invoke(app, list(args))


SINGLE = """\
name: Single with a flywheel
speed: 1200 rpm
geometry: {stroke: 86 mm, conrod_length: 143 mm}
masses: {reciprocating: 0.6 kg, rotating: 0.5 kg}
cylinders:
  - {throw: 0 deg, bank: 0 deg, z: 0 mm}
"""


def test_the_estimate_counts_the_layouts_own_inertia():
    """docs/torque.md: delta = A / ((J_f + <J_layout>) w^2).  With the layout's moving
    masses counted, the constant-speed estimate is the exact periodic fluctuation to 0.1 %
    (inline-4-gas: 1.0925 % against 1.0923 %); with the flywheel alone it was 6 % high.
    Sized for 1 % (v8-crossplane-gas), the flywheel gives 1 % exactly to 0.1 %."""
    engine = balance.load_layout("inline-4-gas")
    torque = balance.compute_result(engine).part("torque")
    w2 = engine.speed**2
    layout = float(np.mean(crank_train(engine, torque.crank_angle).inertia))
    assert torque.speed_fluctuation == pytest.approx(
        torque.excess_work / ((0.12 + layout) * w2), rel=1e-12
    )
    exact = balance.compute_result(engine, speed_model="dynamic").part("dynamics")
    assert exact.speed_fluctuation == pytest.approx(torque.speed_fluctuation, rel=1e-3)
    flywheel_alone = torque.excess_work / (0.12 * w2)
    assert flywheel_alone / exact.speed_fluctuation - 1.0 > 0.05
    v8 = balance.load_layout("v8-crossplane-gas")
    sized = balance.compute_result(v8).part("torque")
    assert sized.speed_fluctuation == 0.01
    wheel = Flywheel(inertia=sized.flywheel_inertia)
    check = balance.compute_result(v8, speed_model="dynamic", flywheel=wheel).part("dynamics")
    assert check.speed_fluctuation == pytest.approx(0.01, rel=1e-3)


def test_a_constant_speed_analysis_states_its_bound():
    engine = balance.load_layout("inline-4-gas")
    result = balance.compute_result(engine)
    bound = constant_speed_bound(engine, result.part("torque"))
    assert bound is not None
    accuracy = json.loads(run("analyse", "inline-4-gas", "-f", "json").stdout)["accuracy"]
    assert accuracy["speed_model"] == "constant"
    assert accuracy["speed_bound"] == pytest.approx(bound.ratio, rel=1e-15)
    assert 0.01 < bound.ratio < 0.05  # 3.8 %: no warning (it warns above 5 %)
    assert not any(w.rule == "constant_speed_bound" for w in result.warnings)
    plain = json.loads(run("analyse", "inline-4", "-f", "json").stdout)["accuracy"]
    assert "speed_model" not in plain  # no gas forces: no bound to state
    table = run("analyse", "inline-4-gas").stdout
    assert "Speed model constant" in table and "% of sum(m r w^2)" in table


def test_the_tolerance_picks_the_speed_model():
    """The ladder's second axis: the dynamic model where the constant rung's bound (3.8 %
    of sum(m r w^2) for inline-4-gas at 7000 rpm) exceeds the tolerance."""
    loose = json.loads(run("analyse", "inline-4-gas", "-f", "json", "--tolerance", "0.1").stdout)
    assert loose["accuracy"]["speed_model"] == "constant" and "dynamics" not in loose
    tight = json.loads(run("analyse", "inline-4-gas", "-f", "json", "--tolerance", "0.01").stdout)
    assert tight["accuracy"]["speed_model"] == "dynamic"
    assert tight["dynamics"]["speed_fluctuation"] == pytest.approx(0.010923, rel=1e-4)


def test_the_dynamic_model_from_the_command_line_and_the_api():
    out = run("analyse", "inline-4-gas", "-f", "json", "--speed-model", "dynamic")
    assert out.exit_code == 0, out.stderr
    block = json.loads(out.stdout)["dynamics"]
    assert block["load"] == {"kind": "mean", "torque_Nm": pytest.approx(210.4, rel=1e-3)}
    assert block["mean_speed_rpm"] == pytest.approx(7000.0, rel=1e-12)
    ds = balance.analyse("inline-4-gas", speed_model="dynamic", load="propeller")
    assert ds.attrs["dynamics_load_kind"] == "propeller"
    assert float(ds.dynamics_mean_speed) == pytest.approx(7000 * math.pi / 30, rel=1e-9)
    assert ds.dynamics_speed.attrs["units"] == "rad/s"
    propeller = run("analyse", "inline-4-gas", "--speed-model", "dynamic", "--load", "propeller")
    assert propeller.exit_code == 0 and "propeller, T = c w^2" in propeller.stdout


@pytest.mark.parametrize(
    ("args", "code", "words"),
    [
        (["--speed-model", "dynamic", "--model", "series"], 2, "samples the exact kinematics"),
        (["--speed-model", "dynamic", "--load", "150Nm"], 1, "the engine accelerates"),
        (["--speed-model", "dynamic", "--load", "300Nm"], 1, "the engine stalls"),
        (["--speed-model", "dynamic", "--load", "2 kg"], 2, "give mean, propeller"),
    ],
)
def test_refusals_are_one_line(args, code, words):
    out = run("analyse", "inline-4-gas", *args)
    assert out.exit_code == code, out.stderr
    assert words in out.stderr and len(out.stderr.strip().splitlines()) == 1


def test_no_flywheel_is_refused():
    out = run("analyse", "inline-4", "--speed-model", "dynamic")
    assert out.exit_code == 1
    assert "needs what turns with the crank beyond the layout's masses" in out.stderr


def test_a_flywheel_without_gas_coasts(tmp_path):
    """docs/dynamics.md: without gas the crank coasts, w = w0 sqrt(J(0)/J(theta)): the
    highest speed where J is least."""
    path = tmp_path / "coast.yaml"
    path.write_text(SINGLE + "flywheel: {inertia: 0.01 kg m^2}\n")
    engine = balance.load_layout(str(path))
    assert engine.section("flywheel") == Flywheel(inertia=0.01)
    part = balance.compute_result(engine, speed_model="dynamic").part("dynamics")
    j = part.inertia
    speed = part.motion.speed
    assert speed[np.argmin(j)] == pytest.approx(speed.max(), rel=1e-12)
    np.testing.assert_allclose(speed * np.sqrt(j), speed[0] * np.sqrt(j[0]), rtol=1e-12)
    refused = run("analyse", str(path), "--speed-model", "dynamic", "--load", "propeller")
    assert refused.exit_code == 1 and "no gas torque" in refused.stderr
    constant = run("analyse", str(path), "-f", "json")  # the constant model ignores it
    assert constant.exit_code == 0 and "speed_model" not in json.loads(constant.stdout)


def test_a_dynamics_section_asks_for_the_dynamic_model(tmp_path):
    path = tmp_path / "dyn.yaml"
    path.write_text(expand_layout("inline-4-gas") + "dynamics:\n  load: propeller\n")
    data = json.loads(run("analyse", str(path), "-f", "json").stdout)
    assert data["accuracy"]["speed_model"] == "dynamic"
    assert data["dynamics"]["load"]["kind"] == "propeller"
    constant = json.loads(
        run("analyse", str(path), "-f", "json", "--speed-model", "constant").stdout
    )
    assert constant["accuracy"]["speed_model"] == "constant" and "dynamics" not in constant
    again = tmp_path / "again.yaml"
    again.write_text(expand_layout(str(path)))
    assert "dynamics:\n  load: propeller" in again.read_text()
    assert load_layout(str(again)).section("dynamics").kind == "propeller"
    for study in (
        ("sweep", str(path), "--vary", "speed=1000rpm,2000rpm", "-o", str(tmp_path / "s.nc")),
        ("tolerance", str(path), "--scatter", "masses.reciprocating=±3g", "--samples", "10"),
    ):
        out = run(*study)
        assert out.exit_code == 2 and "variable-speed analysis" in out.stderr, study
    proposal = run("propose", str(path), "-f", "json")  # proposals at constant speed
    assert proposal.exit_code == 0 and "dynamics" not in json.loads(proposal.stdout)


@pytest.mark.parametrize(
    ("section", "words"),
    [
        ("dynamics:\n  load: fast\n", "dynamics.load"),
        ("dynamics:\n  load: {torque: 80 N m, at: 3000 rpm}\n", "exponent is missing"),
        ("dynamics:\n  load: {torque: 80}\n", "give a unit"),
        ("dynamics:\n  lode: mean\n", "did you mean 'load'"),
    ],
)
def test_bad_dynamics_sections(tmp_path, section, words):
    path = tmp_path / "bad.yaml"
    path.write_text(SINGLE + "flywheel: {inertia: 0.01 kg m^2}\n" + section)
    out = run("analyse", str(path))
    assert out.exit_code == 2 and words in out.stderr, out.stderr
    assert f"{path}:" in out.stderr


def test_figures_solve_the_motion_of_a_layout_with_gas_and_flywheel(tmp_path, monkeypatch):
    """docs/dynamics.md: `balance plot` of a layout with gas: and flywheel: draws the
    variable-speed figures (the motion solved for them, mean load), while `balance analyse`
    stays at constant speed. The variable-speed figures are rendered to PNG here; the
    command's other figures are built, and rendered by their own tests."""
    speed_kinds = ("crank_speed", "reduced_inertia", "speed_model_orders")
    rendered = draw_only(monkeypatch, speed_kinds)
    out = run("plot", "inline-4-gas", "-o", str(tmp_path / "gas"), "-q")
    assert out.exit_code == 0, out.output
    assert rendered == list(speed_kinds)
    names = {p.name for p in (tmp_path / "gas").iterdir()}
    assert {"inline-4-gas-crank_star.png", "inline-4-gas-torque.png"} <= names
    for kind in speed_kinds:
        assert f"inline-4-gas-{kind}.png" in names
        assert (tmp_path / "gas" / f"inline-4-gas-{kind}.png").read_bytes().startswith(b"\x89PNG")
    shown = balance.compute_result("inline-4-gas", dynamics={"figures": True}).part("dynamics")
    exact = balance.compute_result("inline-4-gas", speed_model="dynamic").part("dynamics")
    assert shown.speed_fluctuation == exact.speed_fluctuation
    doc = json.loads(run("analyse", "inline-4-gas", "-f", "json").stdout)
    assert doc["accuracy"]["speed_model"] == "constant"


def test_a_layout_without_gas_draws_no_variable_speed_figure(tmp_path, monkeypatch):
    draw_only(monkeypatch)  # which kinds are written: the image tests render them
    out = run("plot", "inline-4", "-o", str(tmp_path / "plain"), "-q")
    assert out.exit_code == 0, out.output
    drawn = [p.name for p in (tmp_path / "plain").iterdir()]
    assert "inline-4-crank_star.png" in drawn  # the figures were drawn
    assert not any("crank_speed" in name for name in drawn)


def test_the_report_of_a_layout_with_gas_and_flywheel_has_the_variable_speed(tmp_path):
    report = tmp_path / "r.html"
    assert run("report", "inline-4-gas", "-o", str(report), "-q").exit_code == 0
    assert "Variable crank speed" in report.read_text()
