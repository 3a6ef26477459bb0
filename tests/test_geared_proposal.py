"""Balancing proposals with several crankshafts (docs/several-crankshafts.md, "Proposals"):
counterweights turn with their crankshaft, so a counter-rotating shaft's counterweights
cancel a backward first order; a balance factor applies per cylinder on its own shaft;
``two-plane`` uses each shaft's end planes; the JSON names each counterweight's shaft and
the residual's moment about z; ``balance propose`` takes a file with crankshafts.  The
residual is checked against point masses in tests/test_geared_brute_force.py."""

from __future__ import annotations

import json
import math
import textwrap

import numpy as np
import pytest
from typer.testing import CliRunner

from balance.api import compute_result
from balance.cli import app
from tests.geared_engines import twin_crank

runner = CliRunner()
M_R = 0.6 * 0.043  # the helper's reciprocating mass times crank radius [kg m]


def test_counter_rotating_twin_crank_needs_no_first_order_balance_shaft():
    """Each crank takes its own cylinder's forward (or backward) half and shares the other
    cylinder's half of its sense: 100 % of one reciprocating mass on each crank, first order
    0, no shaft at +-1."""
    engine = twin_crank(-1.0, counterweighted=False)
    part = compute_result(engine).part("proposal")
    proposal = part.proposal
    assert [abs(s.speed_ratio) for s in proposal.shafts] == [2, 2]  # the second order only
    assert [(c.axis, c.sense) for c in proposal.counterweights] == [("shaft1", 1), ("shaft2", -1)]
    m_rot_r = float(engine.rotating_mass[0] * engine.crank_radius[0])
    for c in proposal.counterweights:  # opposite the pin (0 deg), big end + 100 % of m_rec
        np.testing.assert_allclose(c.unbalance, -(m_rot_r + M_R), rtol=1e-14)
    assert part.residual.force_forward[0] == 0.0 and part.residual.force_backward[0] == 0.0
    assert part.residual_moment_z[0] == 0.0
    assert part.left == ()


def test_co_rotating_twin_crank_still_needs_a_backward_shaft():
    engine = twin_crank(1.0, counterweighted=False)
    part = compute_result(engine).part("proposal")
    ratios = [s.speed_ratio for s in part.proposal.shafts]
    assert -1 in ratios
    back = next(s for s in part.proposal.shafts if s.speed_ratio == -1)
    # the two cylinders' backward halves: m_rec r per... 2 x 0.5 x m_rec r
    np.testing.assert_allclose(abs(back.total_unbalance), M_R, rtol=1e-12)
    for c in part.proposal.counterweights:  # each its big end and its forward half
        np.testing.assert_allclose(
            c.unbalance, -(engine.rotating_mass[0] * engine.crank_radius[0] + 0.5 * M_R)
        )
    assert part.residual.force_forward[0] == 0.0 and part.residual.force_backward[0] == 0.0


def test_a_balance_factor_applies_per_cylinder_on_its_own_crankshaft():
    """50 %: each crank's counterweight is its big end and half its piston, opposite its
    own pin; the counter-rotating twin then leaves half of each first-order half."""
    engine = twin_crank(-1.0, counterweighted=False)
    part = compute_result(engine, balance_factor=0.5).part("proposal")
    m_rot_r = float(engine.rotating_mass[0] * engine.crank_radius[0])
    for c in part.proposal.counterweights:
        np.testing.assert_allclose(c.unbalance, -(m_rot_r + 0.5 * M_R), rtol=1e-14)
    w2 = engine.speed**2
    # forward: cylinder 1's half + cylinder 2's half (2 x 0.5 M_R) less crank 1's 0.5 M_R
    np.testing.assert_allclose(abs(part.residual.force_forward[0]), 0.5 * M_R * w2, rtol=1e-12)
    np.testing.assert_allclose(abs(part.residual.force_backward[0]), 0.5 * M_R * w2, rtol=1e-12)


def test_two_plane_uses_each_crankshafts_own_end_planes():
    """An H16-like pair (tests/test_geared_brute_force.py): every counterweight sits at an end
    plane of its own shaft's cylinders."""
    from tests.test_geared_brute_force import h16_like

    engine = h16_like()
    proposal = compute_result(engine).part("proposal").proposal
    of = engine.crankshafts.of_cylinder
    for c in proposal.counterweights:
        s = engine.crankshafts.names.index(c.axis)
        planes = {float(engine.z[of == s].min()), float(engine.z[of == s].max())}
        assert c.z in planes


TWIN = """\
name: twin-crank twin
speed: 6000 rpm
geometry: {stroke: 86 mm, conrod_length: 150 mm}
masses: {reciprocating: 0.6 kg, rotating: 0.4 kg}
crankshafts:
  - {name: left, x: -45 mm}
  - {name: right, x: 45 mm, rotation: opposite}
cylinders:
  - {crankshaft: left, throw: 0 deg, bank: 0 deg, z: 0 mm}
  - {crankshaft: right, throw: 0 deg, bank: 0 deg, z: 0 mm}
"""


@pytest.mark.parametrize("strategy", ["two-plane", "per-throw"])
def test_balance_propose_names_each_counterweights_crankshaft(tmp_path, strategy):
    path = tmp_path / "twin.yaml"
    path.write_text(textwrap.dedent(TWIN))
    got = runner.invoke(app, ["propose", str(path), "--format", "json", "--strategy", strategy])
    assert got.exit_code == 0, got.output
    block = json.loads(got.stdout)["proposal"]
    weights = block["counterweights"]
    assert [w["crankshaft"] for w in weights] == ["left", "right"]
    # 0.4 kg big end + 0.6 kg piston at the crank radius, opposite the pin (180 deg)
    for w in weights:
        assert math.isclose(w["mass_kg"], 1.0, rel_tol=1e-12)
        assert w["angle_deg"] == 180.0
    assert [s["speed_ratio"] for s in block["balance_shafts"]] == [2, -2]
    residual = block["residual"]
    assert residual["force"][0]["peak"] == 0.0
    assert residual["moment_z"][0] == {"order": 1, "peak": 0.0}


def test_one_crank_proposal_json_has_no_crankshaft_keys(tmp_path):
    got = runner.invoke(app, ["propose", "single", "--format", "json"])
    assert got.exit_code == 0, got.output
    block = json.loads(got.stdout)["proposal"]
    assert "crankshaft" not in block["counterweights"][0]
    assert "moment_z" not in block["residual"]
