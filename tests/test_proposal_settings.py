"""The balancing proposal as a designer reads it (issue 22, "Balancing and notes"): the
balance factor's two conventions, notes computed from the residual they describe, default
shaft axes within the crank train's reach, per-throw counterweights in z order, and shafts at
speed ratios that are not whole numbers."""

from __future__ import annotations

import json
import math
import re
import textwrap
from dataclasses import replace

import numpy as np
import pytest
from oracles import proposal_force_samples
from test_geared_brute_force import _with_proposal, brute_force
from typer.testing import CliRunner

import balance
from balance.api import builtin_layout_names, load_layout
from balance.cli import app
from balance.core import sampled as td
from balance.core.analysis import compute
from balance.core.errors import InputError
from balance.io.request import build_request
from balance.views.proposal import proposal_summary
from balance.views.report import render_report

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
    shafts = json.loads(result.stdout)["proposal"]["balance_shafts"]
    assert [s["speed_ratio"] for s in shafts] == [2]
    assert np.isfinite(shafts[0]["x_m"])


# --- notes that are true: computed from the residual they describe -------------------------

FACTORS = (0.0, 0.5, 1.0, 1.5)


def _sampled(layout, proposal, lever: bool = False):
    """Forward first-order phasor of the pistons alone and of the whole residual (pistons,
    rotating masses and every proposed mass), from the forces sampled over a revolution."""
    theta = td.crank_angles(256)
    pistons = td.reciprocating_force_samples(layout, theta, lever=lever)
    whole = (
        pistons
        + td.rotating_force_samples(layout, theta, lever=lever)
        + proposal_force_samples(proposal, layout, theta, lever=lever)
    )
    first = np.array([1])
    return td.phasors_from_samples(pistons, first)[0][0], td.phasors_from_samples(whole, first)[0][
        0
    ]


def _brute_forced(layout, proposal):
    """Several crankshafts: the first order of the pistons alone and of the whole residual
    (pistons, rotating masses and every proposed mass as point masses on their axes), force
    and moment, forward and backward, from the bodies of the brute force
    (test_geared_brute_force.py), which shares nothing with the package."""
    first = np.array([1])
    pistons = brute_force(replace(layout, rotating_mass=np.zeros(layout.n_cylinders)), first)
    whole = _with_proposal(layout, proposal, first)
    return {
        (what, j): (complex(pistons[what][j][0]), complex(whole[what][j][0]))
        for what in ("force", "moment")
        for j in (0, 1)
    }


def _rods_per_throw(layout) -> set[int]:
    """Rods on each throw, counted from the cylinder table (pins at one angle and one z, on
    one crankshaft)."""
    shaft = layout.crankshafts.of_cylinder if layout.geared else np.zeros(layout.n_cylinders)
    keys = [
        (int(s), round(math.degrees(t) % 360.0, 6) % 360.0, round(z, 9))
        for s, t, z in zip(shaft, layout.throw, layout.z, strict=True)
    ]
    return {keys.count(key) for key in keys}


def _check_part(
    part: str,
    core: complex,
    sampled: complex,
    pistons: complex,
    unit: float,
    what,
    sense: str = "forward",
):
    """One part of the factor note (force or moment) against the residual's numbers."""
    if core == 0:
        assert part == f"no {sense} first-order {what}", part
        assert abs(sampled) <= 1e-9 * unit
        return
    number = float(part.split(" ", 1)[0])
    assert part.startswith(f"{abs(core):.4g} "), (part, core)
    assert number == pytest.approx(abs(sampled), rel=1e-3, abs=1e-9 * unit)
    share = (sampled * np.conj(pistons)).real / abs(pistons) ** 2 if abs(pistons) else None
    if "under-balanced" in part or "overbalanced" in part:
        assert share is not None
        stated = float(part.split("(", 1)[1].split(" %")[0].split(", and ")[-1]) / 100.0
        assert ("under-balanced" in part) == (share > 0), (part, share)
        assert stated == pytest.approx(abs(share), rel=1e-3, abs=1e-9)
    elif share is not None and abs(pistons) > 1e-6 * unit:
        # no relation stated: the residual is not along the pistons' forward first order
        cross = abs((sampled * np.conj(pistons)).imag) / (abs(sampled) * abs(pistons))
        assert cross > 1e-9, (part, cross)


