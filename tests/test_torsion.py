"""The ``torsion`` section: the train's checks and warnings, the analysis, its outputs and
its views (docs/torsion.md).  The validation against published results is in
test_torsion_validation.py."""

from __future__ import annotations

import functools
import json
import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from torsion_trains import analysed, chain, inline4_train, v8_train, with_train

from balance.core import torsion_excitation as tx
from balance.core import torsion_response as td
from balance.core.analysis import compute
from balance.core.errors import InputError
from balance.core.result import Request
from balance.core.torsion import (
    OUTPUTS,
    Shaft,
    TorsionDamper,
    TorsionMass,
    TorsionTrain,
    resolve_mass,
    torsion_analysis,
    torsion_part,
    torsion_warnings,
    train_problems,
)
from balance.core.torsion_train import WARNING_RULES
from balance.io.layout_file import load_layout

# --------------------------------------------------------------------------- checks


def _fields(train, engine=None, tdc=None):
    return [p.field for p in train_problems(train, engine, tdc)]


def test_a_good_train_has_no_problems():
    engine = load_layout("inline-4-gas")
    assert train_problems(inline4_train(), engine) == ()


def test_every_refusal_names_its_field():
    engine = load_layout("inline-4-gas")
    good = inline4_train()
    m = list(good.masses)

    def with_mass(i, **changes):
        masses = list(m)
        masses[i] = replace(masses[i], **changes)
        return replace(good, masses=tuple(masses))

    cases = [
        (replace(good, masses=m[:1]), "torsion.masses"),
        (with_mass(1, name="pulley"), "torsion.masses[2].name"),
        (with_mass(0, inertia=0.0), "torsion.masses[1].inertia"),
        (with_mass(2, crank_inertia=-1.0), "torsion.masses[3].crank_inertia"),
        (with_mass(0, crank_inertia=0.1), "torsion.masses[1]"),
        (with_mass(2, crank_inertia=None), "torsion.masses[3]"),
        (with_mass(0, inertia=None, crank_inertia=0.01), "torsion.masses[1].crank_inertia"),
        (with_mass(1, shaft=None), "torsion.masses[2]"),
        (with_mass(7, shaft=Shaft(1e4)), "torsion.masses[8].shaft"),
        (with_mass(1, shaft=Shaft(0.0)), "torsion.masses[2].shaft.stiffness"),
        (with_mass(1, shaft=Shaft(1e6, -1.0)), "torsion.masses[2].shaft.damping"),
        (with_mass(1, damping=-0.1), "torsion.masses[2].damping"),
        (with_mass(1, shaft=Shaft(1e6, 0.0, 0.04, 0.04)), "torsion.masses[2].shaft.bore"),
        (with_mass(1, shaft=Shaft(1e6, 0.0, -0.04)), "torsion.masses[2].shaft.diameter"),
        (with_mass(3, cylinders=(1,)), "torsion.masses[4].cylinders"),
        (with_mass(3, cylinders=(9,)), "torsion.masses[4].cylinders"),
        (with_mass(3, cylinders=(2, 2)), "torsion.masses[4].cylinders"),
        (replace(good, loss_factor=-0.01), "torsion.loss_factor"),
        (replace(good, dampers=(TorsionDamper(9, 0.01, 1e4, 1.0),)), "torsion.dampers[1].at"),
        (replace(good, dampers=(TorsionDamper(1, 0.0, 1e4, 1.0),)), "torsion.dampers[1].inertia"),
        (replace(good, dampers=(TorsionDamper(1, 0.01, 0.0, 0.0),)), "torsion.dampers[1]"),
        (
            replace(good, dampers=(TorsionDamper(1, 0.01, -1.0, 1.0),)),
            "torsion.dampers[1].stiffness",
        ),
    ]
    for train, field in cases:
        assert field in _fields(train, engine), (field, _fields(train, engine))
    # a cylinder on no mass
    no_four = with_mass(5, cylinders=())
    problems = train_problems(no_four, engine)
    assert any("cylinder 4 on no mass" in p.message for p in problems)
    # the paths locate the values in the file (0-based list indices)
    stiffness = train_problems(with_mass(1, shaft=Shaft(0.0)), engine)[0]
    assert stiffness.path == ("torsion", "masses", 1, "shaft", "stiffness")
    assert "zero would split the train in two" in stiffness.message


