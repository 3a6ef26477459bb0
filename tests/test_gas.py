"""Gas input: the pressure trace, the parametric model, firing TDCs and every bad input."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import balance
from balance.core.errors import LayoutError
from balance.core.gas import (
    GasModel,
    cylinder_pressure,
    model_pressure,
    periodic_tables,
    piston_gas_force,
    pressure_tables,
)
from balance.io.layout_file import layout_from_text, load_layout

BASE = """name: test
speed: 3000 rpm
geometry: {stroke: 86 mm, conrod_length: 143 mm, bore: 86 mm}
masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}
crank: {throws: [0, 180, 180, 0], spacing: 90 mm}
"""


def _write(tmp_path: Path, text: str, trace: str | None = None) -> Path:
    if trace is not None:
        (tmp_path / "cyl.csv").write_text(trace)
    path = tmp_path / "engine.yaml"
    path.write_text(text)
    return path


def _trace(rows: int = 720, start: float = -360.0, step: float = 1.0) -> str:
    angles = start + step * np.arange(rows)
    return "crank_angle [deg],pressure [bar]\n" + "".join(
        f"{a:g},{1.0 + 40.0 * np.exp(-(((a - 10.0) / 30.0) ** 2)):.6f}\n" for a in angles
    )


def error_of(tmp_path, text, trace=None) -> str:
    with pytest.raises(LayoutError) as info:
        load_layout(_write(tmp_path, text, trace))
    return str(info.value)


GAS = "firing_order: [1, 3, 4, 2]\ngas: {pressure_trace: cyl.csv}\n"


def test_trace_is_read_relative_to_the_layout(tmp_path):
    layout = load_layout(_write(tmp_path, BASE + GAS, _trace()))
    assert layout.gas is not None
    assert layout.gas.pressure is not None and layout.gas.pressure.max() == pytest.approx(41e5)
    assert list(layout.gas.firing_tdc) == [0.0, 540.0, 180.0, 360.0]


def test_missing_trace_file(tmp_path):
    err = error_of(tmp_path, BASE + GAS)
    assert "engine.yaml:7" in err and "gas.pressure_trace: no such file" in err


@pytest.mark.parametrize(
    ("trace", "expected"),
    [
        ("0,1e5\n-1,1e5\n", "cyl.csv:2: gas.pressure_trace: crank angle -1 deg does not increase"),
        ("0,1e5\n1,-3\n", "cyl.csv:2: gas.pressure_trace: pressure -3 Pa is negative"),
        ("0,1e5,3\n", "cyl.csv:1: gas.pressure_trace: 3 columns"),
        ("0,1e5\n1,abc\n", "cyl.csv:2: gas.pressure_trace: cannot read '1,abc' as two numbers"),
        (_trace(rows=300), "does not cover the 720 deg cycle: a gap of 421 deg after -61 deg"),
        (_trace(rows=800), "the trace spans 799 deg, more than the 720 deg cycle"),
        ("a,p [psi]\n", "gas.pressure_trace: 0 data rows"),
        ("a,p [kg]\n0,1\n", "cyl.csv:1: gas.pressure_trace: '1 kg' is a mass, not a pressure"),
    ],
)
def test_bad_traces_name_file_line_and_field(tmp_path, trace, expected):
    assert expected in error_of(tmp_path, BASE + GAS, trace)


def test_both_ends_of_the_cycle_may_be_given(tmp_path):
    layout = load_layout(_write(tmp_path, BASE + GAS, _trace(rows=721)))
    assert layout.gas is not None and layout.gas.angle is not None
    assert layout.gas.angle.size == 720


def test_four_stroke_needs_a_firing_order(tmp_path):
    err = error_of(tmp_path, BASE + "gas: {pressure_trace: cyl.csv}\n", _trace())
    assert "firing_order: a four-stroke with gas forces needs the firing order" in err


def test_tdc_angles_place_the_cycles_without_a_firing_order():
    text = """name: twin
speed: 3000 rpm
geometry: {stroke: 86 mm, conrod_length: 143 mm, bore: 86 mm}
masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}
cylinders:
  - {tdc: 0 deg, z: 0 mm}
  - {tdc: 540 deg, z: 90 mm}
