"""Inputs (issue 22): angles as exact arithmetic, messages in the user's words, the limits,
``balance --version``."""

from __future__ import annotations

import json
import subprocess
import sys
from fractions import Fraction
from importlib import metadata
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st
from typer.testing import CliRunner

import balance
from balance.api import analyse
from balance.cli import app
from balance.core.errors import InputError
from balance.io.arithmetic import read_arithmetic
from balance.io.fields import parse_speed
from balance.io.layout_file import builtin_layout_path, load_layout
from balance.io.orders import parse_orders
from balance.io.units import UnitProblem, parse_quantity

runner = CliRunner()


def run(*args: str):
    return runner.invoke(app, list(args))


# ---------------------------------------------------------------------------------------
# angles as exact arithmetic


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("360/7 deg", 360 / 7),
        ("360/7", 360 / 7),  # bare: degrees
        ("2*360/5 deg", 144.0),
        ("2*360/7 deg", 720 / 7),  # what bank_count: 7 gives the third bank
        ("-(90 - 360/7) deg", float(Fraction(-90) + Fraction(360, 7))),
        ("(1 + 2) * 30deg", 90.0),
        ("0.1 + 0.2", 0.3),  # exact: the decimals as written, rounded once
        ("3 \u2212 1", 2.0),  # the minus sign
        ("2 \u00d7 180", 360.0),  # the times sign
        ("1/3 turn", 120.0),
        ("-360/7 deg", -360 / 7),
        ("12/2/3", 2.0),  # left to right
        ("1e3/10 deg", 100.0),
    ],
)
def test_angles_are_read_as_exact_arithmetic(text, value):
    assert parse_quantity(text, "angle") == value


def test_arithmetic_is_the_float_nearest_the_exact_value():
    """One rounding at the end: 1/3 + 1/3 + 1/3 is 1 (in floats it is 1 too, but 0.1 * 3
    is not 0.3: the exact value is)."""
    assert parse_quantity("0.1*3", "angle") == 0.3 != 0.1 * 3
    assert float(read_arithmetic("360/7").value) == 360 / 7


_UNIT_TEXT = st.text(st.characters(min_codepoint=32, max_codepoint=126), max_size=12)


@st.composite
def _one_number_texts(draw: st.DrawFn) -> str:
    """ASCII text of one unsigned number, then nothing or a unit starting with a letter or
    % ("86 mm", " .5e-3 kg m^2", "7."): what io.units reads without the arithmetic reader."""
    digits = st.text("0123456789", min_size=1, max_size=6)
    whole, fraction = draw(digits), draw(st.one_of(st.none(), st.text("0123456789", max_size=4)))
    number = draw(st.sampled_from([whole, f"{whole}.{fraction or ''}", f".{draw(digits)}"]))
    if draw(st.booleans()):
        number += draw(st.sampled_from("eE")) + draw(st.sampled_from(["", "+", "-"])) + draw(digits)
    unit = ""
    if draw(st.booleans()):
        first = draw(st.sampled_from("abcmNkgdrpsxyzAEM%"))
        unit = draw(st.sampled_from(["", " ", "  "])) + first + draw(_UNIT_TEXT)
    return draw(st.sampled_from(["", " ", "\t"])) + number + unit


@given(_one_number_texts())
def test_one_number_is_read_without_arithmetic_as_arithmetic_would(text):
    """io.units reads a text of one unsigned number and a unit (``86 mm``) without
    importing the arithmetic reader: that reader gives every such text as plain (one
    number, read by the caller as before), and refuses none."""
    from balance.io.units import _ONE_NUMBER

    assert _ONE_NUMBER.fullmatch(text), text
    read = read_arithmetic(text)
    assert read is None or read.plain, (text, read)


