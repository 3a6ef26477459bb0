"""The documentation's examples are what the program reads and prints.

- Every YAML example of the documentation loads with :func:`balance.load_layout` (from a
  file, by the file's rules).  A block that is a whole layout (it has a ``name``) is loaded
  as it stands; a block that shows one section (``masses:``, ``crank:``, ``balance:``,
  ``gas:``, ``bearings:``, ``mounts:``…) is loaded inside the first example of
  docs/layout-format.md, its keys replacing that layout's.  A block that is a deliberate
  error example is marked ``<!-- invalid layout example -->`` on the line before its fence
  and must be refused.
- docs/layouts.md lists every built-in layout with its name, cylinder count and speed.
- Two things of the new-user run of the README: ``balance propose`` of a single says
  "1 cylinder", and ``balance mounts`` shows its top speed and says which speeds it shows.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml
from typer.testing import CliRunner

import balance
from balance.cli import app
from balance.io.layout_file import builtin_layout_names

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
INVALID = "<!-- invalid layout example -->"
FENCE = re.compile(r"^(?P<indent>[ \t]*)```yaml[ \t]*\n(?P<body>.*?)^(?P=indent)```", re.S | re.M)


def _yaml_blocks() -> list[tuple[str, int, str, bool]]:
    """(page, line, text, invalid) of every ```yaml block of docs/*.md and the README."""
    blocks = []
    for page in [*sorted(DOCS.glob("*.md")), ROOT / "README.md"]:
        text = page.read_text(encoding="utf-8")
        for m in FENCE.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            before = text[: m.start()].rstrip().rsplit("\n", 1)[-1].strip()
            indent = m.group("indent")
            body = "".join(
                row[len(indent) :] if row.startswith(indent) else row
                for row in m.group("body").splitlines(keepends=True)
            )
            blocks.append((page.name, line, body, before == INVALID))
    return blocks


BLOCKS = _yaml_blocks()


def _base() -> dict:
    """The first example of docs/layout-format.md: a whole layout."""
    page, _, text, _ = next(b for b in BLOCKS if b[0] == "layout-format.md")
    data = yaml.safe_load(text)
    assert "name" in data, f"the first YAML block of {page} is not a whole layout"
    return data


def _as_layout(fragment: object) -> dict:
    """A whole layout: the fragment itself, or the base layout with the fragment's keys."""
    if isinstance(fragment, list):  # a list of cylinder entries
        fragment = {"cylinders": fragment}
    assert isinstance(fragment, dict)
    if "name" in fragment:
        return fragment
    layout = {**_base(), **fragment}
    if "crank" in fragment:
        layout.pop("cylinders", None)
    parts = {"link", "piston_group", "conrod", "conrod_cg_to_big_end", "conrod_inertia"}
    if "masses" not in fragment and any(
        parts & set(entry) for entry in layout.get("cylinders", [])
    ):  # a link cylinder, or part keys in a cylinder's entry, need masses by part
        layout["masses"] = {
            "piston_group": "0.42 kg",
            "conrod": "0.55 kg",
            "conrod_cg_to_big_end": "38 mm",
        }
    return layout


def test_the_docs_have_yaml_examples():
    pages = {page for page, *_ in BLOCKS}
    assert {"layout-format.md", "tutorial.md", "conventions.md", "mounts.md"} <= pages
    assert sum(page == "layout-format.md" for page, *_ in BLOCKS) >= 10


@pytest.mark.parametrize(
    ("page", "line", "text", "invalid"),
    BLOCKS,
    ids=[f"{page}:{line}" for page, line, _, _ in BLOCKS],
)
def test_every_yaml_example_of_the_docs_loads(page, line, text, invalid, tmp_path):
    layout = _as_layout(yaml.safe_load(text))
    # a pressure trace is named relative to the layout file, as in layouts/
    (tmp_path / "traces").symlink_to(ROOT / "layouts" / "traces")
    path = tmp_path / "example.yaml"
    path.write_text(yaml.safe_dump(layout, sort_keys=False), encoding="utf-8")
    if invalid:
        with pytest.raises(balance.LayoutError):
            balance.load_layout(path)
        return
    engine = balance.load_layout(path)
    assert engine.n_cylinders >= 1, f"{page}:{line}"


def test_layouts_page_lists_every_built_in_layout():
    """docs/layouts.md gives each built-in its name, cylinder count and speed as the file
    does (the idealised radials are listed together, by name)."""
    text = (DOCS / "layouts.md").read_text(encoding="utf-8")
    entries = {
        m["key"]: m
        for m in re.finditer(
            r"^`(?P<key>[\w-]+)`: \*\*(?P<name>.+?)\*\*, (?P<n>\d+) cylinders?, (?P<rpm>\d+) rpm$",
            text,
            re.M,
        )
    }
    for key in builtin_layout_names():
        data = yaml.safe_load((ROOT / "layouts" / f"{key}.yaml").read_text(encoding="utf-8"))
        if key.endswith("-idealised"):
            assert f"`{key}`" in text, key
            continue
        assert key in entries, f"docs/layouts.md has no entry for {key}"
        entry = entries[key]
        assert entry["name"] == data["name"], key
        assert int(entry["n"]) == balance.load_layout(key).n_cylinders, key
        assert f"{entry['rpm']} rpm" == data["speed"], key


def test_propose_on_a_single_says_one_cylinder():
    result = CliRunner().invoke(app, ["propose", "single", "--orders", "1"], env={"COLUMNS": "100"})
    assert result.exit_code == 0, result.output
    assert "\n1 cylinder at 7500 rpm\n" in result.output


def test_mounts_table_says_which_speeds_it_shows_and_ends_at_the_top_speed():
    result = CliRunner().invoke(
        app,
        ["mounts", "inline-4-mounts", "--speed", "800rpm:8000rpm:200", "--orders", "2"],
        env={"COLUMNS": "200"},
    )
    assert result.exit_code == 0, result.output
    assert "\nrows: one per 8 speeds and the top speed; all 200 with --format csv or json\n" in (
        result.output
    )
    table = result.output.split("Largest mount force against speed", 1)[1].split("└", 1)[0]
    speeds = [float(r.split("│")[1]) for r in table.splitlines() if r.startswith("│")]
    assert speeds[0] == 800 and speeds[-1] == 8000
    assert len(speeds) == 26  # one row per 8 of 200 speeds (25 rows) and the top speed
