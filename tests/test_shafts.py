"""Balance shafts and the roll: placing shafts to cancel it, saying when they make it worse,
and shafts whose positions the layout fixes (``balance: shafts:``).

Every roll is checked against the independent crank-angle computation: the engine's roll by
Newton-Euler (:func:`balance.core.sampled.roll_newton_euler`) plus the shafts' forces
sampled at their axes (``proposal_roll_samples`` of ``tests/oracles.py``), transformed by
FFT.
"""

from __future__ import annotations

import json
import math
import textwrap
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from oracles import proposal_force_samples, proposal_roll_samples
from test_phasors import random_layouts
from typer.testing import CliRunner

from balance.api import Engine, load_layout
from balance.cli import app
from balance.core import sampled as td
from balance.core.analysis import compute, compute_phasors
from balance.core.balancing import Proposal
from balance.core.engine import ShaftPosition
from balance.core.errors import LayoutError
from balance.core.proposal import balance_engine
from balance.core.shafts import SHAFT_CLEARANCE
from balance.io.layout_file import expand_layout, layout_from_text
from balance.io.request import build_request
from balance.views.report import render_report

ORDERS = np.arange(1, 5)
K2 = 1  # index of order 2 in ORDERS
runner = CliRunner()


def _sampled_roll(layout: Engine, proposal: Proposal) -> np.ndarray:
    """Roll phasors of the engine (Newton-Euler) and the shafts (sampled forces) together."""
    theta = td.crank_angles(256)
    torque = td.roll_newton_euler(layout, theta) + proposal_roll_samples(proposal, layout, theta)
    return td.roll_phasors_from_samples(torque, ORDERS)


def _sampled_force(layout: Engine, proposal: Proposal) -> tuple[np.ndarray, np.ndarray]:
    """Forward and backward phasors of the whole free force with every proposed mass."""
    theta = td.crank_angles(256)
    force = (
        td.reciprocating_force_samples(layout, theta)
        + td.rotating_force_samples(layout, theta)
        + proposal_force_samples(proposal, layout, theta)
    )
    return td.phasors_from_samples(force, ORDERS)


def _roll_unit(layout: Engine) -> float:
    """m_rec r^2 w^2 of the largest cylinder [N m]."""
    return float(np.max(layout.reciprocating_mass * layout.crank_radius**2) * layout.speed**2)


def _balanced(layout: Engine, **options):
    return balance_engine(layout, compute_phasors(layout, ORDERS), **options)


def run(*args: str):
    return runner.invoke(app, list(args))


# --- the engines: shafts that add roll where the engine has none --------------------


@pytest.mark.parametrize("name", ["v-twin-90", "v4-90-180"])
def test_default_pair_adds_second_order_roll_the_engine_does_not_have(name):
    """Issue 13: a 90 deg V-twin (Ducati 916) and a 90 deg V4 with a 180 deg crank (Honda
    VFR750F) have no second-order roll of their own; the Lanchester pair at its default
    place adds 2 r F2 (theory docs: the shafts at (-r, -sqrt(3) r) and (r, -sqrt(3) r), each
    carrying half of the horizontal line force of peak F2, so the roll's amplitude is
    F2/2 |(y+ + y-) + i(x- - x+)| = F2/2 |2 sqrt(3) r + 2i r| = 2 r F2; it was 2 sqrt(2) r F2
    with the former axes (-2r, -2r) and (2r, -2r)), and the notes say so."""
    layout = load_layout(name)
    result = compute_phasors(layout, ORDERS)
    balanced = balance_engine(layout, result)
    sampled = _sampled_roll(layout, balanced.proposal)
    unit = _roll_unit(layout)
    assert result.phasors.roll[K2] == 0.0
    f2 = abs(result.phasors.force_forward[K2]) + abs(result.phasors.force_backward[K2])
    r = float(np.mean(layout.crank_radius))
    expected = 2 * r * f2
    assert abs(balanced.residual.roll[K2]) == pytest.approx(expected, rel=1e-12)
    assert abs(sampled[K2] - balanced.residual.roll[K2]) <= 1e-9 * unit
    assert (
        f"order 2: the balance shafts raise the roll from 0 to {expected:.4g} N m"
        in (balanced.proposal.notes[0])
    )
    assert "the setting cancel_roll" in balanced.proposal.notes[0]


