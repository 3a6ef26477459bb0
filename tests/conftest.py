"""Shared test fixtures and hypothesis profiles."""

from __future__ import annotations

import gc
import os
import subprocess
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pytest
import typer.testing


def _hypothesis_not_rewritten() -> None:
    """pytest rewrites the asserts of every module of a package that provides a plugin,
    hypothesis included: some 75 modules of hypothesis's internals, parsed, rewritten and
    compiled again by each test process (their pyc cannot be kept where bytecode is not
    written).  Their asserts are hypothesis's own invariants, not ours; they are imported
    as they are.  Must run before hypothesis is first imported (here, below)."""
    for finder in sys.meta_path:
        marked = getattr(finder, "_must_rewrite", None)
        if type(finder).__name__ == "AssertionRewritingHook" and isinstance(marked, set):
            marked.discard("hypothesis")


_hypothesis_not_rewritten()

from hypothesis import settings  # noqa: E402

settings.register_profile("default", max_examples=60, deadline=None)
settings.register_profile("ci", max_examples=60, deadline=None, derandomize=True)
settings.register_profile("long", max_examples=2000, deadline=None)
settings.load_profile(
    os.environ.get("HYPOTHESIS_PROFILE", "ci" if os.environ.get("CI") else "default")
)


def _built_once(build):
    """typer's CliRunner builds the click command of the whole application (every command,
    its options and their type adapters: about 30 ms) on every invoke, and the tests invoke
    the same application hundreds of times; build it once per application (and again if
    commands are added).  Click commands are made to be invoked many times."""
    built = {}

    def get(app):
        key = (id(app), len(app.registered_commands), len(app.registered_groups))
        if key not in built:
            built[key] = (app, build(app))  # holding the app keeps its id unique
        return built[key][1]

    return get


typer.testing._get_command = _built_once(typer.testing._get_command)


def pytest_collection_finish(session: pytest.Session) -> None:
    """Move what the imports and the collection made (some 160 000 objects: numpy, xarray,
    matplotlib, the test modules) out of the garbage collector's sight: they live as long as
    the process, and each full collection of a test process would walk them again (about
    40 full collections in a worker's run).  Garbage made by the tests is collected as
    before."""
    gc.collect()
    gc.freeze()


@pytest.hookimpl(trylast=True)
def pytest_runtest_teardown(item: pytest.Item) -> None:
    """pytest-mpl keeps each image test's figure, by test name, for the rest of the run
    (``ImageComparison.return_value``); it has compared and closed it by now, so let it go
    (17 figures and their artists, which every later full garbage collection would walk)."""
    for plugin in item.config.pluginmanager.get_plugins():
        figures = getattr(plugin, "return_value", None)
        if type(plugin).__name__ == "ImageComparison" and isinstance(figures, dict):
            figures.clear()


@pytest.fixture(autouse=True)
def _no_ambient_terminal_size(monkeypatch: pytest.MonkeyPatch) -> None:
    """Tests do not depend on the terminal they are run from: ``COLUMNS`` and ``LINES``
    exported by a shell (or set by a test runner's worker) would change the width of every
    table printed; a test that wants a width sets it itself (``env={"COLUMNS": "80"}``)."""
    monkeypatch.delenv("COLUMNS", raising=False)
    monkeypatch.delenv("LINES", raising=False)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261122)


class FreshProcess(NamedTuple):
    """What :func:`fresh_process` ran: the finished process and the files it wrote."""

    done: subprocess.CompletedProcess[str]
    report: Path  # ``balance report inline-3``
    directory: Path  # ``balance plot inline-3 -k locus -k roll``


#: Run in a fresh interpreter: import balance and its views, build every plot kind (those
#: the report does not draw here, the report's by the report), run ``balance report`` and
#: ``balance plot``; after each step, assert that no pyplot (and no xarray) was imported.
#: The commands are given as arguments: the number of the report's, then the report's and
#: the plot's.
FRESH_PROCESS_CODE = """\
import sys, balance, balance.views.plots, balance.views.report, balance.views.signals
from balance.core.analysis import compute
from balance.core.result import Request
from balance.cli import main
from balance.views.plots import all_kinds, plot_kind
assert 'matplotlib' not in sys.modules, 'matplotlib imported at import time'
result = compute(balance.load_layout('inline-3'), Request())
in_report = {'crank_star', 'phasors', 'crank_angle', 'locus', 'spectrum', 'roll', 'balance'}
figures = [plot_kind(kind)(result) for kind in all_kinds() if kind not in in_report]
assert 'matplotlib.pyplot' not in sys.modules, 'pyplot imported'
assert 'xarray' not in sys.modules, 'xarray imported'
split = 2 + int(sys.argv[1])
for args in (sys.argv[2:split], sys.argv[split:]):  # the report (SVG), the plot (PNG, Agg)
    sys.argv = ['balance', *args]
    try:
        main()
    except SystemExit as stop:
        assert not stop.code, (args, stop.code)
    assert 'matplotlib.pyplot' not in sys.modules, ('pyplot imported', args)
    assert 'xarray' not in sys.modules, ('xarray imported', args)
"""


@pytest.fixture(scope="session")
def fresh_process(tmp_path_factory: pytest.TempPathFactory) -> FreshProcess:
    """One fresh Python process for the checks that need one (one start of Python and
    matplotlib, one report): ``test_plots.py`` checks what it imported, and
    ``test_report.py`` that the report it wrote is byte for byte the report drawn in this
    process (a report does not depend on the process: hash seed, time, object ids)."""
    directory = tmp_path_factory.mktemp("fresh-process")
    report = ["report", "inline-3", "-o", str(directory / "r.html")]
    plot = ["plot", "inline-3", "-k", "locus", "-k", "roll", "-o", str(directory)]
    done = subprocess.run(
        [sys.executable, "-c", FRESH_PROCESS_CODE, str(len(report)), *report, *plot],
        capture_output=True,
        text=True,
        check=False,
    )
    return FreshProcess(done, directory / "r.html", directory)


class SectionsReport(NamedTuple):
    """What :func:`sections_report` ran: the command's result and the page it wrote."""

    result: typer.testing.Result
    html: str


@pytest.fixture(scope="session")
def sections_report(tmp_path_factory: pytest.TempPathFactory) -> SectionsReport:
    """``balance report inline-4-mounts --bearings``: one report with both optional
    sections, the engine on its mounts (the layout's ``mounts:``) and the bearing loads,
    for the tests of each (test_mounts_analysis.py, test_bearings_cli.py): a report draws
    its seven figures whatever sections it has, so one report instead of two."""
    from balance.cli import app

    path = tmp_path_factory.mktemp("sections") / "r.html"
    result = typer.testing.CliRunner().invoke(
        app, ["report", "inline-4-mounts", "--bearings", "-o", str(path)]
    )
    return SectionsReport(result, path.read_text(encoding="utf-8") if path.exists() else "")
