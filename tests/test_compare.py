"""Comparison of layouts: the textbook table, fair scaling, and every output format."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from balance.cli import app
from balance.io.layout_file import builtin_layout_names, builtin_layout_path, load_layout
from balance.studies.compare import compare_results, scale_layout
from balance.views.compare import compare_table, comparison_dataset


def compare(layouts, names=None, orders="1-4", *, speed=None, displacement=None, **kw):
    """The comparison Dataset, as ``balance compare`` builds it."""
    done = compare_results(layouts, names, orders, speed=speed, displacement=displacement, **kw)
    return comparison_dataset(
        [c.result for c in done],
        [c.label for c in done],
        [c.scale_factor for c in done],
        speed=speed,
        displacement=displacement,
    )


runner = CliRunner()


@pytest.fixture(scope="module")
def textbook() -> xr.Dataset:
    names = builtin_layout_names()
    return compare([load_layout(n) for n in names], names, "1-2", model="textbook")


def test_compare_reproduces_the_textbook_coefficients(textbook):
    """Taylor 1985, vol. 2, ch. 8 (engine balance), two-term model: inline-3 sqrt(3) first-order
    couple; inline-4 4 lambda second-order force; inline-5 0.449 first-order couple and
    4.98 lambda second-order couple; cross-plane V8 sqrt(10) first-order couple turning
    forwards; inline-6 and V12 nothing."""

    def value(name, var, k):
        return float(textbook[var].sel(layout=name, order=k))

    lam = {
        n: float(load_layout(n).crank_radius[0] / load_layout(n).conrod_length[0])
        for n in ("inline-4", "inline-5")
    }
    assert value("inline-3", "reciprocating_moment_peak_normalised", 1) == pytest.approx(
        math.sqrt(3)
    )
    assert value("inline-4", "reciprocating_force_peak_normalised", 2) == pytest.approx(
        4 * lam["inline-4"], rel=1e-12
    )
    assert value("inline-5", "reciprocating_moment_peak_normalised", 1) == pytest.approx(
        0.449, abs=5e-4
    )
    m2 = value("inline-5", "reciprocating_moment_peak_normalised", 2) / lam["inline-5"]
    assert m2 == pytest.approx(4.98, abs=0.01)
    v8 = textbook["reciprocating_moment_normalised"].sel(layout="v8-crossplane", order=1)
    assert float(v8.sel(rotation="forward")) == pytest.approx(math.sqrt(10), rel=1e-12)
    assert float(v8.sel(rotation="backward")) == 0.0
    for name in ("inline-6", "v12-60"):
        for var in ("reciprocating_force_peak", "reciprocating_moment_peak"):
            assert np.all(textbook[var].sel(layout=name).values == 0.0)


def test_zeros_by_symmetry_print_as_zero(textbook):
    headers, rows = compare_table(textbook)
    row = dict(zip(headers, next(r for r in rows if r[0] == "inline-6"), strict=True))
    assert row["F1/F1"] == "0" and row["M2/(F1 a)"] == "0" and row["rot M/(F1 a)"] == "0"


def test_scaling_laws():
    """Geometric similarity: lengths x s, masses x s^3 -> forces x s^4, moments x s^5 at the
    same speed; normalised values unchanged."""
    layout = load_layout("inline-3")
    a = compare([layout], ["a"], "1-2")
    b = compare([scale_layout(layout, 2.0)], ["a"], "1-2")
    np.testing.assert_allclose(b.reciprocating_force_peak, 16 * a.reciprocating_force_peak)
    np.testing.assert_allclose(
        b.reciprocating_moment_peak, 32 * a.reciprocating_moment_peak, rtol=1e-12
    )
    np.testing.assert_allclose(
        b.reciprocating_moment_peak_normalised, a.reciprocating_moment_peak_normalised, rtol=1e-12
    )


def test_common_displacement_and_speed():
    names = ["inline-4", "v8-crossplane", "single"]
    ds = compare(
        [load_layout(n) for n in names], names, "1-2", speed=2 * math.pi * 100, displacement=2e-3
    )
    np.testing.assert_allclose(ds.displacement, 2e-3, rtol=1e-12)
    np.testing.assert_allclose(ds.speed, 2 * math.pi * 100)


@pytest.mark.parametrize("fmt", ["table", "markdown", "csv", "json"])
def test_cli_formats(fmt):
    result = runner.invoke(
        app, ["compare", "inline-3", "inline-4", "v8-crossplane", "-f", fmt, "--orders", "1-2"]
    )
    assert result.exit_code == 0, result.stderr
    out = result.stdout
    if fmt == "json":
        data = json.loads(out)
        assert [e["layout"] for e in data["layouts"]] == ["inline-3", "inline-4", "v8-crossplane"]
    elif fmt == "markdown":
        assert out.splitlines()[0].startswith("| layout | cyl |")
        assert len(out.strip().splitlines()) == 5
    elif fmt == "csv":
        assert out.splitlines()[0].startswith("layout,cyl,F1/F1")
    else:
        assert "v8-crossplane" in out


def test_cli_netcdf_has_a_layout_dimension(tmp_path):
    target = tmp_path / "cmp.nc"
    result = runner.invoke(
        app,
        ["compare", "--all", "-f", "netcdf", "-o", str(target), "--absolute", "--speed", "6000rpm"],
    )
    assert result.exit_code == 0, result.stderr
    with xr.open_dataset(target) as ds:
        assert ds.sizes["layout"] == len(builtin_layout_names())
        for name, var in ds.variables.items():
            assert "units" in var.attrs and "long_name" in var.attrs, name


def test_cli_glob_and_errors(tmp_path):
    (tmp_path / "a.yaml").write_text(builtin_layout_path("inline-4").read_text())
    result = runner.invoke(app, ["compare", str(tmp_path / "*.yaml"), "-f", "csv"])
    assert result.exit_code == 0 and "\na," in result.stdout
    result = runner.invoke(app, ["compare", str(tmp_path / "*.nothing")])
    assert result.exit_code == 2 and "matches no file" in result.stderr
    result = runner.invoke(app, ["compare"])
    assert result.exit_code == 2 and "give layout files" in result.stderr
    result = runner.invoke(app, ["compare", "inline-4", "--displacement", "2 kg"])
    assert result.exit_code == 2 and "--displacement" in result.stderr


def test_every_compared_output_is_a_column(monkeypatch):
    """A section's output that declares itself a comparison column (Output.compare) is a
    column of the Dataset, the table (CSV, Markdown) and the terminal table, in section
    order, NaN (printed "-") for a layout without it: the mean torque made one here, beside
    the mounts' largest force, which the catalogue declares."""
    from dataclasses import replace

    from rich.console import Console

    from balance.core import catalogue
    from balance.core.torque import OUTPUTS
    from balance.views import compare as views

    assert [o.name for o in catalogue.compared()] == ["mount_force_max"]
    assert catalogue.compared()[0].compare.header == "mount F max [N]"
    mean = next(o for o in OUTPUTS if o.name == "torque_mean")
    torque = replace(
        mean, compare=catalogue.Compared("M mean [N m]", "mean torque", "mean engine torque")
    )
    monkeypatch.setattr(views, "compared", lambda: (torque, *catalogue.compared()))
    names = ["inline-4", "inline-4-gas", "inline-4-mounts"]
    ds = compare([load_layout(n) for n in names], names, "1-2")
    assert ds["torque_mean"].attrs == {"units": "N m", "long_name": "mean engine torque"}
    assert np.isnan(ds["torque_mean"].sel(layout="inline-4"))
    assert float(ds["torque_mean"].sel(layout="inline-4-gas")) > 0
    headers, rows = compare_table(ds, normalised=False)
    assert headers[-2:] == ["M mean [N m]", "mount F max [N]"]
    by_layout = {row[0]: row[-2:] for row in rows}
    assert by_layout["inline-4"] == ["-", "-"]
    assert by_layout["inline-4-gas"][0] != "-" and by_layout["inline-4-gas"][1] == "-"
    assert by_layout["inline-4-mounts"][0] == "-" and by_layout["inline-4-mounts"][1] != "-"
    console = Console(width=240, record=True)
    console.print(*views.render_comparison(ds, absolute=True))
    text = console.export_text()
    assert text.index("mean torque") < text.index("largest mount force")