@pytest.mark.parametrize("factor", FACTORS, ids=[f"{100 * f:g}%" for f in FACTORS])
@pytest.mark.parametrize("name", builtin_layout_names())
def test_factor_note_says_what_the_residual_holds(name, factor):
    """Issue 22: the balance factor's note is computed from the residual.  Nothing left when
    the residual's forward first-order force and moment are 0; otherwise the force and moment
    it leaves (to four digits, checked against the forces sampled over a revolution with
    every proposed mass), under-balanced or overbalanced by the sign of the residual along
    the pistons' forward first order, with the share printed; and the factor in the other
    convention from the rods per throw.  The orders the header calls not cancelled in full
    are exactly those whose residual force or moment is not 0.  With several crankshafts the
    reference is the brute force's bodies; where a shaft counter-rotates the note says the
    same of the backward first order (issue 25)."""
    layout = load_layout(name)
    result = compute(layout, build_request(layout, [1, 2], balance_factor=factor))
    part = result.part("proposal")
    note = part.proposal.notes[0]
    rods = _rods_per_throw(layout)
    assert note.startswith(f"balance factor {100 * factor:.4g} % of each cylinder's ")
    if len(rods) == 1:
        n = rods.pop()
        where = "one rod per throw" if n == 1 else f"{n} rods per throw"
        assert f"(= {100 * factor * n:.4g} % of one cylinder's on each throw: {where})" in note
    res = part.residual
    core = {
        ("force", 0): complex(res.force_forward[0]),
        ("moment", 0): complex(res.moment_forward[0]),
        ("force", 1): complex(res.force_backward[0]),
        ("moment", 1): complex(res.moment_backward[0]),
    }
    if layout.geared:
        reference = _brute_forced(layout, part.proposal)
    else:
        reference = {
            ("force", 0): _sampled(layout, part.proposal),
            ("moment", 0): _sampled(layout, part.proposal, lever=True),
        }
    backward = layout.geared and bool(np.any(layout.crankshafts.rotation < 0))
    f_unit = float(np.max(layout.reciprocating_mass * layout.crank_radius) * layout.speed**2)
    m_unit = f_unit * max(float(np.ptp(layout.z)), 2 * float(layout.crank_radius[0]))
    units = {"force": f_unit, "moment": m_unit}
    said = note.split(": the counterweights leave ", 1)[1]
    senses = (0, 1) if backward else (0,)
    keys = [(what, j) for j in senses for what in ("force", "moment")]
    nothing = "no first-order force or moment in either sense"
    if said == (nothing if backward else "no forward first-order force or moment"):
        for key in keys:
            assert core[key] == 0, key
            assert abs(reference[key][1]) <= 1e-9 * units[key[0]], key
    else:
        parts = said.split("; and ") if backward else [said]
        assert len(parts) == len(senses), said
        for j, text in zip(senses, parts, strict=True):
            sense = ("forward", "backward")[j]
            cut = text.rindex(" and ", 0, text.index("first-order moment"))
            for what, piece in (("force", text[:cut]), ("moment", text[cut + 5 :])):
                pistons, sampled = reference[(what, j)]
                args = (core[(what, j)], sampled, pistons, units[what], what, sense)
                _check_part(piece, *args)
    peaks = res.peak("force"), res.peak("moment")
    left = tuple(k for k in (1, 2) if peaks[0][k - 1] != 0 or peaks[1][k - 1] != 0)
    assert part.left == left
    assert set(left) <= {1}  # only the factor leaves anything here, and only of order 1
    assert (1 in left) == any(core[key] != 0 for key in keys)


