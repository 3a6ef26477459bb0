"""The balance-factor study with several crankshafts (docs/several-crankshafts.md,
"Balancing proposals"): each point is the proposal with that ``balance_factor``, bit for
bit, and its outputs say what is left in both senses of the first order."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import balance
from balance.api import compute_result, load_layout
from balance.cli import app
from tests.geared_engines import twin_crank

FACTORS = (0.0, 0.3, 1.0)

ENGINES = {
    "twin crank, counter-rotating": lambda: twin_crank(-1.0, counterweighted=False),
    "twin crank, co-rotating": lambda: twin_crank(1.0, counterweighted=False),
    "deltic-18": lambda: load_layout("deltic-18"),
    "jumo-205": lambda: load_layout("jumo-205"),
}


@pytest.mark.parametrize("name", list(ENGINES))
def test_each_study_point_is_the_proposal_with_that_factor_bit_for_bit(name):
    """At each factor the study's forward and backward first order and its moment peak are
    the residual of the proposal made with that balance_factor, bit for bit.  Where no
    shaft counter-rotates the proposal sends the backward first order to a shaft at -1;
    the study leaves that shaft out and states the backward first order the counterweights
    leave: the engine's own, bit for bit."""
    engine = ENGINES[name]()
    counter = bool(np.any(engine.crankshafts.rotation < 0))
    study = compute_result(engine, 2, factors=FACTORS).part("factor_study")
    np.testing.assert_array_equal(study.factor, FACTORS)
    for i, factor in enumerate(FACTORS):
        single = compute_result(engine, 2, balance_factor=factor)
        part = single.part("proposal")
        left = part.residual
        assert part.proposal.balance_factor == factor
        assert study.force_forward[i] == np.abs(left.force_forward)[0]
        assert study.moment_forward[i] == np.abs(left.moment_forward)[0]
        minus_one = [s for s in part.proposal.shafts if s.speed_ratio == -1]
        if counter:  # the counterweights take both senses: no shaft at -1
            assert not minus_one
            assert study.force_backward[i] == np.abs(left.force_backward)[0]
            assert study.moment_backward[i] == np.abs(left.moment_backward)[0]
            assert study.moment_peak[i] == left.peak("moment")[0]
            fwd, bwd = complex(left.force_forward[0]), complex(left.force_backward[0])
            assert study.vertical_peak[i] == abs(fwd + bwd.conjugate())
            assert study.horizontal_peak[i] == abs(fwd - bwd.conjugate())
        else:  # the proposal's shaft at -1 takes what the study shows is left backward
            free = single.phasors.free()
            assert study.force_backward[i] == np.abs(free.force_backward)[0]
            assert study.moment_backward[i] == np.abs(free.moment_backward)[0]
            assert left.force_backward[0] == 0 and left.moment_backward[0] == 0
            assert minus_one or free.force_backward[0] == free.moment_backward[0] == 0


@pytest.mark.parametrize(
    ("sense", "forward", "backward", "optimal"),
    [(-1.0, lambda f: 1 - f, lambda f: 1 - f, 1.0), (1.0, lambda f: 1 - 2 * f, lambda f: 1, 0.5)],
    ids=["counter-rotating", "co-rotating"],
)
def test_twin_crank_study_in_closed_form(sense, forward, backward, optimal):
    """Two one-cylinder cranks, vertical bores, pins together at theta = 0, F = m_rec r w^2:
    counter-rotating, each crank's counterweight f F turns its own way, so (1 - f) F is left
    forward and backward and 100 % balances the first order; co-rotating, both turn forward:
    (1 - 2f) F forward, F backward, the larger peak smallest at 50 % (vertical (2 - 2f) F,
    horizontal 2f F).  The study is the same whatever orders are analysed."""
    engine = twin_crank(sense, counterweighted=False)
    f1 = float(engine.reciprocating_mass[0] * engine.crank_radius[0] * engine.speed**2)
    study = compute_result(engine, 2, factors=FACTORS).part("factor_study")
    for i, factor in enumerate(FACTORS):
        fwd, bwd = forward(factor) * f1, backward(factor) * f1
        assert study.force_forward[i] == pytest.approx(abs(fwd), rel=1e-12, abs=1e-9 * f1)
        assert study.force_backward[i] == pytest.approx(abs(bwd), rel=1e-12, abs=1e-9 * f1)
        assert study.vertical_peak[i] == pytest.approx(abs(fwd + bwd), rel=1e-12, abs=1e-9 * f1)
        assert study.horizontal_peak[i] == pytest.approx(abs(fwd - bwd), rel=1e-12, abs=1e-9 * f1)
        assert study.moment_peak[i] == 0.0  # one plane, moments about it
    assert study.optimal == pytest.approx(optimal, abs=1e-9)
    # without order 1 among the orders analysed, or without the moments: the same study
    for settings in ({"orders": "2-3"}, {"orders": 2, "moments": False}):
        other = compute_result(engine, factors=FACTORS, **settings).part("factor_study")
        np.testing.assert_array_equal(other.force_forward, study.force_forward)
        np.testing.assert_array_equal(other.force_backward, study.force_backward)


runner = CliRunner()


