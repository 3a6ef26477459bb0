"""Master and link rods on engines with several crankshafts (docs/several-crankshafts.md,
"Articulated rods"): each crankshaft's quantities are those of its cylinders analysed alone
as a one-crank layout, a counter-rotating shaft's those of its mirror image across the
frame's y axis, in every rung; bearings, gas, the proposal and sweeps take them; a link rod
across shafts or in an opposed bore stays refused.  The brute force of
tests/test_geared_brute_force.py checks the physics itself."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from typer.testing import CliRunner

from balance.api import analyse, compute_result, load_layout
from balance.cli import app
from balance.core.engine import Links
from balance.core.errors import InputError
from balance.io.layout_file import layout_from_text
from tests.geared_engines import cylinders, with_crankshafts

MODELS = ["exact", "series", "textbook", "time"]
runner = CliRunner()

HEAD = """\
name: {name}
speed: 1800 rpm
cycle: two-stroke
geometry: {{bore: 150 mm, stroke: 180 mm, conrod_length: 320 mm}}
masses: {{piston_group: 3.6 kg, conrod: 6.0 kg, conrod_cg_to_big_end: 90 mm,
         conrod_inertia: 0.08 kg m^2, crank_unbalance: 2.0 kg}}
reference_z: 200 mm
"""
LINK = "conrod: 3.0 kg, conrod_cg_to_big_end: 100 mm, conrod_inertia: 0.02 kg m^2"


def shaft_a(m1: int, m2: int, key: str = "") -> str:
    """Shaft a's cylinders (crankshaft 1): a V-twin pair of throws, link rods with the V-2's
    pin angle; ``m1``, ``m2`` the numbers of their masters."""
    out = ""
    for throw, z, master in ((0.0, 0.0, m1), (180.0, 170.0, m2)):
        out += (
            f"  - {{{key}throw: {throw!r} deg, bank: -30 deg, z: {z!r} mm}}\n"
            f"  - {{{key}throw: {throw!r} deg, bank: 30 deg, z: {z!r} mm, offset: 3 mm, {LINK},\n"
            f"     link: {{master: {master}, pin_radius: 62 mm, pin_angle: 70.17 deg, "
            "length: 258 mm}}\n"
        )
    return out


def _shaft_b(sign: float, shift: float, key: str, m1: int, m2: int) -> str:
    """Shaft b's master and link cylinders; ``sign`` -1 and ``shift`` its phase give the
    mirror image across the y axis (banks and pin angles negated, throws less the phase)."""
    out = ""
    for throw, z, master in ((90.0, 0.0, m1), (270.0, 170.0, m2)):
        t = throw - shift
        out += (
            f"  - {{{key}throw: {t!r} deg, bank: {sign * 20.0!r} deg, z: {z!r} mm, offset: 2 mm}}\n"
            f"  - {{{key}throw: {t!r} deg, bank: {sign * 80.0!r} deg, z: {z!r} mm, "
            f"offset: -4 mm, {LINK},\n"
            f"     link: {{master: {master}, pin_radius: 60 mm, pin_angle: {sign * 55.0!r} deg, "
            "length: 250 mm}}\n"
        )
    return out


def geared_text(rotation: str = "opposite", phase: float = 25.0, gas: bool = False) -> str:
    """Shaft a at the origin; shaft b displaced, turning ``rotation``, with ``phase``."""
    text = HEAD.format(name="two link-rod shafts")
    text += (
        "crankshafts:\n  - {name: a}\n"
        f"  - {{name: b, x: 400 mm, y: -50 mm, rotation: {rotation}, phase: {phase!r} deg}}\n"
        "cylinders:\n"
    )
    text += shaft_a(1, 3) + _shaft_b(1.0, 0.0, "crankshaft: b, ", 5, 7)
    if gas:
        text += "firing_order: [1, 2, 5, 6, 3, 4, 7, 8]\n"
        text += "gas: {model: {compression_ratio: 15, peak_pressure: 80 bar}}\n"
    return text


def shaft_a_alone() -> str:
    return HEAD.format(name="shaft a alone") + "cylinders:\n" + shaft_a(1, 3)


def shaft_b_mirrored(phase: float = 25.0) -> str:
    """Shaft b's cylinders mirrored across the frame's y axis: a forward one-crank layout."""
    return HEAD.format(name="shaft b mirrored") + "cylinders:\n" + _shaft_b(-1.0, phase, "", 1, 3)


def _close(actual, expected, scale, rel=1e-12):
    np.testing.assert_allclose(np.asarray(actual), np.asarray(expected), rtol=0, atol=rel * scale)


@pytest.mark.parametrize("model", MODELS)
def test_the_shaft_at_the_origin_is_its_cylinders_alone_bit_for_bit(model):
    """Shaft a (crankshaft 1: at the origin, phase 0, forward) carries two master-and-link
    sets: its force, moment and own roll are those of its four cylinders analysed alone as
    a one-crank layout, bit for bit, in every rung; so are their acceleration coefficients,
    strokes and dead centres."""
    geared = compute_result(layout_from_text(geared_text()), model=model, proposal=False)
    alone = compute_result(layout_from_text(shaft_a_alone()), model=model, proposal=False)
    part, p = geared.part("crankshafts"), alone.phasors
    for name in ("force_forward", "force_backward", "moment_forward", "moment_backward"):
        np.testing.assert_array_equal(getattr(part.force, name)[0], getattr(p, name))
    np.testing.assert_array_equal(part.force.rotating_force[0], p.rotating_force)
    np.testing.assert_array_equal(part.force.roll[0], p.roll)
    assert np.max(np.abs(p.force_forward)) > 100.0  # N: the link rods' own orders
    np.testing.assert_array_equal(geared.coefficients[:4], alone.coefficients)
    cyl, one = geared.part("cylinders"), alone.part("cylinders")
    np.testing.assert_array_equal(cyl.stroke[:4], one.stroke)
    np.testing.assert_array_equal(cyl.tdc[:4], one.tdc)
    assert geared.model.error_bound >= alone.model.error_bound


@pytest.mark.parametrize("model", MODELS)
def test_a_counter_rotating_shaft_with_link_rods_is_its_mirror_image(model):
    """Shaft b turns against crankshaft 1 with a phase of 25 deg: its force is the mirror
    image across the y axis (F -> conj F: forward and backward swap and conjugate) of the
    forward one-crank layout with its banks and link-pin angles negated and its throws less
    the phase, its own roll that layout's with the sign of its sense; its cylinders' strokes
    and dead centres are that layout's."""
    geared = compute_result(layout_from_text(geared_text()), model=model, proposal=False)
    mirror = compute_result(layout_from_text(shaft_b_mirrored()), model=model, proposal=False)
    part, p = geared.part("crankshafts"), mirror.phasors
    scale = float(np.max(np.abs(p.force_forward)))
    assert scale > 100.0
    _close(part.force.force_forward[1], np.conj(p.force_backward), scale)
    _close(part.force.force_backward[1], np.conj(p.force_forward), scale)
    _close(part.force.moment_forward[1], np.conj(p.moment_backward), scale)
    _close(part.force.moment_backward[1], np.conj(p.moment_forward), scale)
    _close(part.force.rotating_force_backward[1], np.conj(p.rotating_force), scale)
    assert part.force.rotating_force[1] == 0.0
    roll_scale = float(np.max(np.abs(p.roll)))
    _close(part.force.roll[1], -p.roll, roll_scale)
    _close(geared.coefficients[4:], mirror.coefficients, 1.0)
    cyl, one = geared.part("cylinders"), mirror.part("cylinders")
    _close(cyl.stroke[4:], one.stroke, 0.18)
    turn = np.angle(np.exp(1j * (cyl.tdc[4:] - one.tdc)))
    _close(turn, 0.0, 1.0)
    # the sign of the link-pin angle matters: the same shaft without the mirror differs
    assert np.max(np.abs(part.force.force_forward[1] - p.force_forward)) > 1e3 * 1e-12 * scale


