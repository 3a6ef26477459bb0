"""Tables never cut a number: every table-printing command at 80, 100 and 200 columns.

Each test runs the command line with ``COLUMNS`` set (the width a terminal of that size
gives) and checks that every number of the result, formatted as the tables format it,
appears whole in the output (as a word between spaces and box lines), that nothing is
shortened with an ellipsis and that no line is wider than the terminal.  The numbers come
from the command's own JSON (or from the study it runs), not from the table code.
"""

from __future__ import annotations

import json
import re

import pytest
from rich.cells import cell_len
from typer.testing import CliRunner

import balance
from balance.cli import app
from balance.io.request import build_request
from balance.views.fitted import Column, NumberTable
from balance.views.table import format_number

runner = CliRunner()
WIDTHS = (80, 100, 200)
BOX = "┃│┏┓┗┛┡┩┢┪┣┫━─┳┻╇╈╋┼┬┴├┤└┘┌┐╀╁╂╃╄╅╆"


def run(*args: str, columns: int) -> str:
    result = runner.invoke(app, list(args), env={"COLUMNS": str(columns)})
    assert result.exit_code == 0, result.stderr
    return result.stdout


def words(text: str) -> set[str]:
    """The words of a printed table: what stands between spaces and box lines."""
    return set(text.translate({ord(c): " " for c in BOX}).split())


def assert_whole(text: str, columns: int, numbers) -> None:
    """No ellipsis, no line wider than the terminal, every number a whole word."""
    assert "…" not in text and "..." not in text
    widest = max(cell_len(line) for line in text.splitlines())
    assert widest <= columns, widest
    found = words(text)
    missing = sorted({n for n in numbers if n not in found})
    assert not missing, missing[:20]


def ratio(value) -> str:
    return "n/a" if value is None else format_number(value)


def analysis_numbers(data: dict) -> list[str]:
    """Every number of the analysis JSON that the table prints, formatted as it prints it."""
    out = []
    for what in ("force", "moment"):
        for entry in data["reciprocating"][what]:
            out += [
                format_number(entry["forward"]["magnitude"]),
                format_number(entry["forward"]["phase_deg"]),
                format_number(entry["backward"]["magnitude"]),
                format_number(entry["backward"]["phase_deg"]),
                format_number(entry["peak"]),
                ratio(entry["peak_normalised"]),
            ]
    for entry in data["roll"]:
        out += [format_number(entry["amplitude"]), format_number(entry["phase_deg"])]
    proposal = data["proposal"]
    for c in proposal["counterweights"]:
        out += [
            format_number(c["z_m"] * 1e3),
            format_number(c["mass_kg"]),
            format_number(c["radius_m"] * 1e3),
            format_number(c["angle_deg"]),
        ]
    for s in proposal["balance_shafts"]:
        out += [format_number(s["x_m"] * 1e3), format_number(s["y_m"] * 1e3)]
        for plane in s["planes"]:
            out += [
                format_number(plane["z_m"] * 1e3),
                format_number(plane["unbalance_kgm"] * 1e3),
                format_number(plane["angle_deg"]),
            ]
    residual = proposal["residual"]
    for what in ("force", "moment"):
        for entry in residual[what]:
            out += [format_number(entry["peak"]), ratio(entry["peak_normalised"])]
    out += [format_number(entry["amplitude"]) for entry in residual["roll"]]
    return out


def bearing_numbers(data: dict) -> list[str]:
    """The bearing loads as the tables print them: what is below 1e-12 of the largest pin
    load is rounding and prints as 0 (test_near_zero_prints_as_zero checks that rule)."""
    b = data["bearings"]
    scale = max(p["max_N"] for p in b["crank_pins"])

    def load(v: float, factor: float = 1.0) -> str:
        return "0" if v < 1e-12 * scale * factor else format_number(v)

    out = []
    for p in b["crank_pins"]:
        out += [format_number(p["z_m"] * 1e3), load(p["max_N"]), load(p["mean_N"])]
    for m in b["mains"]:
        out += [format_number(m["z_m"] * 1e3)]
        out += [load(m[k]) for k in ("max_N", "mean_N", "max_with_proposal_N")]
        out += [load(m["mean_with_proposal_N"])]
    for m in b["internal_moment"]:
        out += [load(m["max_Nm"]), load(m["max_with_proposal_Nm"])]
    return out


@pytest.mark.parametrize("columns", WIDTHS)
def test_analyse_prints_every_number_whole(columns):
    """A cross-plane V8 with bearing loads (seven tables) and a boxer twin (counterweights,
    three balance shafts; its centre main carries no load)."""
    for name in ("v8-crossplane", "boxer-2"):
        data = json.loads(run("analyse", name, "--bearings", "-f", "json", columns=columns))
        text = run("analyse", name, "--bearings", columns=columns)
        assert_whole(text, columns, analysis_numbers(data) + bearing_numbers(data))