def test_crank_inertia_needs_masses_by_part():
    from helpers import engine as compact

    lumped = compact([0, 180, 180, 0], firing_order=[1, 3, 4, 2])  # lumped masses
    assert lumped.mass_parts is None
    found = train_problems(inline4_train(), lumped)
    assert {p.field for p in found} == {f"torsion.masses[{i}].crank_inertia" for i in (3, 4, 5, 6)}
    assert "crank's own unbalance" in found[0].message


def test_four_stroke_firing_tdcs_must_be_placed():
    engine = replace(load_layout("inline-6"), firing_order=None)
    train = _throw_train(6)
    found = train_problems(train, engine)
    assert [p.field for p in found] == ["firing_order"]
    assert "torsion section" in found[0].message
    # every cylinder's tdc given (the reader passes them): placed
    tdc = [0.0, 480.0, 240.0, 600.0, 120.0, 360.0]
    assert train_problems(train, engine, tdc) == ()
    placed = tx.place_firing_tdc(engine, tdc)
    np.testing.assert_allclose(placed, tdc)


def test_resolve_mass_by_number_or_name():
    masses = inline4_train().masses
    assert resolve_mass(masses, 1) == 1
    assert resolve_mass(masses, "flywheel") == 7
    assert resolve_mass(masses, "clutch") is None
    assert resolve_mass(masses, 9) is None


def _throw_train(n: int, **changes) -> TorsionTrain:
    masses = [TorsionMass("pulley", inertia=0.004, shaft=Shaft(1e6, 0.5))]
    masses += [
        TorsionMass(f"throw {c}", crank_inertia=0.003, cylinders=(c,), shaft=Shaft(8e5, 0.5, 0.05))
        for c in range(1, n + 1)
    ]
    masses.append(TorsionMass("flywheel", inertia=0.12, damping=1.0))
    return replace(TorsionTrain(tuple(masses)), **changes)


# --------------------------------------------------------------------------- warnings


def test_warnings():
    engine = load_layout("inline-4-gas")
    assert torsion_warnings(engine, inline4_train()) == ()
    undamped = TorsionTrain(
        tuple(
            replace(
                m, damping=0.0, shaft=None if m.shaft is None else replace(m.shaft, damping=0.0)
            )
            for m in inline4_train().masses
        ),
        (TorsionDamper(1, 0.01, 7e4, 0.0),),
    )
    rules = [w.rule for w in torsion_warnings(engine, undamped)]
    assert rules == ["torsion_damping"]
    # cylinders on the wrong masses: 1, 3, 2, 4 along the table
    masses = list(inline4_train().masses)
    masses[3], masses[4] = (
        replace(masses[3], cylinders=(3,)),
        replace(masses[4], cylinders=(2,)),
    )
    swapped = replace(inline4_train(), masses=tuple(masses))
    assert [w.rule for w in torsion_warnings(engine, swapped)] == ["torsion_order"]
    # written from the driven end
    reversed_train = replace(
        inline4_train(),
        masses=(
            TorsionMass("vehicle", inertia=0.5, shaft=Shaft(8000.0, 4.0)),
            *inline4_train().masses[1:-1],
            replace(inline4_train().masses[-1], inertia=0.0035),
        ),
    )
    assert "torsion_free_end" in [w.rule for w in torsion_warnings(engine, reversed_train)]
    lossy = inline4_train(loss_factor=0.3)
    assert [w.rule for w in torsion_warnings(engine, lossy)] == ["torsion_loss_factor"]
    detuned = inline4_train(dampers=(TorsionDamper(1, 0.010, 7.0e8, 8.0),))
    found = torsion_warnings(engine, detuned)
    assert [w.rule for w in found] == ["torsion_tuning"]
    assert found[0].field == "torsion.dampers[1]"
    assert set(WARNING_RULES) >= {w.rule for w in found}


# --------------------------------------------------------------------------- the analysis


def test_section_part_defaults():
    engine = with_train("inline-4-gas", inline4_train())
    result = analysed(engine)
    t = result.part("torsion")
    assert t.speeds.size == 200
    np.testing.assert_allclose(t.speeds[[0, -1]], [0.2 * engine.speed, 1.2 * engine.speed])
    np.testing.assert_allclose(t.orders, np.arange(1, 25) / 2)
    assert t.free_end.shape == (24, 200)
    assert t.section_torque.shape == (7, 24, 200)
    assert t.damper_power.shape == (1, 24, 200)
    one = analysed(engine, speeds="analysis").part("torsion")
    np.testing.assert_allclose(one.speeds, [engine.speed])
    # without speeds the part is at the analysis speed alone (balance analyse --torsion)
    bare = torsion_part(engine, Request(), compute(engine, Request())).part("torsion")
    np.testing.assert_allclose(bare.speeds, [engine.speed])
    # the warnings join the result's
    assert result.warnings == ()


