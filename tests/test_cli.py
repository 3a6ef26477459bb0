"""The command line: contract JSON, formats, exit codes and one-line errors."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest
import xarray as xr
from typer.testing import CliRunner

from balance.cli import app
from balance.io.layout_file import builtin_layout_names

runner = CliRunner()

BAD = """\
name: bad
speed: 6000 rpm
geometry:
  stroke: 86 kg
  conrod_length: 143 mm
masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}
crank: {throws: [0, 180], spacing: 90 mm}
"""


def run(*args: str):
    return runner.invoke(app, list(args))


def test_analyse_json_is_the_contract():
    result = run("analyse", "inline-4", "--format", "json")
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    assert data["schema"] == "balance.analysis/1"
    assert data["layout"]
    assert isinstance(data["speed_rpm"], float) and isinstance(data["reference_z_m"], float)
    forces = data["reciprocating"]["force"]
    assert [f["order"] for f in forces] == list(range(1, 9))  # every listed order, even zeros
    for entry in forces + data["reciprocating"]["moment"]:
        assert set(entry) >= {"order", "forward", "backward", "peak"}
        for rotation in ("forward", "backward"):
            assert set(entry[rotation]) == {"magnitude", "phase_deg"}
            assert 0.0 <= entry[rotation]["phase_deg"] < 360.0
        assert entry["peak"] == pytest.approx(
            entry["forward"]["magnitude"] + entry["backward"]["magnitude"]
        )
    for what in ("force", "moment"):
        assert set(data["rotating"][what]) >= {"forward", "peak"}
    assert [r["order"] for r in data["roll"]] == list(range(1, 9))
    assert set(data["roll"][0]) == {"order", "amplitude", "phase_deg"}
    # the inline-4: only even orders of free force
    assert forces[0]["peak"] == 0.0 and forces[1]["peak"] > 0.0


def test_json_orders_and_speed_options():
    result = run("analyse", "inline-3", "-f", "json", "--orders", "1,2,4-5", "--speed", "3000rpm")
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    assert [f["order"] for f in data["reciprocating"]["force"]] == [1, 2, 4, 5]
    assert data["speed_rpm"] == pytest.approx(3000.0)


def test_table_is_default_and_readable():
    result = run("analyse", "inline-4")
    assert result.exit_code == 0
    assert "reciprocating inertia" in result.stdout and "Roll" in result.stdout
    assert result.stderr == ""


def test_csv_output():
    result = run("analyse", "v8-crossplane", "-f", "csv", "--orders", "1-2")
    assert result.exit_code == 0
    lines = result.stdout.strip().splitlines()
    assert lines[0].startswith("order,force_forward_magnitude [N]")
    assert len(lines) == 3


def test_netcdf_output_has_units_and_matches_json(tmp_path):
    target = tmp_path / "out.nc"
    result = run("analyse", "inline-3", "-f", "netcdf", "-o", str(target))
    assert result.exit_code == 0, result.stderr
    assert f"wrote {target}" in result.stderr
    with xr.open_dataset(target, engine="netcdf4") as ds:
        for name, var in ds.variables.items():
            assert "units" in var.attrs and "long_name" in var.attrs, name
        peak = float(ds.reciprocating_moment_peak.sel(order=1))
    data = json.loads(run("analyse", "inline-3", "-f", "json").stdout)
    assert data["reciprocating"]["moment"][0]["peak"] == pytest.approx(peak, rel=1e-15)


def test_existing_output_is_kept_without_force(tmp_path):
    target = tmp_path / "out.json"
    target.write_text("previous")
    result = run("analyse", "inline-4", "-f", "json", "-o", str(target))
    assert result.exit_code == 2
    assert "file exists; use --force" in result.stderr
    assert target.read_text() == "previous"
    result = run("analyse", "inline-4", "-f", "json", "-o", str(target), "--force")
    assert result.exit_code == 0
    assert json.loads(target.read_text())["schema"] == "balance.analysis/1"


def test_the_library_names_its_settings_and_the_command_line_its_options(tmp_path):
    """A problem found by the library names the parameter or setting (``vary:``,
    ``(force)``); the command line names its option for the same problem."""
    from balance.core.errors import InputError, OutputExists
    from balance.io.atomic import check_target
    from balance.io.layout_file import load_layout
    from balance.studies.search import search
    from balance.studies.sweep import sweep
    from balance.studies.tolerance import tolerance

    engine = load_layout("inline-4")
    target = tmp_path / "out.json"
    target.write_text("previous")
    library = [
        (lambda: check_target(target), f"{target}: file exists and replacing it was not "
         "asked for (force)"),
        (lambda: sweep(engine, ["conrod_length=130:160:3"]), "vary: conrod_length: 130 has no "
         "unit; give a unit, e.g. conrod_length=130mm"),
        (lambda: sweep(engine, ["speed=1000rpm:2000rpm:2"], model="time"), "model: 'time'; a "
         "sweep uses one of exact, series, textbook"),
        (lambda: tolerance(engine, ["reciprocating=±3"], samples=10), "scatter: reciprocating: "
         "3 has no unit; give a unit, e.g. reciprocating=±3g"),
        (lambda: tolerance(engine, ["reciprocating=±3g"], distribution="flat"), "distribution: "
         "'flat'; valid: uniform, normal"),
        (lambda: search(4, objective="best"), "objective: 'best'; valid: free, moments, shafts"),
    ]  # fmt: skip
    for call, message in library:
        with pytest.raises(InputError) as info:
            call()
        assert str(info.value) == message
    with pytest.raises(OutputExists):
        check_target(target)
    command_line = [
        (["analyse", "inline-4", "-f", "json", "-o", str(target)], f"{target}: file exists; "
         "use --force to replace it"),
        (["sweep", "inline-4", "--vary", "speed=1000rpm:2000rpm:2", "--model", "time", "-o",
          str(tmp_path / "s.nc")], "--model: 'time'; a sweep uses one of exact, series, textbook"),
        (["tolerance", "inline-4", "--scatter", "reciprocating=±3g", "--distribution", "flat"],
         "--distribution: 'flat'; valid: uniform, normal"),
        (["search", "--cylinders", "4", "--objective", "best"], "--objective: 'best'; valid: "
         "free, moments, shafts"),
        (["search", "--cylinders", "4", "--rod-ratio", "1.5"], "--rod-ratio: 1.5 is not between "
         "0 and 1"),
    ]  # fmt: skip
    for args, message in command_line:
        result = run(*args)
        assert result.exit_code == 2, result.output
        assert result.stderr == f"balance: {message}\n"


def test_output_into_missing_directory(tmp_path):
    result = run("analyse", "inline-4", "-f", "json", "-o", str(tmp_path / "nope" / "x.json"))
    assert result.exit_code == 2
    assert "does not exist" in result.stderr


def test_netcdf_needs_a_file():
    result = run("analyse", "inline-4", "-f", "netcdf")
    assert result.exit_code == 2 and "give -o PATH" in result.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["analyse", "no-such-engine"], "no such file or built-in layout"),
        (["analyse", "inline-4", "--orders", "0-3"], "every order must be between 1"),
        (["analyse", "inline-4", "--orders", "two"], "cannot read 'two'"),
        (["analyse", "inline-4", "--speed", "5 kg"], "--speed: '5 kg' is a mass, not a speed"),
        (
            ["analyse", "inline-4", "--speed", "-100 rpm"],
            "speed must be a finite number above zero",
        ),
    ],
)
def test_bad_options_exit_2_with_one_line(args, message):
    result = run(*args)
    assert result.exit_code == 2
    assert message in result.stderr
    assert result.stderr.count("\n") == 1
    assert "Traceback" not in result.stderr
    assert result.stdout == ""


def test_bad_layout_file_exit_2_with_location(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text(BAD)
    result = run("analyse", str(path), "-f", "json")
    assert result.exit_code == 2
    assert result.stderr == (
        f"balance: {path}:4:11: geometry.stroke: '86 kg' is a mass, not a length; give length "
        "with a unit, e.g. '86 mm'\n"
    )
    assert result.stdout == ""


def test_debug_shows_the_exception(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text(BAD)
    result = run("--debug", "analyse", str(path))
    assert result.exit_code != 0
    assert result.exception is not None


@pytest.mark.parametrize("name", builtin_layout_names())
def test_every_builtin_layout_analyses(name):
    result = run("analyse", name, "-f", "json")
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    values = [f["peak"] for f in data["reciprocating"]["force"]]
    assert all(v is not None and math.isfinite(v) and v >= 0 for v in values)


def test_layouts_lists_builtins():
    result = run("layouts")
    assert result.exit_code == 0
    for name in ("inline-4", "v8-crossplane", "radial-9"):
        assert name in result.stdout


def test_layout_expand_prints_explicit_form():
    result = run("layout", "expand", "v8-crossplane")
    assert result.exit_code == 0
    assert "cylinders:" in result.stdout and "crank:" not in result.stdout
    assert result.stdout.count("throw:") == 8


def test_installed_entry_point_runs_in_a_fresh_process(tmp_path):
    """The real process: `balance analyse inline-4 --format json`, clean stdout, exit 0."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    proc = subprocess.run(
        [sys.executable, "-m", "balance", "analyse", "inline-4", "--format", "json"],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp_path,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["schema"] == "balance.analysis/1"
    bad = Path(tmp_path / "bad.yaml")
    bad.write_text(BAD)
    proc = subprocess.run(
        [sys.executable, "-m", "balance", "analyse", str(bad)],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp_path,
        check=False,
    )
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


