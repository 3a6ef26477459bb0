"""Units at the boundary, including pint's rpm."""

from __future__ import annotations

import itertools
import json
import math
import re
import sys

import pytest
from typer.testing import CliRunner

from balance.cli import app
from balance.io import units
from balance.io.units import (
    _FAST_UNITS,
    ANY_CASE,
    CASE_MATTERS,
    UnitProblem,
    parse_quantity,
    registry,
)


def test_pint_rpm_is_two_pi_radians_per_minute():
    """pint defines rpm as revolution/minute with revolution = 2 pi rad: converting to 'Hz'
    gives 628 Hz for 6000 rpm, which is wrong for a rotation frequency.  balance must give
    628.3 rad/s (and never 100 or 6000 * 2 pi)."""
    ureg = registry()
    assert ureg.Quantity("6000 rpm").to("Hz").magnitude == pytest.approx(200 * math.pi)  # the trap
    assert parse_quantity("6000 rpm", "speed") == pytest.approx(2 * math.pi * 6000 / 60)


@pytest.mark.parametrize(
    ("text", "rad_per_s"),
    [
        ("6000 rpm", 200 * math.pi),
        ("6000 rev/min", 200 * math.pi),
        ("100 Hz", 200 * math.pi),  # Hz: revolutions per second
        ("628.3185307179586 rad/s", 200 * math.pi),
        ("36000 deg/s", 200 * math.pi),
        ("100 turn/s", 200 * math.pi),
        ("1 rpm", 2 * math.pi / 60),
    ],
)
def test_speed_units(text, rad_per_s):
    assert parse_quantity(text, "speed") == pytest.approx(rad_per_s, rel=1e-12)


def test_bare_inverse_seconds_are_ambiguous():
    with pytest.raises(UnitProblem, match="ambiguous"):
        parse_quantity("100 1/s", "speed")
    with pytest.raises(UnitProblem, match="ambiguous"):
        parse_quantity("100 /s", "speed")


@pytest.mark.parametrize(
    ("text", "kind", "value"),
    [
        ("86 mm", "length", 0.086),
        ("3.386 in", "length", 0.0860044),
        (0, "length", 0.0),  # only 0 may be bare
        ("0", "mass", 0.0),
        ("0.45 kg", "mass", 0.45),
        ("450 g", "mass", 0.45),
        ("1.9e-3 kg m^2", "inertia", 1.9e-3),
        ("19 kg cm^2", "inertia", 1.9e-3),
        ("90 deg", "angle", 90.0),
        ("90°", "angle", 90.0),
        (90, "angle", 90.0),  # plain numbers for angles are degrees
        ("3.141592653589793 rad", "angle", 180.0),
        ("50 %", "fraction", 0.5),
        (0.5, "fraction", 0.5),
        ("1 bar", "pressure", 1e5),
    ],
)
def test_quantities(text, kind, value):
    assert parse_quantity(text, kind) == pytest.approx(value, rel=1e-6)


@pytest.mark.parametrize(
    ("text", "kind", "message"),
    [
        ("86 kg", "length", "'86 kg' is a mass, not a length"),
        ("5 kg", "speed", "'5 kg' is a mass, not a speed"),
        ("86 mmm", "length", "unknown unit 'mmm'"),
        ("nan", "length", "not a finite number"),
        ("inf kg", "mass", "not a finite number"),
        (float("nan"), "mass", "not a finite number"),
        ("1e300 m", "length", "out of range"),
        ("86 m**1000", "length", "absurd exponent"),
        (True, "length", "expected length"),
        ([1, 2], "length", "got a list"),
        ("eighty mm", "length", "cannot read"),
    ],
)
def test_bad_quantities(text, kind, message):
    with pytest.raises(UnitProblem, match=message.replace("*", r"\*")):
        parse_quantity(text, kind)


# --- units required, letter case, thousands separators: the rules and the command line ---


def _capitalisations(name: str) -> set[str]:
    letters = [i for i, c in enumerate(name) if c.isalpha()]
    out = set()
    for bits in itertools.product((str.lower, str.upper), repeat=len(letters)):
        chars = list(name)
        for i, case in zip(letters, bits, strict=True):
            chars[i] = case(chars[i])
        out.add("".join(chars))
    return out


def _same_kind_other_unit(name: str, other: str) -> bool:
    """Whether pint reads ``other`` as a unit of the same dimension as ``name``, but not
    the same unit."""
    ureg = registry()
    try:
        unit, candidate = ureg.parse_units(name), ureg.parse_units(other)
    except Exception:
        return False
    if unit.dimensionality != candidate.dimensionality:
        return False
    return ureg.Quantity(1, candidate).to(unit).magnitude != pytest.approx(1.0)