def test_section_refusals():
    engine = load_layout("inline-4-gas")
    with pytest.raises(InputError, match="no torsion: section"):
        analysed(engine)
    engine = with_train(engine, inline4_train())
    with pytest.raises(InputError, match=r"not a multiple of 0\.5"):
        analysed(engine, orders=[0.25])
    with pytest.raises(InputError, match="above zero"):
        analysed(engine, speeds=[0.0, 100.0])
    two_stroke = with_train(
        replace(load_layout("inline-4-gas"), cycle="two-stroke", gas=None), inline4_train()
    )
    with pytest.raises(InputError, match="whole orders only"):
        analysed(two_stroke, orders=[1.5])
    bad = with_train(load_layout("inline-4-gas"), inline4_train(loss_factor=-1.0))
    with pytest.raises(InputError, match=r"torsion\.loss_factor"):
        analysed(bad)


def test_order_and_speed_checks():
    assert tx.order_problem([0.5, 1, 12], "four-stroke") is None
    assert "whole orders" in tx.order_problem([0.5], "two-stroke")
    assert "multiple of 0.5" in tx.order_problem([1.25], "four-stroke")
    assert "twice" in tx.order_problem([1, 1], "four-stroke")
    assert tx.order_problem([], "four-stroke").startswith("no orders")
    assert tx.speed_problem([10.0]) is None
    assert tx.speed_problem([-1.0]) is not None
    np.testing.assert_allclose(tx.default_orders("two-stroke"), np.arange(1, 13))


def test_inertia_only_half_orders_are_zero():
    engine = with_train("inline-6", _throw_train(6))
    t = analysed(engine, speeds=[300.0, 600.0]).part("torsion")
    half = t.orders != np.round(t.orders)
    assert t.excitation.gas is None and t.excitation.tangential_pressure is None
    assert np.all(t.excitation.inertia[:, half] == 0)
    assert np.all(t.free_end[half] == 0)
    assert np.all(np.abs(t.excitation.inertia[:, ~half][:, :4]) > 0)
    # the inertia excitation scales with the speed squared: so does the response
    np.testing.assert_allclose(np.abs(t.section_torque).sum() > 0, True)


def test_excitation_phases_add_up_to_the_engine_torque():
    """Cylinder c's order k in the crank angle is its own, lagged by k theta_c: the sum over
    the cylinders is the order k of the engine torque (balance.core.torque)."""
    engine = load_layout("v8-crossplane-gas")
    orders = tx.default_orders(engine.cycle)
    exc = tx.excitation(engine, orders, engine.gas.firing_tdc)
    from balance.core.torque import compute_torque

    torque = compute_torque(engine, np.arange(1, 9))
    n = torque.engine_torque.size
    spectrum = 2 * np.fft.rfft(torque.engine_torque)[tx.harmonic_numbers(orders, engine.cycle)] / n
    total = exc.at_crank([engine.speed])[0].sum(axis=1)
    np.testing.assert_allclose(total, spectrum, atol=1e-9 * np.max(np.abs(spectrum)))
    # same trace, same geometry: every cylinder's own spectrum is the same
    np.testing.assert_allclose(exc.gas, np.broadcast_to(exc.gas[:1], exc.gas.shape), atol=1e-9)
    # the tangential pressure is the gas amplitude per piston area and crank radius
    area = engine.gas.piston_area
    np.testing.assert_allclose(
        exc.tangential_pressure * area * engine.crank_radius[0], np.abs(exc.gas)
    )


def test_undamped_train_gives_modes_but_no_response():
    train = _throw_train(6)
    bare = replace(
        train,
        masses=tuple(
            replace(
                m, damping=0.0, shaft=None if m.shaft is None else replace(m.shaft, damping=0.0)
            )
            for m in train.masses
        ),
    )
    engine = with_train("inline-6", bare)
    result = analysed(engine, speeds=[200.0, 700.0])
    t = result.part("torsion")
    assert not t.damped and t.free_end is None and t.section_stress is None
    assert t.frequencies.size == 7 and t.resonances
    assert all(r.free_end is None for r in t.resonances)
    assert [w.rule for w in result.warnings] == ["torsion_damping"]
    from balance.views import torsion as views

    doc = views.torsion_document(result)
    assert doc["response"] is None
    json.dumps(doc, allow_nan=False)
    assert views.torsion_csv(result).splitlines()[1].endswith(",")