@pytest.mark.parametrize(
    ("name", "factor", "left", "share"),
    [("single", 0.0, "100 % of the pistons'", "under"), ("single", 1.5, "and 200 % of it", "over")],
)
def test_factor_note_for_a_single_in_closed_form(name, factor, left, share):
    """A single without offset: the pistons' forward first order is F1/2, the counterweight
    takes f F1 of it, so (1/2 - f) F1 is left: all of it at 0 %, twice it the other way at
    150 %."""
    layout = load_layout(name)
    result = compute(layout, build_request(layout, [1, 2], balance_factor=factor))
    note = result.part("proposal").proposal.notes[0]
    f1 = float(layout.reciprocating_mass[0] * layout.crank_radius[0] * layout.speed**2)
    assert f"leave {abs(0.5 - factor) * f1:.4g} N of forward first-order force" in note
    assert left in note and f"{share}" in note.split("force (", 1)[1]
    assert note.endswith("and no forward first-order moment")


def test_header_says_when_an_order_is_not_cancelled_in_full():
    """Issue 22: --balance-factor 100% --cancel 1 on a single leaves half its first order:
    the header no longer says "cancelling orders 1"; the JSON lists the order left, and the
    report says it too."""
    table = run("propose", "single", "--balance-factor", "100%", "--cancel", "1", "--orders", "1-2")
    assert table.exit_code == 0, table.stderr
    head = " ".join(table.stdout.split())
    assert "cancelling orders 1" not in head
    assert (
        "Proposal: strategy two-plane, asked to cancel order 1; order 1 not cancelled in full "
        "(see the notes), balance factor 100 % of each cylinder's reciprocating mass"
    ) in head
    data = json.loads(
        run("propose", "single", "--balance-factor", "100%", "--cancel", "1", "-f", "json").stdout
    )["proposal"]
    assert data["orders"] == [1] and data["orders_left"] == [1]
    assert data["residual"]["force"][0]["peak"] > 0
    full = json.loads(run("propose", "single", "-f", "json").stdout)["proposal"]
    assert full["orders_left"] == [] and full["residual"]["force"][0]["peak"] == 0.0
    plain = run("propose", "single", "--orders", "1-2")
    assert "Proposal: strategy two-plane, cancelling orders 1,2" in plain.stdout


@pytest.mark.parametrize("name", builtin_layout_names())
def test_cancel_roll_always_says_what_it_did(name):
    """Issue 22: with cancel_roll every order that has shafts has a note (placed, why not,
    or already cancelled where they are, with the residual roll it states), and an engine
    without shafts says there is nothing to place."""
    layout = load_layout(name)
    result = compute(layout, build_request(layout, [1, 2], cancel_roll=True))
    part = result.part("proposal")
    proposal = part.proposal
    if not proposal.shafts:
        assert proposal.notes[-1].startswith("cancel_roll: no balance shafts are proposed")
        return
    for k in sorted({abs(s.speed_ratio) for s in proposal.shafts}):
        said = [n for n in proposal.notes if n.startswith(f"order {k}:")]
        assert said, (k, proposal.notes)
        for note in said:
            if "already 0 N m" in note:
                assert part.residual.roll[k - 1] == 0


def test_cancel_roll_in_the_header():
    placed = run("propose", "v-twin-90", "--cancel-roll", "--orders", "1-2")
    assert "cancel_roll: 2 shafts placed for the roll" in " ".join(placed.stdout.split())
    nothing = run("propose", "inline-6", "--cancel-roll", "--orders", "1-2")
    text = " ".join(nothing.stdout.split())
    assert "cancel_roll: no shaft moved (see the notes)" in text
    assert "Note: cancel_roll: no balance shafts are proposed, so there is nothing to place" in text


# --- the balance factor's two conventions --------------------------------------------------


def _proposal_json(*args: str) -> dict:
    result = run("propose", *args, "-f", "json", "--orders", "1-2")
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)["proposal"]