def test_the_shafts_torque_is_the_same_cylinders_on_crankshaft_one():
    """A shaft's torque in its own sense does not change with the mirror: shaft b's is that
    of its mirror image put on crankshaft 1 (with shaft a as shaft 2)."""
    engine = layout_from_text(geared_text())
    swapped = layout_from_text(
        HEAD.format(name="swapped")
        + "crankshafts:\n  - {name: b}\n  - {name: a, x: -400 mm, y: 50 mm}\n"
        + "cylinders:\n"
        + _shaft_b(-1.0, 25.0, "", 1, 3)
        + shaft_a(5, 7, "crankshaft: a, ")
    )
    m_b = compute_result(engine, proposal=False).part("crankshafts").torque[1]
    m_mirror = compute_result(swapped, proposal=False).part("crankshafts").torque[0]
    scale = float(np.max(np.abs(m_b)))
    assert scale > 100.0  # N m
    _close(m_b, m_mirror, scale)


def test_the_bearings_of_each_shaft_are_its_one_crank_engines():
    """Crank-pin loads with link rods hung on their masters: shaft a's are its cylinders'
    alone; shaft b's are its mirror image's mirrored back (F -> conj F)."""
    geared = compute_result(layout_from_text(geared_text()), bearings=True, proposal=False)
    loads = geared.part("bearings").loads
    alone = compute_result(layout_from_text(shaft_a_alone()), bearings=True, proposal=False)
    mirror = compute_result(layout_from_text(shaft_b_mirrored()), bearings=True, proposal=False)
    a, b = alone.part("bearings").loads, mirror.part("bearings").loads
    assert loads.pin_axis.tolist() == [0, 0, 1, 1]
    assert loads.pin_cylinders == ((1, 2), (3, 4), (5, 6), (7, 8))
    np.testing.assert_array_equal(loads.pin_load[:2], a.pin_load)
    scale = float(np.max(np.abs(b.pin_load)))
    _close(loads.pin_load[2:], np.conj(b.pin_load), scale)