def test_default_pitch_is_the_bore_pitch_so_moments_compare():
    """A boxer's moments are normalised by its bore pitch (between neighbouring cylinders
    of one bank: 113 mm on boxer-4, twice its 56.5 mm rod stagger), an inline's by its throw
    spacing; a boxer twin has none (n/a). docs/conventions.md, "Normalisation and pitch"."""
    names = ["boxer-4", "inline-4", "boxer-6", "boxer-2"]
    ds = compare([load_layout(n) for n in names], names, "1-2")
    pitch = ds["pitch"].values
    assert pitch[:3] == pytest.approx([0.113, 0.090, 0.118], rel=1e-12)
    assert math.isnan(pitch[3])
    for label in names[:3]:
        one = ds.sel(layout=label)
        per = float(one["reference_force"]) * float(one["pitch"])
        np.testing.assert_allclose(
            one["reciprocating_moment_peak_normalised"], one["reciprocating_moment_peak"] / per
        )
    text = runner.invoke(app, ["compare", *names, "--orders", "1-2"], env={"COLUMNS": "240"})
    assert text.exit_code == 0, text.stderr
    assert "moments per F1 a with a the layout's pitch: its pitch: key, else its bore pitch" in (
        text.stdout
    )
    moments = text.stdout.split("Free moment peaks", 1)[1].split("Roll torque", 1)[0]
    rows = {line.split()[1]: line.split()[3] for line in moments.splitlines() if "│" in line}
    assert rows["boxer-4"] == "113" and rows["inline-4"] == "90" and rows["boxer-2"] == "n/a"


