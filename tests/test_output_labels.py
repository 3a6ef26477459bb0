"""What the tables and figures say they show (docs/cli.md, "Tables" and "balance plot").

- Every table title names its quantity, and the free-force and free-moment tables show the
  reciprocating inertia, the rotating masses and their sum, the free force the figures draw
  (a crossplane engine's first-order moment is twice as large free as reciprocating).
- Every figure title begins with the layout and its crank speed.
- One noise rule (docs/conventions.md, "Zero by symmetry") in the tables of the mounts and in
  the labels of the figures.
- The figure review: crank-star labels of throws 10 degrees apart do not overlap, the mount
  crossings are those of the orders that load the mounts and their labels do not overlap,
  the pin-load figure says what its red line is; the HTML report lists every section.
"""

from __future__ import annotations

import dataclasses
import io
import re
from functools import cache
from html.parser import HTMLParser
from itertools import combinations

import numpy as np
import pytest
from rich.console import Console
from typer.testing import CliRunner

import balance
from balance.cli import app
from balance.core.catalogue import speed_rpm
from balance.views import mounts as mounts_views
from balance.views import plots
from balance.views.figures import significant_mask
from balance.views.report import render_report

runner = CliRunner()


def run(*args: str, columns: int = 100) -> str:
    result = runner.invoke(app, list(args), env={"COLUMNS": str(columns)})
    assert result.exit_code == 0, result.stderr
    return result.stdout


def _rows(text: str, title: str) -> dict[str, list[str]]:
    """The rows of the table under ``title``: key cell -> the other cells."""
    block = text.split(title, 1)[1].split("└", 1)[0]
    rows = {}
    for line in block.splitlines():
        if line.startswith("│"):
            cells = [c.strip() for c in line.strip("│").split("│")]
            rows[cells[0]] = cells[1:]
    return rows


@cache
def _result(name: str, **settings):
    return balance.compute_result(name, list(range(1, 9)), **settings)


def test_free_tables_show_reciprocating_rotating_and_free():
    """v8-crossplane's first-order moment: reciprocating 7855/2 ... the table's ``1`` row is
    the reciprocating inertia, ``1 rot.`` the rotating masses and ``1 free`` their sum, the
    number the spectrum figure draws; the titles say which."""
    text = run("analyse", "v8-crossplane", "--orders", "1-2")
    assert "Free moments about reference_z: reciprocating; order 1 also rotating and free" in text
    assert "1 rot.: the rotating masses; 1 free = reciprocating + rotating (as drawn)" in text
    rows = _rows(text, "Free moments about reference_z")
    ds = balance.analyse("v8-crossplane", orders=[1, 2])
    result = _result("v8-crossplane")
    reciprocating = float(ds["reciprocating_moment_peak"].sel(order=1))
    rotating = float(ds["rotating_moment_magnitude"])
    free = float(result.phasors.free().peak("moment")[0])
    assert float(rows["1"][4]) == pytest.approx(reciprocating, rel=1e-3)
    assert float(rows["1 rot."][4]) == pytest.approx(rotating, rel=1e-3)
    assert float(rows["1 free"][4]) == pytest.approx(free, rel=1e-3)
    # a cross-plane crank: both turn forwards at the same phase, so free is their sum
    assert free == pytest.approx(reciprocating + rotating, rel=1e-12)
    assert free > 1.9 * reciprocating
    spectrum = plots.plot_kind("spectrum")(result)
    bars = [p.get_height() for p in spectrum.axes[1].patches]
    assert bars[0] == pytest.approx(free, rel=1e-12)
    assert "free (reciprocating + rotating)" in " ".join(spectrum.get_suptitle().split())


#: Layouts whose figures together are every kind: gas, bearings, mounts, dynamics, torsion.
TITLED = {
    "inline-4-gas": {"bearings": True},
    "inline-4-mounts": {"bearings": True},
    "single-idle": {},
    "inline-6-diesel-torsion": {},
}


