"""Gas forces, torque, roll with half orders and flywheel against independent references."""

from __future__ import annotations

import dataclasses
import json
import math
from functools import cache

import numpy as np
import pytest
from articulated_sim import Cylinder, Mechanism, dead_centres
from helpers import engine, image_compare
from oracles import crank_torque_newton_euler, crank_train_newton_euler

import balance
from balance.core import sampled as timedomain
from balance.core.analysis import compute, compute_phasors
from balance.core.gas import GasInput, cylinder_volume
from balance.core.kinematics import piston_position
from balance.core.result import Request
from balance.core.torque import compute_torque, layout_inertia
from balance.io.layout_file import builtin_layout_path
from balance.io.traces import read_pressure_trace
from balance.views import plots
from balance.views import torque as torque_views
from balance.views.json import to_dict

ORDERS = np.arange(1, 13)


@cache
def gas_layout():
    return balance.load_layout("inline-4-gas")


def _trace():
    path = builtin_layout_path("inline-4-gas").parent / "traces" / "petrol-na-full-load.csv"
    return read_pressure_trace(path, 720.0)


def _indicated_work_of_trace(layout) -> float:
    """Closed integral of p dV over the trace's own points (trapezoidal in V), all cylinders."""
    angle, pressure = _trace()
    area = math.pi / 4 * layout.gas.bore**2
    total = 0.0
    for i in range(layout.n_cylinders):
        s = piston_position(
            np.radians(angle), layout.crank_radius[i], layout.conrod_length[i], layout.offset[i]
        )
        volume = -area * s  # V = const - A s
        total += float(
            np.sum(0.5 * (pressure + np.roll(pressure, -1)) * (np.roll(volume, -1) - volume))
        )
    return total


def test_energy_mean_torque_equals_indicated_work():
    """Mean torque x 2 pi x 2 revolutions = closed integral of p dV of the trace, to 0.1 %."""
    layout = gas_layout()
    result = compute_torque(layout, ORDERS)
    work = _indicated_work_of_trace(layout)
    error = abs(result.mean * 4 * math.pi - work) / work
    assert error < 1e-3
    assert error < 2e-5  # measured 1.1e-5: trace linear in angle, integral in V


@pytest.mark.parametrize("step", [10.0, 30.0])
def test_seed_mean_tangential_force_check(step):
    """Mean tangential force against the mean indicated pressure, the classical check of a
    tangential force diagram (indicated work per cycle; derivation in docs/torque.md):
    p_i A 2 r z = T_mean A r 2 pi (z = 0.5 four-stroke) within 5 % (the acceptance band of
    engine-design course work for hand-integrated diagrams, our tolerance) with a tangential
    force table every 10 or 30 deg (trapezoidal rule, as done by hand), and within 0.1 % with
    the 0.25 deg integration."""
    layout = gas_layout()
    result = compute_torque(layout, ORDERS)
    r = float(layout.crank_radius[0])
    area = math.pi / 4 * layout.gas.bore**2
    p_i = _indicated_work_of_trace(layout) / layout.n_cylinders / (area * 2 * r)
    tdc = float(layout.gas.firing_tdc[0])
    alpha = np.mod(result.crank_angle - tdc, 720.0)
    tangential = result.tangential_force[0][np.argsort(alpha)] / area  # per unit area [Pa]
    fine = float(np.mean(tangential))
    left = p_i * 2 * r * 0.5
    assert abs(fine * r * 2 * math.pi - left) / left < 1e-3
    every = int(step * 4)
    table = np.append(tangential[::every], tangential[0])
    coarse = float(np.trapezoid(table) / (table.size - 1))
    assert abs(coarse * r * 2 * math.pi - left) / left < 0.05


def _even_four_stroke(throws, firing, bore=0.086):
    layout = engine(
        throws,
        firing_order=firing,
        geometry={"stroke": 0.086, "conrod_length": 0.143, "bore": bore, "offset": 0.0},
    )
    return layout