gas: {model: {compression_ratio: 10, peak_pressure: 60 bar}}
"""
    layout = layout_from_text(text)
    assert layout.gas is not None
    assert list(layout.gas.firing_tdc) == [0.0, 540.0]


def test_tdc_angles_with_offsets_fire_at_the_actual_top_dead_centre():
    """A given ``tdc`` is the nominal TDC (it defines the throw); with an offset the cylinder
    fires where rod and crank are in line, arcsin(e / (l + r)) later (earlier for a negative
    offset), in the revolution that ``tdc`` names."""
    text = """name: twin
speed: 3000 rpm
geometry: {stroke: 86 mm, conrod_length: 143 mm, bore: 86 mm}
masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}
cylinders:
  - {tdc: 0 deg, z: 0 mm, offset: 5 mm}
  - {tdc: 540 deg, z: 90 mm, offset: -5 mm}
gas: {model: {compression_ratio: 10, peak_pressure: 60 bar}}
"""
    layout = layout_from_text(text)
    assert layout.gas is not None
    lag = math.degrees(math.asin(0.005 / (0.143 + 0.043)))
    np.testing.assert_allclose(layout.gas.firing_tdc, [lag, 540.0 - lag], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.cos(layout.throw), [1.0, -1.0], rtol=0, atol=1e-12)


def test_firing_order_that_does_not_fit_a_cycle(tmp_path):
    text = BASE.replace("[0, 180, 180, 0]", "[0, 180, 180, 0]") + (
        "firing_order: [1, 2, 3, 4]\ngas: {pressure_trace: cyl.csv}\n"
    )
    err = error_of(tmp_path, text, _trace())
    assert "firing order 1-2-3-4 does not fit in one 720 deg cycle" in err


@pytest.mark.parametrize(
    ("section", "expected"),
    [
        ("gas: {model: {compression_ratio: 10}}", "give exactly one of heat_released and peak"),
        ("gas: {model: {compression_ratio: 0.5, peak_pressure: 60 bar}}", "compression_ratio is"),
        ("gas: {model: {compression_ratio: 10, heat_released: 2 kg}}", "cannot read '2 kg'"),
        (
            "gas: {model: {compression_ratio: 10, heat_released: '1,600 J'}}",
            "'1,600 J' has a thousands separator",
        ),
        (
            "gas: {model: {compression_ratio: 10, peak_pressure: 60 bar, "
            "combustion_start: 150 deg}}",
            "combustion_start is 150 deg",
        ),
        ("gas: {pressure_trace: a.csv, crankcase_pressure: -1 bar}", "crankcase_pressure is"),
        (
            "gas: {model: {compression_ratio: 10, peak_pressure: 60 bar}}\nflywheel: {}",
            "flywheel: give exactly one of inertia and speed_fluctuation",
        ),
        (
            "gas: {model: {compression_ratio: 10, peak_pressure: 60 bar}}\n"
            "flywheel: {speed_fluctuation: 150 %}",
            "flywheel.speed_fluctuation: speed_fluctuation is 1.5",
        ),
        (
            "flywheel: {speed_fluctuation: 1 %}",
            "flywheel: a speed fluctuation to size the flywheel for needs a 'gas' section",
        ),
        ("gas: {model: {compression_ratio: 10, peak_pressure: 60 bar}, bore: 8 kg}", "a mass"),
    ],
)
def test_bad_gas_and_flywheel_sections(section, expected):
    with pytest.raises(LayoutError) as info:
        layout_from_text(BASE + "firing_order: [1, 3, 4, 2]\n" + section + "\n")
    assert expected in str(info.value)


@pytest.mark.parametrize("text", ["1.6 kJ", "1.6 KJ", "1.6kJ", "1600 J", "0.0016 MJ"])
def test_heat_released_in_any_unit_of_energy(text):
    """The heat released in J, kJ (in any letter case: docs/layout-format.md) or MJ, read
    without pint, is 1600 J (0.0016 MJ to rounding)."""
    section = f"gas: {{model: {{compression_ratio: 10, heat_released: {text}}}}}\n"
    engine = layout_from_text(BASE + "firing_order: [1, 3, 4, 2]\n" + section)
    assert engine.gas is not None and engine.gas.model is not None
    assert engine.gas.model.heat_released == pytest.approx(1600.0, rel=1e-15)


def test_bore_is_needed():
    text = BASE.replace(", bore: 86 mm", "") + (
        "firing_order: [1, 3, 4, 2]\ngas: {model: {compression_ratio: 10, peak_pressure: 6 MPa}}\n"
    )
    with pytest.raises(LayoutError, match="gas: missing 'bore'"):
        layout_from_text(text)


def test_model_reaches_the_peak_pressure_and_the_polytropes():
    spec = GasModel(compression_ratio=10.0, peak_pressure=60e5, polytropic_compression=1.35)
    angle, pressure = model_pressure(spec, 0.086, 0.043, 0.143, 0.0, "four-stroke")
    assert pressure.max() == pytest.approx(60e5, rel=1e-9)
    assert 0.0 < angle[np.argmax(pressure)] < 40.0
    # compression: p V^n constant from BDC to the start of combustion
    from balance.core.gas import cylinder_volume

    volume = cylinder_volume(angle, 0.086, 0.043, 0.143, 0.0, 10.0)
    closed = (angle >= -180.0) & (angle < spec.combustion_start)
    pvn = pressure[closed] * volume[closed] ** 1.35
    assert np.ptp(pvn) <= 1e-12 * pvn.max()
    assert volume.max() / volume.min() == pytest.approx(10.0, rel=1e-12)
    assert np.all(pressure[angle < -180.0] == spec.intake_pressure)
    assert np.all(pressure[angle > 180.0] == spec.exhaust_pressure)


def test_builtin_gas_layouts_are_listed_and_load():
    names = balance.builtin_layout_names()
    assert "inline-4-gas" in names and "v8-crossplane-gas" in names
    assert load_layout("inline-4-gas").gas is not None
    assert load_layout("inline-4").gas is None


@pytest.mark.parametrize("name", ["inline-4-gas", "v8-crossplane-gas"])
def test_cylinder_pressure_and_gas_force_are_np_interp_and_p_minus_p0_times_a(name):
    """The one gas force: each cylinder's pressure at the crank angles (its tables prepared
    once by periodic_tables) has the bits of np.interp with the cycle as period at
    alpha = theta - theta_TDC (mod the cycle), and the force is (p - p0) pi B^2/4
    (Kolchin and Demidov 1984: P_g = (p_g - p_0) F_p)."""
    engine = load_layout(name)
    gas = engine.gas
    tables = pressure_tables(
        gas, engine.crank_radius, engine.conrod_length, engine.offset, engine.cycle
    )
    theta = np.linspace(-30.0, 750.0, 1001)
    pressure = cylinder_pressure(gas, periodic_tables(tables, gas.cycle_deg), theta)
    for i, (angle, p) in enumerate(tables):
        alpha = np.mod(theta - gas.firing_tdc[i], gas.cycle_deg)
        want = np.interp(alpha, angle, p, period=gas.cycle_deg)
        np.testing.assert_array_equal(pressure[i], want)
    area = math.pi / 4.0 * gas.bore**2
    force = piston_gas_force(pressure, gas)
    np.testing.assert_array_equal(force, (pressure - gas.crankcase_pressure) * area)


def test_periodic_tables_keep_each_table_its_own():
    """Each cylinder's prepared table is its own: with 2000 tables, a key folded from the two
    arrays' ids into one int (id(angle) ^ id(pressure) << 1) gave some tables another's
    (a cylinder then took another's pressures, as memory addresses fell)."""
    from balance.core.gas import periodic_tables

    tables = [(np.array([0.0, 90.0, 180.0]), np.array([1.0, 2.0, 3.0]) * i) for i in range(2000)]
    prepared = periodic_tables(tables, 720.0)
    for i, (xp, fp) in enumerate(prepared):
        np.testing.assert_array_equal(xp, [-540.0, 0.0, 90.0, 180.0, 720.0])
        np.testing.assert_array_equal(fp, np.array([3.0, 1.0, 2.0, 3.0, 1.0]) * i)