def test_one_pitch_for_every_layout():
    """``--pitch 90mm`` normalises every layout's moments by one F1 a; the moments in N m
    and the forces do not change, and the heading, the JSON and the Dataset say so."""
    names = ["boxer-4", "vr6"]
    own = compare([load_layout(n) for n in names], names, "1-2")
    done = compare_results([load_layout(n) for n in names], names, "1-2", pitch=0.09)
    ds = comparison_dataset(
        [c.result for c in done], names, [1.0, 1.0], speed=None, displacement=None, pitch=0.09
    )
    assert ds.attrs["common_pitch_m"] == 0.09
    np.testing.assert_array_equal(ds["pitch"], [0.09, 0.09])
    np.testing.assert_array_equal(ds["reciprocating_moment_peak"], own["reciprocating_moment_peak"])
    np.testing.assert_array_equal(
        ds["reciprocating_force_peak_normalised"], own["reciprocating_force_peak_normalised"]
    )
    np.testing.assert_allclose(
        ds["reciprocating_moment_peak_normalised"],
        own["reciprocating_moment_peak_normalised"] * (own["pitch"] / 0.09),
        rtol=1e-12,
    )
    r = runner.invoke(app, ["compare", *names, "--pitch", "90mm", "-f", "json"])
    assert r.exit_code == 0, r.stderr
    assert [e["pitch_m"] for e in json.loads(r.stdout)["layouts"]] == [0.09, 0.09]
    r = runner.invoke(app, ["compare", *names, "--pitch", "90mm"], env={"COLUMNS": "240"})
    assert "moments per F1 a with one pitch a = 90 mm for every layout" in r.stdout
    bad = runner.invoke(app, ["compare", *names, "--pitch", "0mm"])
    assert bad.exit_code != 0 and "--pitch: must be a length above zero" in bad.stderr
    with pytest.raises(Exception, match="pitch must be a length above zero"):
        compare_results([load_layout("boxer-4")], pitch=-1.0)