@pytest.mark.parametrize("name", ["v-twin-90", "v4-90-180"])
def test_cancel_roll_cancels_the_pairs_own_roll(name):
    """With cancel_roll the pair sits on either side of the crank axis across its horizontal
    force, sqrt(2) x 2r from it (the nearest placement to the default would be on the crank
    axis); the second-order roll of engine and shafts is zero by Newton-Euler plus sampled
    shaft torque, and the force is still cancelled."""
    layout = load_layout(name)
    balanced = _balanced(layout, cancel_roll=True)
    proposal = balanced.proposal
    assert balanced.residual.roll[K2] == 0.0
    assert abs(_sampled_roll(layout, proposal)[K2]) <= 1e-9 * _roll_unit(layout)
    fwd, bwd = _sampled_force(layout, proposal)
    f1 = float(np.max(layout.reciprocating_mass * layout.crank_radius) * layout.speed**2)
    assert abs(fwd[K2]) <= 1e-9 * f1 and abs(bwd[K2]) <= 1e-9 * f1
    distance = math.sqrt(2) * SHAFT_CLEARANCE * float(np.mean(layout.crank_radius))
    forward, backward = proposal.shafts
    assert (forward.speed_ratio, backward.speed_ratio) == (2, -2)
    assert (forward.x, backward.x) == (0.0, 0.0)
    assert forward.y == pytest.approx(-distance, rel=1e-12)
    assert backward.y == pytest.approx(distance, rel=1e-12)
    assert (forward.x_from, forward.y_from) == ("cancel-roll", "cancel-roll")
    assert "on either side of the crank axis" in proposal.notes[0]
    assert not any("raise the roll" in note for note in proposal.notes)


def test_inline4_heights_differ_by_the_conrod_length():
    """The Mitsubishi arrangement (Nakamura, SAE 760111, 1976): a Lanchester pair at two
    heights cancels the inline-4's second-order roll.  With a two-mass rod (no inertia
    correction) the heights differ by l / (1 + lambda^2/4) (theory docs; the leading term l
    is the classical result), to O(lambda^4); the roll is zero by Newton-Euler."""
    text = _file(
        """\
        geometry: {stroke: 20 mm, conrod_length: 400 mm}
        masses: {reciprocating: 0.5 kg, rotating: 0.4 kg}
        crank: {throws: [0, 180, 180, 0], spacing: 90 mm}
        """
    )
    layout = layout_from_text(text)
    proposal = _balanced(layout, cancel_roll=True).proposal
    lam = 0.01 / 0.4
    forward, backward = proposal.shafts
    height = abs(forward.y - backward.y)
    assert abs(height / 0.4 * (1 + lam**2 / 4) - 1) <= lam**4
    assert (forward.x, backward.x) == (-0.01, 0.01)  # lateral positions kept (defaults, -/+r)
    assert (forward.x_from, forward.y_from) == ("default", "cancel-roll")
    assert abs(_sampled_roll(layout, proposal)[K2]) <= 1e-9 * _roll_unit(layout)


@pytest.mark.parametrize("shift", [37.0, 200.0])
@pytest.mark.parametrize("name", ["v-twin-90", "inline-4"])
def test_placement_does_not_depend_on_the_crank_angle_origin(name, shift):
    """Measuring crank angles from another origin turns every throw by the same angle: the
    shaft axes, the eccentrics' sizes and the residual roll amplitudes stay the same."""
    layout = load_layout(name)
    turned = replace(layout, throw=layout.throw + math.radians(shift))
    a = _balanced(layout, cancel_roll=True)
    b = _balanced(turned, cancel_roll=True)
    scale = float(np.mean(layout.crank_radius))
    for sa, sb in zip(a.proposal.shafts, b.proposal.shafts, strict=True):
        assert sa.speed_ratio == sb.speed_ratio
        assert abs(sa.x - sb.x) <= 1e-9 * scale and abs(sa.y - sb.y) <= 1e-9 * scale
        assert abs(sa.total_unbalance) == pytest.approx(abs(sb.total_unbalance), rel=1e-9)
    np.testing.assert_allclose(
        np.abs(a.residual.roll), np.abs(b.residual.roll), rtol=0, atol=1e-9 * _roll_unit(layout)
    )