def test_resonance_response_is_that_speed_s():
    engine = with_train("inline-4-gas", inline4_train())
    t = analysed(engine).part("torsion")
    assert t.resonances
    speeds = sorted(r.speed for r in t.resonances)
    assert [r.speed for r in t.resonances] == speeds
    r = max(t.resonances, key=lambda r: r.vector_sum)
    at = analysed(engine, speeds=[r.speed]).part("torsion")
    i = int(np.flatnonzero(at.orders == r.order)[0])
    np.testing.assert_allclose(np.abs(at.free_end[i, 0]), r.free_end, rtol=1e-12)
    torques = np.abs(at.section_torque[:, i, 0])
    assert r.section == int(np.argmax(torques)) + 1
    np.testing.assert_allclose(torques.max(), r.section_torque, rtol=1e-12)
    freq = t.frequencies[r.mode - 1]
    np.testing.assert_allclose(r.speed * r.order, 2 * math.pi * freq, rtol=1e-12)


def test_stress_is_the_nominal_shear_stress():
    engine = with_train("inline-4-gas", inline4_train())
    t = analysed(engine, speeds=[500.0]).part("torsion")
    shaft = t.train.sections[2]  # 50 mm with an 18 mm bore
    d, di = shaft.diameter, shaft.bore
    expected = 16 * np.abs(t.section_torque[2]) * d / (math.pi * (d**4 - di**4))
    np.testing.assert_allclose(t.section_stress[2], expected, rtol=1e-14)
    assert np.all(np.isnan(t.section_stress[6]))  # the clutch: no diameter


# --------------------------------------------------------------------------- properties


_inertia = st.floats(1e-3, 1.0)
_stiffness = st.floats(1e3, 1e7)


@given(st.lists(_inertia, min_size=2, max_size=8), st.data())
def test_reversed_numbering_changes_nothing_physical(inertias, data):
    """A train written from the other end has the same frequencies, and its masses' and
    sections' amplitudes in reverse order (a section's torque changes sign, not size)."""
    n = len(inertias)
    k = data.draw(st.lists(_stiffness, min_size=n - 1, max_size=n - 1))
    c_abs = data.draw(st.lists(st.floats(0.01, 2.0), min_size=n, max_size=n))
    m = td.assemble(inertias, k, [0.1] * (n - 1), c_abs, loss_factor=0.01)
    r = td.assemble(inertias[::-1], k[::-1], [0.1] * (n - 1), c_abs[::-1], loss_factor=0.01)
    f1, _ = td.normal_modes(m)
    f2, _ = td.normal_modes(r)
    np.testing.assert_allclose(f1**2, f2**2, rtol=1e-9, atol=1e-12 * float(np.max(f1**2)))
    w = np.array([50.0, 400.0, 3000.0])
    force = np.ones((3, n), dtype=complex) * np.exp(1j * np.arange(n))
    q = td.harmonic_response(m, w, force)
    qr = td.harmonic_response(r, w, force[:, ::-1])
    np.testing.assert_allclose(np.abs(q), np.abs(qr[:, ::-1]), rtol=1e-8, atol=1e-14)


@given(st.lists(_inertia, min_size=2, max_size=7), st.floats(0.01, 100.0), st.data())
def test_scaling_inertias_and_stiffnesses_keeps_the_frequencies(inertias, scale, data):
    """K phi = w^2 M phi: scaling M and K alike changes no frequency and no shape; scaling
    the damping and the excitation too changes no response."""
    n = len(inertias)
    k = np.array(data.draw(st.lists(_stiffness, min_size=n - 1, max_size=n - 1)))
    j = np.array(inertias)
    c = np.full(n - 1, 0.3)
    m1 = td.assemble(j, k, c, np.full(n, 0.1), [0], [0.002], [5e3], [1.0])
    m2 = td.assemble(
        scale * j,
        scale * k,
        scale * c,
        scale * np.full(n, 0.1),
        [0],
        [scale * 0.002],
        [scale * 5e3],
        [scale * 1.0],
    )
    f1, s1 = td.normal_modes(m1)
    f2, s2 = td.normal_modes(m2)
    # eigenvalues are accurate to rounding of the largest: compare w^2 on that scale
    np.testing.assert_allclose(f1**2, f2**2, rtol=1e-9, atol=1e-12 * float(np.max(f1**2)))
    well_apart = np.min(np.diff(f1)) > 1e-3 * np.max(f1)
    if well_apart:
        np.testing.assert_allclose(s1, s2, rtol=1e-5, atol=1e-5 * float(np.max(np.abs(s1))))
    w = np.array([10.0, 300.0])
    force = np.ones((2, m1.size), dtype=complex)
    force[:, m1.rings] = 0
    np.testing.assert_allclose(
        td.harmonic_response(m1, w, force),
        td.harmonic_response(m2, w, scale * force),
        rtol=1e-8,
        atol=1e-15,
    )