def test_units_read_without_pint_are_the_units_pint_reads(monkeypatch):
    """Every unit of the fast table (read without starting pint) has the value pint's reading
    gives it, to rounding.  The table holds the exact definitions (1 ft = 0.3048 m, 1 L =
    1e-3 m^3), where pint's own conversion is one or two units in the last place off for a
    few (0.30479999999999996 m); for J, kJ, N m/rad and the other units of the built-in
    layouts the two agree to the bit."""
    table = dict(units._FAST_UNITS)
    monkeypatch.setattr(units, "_FAST_UNITS", {})
    monkeypatch.setattr(units, "ANY_CASE", {})
    read_by_pint = units._from_text.__wrapped__  # the reading itself, not its cache
    for name, (kind, factor) in table.items():
        value, bare = read_by_pint(f"1 {name}", kind, "")
        assert not bare
        assert value == pytest.approx(factor, rel=4 * sys.float_info.epsilon, abs=0), name
    exact = ("J", "kJ", "MJ", "N m/rad", "N m/deg", "N m s/rad", "kg m^2", "mm", "bar", "rpm")
    for name in exact:
        assert read_by_pint(f"1 {name}", table[name][0], "")[0] == table[name][1], name


def test_any_case_names_follow_the_documented_rule():
    """A fast-table name is read in any letter case exactly when every word of it has two
    or more letters and no other capitalisation is another unit of the same kind."""
    for name in _FAST_UNITS:
        words = re.split(r"[ */·^]+", name)
        long_words = all(sum(c.isalpha() for c in w) >= 2 for w in words if w and w[0].isalpha())
        clash = [v for v in _capitalisations(name) if _same_kind_other_unit(name, v)]
        eligible = long_words and not clash and any(c.isalpha() for c in name)
        in_table = ANY_CASE.get(name.lower()) == name
        assert in_table == eligible, (name, clash)


def test_case_matters_names_two_units_of_one_kind():
    ureg = registry()
    for lower, (spellings, valid) in CASE_MATTERS.items():
        for spelling in spellings:
            assert spelling.lower() == lower
            ureg.parse_units(spelling)  # each reading is a unit pint knows
            assert f"'{spelling}'" in valid
        if len(spellings) == 2:
            assert _same_kind_other_unit(*spellings)


@pytest.mark.parametrize(
    ("text", "kind", "value"),
    [
        ("6000 RPM", "speed", 200 * math.pi),
        ("6000 Rpm", "speed", 200 * math.pi),
        ("0.6 KG", "mass", 0.6),
        ("2 BAR", "pressure", 2e5),
        ("90 DEG", "angle", 90.0),
        ("100 hz", "speed", 200 * math.pi),
    ],
)
def test_unit_names_in_another_case(text, kind, value):
    assert parse_quantity(text, kind) == pytest.approx(value, rel=1e-12)


@pytest.mark.parametrize(
    ("text", "kind", "message"),
    [
        ("86 MM", "length", "did you mean 'mm' (millimetres) or 'Mm' (megametres)?"),
        ("2 MPA", "pressure", "did you mean 'MPa' (megapascals) or 'mPa' (millipascals)?"),
        ("5 MG", "mass", "did you mean 'mg' (milligrams) or 'Mg' (megagrams)?"),
        ("450 G", "mass", "for grams write 'g' ('G' is the gauss)"),
    ],
)
def test_case_that_tells_units_apart_is_not_guessed(text, kind, message):
    with pytest.raises(UnitProblem, match="letter case matters here") as info:
        parse_quantity(text, kind)
    assert info.value.valid == message


@pytest.mark.parametrize(
    ("value", "kind", "proposal"),
    [
        (6000, "speed", "6000 rpm"),
        ("6000", "speed", "6000 rpm"),
        (360, "mass", "360 g"),
        (0.61, "mass", "0.61 kg"),
        (60, "length", "60 mm"),
        (0.086, "length", "0.086 m"),
        (19, "inertia", "19 kg cm^2"),
        (1.9e-3, "inertia", "0.0019 kg m^2"),
        (75, "pressure", "75 bar"),
        (100000, "pressure", "100000 Pa"),
        (2, "volume", "2 L"),
        (1998, "volume", "1998 cc"),
    ],
)
def test_a_bare_number_gets_the_unit_that_fits_it(value, kind, proposal):
    with pytest.raises(UnitProblem, match="has no unit") as info:
        parse_quantity(value, kind)
    assert info.value.suggestion == proposal
    assert info.value.valid == f"give a unit, e.g. '{proposal}'"


def test_bare_fraction_above_two_is_taken_for_a_percentage():
    assert parse_quantity(0.6, "fraction") == 0.6
    assert parse_quantity(2, "fraction") == 2.0
    with pytest.raises(UnitProblem, match=r"60 is read as a fraction \(6000 %\)") as info:
        parse_quantity(60, "fraction")
    assert info.value.suggestion == "60 %"


@pytest.mark.parametrize("text", ["13,000 rpm", "13 000 rpm", "13_000 rpm", "13'000rpm"])
def test_thousands_separators_are_named(text):
    with pytest.raises(UnitProblem, match="has a thousands separator") as info:
        parse_quantity(text, "speed")
    assert info.value.suggestion.replace(" ", "") == "13000rpm"