def test_gas_on_link_rods_of_a_counter_rotating_shaft():
    """Shaft b is the mirror image of shaft a (phase 0, turning against it): with gas each
    of its cylinders fires at its own top dead centre, and the two shafts' torques in their
    own senses are the same."""
    text = geared_text(phase=0.0, gas=True)
    mirrored = text.replace(_shaft_b(1.0, 0.0, "crankshaft: b, ", 5, 7), "")
    for throw, z, master in ((0.0, 0.0, 5), (180.0, 170.0, 7)):
        mirrored = mirrored.replace(
            "firing_order",
            f"  - {{crankshaft: b, throw: {throw!r} deg, bank: 30 deg, z: {z!r} mm}}\n"
            f"  - {{crankshaft: b, throw: {throw!r} deg, bank: -30 deg, z: {z!r} mm, "
            f"offset: 3 mm, {LINK},\n"
            f"     link: {{master: {master}, pin_radius: 62 mm, pin_angle: -70.17 deg, "
            "length: 258 mm}}\nfiring_order",
            1,
        )
    engine = layout_from_text(mirrored)
    tdc = engine.gas.firing_tdc
    np.testing.assert_allclose(np.mod(tdc[4:] - tdc[:4] + 180.0, 360.0) - 180.0, 0.0, atol=1e-9)
    assert abs(tdc[1] - 30.0) > 0.5  # deg: the link piston's dead centre is its own
    result = compute_result(engine, proposal=False)
    part = result.part("crankshafts")
    scale = float(np.max(np.abs(part.torque[0])))
    assert scale > 1e3  # N m
    _close(part.torque[1], part.torque[0], scale, 1e-9)
    assert part.torque_mean[0] > 1e3
    assert part.torque_mean[1] == pytest.approx(part.torque_mean[0], rel=1e-9)


def test_the_proposal_cancels_the_whole_first_order_link_pins_included():
    """The default proposal: counterweights on each shaft, turning with it, cancel the
    engine's first-order force and moment, the link pins' relative motion included."""
    result = compute_result(layout_from_text(geared_text()), model="exact")
    residual = result.part("proposal").residual
    free = result.phasors.free()
    scale = float(np.max(np.abs(free.force_forward)))
    assert scale > 1e3
    for name in ("force_forward", "force_backward", "moment_forward", "moment_backward"):
        assert abs(getattr(residual, name)[0]) < 1e-9 * scale, name


def test_a_sweep_point_is_the_hand_edited_file_bit_for_bit(tmp_path):
    import xarray as xr

    base = tmp_path / "links.yaml"
    base.write_text(geared_text(), encoding="utf-8")
    out = tmp_path / "s.nc"
    got = runner.invoke(
        app, ["sweep", str(base), "--vary", "crankshafts.b.phase=0,60", "-o", str(out)]
    )
    assert got.exit_code == 0, got.output
    edited = tmp_path / "edited.yaml"
    edited.write_text(geared_text(phase=60.0), encoding="utf-8")
    reference = analyse(load_layout(edited), "1-8", proposal=False)
    with xr.open_dataset(out) as ds:
        dim = ds.reciprocating_force_magnitude.dims[0]
        point = ds.isel({dim: 1}).load()
    for name in point.data_vars:
        a, b = point[name].values, reference[name].values
        assert np.array_equal(a, b), (name, np.max(np.abs(a - b)))