@given(st.lists(_inertia, min_size=2, max_size=8), st.data())
def test_modes_are_orthogonal_and_solve_the_eigenproblem(inertias, data):
    n = len(inertias)
    k = data.draw(st.lists(_stiffness, min_size=n - 1, max_size=n - 1))
    m = td.assemble(inertias, k, [0.0] * (n - 1), [0.0] * n, [0], [0.003], [2e4], [0.0])
    freq, shape = td.normal_modes(m)
    assert freq.size == n  # n masses + 1 tuned ring - the rigid-body mode
    assert np.all(np.diff(freq) >= 0) and np.all(freq > 0)
    mass, stiff = m.mass, m.stiffness
    w2 = (2 * math.pi * freq) ** 2
    residual = shape @ stiff - w2[:, None] * (shape @ mass)
    scale = np.max(np.abs(shape @ stiff), axis=1)
    assert np.all(np.max(np.abs(residual), axis=1) <= 1e-7 * scale)
    gram = shape @ mass @ shape.T
    off = gram - np.diag(np.diag(gram))
    assert np.max(np.abs(off)) <= 1e-8 * np.max(np.abs(np.diag(gram)))


#: Samples a period of the dense reference of :func:`test_half_range_is_the_sums_half_range`.
_DENSE_SAMPLES = 1 << 16


@functools.cache
def _dense_turns() -> np.ndarray:
    """:math:`e^{iht}` at the dense reference's samples for h = 1..24, computed once (the
    same values as computing them per example)."""
    t = 2 * math.pi * np.arange(_DENSE_SAMPLES) / _DENSE_SAMPLES
    return np.exp(1j * np.outer(t, np.arange(1, 25)))


@given(st.integers(1, 24), st.data())
def test_half_range_is_the_sums_half_range(top, data):
    """The synthesis of a sum of harmonics: never below a dense sampling's, and above it by
    no more than that sampling's step allows (fresh draws each run; the examples a draw
    once found, among them an extreme beside no local extreme of its samples, are
    :data:`FOUND_SUMS`, :data:`MISSED_SUM` and :data:`SHOULDER_SUM`)."""
    h = np.arange(1, top + 1)
    re = data.draw(st.lists(st.floats(-1, 1), min_size=top, max_size=top))
    im = data.draw(st.lists(st.floats(-1, 1), min_size=top, max_size=top))
    x = (np.array(re) + 1j * np.array(im)) / h
    found = float(td.half_range(x[None], h)[0])
    n = _DENSE_SAMPLES
    f = np.real(_dense_turns()[:, :top] @ x)
    dense = 0.5 * (f.max() - f.min())
    slack = (2 * math.pi / n) ** 2 / 8 * float(np.sum(h * h * np.abs(x)))
    assert dense - 1e-12 <= found <= dense + slack + 1e-12


# --------------------------------------------------------------------------- outputs


def _sizes(t):
    return {
        "torsion_mass": t.train.n_masses,
        "torsion_section": t.train.n_masses - 1,
        "torsion_mode": t.frequencies.size,
        "torsion_order": t.orders.size,
        "torsion_speed": t.speeds.size,
        "torsion_damper": len(t.train.dampers),
        "torsion_station": len(t.stations),
        "torsion_resonance": len(t.resonances),
        "cylinder": t.cylinder_mass.size,
    }


