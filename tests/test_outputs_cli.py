"""What the commands write, through the command line: directories made for figures, the
sweep's summary line and its file, numbers kept as numbers in every Dataset written, what
a tolerance study states, the report's free-moment table and the per-order phasor panels.

(The tables at 80, 100 and 200 columns are in test_tables.py; docs/cli.md against the
program in test_docs.py.)
"""

from __future__ import annotations

import cmath
import json
import math
import re

import numpy as np
import pytest
import xarray as xr
from helpers import needs
from typer.testing import CliRunner

import balance
from balance.cli import app
from balance.io.request import build_request
from balance.views.table import format_number

runner = CliRunner()


def run(*args: str):
    return runner.invoke(app, list(args), env={"COLUMNS": "100"})


# --------------------------------------------------------------------------- figures directory


def test_plot_makes_its_directory_with_parents(tmp_path):
    """The README's `balance plot inline-4 -o figures/` with no figures/ yet."""
    target = tmp_path / "figures" / "review"
    result = run("plot", "inline-4", "-k", "crank-star", "-o", f"{target}/")
    assert result.exit_code == 0, result.stderr
    assert [p.name for p in target.iterdir()] == ["inline-4-crank_star.png"]
    assert result.stderr == f"balance: wrote {target / 'inline-4-crank_star.png'}\n"
    (tmp_path / "taken").write_text("a file")
    for where in (tmp_path / "taken", tmp_path / "taken" / "below"):
        refused = run("plot", "inline-4", "-k", "crank_star", "-o", str(where))
        assert refused.exit_code == 2 and "is a file" in refused.stderr
        assert refused.stderr.count("\n") == 1
    assert "created, with its parents" in " ".join(run("plot", "--help").stdout.split())


# --------------------------------------------------------------------------- Dataset attributes


_NUMBER = r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?"
#: a number, or a list of numbers, written as text ("6000.0", "1,3,4,2"); not a version
NUMBER_TEXT = re.compile(rf"\s*{_NUMBER}(\s*[,;]\s*{_NUMBER})*\s*")


def assert_numbers_are_numbers(ds: xr.Dataset) -> None:
    """No attribute of the Dataset or of any of its variables is a number (or a list of
    numbers) written as text; ``units`` is text by the CF conventions ("1")."""
    owners = [("Dataset", ds.attrs)] + [(name, var.attrs) for name, var in ds.variables.items()]
    for owner, attrs in owners:
        for key, value in attrs.items():
            if isinstance(value, str) and key != "units":
                assert not NUMBER_TEXT.fullmatch(value), (owner, key, value)


@needs("zarr", "zarr")
def test_sweep_summary_speed_in_rpm_and_attributes(tmp_path):
    target = tmp_path / "s.nc"
    result = run(
        "sweep", "inline-4", "--vary", "speed=1000rpm:8000rpm:3",
        "--vary", "conrod_length=130mm,140mm", "--orders", "1-2", "-o", str(target),
    )  # fmt: skip
    assert result.exit_code == 0, result.stderr
    line = result.stderr.strip()
    assert "\n" not in line
    size = target.stat().st_size
    match = re.fullmatch(
        rf"balance: wrote {re.escape(str(target))} \(([\d.]+) kB\): 6 points "
        r"\(speed 3 × conrod_length 2\) in (\d+\.\d\d) s",
        line,
    )
    assert match, line
    assert float(match.group(1)) == pytest.approx(size / 1000, rel=5e-3)
    with xr.open_dataset(target) as ds:
        np.testing.assert_array_equal(ds["speed_rpm"].values, [1000.0, 4500.0, 8000.0])
        assert ds["speed_rpm"].dims == ("speed",) and "speed_rpm" in ds.coords
        assert ds["speed"].attrs["units"] == "rad/s" and ds["speed_rpm"].attrs["units"] == "rpm"
        assert "speed_rpm" not in ds.attrs  # the layout's speed: stale when speed is varied
        assert_numbers_are_numbers(ds)
    fixed = tmp_path / "fixed.zarr"
    result = run("sweep", "inline-4", "--vary", "conrod_length=130mm,140mm", "-o", str(fixed))
    assert result.exit_code == 0, result.stderr
    assert "2 points (conrod_length 2)" in result.stderr
    with xr.open_zarr(fixed) as ds:
        assert float(ds["speed_rpm"]) == 8000.0  # the layout's speed, as scalar coordinates
        assert float(ds["speed"]) == pytest.approx(8000.0 * math.pi / 30.0, rel=1e-15)
        assert_numbers_are_numbers(ds)


