"""Crank-arrangement search: the known best answers, symmetry, CLI."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from balance.cli import app
from balance.studies.search import firing_order, search

runner = CliRunner()


def test_inline_4_flat_crank():
    result = search(4, even_firing=True)
    assert result.best[0].throws == (0.0, 180.0, 180.0, 0.0)
    assert result.best[0].force_peaks[0] == 0.0 and result.best[0].moment_peaks == (0.0, 0.0)
    assert result.enumerated == 12**3 and result.evaluated == 3


def test_inline_6_120_crank_is_balanced():
    result = search(6, even_firing=True)
    best = result.best[0]
    assert best.score == 0.0 and best.shafts == 0
    assert sorted(best.throws) == [0.0, 0.0, 120.0, 120.0, 240.0, 240.0]
    assert best.throws[:3] == tuple(reversed(best.throws[3:]))  # mirror-symmetric crank
    assert result.best[1].score > 0  # the answer is unique up to symmetry


def test_v8_cross_plane_beats_flat_plane():
    result = search(8, (-45.0, 45.0), even_firing=True, step=45.0)
    best = result.best[0]
    assert best.throws == (0.0, 90.0, 270.0, 180.0) and not any(best.splits)
    assert best.score == 0.0 and best.firing_order is not None
    flat = next(
        a for a in result.best if a.throws in {(0.0, 180.0, 180.0, 0.0), (0.0, 0.0, 180.0, 180.0)}
    )
    assert flat.force_peaks[1] > 1.0  # the flat-plane's second-order force


def test_symmetry_removes_duplicates():
    result = search(4, step=90.0)
    # 64 codes; mirror images and reflections removed
    assert result.enumerated == 64 and result.evaluated < 30


def test_firing_order():
    assert firing_order([0, 180, 180, 0], [0, 0, 0, 0]) == (1, 2, 4, 3)
    assert firing_order([0, 90, 90, 0], [0, 0, 0, 0]) is None


def test_cli_search_prints_best():
    result = runner.invoke(app, ["search", "--cylinders", "4", "--even-firing", "--top", "2"])
    assert result.exit_code == 0, result.stderr
    first = next(line for line in result.stdout.splitlines() if "0/180/180/0" in line)
    assert first.split()[1] == "1"  # ranked first
    assert "arrangements enumerated" in result.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--cylinders", "5", "--banks", "-45,45"], "cannot be shared"),
        (["--cylinders", "4", "--step", "7deg"], "does not divide"),
        (["--cylinders", "4", "--step", "7mm"], "--step: '7mm' is a length, not an angle"),
        (["--cylinders", "4", "--banks", "0,9kg"], "--banks: '9kg' is a mass, not an angle"),
        (["--cylinders", "4", "--objective", "best"], "--objective"),
    ],
)
def test_cli_search_errors(args, message):
    result = runner.invoke(app, ["search", *args])
    assert result.exit_code == 2
    assert message in result.stderr and result.stderr.count("\n") == 1
