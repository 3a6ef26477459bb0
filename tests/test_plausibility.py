"""Plausibility warnings (balance.core.plausibility): each rule, where they are reported
(stderr, the JSON ``warnings`` list, the table's footer), ``--quiet``, studies, and that a
warning never changes a number."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from balance.cli import app
from balance.core.plausibility import (
    MAX_MEAN_PISTON_SPEED,
    MAX_SPEED_RPM,
    RULES,
    PlausibilityWarning,
    check_engine,
    summarise,
)
from balance.io.layout_file import builtin_layout_names, layout_from_text, load_layout

runner = CliRunner()

# a plausible engine: 86 mm stroke, 143 mm rod, 0.61 kg at 86 mm bore (0.96 g/cm^3)
BASE = """\
name: Plausible four
speed: 6000 rpm
geometry: {stroke: 86 mm, conrod_length: 143 mm}
masses:
  piston_group: 0.42 kg
  conrod: 0.55 kg
  conrod_cg_to_big_end: 38 mm
  conrod_inertia: 1.9e-3 kg m^2
crank: {throws: [0, 180, 180, 0], spacing: 91 mm}
"""


def rules_of(text: str, **kwargs: float) -> list[str]:
    return [w.rule for w in check_engine(layout_from_text(text), **kwargs)]


def test_a_plausible_engine_has_no_warning():
    assert rules_of(BASE) == []
    assert rules_of(BASE.replace("geometry: {", "geometry: {bore: 86 mm, ")) == []


@pytest.mark.parametrize("name", builtin_layout_names())
def test_no_builtin_layout_warns(name):
    assert check_engine(load_layout(name)) == ()


@pytest.mark.parametrize(
    ("old", "new", "rule", "field"),
    [
        # 30 m/s at 86 mm is 10 465 rpm: 11 000 rpm is 31.5 m/s
        ("speed: 6000 rpm", "speed: 11000 rpm", "mean_piston_speed", "speed"),
        ("speed: 6000 rpm", "speed: 6000 rad/s", "speed", "speed"),  # 57 296 rpm
        ("stroke: 86 mm", "stroke: 4 mm", "stroke", "geometry.stroke"),
        ("conrod_length: 143 mm", "conrod_length: 80 mm", "rod_ratio", "geometry.conrod_length"),
        ("conrod_length: 143 mm", "conrod_length: 500 mm", "rod_ratio", "geometry.conrod_length"),
        ("conrod_inertia: 1.9e-3 kg m^2", "conrod_inertia: 19 kg m^2", "conrod_inertia",
         "masses.conrod_inertia"),
        ("geometry: {", "geometry: {bore: 86 cm, ", "reciprocating_mass", "masses.reciprocating"),
        ("geometry: {", "geometry: {bore: 8.6 mm, ", "reciprocating_mass",
         "masses.reciprocating"),
        ("crank:", "balance: {counterweight_radius: 100 mm}\ncrank:", "counterweight_radius",
         "balance.counterweight_radius"),
    ],
)  # fmt: skip
def test_each_rule_warns_with_the_field_read(old, new, rule, field):
    warnings = check_engine(layout_from_text(BASE.replace(old, new)))
    found = {w.rule: w for w in warnings}
    assert rule in found, warnings
    assert found[rule].field == field
    assert found[rule].excess > 1


def test_thresholds_are_where_the_docs_say():
    """Just inside and just outside each numeric threshold."""
    stroke = 0.086
    rpm_at_limit = MAX_MEAN_PISTON_SPEED * 60 / (2 * stroke)
    for rpm, expected in (
        (rpm_at_limit * 0.999, []),
        (rpm_at_limit * 1.001, ["mean_piston_speed"]),
    ):
        assert rules_of(BASE.replace("6000 rpm", f"{rpm!r} rpm")) == expected
    # a short stroke keeps the piston speed low: 20 mm at 25 000 rpm is 16.7 m/s
    short = BASE.replace(
        "stroke: 86 mm, conrod_length: 143 mm", "stroke: 20 mm, conrod_length: 50 mm"
    )
    short = short.replace("conrod_cg_to_big_end: 38 mm", "conrod_cg_to_big_end: 15 mm")
    short = short.replace("1.9e-3 kg m^2", "1e-4 kg m^2")
    assert rules_of(short.replace("6000 rpm", f"{MAX_SPEED_RPM} rpm")) == []
    assert rules_of(short.replace("6000 rpm", f"{MAX_SPEED_RPM + 1} rpm")) == ["speed"]
    # rod ratio 0.5 exactly: r = 43 mm, l = 86 mm; just beyond: 85.9 mm
    assert rules_of(BASE.replace("143 mm", "86 mm")) == []
    assert rules_of(BASE.replace("143 mm", "85.9 mm")) == ["rod_ratio"]
    # conrod inertia bound m l^2 = 0.55 kg x 0.143^2 m^2
    bound = 0.55 * 0.143**2
    text = BASE.replace("1.9e-3 kg m^2", f"{bound * 0.999!r} kg m^2")
    assert rules_of(text) == []
    assert rules_of(BASE.replace("1.9e-3 kg m^2", f"{bound * 1.001!r} kg m^2")) == [
        "conrod_inertia"
    ]
    # counterweight radius: the stroke itself is allowed, beyond it is not
    assert rules_of(BASE, counterweight_radius=0.086) == []
    assert rules_of(BASE, counterweight_radius=0.0861) == ["counterweight_radius"]


def test_the_message_says_what_was_read_and_why():
    text = BASE.replace("geometry: {", "geometry: {bore: 86 mm, ").replace(
        "  piston_group: 0.42 kg", "  piston_group: 420 kg"
    )
    (warning,) = check_engine(layout_from_text(text))
    assert warning.field == "masses.reciprocating"
    # 420 kg + the rod's small-end share 0.55 kg x 38/143 on an 86 mm bore
    mass = 420 + 0.55 * 38 / 143
    density = mass / 0.086**3 / 1e3
    assert f"reciprocating mass {mass:.4g} kg on a bore of 86 mm" in warning.message
    assert f"{density:.3g} g per cm^3 of bore cubed, outside 0.1 to 20 g/cm^3" in warning.message


def test_one_cylinder_out_of_line_is_named():
    text = (
        "name: one long\nspeed: 6000 rpm\n"
        "geometry: {stroke: 86 mm, conrod_length: 143 mm}\n"
        "masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}\n"
        "cylinders:\n  - {throw: 0, z: 0}\n  - {throw: 180, z: 91 mm, stroke: 3 mm}\n"
    )
    (warning,) = [w for w in check_engine(layout_from_text(text)) if w.rule == "stroke"]
    assert warning.field == "cylinders[2].stroke"
    assert warning.message.startswith("stroke 3 mm (cylinder 2) is outside 5 mm to 4 m")


def test_summarise_reports_each_rule_once_with_its_worst_case():
    a = PlausibilityWarning("speed", "speed", "speed 30000 rpm", 1.2)
    b = PlausibilityWarning("speed", "speed", "speed 50000 rpm", 2.0)
    c = PlausibilityWarning("stroke", "geometry.stroke", "stroke 3 mm", 1.7)
    out = summarise([(a,), (b, c), ()], "corners")
    assert [(w.rule, w.message) for w in out] == [
        ("speed", "speed 50000 rpm (at 2 of 3 corners)"),
        ("stroke", "stroke 3 mm (at 1 of 3 corners)"),
    ]
    assert [w.rule for w in out] == sorted((w.rule for w in out), key=RULES.index)


# --- through the command line -------------------------------------------------------------


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "engine.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def test_cli_warning_on_stderr_in_json_and_in_the_table(tmp_path):
    path = write(tmp_path, BASE.replace("6000 rpm", "11000 rpm"))
    result = runner.invoke(app, ["analyse", str(path), "-f", "json"])
    assert result.exit_code == 0, result.output
    (line,) = result.stderr.splitlines()
    assert line.startswith(f"balance: warning: {path}: speed: mean piston speed 31.5 m/s")
    doc = json.loads(result.stdout)
    assert doc["warnings"] == [
        {"rule": "mean_piston_speed", "field": "speed", "message": line.split(": speed: ", 1)[1]}
    ]
    table = runner.invoke(app, ["analyse", str(path), "--quiet"])
    assert table.exit_code == 0 and table.stderr == ""
    assert "warning: speed: mean piston speed 31.5 m/s" in " ".join(table.stdout.split())
    proposal = runner.invoke(app, ["propose", str(path), "-q"])
    assert "warning: speed: mean piston speed" in " ".join(proposal.stdout.split())


def test_quiet_silences_stderr_but_not_the_json(tmp_path):
    path = write(tmp_path, BASE)
    loud = runner.invoke(app, ["analyse", str(path), "-f", "json", "--speed", "30000rpm"])
    quiet = runner.invoke(app, ["analyse", str(path), "-f", "json", "--speed", "30000rpm", "-q"])
    assert [line.split(": ")[3] for line in loud.stderr.splitlines()] == ["speed", "speed"]
    assert quiet.stderr == ""
    assert json.loads(quiet.stdout)["warnings"] == json.loads(loud.stdout)["warnings"]
    assert [w["rule"] for w in json.loads(quiet.stdout)["warnings"]] == [
        "speed",
        "mean_piston_speed",
    ]


def test_a_plausible_engine_prints_nothing_and_lists_no_warning():
    result = runner.invoke(app, ["analyse", "inline-4", "-f", "json"])
    assert result.stderr == ""
    assert json.loads(result.stdout)["warnings"] == []


def test_a_warning_changes_no_number(tmp_path):
    """The bore enters no inertia number: with a bore of 10 mm the reciprocating mass per
    bore cubed warns, and every number of the JSON is the same as without a bore."""
    without = runner.invoke(app, ["analyse", str(write(tmp_path, BASE)), "-f", "json"])
    warned = BASE.replace("geometry: {", "geometry: {bore: 10 mm, ")
    with_bore = runner.invoke(app, ["analyse", str(write(tmp_path, warned)), "-f", "json"])
    a, b = json.loads(without.stdout), json.loads(with_bore.stdout)
    assert [w["rule"] for w in b.pop("warnings")] == ["reciprocating_mass"]
    assert a.pop("warnings") == []
    assert a == b


def test_the_counterweight_radius_of_the_command_line_is_checked(tmp_path):
    result = runner.invoke(app, ["propose", "inline-4", "--counterweight-radius", "100mm"])
    assert result.exit_code == 0
    assert "balance: warning: inline-4: counterweight_radius: counterweight radius 100 mm" in (
        result.stderr
    )


def test_a_sweep_warns_once_per_rule_not_per_grid_point(tmp_path):
    result = runner.invoke(
        app,
        [
            "sweep", "inline-4",
            "--vary", "speed=1000rpm:30000rpm:50",
            "--vary", "conrod_length=130mm:160mm:20",
            "--orders", "1", "--no-roll", "-o", str(tmp_path / "s.nc"),
        ],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    lines = [line for line in result.stderr.splitlines() if "warning" in line]
    assert [line.split(": ")[3] for line in lines] == ["speed", "speed"]  # two rules, once each
    assert lines[0].endswith("(at 2 of 4 corners of the sweep grid)")
    assert "speed 30000 rpm is above 25000 rpm" in lines[0]


def test_a_tolerance_study_warns_once(tmp_path):
    path = write(tmp_path, BASE.replace("geometry: {", "geometry: {bore: 35 mm, "))
    args = ["tolerance", str(path), "--scatter", "piston_group=±400g", "--samples", "50"]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    (line,) = [line for line in result.stderr.splitlines() if "warning" in line]
    # +400 g: (0.82 + 0.55 x 38/143) kg on a 35 mm bore is 22.5 g/cm^3, above 20; the
    # base layout (13.2 g/cm^3) and -400 g (3.9 g/cm^3) are within
    assert "masses.reciprocating: reciprocating mass 0.9662 kg on a bore of 35 mm" in line
    assert "22.5 g per cm^3 of bore cubed" in line
    assert line.endswith("(at 1 of 2 corners of the scatter)")
    assert runner.invoke(app, [*args, "--quiet"]).stderr == ""


def test_compare_names_the_layout_of_each_warning(tmp_path):
    tiny = (
        "name: tiny\nspeed: 6000 rpm\ngeometry: {stroke: 4 mm, conrod_length: 10 mm}\n"
        "masses: {reciprocating: 1 g, rotating: 1 g}\ncrank: {throws: [0]}\n"
    )
    path = write(tmp_path, tiny)
    result = runner.invoke(app, ["compare", "inline-4", str(path), "-f", "csv"])
    assert result.exit_code == 0, result.output
    (line,) = result.stderr.splitlines()
    assert line.startswith("balance: warning: engine: geometry.stroke: stroke 4 mm")


def test_mounts_checks_the_top_speed_of_its_sweep():
    result = runner.invoke(
        app, ["mounts", "inline-4-mounts", "--speed", "1000rpm:26000rpm:3", "-f", "csv"]
    )
    assert result.exit_code == 0, result.output
    fields = [line.split(": ")[3] for line in result.stderr.splitlines()]
    assert fields == ["speed", "speed"]
    assert "speed 26000 rpm" in result.stderr
    assert "mean piston speed 74.5 m/s" in result.stderr  # 2 x 86 mm x 26000 / 60 s