@pytest.mark.parametrize("text", ["360/7 deg", "5-1/8 in", "-86 mm", "2*3 mm", "(1) mm", "1e3*2"])
def test_arithmetic_texts_are_not_one_number(text):
    from balance.io.units import _ONE_NUMBER

    assert not _ONE_NUMBER.fullmatch(text)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("2**3 deg", "arithmetic has numbers, + - * / and parentheses only (no powers, no names)"),
        ("2^3", "no powers"),
        ("2 * pi rad", "no names"),
        ("__import__('os') deg", "cannot read"),
        ("(360/7 deg", "a '(' without its ')'"),
        ("360/7) deg", "a ')' without its '('"),
        ("360/0 deg", "division by zero"),
        ("1e999*2 deg", "the number '1e999' is out of range"),
        ("(" * 17 + "1" + ")" * 17, "parentheses nested deeper than 16"),
        ("360/7 mm", "'360/7 mm' is a length, not an angle"),
        # before: "unknown unit 'deg/7' (Unit expression cannot have a scaling factor.)"
        ("360 deg/7", "cannot read '360 deg/7': the arithmetic goes before the unit"),
        ("90 deg + 1 deg", "cannot read '90 deg + 1 deg': the arithmetic goes before the unit"),
        # before: accepted as 0.01745 deg (pint's degrees squared, converted to degrees)
        ("1 deg**2", "'1 deg**2': 'deg**2' is not a unit of angle"),
    ],
)
def test_arithmetic_refused(text, message):
    with pytest.raises(UnitProblem) as problem:
        parse_quantity(text, "angle")
    assert message in str(problem.value)


@pytest.mark.parametrize(
    ("text", "kind", "message", "valid"),
    [
        (
            "86/2 mm",
            "length",
            "'86/2 mm': arithmetic is read in angles only, not in a length",
            "write one number, e.g. '43 mm'",
        ),
        (  # an inch size written as a mixed number: arithmetic would read 4.875 in
            "5-1/8 in",
            "length",
            "'5-1/8 in': arithmetic is read in angles only, not in a length",
            "write one number: '5.125 in' for 5 1/8, '4.875 in' for 5 - 1/8",
        ),
        (
            "1/2",
            "fraction",
            "'1/2': arithmetic is read in angles only, not in a fraction",
            "'0.5'",
        ),
        (
            "6000*2 rpm",
            "speed",
            "'6000*2 rpm': arithmetic is read in angles only, not in a speed",
            "'12000 rpm'",
        ),
    ],
)
def test_arithmetic_only_in_angles(text, kind, message, valid):
    with pytest.raises(UnitProblem) as problem:
        parse_quantity(text, kind)
    assert str(problem.value) == message
    assert valid in problem.value.valid


def test_one_number_is_read_as_before():
    """A number alone never takes the arithmetic path: nan, inf, units after a slash."""
    assert parse_quantity("6000 rpm", "speed") == 6000 * 2 * 3.141592653589793 / 60
    assert parse_quantity("-45", "angle") == -45.0
    with pytest.raises(UnitProblem, match="not a finite number"):
        parse_quantity("1e500 mm", "length")
    with pytest.raises(UnitProblem, match="ambiguous"):
        parse_quantity("6000/min", "speed")  # the number 6000 in /min, as before


RADIAL = """\
name: Radial-7, {name}
speed: 2200 rpm
geometry: {{stroke: 117.5 mm, conrod_length: 225 mm}}
masses: {{reciprocating: 1.86 kg, rotating: 0.84 kg}}
"""


def _radial(tmp_path: Path, name: str, cylinders: list[str] | None, crank: str = "") -> Path:
    text = RADIAL.format(name=name)
    if cylinders is not None:
        text += "cylinders:\n" + "".join(
            f"  - {{throw: 0 deg, bank: {b}, z: 0 mm}}\n" for b in cylinders
        )
    else:
        text += crank
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    return path


def _forces(path: Path) -> list[dict]:
    result = run("analyse", str(path), "-f", "json")
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)["reciprocating"]["force"]