def _with_trace(layout, pressure_offset=None):
    angle, pressure = _trace()
    if pressure_offset is not None:
        pressure = np.full_like(pressure, pressure_offset)
    from balance.core.gas import firing_tdc

    tdc = firing_tdc(
        np.degrees(layout.throw), np.degrees(layout.bank), "four-stroke", layout.firing_order, None
    )
    assert not isinstance(tdc, str)
    gas = GasInput(
        angle=angle,
        pressure=pressure,
        model=None,
        crankcase_pressure=1e5,
        bore=0.086,
        firing_tdc=tdc,
        cycle_deg=720.0,
    )
    return dataclasses.replace(layout, gas=gas)


def test_inline6_gas_roll_only_in_multiples_of_three():
    layout = _with_trace(engine([0, 240, 120, 120, 240, 0], firing_order=[1, 5, 3, 6, 2, 4]))
    result = compute_torque(layout, ORDERS)
    for k, value in zip(result.roll_orders, result.roll, strict=True):
        if k % 3 == 0:
            assert abs(value) > 1.0
        else:
            assert value == 0.0, k


def test_inline4_gas_roll_only_in_even_orders():
    layout = _with_trace(engine([0, 180, 180, 0], firing_order=[1, 3, 4, 2]))
    result = compute_torque(layout, ORDERS)
    for k, value in zip(result.roll_orders, result.roll, strict=True):
        if k % 2 == 0:
            assert abs(value) > 1.0
        else:
            assert value == 0.0, k


@pytest.mark.parametrize("name", ["inline-4-gas", "v8-crossplane-gas"])
def test_inertia_only_roll_equals_the_core_roll(name):
    """Pressure equal to the crankcase pressure: no gas force, the roll is the core's (half
    orders zero), to 1e-9 of m r^2 w^2."""
    layout = balance.load_layout(name)
    assert layout.gas is not None
    flat = dataclasses.replace(
        layout.gas,
        angle=np.arange(0.0, 720.0, 5.0),
        pressure=np.full(144, 1e5),
        model=None,
        crankcase_pressure=1e5,
    )
    result = compute_torque(dataclasses.replace(layout, gas=flat), ORDERS)
    core = compute_phasors(layout, ORDERS).phasors.roll
    scale = float(np.max(layout.reciprocating_mass * layout.crank_radius**2) * layout.speed**2)
    integer = np.isclose(result.roll_orders, np.round(result.roll_orders))
    np.testing.assert_allclose(result.roll[integer], core, rtol=0, atol=1e-9 * scale)
    assert np.all(np.abs(result.roll[~integer]) <= 1e-9 * scale)
    assert abs(result.mean) <= 1e-9 * scale


def _assert_forces_equal_newton_euler(layout, result, every: int = 1) -> None:
    """Engine torque (two rod splits), side thrust, rod force and each throw's tangential and
    radial force against the Newton-Euler solution of the rigid rods, to 1e-9 of the
    largest value, on every ``every``-th angle of the cycle grid."""
    pick = slice(None, None, every)
    theta = np.radians(result.crank_angle[pick])
    gas = result.gas_force[:, pick].T
    scale = float(np.max(np.abs(result.engine_torque)))
    for share, cg in ((1.0 / 3.0, 0.3), (0.4, 0.25)):
        torque = crank_torque_newton_euler(
            layout, theta, gas_force=gas, small_end_share=share, cg_fraction=cg
        )
        assert np.max(np.abs(torque - result.engine_torque[pick])) <= 1e-9 * scale
    # the rod force is the one between a massless rod of inertia Delta I and the whole
    # reciprocating mass: small-end share 0
    rigid = crank_train_newton_euler(layout, theta, gas, small_end_share=0.0)
    for got, want in ((rigid.wall, result.side_thrust), (rigid.rod_force, result.rod_force)):
        assert np.max(np.abs(got.T - want[:, pick])) <= 1e-9 * np.max(np.abs(want))
    # tangential and radial force: summed over the rods on one crank pin (a link rod's is
    # what it passes through its master rod); the rod's big-end share turns with the pin
    rigid = crank_train_newton_euler(layout, theta, gas, 1.0 / 3.0, 0.3)
    masters = np.arange(layout.n_cylinders) if layout.links is None else layout.links.masters
    for m in masters.tolist():
        on_pin = [m] if layout.links is None else [m, *np.flatnonzero(layout.links.master == m)]
        outwards = np.exp(1j * (theta + layout.throw[m]))
        force = rigid.pin_force[:, m] * np.conj(outwards)
        small = layout.reciprocating_mass[m] / 3.0
        big_end = (small / 0.3 - small) * layout.crank_radius[m] * layout.speed**2
        for got, name in (
            (force.imag, "tangential_force"),
            (-force.real + big_end, "radial_force"),
        ):
            want = getattr(result, name)[on_pin][:, pick].sum(axis=0)
            assert np.max(np.abs(got - want)) <= 1e-9 * np.max(np.abs(want)), (m, name)


