"""The bearing loads through the command line and the views (issue 15, CONTRACT §6)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from balance.cli import app
from balance.core.analysis import compute
from balance.core.bearing_loads import analysis_bearings
from balance.core.bearings import bearing_loads, counterweights_of
from balance.core.result import Request
from balance.io.layout_file import load_layout
from balance.io.request import build_request

runner = CliRunner()

LAYOUT = """\
name: twin with mains
speed: 6000 rpm
geometry: {stroke: 86 mm, conrod_length: 143 mm}
masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}
crank: {throws: [0, 180], spacing: 90 mm}
"""


def run(*args: str):
    return runner.invoke(app, list(args))


def write(tmp_path: Path, text: str) -> str:
    path = tmp_path / "layout.yaml"
    path.write_text(text)
    return str(path)


def test_json_block_is_the_contract():
    result = run("analyse", "inline-4", "--bearings", "--format", "json")
    assert result.exit_code == 0, result.stderr
    block = json.loads(result.stdout)["bearings"]
    assert set(block) == {"crank_pins", "mains", "internal_moment"}
    assert set(block["crank_pins"][0]) == {"z_m", "cylinders", "max_N", "mean_N"}
    assert set(block["mains"][0]) == {
        "z_m",
        "max_N",
        "mean_N",
        "max_with_proposal_N",
        "mean_with_proposal_N",
    }
    assert set(block["internal_moment"][0]) == {"z_m", "max_Nm", "max_with_proposal_Nm"}
    assert [p["cylinders"] for p in block["crank_pins"]] == [[1], [2], [3], [4]]
    assert [m["z_m"] for m in block["mains"]] == pytest.approx([-0.045, 0.045, 0.135, 0.225, 0.315])


def test_not_computed_unless_asked():
    result = run("analyse", "inline-4", "--format", "json")
    assert result.exit_code == 0
    assert "bearings" not in json.loads(result.stdout)
    assert compute(load_layout("inline-4"), Request()).part("bearings") is None


def test_section_sets_the_mains_and_asks(tmp_path):
    path = write(tmp_path, LAYOUT + "bearings:\n  mains: [-50 mm, 40 mm, 140 mm]\n")
    result = run("analyse", path, "--format", "json")
    assert result.exit_code == 0, result.stderr
    mains = json.loads(result.stdout)["bearings"]["mains"]
    assert [m["z_m"] for m in mains] == pytest.approx([-0.05, 0.04, 0.14])


def test_empty_section_means_default_mains(tmp_path):
    path = write(tmp_path, LAYOUT + "bearings: {}\n")
    engine = load_layout(path)
    assert engine.section("bearings") == pytest.approx((-0.045, 0.045, 0.135))


@pytest.mark.parametrize(
    ("section", "line", "field", "words"),
    [
        ("bearings:\n  mains: [0.05 mm]\n", 7, "bearings.mains", "at least two"),
        ("bearings:\n  mains: [-45 mm, 45 mm, 40 mm]\n", 7, "bearings.mains[3]", "not after"),
        ("bearings:\n  mains: [-45 mm, 90 mm, 135 mm]\n", 7, "bearings.mains[2]", "crank pin"),
        ("bearings:\n  mains: [-45 mm, 45 kg]\n", 7, "bearings.mains", "length"),
        ("bearings:\n  main: [-45 mm, 45 mm]\n", 7, "bearings.main", "mains"),
    ],
)
def test_bad_section_names_line_and_field(tmp_path, section, line, field, words):
    path = write(tmp_path, LAYOUT + section)
    result = run("analyse", path, "--bearings")
    assert result.exit_code != 0
    message = result.stderr
    assert f"{path}:{line}:" in message, message
    assert field in message, message
    assert words in message, message


def test_table_shows_both_variants():
    result = run("analyse", "inline-4", "--bearings")
    assert result.exit_code == 0, result.stderr
    for words in ("Crank-pin loads", "Main-bearing loads", "max with proposal [N]", "mean [N]"):
        assert words in result.stdout


def test_propose_shows_both_strategies_side_by_side():
    result = run("propose", "inline-4", "--bearings", "--strategy", "per-throw")
    assert result.exit_code == 0, result.stderr
    out = result.stdout
    assert "Counterweight strategies" in out
    assert "two-plane" in out and "per-throw" in out
    assert "largest main load [N]" in out and "largest internal moment [N m]" in out


def test_factor_study_columns():
    result = run("propose", "single", "--factor-study", "--bearings")
    assert result.exit_code == 0, result.stderr
    assert "largest main load [N]" in result.stdout
    assert "largest internal moment [N m]" in result.stdout
    plain = run("propose", "single", "--factor-study")
    assert "largest main load" not in plain.stdout


def test_factor_study_dataset_matches_single_analyses():
    from balance.views.dataset import build_dataset

    engine = load_layout("single")
    request = build_request(engine, factors=[0.0, 0.5, 1.0], bearings=True)
    study = build_dataset(compute(engine, request))
    for i, f in enumerate((0.0, 0.5, 1.0)):
        result = compute(engine, build_request(engine, balance_factor=f, bearings=True))
        b = result.part("bearings").loads
        assert b is not None
        assert float(study["study_largest_main_load"][i]) == pytest.approx(
            float(np.max(b.main_max_with_proposal)), rel=1e-12
        )
        assert float(study["study_largest_internal_moment"][i]) == pytest.approx(
            float(np.max(b.moment_max_with_proposal)), rel=1e-12
        )
        assert study["study_largest_main_load"].attrs["units"] == "N"


def test_dataset_variables_have_units_and_long_names():
    from balance.views.dataset import build_dataset

    ds = build_dataset(
        compute(load_layout("inline-4"), build_request(load_layout("inline-4"), bearings=True))
    )
    names = [v for v in ds.variables if "bearing" in v or "crank_pin" in v or "internal" in v]
    assert "main_bearing_max_load_with_proposal" in names
    assert "crank_pin_load_y" in names and "internal_moment_max" in names
    for name in names:
        assert ds[name].attrs.get("units"), name
        assert ds[name].attrs.get("long_name"), name


@pytest.mark.parametrize(
    ("layout", "strategy"),
    [
        ("inline-4", "two-plane"),
        ("inline-4", "per-throw"),
        ("single", "two-plane"),
        ("single", "per-throw"),
        # with gas once: three gas computations over 720 deg take about 17 s
        ("v8-crossplane-gas", "per-throw"),
    ],
)
def test_result_equals_two_separate_computations(layout, strategy):
    engine = load_layout(layout)
    result = compute(engine, build_request(engine, bearings=True, strategy=strategy))
    b = result.part("bearings").loads
    assert b is not None
    cws = counterweights_of(result.part("proposal").proposal if result.part("proposal") else None)
    without, with_cw = bearing_loads(engine), bearing_loads(engine, counterweights=cws)
    order = np.argsort(without.pin_z, kind="stable")
    np.testing.assert_allclose(b.pin_max, without.pin_max[order], rtol=1e-12)
    np.testing.assert_allclose(b.main_max, without.main_max, rtol=1e-12)
    np.testing.assert_allclose(b.main_mean, without.main_mean, rtol=1e-12)
    np.testing.assert_allclose(b.main_max_with_proposal, with_cw.main_max, rtol=1e-12)
    np.testing.assert_allclose(b.main_mean_with_proposal, with_cw.main_mean, rtol=1e-12)
    scale = float(np.max(with_cw.moment_max))
    np.testing.assert_allclose(b.moment_max_with_proposal, with_cw.moment_max, atol=1e-12 * scale)
    assert b.gas == (engine.gas is not None)


def test_per_throw_counterweights_unload_the_centre_main_of_an_inline_4():
    """The worked example of docs/bearings.md."""
    engine = load_layout("inline-4")
    two = analysis_bearings(
        engine,
        counterweights_of(
            compute(engine, build_request(engine, strategy="two-plane")).part("proposal").proposal
        ),
    )
    per = analysis_bearings(
        engine,
        counterweights_of(
            compute(engine, build_request(engine, strategy="per-throw")).part("proposal").proposal
        ),
    )
    centre = 2
    assert per.main_max_with_proposal[centre] < 0.5 * two.main_max_with_proposal[centre]
    assert np.max(per.moment_max_with_proposal) < np.max(two.moment_max_with_proposal)


@pytest.mark.xdist_group("sections_report")  # one worker builds the session fixture once
def test_plots_and_report(tmp_path, sections_report):
    """The bearing kinds drawn by 'balance plot' (inline-4), and the report's bearings
    section (conftest.sections_report: the inline-4 on its mounts, with --bearings)."""
    result = run(
        "plot",
        "inline-4",
        "-k",
        "pin-load",
        "-k",
        "main-loads",
        "-k",
        "internal-moment",
        "-o",
        str(tmp_path),
        "-f",
        "svg",
    )
    assert result.exit_code == 0, result.stderr
    for kind in ("pin_load", "main_loads", "internal_moment"):
        assert (tmp_path / f"inline-4-{kind}.svg").stat().st_size > 1000
    result, html = sections_report
    assert result.exit_code == 0, result.stderr
    assert 'id="bearings"' in html and "Crank-pin loads" in html
    assert 'id="figure-pin_load"' in html


def test_default_plots_leave_out_bearing_kinds_without_loads(tmp_path, monkeypatch):
    from balance.views import plots
    from balance.views.bearings import PLOTS
    from balance.views.plots import PLOT_KINDS

    BEARING_KINDS = tuple(PLOTS)
    assert set(BEARING_KINDS) <= set(plots.all_kinds())
    result = compute(load_layout("inline-2-180"), Request())
    for kind in BEARING_KINDS:  # a figure that says what to ask for, not an error
        fig = plots.plot_kind(kind)(result)
        texts = [t.get_text() for ax in fig.axes for t in ax.texts]
        assert any("ask for them" in t for t in texts)
    # which kinds are written, not how: every default kind is drawn as SVG in each report
    # (no figure is built or drawn here)
    monkeypatch.setattr(plots, "figure_bytes", lambda fig, fmt="png": b"")
    for kind in PLOT_KINDS:
        monkeypatch.setitem(PLOT_KINDS, kind, lambda result, **options: None)
    written = plots.save_plots(result, tmp_path, fmt="svg")
    assert written and not any(kind in p.name for p in written for kind in BEARING_KINDS)


def test_expand_keeps_the_mains(tmp_path):
    path = write(tmp_path, LAYOUT + "bearings: {}\n")
    result = run("layout", "expand", path)
    assert result.exit_code == 0, result.stderr
    assert "bearings:" in result.stdout and "-45 mm" in result.stdout
    again = tmp_path / "expanded.yaml"
    again.write_text(result.stdout)
    assert load_layout(str(again)).section("bearings") == pytest.approx((-0.045, 0.045, 0.135))