def test_one_cylinder_100_percent_is_each_cylinder_50_on_a_90_degree_v_twin():
    """Issue 22: on the 90 deg V-twin's common pin, "100 %" of the motorcycle texts (one
    cylinder's reciprocating mass) is today's 50 % (of each cylinder's): the same
    counterweight, bit for bit, and the whole first order cancelled; each output states the
    convention and the equivalent."""
    each = _proposal_json("v-twin-90", "--balance-factor", "50%")
    one = _proposal_json(
        "v-twin-90", "--balance-factor", "100%", "--balance-factor-of", "one-cylinder"
    )
    assert each["counterweights"] == one["counterweights"]
    assert each["residual"] == one["residual"]
    assert one["residual"]["force"][0]["peak"] == 0.0  # the whole first order
    layout = load_layout("v-twin-90")
    m = float(layout.rotating_mass.sum() + layout.reciprocating_mass[0])  # one cylinder's
    assert one["counterweights"][0]["mass_kg"] == pytest.approx(m, rel=1e-12)
    for data, of in ((each, "each-cylinder"), (one, "one-cylinder")):
        assert data["balance_factor"] == 0.5 and data["balance_factor_one_cylinder"] == 1.0
        assert data["balance_factor_of"] == of
    assert each["balance_factor_convention"] == (
        "50 % of each cylinder's reciprocating mass (= 100 % of one cylinder's on each throw: "
        "2 rods per throw)"
    )
    assert one["balance_factor_convention"] == (
        "100 % of one cylinder's reciprocating mass on each throw (= 50 % of each cylinder's: "
        "2 rods per throw)"
    )
    assert one["notes"][0] == (
        f"balance factor {one['balance_factor_convention']}: the counterweights leave no "
        "forward first-order force or moment"
    )


def test_the_conventions_agree_where_every_throw_has_one_rod():
    each = _proposal_json("single", "--balance-factor", "70%")
    one = _proposal_json("single", "--balance-factor", "70%", "--balance-factor-of", "one-cylinder")
    assert each["counterweights"] == one["counterweights"]
    assert each["balance_factor_one_cylinder"] == one["balance_factor"] == pytest.approx(0.7)


V_TWIN = """\
name: V-twin
speed: 9000 rpm
geometry: {stroke: 66 mm, conrod_length: 124 mm}
masses: {reciprocating: 0.5 kg, rotating: 0.6 kg}
crank: {throws: [0], banks: [-45 deg, 45 deg]}
"""


def test_staggered_rods_on_one_throw_count_as_that_throws_rods(tmp_path):
    """Rods staggered side by side on one pin (``bank_stagger``: two planes, one throw, one
    angle, as on a real L-twin) are that pin's two rods for the one-cylinder convention:
    100 % of one cylinder is 50 % of each, the same counterweights and residual, and the
    equivalents say 2 rods per throw (counting planes gave 1 rod per throw and took 100 % of
    one cylinder for 100 % of each: a counterweight of 2.2 kg instead of 1.7 kg)."""
    staggered = V_TWIN.replace(
        "banks: [-45 deg, 45 deg]}", "banks: [-45 deg, 45 deg], bank_stagger: 24 mm}"
    )
    path = _write(tmp_path, staggered, "staggered.yaml")
    each = _proposal_json(str(path), "--balance-factor", "50%")
    one = _proposal_json(
        str(path), "--balance-factor", "100%", "--balance-factor-of", "one-cylinder"
    )
    assert each["counterweights"] == one["counterweights"]
    assert each["residual"] == one["residual"]
    assert one["balance_factor"] == 0.5 and one["balance_factor_one_cylinder"] == 1.0
    assert one["balance_factor_convention"].endswith(
        "(= 50 % of each cylinder's: 2 rods per throw)"
    )


def test_the_layout_file_says_the_convention(tmp_path):
    """``balance_factor: {of: one-cylinder, value: 100 %}`` in the file is the command
    line's --balance-factor 100% --balance-factor-of one-cylinder; a bare value keeps its
    meaning (each cylinder's); ``layout expand`` writes the convention and reads back to the
    same proposal."""
    nested = _write(
        tmp_path,
        V_TWIN + "balance:\n  balance_factor: {of: one-cylinder, value: 100 %}\n",
        "a.yaml",
    )
    bare = _write(tmp_path, V_TWIN + "balance:\n  balance_factor: 50 %\n", "b.yaml")
    plain = _write(tmp_path, V_TWIN, "c.yaml")
    from_file = _proposal_json(str(nested))
    from_bare = _proposal_json(str(bare))
    from_cli = _proposal_json(
        str(plain), "--balance-factor", "100%", "--balance-factor-of", "one-cylinder"
    )
    assert from_file == from_cli
    assert from_bare["counterweights"] == from_file["counterweights"]
    assert from_bare["balance_factor_of"] == "each-cylinder"
    expanded = run("layout", "expand", str(nested))
    assert expanded.exit_code == 0, expanded.stderr
    assert "  balance_factor:\n    value: 100 %\n    of: one-cylinder\n" in expanded.stdout
    again = _write(tmp_path, expanded.stdout, "d.yaml")
    assert _proposal_json(str(again)) == from_file
    expanded_bare = run("layout", "expand", str(bare)).stdout
    assert "  balance_factor:\n    value: 50 %\n    of: each-cylinder\n" in expanded_bare