GOOD = BAD.replace("86 kg", "86 mm")


@pytest.mark.parametrize(
    ("old", "new", "where", "message"),
    [
        ("  stroke: 86 mm", "  strok: 86 mm", ":4:3: geometry.strok:", "did you mean 'stroke'?"),
        ("  conrod_length: 143 mm\n", "", ":4:3: geometry.conrod_length:", "missing"),
        ("86 mm", "86 kg", ":4:11: geometry.stroke:", "is a mass, not a length"),
        ("143 mm", "40 mm", ":5:18: geometry.conrod_length:", "'40 mm' is not more than crank_r"),
        ("reciprocating: 0.6 kg", "reciprocating: -0.6 kg", ":6:", "must be more than zero"),
        ("speed: 6000 rpm", "speed: 6000 rpm\nspeed: 5000 rpm", ":3:1: speed:", "duplicate key"),
    ],
)
def test_each_bad_input_class_exits_2_with_location(tmp_path, old, new, where, message):
    path = tmp_path / "engine.yaml"
    path.write_text(GOOD.replace(old, new))
    result = run("analyse", str(path), "-f", "json")
    assert result.exit_code == 2
    line = result.stderr
    assert line.startswith(f"balance: {path}{where}"), line
    assert message in line and line.count("\n") == 1
    assert result.stdout == ""