@pytest.mark.parametrize("name", list(TITLED))
def test_every_figure_title_states_the_speed(name):
    """Every figure title begins with the layout's name and its crank speed (the mean speed
    of a variable-speed analysis, the range of a sweep); the torsional mode shapes, which
    do not depend on the speed, say so."""
    result = _result(name, **TITLED[name])
    rpm = f"{speed_rpm(result.engine.speed):.6g}"
    kinds = plots.applicable_kinds(result)
    for kind in kinds:
        fig = plots.plot_kind(kind)(result)
        title = " ".join(fig.get_suptitle().replace("\u00a0", " ").split())
        assert title.startswith(" ".join(str(result.engine.name).split())), (kind, title)
        assert (
            f"at {rpm} rpm" in title
            or re.search(r"at \d[\d.]* rpm mean", title)
            or re.search(r"\d+-\d+ rpm", title)
            or "the same at every speed" in title
        ), (kind, title)


def test_noise_of_the_mounts_response_prints_as_zero():
    """A response component within the rounding of its order's largest motion (1e-38 m next
    to 5e-5 m) prints as 0, as the phasor sums do; a small genuine one keeps its value."""
    result = _result("inline-4-mounts")
    part = result.part("mounts")
    m = part.response
    response = np.array(m.response, copy=True)
    i = int(np.searchsorted(m.orders, 4))
    response[i, 1] = 1.44e-41  # CG y [m]: 1.44e-38 mm
    response[i, 3] = 6.721e-39  # rx [rad]: 6.721e-36 mrad
    noisy = dataclasses.replace(m, response=response)
    out = result.with_part("mounts", dataclasses.replace(part, response=noisy))
    console = Console(width=160, record=True, file=io.StringIO())
    for table in mounts_views.tables(out):
        console.print(table)
    text = console.export_text()
    row = _rows(text, "Response on the mounts per order")["4"]
    assert row[1] == "0" and row[3] == "0", row
    assert float(row[0]) == pytest.approx(abs(response[i, 0]) * 1e3, rel=1e-3)
    assert not re.search(r"e-[2-9]\d\b", text)


def test_figure_labels_follow_the_rule_of_every_view():
    """A bar is drawn and labelled unless it is within the rounding of the bars' sum
    (64 n eps of it): 1e-12 of the largest is drawn, 1e-15 is not."""
    values = np.array([1.0e4, 1.0e-8, 1.0e-11, 0.0, np.nan])
    assert significant_mask(values).tolist() == [True, True, False, False, False]
    assert not significant_mask(np.zeros(3)).any()


@pytest.mark.parametrize("name", ["inline-4", "inline-6", "boxer-4", "v8-crossplane"])
def test_no_figure_label_is_round_off(name):
    """No text of any figure of an engine with orders that cancel by symmetry shows a value
    with an exponent below -20 (round-off printed as a number)."""
    result = _result(name, bearings=True)
    for kind in plots.applicable_kinds(result):
        fig = plots.plot_kind(kind)(result)
        texts = [fig.get_suptitle()] + [t.get_text() for ax in fig.axes for t in ax.texts]
        assert not [t for t in texts if re.search(r"e-[2-9]\d\b", t)], kind