@pytest.mark.parametrize(
    ("entry", "where", "message"),
    [
        ("{of: half, value: 50 %}", ":7:24: balance.balance_factor.of:", "'half' is not allowed"),
        ("{of: one-cylinder}", ":7:19: balance.balance_factor.value:", "missing 'value'"),
        ("{value: 60}", ":7:27: balance.balance_factor.value:", "did you mean '60 %'"),
        (
            "{of: one-cylinder, value: 250 %}",
            ":7:19: balance.balance_factor:",
            "between 0 % and 200 % of one cylinder's reciprocating mass",
        ),
        ("{of: one-cylinder, value: 1, x: 1}", ":7:48: balance.balance_factor.x:", "unknown key"),
    ],
)
def test_bad_balance_factors_are_located(tmp_path, entry, where, message):
    path = _write(tmp_path, V_TWIN + f"balance:\n  balance_factor: {entry}\n")
    result = run("propose", str(path))
    assert result.exit_code == 2
    assert result.stderr.startswith(f"balance: {path}{where}"), result.stderr
    assert message in result.stderr and result.stderr.count("\n") == 1


def test_command_line_and_api_refuse_a_convention_alone_or_unknown():
    alone = run("propose", "v-twin-90", "--balance-factor-of", "one-cylinder")
    assert alone.exit_code == 2
    assert "--balance-factor-of: says what --balance-factor is a share of" in alone.stderr
    unknown = run("propose", "v-twin-90", "--balance-factor", "1", "--balance-factor-of", "x")
    assert unknown.exit_code == 2
    with pytest.raises(InputError, match="balance_factor_of: 'half'; use one of each-cylinder"):
        balance.analyse("v-twin-90", balance_factor=1.0, balance_factor_of="half")
    with pytest.raises(InputError, match="give the factor too"):
        balance.analyse("v-twin-90", balance_factor_of="one-cylinder")


MIXED = """\
name: Two rods on one throw, one on the other
speed: 6000 rpm
geometry: {stroke: 60 mm, conrod_length: 120 mm}
masses: {reciprocating: 0.5 kg, rotating: 0.3 kg}
cylinders:
  - {throw: 0 deg, bank: -45 deg, z: 0 mm}
  - {throw: 0 deg, bank: 45 deg, z: 0 mm}
  - {throw: 180 deg, bank: 0 deg, z: 80 mm}
"""


def test_one_cylinder_on_throws_with_different_numbers_of_rods(tmp_path):
    """100 % of one cylinder's reciprocating mass on each throw: the throw of two rods
    carries 2 m_rot + m_rec, the throw of one m_rot + m_rec (per-throw strategy); there is
    no single share of each cylinder's (null in the JSON), and the note gives both."""
    path = _write(tmp_path, MIXED)
    data = _proposal_json(
        str(path),
        "--balance-factor",
        "100%",
        "--balance-factor-of",
        "one-cylinder",
        "--strategy",
        "per-throw",
    )
    masses = [w["mass_kg"] for w in data["counterweights"]]
    assert masses == pytest.approx([2 * 0.3 + 0.5, 0.3 + 0.5], rel=1e-12)
    assert data["balance_factor"] is None and data["balance_factor_one_cylinder"] == 1.0
    assert data["balance_factor_convention"] == (
        "100 % of one cylinder's reciprocating mass on each throw (= 100 % of each cylinder's "
        "on the throws of 1 rod, 50 % on those of 2 rods)"
    )
    ds = balance.analyse(
        str(path), orders=[1, 2], balance_factor=1.0, balance_factor_of="one-cylinder"
    )
    assert "proposal_balance_factor" not in ds.attrs
    assert ds.attrs["proposal_balance_factor_one_cylinder"] == 1.0