def test_radial_with_exact_angles_cancels_where_symmetry_says(tmp_path):
    """A 7-cylinder radial (rods on one pin): the free force of order k is
    (n/2) F1 (a_k forward or backward) only where k - 1 or k + 1 is a multiple of 7
    (docs/theory.md); every other phasor cancels by symmetry.  Written with 360/7, the
    zero-by-symmetry rule (docs/conventions.md) sets them to 0; written as decimals (as
    radial-7.yaml was before it was written with 360/7), they are residues of the rounded
    angles, far above rounding."""
    decimals = ["0 deg", "51.42857143 deg", "102.8571429 deg", "154.2857143 deg"]
    decimals += ["205.7142857 deg", "257.1428571 deg", "308.5714286 deg"]
    exact = ["0 deg", "360/7 deg"] + [f"{k}*360/7 deg" for k in range(2, 7)]
    before = _forces(_radial(tmp_path, "decimal", decimals))
    after = _forces(_radial(tmp_path, "exact", exact))
    counted = _forces(_radial(tmp_path, "counted", None, "crank: {throws: [0], bank_count: 7}\n"))
    assert after == counted  # bit for bit the compact form's 360 * j / 7
    survives = {(1, "forward"), (6, "backward"), (8, "forward")}
    for b, a in zip(before, after, strict=True):
        for rotation in ("forward", "backward"):
            if (a["order"], rotation) in survives:
                assert a[rotation]["magnitude"] > 0.03
                assert a[rotation]["magnitude"] == pytest.approx(b[rotation]["magnitude"])
            else:
                assert a[rotation] == {"magnitude": 0.0, "phase_deg": 0.0}
    # the decimals leave residues: order 1 backward 8.7e-6 N, order 2 3.4e-6 N peak
    assert before[0]["backward"]["magnitude"] == pytest.approx(8.73e-6, rel=1e-2)
    assert before[1]["peak"] == pytest.approx(3.36e-6, rel=1e-2)
    assert after[0]["backward"]["magnitude"] == 0.0 and after[1]["peak"] == 0.0
    # and the phase of order 6 backward reads 0, not 3e-08
    assert before[5]["backward"]["phase_deg"] == pytest.approx(3e-8, abs=2e-8)
    assert after[5]["backward"]["phase_deg"] == 0.0


def _proposal(path: Path | str) -> dict:
    result = run("propose", str(path), "-f", "json")
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)["proposal"]


def test_radial_with_exact_angles_has_an_exact_residual_with_the_proposal(tmp_path):
    """The issue's symptom: the decimals' residues make the proposal add three balance
    shafts of 1.6e-07 kg mm and less, and leave a residual force of order 4 of 2.5e-11 F1
    and a roll of 1e-06 N m.  Written with 360/7 the proposal is the counterweight alone,
    and every residual first-, second- (and other) order value that symmetry cancels is 0."""
    decimals = ["0 deg", "51.42857143 deg", "102.8571429 deg", "154.2857143 deg"]
    decimals += ["205.7142857 deg", "257.1428571 deg", "308.5714286 deg"]
    exact = ["0 deg", "360/7 deg"] + [f"{k}*360/7 deg" for k in range(2, 7)]
    before = _proposal(_radial(tmp_path, "decimal", decimals))
    after = _proposal(_radial(tmp_path, "exact", exact))
    assert len(before["balance_shafts"]) == 3
    unbalance = [p["unbalance_kgm"] for s in before["balance_shafts"] for p in s["planes"]]
    assert max(unbalance) < 2e-10  # kg m: 1.6e-07 kg mm
    assert before["residual"]["force"][3]["peak_normalised"] == pytest.approx(2.47e-11, rel=0.01)
    assert after["balance_shafts"] == []
    force, roll = after["residual"]["force"], after["residual"]["roll"]
    for k in (1, 2, 3, 4, 5, 7):
        assert force[k - 1]["peak"] == 0.0 and force[k - 1]["peak_normalised"] == 0.0
    assert [r["amplitude"] for r in roll if r["order"] != 7] == [0.0] * 7
    assert force[5]["peak"] == pytest.approx(1.8906, rel=1e-4)  # order 6: 6 = 7 - 1