def test_study_outputs_state_both_senses():
    """JSON, Dataset and table of `propose --factor-study` on the twin-crank built-in carry the
    forward and backward first order per factor (the Dataset with units); one crankshaft's
    study is as before (no such keys)."""
    result = runner.invoke(app, ["propose", "twin-crank-2", "--factor-study", "-f", "json"])
    assert result.exit_code == 0, result.stderr
    study = json.loads(result.stdout)["balance_factor_study"]
    assert study["factor_of"] == "each-cylinder"
    assert study["optimal_factor"] == pytest.approx(1.0, abs=1e-9)
    last = study["factors"][-1]
    assert last["factor"] == 1.0 and last["force_forward"] == last["force_backward"] == 0.0
    first = study["factors"][0]
    assert first["force_forward"] > 0 and first["force_backward"] > 0
    ds = balance.analyse("twin-crank-2", orders=2, factor_study=True)
    for name, unit in (("force", "N"), ("moment", "N m")):
        for sense in ("forward", "backward"):
            variable = ds[f"study_{name}_{sense}"]
            assert variable.attrs["units"] == unit and variable.dims == ("study_factor",)
            assert sense in variable.attrs["long_name"]
    np.testing.assert_array_equal(
        ds["study_force_backward"].values, [e["force_backward"] for e in study["factors"]]
    )
    table = runner.invoke(app, ["propose", "twin-crank-2", "--factor-study"], terminal_width=200)
    assert table.exit_code == 0
    assert "backward force [N]" in table.stdout and "forward moment [N m]" in table.stdout
    assert "without a balance shaft at +1 or -1" in " ".join(table.stdout.split())
    one = runner.invoke(app, ["propose", "single", "--factor-study", "-f", "json"])
    assert "force_forward" not in json.loads(one.stdout)["balance_factor_study"]["factors"][0]
    assert "study_force_forward" not in balance.analyse("single", orders=2, factor_study=True)


def test_factor_note_with_a_counter_rotating_crank_in_closed_form():
    """The note speaks of both senses when a shaft counter-rotates: the counter-rotating twin
    crank at 40 % leaves 60 % of the pistons' F forward and 60 % of their F backward (each
    crank's counterweight 0.4 F turning its own way), no moment; at 100 % nothing."""
    engine = twin_crank(-1.0, counterweighted=False)
    f1 = float(engine.reciprocating_mass[0] * engine.crank_radius[0] * engine.speed**2)
    note = compute_result(engine, 2, balance_factor=0.4).part("proposal").proposal.notes[0]
    for sense in ("forward", "backward"):
        assert (
            f"{0.6 * f1:.4g} N of {sense} first-order force (60 % of the pistons' {f1:.4g} N: "
            f"under-balanced) and no {sense} first-order moment"
        ) in note
    assert "; and " in note
    full = compute_result(engine, 2, balance_factor=1.0).part("proposal").proposal.notes[0]
    assert full.endswith("leave no first-order force or moment in either sense")


TWIN_WITH_GAS = """\
name: twin crank with gas
speed: 7500 rpm
geometry: {bore: 90 mm, stroke: 68 mm, conrod_length: 125 mm}
masses: {reciprocating: 0.51 kg, rotating: 0.27 kg}
crankshafts:
  - {name: left, x: -50 mm}
  - {name: right, x: 50 mm, rotation: opposite}
crank:
  - {crankshaft: left, throws: [0], spacing: 100 mm}
  - {crankshaft: right, throws: [0], spacing: 100 mm}
firing_order: [1, 2]
gas:
  model: {compression_ratio: 10.5, heat_released: 0.5 kJ, combustion_start: -20 deg}
"""


@pytest.mark.parametrize(
    ("gas", "strategy", "factors"), [(False, "two-plane", (0.0, 0.6)), (True, "per-throw", (0.6,))]
)
def test_study_bearing_columns_are_each_factors_loads(tmp_path, gas, strategy, factors):
    """With the bearing loads, the study's largest main load and internal moment at each
    factor are those of the analysis with that factor's proposal, shaft by shaft (the
    counter-rotating one mirrored), without and with gas forces, to 1e-12."""
    from balance.core.bearing_loads import axes_bearings

    if gas:
        path = tmp_path / "twin.yaml"
        path.write_text(TWIN_WITH_GAS)
        engine = load_layout(str(path))
    else:
        engine = load_layout("twin-crank-2")
    result = compute_result(
        engine, 2, factors=factors, bearings=True, strategy=strategy, balance_factor=0.6
    )
    study = result.part("factor_study")
    for i, factor in enumerate(factors):
        if factor == 0.6:  # the analysis's own loads, with its proposal at 60 %
            loads = result.part("bearings").loads
        else:
            proposal = compute_result(engine, 2, balance_factor=factor, strategy=strategy)
            loads = axes_bearings(engine, proposal.part("proposal").proposal)
        assert loads.counterweights and loads.gas == gas
        main, moment = loads.main_max_with_proposal.max(), loads.moment_max_with_proposal.max()
        assert study.largest_main_load[i] == pytest.approx(main, rel=1e-12)
        assert study.largest_internal_moment[i] == pytest.approx(moment, rel=1e-12)