def test_analyse_json_has_the_contract_proposal():
    data = json.loads(run("analyse", "inline-3", "-f", "json").stdout)
    proposal = data["proposal"]
    assert proposal["strategy"] == "two-plane" and proposal["orders"] == [1, 2]
    for cw in proposal["counterweights"]:
        assert set(cw) == {"z_m", "mass_kg", "radius_m", "angle_deg"}
    for shaft in proposal["balance_shafts"]:
        assert set(shaft) == {"speed_ratio", "x_m", "y_m", "position_from", "planes"}
        assert shaft["position_from"] == {"x": "default", "y": "default"}
        for plane in shaft["planes"]:
            assert set(plane) == {"z_m", "unbalance_kgm", "angle_deg"}
    assert [s["speed_ratio"] for s in proposal["balance_shafts"]] == [-1, 2, -2]
    residual = proposal["residual"]
    assert [r["order"] for r in residual["force"]] == list(range(1, 9))
    assert residual["moment"][0]["peak"] == 0.0 and residual["moment"][1]["peak"] == 0.0
    assert "peak" in residual["force"][0]


def test_propose_options():
    result = run(
        "propose",
        "single",
        "-f",
        "json",
        "--cancel",
        "1",
        "--balance-factor",
        "60%",
        "--counterweight-radius",
        "50mm",
        "--factor-study",
    )
    assert result.exit_code == 0, result.stderr
    data = json.loads(result.stdout)
    proposal = data["proposal"]
    assert proposal["orders"] == [1] and proposal["balance_factor"] == pytest.approx(0.6)
    assert proposal["counterweights"][0]["radius_m"] == pytest.approx(0.05)
    assert data["balance_factor_study"]["optimal_factor"] == pytest.approx(0.5, abs=1e-6)
    table = run("propose", "inline-4", "--strategy", "per-throw", "--cancel-roll")
    assert table.exit_code == 0, table.stderr
    assert "per-throw" in table.stdout and "Balance shafts" in table.stdout
    # from the default axes (x = -/+r) the nearest placement would crowd the crank, so the
    # pair goes either side of the crank axis, across its force (theory docs, "Balance shafts")
    assert (
        "Note: order 2: shafts placed on either side of the crank axis, across their force, to "
        "cancel the roll" in " ".join(table.stdout.split())
    )


