"""Several crankshafts through the API: one crankshaft written in the new form is today's
engine bit for bit, a moved crankshaft adds exactly its moment about z to the roll, a
twin-crank twin balances its first order with counter-rotating cranks, the geared roll,
the mounts take the whole wrench, the proposal is on by default, and what is not in this
version is refused in one line
(docs/several-crankshafts.md)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from balance.api import analyse, compute_result, load_layout
from balance.core.errors import InputError
from balance.core.mount_loads import order_loads
from balance.views.json import to_dict
from tests.geared_engines import cylinders, twin_crank, with_crankshafts

MODELS = ["exact", "series", "textbook", "time"]


def _at_origin(engine):
    return with_crankshafts(engine, [0] * engine.n_cylinders, x=[0.0], y=[0.0])


def _moved(engine):
    return with_crankshafts(engine, [0] * engine.n_cylinders, x=[0.07], y=[-0.11])


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize(
    "name", ["single", "v-twin-45", "inline-4-gas", "v12-60-articulated", "single-mounts"]
)
def test_one_crankshaft_at_the_origin_is_todays_engine_bit_for_bit(name, model):
    engine = load_layout(name)
    settings = {"model": model}
    if name == "single-mounts":
        settings["mounts"] = True
    today = analyse(engine, **settings)
    written = analyse(_at_origin(engine), **settings)
    assert written.identical(today)


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("name", ["single", "v-twin-45", "inline-2-180"])
def test_a_moved_crankshaft_adds_exactly_its_moment_about_z_to_the_roll(name, model):
    engine = load_layout(name)
    today = compute_result(engine, model=model, proposal=False)
    moved = compute_result(_moved(engine), model=model, proposal=False)
    a, b = today.phasors, moved.phasors
    for field in ("force_forward", "force_backward", "moment_forward", "moment_backward"):
        np.testing.assert_array_equal(getattr(b, field), getattr(a, field))
    assert b.rotating_force == a.rotating_force
    part = moved.part("crankshafts")
    np.testing.assert_array_equal(part.force.roll[0], today.roll)  # its own roll
    np.testing.assert_array_equal(part.gear_couple, 0.0)
    free = a.free()
    p = -0.11 + 0.07j  # y + i x
    # y F_x - x F_y = Im(conj(p) F): per order Re(Z e^{ik theta}) with
    # Z = -i conj(p) P+ + i p conj(P-)
    expected_z = -1j * np.conj(p) * free.force_forward + 1j * p * np.conj(free.force_backward)
    scale = float(np.max(np.abs(expected_z)))
    assert scale > 100.0  # N m: the single's first order is several kN at 0.13 m
    np.testing.assert_allclose(part.moment_z, expected_z, rtol=0, atol=1e-14 * scale)
    np.testing.assert_allclose(moved.roll, today.roll + expected_z, rtol=0, atol=1e-14 * scale)


def test_a_counter_rotating_twin_crank_cancels_its_first_order():
    """Each crank counterweighted for its big end and 100 % of its reciprocating mass."""
    result = compute_result(twin_crank(-1.0), proposal=False)
    free = result.phasors.free()
    assert free.force_forward[0] == 0.0 and free.force_backward[0] == 0.0
    m_r_w2 = 0.6 * 0.043 * (6000 * math.pi / 30) ** 2
    # the second order is two singles' (nothing cancels it)
    np.testing.assert_allclose(
        abs(free.force_forward[1]), 2 * 0.5 * m_r_w2 * result.coefficients[0, 1].real, rtol=1e-12
    )


def test_a_co_rotating_twin_crank_keeps_m_r_w2_forward_and_backward():
    result = compute_result(twin_crank(1.0), proposal=False)
    free = result.phasors.free()
    m_r_w2 = 0.6 * 0.043 * (6000 * math.pi / 30) ** 2  # 10185.4 N
    np.testing.assert_allclose(abs(free.force_forward[0]), m_r_w2, rtol=1e-12)
    np.testing.assert_allclose(abs(free.force_backward[0]), m_r_w2, rtol=1e-12)
    assert result.phasors.rotating_force_backward == 0.0


@pytest.mark.parametrize("output", [1.0, -1.0])
@pytest.mark.parametrize("model", MODELS)
def test_the_geared_twin_crank_rolls_with_minus_its_torques(output, model):
    """Counter-rotating cranks mirror images of each other across the y axis (x = -g/2 and
    +g/2, throws 0, vertical bores, no offset, two-mass rods): their moment about z cancels
    and each crank's own roll is -sigma_s M_s, so the block receives -sigma_o (M_1 + M_2)."""
    engine = twin_crank(-1.0)
    engine = replace(engine, crankshafts=replace(engine.crankshafts, output_rotation=output))
    result = compute_result(engine, model=model, proposal=False)
    part = result.part("crankshafts")
    m1, m2 = part.torque
    scale = float(np.max(np.abs(m1)))
    assert scale > 100.0
    np.testing.assert_array_equal(part.moment_z, 0.0)
    np.testing.assert_allclose(result.roll, -output * (m1 + m2), rtol=0, atol=1e-13 * scale)
    # the gear couple: the counter-rotating crank's torque reaches the block with the
    # output's sign, (sigma_s - sigma_o) M_s
    np.testing.assert_allclose(
        part.gear_couple, (1.0 - output) * m1 + (-1.0 - output) * m2, atol=1e-13 * scale
    )