def test_builtin_radial_7_is_written_exactly():
    """radial-7.yaml (link rods) writes its banks and link pins as 360/7: its phases print
    0, not 360 or 7e-09, and the proposal's second-order shaft angle 0, not 4e-09."""
    assert "360/7 deg" in builtin_layout_path("radial-7").read_text(encoding="utf-8")
    table = run("analyse", "radial-7")
    assert table.exit_code == 0
    assert "7e-09" not in table.stdout and " 360 " not in table.stdout
    forces = _forces(builtin_layout_path("radial-7"))
    assert forces[5]["backward"]["phase_deg"] == 0.0
    # order 1 and 2 backward, order 4 forward: 0, where the decimals printed 360
    assert forces[0]["backward"]["phase_deg"] == forces[1]["backward"]["phase_deg"] == 0.0
    assert forces[3]["forward"]["phase_deg"] == 0.0
    shafts = _proposal("radial-7")["balance_shafts"]
    assert [s["speed_ratio"] for s in shafts] == [-1, 2, -2]
    assert shafts[1]["planes"][0]["angle_deg"] == 0.0


def test_arithmetic_wherever_an_angle_is_read(tmp_path):
    """crank throws and banks, split, a cylinder's tdc, a link's pin_angle, the gas model's
    combustion start: each the same engine as the decimals it stands for."""
    base = (
        "name: five\nspeed: 6000 rpm\ngeometry: {stroke: 80 mm, conrod_length: 140 mm}\n"
        "masses: {reciprocating: 0.5 kg, rotating: 0.4 kg}\n"
    )
    plain = tmp_path / "plain.yaml"
    plain.write_text(base + "crank: {throws: [0, 144, 288, 72, 216], spacing: 90 mm}\n")
    written = tmp_path / "written.yaml"
    written.write_text(
        base + "crank: {throws: [0, 2*360/5, 4*360/5 deg, 360/5, 3*360/5 deg], spacing: 90 mm}\n"
    )
    a, b = analyse(load_layout(plain)), analyse(load_layout(written))
    assert a.reciprocating_force_magnitude.equals(b.reciprocating_force_magnitude)
    gas = (
        "firing_order: [1, 5, 4, 3, 2]\ngas: {model: {compression_ratio: 10, peak_pressure: "
        "70 bar, combustion_start: %s}, bore: 82 mm}\n"
    )
    with_gas = tmp_path / "gas.yaml"
    with_gas.write_text(written.read_text() + gas % "-360/36 deg")
    assert load_layout(with_gas).gas.model.combustion_start == -10.0
    tdc = tmp_path / "tdc.yaml"
    tdc.write_text(base + "cylinders:\n  - {tdc: 720/3 deg, bank: 360/3, z: 0}\n")
    assert load_layout(tdc).throw[0] == pytest.approx(-2.0943951023931957, abs=1e-15)