def test_every_output_that_shows_a_factor_states_its_convention():
    """Table header, JSON, Dataset attributes and long names, report, figure title and the
    balance-factor study (table note, JSON, Dataset)."""
    table = run(
        "propose", "v-twin-90", "--balance-factor", "50%", "--factor-study", "--orders", "1-2"
    )
    text = " ".join(table.stdout.split())
    assert (
        "balance factor 50 % of each cylinder's reciprocating mass, " in text
        or text.count("balance factor 50 % of each cylinder's reciprocating mass") >= 1
    )
    assert (
        "balance factor: the share of each cylinder's reciprocating mass put on the crank "
        "(balance_factor of: each-cylinder)" in text
    )
    assert (
        "Factor minimising the larger force peak: 50.0% (= 100 % of one cylinder's on each "
        "throw: 2 rods per throw)" in text
    )
    study = json.loads(
        run("propose", "v-twin-90", "--factor-study", "-f", "json", "--orders", "1-2").stdout
    )["balance_factor_study"]
    assert study["factor_of"] == "each-cylinder"
    assert study["optimal_factor_one_cylinder"] == pytest.approx(1.0, abs=1e-6)
    ds = balance.analyse(
        "v-twin-90",
        orders=[1, 2],
        balance_factor=1.0,
        balance_factor_of="one-cylinder",
        factor_study=True,
    )
    assert ds.attrs["proposal_balance_factor"] == 0.5
    assert ds.attrs["proposal_balance_factor_one_cylinder"] == 1.0
    assert ds.attrs["proposal_balance_factor_of"] == "one-cylinder"
    assert ds.attrs["proposal_balance_factor_convention"].startswith(
        "100 % of one cylinder's reciprocating mass on each throw (= 50 % of each cylinder's"
    )
    assert "each cylinder's reciprocating mass" in ds.study_factor.attrs["long_name"]
    assert "each cylinder's reciprocating mass" in ds.optimal_balance_factor.attrs["long_name"]
    layout = load_layout("v-twin-90")
    result = compute(
        layout,
        build_request(layout, [1, 2], balance_factor=1.0, balance_factor_of="one-cylinder"),
    )
    html = render_report(result, figures=False)
    assert (
        "100 % of one cylinder&#x27;s reciprocating mass on each throw (= 50 % of each "
        "cylinder&#x27;s: 2 rods per throw)"
        in html
        or "100 % of one cylinder's reciprocating mass on each throw (= 50 % of each "
        "cylinder's: 2 rods per throw)"
        in html
    )
    assert "balance factor 100 % of one cylinder's reciprocating mass on each throw" in (
        proposal_summary(result)
    )


# --- default shaft axes within the crank train's reach -------------------------------------

MARINE_SIX = """\
name: Marine six, two-stroke crosshead (sizes of a large bore engine)
speed: 72 rpm
cycle: two-stroke
geometry: {bore: 800 mm, stroke: 3720 mm, conrod_length: 3600 mm}
masses: {reciprocating: 30000 kg, rotating: 20000 kg}
crank: {throws: [0, 240, 120, 180, 300, 60], spacing: 1400 mm}
"""


def test_default_shaft_axes_of_a_marine_six_sit_within_the_crank_trains_reach(tmp_path):
    """Issue 22: the default axes of a pair used to be 2r sideways (x = -/+3.72 m on this
    engine, outside any bedplate).  Now every default axis is 2r from the crank axis, below
    it: the second-order pair 30 deg either side of straight down, x = -/+r = -/+1.86 m,
    y = -sqrt(3) r, the first-order backward shaft straight below (as before); within r + l
    and within the crank's own width.  The table and the JSON say so."""
    path = _write(tmp_path, MARINE_SIX)
    data = _proposal_json(str(path))
    r = 1.86
    shafts = data["balance_shafts"]
    assert [s["speed_ratio"] for s in shafts] == [-1, 2, -2]
    assert [s["x_m"] for s in shafts] == pytest.approx([0.0, -r, r], rel=1e-12)
    assert [s["y_m"] for s in shafts] == pytest.approx(
        [-2 * r, -math.sqrt(3) * r, -math.sqrt(3) * r], rel=1e-12
    )
    assert data["shaft_default_axes"] == (
        "default axes: 3720 mm (2 r) from the crank axis, below it, a pair 30° either side "
        "of straight down (x = ∓1860 mm): within the crank train's reach; to place them "
        "elsewhere, give their axes in the layout's balance: shafts:"
    )
    table = run("propose", str(path), "--orders", "1-2")
    assert "default axes: 3720 mm (2 r) from the crank axis" in " ".join(table.stdout.split())