def test_a_counter_rotating_crank_puts_its_rotating_masses_backward():
    base = cylinders([0.0, 0.0], [0.0, 0.0], [0.0, 0.0])
    engine = with_crankshafts(
        base, [0, 1], x=[-0.05, 0.05], y=[0.0, 0.0], rotation=[1.0, -1.0], phase_deg=[0, 30.0]
    )
    p = compute_result(engine, proposal=False).phasors
    w2 = (6000 * math.pi / 30) ** 2
    # the second crank's pin is at phase - theta - throw = 30 deg - theta: backward at 30 deg
    np.testing.assert_allclose(
        p.rotating_force_backward, 0.4 * 0.043 * w2 * np.exp(1j * math.radians(30.0))
    )
    np.testing.assert_allclose(p.rotating_force, 0.4 * 0.043 * w2)


def test_the_cylinders_tdc_on_a_counter_rotating_crank():
    """TDC at theta = sigma (bank - phase) - throw: -(20 - 30) - 50 = -40 = 320 deg."""
    base = cylinders([0.0, 50.0], [0.0, 20.0], [0.0, 0.1])
    engine = with_crankshafts(
        base, [0, 1], x=[0.0, 0.3], y=[0.0, 0.0], rotation=[1.0, -1.0], phase_deg=[0, 30.0]
    )
    tdc = np.degrees(compute_result(engine, proposal=False).part("cylinders").tdc)
    np.testing.assert_allclose(tdc, [0.0, 320.0], atol=1e-9)


def test_the_mounts_take_the_whole_wrench():
    """The mounts read the roll with the moment about z (and the gear couple) and the
    backward rotating forces."""
    engine = load_layout("single-mounts")
    moved = _moved(engine)
    today = compute_result(engine, mounts=True, proposal=False)
    result = compute_result(moved, mounts=True, proposal=False)
    orders, _, _, _, _, roll = order_loads(result, False)
    part = result.part("crankshafts")
    at = np.searchsorted(orders, result.roll_orders)
    np.testing.assert_array_equal(roll[at], result.roll)
    assert np.max(np.abs(part.moment_z)) > 1000.0
    np.testing.assert_allclose(
        roll[at], today.roll + part.moment_z, atol=1e-12 * np.max(np.abs(part.moment_z))
    )
    # the mounts' response changes with it
    assert not np.allclose(
        result.part("mounts").response.force_amplitude,
        today.part("mounts").response.force_amplitude,
    )
    twin = compute_result(
        twin_crank(-1.0, counterweighted=False).with_section("mounts", engine.section("mounts")),
        mounts=True,
        proposal=False,
    )
    orders, _, fb, _, _, roll = order_loads(twin, False)
    free = twin.phasors.free()
    first = int(np.searchsorted(orders, 1))
    assert fb[first] == free.force_backward[0]
    assert twin.phasors.rotating_force_backward != 0.0
    # the roll they read holds the gear couple (the counter-rotating crank's -2 M_2)
    gear = twin.part("crankshafts").gear_couple
    assert np.max(np.abs(gear)) > 100.0
    np.testing.assert_array_equal(roll[np.searchsorted(orders, twin.roll_orders)], twin.roll)