def test_one_shaft_cannot_cancel_roll_near_the_crank_axis():
    """A single's -1 shaft would have to sit 2.8 mm from the crank axis to cancel the first
    order roll: it stays, the notes say why, and that it raises the roll; the second-order
    pair is placed and its roll is zero (across its vertical force: the placement nearest to
    the default axes, 2r from the crank axis at x = -/+r, would crowd the crank)."""
    layout = load_layout("single")
    balanced = _balanced(layout, cancel_roll=True)
    notes = balanced.proposal.notes
    first = next(s for s in balanced.proposal.shafts if s.speed_ratio == -1)
    assert (first.x, first.y) == (0.0, -2 * float(layout.crank_radius[0]))
    assert notes[0].startswith("order 1: one shaft (at -1) would cancel the roll only with")
    assert "within the 84.5 mm kept free for the crank" in notes[0]
    assert notes[1].startswith("order 1: the balance shafts raise the roll from 24.71 to")
    assert notes[2].startswith("order 2: shafts placed on either side of the crank axis")
    sampled = _sampled_roll(layout, balanced.proposal)
    assert abs(sampled[K2]) <= 1e-9 * _roll_unit(layout)
    assert abs(sampled[0] - balanced.residual.roll[0]) <= 1e-9 * _roll_unit(layout)


def test_a_shaft_placed_beyond_the_crank_trains_reach_is_noted():
    """radial-9's first-order roll (200.7 N m) needs its -1 shaft 804.6 mm above the crank
    axis, more than twice crank radius + conrod length (65 + 250 mm): cancelled on paper, so
    the note says so; the inline-4's pair (at -/+121.6 mm, heights 70.2 and -70.2 mm) gets no
    such note."""
    layout = load_layout("radial-9")
    balanced = _balanced(layout, cancel_roll=True)
    first = next(s for s in balanced.proposal.shafts if s.speed_ratio == -1)
    assert first.y == pytest.approx(0.8046, abs=1e-4) and first.x == 0.0
    note = balanced.proposal.notes[0]
    assert note.startswith("order 1: shaft placed to cancel the roll: -1 at x = 0 mm")
    assert "the shaft at -1 is 804.6 mm from the crank axis, beyond the crank train's reach" in (
        note
    )
    assert "(crank radius + conrod length = 315 mm)" in note
    sampled = _sampled_roll(layout, balanced.proposal)
    assert abs(sampled[0]) <= 1e-9 * _roll_unit(layout)  # the roll is cancelled all the same
    inline = _balanced(load_layout("inline-4"), cancel_roll=True)
    assert not any("reach" in n for n in inline.proposal.notes)


def test_shafts_carrying_pure_couples_cannot_move_the_roll():
    """A boxer twin's shafts carry couples only (no net force): no torque about the crank
    axis wherever they sit, so the engine's roll stays and the notes say why."""
    layout = load_layout("boxer-2")
    balanced = _balanced(layout, cancel_roll=True)
    assert balanced.proposal.notes[1].startswith(
        "order 2: the shafts carry pure couples (no net force)"
    )
    result = compute_phasors(layout, ORDERS)
    assert abs(balanced.residual.roll[K2]) == pytest.approx(abs(result.phasors.roll[K2]), rel=1e-12)
    assert abs(result.phasors.roll[K2]) > 0.1 * _roll_unit(layout)


@settings(max_examples=30)
@given(layout=random_layouts(max_cylinders=6))
def test_random_layouts_roll_cancelled_or_said_why(layout):
    """For any layout, each order that has shafts ends with zero roll (Newton-Euler plus the
    sampled shafts), or a note of that order says why not; placed axes keep the clearance."""
    balanced = balance_engine(layout, compute_phasors(layout, ORDERS), cancel_roll=True)
    proposal = balanced.proposal
    sampled = _sampled_roll(layout, proposal)
    unit = _roll_unit(layout) + float(np.sum(np.abs(layout.conrod_inertia_correction))) * (
        layout.speed**2
    )
    clearance = SHAFT_CLEARANCE * float(np.mean(layout.crank_radius))
    for k in sorted({abs(s.speed_ratio) for s in proposal.shafts}):
        said = [n for n in proposal.notes if n.startswith(f"order {k}:") and "placed" not in n]
        assert said or abs(sampled[k - 1]) <= 1e-9 * unit, (k, proposal.notes)
        for shaft in proposal.shafts:
            if "cancel-roll" in (shaft.x_from, shaft.y_from):
                assert math.hypot(shaft.x, shaft.y) >= clearance * (1 - 1e-9)


