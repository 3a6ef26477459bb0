"""Units at the boundary, including pint's rpm."""

from __future__ import annotations

import math

import pytest

from balance.io.units import UnitProblem, parse_quantity, registry


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