def test_the_json_and_the_dataset_of_several_crankshafts():
    result = compute_result(twin_crank(-1.0), 3, proposal=False)
    data = to_dict(result)
    assert data["output_rotation"] == 1
    assert [s["name"] for s in data["crankshafts"]] == ["shaft1", "shaft2"]
    assert data["crankshafts"][1]["rotation"] == -1
    assert data["crankshafts"][1]["cylinders"] == [2]
    assert set(data["crankshafts"][0]) == {
        "name",
        "x_m",
        "y_m",
        "rotation",
        "phase_deg",
        "cylinders",
        "force",
        "roll",
        "torque",
    }
    assert data["cylinders"][1]["crankshaft"] == "shaft2"
    assert data["cylinders"][1]["opposed"] is None
    rot = data["rotating"]["force"]
    assert rot["backward"]["magnitude"] == pytest.approx(0.6 * 0.043 * (200 * math.pi) ** 2)
    assert rot["peak"] == pytest.approx(2 * rot["backward"]["magnitude"])
    assert [e["order"] for e in data["moment_z"]] == [1, 2, 3]
    assert [e["order"] for e in data["gear_couple"]] == [1, 2, 3]
    assert data["roll"][0]["amplitude"] == pytest.approx(data["gear_couple"][0]["amplitude"])
    ds = analyse(twin_crank(-1.0), 3, proposal=False)
    assert ds.sizes["crankshaft"] == 2
    assert list(ds["crankshaft"].values) == ["shaft1", "shaft2"]
    for name in ds.data_vars:
        if "crankshaft" in name or name.startswith(("moment_z", "gear_couple")):
            assert ds[name].attrs["units"] is not None and ds[name].attrs["long_name"]
    assert ds["crankshaft_force_peak"].dims == ("crankshaft", "order")
    assert ds["crankshaft_torque_amplitude"].dims == ("crankshaft", "roll_order")
    np.testing.assert_array_equal(ds["cylinder_crankshaft"].values, [1, 2])
    assert ds.attrs["output_rotation"] == 1


def test_the_table_and_csv_show_the_crankshafts():
    from balance.views.csv import to_csv
    from balance.views.fitted import NumberTable
    from balance.views.table import render

    result = compute_result(twin_crank(-1.0), 3, proposal=False)
    text = to_csv(result)
    header = text.splitlines()[0]
    assert "moment_z_amplitude [N m]" in header and "shaft2_torque_amplitude [N m]" in header
    titles = [t.title for t in render(result).renderables if isinstance(t, NumberTable)]
    assert any(title.startswith("Crankshafts: shaft1 at (-45, 0) mm same") for title in titles)
    forces = next(t for t in render(result).renderables if isinstance(t, NumberTable))
    rows = {row[0]: row for row in forces.rows}
    assert rows["1 rot."][3] == "1.019e+04"  # the counter-rotating crank's masses, backward
    assert rows["1 free"][1] == rows["1 free"][3] == "0"  # first order balanced


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        ({"speed_model": "dynamic"}, "speed_model: 'dynamic' is for one crankshaft; this"),
    ],
)
def test_what_is_not_in_this_version_is_refused_in_one_line(settings, message):
    with pytest.raises(InputError) as caught:
        compute_result(twin_crank(-1.0), **settings)
    text = str(caught.value)
    assert message in text
    assert "with several crankshafts is not in this version" in text or "is for one" in text
    assert "\n" not in text and "--" not in text


def test_gas_on_a_four_stroke_opposed_bore_is_refused_and_bearings_are_computed():
    gas = load_layout("inline-4-gas")
    opposed = with_crankshafts(gas, [0, 0, 1, 1], x=[0.0, 0.2], y=[0.0, 0.0])
    opposed = replace(
        opposed, crankshafts=replace(opposed.crankshafts, opposed=np.array([2, -1, 0, -1]))
    )
    # gas on opposed pistons is in (tests/test_opposed_gas.py), a four-stroke bore is not
    with pytest.raises(InputError, match="cycle: an opposed-piston bore with gas forces works"):
        compute_result(opposed, proposal=False)
    # bearing loads with several crankshafts are computed now, per shaft
    # (tests/test_geared_bearings.py): two pins and their mains on each of the two shafts
    plain = with_crankshafts(load_layout("inline-4"), [0, 0, 1, 1], x=[0.0, 0.2], y=[0.0, 0.0])
    loads = compute_result(plain, bearings=True, proposal=False).part("bearings").loads
    assert loads.pin_axis.tolist() == [0, 0, 1, 1]
    assert loads.axis_names == ("shaft1", "shaft2")