def test_arithmetic_error_in_a_file_is_one_line_with_its_place(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text(
        "name: bad\nspeed: 6000 rpm\ngeometry: {stroke: 86/2 mm, conrod_length: 143 mm}\n"
        "masses: {reciprocating: 0.5 kg, rotating: 0.4 kg}\ncrank: {throws: [0, 360/0]}\n"
    )
    result = run("analyse", str(path))
    assert result.exit_code == 2
    assert result.stderr == (
        f"balance: {path}:3:20: geometry.stroke: '86/2 mm': arithmetic is read in angles only, "
        "not in a length; write one number, e.g. '43 mm'\n"
        f"balance: {path}:5:21: crank.throws[2]: cannot read '360/0': division by zero; write "
        "numbers with + - * / and parentheses, then the unit, e.g. '360/7 deg' or "
        "'2*360/5 deg'\n"
    )


MALICIOUS = [
    "__import__('os')",
    "__import__('os').system('true') deg",
    "eval('1') deg",
    "(lambda: 0)() deg",
    "2**8 deg",
    "360/7 deg; import os",
    "[].__class__ deg",
]


@pytest.mark.parametrize("text", MALICIOUS)
def test_malicious_angles_are_refused_in_one_line(tmp_path, text):
    """Nothing but numbers and + - * / ( ) is read: code in an angle's place is refused
    with file:line:column, the field and what to write, and nothing runs."""
    path = tmp_path / "m.yaml"
    quoted = text.replace("'", "''")
    path.write_text(
        "name: m\nspeed: 6000 rpm\ngeometry: {stroke: 86 mm, conrod_length: 143 mm}\n"
        "masses: {reciprocating: 0.5 kg, rotating: 0.4 kg}\n"
        f"cylinders:\n  - {{throw: 0, bank: '{quoted}', z: 0}}\n"
    )
    result = run("analyse", str(path))
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and not result.stdout
    assert lines[0].startswith(f"balance: {path}:6:22: cylinders[1].bank: ")
    assert any(w in lines[0] for w in ("cannot read", "unknown unit 'deg; import os'"))
    assert "e.g. '90 deg'" in lines[0] or "e.g. '360/7 deg'" in lines[0]


def test_arithmetic_on_the_command_line():
    result = run("search", "--cylinders", "3", "--step", "360/3", "--top", "1")
    assert result.exit_code == 0, result.stderr
    with pytest.raises(InputError, match="--step: cannot read '360/0': division by zero"):
        from balance.io.fields import parse_option_quantity

        parse_option_quantity("360/0", "angle", "--step")


# ---------------------------------------------------------------------------------------
# messages


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (  # before: "orders: '1-100000' is not an increasing range"
            ["analyse", "inline-4", "--orders", "1-100000"],
            "--orders: '1-100000': every order must be between 1 and 1000",
        ),
        (
            ["analyse", "inline-4", "--orders", "8-1"],
            "--orders: '8-1' is not an increasing range; write the lower order first, e.g. 1-8",
        ),
        (  # before: "orders: every order must be between 1 and 1000" for --cancel
            ["propose", "inline-4", "--cancel", "0"],
            "--cancel: '0': every order must be between 1 and 1000",
        ),
        (  # before: "speed must be a finite number above zero, got -10.471975511965976 rad/s"
            ["analyse", "inline-4", "--speed", "-100rpm"],
            "--speed: -100rpm: the speed must be a finite number above zero, e.g. 6000rpm",
        ),
        (
            ["analyse", "inline-4", "--speed", "-2 Hz"],
            "--speed: -2 Hz: the speed must be a finite number above zero, e.g. 6000rpm",
        ),
        (  # before: "--vary: speed: values must be above zero, got -10.472"
            ["sweep", "inline-4", "--vary", "speed=-100rpm:100rpm:3", "-o", "x.nc"],
            "--vary: speed: values must be above zero, got -100rpm",
        ),
        (  # before: an internal error (MemoryError) allocating the values
            ["sweep", "inline-4", "--vary", "speed=1rpm:9rpm:99999999999999", "-o", "x.nc"],
            "--vary: speed: count 99999999999999 is more than the 1000000 values a field may have",
        ),
        (  # before: "--step/--banks: unknown unit '1/7' (Unit expression cannot have a ...)"
            ["search", "--cylinders", "4", "--banks", "0,1/0"],
            "--banks: cannot read '1/0': division by zero; write numbers with + - * / and "
            "parentheses, then the unit, e.g. '360/7 deg' or '2*360/5 deg'",
        ),
        (
            ["tolerance", "inline-4", "--scatter", "throw=±1deg", "--orders", "0-2"],
            "--orders: '0-2': every order must be between 1 and 1000",
        ),
    ],
)
def test_option_messages(args, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = run(*args)
    assert result.exit_code == 2, result.output
    assert result.stderr == f"balance: {message}\n"


def test_library_messages_name_the_parameter():
    with pytest.raises(InputError, match=r"^orders: '1-5000': every order must be between 1"):
        parse_orders("1-5000")
    with pytest.raises(InputError, match=r"^orders: 100000: every order must be between 1"):
        parse_orders(100_000)  # refused before a list of 100000 orders is made
    with pytest.raises(InputError, match=r"^speed: -3 Hz: the speed must be"):
        parse_speed("-3 Hz")


LAYOUT = """\
name: t
speed: {speed}
geometry: {{stroke: 86 mm, conrod_length: 143 mm}}
masses: {masses}
crank: {crank}
"""


def _layout(tmp_path: Path, **changes: str) -> Path:
    values = {
        "speed": "6000 rpm",
        "masses": "{reciprocating: 0.45 kg, rotating: 0.5 kg}",
        "crank": "{throws: [0, 180, 180, 0], spacing: 90 mm}",
    }
    values.update(changes)
    path = tmp_path / "t.yaml"
    path.write_text(LAYOUT.format(**values) + changes.get("extra", ""))
    return path


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (  # before: "masses.piston_group: piston_group is -0.4; ..."
            {"masses": "{piston_group: -0.4 kg, conrod: 500 g, conrod_cg_to_big_end: 40 mm}"},
            "4:24: masses.piston_group: piston_group is -0.4 kg; piston_group must be more "
            "than zero",
        ),
        (  # before: "reciprocating is -0.453592"
            {"masses": "{reciprocating: -1 lb, rotating: 0.5 kg}"},
            "4:25: masses.reciprocating: reciprocating is -1 lb; reciprocating must be more "
            "than zero",
        ),
        (  # before: "speed is -10.472 rad/s"
            {"speed": "-100 rpm"},
            "2:8: speed: speed is -100 rpm; speed must be more than zero",
        ),
        (  # before: "balance_factor is -0.5"
            {"extra": "balance: {balance_factor: -50 %}\n"},
            "6:27: balance.balance_factor: balance_factor is -50 %; a share between 0 % and "
            "200 % of each cylinder's reciprocating mass",
        ),
        (  # before: "crank.throws: 300 entries; at most 256 entries"
            {"crank": "{throws: [" + ", ".join(["0"] * 300) + "], spacing: 90 mm}"},
            "5:17: crank.throws: 300 throws; at most 256 throws",
        ),
        (  # before: "Input should be greater than or equal to 1"
            {"crank": "{throws: [0], bank_count: 0}"},
            "5:34: crank.bank_count: bank_count is 0; at least 1",
        ),
        (  # before: "Input should be less than or equal to 64"
            {"crank": "{throws: [0], bank_count: 1000}"},
            "5:34: crank.bank_count: bank_count is 1000; at most 64",
        ),
        (  # before: accepted as one bank
            {"crank": "{throws: [0], bank_count: true}"},
            "5:34: crank.bank_count: expected a whole number, got true or false; write a "
            "whole number here",
        ),
        (  # before: accepted, and the proposal asked for order 100000
            {"extra": "balance: {orders: [1, 100000]}\n"},
            "6:19: balance.orders: orders must be 1 to 1000; for example [1, 2]",
        ),
        (  # before: "internal error: OverflowError: cannot convert float infinity to integer"
            {"extra": "balance: {shafts: [{speed_ratio: .inf}]}\n"},
            "6:34: balance.shafts[1].speed_ratio: speed_ratio is inf; a whole number from -64 "
            "to 64 other than 0, e.g. 2 or -2 (negative: against the crank)",
        ),
        (  # before: "Value error, cannot convert float NaN to integer"
            {"extra": "balance: {shafts: [{speed_ratio: .nan}]}\n"},
            "6:34: balance.shafts[1].speed_ratio: speed_ratio is nan; a whole number from -64 "
            "to 64 other than 0, e.g. 2 or -2 (negative: against the crank)",
        ),
        (  # before: "unknown unit '1/7 deg' (Unit expression cannot have a scaling factor.)"
            {"crank": "{throws: [0, 1/7 mm], spacing: 90 mm}"},
            "5:21: crank.throws[2]: '1/7 mm' is a length, not an angle; give angle with a "
            "unit, e.g. '90 deg', or a plain number in degrees",
        ),
    ],
)
def test_layout_messages(tmp_path, changes, message):
    path = _layout(tmp_path, **changes)
    result = run("analyse", str(path))
    assert result.exit_code == 2, result.output
    assert result.stderr == f"balance: {path}:{message}\n"