def test_a_link_rod_on_another_shafts_master_is_refused_in_the_core_too():
    """The layout reader refuses it with file and line
    (tests/test_several_crankshafts_layout.py); an engine built in Python gets one line."""
    base = cylinders([0.0, 0.0], [-30.0, 30.0], [0.0, 0.0])
    base = replace(
        base,
        links=Links(
            master=np.array([-1, 0], dtype=np.intp),
            pin_radius=np.array([0.0, 0.03]),
            pin_angle=np.radians([0.0, 60.0]),
        ),
    )
    engine = with_crankshafts(base, [0, 1], x=[0.0, 0.2], y=[0.0, 0.0], rotation=[1.0, -1.0])
    with pytest.raises(InputError) as caught:
        compute_result(engine, proposal=False)
    text = str(caught.value)
    assert "link cylinder 2 hangs on a master rod of another crankshaft" in text
    assert "\n" not in text


def test_layout_expand_writes_each_link_cylinders_own_dead_centre(tmp_path):
    """The expanded file's comments give each cylinder's stroke and TDC as the analysis
    does, on a counter-rotating shaft too (its shaft's sense, its mirror image's link pins)."""
    path = tmp_path / "links.yaml"
    path.write_text(geared_text(), encoding="utf-8")
    got = runner.invoke(app, ["layout", "expand", str(path)])
    assert got.exit_code == 0, got.output
    tdc = np.degrees(compute_result(load_layout(path), proposal=False).part("cylinders").tdc)
    lines = [line for line in got.output.splitlines() if line.startswith("#   cylinder ")]
    written = [float(line.split("TDC at ")[1].split(" deg")[0]) for line in lines]
    np.testing.assert_allclose(written, tdc, rtol=1e-5)
    assert "link rod on cylinder 5's rod" in lines[5]


RADIAL_ROW = """\
  - throws: [0]
    spacing: 100 mm
    banks: [{banks}]
    link: {{master: 1, pin_radius: 50 mm, length: 200 mm, conrod: 0.7 kg,
            conrod_cg_to_big_end: 70 mm}}
"""
RADIAL_HEAD = """\
name: radial rows
speed: 2000 rpm
geometry: {stroke: 120 mm, conrod_length: 250 mm}
masses: {piston_group: 1.0 kg, conrod: 2.5 kg, conrod_cg_to_big_end: 60 mm,
         crank_unbalance: 0.5 kg}
reference_z: 100 mm
"""
FRONT = RADIAL_ROW.format(banks="0 deg, 72 deg, 144 deg, 216 deg, 288 deg")
REAR = RADIAL_ROW.format(banks="36 deg, 108 deg, 180 deg, 252 deg, 324 deg")


@pytest.mark.parametrize("model", MODELS)
def test_a_two_row_radial_on_two_crankshafts_in_the_compact_form(model):
    """Two five-cylinder radial rows, each a block of the compact form with its master and
    four link rods, on two crankshafts (the rear one counter-rotating): the front row's
    quantities are the one-row radial's bit for bit, and each link rod hangs on its own
    row's master (cylinder 6 for the rear row)."""
    two = layout_from_text(
        RADIAL_HEAD
        + "crankshafts:\n  - {name: front}\n"
        + "  - {name: rear, x: 300 mm, rotation: opposite, phase: 20 deg}\n"
        + "crank:\n"
        + FRONT.replace("  - throws", "  - crankshaft: front\n    throws")
        + REAR.replace("  - throws", "  - crankshaft: rear\n    z0: 200 mm\n    throws")
    )
    assert two.links.master.tolist() == [-1, 0, 0, 0, 0, -1, 5, 5, 5, 5]
    one = layout_from_text(RADIAL_HEAD + "crank:\n" + FRONT)
    geared = compute_result(two, model=model, proposal=False)
    alone = compute_result(one, model=model, proposal=False)
    part, p = geared.part("crankshafts"), alone.phasors
    for name in ("force_forward", "force_backward", "moment_forward", "moment_backward"):
        np.testing.assert_array_equal(getattr(part.force, name)[0], getattr(p, name))
    np.testing.assert_array_equal(part.force.roll[0], p.roll)
    # a radial row's link rods leave a second order that plain rods would not
    assert abs(p.force_forward[1]) > 5.0  # N