@pytest.mark.parametrize("columns", WIDTHS)
def test_propose_with_factor_study(columns):
    data = json.loads(run("propose", "single", "--factor-study", "-f", "json", columns=columns))
    text = run("propose", "single", "--factor-study", columns=columns)
    study = data["balance_factor_study"]
    numbers = [f"{100 * e['factor']:.4g}" for e in study["factors"]]
    numbers += [
        format_number(e[k])
        for e in study["factors"]
        for k in ("vertical_peak", "horizontal_peak", "moment_peak")
    ]
    assert_whole(text, columns, numbers)


@pytest.mark.parametrize("columns", WIDTHS)
def test_compare_fits_a_terminal(columns):
    """The issue's case: a 100-column terminal cut nearly every cell to '0…'; the default
    orders 1-4 made the single table about 230 columns wide."""
    layouts = ["inline-4", "v8-crossplane", "inline-3", "v-twin-90"]
    data = json.loads(run("compare", *layouts, "-f", "json", columns=columns))
    text = run("compare", *layouts, columns=columns)
    numbers = []
    for entry in data["layouts"]:
        for what in ("force", "moment"):
            numbers += [ratio(e["peak_normalised"]) for e in entry["reciprocating"][what]]
            numbers.append(ratio(entry["rotating"][what]["peak_normalised"]))
        numbers += [format_number(e["amplitude_normalised"]) for e in entry["roll"]]
        numbers.append(format_number(entry["balancing"]["counterweight_total_mass_kg"]))
        numbers += [entry["layout"], str(entry["n_cylinders"]), str(entry["balancing"]["n_shafts"])]
    assert_whole(text, columns, numbers)
    # the V-twin has no pitch: its normalised moments are n/a, and a note says why
    assert "n/a" in words(text) and "all cylinders in one plane" in " ".join(text.split())
    absolute = run("compare", *layouts, "--absolute", columns=columns)
    numbers = [
        format_number(e["peak"])
        for entry in data["layouts"]
        for what in ("force", "moment")
        for e in entry["reciprocating"][what]
    ]
    assert_whole(absolute, columns, numbers)


@pytest.mark.parametrize("columns", WIDTHS)
def test_mounts_tables(columns):
    data = json.loads(
        run("mounts", "inline-4-mounts", "--speed", "800rpm:8000rpm:4", "-f", "json", columns=80)
    )
    text = run("mounts", "inline-4-mounts", "--speed", "800rpm:8000rpm:4", columns=columns)
    numbers = [format_number(m["frequency_Hz"]) for m in data["modes"]]
    numbers += [format_number(v) for row in data["largest_mount_force_N"] for v in row]
    numbers += [f"{v:.5g}" for v in data["speed_rpm"]]
    assert_whole(text, columns, numbers)
    analysed = json.loads(run("analyse", "single-mounts", "--on-mounts", "-f", "json", columns=80))
    text = run("analyse", "single-mounts", "--on-mounts", columns=columns)
    mounts = analysed["mounts"]
    numbers = [format_number(1e3 * v) for r in mounts["response"] for v in r["cg_translation_m"]]
    numbers += [format_number(1e3 * v) for r in mounts["response"] for v in r["rotation_rad"]]
    numbers += [format_number(max(r["mount_force_peak_N"])) for r in mounts["response"]]
    numbers += [format_number(1e3 * v) for m in mounts["mounts"] for v in m["position_m"]]
    assert_whole(text, columns, numbers)


@pytest.mark.parametrize("columns", WIDTHS)
def test_search_and_tolerance_tables(columns):
    from balance.studies.search import search
    from balance.studies.tolerance import PERCENTILES, tolerance

    text = run("search", "--cylinders", "4", "--even-firing", "--top", "3", columns=columns)
    found = search(4, [0.0], step=30.0, even_firing=True, orders=[1, 2], top=3)
    numbers = []
    for a in found.best:
        numbers += ["/".join(f"{t:g}" for t in a.throws), format_number(a.score)]
        numbers += [format_number(v) for v in (*a.force_peaks, *a.moment_peaks)]
    assert_whole(text, columns, numbers)
    args = ["v8-crossplane", "--scatter", "masses.reciprocating=±3g", "--samples", "300"]
    text = run("tolerance", *args, "--seed", "4", columns=columns)
    study = tolerance(
        balance.load_layout("v8-crossplane"), ["masses.reciprocating=±3g"], samples=300, seed=4
    )
    numbers = [
        format_number(v) for table in study.percentiles(PERCENTILES).values() for v in table.ravel()
    ]
    assert_whole(text, columns, numbers)


def test_layouts_list_fits():
    """Names and cylinder counts whole; only the descriptions wrap (between words)."""
    from balance.io.layout_file import builtin_layout_names, load_layout

    text = run("layouts", columns=80)
    rows = [line.split("│") for line in text.splitlines() if line.startswith("│")]
    named = [(cells[1].strip(), cells[2].strip()) for cells in rows if cells[1].strip()]
    expected = [(n, str(load_layout(n).n_cylinders)) for n in builtin_layout_names()]
    assert named == expected
    assert_whole(text, 80, [n for n, _ in expected])