@pytest.mark.parametrize("damped", [True, False])
def test_outputs_match_their_dims(damped):
    train = inline4_train()
    if not damped:
        train = TorsionTrain(
            tuple(
                replace(
                    m, damping=0.0, shaft=None if m.shaft is None else replace(m.shaft, damping=0.0)
                )
                for m in train.masses
            )
        )
    result = analysed(with_train("inline-4-gas", train), speeds=np.linspace(100, 800, 9))
    t = result.part("torsion")
    sizes = _sizes(t)
    names = set()
    for output in OUTPUTS:
        assert output.name.startswith("torsion_") and output.name not in names
        names.add(output.name)
        assert output.units is not None and output.describe(result)
        if not output.present(result):
            assert not damped or "damper" in output.name
            continue
        values = np.asarray(output.get(result))
        assert values.shape == tuple(sizes[d] for d in output.dims), output.name
    assert {"torsion_free_end_synthesis", "torsion_mode_frequency", "torsion_vector_sum"} <= names


def test_dataset_of_the_outputs():
    """The outputs make an xarray Dataset with units and long names (what the registry's
    Dataset view builds from them)."""
    import xarray as xr

    from balance.views.dataset import variable

    result = analysed(with_train("inline-4-gas", inline4_train()), speeds=np.linspace(100, 800, 5))
    data, coords = {}, {}
    for output in OUTPUTS:
        if output.present(result):
            target = coords if output.kind == "coord" else data
            target[output.name] = variable(output, np.asarray(output.get(result)), result)
    ds = xr.Dataset(data, coords=coords)
    assert ds.torsion_free_end_amplitude.attrs["units"] == "deg"
    assert ds.torsion_section_stress_synthesis.dims == ("torsion_section", "torsion_speed")
    np.testing.assert_allclose(
        ds.torsion_speed, [speed * 30 / math.pi for speed in np.linspace(100, 800, 5)]
    )


# --------------------------------------------------------------------------- views


def test_json_document_and_block():
    from balance.views import torsion as views

    engine = with_train("inline-4-gas", inline4_train())
    result = analysed(engine, speeds=np.linspace(200, 800, 4))
    doc = views.torsion_document(result)
    assert list(doc)[:4] == ["schema", "layout", "cycle", "speed_rpm"]
    assert doc["schema"] == "balance.torsion/1"
    for key in (
        "orders",
        "masses",
        "sections",
        "dampers",
        "excitation",
        "modes",
        "vector_sums",
        "resonances",
        "response",
        "warnings",
    ):
        assert key in doc
    assert doc["orders"][:3] == [0.5, 1, 1.5]
    assert doc["masses"][2]["cylinders"] == [1]
    assert doc["sections"][6]["diameter_m"] is None
    assert doc["dampers"][0]["type"] == "tuned"
    exc = doc["excitation"]["cylinders"][0]["orders"][0]
    assert set(exc) == {"order", "gas", "inertia", "tangential_pressure_bar"}
    response = doc["response"]
    assert len(response["free_end_deg"]["amplitude"]) == 24
    assert len(response["free_end_deg"]["amplitude"][0]) == 4
    assert response["sections"][6]["stress_MPa"] is None
    assert len(response["dampers"][0]["power_W"]["total"]) == 4
    text = views.torsion_text(result)
    assert json.loads(text)["layout"] == engine.name
    block = views.json_block(analysed(engine, speeds="analysis"))
    assert "schema" not in block["torsion"]
    assert list(block["torsion"])[:3] == ["layout", "cycle", "speed_rpm"]
    assert len(block["torsion"]["speed_rpm"]) == 1
    inertia_only = views.torsion_document(
        analysed(with_train("inline-6", _throw_train(6)), speeds=[300.0])
    )
    first = inertia_only["excitation"]["cylinders"][0]["orders"][0]
    assert set(first) == {"order", "inertia"}
    assert first["inertia"] == {"amplitude_Nm": 0.0, "phase_deg": 0.0}


def test_csv_tables_report():
    from rich.console import Console

    from balance.views import torsion as views

    result = analysed(with_train("inline-4-gas", inline4_train()), speeds=np.linspace(200, 800, 30))
    rows = views.torsion_csv(result).splitlines()
    assert len(rows) == 31
    assert rows[0].startswith("speed_rpm,free_end_deg,section_1_torque_Nm")
    assert rows[0].endswith("damper_1_power_W")
    console = Console(width=100, record=True)
    for part in views.tables(result):
        console.print(part)
    text = console.export_text()
    assert "Torsional modes" in text and "Resonances" in text and "Synthesis" in text
    html = views.report_section(result, figures=False)
    assert "Torsional modes" in html and "<table>" in html
    assert views.REPORT_TITLE


