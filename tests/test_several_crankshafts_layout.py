"""Several crankshafts in a layout file (issue 25, the input side): ``crankshafts:``,
``output:``, each cylinder's ``crankshaft`` and ``opposed``, the compact form's blocks, the
angle rules, every refusal about the file, and the crankshafts of the engine read.

The examples of docs/layout-format.md, "Several crankshafts": a Jumo-205-like opposed-piston
six (two crankshafts 945 mm apart, the exhaust shaft leading by 11 degrees), a Deltic-like
triangle (three opposed blocks, one shaft turning the other way) and an H16-like (two
crankshafts, one flat-eight block on each).  Each compact form must be the engine written
cylinder by cylinder, bit for bit.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from balance.cli import app
from balance.core.engine import CYLINDER_FIELDS, Engine
from balance.core.errors import LayoutError
from balance.io.layout_file import load_layout
from balance.io.layout_reader import layout_from_text

runner = CliRunner()

HEAD = """\
name: {name}
speed: 3000 rpm
cycle: two-stroke
geometry: {{stroke: 160 mm, conrod_length: 350 mm}}
masses: {{piston_group: 3 kg, conrod: 2 kg, conrod_cg_to_big_end: 100 mm,
         crank_unbalance: 1.5 kg}}
"""

JUMO = (
    HEAD.format(name="Jumo-205-like")
    + """\
crankshafts:
  - {name: intake}
  - {name: exhaust, y: 945 mm, phase: 191 deg}   # 180 (it faces the other way) + 11 lead
crank:
  throws: [0, 120, 240, 180, 300, 60]
  spacing: 160 mm
  opposed: [intake, exhaust]
"""
)
THROWS = [0, 120, 240, 180, 300, 60]
SIDE = 1000.0  # mm, the Deltic-like triangle's side
DELTIC_AXES = {"A": (-SIDE / 2, 0.0), "B": (SIDE / 2, 0.0), "C": (0.0, SIDE * math.sqrt(3) / 2)}
DELTIC = (
    HEAD.format(name="Deltic-like")
    + f"""\
crankshafts:
  - {{name: A, x: {-SIDE / 2!r} mm}}
  - {{name: B, x: {SIDE / 2!r} mm, phase: 200 deg}}
  - {{name: C, y: {DELTIC_AXES["C"][1]!r} mm, rotation: opposite, phase: 270 deg}}
crank:
  - {{throws: [0, 120, 240], spacing: 200 mm, opposed: [A, B]}}
  - {{throws: [0, 120, 240], spacing: 200 mm, opposed: [B, C]}}
  - {{throws: [0, 120, 240], spacing: 200 mm, opposed: [C, A]}}
"""
)
H16 = """\
name: H16-like
speed: 8000 rpm
geometry: {stroke: 48 mm, conrod_length: 110 mm}
masses: {reciprocating: 0.4 kg, rotating: 0.3 kg}
crankshafts:
  - {name: lower}
  - {name: upper, y: 220 mm, rotation: opposite, phase: 90 deg}
output: {rotation: opposite}
crank:
  - {crankshaft: lower, throws: [0, 180, 180, 0], spacing: 80 mm, banks: [-90 deg, 90 deg]}
  - {crankshaft: upper, throws: [0, 180, 180, 0], spacing: 80 mm, banks: [-90 deg, 90 deg],
     z0: 10 mm}