def test_propose_bad_options():
    result = run("propose", "single", "--balance-factor", "5 kg")
    assert result.exit_code == 2 and "--balance-factor" in result.stderr
    result = run("propose", "single", "--strategy", "diagonal")
    assert result.exit_code == 2


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["analyse"], "Missing argument"),
        (["analyse", "inline-4", "--format", "xml"], "'xml' is not one of"),
        (["frobnicate"], "No such command 'frobnicate'"),
        (["analyse", "inline-4", "--orders"], "requires an argument"),
    ],
)
def test_usage_errors_are_one_line_from_the_real_entry_point(args, message):
    proc = subprocess.run(
        [sys.executable, "-m", "balance", *args], capture_output=True, text=True, check=False
    )
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and message in proc.stderr
    assert proc.stderr.startswith("balance: ") and "--help'" in proc.stderr
    assert proc.stdout == ""


@pytest.mark.parametrize(
    ("args", "flag"),
    [
        (["analyse", "inline-4", "--on-mounts"], "--mounts FILE"),
        (["analyse", "inline-4", "--with-proposal"], "--with-proposal"),
        (["mounts", "inline-4", "--speed", "1000rpm:2000rpm:3"], "--mounts FILE"),
    ],
)
def test_the_mounts_of_a_layout_without_them_one_line_naming_the_flag(args, flag):
    """``--on-mounts`` (on the mounts, the default for a layout with a mounts: section), and
    the other ways of asking for the mounts, on a layout without a mounts: section: exit 2,
    one line naming the option that gives mounts, nothing on stdout (the real entry point)."""
    proc = subprocess.run(
        [sys.executable, "-m", "balance", *args], capture_output=True, text=True, check=False
    )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith("balance: ")
    assert "has no mounts: section" in proc.stderr and flag in proc.stderr
    assert proc.stdout == ""


def test_on_mounts_is_the_default_of_a_layout_with_mounts():
    """``--on-mounts`` asks for what a layout's mounts: section turns on anyway."""
    bare = run("analyse", "inline-4-mounts", "--orders", "1-2", "-f", "json")
    on = run("analyse", "inline-4-mounts", "--orders", "1-2", "-f", "json", "--on-mounts")
    assert bare.exit_code == on.exit_code == 0, bare.stderr + on.stderr
    assert "mounts" in json.loads(bare.stdout)
    assert on.stdout == bare.stdout


@pytest.mark.parametrize(
    "args",
    [
        ["analyse", "--help"],
        ["analyse", "inline-4", "--orders", "1-2", "--format", "json"],
        ["--debug", "analyse", "v6-90", "--orders", "1-3", "--format", "json"],
        ["analyse"],
        ["analyse", "inline-4", "--bogus"],
        ["sweep", "--help"],
        ["layouts"],
        ["propose", "inline-3", "--format", "json"],
    ],
)
def test_the_one_command_application_behaves_as_the_full_one(args):
    """main() runs an application with only the named command (start-up time); its output,
    help and errors must be those of the full application."""
    from balance.cli import _app_for

    chosen = _app_for(args)
    assert chosen is not app
    assert len(chosen.registered_commands) == 1
    one = runner.invoke(chosen, args, prog_name="balance")
    full = runner.invoke(app, args, prog_name="balance")
    assert one.exit_code == full.exit_code
    assert one.output == full.output


@pytest.mark.parametrize(
    "args", [[], ["--help"], ["layout", "expand", "inline-4"], ["analys", "inline-4"], ["--debug"]]
)
def test_other_command_lines_run_the_full_application(args):
    from balance.cli import _app_for

    assert _app_for(args) is app


def test_the_table_of_commands_says_where_each_command_is():
    """balance.cli lists each command (in the order of ``balance --help``) with the module
    that holds it; each module's ``COMMANDS`` holds exactly those."""
    from balance.cli import _COMMANDS, _commands_of

    for module in set(_COMMANDS.values()):
        assert set(_commands_of(module)) == {n for n, m in _COMMANDS.items() if m == module}
    assert [c.name for c in app.registered_commands] == list(_COMMANDS)