@pytest.mark.parametrize("sense", [1.0, -1.0])
@pytest.mark.parametrize("output", [1.0, -1.0])
def test_gas_torque_reaches_the_block_with_the_outputs_sign(sense, output):
    """The gas inline-4 (no offset, two-mass rods) on two cranks on one axis geared to one
    output: no part's angular momentum changes, so the block receives -sigma_o times the
    output's torque whichever way the second crank turns: today's roll with gas (half
    orders), times sigma_o.  Each shaft's mean torque is half today's."""
    engine = replace(load_layout("inline-4-gas"), conrod_inertia_correction=np.zeros(4))
    today = compute_result(engine, proposal=False)
    geared = with_crankshafts(
        engine, [0, 0, 1, 1], x=[0.0, 0.0], y=[0.0, 0.0], rotation=[1.0, sense], output=output
    )
    result = compute_result(geared, proposal=False)
    np.testing.assert_array_equal(result.roll_orders, today.roll_orders)
    scale = float(np.max(np.abs(today.roll)))
    assert scale > 500.0  # N m
    np.testing.assert_allclose(result.roll, output * today.roll, rtol=0, atol=1e-12 * scale)
    part = result.part("crankshafts")
    np.testing.assert_allclose(part.torque_mean, today.part("torque").mean / 2, rtol=1e-12)
    assert result.part("torque").mean == today.part("torque").mean
    np.testing.assert_allclose(
        np.mean(result.part("torque").roll_torque),
        -output * today.part("torque").mean,
        rtol=1e-9,
    )
    # the shafts' own rolls and the gear couple add up to it
    total = part.force.roll.sum(axis=0) + part.gear_couple
    np.testing.assert_allclose(total, result.roll, rtol=0, atol=1e-12 * scale)
    data = to_dict(result)
    assert data["crankshafts"][1]["torque_mean_Nm"] == pytest.approx(part.torque_mean[1])
    assert [e["order"] for e in data["crankshafts"][0]["torque"]][:2] == [0.5, 1]


def test_the_default_analysis_of_several_crankshafts_has_a_proposal():
    """The proposal is a default section for several crankshafts as for one
    (docs/several-crankshafts.md, "Proposals"); tests/test_geared_proposal.py checks it."""
    result = compute_result(twin_crank(-1.0))
    assert result.part("proposal") is not None
    assert result.part("crankshafts") is not None


GEARED_GAS = """\
name: two cranks with gas
speed: 3000 rpm
cycle: two-stroke
geometry: {stroke: 60 mm, conrod_length: 120 mm, bore: 56 mm}
masses: {reciprocating: 0.3 kg, rotating: 0.2 kg}
crankshafts:
  - {name: a, x: -100 mm}
  - {name: b, x: 100 mm, rotation: opposite, phase: 90 deg}
cylinders:
  - {crankshaft: a, throw: 0 deg, bank: 0 deg, z: 0 mm}
  - {crankshaft: b, throw: 0 deg, bank: 90 deg, z: 0 mm}
firing_order: [1, 2]
gas: {model: {compression_ratio: 9, peak_pressure: 50 bar}}
"""


def test_each_cylinder_fires_at_its_own_top_dead_centre_on_a_counter_rotating_shaft():
    """Cylinder 2's bore lies along its shaft's reference line (bank = phase = 90°), so it
    is at TDC at θ = σ(bank − phase) − throw = 0, like cylinder 1, not at bank − throw = 90°:
    the same cylinder on either shaft does the same work per cycle.  (Its firing placed from
    the raw throw gave shaft b a mean torque of 42.5 N m against shaft a's 31.2 N m.)"""
    from balance.io.layout_file import layout_from_text

    engine = layout_from_text(GEARED_GAS)
    np.testing.assert_array_equal(engine.gas.firing_tdc, [0.0, 0.0])
    data = to_dict(compute_result(engine))
    a, b = (shaft["torque_mean_Nm"] for shaft in data["crankshafts"])
    assert a == pytest.approx(31.18, rel=1e-3)
    assert b == pytest.approx(a, rel=1e-12)