# --- fixed shafts: balance: shafts: --------------------------------------------------------

INLINE4 = """\
geometry: {stroke: 86 mm, conrod_length: 139 mm}
masses: {reciprocating: 0.55 kg, rotating: 0.4 kg}
crank: {throws: [0, 180, 180, 0], spacing: 90 mm}
"""


def _file(body: str, balance: str = "") -> str:
    head = "name: Test engine\nspeed: 6000 rpm\n"
    return head + textwrap.dedent(body) + textwrap.dedent(balance)


def test_fixed_shafts_as_in_the_contract():
    """CONTRACT 3's example: the shafts at the given axes, their unbalances as the default
    proposal's; the force is cancelled and the roll reported is the Newton-Euler one."""
    text = _file(
        INLINE4,
        """\
        balance:
          shafts:
            - {speed_ratio: 2, x: 80 mm, y: -90 mm}
            - {speed_ratio: -2, x: -80 mm, y: -90 mm}
        """,
    )
    layout = layout_from_text(text)
    assert layout.balance is not None and layout.balance.shafts == (
        ShaftPosition(2, 0.08, -0.09),
        ShaftPosition(-2, -0.08, -0.09),
    )
    fixed = _balanced(layout)
    free = _balanced(replace(layout, balance=None))
    for a, b in zip(fixed.proposal.shafts, free.proposal.shafts, strict=True):
        assert a.speed_ratio == b.speed_ratio and a.planes == b.planes
        assert (a.x_from, a.y_from) == ("layout", "layout")
    assert [(s.x, s.y) for s in fixed.proposal.shafts] == [(0.08, -0.09), (-0.08, -0.09)]
    fwd, bwd = _sampled_force(layout, fixed.proposal)
    f1 = 0.55 * 0.043 * layout.speed**2
    assert abs(fwd[K2]) <= 1e-9 * f1 and abs(bwd[K2]) <= 1e-9 * f1
    sampled = _sampled_roll(layout, fixed.proposal)
    np.testing.assert_allclose(fixed.residual.roll, sampled, rtol=0, atol=1e-9 * _roll_unit(layout))
    assert fixed.proposal.notes == ()  # equal heights, symmetric: the roll is the engine's


def test_fixed_shafts_say_what_they_leave():
    """Shafts at +2 only cannot cancel a line force: its backward half stays; a shaft at -1
    has nothing to carry in an inline-4, one at +3 is for an order not to be cancelled."""
    text = _file(
        INLINE4,
        """\
        balance:
          shafts:
            - {speed_ratio: 2, x: 80 mm, y: -90 mm}
            - {speed_ratio: -1}
            - {speed_ratio: 3, y: -100 mm}
        """,
    )
    layout = layout_from_text(text)
    result = compute_phasors(layout, ORDERS)
    balanced = balance_engine(layout, result)
    notes = balanced.proposal.notes
    assert [s.speed_ratio for s in balanced.proposal.shafts] == [2]
    assert notes[0].startswith("order 2: the backward part is left (force ")
    assert (
        "balance.shafts has no shaft at -2 (a force along a line needs a shaft at +2" in (notes[0])
    )
    assert "the shaft at -1 in balance.shafts carries nothing" in notes[1]
    assert "no backward order-1 force or moment" in notes[1]
    assert "the shaft at +3 in balance.shafts carries nothing" in notes[2]
    assert "order 3 is not among the orders to cancel (1, 2)" in notes[2]
    fwd, bwd = _sampled_force(layout, balanced.proposal)
    assert abs(fwd[K2]) <= 1e-9 * abs(result.phasors.force_forward[K2])
    assert abs(bwd[K2] - result.phasors.force_backward[K2]) <= 1e-9 * abs(
        result.phasors.force_backward[K2]
    )