@pytest.mark.parametrize("name", ["inline-4-gas", "v8-crossplane-gas"])
def test_roll_and_torque_against_newton_euler_with_gas(name):
    """Newton-Euler of piston and rigid rod (its real inertia, Delta I != 0) with the gas
    force on piston and head: the block torque equals the roll; the torque on the crank the
    engine torque, for two splits of the rod; N, S, T and K per cylinder; to 1e-9."""
    layout = balance.load_layout(name)
    assert np.all(layout.conrod_inertia_correction != 0.0)
    result = compute_torque(layout, ORDERS)
    theta = np.radians(result.crank_angle)
    roll = timedomain.roll_newton_euler(layout, theta, gas_force=result.gas_force.T)
    scale = float(np.max(np.abs(result.roll_torque)))
    assert np.max(np.abs(roll - result.roll_torque)) <= 1e-9 * scale
    _assert_forces_equal_newton_euler(layout, result, every=4)


def test_rod_inertia_is_in_the_engine_torque():
    """The rod's inertia beyond its two-mass model adds -Delta I w^2 gamma' gamma'' per
    cylinder: nothing to the mean, to the inline-4-gas's second-order torque swing about
    n Delta I w^2 lambda^2 / 2 (gamma' gamma'' ~ -lambda^2 sin(2 beta) / 2, within 2 %), which the
    two-mass torque would miss."""
    layout = gas_layout()
    two_mass = dataclasses.replace(layout, conrod_inertia_correction=np.zeros(layout.n_cylinders))
    exact, lumped = compute_torque(layout, ORDERS), compute_torque(two_mass, ORDERS)
    assert exact.mean == pytest.approx(lumped.mean, rel=1e-12)
    lam = float(layout.crank_radius[0] / layout.conrod_length[0])
    estimate = 4 * abs(layout.conrod_inertia_correction[0]) * layout.speed**2 * lam**2 / 2
    difference = exact.engine_torque - lumped.engine_torque
    assert 0.98 * estimate < np.max(np.abs(difference)) < 1.02 * estimate


def _offset_layout(offset: str, **extra):
    """An inline-4 with offset bores, rods with their own inertia and the K20 trace."""
    trace = builtin_layout_path("inline-4-gas").parent / "traces" / "petrol-na-full-load.csv"
    return engine(
        [0, 180, 180, 0],
        firing_order=[1, 3, 4, 2],
        geometry={"stroke": 0.086, "conrod_length": 0.143, "offset": offset},
        masses={
            "piston_group": "0.42 kg",
            "conrod": "0.50 kg",
            "conrod_cg_to_big_end": "37 mm",
            "conrod_inertia": "1.6e-3 kg m^2",
        },
        gas={"pressure_trace": str(trace), "crankcase_pressure": "1 bar", "bore": "86 mm"},
        **extra,
    )


def test_offset_engine_torque_is_exact_against_newton_euler():
    """Offset 4 mm and the rods' own inertia: engine torque, N, S, T, K against Newton-Euler
    to 1e-9; and without Delta I the tangential force is the textbook
    T = P sin(beta + psi) / cos(psi) (Kolchin and Demidov 1984), offset included."""
    layout = _offset_layout("4 mm")
    assert np.all(layout.conrod_inertia_correction != 0.0)
    result = compute_torque(layout, ORDERS)
    _assert_forces_equal_newton_euler(layout, result, every=4)
    lumped = compute_torque(
        dataclasses.replace(layout, conrod_inertia_correction=np.zeros(4)), ORDERS
    )
    beta = np.radians(np.mod(lumped.crank_angle, 360.0))
    r, rod, e = 0.043, 0.143, 0.004
    psi = np.arcsin((r * np.sin(beta) - e) / rod)
    seed = lumped.piston_force[0] * np.sin(beta + psi) / np.cos(psi)
    np.testing.assert_allclose(lumped.tangential_force[0], seed, atol=1e-9 * np.abs(seed).max())
    np.testing.assert_allclose(lumped.side_thrust[0], lumped.piston_force[0] * np.tan(psi),
                               atol=1e-9 * np.abs(seed).max())  # fmt: skip