runner = CliRunner()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["analyse", "inline-4", "--speed", "6000"], "--speed: 6000 has no unit; give a unit, "
         "e.g. --speed 6000rpm"),
        (["propose", "inline-4", "--speed", "6000"], "e.g. --speed 6000rpm"),
        (["plot", "inline-4", "--speed", "6000"], "e.g. --speed 6000rpm"),
        (["report", "inline-4", "--speed", "6000", "-o", "r.html"], "e.g. --speed 6000rpm"),
        (["compare", "inline-4", "--speed", "6000"], "e.g. --speed 6000rpm"),
        (["propose", "inline-4", "--counterweight-radius", "55"],
         "--counterweight-radius: 55 has no unit; give a unit, e.g. --counterweight-radius 55mm"),
        (["compare", "inline-4", "--displacement", "2"], "e.g. --displacement 2L"),
        (["mounts", "inline-4-mounts", "--speed", "800:8000:3"], "e.g. --speed 800rpm"),
        (["sweep", "inline-4", "--vary", "conrod_length=130:160:3", "-o", "s.nc"],
         "--vary: conrod_length: 130 has no unit; give a unit, e.g. --vary conrod_length=130mm"),
        (["sweep", "inline-4", "--vary", "speed=1000rpm,7000", "-o", "s.nc"],
         "e.g. --vary speed=7000rpm"),
        (["tolerance", "inline-4", "--scatter", "reciprocating=±3"],
         "--scatter: reciprocating: 3 has no unit; give a unit, e.g. --scatter reciprocating=±3g"),
        (["tolerance", "inline-4", "--scatter", "stroke=±0.1"], "e.g. --scatter stroke=±0.1mm"),
        (["propose", "inline-4", "--balance-factor", "60"],
         "--balance-factor: 60 is read as a fraction (6000 %); a bare number is a fraction "
         "(0.5 = 50 %); did you mean 60%?"),
        (["analyse", "inline-4", "--speed", "13,000rpm"],
         "--speed: '13,000rpm' has a thousands separator; write the number without it, e.g. "
         "13000rpm"),
        (["sweep", "inline-4", "--vary", "speed=1,000rpm,2000rpm", "-o", "s.nc"],
         "'1,000rpm' has a thousands separator (a comma separates the values of a list); "
         "write 1000rpm"),
        (["analyse", "inline-4", "--speed", "6000 MM"], "did you mean 'mm' (millimetres) or "),
    ],
)  # fmt: skip
def test_cli_refuses_a_bare_dimensional_number_and_proposes_a_unit(tmp_path, args, message):
    args = [str(tmp_path / a) if a in {"r.html", "s.nc"} else a for a in args]
    result = runner.invoke(app, args)
    assert result.exit_code == 2, result.output
    assert result.stdout == ""
    assert result.stderr == f"balance: {result.stderr.removeprefix('balance: ')}"
    assert result.stderr.count("\n") == 1
    assert message in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_cli_accepts_a_bare_zero_and_bare_angles(tmp_path):
    path = tmp_path / "zero.yaml"
    path.write_text(
        "name: zero\nspeed: 6000 rpm\ngeometry: {stroke: 86 mm, conrod_length: 143 mm, "
        "offset: 0}\nmasses: {reciprocating: 0.6 kg, rotating: 0}\n"
        "cylinders: [{throw: 0, bank: 0, z: 0}, {throw: 180, bank: 0, z: 90 mm}]\n"
    )
    assert runner.invoke(app, ["analyse", str(path), "-f", "json"]).exit_code == 0


def test_cli_reads_rpm_in_any_case_as_rpm():
    lower = runner.invoke(app, ["analyse", "inline-4", "--speed", "7000rpm", "-f", "json"])
    upper = runner.invoke(app, ["analyse", "inline-4", "--speed", "7000 RPM", "-f", "json"])
    assert upper.exit_code == 0 and upper.stdout == lower.stdout
    assert json.loads(upper.stdout)["speed_rpm"] == pytest.approx(7000.0, rel=1e-12)


def test_cli_balance_factor_in_a_file_proposes_a_percentage(tmp_path):
    path = tmp_path / "factor.yaml"
    path.write_text(
        "name: factor\nspeed: 6000 rpm\ngeometry: {stroke: 86 mm, conrod_length: 143 mm}\n"
        "masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}\ncrank: {throws: [0]}\n"
        "balance: {balance_factor: 60}\n"
    )
    result = runner.invoke(app, ["propose", str(path)])
    assert result.exit_code == 2
    assert result.stderr == (
        f"balance: {path}:6:27: balance.balance_factor: 60 is read as a fraction (6000 %); "
        "a bare number is a fraction (0.5 = 50 %); did you mean '60 %'?\n"
    )