@pytest.mark.parametrize("name", builtin_layout_names())
def test_default_axes_of_every_builtin_keep_the_rule(name):
    """Every default coordinate: the axis 2r from the crank axis (r the mean crank radius),
    below it, |x| <= r, so within r + l of every rod; a shaft alone straight below."""
    layout = load_layout(name)
    result = compute(layout, build_request(layout, [1, 2]))
    shafts = result.part("proposal").proposal.shafts
    r = float(np.mean(layout.crank_radius))
    reach = float(np.min(layout.crank_radius + layout.conrod_length))
    for s in shafts:
        assert (s.x_from, s.y_from) == ("default", "default")
        assert math.hypot(s.x, s.y) == pytest.approx(2 * r, rel=1e-12)
        assert math.hypot(s.x, s.y) <= reach and s.y < 0 and abs(s.x) <= r * (1 + 1e-12)
        pair = sum(abs(o.speed_ratio) == abs(s.speed_ratio) for o in shafts) == 2
        assert s.x == (pytest.approx(-r if s.speed_ratio > 0 else r, rel=1e-12) if pair else 0.0)


RAISED = re.compile(r"^order (\d+): the balance shafts raise the roll from (\S+) to (\S+) N m")
KEPT = re.compile(r"the roll of this order with them is (\S+) N m")


@pytest.mark.parametrize("cancel_roll", [False, True], ids=["default", "cancel-roll"])
@pytest.mark.parametrize("name", builtin_layout_names())
def test_roll_notes_state_the_residual_roll(name, cancel_roll):
    """Issue 22: the notes that give a roll give the residual's.  "raise the roll from A to
    B N m": A is the engine's own (inertia) roll of that order and B the residual's with the
    shafts, both to four digits, and B > A; "the roll of this order with them is X N m" is the
    residual's; "already 0 N m" only where the residual's roll is 0.  Every built-in layout,
    with and without cancel_roll."""
    layout = load_layout(name)
    result = compute(layout, build_request(layout, [1, 2], cancel_roll=cancel_roll))
    part = result.part("proposal")
    engine = result.phasors.roll
    after = part.residual.roll
    assert engine is not None and after is not None
    orders = list(np.asarray(part.residual.orders))
    seen = 0
    for note in part.proposal.notes:
        raised = RAISED.match(note)
        if raised:
            at = orders.index(int(raised.group(1)))
            assert raised.group(2) == f"{abs(engine[at]):.4g}", note
            assert raised.group(3) == f"{abs(after[at]):.4g}", note
            assert abs(after[at]) > abs(engine[at])
            seen += 1
        kept = KEPT.search(note)
        if kept:
            at = orders.index(int(note.split(":", 1)[0].split()[1]))
            assert kept.group(1) == f"{abs(after[at]):.4g}", note
            seen += 1
        if "already 0 N m" in note:
            at = orders.index(int(note.split(":", 1)[0].split()[1]))
            assert after[at] == 0
            seen += 1
    # every order whose residual roll the shafts make larger than the engine's has its note
    # when the shafts stay where they are by default
    if not cancel_roll:
        for k in {abs(s.speed_ratio) for s in part.proposal.shafts}:
            at = orders.index(k)
            grows = abs(after[at]) > abs(engine[at]) * (1 + 1e-9) + 1e-9 * max(abs(engine[at]), 1.0)
            noted = any(
                note.startswith(f"order {k}: the balance shafts raise")
                for note in part.proposal.notes
            )
            assert noted == grows, (k, abs(engine[at]), abs(after[at]), part.proposal.notes)