def test_fixed_lateral_positions_heights_chosen_for_roll():
    """Give x only (the design's walls), let cancel_roll choose the heights: x as given, y
    from the placement, the second-order roll zero by Newton-Euler."""
    text = _file(
        INLINE4,
        """\
        balance:
          shafts:
            - {speed_ratio: 2, x: -95 mm}
            - {speed_ratio: -2, x: 95 mm}
        """,
    )
    layout = layout_from_text(text)
    proposal = _balanced(layout, cancel_roll=True).proposal
    assert [(s.x, s.x_from, s.y_from) for s in proposal.shafts] == [
        (-0.095, "layout", "cancel-roll"),
        (0.095, "layout", "cancel-roll"),
    ]
    assert abs(_sampled_roll(layout, proposal)[K2]) <= 1e-9 * _roll_unit(layout)


def test_fully_fixed_shafts_are_not_moved_and_worse_roll_is_noted():
    """A V-twin's pair fixed below the crank: cancel_roll cannot move it; the notes say the
    roll is not cancelled, and that it is larger than the engine's (0)."""
    layout = load_layout("v-twin-90")
    fixed = (ShaftPosition(2, -0.07, -0.08), ShaftPosition(-2, 0.07, -0.08))
    balanced = _balanced(layout, cancel_roll=True, fixed_shafts=fixed)
    assert [(s.x, s.y) for s in balanced.proposal.shafts] == [(-0.07, -0.08), (0.07, -0.08)]
    sampled = _sampled_roll(layout, balanced.proposal)
    assert abs(sampled[K2] - balanced.residual.roll[K2]) <= 1e-9 * _roll_unit(layout)
    amplitude = abs(balanced.residual.roll[K2])
    assert amplitude > 100.0
    notes = balanced.proposal.notes
    assert notes[0].startswith("order 2: the shaft axes are all given in balance.shafts")
    assert notes[1] == f"order 2: the balance shafts raise the roll from 0 to {amplitude:.4g} N m"


@pytest.mark.parametrize(
    ("entry", "where", "message"),
    [
        ("{speed_ratio: 0, x: 80 mm}", ":9:21: balance.shafts[2].speed_ratio:", "is 0"),
        ("{speed_ratio: 2.5}", ":9:21: balance.shafts[2].speed_ratio:", "a whole number"),
        ("{speed_ratio: '2'}", ":9:21: balance.shafts[2].speed_ratio:", "a whole number"),
        ("{speed_ration: 2}", ":9:8: balance.shafts[2].speed_ration:", "did you mean"),
        ("{speed_ratio: 2, z: 10 mm}", ":9:24: balance.shafts[2].z:", "valid keys: speed"),
        ("{speed_ratio: 2, x: 80 kg}", ":9:27: balance.shafts[2].x:", "not a length"),
        ("{x: 80 mm}", ":9:7: balance.shafts[2].speed_ratio:", "e.g. 'speed_ratio: 2'"),
        ("{speed_ratio: -2}", ":9:21: balance.shafts[2].speed_ratio:", "a second shaft"),
    ],
)
def test_bad_shaft_entries_are_located(tmp_path, entry, where, message):
    text = _file(
        INLINE4,
        f"""\
        balance:
          shafts:
            - {{speed_ratio: -2, x: 80 mm, y: -90 mm}}
            - {entry}
        """,
    )
    path = tmp_path / "engine.yaml"
    path.write_text(text, encoding="utf-8")
    result = run("propose", str(path))
    assert result.exit_code == 2
    assert result.stderr.startswith(f"balance: {path}{where}"), result.stderr
    assert message in result.stderr and result.stderr.count("\n") == 1
    with pytest.raises(LayoutError):
        layout_from_text(text)