def test_every_dataset_written_keeps_numbers_as_numbers(tmp_path):
    analysis, proposal, comparison = (tmp_path / n for n in ("a.nc", "p.nc", "c.nc"))
    assert run("analyse", "inline-4", "-f", "netcdf", "-o", str(analysis)).exit_code == 0
    result = run(
        "propose", "single", "--balance-factor", "60%", "--factor-study",
        "-f", "netcdf", "-o", str(proposal),
    )  # fmt: skip
    assert result.exit_code == 0, result.stderr
    result = run(
        "compare", "inline-3", "single", "--speed", "6000rpm", "--orders", "1-2",
        "-f", "netcdf", "-o", str(comparison),
    )  # fmt: skip
    assert result.exit_code == 0, result.stderr
    with xr.open_dataset(analysis) as ds:
        assert_numbers_are_numbers(ds)
        assert ds.attrs["speed_rpm"] == 8000.0
        assert list(ds.attrs["firing_order"]) == [1, 3, 4, 2]
        assert list(np.atleast_1d(ds.attrs["proposal_orders"])) == [1, 2]
        assert "proposal_balance_factor" not in ds.attrs  # not given: absent, not ""
    with xr.open_dataset(proposal) as ds:
        assert_numbers_are_numbers(ds)
        assert ds.attrs["proposal_balance_factor"] == pytest.approx(0.6)
        assert list(np.atleast_1d(ds.attrs["firing_order"])) == [1]
    with xr.open_dataset(comparison) as ds:
        assert_numbers_are_numbers(ds)
        assert ds.attrs["common_speed_rpm"] == 6000.0
        assert list(ds.attrs["orders"]) == [1, 2]
        assert "displacement_m3" not in ds.attrs


# --------------------------------------------------------------------------- tolerance


def test_tolerance_states_what_it_drew(tmp_path):
    plot = tmp_path / "hist.png"
    result = run(
        "tolerance", "inline-4", "--scatter", "reciprocating=±3g",
        "--scatter", "cylinders[2].offset=±0.1mm", "--samples", "200",
        "--distribution", "normal", "--seed", "3", "--plot", str(plot),
    )  # fmt: skip
    assert result.exit_code == 0, result.stderr
    text = " ".join(result.stdout.split())
    statement = (
        "200 samples, normal, standard deviation TOL/3, seed 3",
        "reciprocating ±0.003 kg (every cylinder, independently)",
        "cylinders[2].offset ±0.0001 m (cylinder 2)",
    )
    for part in statement:
        assert part in text, part
    png = plot.read_bytes()
    assert b"Description" in png
    described = png.split(b"Description\x00", 1)[1].decode("latin-1")
    for part in statement:
        assert part in described, part
    wrong = run("tolerance", "inline-4", "--scatter", "reciprocating=±3g", "--plot", "h.jpg")
    assert wrong.exit_code == 2 and ".png, .svg or .pdf" in wrong.stderr


def test_tolerance_histogram_title_states_the_study():
    from balance.studies.tolerance import tolerance
    from balance.views.studies import tolerance_histogram

    study = tolerance(balance.load_layout("single"), ["stroke=±0.05mm"], samples=50, seed=1)
    title = " ".join(tolerance_histogram(study).get_suptitle().split())
    assert "50 samples, uniform over ±TOL, seed 1" in title
    assert "stroke ±5e-05 m (every cylinder, independently)" in title


# --------------------------------------------------------------------------- report


def test_report_free_moments_table_shows_what_its_figures_draw(tmp_path, monkeypatch):
    """V8 cross-plane, order 1: the reciprocating moment (3964 N m) and, labelled beside it,
    the free moment reciprocating + rotating (7855 N m) that the figures draw.  The free
    peak is formed here from the JSON's phasors."""
    import balance.views.report as report

    monkeypatch.setattr(report, "html_figure", lambda *args: "")  # tables only: figures are slow
    target = tmp_path / "v8.html"
    assert run("report", "v8-crossplane", "-o", str(target)).exit_code == 0
    html = target.read_text(encoding="utf-8")
    data = json.loads(run("analyse", "v8-crossplane", "-f", "json").stdout)
    first = data["reciprocating"]["moment"][0]
    rotating = data["rotating"]["moment"]["forward"]

    def phasor(p):
        return cmath.rect(p["magnitude"], math.radians(p["phase_deg"]))

    free = abs(phasor(first["forward"]) + phasor(rotating)) + first["backward"]["magnitude"]
    section = html.split('<section id="moments">', 1)[1].split("</section>", 1)[0]
    assert format_number(first["peak"]) == "3964" and format_number(free) == "7855"
    row = re.search(r"<tr><td[^>]*>1</td>(.*?)</tr>", section).group(1)
    cells = re.findall(r">([^<]*)</td>", row)
    assert cells[4] == "3964" and cells[6] == "7855"
    assert "reciprocating inertia" in section
    assert "free: reciprocating + rotating (the figures)" in section


def test_phasor_panels_each_order_on_its_own_scale(tmp_path):
    """Each order's panel is scaled to that order: the longest arrow of every panel reaches
    1/1.12 of its radius, whether it is 242 N (order 4 of the V8) or 0.18 N (order 8)."""
    from balance.core.analysis import compute
    from balance.views.plots import plot_phasors

    result = compute(
        balance.load_layout("v8-crossplane"),
        build_request(balance.load_layout("v8-crossplane"), range(1, 9)),
    )
    fig = plot_phasors(result)
    panels = [ax for ax in fig.axes if ax.get_title().startswith("order ")]
    assert [ax.get_title().split("\n")[0] for ax in panels] == ["order 4", "order 8", "order 1"]
    rmax = []
    for ax in panels:  # the frame is drawn in (x, y); its outer circle is the radius
        lengths = [abs(complex(*t.xy)) for t in ax.texts if getattr(t, "arrow_patch", None)]
        rmax.append(max(float(np.nanmax(np.hypot(*line.get_data()))) for line in ax.lines))
        assert max(lengths) == pytest.approx(rmax[-1] / 1.12, rel=1e-12)
    assert rmax[0] / rmax[1] > 1000  # one linear scale would shrink order 8 to a dot
