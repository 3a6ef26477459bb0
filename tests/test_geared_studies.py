"""Sweeps and tolerance studies of engines with several crankshafts
(docs/several-crankshafts.md, "Sweeps and tolerance studies"): point by point, each point
the analysis of the hand-edited file bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

from balance.api import analyse, compute_result, load_layout
from balance.cli import app
from tests.test_geared_proposal import TWIN

runner = CliRunner()


def _file(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("vary", "at", "old", "new"),
    [
        (
            "crankshafts.right.phase=0:90:4",
            2,
            "rotation: opposite}",
            "rotation: opposite, phase: 60 deg}",
        ),
        ("crankshafts.right.x=40mm,50mm,60mm", 2, "x: 45 mm, rotation", "x: 60 mm, rotation"),
        ("crankshafts.right.y=-10mm,0mm,25mm", 0, "x: 45 mm,", "x: 45 mm, y: -10 mm,"),
        ("masses.reciprocating=0.5kg,0.7kg", 1, "reciprocating: 0.6 kg", "reciprocating: 0.7 kg"),
        ("speed=3000rpm,4500rpm", 1, "speed: 6000 rpm", "speed: 4500 rpm"),
    ],
)
def test_a_sweep_point_is_the_hand_edited_file_bit_for_bit(tmp_path, vary, at, old, new):
    import xarray as xr

    base = _file(tmp_path, "twin.yaml", TWIN)
    out = tmp_path / "s.nc"
    got = runner.invoke(app, ["sweep", str(base), "--vary", vary, "-o", str(out)])
    assert got.exit_code == 0, got.output
    assert old in TWIN
    edited = _file(tmp_path, "edited.yaml", TWIN.replace(old, new))
    reference = analyse(load_layout(edited), "1-8", proposal=False)
    with xr.open_dataset(out) as ds:
        dim = ds.reciprocating_force_magnitude.dims[0]
        point = ds.isel({dim: at}).load()
    assert "roll_amplitude" in point.data_vars
    for name in point.data_vars:
        a, b = point[name].values, reference[name].values
        assert a.shape == b.shape, name
        assert np.array_equal(a, b), (name, np.max(np.abs(a - b)))


def test_a_sweep_of_the_balance_factor_has_the_proposals_residual(tmp_path):
    """The residual with the proposal at a point: that of the hand-edited file."""
    import xarray as xr

    base = _file(tmp_path, "twin.yaml", TWIN)
    out = tmp_path / "s.nc"
    vary = "balance.balance_factor=30%,60%,90%"
    got = runner.invoke(app, ["sweep", str(base), "--vary", vary, "-o", str(out)])
    assert got.exit_code == 0, got.output
    edited = _file(tmp_path, "edited.yaml", TWIN + "balance: {balance_factor: 60 %}\n")
    reference = analyse(load_layout(edited), "1-8", proposal=True)
    with xr.open_dataset(out) as ds:
        point = ds.isel(balance_factor=1).load()
    for name in ("residual_force_peak", "residual_moment_peak", "reciprocating_force_peak"):
        np.testing.assert_array_equal(point[name].values, reference[name].values)
    # 60 % on each crank: 40 % of m_rec r w^2 of each first-order half is left
    m_r_w2 = 0.6 * 0.043 * (6000 * np.pi / 30) ** 2
    np.testing.assert_allclose(point.residual_force_peak.values[0], 0.8 * m_r_w2, rtol=1e-12)


def test_a_tolerance_sample_is_the_drawn_engine_analysed(tmp_path):
    """Sample by sample: each sample's free and balanced peaks are those of the engine with
    the drawn masses, with the nominal proposal's masses added."""
    from balance.core.counterweights import proposal_phasors
    from balance.studies.tolerance import tolerance

    engine = load_layout(_file(tmp_path, "twin.yaml", TWIN))
    study = tolerance(engine, ["masses.reciprocating=±3g"], samples=5, seed=7)
    draw = np.random.default_rng(7).uniform(-1.0, 1.0, (5, 2)) * 0.003
    proposal = compute_result(engine, "1-2").part("proposal").proposal
    from dataclasses import replace

    for j in range(5):
        drawn = replace(engine, reciprocating_mass=engine.reciprocating_mass + draw[j])
        free = compute_result(drawn, "1-2", proposal=False).phasors.free()
        balanced = free + proposal_phasors(proposal, engine, np.array([1, 2]))
        np.testing.assert_allclose(study.force["free"][j], free.peak("force"), rtol=1e-12)
        np.testing.assert_allclose(study.force["balanced"][j], balanced.peak("force"), rtol=1e-12)
    # the counter-rotating twin's counterweights leave only the scatter in the first order
    assert np.all(study.force["balanced"][:, 0] < 0.01 * study.force["free"][:, 0])