def test_too_many_cylinders_says_cylinders(tmp_path):
    """before: "List should have at most 256 items after validation" (pydantic's words),
    then "5000 entries; at most 256 entries"."""
    rows = "".join(f"  - {{throw: 0 deg, z: {i} mm}}\n" for i in range(5000))
    path = tmp_path / "big.yaml"
    path.write_text(
        "name: big\nspeed: 6000 rpm\ngeometry: {stroke: 86 mm, conrod_length: 143 mm}\n"
        "masses: {reciprocating: 0.45 kg, rotating: 0.5 kg}\ncylinders:\n" + rows
    )
    result = run("analyse", str(path))
    assert result.exit_code == 2
    assert (
        result.stderr == f"balance: {path}:6:3: cylinders: 5000 cylinders; at most 256 cylinders\n"
    )


USAGE_SCRIPT = """\
import sys
from balance.cli import main
for args in sys.argv[1:]:
    sys.argv = ['balance', *args.split('|')]
    try:
        main()
    except SystemExit:
        pass
"""


def test_typer_usage_errors_in_our_words():
    """The command line's own checks of an option's type and bounds (typer) are worded as
    the rest: the option, the value as typed, what is valid.  Run through ``main`` (a
    fresh process), which is where they are translated."""
    cases = {
        # before: "Invalid value for '--samples': Input should be greater than or equal to 1"
        "tolerance|inline-4|--samples|0|--scatter|throw=±1deg": "--samples: 0 is below 1; give "
        "1 or more; see 'balance tolerance --help'",
        # before: "Invalid value for '--cylinders': Input should be less than or equal to 16"
        "search|--cylinders=20": "--cylinders: 20 is above 16; give at most 16; see 'balance "
        "search --help'",
        # before: "... Input should be a valid integer, unable to parse string as an integer"
        "search|--cylinders|2.5": "--cylinders: 2.5 is not a whole number; see 'balance search "
        "--help'",
        # before: "Invalid value for '--format' / '-f': Value error, 'xml' is not one of ..."
        "analyse|inline-4|-f|xml": "--format: 'xml' is not one of 'table', 'json', 'csv', "
        "'netcdf'; see 'balance analyse --help'",
    }
    done = subprocess.run(
        [sys.executable, "-c", USAGE_SCRIPT, *cases],
        capture_output=True,
        text=True,
        check=False,
    )
    lines = done.stderr.splitlines()
    assert lines == [f"balance: {message}" for message in cases.values()], done.stderr


# ---------------------------------------------------------------------------------------
# balance --version


def test_version_prints_the_installed_version():
    result = run("--version")
    assert result.exit_code == 0
    assert result.stdout == f"balance {metadata.version('balance')}\n"
    assert result.stdout == f"balance {balance.__version__}\n"  # the metadata is the source's
    done = subprocess.run(
        [sys.executable, "-m", "balance", "--version"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0 and done.stdout == result.stdout and done.stderr == ""