def test_expand_keeps_the_shafts(tmp_path):
    text = _file(
        INLINE4,
        """\
        balance:
          shafts:
            - {speed_ratio: 2, x: 80 mm}
            - {speed_ratio: -2, x: -80 mm, y: -90 mm}
        """,
    )
    path = tmp_path / "engine.yaml"
    path.write_text(text, encoding="utf-8")
    expanded = expand_layout(str(path))
    assert "- {speed_ratio: 2, x: 80 mm}" in expanded
    assert "- {speed_ratio: -2, x: -80 mm, y: -90 mm}" in expanded
    again = layout_from_text(expanded)
    assert again.balance is not None and again.balance.shafts == (
        ShaftPosition(2, 0.08, None),
        ShaftPosition(-2, -0.08, -0.09),
    )


# --- through the command line: table, JSON and report -------------------------------------


def test_cli_notes_in_table_json_and_report():
    """Issue 13: the V-twin's default proposal says that its shafts raise the second-order
    roll (2 r F2 = 406.6 N m with the default axes; 574.9 N m, 2 sqrt(2) r F2, with the
    former ones), in the table, the JSON (proposal.notes) and the report; with --cancel-roll
    the JSON has the placed axes, where they come from, and a zero second-order residual
    roll."""
    table = run("propose", "v-twin-90", "--orders", "1-2")
    assert table.exit_code == 0, table.stderr
    assert "Note: order 2: the balance shafts raise the roll from 0 to 406.6 N m" in " ".join(
        table.stdout.split()
    )
    data = json.loads(run("propose", "v-twin-90", "-f", "json", "--orders", "1-2").stdout)
    assert data["proposal"]["cancel_roll"] is False
    assert data["proposal"]["notes"][0].startswith(
        "order 2: the balance shafts raise the roll from 0 to 406.6 N m"
    )
    # the report command's text without its figures (the figures take seconds to draw)
    html = render_report(
        compute(load_layout("v-twin-90"), build_request(load_layout("v-twin-90"), [1, 2])),
        figures=False,
    )
    note = "order 2: the balance shafts raise the roll from 0 to 406.6"
    assert f'<ul class="note notes"><li>{note}' in html
    placed = json.loads(
        run("propose", "v-twin-90", "-f", "json", "--orders", "1-2", "--cancel-roll").stdout
    )["proposal"]
    assert placed["cancel_roll"] is True
    assert [s["position_from"] for s in placed["balance_shafts"]] == [
        {"x": "cancel-roll", "y": "cancel-roll"}
    ] * 2
    assert [s["y_m"] for s in placed["balance_shafts"]] == pytest.approx(
        [-0.033 * 2 * math.sqrt(2), 0.033 * 2 * math.sqrt(2)], rel=1e-12
    )
    assert placed["residual"]["roll"][1] == {"order": 2, "amplitude": 0.0, "phase_deg": 0.0}
    assert placed["notes"][0].startswith("order 2: shafts placed on either side of the crank")


def test_cli_fixed_shafts_in_json_and_table(tmp_path):
    """`balance propose` of a layout with balance: shafts: reports the shafts where the file
    puts them, says so (position_from), and the residual roll with them (the one the core
    computes, itself checked against Newton-Euler above)."""
    text = _file(
        INLINE4,
        """\
        balance:
          shafts:
            - {speed_ratio: 2, x: 80 mm, y: -60 mm}
            - {speed_ratio: -2, x: -80 mm, y: -120 mm}
        """,
    )
    path = tmp_path / "engine.yaml"
    path.write_text(text, encoding="utf-8")
    result = run("propose", str(path), "-f", "json", "--orders", "1-2")
    assert result.exit_code == 0, result.stderr
    proposal = json.loads(result.stdout)["proposal"]
    shafts = proposal["balance_shafts"]
    assert [(s["speed_ratio"], s["x_m"], s["y_m"]) for s in shafts] == [
        (2, 0.08, -0.06),
        (-2, -0.08, -0.12),
    ]
    assert all(s["position_from"] == {"x": "layout", "y": "layout"} for s in shafts)
    layout = layout_from_text(text)
    core = balance_engine(layout, compute_phasors(layout, np.arange(1, 3)))
    assert proposal["residual"]["roll"][1]["amplitude"] == pytest.approx(
        abs(core.residual.roll[1]), rel=1e-12
    )
    table = run("propose", str(path), "--orders", "1-2")
    assert table.exit_code == 0, table.stderr
    assert "-120" in table.stdout and "80" in table.stdout