"""


def direction(a: tuple[float, float], b: tuple[float, float]) -> float:
    """The engine-frame angle [deg] from a to b (as the reader forms an opposed bank)."""
    return math.degrees(math.atan2(b[0] - a[0], b[1] - a[1]))


def explicit(text: str, rows: list[str]) -> str:
    """``text`` with its ``crank:`` replaced by the cylinders ``rows``."""
    head = text[: text.index("crank:")]
    return head + "cylinders:\n" + "".join(f"  - {{{row}}}\n" for row in rows)


def same_engine(a: Engine, b: Engine) -> None:
    for key in (*CYLINDER_FIELDS, "throw_index"):
        assert np.array_equal(getattr(a, key), getattr(b, key)), key
        assert getattr(a, key).tobytes() == getattr(b, key).tobytes(), key
    assert a.reference_z == b.reference_z
    sa, sb = a.crankshafts, b.crankshafts
    assert sa is not None and sb is not None
    assert sa.names == sb.names and sa.output_rotation == sb.output_rotation
    for key in ("x", "y", "rotation", "phase", "of_cylinder", "opposed"):
        assert getattr(sa, key).tobytes() == getattr(sb, key).tobytes(), key


def refused(text: str) -> str:
    with pytest.raises(LayoutError) as info:
        layout_from_text(textwrap.dedent(text), "f.yaml")
    return info.value.one_line()


# --- the examples: the compact form is the explicit form ---------------------------------


def test_jumo_compact_is_the_engine_written_cylinder_by_cylinder():
    compact = layout_from_text(JUMO)
    rows = []
    for t, throw in enumerate(THROWS):
        z = f"{160 * t} mm"
        rows.append(f"crankshaft: intake, throw: {throw}, bank: 0, z: {z}, opposed: {2 * t + 2}")
        rows.append(f"crankshaft: exhaust, throw: {throw}, bank: 180 deg, z: {z}")
    written = layout_from_text(explicit(JUMO, rows) + "pitch: 160 mm\n")
    same_engine(compact, written)
    shafts = compact.crankshafts
    assert shafts is not None
    assert shafts.names == ("intake", "exhaust")
    assert shafts.y.tolist() == pytest.approx([0.0, 0.945], abs=1e-15)
    assert shafts.phase[1] == math.radians(191.0)
    assert shafts.of_cylinder.tolist() == [0, 1] * 6
    assert shafts.opposed.tolist() == [1, 0, 3, 2, 5, 4, 7, 6, 9, 8, 11, 10]
    # the pistons of a bore face each other: banks 0 and 180 deg
    assert np.degrees(compact.bank).tolist() == [0.0, 180.0] * 6
    # a throw is on one crankshaft: twelve throws, each with one rod and a whole
    # crank_unbalance (not two rods sharing one)
    assert compact.throw_index.tolist() == list(range(12))
    one = layout_from_text(JUMO.replace("crank_unbalance: 1.5 kg", "crank_unbalance: 0 kg"))
    assert np.allclose(compact.rotating_mass - one.rotating_mass, 1.5, rtol=0, atol=1e-12)


def test_deltic_triangle_is_the_engine_written_cylinder_by_cylinder():
    compact = layout_from_text(DELTIC)
    rows = []
    n = 0
    for a, b in (("A", "B"), ("B", "C"), ("C", "A")):
        bank_a = direction(DELTIC_AXES[a], DELTIC_AXES[b])
        bank_b = direction(DELTIC_AXES[b], DELTIC_AXES[a])
        for t, throw in enumerate([0, 120, 240]):
            z = f"{200 * t} mm"
            rows.append(f"crankshaft: {a}, throw: {throw}, bank: {bank_a!r} deg, z: {z}")
            rows.append(
                f"crankshaft: {b}, throw: {throw}, bank: {bank_b!r} deg, z: {z}, opposed: {n + 1}"
            )
            n += 2
    written = layout_from_text(explicit(DELTIC, rows) + "pitch: 200 mm\n")
    same_engine(compact, written)
    shafts = compact.crankshafts
    assert shafts is not None
    assert shafts.rotation.tolist() == [1.0, 1.0, -1.0]
    # the banks of the triangle's sides: A->B 90 deg, B->C -30 deg, C->A -150 deg
    assert np.degrees(compact.bank[[0, 1, 6, 7, 12, 13]]) == pytest.approx(
        [90, -90, -30, 150, -150, 30], abs=1e-12
    )
    # each crank pin carries two rods, one of each block that names its shaft: nine throws
    assert int(compact.throw_index.max()) + 1 == 9
    assert compact.throw_index[0] == compact.throw_index[13]  # A's first pin: blocks 1 and 3


def test_h16_is_the_engine_written_cylinder_by_cylinder():
    compact = layout_from_text(H16)
    rows = []
    for name, z0 in (("lower", 0), ("upper", 10)):
        for t, throw in enumerate([0, 180, 180, 0]):
            for bank in (-90, 90):
                rows.append(
                    f"crankshaft: {name}, throw: {throw}, bank: {bank} deg, z: {80 * t + z0} mm"
                )
    same_engine(compact, layout_from_text(explicit(H16, rows)))
    shafts = compact.crankshafts
    assert shafts is not None and shafts.output_rotation == -1.0
    assert compact.z[8:].tolist() == pytest.approx([0.01, 0.01, 0.09, 0.09, 0.17, 0.17, 0.25, 0.25])
    assert int(compact.throw_index.max()) + 1 == 8  # four throws per crankshaft


def test_tdc_is_a_throw_in_the_shafts_own_sense():
    # throw = sigma (bank - phase) - tdc; crankshaft 1: bank - tdc, as before
    text = explicit(
        H16,
        [
            "crankshaft: lower, tdc: 30 deg, bank: -90 deg, z: 0 mm",
            "crankshaft: upper, tdc: 30 deg, bank: 90 deg, z: 0 mm",
        ],
    )
    engine = layout_from_text(text)
    assert math.degrees(engine.throw[0]) == pytest.approx(-90 - 30)
    assert math.degrees(engine.throw[1]) == pytest.approx(-(90 - 90) - 30)
    # the cylinder's crank angle from TDC is 0 at theta = tdc on both shafts
    for i in range(2):
        s = engine.crankshafts.of_cylinder[i]
        sigma, phase = engine.crankshafts.rotation[s], engine.crankshafts.phase[s]
        beta = math.radians(30) + engine.throw[i] + sigma * (phase - engine.bank[i])
        assert math.cos(beta) == pytest.approx(1.0)


def test_without_crankshafts_the_engine_has_none():
    for name in ("inline-4", "v8-crossplane", "boxer-4"):
        assert load_layout(name).crankshafts is None


def test_two_shafts_rods_at_one_angle_and_z_are_two_throws():
    text = explicit(
        H16,
        [
            "crankshaft: lower, throw: 0, bank: -90 deg, z: 0 mm",
            "crankshaft: upper, throw: 0, bank: 90 deg, z: 0 mm",
        ],
    )
    assert layout_from_text(text).throw_index.tolist() == [0, 1]
    # one throw_id on two shafts names two throws
    text = text.replace("z: 0 mm}", "z: 0 mm, throw_id: 1}")
    assert layout_from_text(text).throw_index.tolist() == [0, 1]


# --- refusals ------------------------------------------------------------------------------

TWO = HEAD.format(name="two") + "crankshafts:\n  - {name: a}\n  - {name: b, y: 1000 mm}\n"


def cyls(*rows: str) -> str:
    return "cylinders:\n" + "".join(f"  - {{{r}}}\n" for r in rows)


A0 = "crankshaft: a, throw: 0, bank: 0, z: 0 mm"
B0 = "crankshaft: b, throw: 0, bank: 180 deg, z: 0 mm"


B100 = B0.replace("z: 0 mm", "z: 100 mm")
A180 = "crankshaft: a, throw: 0, bank: 180 deg, z: 0 mm"
LINE = "rotation: same or rotation: opposite"
CASES = [
    (
        TWO + cyls(A0, "crankshaft: bb, throw: 0, bank: 0, z: 9 mm"),
        12,
        ["cylinders[2].crankshaft", "no crankshaft is named 'bb'", "did you mean 'b'?"],
    ),
    (
        HEAD.format(name="x") + cyls("crankshaft: a, throw: 0, bank: 0, z: 0 mm"),
        8,
        ["cylinders[1].crankshaft", "without a crankshafts: section"],
    ),
    (
        HEAD.format(name="x")
        + cyls("throw: 0, bank: 0, z: 0, opposed: 2", "throw: 0, bank: 0, z: 0"),
        8,
        ["cylinders[1].opposed", "without a crankshafts: section"],
    ),
    (
        HEAD.format(name="x") + "output: {rotation: opposite}\n" + cyls("throw: 0, bank: 0, z: 0"),
        7,
        ["output", "without a crankshafts: section"],
    ),
    (
        TWO.replace("name: b,", "name: a,") + cyls(A0),
        9,
        ["crankshafts[2].name", "two crankshafts are named 'a'"],
    ),
    (
        TWO.replace("y: 1000 mm", "y: 1000 mm, rotation: backwards") + cyls(A0, B0),
        9,
        ["crankshafts[2].rotation", LINE],
    ),
    (
        TWO.replace("y: 1000 mm", "y: 1000 mm, speed_ratio: 2") + cyls(A0, B0),
        9,
        [
            "crankshafts[2].speed_ratio",
            "crankshafts turn at ±1 × crankshaft 1; a shaft at another speed is a balance shaft",
        ],
    ),
    (
        TWO.replace("{name: a}", "{name: a, rotation: opposite}") + cyls(A0, B0),
        8,
        ["crankshafts[1].rotation", "crankshaft 1 ('a') has rotation: opposite"],
    ),
    (
        TWO.replace("{name: a}", "{name: a, phase: 10 deg}") + cyls(A0, B0),
        8,
        ["crankshafts[1].phase", "crankshaft 1 ('a') has phase 10 deg"],
    ),
    (
        TWO.replace("y: 1000 mm", "y: 0 mm") + cyls(A0, B0),
        9,
        ["crankshafts[2]", "crankshafts 'a' and 'b' are on one axis"],
    ),
    (TWO + cyls(A0), 9, ["crankshafts[2].name", "crankshaft 'b' carries no cylinder"]),
    (
        TWO + cyls(A0 + ", opposed: 3", B0),
        11,
        ["cylinders[1].opposed", "opposed 3 is not a cylinder"],
    ),
    (TWO + cyls(A0 + ", opposed: 1", B0), 11, ["cylinders[1].opposed", "names itself"]),
    (
        TWO + cyls(A0 + ", opposed: 2", A180, B100),
        11,
        ["cylinders[1].opposed", "cylinders 1 and 2 are opposed but on one crankshaft"],
    ),
    (
        TWO + cyls(A0 + ", opposed: 2", B0, B0 + ", opposed: 1"),
        13,
        ["cylinders[3].opposed", "cylinder 1 is already opposed to cylinder 2"],
    ),
    (TWO + cyls(A0 + ", opposed: 2", B100), 12, ["cylinders[2].z", "at z 0 mm and 100 mm"]),
    (
        TWO + cyls(A0 + ", opposed: 2", B0.replace("180 deg", "170 deg")),
        12,
        ["cylinders[2].bank", "not 180 deg apart"],
    ),
    (
        TWO.replace("y: 1000 mm", "y: 1000 mm, x: 1 mm") + cyls(A0 + ", opposed: 2", B0),
        11,
        ["cylinders[1].opposed", "their bore lines are 1 mm apart"],
    ),
    (
        TWO.replace("1000 mm", "860 mm") + cyls(A0 + ", opposed: 2", B0),
        11,
        ["cylinders[1].opposed", "860 mm apart along the bore", "pins reach 860 mm"],
    ),
    (
        TWO + "crank: {throws: [0], crankshaft: a, opposed: [a, b]}\n",
        10,
        ["crank.opposed", "give crankshaft or opposed in a block, not both"],
    ),
    (
        TWO + "crank: {throws: [0], opposed: [a, a]}\n",
        10,
        ["crank.opposed", "opposed names crankshaft 'a' twice"],
    ),
    (
        TWO + "crank: {throws: [0], opposed: [a, c]}\n",
        10,
        ["crank.opposed[2]", "no crankshaft is named 'c'"],
    ),
    (
        TWO + "crank: [{throws: [0], crankshaft: a}, {throws: [0], crankshaft: d}]\n",
        10,
        ["crank[2].crankshaft", "no crankshaft is named 'd'"],
    ),
    (
        TWO + "crank: {throws: [0], opposed: [a, b], banks: [0, 90]}\n",
        10,
        ["crank.banks", "'banks' in an opposed block"],
    ),
    (
        TWO + "crank: {throws: [0], opposed: [a, b], split: [0]}\n",
        10,
        ["crank.split", "'split' in an opposed block"],
    ),
    (
        TWO + "crank: {throws: [0], opposed: [a, b], bank_stagger: 5 mm}\n",
        10,
        ["crank.bank_stagger", "'bank_stagger' in an opposed block"],
    ),
    (TWO + "output: {rotation: sideways}\n" + cyls(A0, B0), 10, ["output.rotation", LINE]),
]


@pytest.mark.parametrize(("text", "line", "words"), CASES)
def test_refused_with_one_line_naming_file_line_and_field(text, line, words):
    message = refused(text)
    assert message.startswith(f"f.yaml:{line}:"), message
    assert "more problem" not in message, message
    for word in words:
        assert word in message, message


def test_link_rods_across_shafts_and_in_opposed_bores_are_refused():
    parts = TWO.replace("crank_unbalance: 1.5 kg", "crank_unbalance: 0 kg")
    link = "link: {master: 1, pin_radius: 40 mm, pin_angle: 0 deg, length: 300 mm}"
    rod = "conrod: 1 kg, conrod_cg_to_big_end: 80 mm"
    message = refused(parts + cyls(A0, f"crankshaft: b, throw: 0, bank: 0, z: 0 mm, {link}, {rod}"))
    assert "cylinders[2].crankshaft" in message
    assert "on another crankshaft" in message
    message = refused(
        parts
        + cyls(A0 + ", opposed: 2", B0, f"crankshaft: a, throw: 0, bank: 0, z: 0 mm, {link}, {rod}")
    )
    assert "cylinders[1].opposed" in message and "carries link cylinder 3" in message


def test_the_command_line_refuses_with_exit_2(tmp_path: Path):
    path = tmp_path / "bad.yaml"
    path.write_text(TWO + cyls(A0, "crankshaft: bb, throw: 0, bank: 0, z: 9 mm"), encoding="utf-8")
    out = runner.invoke(app, ["analyse", str(path)])
    assert out.exit_code == 2
    lines = [line for line in out.output.splitlines() if line.strip()]
    assert len(lines) == 1, out.output
    assert "bad.yaml:12:" in lines[0] and "did you mean 'b'?" in lines[0]


def test_torsion_and_the_dynamic_speed_model_are_refused_with_several_crankshafts(tmp_path):
    from balance.api import analyse
    from balance.core.errors import InputError

    engine = layout_from_text(JUMO)
    with pytest.raises(InputError, match=r"^torsion: .* one crankshaft; this engine has 2"):
        analyse(engine, torsion=True)
    with pytest.raises(InputError, match=r"^speed_model: 'dynamic' is for one crankshaft"):
        analyse(engine, speed_model="dynamic")
    path = tmp_path / "jumo.yaml"
    path.write_text(JUMO, encoding="utf-8")
    out = runner.invoke(app, ["analyse", str(path), "--speed-model", "dynamic"])
    assert out.exit_code == 2
    assert "speed_model: 'dynamic' is for one crankshaft" in out.output


# --- layout expand ---------------------------------------------------------------------------

TDC_LAYOUT = explicit(
    H16,
    [
        "crankshaft: lower, tdc: 30 deg, bank: -90 deg, z: 0 mm",
        "crankshaft: upper, tdc: 210 deg, bank: 90 deg, z: 0 mm",
        "crankshaft: lower, throw: 180 deg, bank: 90 deg, z: 80 mm",
        "crankshaft: upper, throw: 180 deg, bank: -90 deg, z: 80 mm",
    ],
)


@pytest.mark.parametrize(
    "text", [JUMO, DELTIC, H16, TDC_LAYOUT], ids=["jumo", "deltic", "h16", "tdc"]
)
def test_expand_writes_the_same_engine_and_is_a_fixed_point(tmp_path: Path, text: str):
    from balance.io.layout_file import expand_layout

    path = tmp_path / "layout.yaml"
    path.write_text(text, encoding="utf-8")
    once = expand_layout(path)
    again = tmp_path / "expanded.yaml"
    again.write_text(once, encoding="utf-8")
    assert "\nopposed" not in once and "crankshafts:" in once and "output:" in once
    same_engine(load_layout(path), load_layout(again))
    twice = expand_layout(again)
    assert twice.split("\n", 1)[1] == once.split("\n", 1)[1]  # the header names the file


def test_expand_comments_the_drawn_pin_and_the_tdc(tmp_path: Path):
    from balance.io.layout_file import expand_layout

    path = tmp_path / "jumo.yaml"
    path.write_text(JUMO, encoding="utf-8")
    text = expand_layout(path)
    # the exhaust piston of the first bore: its pin drawn at 191 deg at theta = 0, its
    # inner dead centre 11 deg before the intake piston's (349 deg)
    assert "# cylinder 2: alpha(0) 191 deg, TDC at crank angle 349 deg" in text
    assert "# cylinder 3: alpha(0) 120 deg, TDC at crank angle 240 deg" in text
    assert "crankshaft: exhaust, opposed: 1}" in text
    path = tmp_path / "h16.yaml"
    path.write_text(H16, encoding="utf-8")
    text = expand_layout(path)
    # upper shaft turns the other way, phase 90: cylinder 9's pin (throw 0) drawn at 90 deg;
    # bank -90: TDC at -(-90 - 90) - 0 = 180 deg
    assert "# cylinder 9: alpha(0) 90 deg, TDC at crank angle 180 deg" in text
    # cylinder 11 (throw 180): alpha(0) = 90 - 180 = -90 = 270 deg
    assert "# cylinder 11: alpha(0) 270 deg, TDC at crank angle 0 deg" in text


# --- warnings ----------------------------------------------------------------------------------


def rules(text: str) -> dict[str, object]:
    from balance.core.plausibility import check_engine

    return {w.rule: w for w in check_engine(layout_from_text(text))}


def test_a_sound_opposed_piston_engine_has_no_warning_of_its_crankshafts():
    for text in (JUMO, DELTIC, H16):
        found = rules(text)
        assert not {"shared_bore", "opposed_phase", "crankshaft_position"} & set(found), found


def test_the_missing_180_degrees_of_a_piston_facing_the_other_way_is_warned():
    w = rules(JUMO.replace("phase: 191 deg", "phase: 11 deg"))["opposed_phase"]
    assert w.field == "crankshafts[2].phase"
    assert w.message == (
        "cylinder 2 reaches its inner dead centre 169° after cylinder 1: the 180° of a "
        "piston facing the other way missing from `phase`?"
    )
    assert w.excess == pytest.approx(169 / 40)
    # 40 degrees apart is still an opposed-piston engine's lead; 41 is warned
    assert "opposed_phase" not in rules(JUMO.replace("phase: 191 deg", "phase: 220 deg"))
    assert "opposed_phase" in rules(JUMO.replace("phase: 191 deg", "phase: 221 deg"))


def test_an_undeclared_shared_bore_and_a_far_axis_are_warned(tmp_path: Path):
    w = rules(TWO + cyls(A0, B0))["shared_bore"]
    assert (w.field, w.message) == (
        "cylinders[2].opposed",
        "cylinders 1 and 2 share a bore: declare `opposed`?",
    )
    far = rules(TWO.replace("y: 1000 mm", "y: 10 m") + cyls(A0 + ", opposed: 2", B0))
    w = far["crankshaft_position"]
    assert w.field == "crankshafts[2].y" and "'b' is 10 m from the origin" in w.message
    assert w.excess == pytest.approx(10 / (50 * 0.16))
    assert "crankshaft_position" not in rules(
        TWO.replace("y: 1000 mm", "y: 8 m") + cyls(A0 + ", opposed: 2", B0)
    )
    # through the command line: on stderr, and silenced by --quiet
    path = tmp_path / "shared.yaml"
    path.write_text(TWO + cyls(A0, B0), encoding="utf-8")
    out = runner.invoke(app, ["analyse", str(path)])
    assert out.exit_code == 0, out.output
    assert "cylinders 1 and 2 share a bore: declare `opposed`?" in out.stderr
    quiet = runner.invoke(app, ["--quiet", "analyse", str(path)])
    assert "share a bore" not in quiet.stderr


# --- sweep and tolerance fields ----------------------------------------------------------------


def test_a_varied_crankshaft_is_the_hand_edited_file():
    from balance.io.fields import parse_field
    from balance.studies.changes import apply_changes

    base = layout_from_text(JUMO)
    changes = []
    for text, value in (("crankshafts.exhaust.phase", 200.0), ("crankshafts.exhaust.y", 1.0)):
        field = parse_field(text, base)
        changes.append((field, field.to_layout_units(value)))
    varied = apply_changes(base, changes)
    edited = layout_from_text(JUMO.replace("y: 945 mm, phase: 191 deg", "y: 1 m, phase: 200 deg"))
    same_engine(varied, edited)
    assert parse_field("crankshafts.exhaust.phase", base).name == "shaft2_phase"
    # a grid of values: the crankshafts' arrays gain the grid's axes, crankshafts last
    field = parse_field("crankshafts.exhaust.x", base)
    grid = apply_changes(base, [(field, np.array([[0.0], [0.01], [0.02]]))])
    assert grid.crankshafts.x.tolist() == [[0.0, 0.0], [0.0, 0.01], [0.0, 0.02]]
    assert grid.crankshafts.y.tolist() == base.crankshafts.y.tolist()
    # a tolerance study adds its scatter
    moved = apply_changes(base, [(field, 0.001)], add=True)
    assert moved.crankshafts.x.tolist() == [0.0, 0.001]


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("crankshafts.exhuast.phase", "no crankshaft is named 'exhuast'; did you mean 'exhaust'?"),
        ("crankshafts.exhaust.speed_ratio", "valid: crankshafts.exhaust.phase"),
    ],
)
def test_a_crankshaft_field_that_is_none_is_refused(text, words):
    from balance.core.errors import InputError
    from balance.io.fields import parse_field

    with pytest.raises(InputError, match=r"^vary: ") as info:
        parse_field(text, layout_from_text(JUMO))
    assert words in str(info.value)
    with pytest.raises(InputError, match="has no crankshafts: section"):
        parse_field("crankshafts.a.phase", load_layout("inline-4"))
