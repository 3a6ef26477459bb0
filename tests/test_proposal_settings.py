"""The balancing proposal as a designer reads it (issue 22, "Balancing and notes"): the
balance factor's two conventions, notes computed from the residual they describe, default
shaft axes within the crank train's reach, per-throw counterweights in z order, and shafts at
speed ratios that are not whole numbers."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest
from typer.testing import CliRunner

from balance.cli import app

runner = CliRunner()

INLINE4 = """\
name: Test engine
speed: 6000 rpm
geometry: {stroke: 86 mm, conrod_length: 139 mm}
masses: {reciprocating: 0.55 kg, rotating: 0.4 kg}
crank: {throws: [0, 180, 180, 0], spacing: 90 mm}
"""


def run(*args: str):
    return runner.invoke(app, list(args))


def _write(tmp_path, text: str, name: str = "engine.yaml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


# --- per-throw counterweights in z order ---------------------------------------------------


@pytest.mark.parametrize("name", ["v8-crossplane", "v6-90-split", "inline-4", "radial-5"])
def test_per_throw_counterweights_are_listed_along_the_crank(name):
    """The counterweights of the per-throw strategy come in z order (throws in one plane by
    angle), in the JSON and so in every view; the v8-crossplane's were listed by angle."""
    result = run("propose", name, "--strategy", "per-throw", "-f", "json", "--orders", "1-2")
    assert result.exit_code == 0, result.stderr
    import json

    weights = json.loads(result.stdout)["proposal"]["counterweights"]
    keys = [(w["z_m"], w["angle_deg"]) for w in weights]
    assert keys == sorted(keys)
    assert len({w["z_m"] for w in weights}) > 1 or name == "radial-5"


# --- balance shafts at speed ratios that are not whole numbers -----------------------------


@pytest.mark.parametrize("ratio", ["1.5", "-0.5", "2.25"])
def test_a_shaft_at_a_ratio_that_is_not_whole_is_refused_with_the_reason(tmp_path, ratio):
    """A shaft at 1.5 x crank speed cancels no engine order (the inertia forces have whole
    orders only): refused in one line naming file, line, column and field, saying why."""
    path = _write(
        tmp_path,
        INLINE4 + f"balance:\n  shafts:\n    - {{speed_ratio: {ratio}, x: 80 mm}}\n",
    )
    result = run("propose", str(path))
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 1
    order = f"{abs(float(ratio)):g}"
    assert result.stderr == (
        f"balance: {path}:8:21: balance.shafts[1].speed_ratio: speed_ratio is "
        f"{float(ratio):g}: a shaft at a ratio that is not a whole number turns at order "
        f"{order}, which the engine's inertia forces do not have (their orders are whole "
        "numbers), so it cancels nothing and adds a shaking force of its own; a whole number "
        "from -64 to 64 other than 0, e.g. 2 or -2 (negative: against the crank)\n"
    )


def test_an_infinite_speed_ratio_is_refused_not_an_internal_error(tmp_path):
    path = _write(tmp_path, INLINE4 + "balance:\n  shafts:\n    - {speed_ratio: .inf}\n")
    result = run("propose", str(path))
    assert result.exit_code == 2
    assert "balance.shafts[1].speed_ratio: speed_ratio is inf; a whole number" in result.stderr
    assert "internal error" not in result.stderr


def test_whole_ratios_written_as_floats_still_work(tmp_path):
    """2.0 is the whole number 2 (as before)."""
    path = _write(tmp_path, INLINE4 + "balance:\n  shafts:\n    - {speed_ratio: 2.0}\n")
    result = run("propose", str(path), "-f", "json", "--orders", "1-2")
    assert result.exit_code == 0, result.stderr
    import json

    shafts = json.loads(result.stdout)["proposal"]["balance_shafts"]
    assert [s["speed_ratio"] for s in shafts] == [2]
    assert np.isfinite(shafts[0]["x_m"])