@pytest.mark.parametrize(
    ("command", "module"),
    [("analyse", "analysis"), ("sweep", "studies"), ("layouts", "layouts")],
)
def test_a_command_imports_only_its_own_module_of_the_command_line(command, module):
    """Start-up: ``balance COMMAND`` builds and imports only the module of that command."""
    code = (
        "import sys, typer.main\n"
        "from balance.cli import _app_for\n"
        f"typer.main.get_command(_app_for([{command!r}, 'inline-4']))\n"
        "print(' '.join(sorted(m for m in sys.modules if m.startswith('balance.cli'))))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = set(proc.stdout.split())
    assert loaded == {"balance.cli", f"balance.cli.{module}", "balance.cli.common"}


def test_every_problem_of_a_file_at_once_one_line_each(tmp_path):
    """Each line: file:line:column: field: what was read; what would be valid (in file
    order), exit code 2, nothing on stdout, no traceback."""
    path = tmp_path / "many.yaml"
    path.write_text(
        "name: many\n"
        "speed: 6000\n"
        "geometry: {stroke: 86, conrod_lenght: 143 mm}\n"
        "masses: {reciprocating: 360, rotating: 0.4 kg}\n"
        "cylinders:\n  throw: 0\n  z: 0\n"
        "mounts: {mass: 160, cg: [0, 60 mm, 140 mm], inertia: {xx: 7.5 kg m^2, yy: 9 kg m^2,"
        " zz: 4 kg m^2}, points: [{position: [0 mm, 0 mm, 0 mm], stiffness: [1 N/mm, 1 N/mm,"
        " 1 N/mm]}]}\n"
    )
    result = run("analyse", str(path), "-f", "json")
    assert result.exit_code == 2
    assert result.stdout == ""
    assert result.stderr.splitlines() == [
        f"balance: {path}:2:8: speed: 6000 has no unit; give a unit, e.g. '6000 rpm'",
        f"balance: {path}:3:20: geometry.stroke: 86 has no unit; give a unit, e.g. '86 mm'",
        f"balance: {path}:3:24: geometry.conrod_lenght: unknown key 'conrod_lenght'; did you "
        "mean 'conrod_length'? valid keys: stroke, crank_radius, conrod_length, offset, bore",
        f"balance: {path}:4:25: masses.reciprocating: 360 has no unit; give a unit, e.g. '360 g'",
        f"balance: {path}:6:3: cylinders: expected a list, got a mapping; a list of cylinders, "
        "each {throw: ..., bank: ..., z: ...}",
        f"balance: {path}:8:16: mounts.mass: 160 has no unit; give a unit, e.g. '160 kg'",
    ]


def test_problems_found_after_reading_are_reported_together(tmp_path):
    """Problems that only show once every value is read (an impossible crank slider, a
    firing order, a bearing in a pin's plane) come together too."""
    path = tmp_path / "later.yaml"
    path.write_text(
        "name: later\nspeed: 6000 rpm\n"
        "geometry: {stroke: 300 mm, conrod_length: 120 mm}\n"
        "masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}\n"
        "crank: {throws: [0, 180], spacing: 90 mm}\n"
        "firing_order: [1, 1]\n"
        "bearings: {mains: [-45 mm, 90 mm]}\n"
    )
    result = run("analyse", str(path))
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert [line.split(": ")[2] for line in lines] == [
        "geometry.conrod_length",
        "firing_order",
        "bearings.mains[2]",
    ]
    assert (
        "conrod_length '120 mm' is not more than crank_radius (stroke '300 mm' / 2) + |offset| "
        "0 (not given) (every cylinder)" in lines[0]
    )


def test_a_tab_is_named_at_its_line_and_column(tmp_path):
    path = tmp_path / "tab.yaml"
    path.write_text("name: tab\nspeed: 6000 rpm\ngeometry:\n  stroke: 86 mm\n\tconrod_length: 1\n")
    result = run("analyse", str(path))
    assert result.exit_code == 2
    assert result.stderr == (
        f"balance: {path}:5:1: a tab character: YAML does not allow tabs for indentation; "
        "indent with spaces\n"
    )