def test_titles_do_not_wrap_and_headers_carry_units():
    """At 80 columns each table's title is one line of its own; every column of a quantity
    has its unit (the counterweights and shafts printed bare z, mass, radius, x, y)."""
    from balance.core.analysis import compute
    from balance.views.table import render

    text = run("analyse", "boxer-2", "--bearings", columns=80)
    lines = {line.strip() for line in text.splitlines()}
    result = compute(
        balance.load_layout("boxer-2"),
        build_request(balance.load_layout("boxer-2"), range(1, 9), bearings=True),
    )
    titles = [part.title for part in render(result).renderables if isinstance(part, NumberTable)]
    assert len(titles) == 10  # forces, moments, roll, cylinders, proposal (3), bearings (3)
    for title in titles:
        assert title in lines or f"{title} (part 1 of 2)" in lines, title
    wide = run("analyse", "boxer-2", "--bearings", columns=200)
    for header in (
        "z [mm]",
        "mass [kg]",
        "radius [mm]",
        "angle [deg]",
        "m R [kg mm]",
        "x [mm]",
        "y [mm]",
        "plane z [mm]",
        "m e [kg mm]",
        "phase [deg]",
        "at theta [deg]",
    ):
        assert header in wide, header


def test_missing_pitch_prints_na_with_the_reason():
    text = run("analyse", "single", columns=100)
    assert "pitch a = n/a (all cylinders in one plane)" in text
    assert "- mm" not in text
    moments = text.split("Free moments about reference_z", 1)[1].split("Roll torque", 1)[0]
    normalised = [line.split()[-2] for line in moments.splitlines() if re.match(r"│\s+\d", line)]
    assert normalised == ["n/a"] * 10  # orders 1 to 8, and 1 rotating and 1 free
    assert "no pitch a (all cylinders in one plane)" in moments
    # in several planes but one cylinder per bank (a boxer twin): no bore pitch either
    boxer = run("analyse", "boxer-2", columns=100)
    assert "pitch a = n/a (one cylinder per bank: no bore pitch; set pitch: in the layout)" in boxer
    assert "n/a: no pitch a (one cylinder per bank: no bore pitch), so no moment per F1 a" in boxer


def test_near_zero_prints_as_zero():
    """Below the rounding of its own sums a value prints 0: the inline-4's balance-factor
    study (3.96e-12 N before) and the boxer twin's centre main (4.8e-12 N)."""
    study = json.loads(run("propose", "inline-4", "--factor-study", "-f", "json", columns=100))
    values = [
        e[k]
        for e in study["balance_factor_study"]["factors"]
        for k in ("vertical_peak", "horizontal_peak", "moment_peak")
    ]
    assert values == [0.0] * len(values)  # a flat-plane four has no first order at all
    text = run("propose", "inline-4", "--factor-study", columns=100)
    rows = [line for line in text.splitlines() if line.startswith("│")]
    assert rows and not any(re.search(r"\de-1\d", line) for line in rows)
    boxer = run("analyse", "boxer-2", "--bearings", columns=100)
    mains = boxer.split("Main-bearing loads", 1)[1].split("Internal moment", 1)[0]
    centre = next(line for line in mains.splitlines() if re.match(r"│\s+2 ", line))
    assert centre.split()[5:12:2] == ["0", "0", "0", "0"]
    rows = [line for line in boxer.splitlines() if line.startswith("│")]
    assert not any(re.search(r"\de-1\d", line) for line in rows)


def test_number_table_layouts():
    """The layouts of a NumberTable at any width: one-line headers, wrapped headers, parts
    that repeat the key column, one line per value; every cell whole in each."""
    from rich.console import Console

    columns = [Column("order", key=True)] + [
        Column(f"moment max with proposal {i}", "N m") for i in range(6)
    ]
    rows = [[str(k), *(f"{1.2345e4 * k * (i + 1):.4g}" for i in range(6))] for k in range(1, 4)]
    table = NumberTable("A title", columns, rows, notes=("a note",))
    seen = {}
    for width in (20, 40, 60, 80, 120, 240):
        console = Console(width=width, record=True, file=open("/dev/null", "w"))  # noqa: SIM115
        console.print(table)
        text = console.export_text()
        console.file.close()
        assert "…" not in text
        assert max(cell_len(line) for line in text.splitlines()) <= width
        assert {cell for row in rows for cell in row} <= words(text)
        assert "a note" in text
        seen[width] = text
    assert "moment max with proposal 5 [N m]" in seen[240]  # one line
    assert "[N m]" in seen[80] and "moment max with proposal 5 [N m]" not in seen[80]
    assert "A title (part 2 of 3)" in seen[40]  # three parts, the order column in each
    assert seen[40].count("┃ order ┃") == 3
    assert "one line per value" in " ".join(seen[20].split())
