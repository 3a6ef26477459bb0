"""Tolerance studies: zero scatter, the one-cylinder limit, CLI and plot."""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

import balance
from balance.api import analyse
from balance.cli import app
from balance.io.fields import parse_scatter
from balance.studies.sweep import variant
from balance.studies.tolerance import tolerance
from balance.views.studies import tolerance_histogram as histogram

runner = CliRunner()


def test_zero_scatter_reproduces_the_analysis():
    layout = balance.load_layout("inline-4")
    result = tolerance(layout, ["reciprocating=±0g"], samples=5, orders="1-2")
    ref = analyse(layout, "1-2")
    free = ref.reciprocating_force_peak.values.copy()
    np.testing.assert_allclose(result.force["free"], np.broadcast_to(free, (5, 2)), rtol=1e-12)
    np.testing.assert_allclose(
        result.force["balanced"],
        np.broadcast_to(ref.residual_force_peak.values, (5, 2)),
        atol=1e-9 * free.max(),
    )


def test_samples_match_single_layouts():
    layout = balance.load_layout("v8-crossplane")
    result = tolerance(layout, ["cylinders[2].reciprocating=±5g"], samples=3, seed=1)
    rng = np.random.default_rng(1)
    draws = rng.uniform(-1, 1, 3) * 0.005
    for i, d in enumerate(draws):
        mass = float(layout.reciprocating_mass[1] + d)
        ref = analyse(variant(layout, {"cylinders[2].reciprocating": mass}), "1-2", proposal=False)
        np.testing.assert_allclose(
            result.moment["free"][i, 1], ref.reciprocating_moment_peak.values[1], rtol=1e-12
        )


def test_part_scatter_is_lumped_again_like_the_layout_file():
    """Scattering a part (by-part layout) changes the lumped masses as the file would."""
    layout = balance.load_layout("v6-60-split")
    assert layout.mass_parts is not None
    result = tolerance(layout, ["cylinders[3].piston_group=±4g"], samples=3, seed=7)
    draws = np.random.default_rng(7).uniform(-1, 1, 3) * 0.004
    for i, d in enumerate(draws):
        piston = float(layout.mass_parts.piston_group[2] + d)
        ref = analyse(variant(layout, {"cylinders[3].piston_group": piston}), "1-2", proposal=False)
        np.testing.assert_allclose(
            result.force["free"][i], ref.reciprocating_force_peak.values, rtol=1e-12
        )
    # the conrod length moves mass between the small and the big end
    zero = tolerance(layout, ["conrod_length=±0mm"], samples=2, orders="1-2")
    np.testing.assert_allclose(
        zero.force["free"][0], analyse(layout, "1-2").reciprocating_force_peak.values, rtol=1e-12
    )


def test_scatter_grows_the_balanced_residual():
    layout = balance.load_layout("v8-crossplane")
    result = tolerance(layout, ["reciprocating=±3g", "throw=±0.2deg"], samples=2000)
    p = result.percentiles()
    assert np.all(np.diff(p["moment_balanced"], axis=0) >= 0)  # percentiles increase
    assert p["moment_balanced"][-1, 0] > 0
    assert p["moment_free"][0, 0] > 10 * p["moment_balanced"][0, 0]  # counterweights help
    fig = histogram(result)
    assert len(fig.axes) == 4


@pytest.mark.parametrize(
    ("scatter", "message"),
    [
        ("name=±3g", "not a numeric layout field"),
        ("speed=±3rpm", "not a part or geometry field"),
        ("reciprocating=3g", "±TOL"),
        ("reciprocating=±3mm", "is a length, not a mass"),
        ("reciprocating", "write FIELD=±TOL"),
    ],
)
def test_cli_bad_scatter(scatter, message):
    result = runner.invoke(app, ["tolerance", "inline-4", "--scatter", scatter])
    assert result.exit_code == 2
    assert message in result.stderr and result.stderr.count("\n") == 1


def test_cli_tolerance_and_plot(tmp_path):
    plot = tmp_path / "h.png"
    result = runner.invoke(
        app,
        [
            "tolerance",
            "inline-4",
            "--scatter",
            "reciprocating=±3g",
            "--samples",
            "500",
            "--plot",
            str(plot),
        ],
    )
    assert result.exit_code == 0, result.stderr
    assert "Free moment (reciprocating + rotating) peak per order: percentiles" in result.stdout
    assert plot.stat().st_size > 1000


def test_parse_scatter_units():
    layout = balance.load_layout("inline-4")
    assert parse_scatter("masses.reciprocating=±3g", layout).tolerance == pytest.approx(0.003)
    assert parse_scatter("cylinders[2].offset=+-0.1mm", layout).field.cylinder == 1