def _drawn(fig):
    """The figure on an Agg canvas, drawn, so that its texts have their extents."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    return fig


def _boxes(fig, texts):
    renderer = fig.canvas.get_renderer()
    return [t.get_window_extent(renderer) for t in texts]


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def _close_throws() -> balance.Engine:
    """The inline-4 with its throws 10 degrees apart in pairs: 0, 10, 180, 190."""
    engine = balance.load_layout("inline-4")
    return dataclasses.replace(engine, throw=np.radians([0.0, 10.0, 180.0, 190.0]))


@pytest.mark.parametrize("name", ["close", "w12", "v10-90-split", "radial-9", "v6-60-split"])
def test_crank_star_labels_do_not_overlap(name):
    """Throws 10 degrees apart (and a W12's twelve pins, 10 to 12 degrees apart) get labels
    that do not overlap one another, nor the bank labels; each names its throw's angle."""
    engine = _close_throws() if name == "close" else balance.load_layout(name)
    result = balance.compute_result(engine, [1, 2])
    fig = _drawn(plots.plot_kind("crank_star")(result))
    labels = [t for t in fig.axes[0].texts if t.get_text() not in ("rotation", "")]
    shown = " ".join(t.get_text() for t in labels)
    for throw in np.unique(np.round(np.degrees(engine.throw) % 360.0, 6)):
        assert f"({throw:g}°)" in shown, throw
    for a, b in combinations(zip(labels, _boxes(fig, labels), strict=True), 2):
        assert not _overlap(a[1], b[1]), (a[0].get_text(), b[0].get_text())
    limits = fig.axes[0].get_window_extent()
    for box in _boxes(fig, labels):
        assert limits.x0 <= box.x0 and box.x1 <= limits.x1, box
        assert limits.y0 <= box.y0 and box.y1 <= limits.y1, box


def test_mount_crossings_are_those_of_orders_that_load_the_mounts():
    """The single's mount figure marks the crossings of orders 1 and 2 (both load the
    mounts) with labels that do not overlap; the inline-4's first order is zero, so no
    ``1×m`` crossing is marked on its figure."""
    sweep = (
        balance.compute_result(
            "single-mounts", [1, 2], mounts={"speeds": np.linspace(80.0, 840.0, 200)}
        )
        .part("mounts")
        .sweep
    )
    crossings = mounts_views.sweep_json(sweep, "single")["crossings"]
    expected = {f"{c['order']}×m{c['mode']}" for c in crossings}
    assert {c["order"] for c in crossings} == {1, 2}
    fig = _drawn(mounts_views.plot_mount_sweep(sweep, layout="single"))
    labels = [t for t in fig.axes[0].texts if "×m" in t.get_text()]
    assert {t.get_text() for t in labels} == expected and len(labels) == len(expected)
    for a, b in combinations(zip(labels, _boxes(fig, labels), strict=True), 2):
        assert not _overlap(a[1], b[1]), (a[0].get_text(), b[0].get_text())
    four = plots.plot_kind("mounts")(_result("inline-4-mounts"))
    marked = [t.get_text() for t in four.axes[0].texts if "×m" in t.get_text()]
    assert not [t for t in marked if t.startswith("1×")]


def test_pin_load_figure_says_what_its_red_line_is():
    """The line from the origin is the largest load, labelled with its crank angle."""
    result = _result("v8-crossplane", bearings=True)
    fig = plots.plot_kind("pin_load")(result)
    b = result.part("bearings").loads
    drawn = [ax for ax in fig.axes if ax.get_legend() is not None]
    assert len(drawn) == 4  # the four pins
    for ax in drawn:
        legend = [t.get_text() for t in ax.get_legend().get_texts()]
        assert legend[0] == "pin load over the cycle"
        assert re.fullmatch(r"largest load \(θ = \d+\.\d°\)", legend[1]), legend
    first = fig.axes[0].get_legend().get_texts()[1].get_text()
    angle = float(re.search(r"= ([\d.]+)°", first).group(1))
    assert angle == pytest.approx(np.degrees(b.pin_max_angle[0]) % 360.0, abs=0.06)


class _Nav(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.inside = False
        self.items: list[str] = []
        self.headings: list[str] = []
        self._h2 = False

    def handle_starttag(self, tag, attrs):
        if tag == "nav":
            self.inside = True
        self._h2 = tag == "h2"

    def handle_endtag(self, tag):
        if tag == "nav":
            self.inside = False
        if tag == "h2":
            self._h2 = False

    def handle_data(self, data):
        if self.inside and data.strip():
            self.items.append(data.strip())
        elif self._h2 and data.strip():
            self.headings.append(data.strip())


def test_report_contents_list_every_section():
    """The HTML report's contents list is its section headings, in order, with the
    bearing loads and the engine on its mounts when the result has them."""
    nav = _Nav()
    nav.feed(render_report(_result("inline-4-mounts", bearings=True), figures=False))
    assert "Crank-pin and main-bearing loads" in nav.items
    assert "The engine on its mounts" in nav.items
    assert nav.items == [re.sub(r"^\d+\. ", "", h) for h in nav.headings]