@pytest.mark.parametrize("kind", ["torsion_campbell", "torsion_modes", "torsion_response"])
def test_figures(kind):
    from balance.views import torsion as views

    result = analysed(with_train("inline-4-gas", inline4_train()), speeds=np.linspace(200, 800, 12))
    fig = views.PLOTS[kind](result)
    assert "Inline-4" in fig.texts[0].get_text() if fig.texts else fig._suptitle.get_text()
    axes = fig.axes
    assert axes and all(ax.get_xlabel() for ax in axes)
    one = views.PLOTS[kind](
        analysed(with_train("inline-4-gas", inline4_train()), speeds="analysis")
    )
    assert one.axes


def test_v8_benchmark_train():
    """The benchmark's 12-mass V8: 200 speeds x 24 orders, and the major orders of an
    even-firing V8 (4, 8, 12)."""
    engine = with_train("v8-crossplane-gas", v8_train())
    t = analysed(engine).part("torsion")
    assert t.section_torque.shape == (11, 24, 200)
    assert [float(k) for k in t.orders[t.major]] == [4.0, 8.0, 12.0]


def test_part_without_a_result_torque():
    """Without the torque part (the gas section turned off), the part computes the gas
    torque itself: the same numbers."""
    from balance.core.analysis import compute

    engine = with_train("inline-4-gas", inline4_train())
    bare = compute(engine, Request(sections={}))
    a = torsion_part(engine, Request(), bare, speeds=[400.0]).part("torsion")
    b = analysed(engine, speeds=[400.0]).part("torsion")
    np.testing.assert_allclose(a.free_end, b.free_end, rtol=1e-12)
    c = torsion_analysis(engine, engine.section("torsion"), [400.0])
    np.testing.assert_allclose(c.free_end, b.free_end, rtol=1e-12)


def test_chain_helper():
    assert chain([1, 2], [3]).masses[0].shaft.stiffness == 3


def test_two_stroke_whole_orders():
    """A two-stroke fires every revolution: whole orders 1 to 12 by default, its cycle one
    revolution, major orders the multiples of its cylinder count (a four-cylinder: 4, 8,
    12)."""
    engine = replace(load_layout("inline-4-gas"), cycle="two-stroke", gas=None)
    t = analysed(with_train(engine, inline4_train()), speeds=[300.0, 500.0]).part("torsion")
    np.testing.assert_allclose(t.orders, np.arange(1, 13))
    np.testing.assert_allclose(t.excitation.firing_tdc, [0.0, 180.0, 180.0, 0.0])
    assert [float(k) for k in t.orders[t.major]] == [2.0, 4.0, 6.0, 8.0, 10.0, 12.0]
    assert t.damped and np.all(np.isfinite(t.free_end_synthesis))


def test_link_rods_and_lumped_masses():
    """An engine with master and link rods (the V12 of the Kharkiv V-2): the moving parts'
    inertia of its link cylinders, and its excitation, come from the link kinematics; with
    whole-station inertias a lumped engine is analysed too, its moving parts' inertia
    undefined (NaN)."""
    engine = load_layout("v12-60-articulated")
    order = np.argsort(engine.z, kind="stable")
    masses = [TorsionMass("pulley", inertia=0.05, shaft=Shaft(3e6, 2.0))]
    for t in range(6):
        cyl = tuple(int(c) + 1 for c in order[2 * t : 2 * t + 2])
        masses.append(
            TorsionMass(
                f"throw {t + 1}",
                crank_inertia=0.05,
                cylinders=cyl,
                damping=2.0,
                shaft=Shaft(3e6, 2.0),
            )
        )
    masses.append(TorsionMass("flywheel", inertia=3.0, damping=5.0))
    # the layout gives no firing order: every cylinder's nominal TDC, as a reader would pass
    nominal = list(np.mod(np.degrees(engine.bank - engine.throw), 360.0))
    firing = tx.place_firing_tdc(engine, nominal)
    train = TorsionTrain(tuple(masses), firing_tdc=tuple(firing))
    result = analysed(with_train(engine, train), speeds=[100.0, 200.0])
    t = result.part("torsion")
    assert np.all(np.isfinite(t.moving_inertia)) and np.all(t.moving_inertia > 0)
    linked = engine.links.linked
    assert not np.allclose(t.moving_inertia[linked], t.moving_inertia[~linked])
    from helpers import engine as compact

    lumped = compact([0, 180, 180, 0], firing_order=[1, 3, 4, 2])
    whole = TorsionTrain(
        tuple(
            TorsionMass(
                m.name,
                inertia=m.inertia or 0.006,
                cylinders=m.cylinders,
                damping=m.damping,
                shaft=m.shaft,
            )
            for m in inline4_train().masses
        )
    )
    t = analysed(with_train(lumped, whole), speeds=[400.0]).part("torsion")
    assert np.all(np.isnan(t.moving_inertia))
    assert np.all(np.isfinite(t.inertias))