def _actual_tdc(layout) -> np.ndarray:
    """Each cylinder's actual TDC crank angle [rad] by the independent simulation of
    ``tests/articulated_sim.py`` (dense sampling and Newton on the piston's distance)."""
    cylinders = [
        Cylinder(float(layout.throw[i]), float(layout.bank[i]), 0.0, 0.4, 0.5, 0.04, 1e-3,
                 float(layout.conrod_length[i]), float(layout.offset[i]))
        for i in range(layout.n_cylinders)
    ]  # fmt: skip
    _, tdc = dead_centres(Mechanism(float(layout.crank_radius[0]), 3000.0, cylinders))
    return tdc


def test_an_offset_cylinder_fires_at_its_actual_top_dead_centre(tmp_path):
    """A desaxe single (offset putting its actual TDC 3.75 deg after the nominal one, on the
    0.25 deg grid) with a trace symmetric about its firing TDC: the trace's peak falls where
    the piston is farthest from the crank axis, and the firing TDC is the independent
    simulation's TDC; the parametric model's volume is smallest at cycle angle 0."""
    r, rod = 0.043, 0.143
    offset = (rod + r) * math.sin(math.radians(3.75))
    alpha = np.arange(-360.0, 360.0, 0.5)
    trace = tmp_path / "symmetric.csv"
    pressure = 1e5 + 60e5 * np.exp(-((alpha / 30.0) ** 2))
    trace.write_text(
        "".join(f"{a!r},{q!r}\n" for a, q in zip(alpha.tolist(), pressure.tolist(), strict=True))
    )
    layout = engine(
        [0],
        firing_order=[1],
        geometry={"stroke": 2 * r, "conrod_length": rod, "offset": offset},
        gas={"pressure_trace": str(trace), "crankcase_pressure": "1 bar", "bore": "86 mm"},
    )
    (tdc,) = np.degrees(_actual_tdc(layout))
    (fired,) = layout.gas.firing_tdc
    assert abs(fired - tdc) < 1e-9 and abs(fired - 3.75) < 1e-9
    result = compute_torque(layout, ORDERS)
    peak = int(np.argmax(result.pressure[0]))
    s = piston_position(np.radians(result.crank_angle), r, rod, offset)
    assert peak == int(np.argmax(s)) and result.crank_angle[peak] == 3.75
    assert result.pressure[0, peak] == pytest.approx(61e5, rel=1e-12)
    volume = cylinder_volume(np.array([-0.01, 0.0, 0.01]), 0.086, r, rod, offset, 10.0)
    clearance = math.sqrt((rod + r) ** 2 - offset**2) - math.sqrt((rod - r) ** 2 - offset**2)
    clearance *= math.pi / 4 * 0.086**2 / 9.0
    assert volume[1] < volume[0] and volume[1] < volume[2]
    assert volume[1] == pytest.approx(clearance, rel=1e-12)


def test_energy_mean_torque_equals_indicated_work_with_offset():
    """Offset 4 mm: mean torque x 4 pi = closed integral of p dV of the trace with each
    cylinder's volume counted from its actual TDC (the independent simulation's), to
    2e-5 (measured 1.0e-5; counted from the nominal TDC it would be 5.1 % off)."""
    layout = _offset_layout("4 mm")
    result = compute_torque(layout, ORDERS)
    angle, pressure = _trace()
    area = math.pi / 4 * 0.086**2
    top = _actual_tdc(layout) + layout.throw - layout.bank  # beta of the actual TDC
    np.testing.assert_allclose(
        np.radians(result.firing_tdc) % (2 * np.pi), _actual_tdc(layout), atol=1e-9
    )
    work = 0.0
    for i in range(layout.n_cylinders):
        volume = -area * piston_position(np.radians(angle) + top[i], 0.043, 0.143, 0.004)
        work += float(
            np.sum(0.5 * (pressure + np.roll(pressure, -1)) * (np.roll(volume, -1) - volume))
        )
    assert abs(result.mean * 4 * math.pi - work) / work < 2e-5


def test_flywheel_inertia_and_speed_fluctuation_are_inverse():
    layout = gas_layout()
    result = compute_torque(layout, ORDERS)
    w2 = layout.speed**2
    # J: the flywheel's 0.12 kg m^2 and the layout's moving masses' cycle mean
    total = 0.12 + layout_inertia(layout, result.crank_angle)
    assert 0.005 < total - 0.12 < 0.01  # a four's pistons and rods: about 6 % of it
    assert result.speed_fluctuation == pytest.approx(result.excess_work / (total * w2), rel=1e-12)
    sized = dataclasses.replace(
        layout,
        gas=dataclasses.replace(
            layout.gas, flywheel_inertia=None, speed_fluctuation=result.speed_fluctuation
        ),
    )
    assert compute_torque(sized, ORDERS).flywheel_inertia == pytest.approx(0.12, rel=1e-12)
    # the excess work is the largest swing of the integral of M - M_mean
    theta = np.radians(result.crank_angle)
    energy = np.cumsum(result.engine_torque - result.mean) * (theta[1] - theta[0])
    assert np.ptp(energy) == pytest.approx(result.excess_work, rel=1e-3)


def test_json_torque_and_half_order_roll():
    data = to_dict(compute(gas_layout(), Request()))
    assert set(data["torque"]) == {
        "mean_Nm",
        "max_Nm",
        "min_Nm",
        "speed_fluctuation",
        "flywheel_inertia_kgm2",
    }
    assert data["torque"]["flywheel_inertia_kgm2"] == 0.12
    orders = [entry["order"] for entry in data["roll"]]
    assert orders[:4] == [0.5, 1, 1.5, 2] and orders[-1] == 8
    json.dumps(data, allow_nan=False)
    assert "torque" not in to_dict(compute(balance.load_layout("inline-4"), Request()))


def test_without_gas_the_analysis_is_unchanged():
    layout = balance.load_layout("inline-4")
    ds = balance.analyse(layout)
    assert "crank_angle" not in ds.dims and "engine_torque" not in ds
    assert list(ds["roll_order"].values) == list(range(1, 9))


def test_dataset_variables_have_units_and_long_names():
    ds = balance.analyse(gas_layout())
    for name in (
        "gas_force",
        "piston_force",
        "side_thrust",
        "rod_force",
        "tangential_force",
        "radial_force",
        "cylinder_torque",
        "engine_torque",
        "torque_mean",
    ):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]
    assert ds["gas_force"].dims == ("cylinder", "crank_angle")
    assert ds.sizes["crank_angle"] == 2880


def test_gas_plots_without_gas_draw_only_a_note():
    result = compute(balance.load_layout("inline-4"), Request())
    for function in (torque_views.plot_torque, torque_views.plot_forces):
        fig = function(result)
        assert not fig.axes[0].lines


@image_compare
def test_image_torque():
    return torque_views.plot_torque(compute(gas_layout(), Request()))


@image_compare
def test_image_forces():
    return torque_views.plot_forces(compute(gas_layout(), Request()))


@image_compare
def test_image_roll_half_orders():
    return plots.plot_roll(compute(balance.load_layout("v8-crossplane-gas"), Request()))


def test_the_torque_views_read_the_indicated_work_from_the_catalogue():
    """views/torque prints the catalogue's ``indicated_work`` (catalogue.value), the mean
    torque times the cycle angle; a name the result lacks is a KeyError."""
    from balance.core.catalogue import value
    from balance.core.torque import indicated_work

    result = compute(gas_layout(), Request())
    assert value(result, "indicated_work") == indicated_work(result.part("torque"))
    assert to_dict(result)["gas"]["indicated_work_J"] == indicated_work(result.part("torque"))
    with pytest.raises(KeyError, match="mount_force_max"):
        value(result, "mount_force_max")