#: Two sums of 22 harmonics that hypothesis found (real and imaginary parts before the
#: division by h): an asymmetric minimum between two samples, where two Newton steps from
#: the parabola's vertex stopped 4e-6 short, and a shoulder of near extremes within one
#: step, where the vertex led Newton to a lower one.
FOUND_SUMS = [
    (
        [
            -0.875,
            0.125,
            0,
            0.875,
            0,
            -0.5,
            0.5,
            0.3125,
            0,
            0.5,
            0.5,
            0,
            0.9375,
            0,
            0,
            -0.375,
            -0.5,
            0.375,
            0.75,
            0,
            0.375,
            0,
        ],
        [
            0,
            -0.5,
            0.5,
            0,
            0.5,
            0,
            0.75,
            0.5,
            -0.5,
            0,
            0,
            -0.5,
            -0.125,
            0,
            0.375,
            0,
            -0.375,
            0,
            0.125,
            -0.5,
            0,
            -0.0625,
        ],
    ),
    (
        [
            -0.875,
            0.125,
            0,
            0.875,
            0,
            -0.75,
            0.5,
            0.3125,
            0,
            0.5,
            0.5,
            0,
            0.9375,
            0,
            0,
            -0.375,
            -0.5625,
            0.375,
            0.75,
            0,
            0.375,
            0,
        ],
        [
            0,
            -0.375,
            0.5,
            0,
            0.75,
            0,
            -0.9375,
            0.5,
            -0.5,
            0,
            0,
            -0.75,
            -0.1875,
            -0.1875,
            0.375,
            0,
            -0.4375,
            0,
            0.125,
            -0.5,
            0,
            -0.0625,
        ],
    ),
]


#: A third sum hypothesis found: its maximum lies between two samples that are not a local
#: maximum of the samples (the samples rise on to a lower extreme one step away), so that
#: no local extreme of the samples is near it; the synthesis fell 3.5e-5 short before the
#: intervals beside no local extreme were bounded by their Hermite cubics (docs/torsion.md,
#: "Synthesis").
MISSED_SUM = (
    [
        -0.9375,
        0.109375,
        0,
        0.84375,
        0,
        -0.75,
        0.5,
        0.3125,
        -0.21875,
        0.53125,
        0.53125,
        0,
        0.90625,
        0,
        0,
        -0.328125,
        -0.625,
        0.5,
        0.75,
        -0.25,
        0.3125,
        0,
    ],
    [
        0,
        -0.375,
        0.5,
        0,
        0.75,
        0,
        -0.9375,
        0.5,
        -0.5,
        0,
        0,
        -0.75,
        -0.1875,
        -0.1875,
        0.5,
        0,
        -0.4375,
        0,
        0.125,
        -0.5,
        0,
        -0.0625,
    ],
)


#: A sum of three harmonics whose minimum is a shallow dip beside a maximum within one
#: sample step (f'' = 0.013 there against |f| = 1), in the same sample interval as a
#: higher minimum at a sample (t = pi/2): the synthesis fell 2.85e-6 short of the sampled
#: half range before the interval of a refined extreme was split there and bounded on each
#: side (found by hypothesis with an edited test of the sums' half range).
SHOULDER_SUM = ([0.125, 0.875, 0], [0.875, 0.125, 0.875])


@pytest.mark.parametrize("re, im", [*FOUND_SUMS, MISSED_SUM, SHOULDER_SUM])
def test_half_range_of_the_sums_hypothesis_found(re, im):
    h = np.arange(1, len(re) + 1)
    x = (np.array(re) + 1j * np.array(im)) / h
    found = float(td.half_range(x[None], h)[0])
    n = 1 << 18
    f = np.fft.irfft(np.pad(x * (n / 2), (1, n // 2 - h.size)), n=n)
    dense = 0.5 * (f.max() - f.min())
    slack = (2 * math.pi / n) ** 2 / 8 * float(np.sum(h * h * np.abs(x)))
    assert dense - 1e-12 <= found <= dense + slack + 1e-12
