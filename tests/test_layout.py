"""Layout files: the explicit and compact forms, overrides, masses, and every bad input."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

from balance.core.errors import InputError, LayoutError
from balance.io.layout_file import (
    builtin_layout_names,
    expand_layout,
    layout_from_text,
    load_layout,
)

BASE = """\
name: Test four
speed: 6000 rpm
geometry:
  stroke: 86 mm
  conrod_length: 143 mm
masses:
  reciprocating: 0.61 kg
  rotating: 0.38 kg
cylinders:
  - {throw: 0 deg,   bank: 0 deg, z: 0 mm}
  - {throw: 180 deg, bank: 0 deg, z: 91 mm}
  - {throw: 180 deg, bank: 0 deg, z: 182 mm}
  - {throw: 0 deg,   bank: 0 deg, z: 273 mm}
"""


def write(tmp_path: Path, text: str, name: str = "layout.yaml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def error_of(tmp_path: Path, text: str) -> LayoutError:
    path = write(tmp_path, text)
    with pytest.raises(LayoutError) as info:
        load_layout(path)
    return info.value


# --- valid files -------------------------------------------------------------------------


def test_explicit_form_in_si(tmp_path):
    layout = load_layout(write(tmp_path, BASE))
    assert layout.n_cylinders == 4
    np.testing.assert_allclose(np.degrees(layout.throw), [0, 180, 180, 0])
    np.testing.assert_allclose(layout.z, [0, 0.091, 0.182, 0.273])
    np.testing.assert_allclose(layout.crank_radius, 0.043)
    assert layout.speed == pytest.approx(2 * math.pi * 100)
    assert layout.reference_z == pytest.approx(0.1365)
    assert layout.pitch == pytest.approx(0.091)
    assert layout.cycle == "four-stroke"


def test_bare_angles_are_degrees_and_a_bare_zero_needs_no_unit(tmp_path):
    text = BASE.replace("throw: 180 deg", "throw: 180").replace("z: 0 mm", "z: 0")
    layout = load_layout(write(tmp_path, text))
    np.testing.assert_allclose(np.degrees(layout.throw), [0, 180, 180, 0])
    np.testing.assert_allclose(layout.z, [0, 0.091, 0.182, 0.273])


@pytest.mark.parametrize(
    ("written", "instead", "field", "proposal"),
    [
        ("stroke: 86 mm", "stroke: 0.086", "geometry.stroke", "'0.086 m'"),
        ("stroke: 86 mm", "stroke: 86", "geometry.stroke", "'86 mm'"),
        ("speed: 6000 rpm", "speed: 6000", "speed", "'6000 rpm'"),
        ("reciprocating: 0.61 kg", "reciprocating: 610", "masses.reciprocating", "'610 g'"),
        ("z: 91 mm", "z: 91", "cylinders[2].z", "'91 mm'"),
    ],
)
def test_a_bare_dimensional_number_is_refused_with_the_likely_unit(
    tmp_path, written, instead, field, proposal
):
    err = error_of(tmp_path, BASE.replace(written, instead))
    assert err.field == field
    assert f"give a unit, e.g. {proposal}" in str(err)


def test_compact_form_expands_like_explicit(tmp_path):
    compact = BASE.split("cylinders:")[0] + "crank:\n  throws: [0, 180, 180, 0]\n  spacing: 91 mm\n"
    a = load_layout(write(tmp_path, compact, "a.yaml"))
    b = load_layout(write(tmp_path, BASE, "b.yaml"))
    for name in ("throw", "bank", "z", "crank_radius", "reciprocating_mass"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name))


def test_v_compact_form_with_split_and_stagger(tmp_path):
    text = BASE.split("cylinders:")[0] + textwrap.dedent("""\
        crank:
          throws: [0, 120, 240]
          spacing: 100 mm
          banks: [-45 deg, 45 deg]
          split: [0 deg, 30 deg]
          bank_stagger: 20 mm
        """)
    layout = load_layout(write(tmp_path, text))
    np.testing.assert_allclose(np.degrees(layout.throw), [0, 30, 120, 150, 240, 270])
    np.testing.assert_allclose(np.degrees(layout.bank), [-45, 45] * 3)
    np.testing.assert_allclose(layout.z, [0, 0.02, 0.1, 0.12, 0.2, 0.22])
    assert layout.pitch == pytest.approx(0.1)


def test_tdc_instead_of_throw(tmp_path):
    text = BASE.replace(
        "{throw: 180 deg, bank: 0 deg, z: 91 mm}", "{tdc: 540 deg, bank: 0 deg, z: 91 mm}"
    )
    layout = load_layout(write(tmp_path, text))
    # throw = bank - tdc = -540 deg, the same pin position as 180 deg
    assert math.cos(layout.throw[1]) == pytest.approx(-1.0)
    assert math.sin(layout.throw[1]) == pytest.approx(0.0, abs=1e-12)


def test_parts_masses_two_mass_split(tmp_path):
    text = BASE.replace(
        "  reciprocating: 0.61 kg\n  rotating: 0.38 kg\n",
        "  piston_group: 0.42 kg\n  conrod: 0.55 kg\n  conrod_cg_to_big_end: 38 mm\n"
        "  conrod_inertia: 1.9e-3 kg m^2\n  crank_unbalance: 0.20 kg\n",
    )
    layout = load_layout(write(tmp_path, text))
    small_end = 0.55 * 0.038 / 0.143
    np.testing.assert_allclose(layout.reciprocating_mass, 0.42 + small_end, rtol=1e-14)
    np.testing.assert_allclose(layout.rotating_mass, 0.55 - small_end + 0.20, rtol=1e-14)
    np.testing.assert_allclose(
        layout.conrod_inertia_correction, 1.9e-3 - 0.55 * 0.038 * (0.143 - 0.038), rtol=1e-12
    )


def test_per_cylinder_overrides(tmp_path):
    text = BASE.replace(
        "{throw: 180 deg, bank: 0 deg, z: 182 mm}",
        "{throw: 180 deg, bank: 0 deg, z: 182 mm, reciprocating: 0.62 kg, offset: 2 mm, "
        "conrod_length: 150 mm}",
    )
    layout = load_layout(write(tmp_path, text))
    np.testing.assert_allclose(layout.reciprocating_mass, [0.61, 0.61, 0.62, 0.61])
    np.testing.assert_allclose(layout.offset, [0, 0, 0.002, 0])
    np.testing.assert_allclose(layout.conrod_length, [0.143, 0.143, 0.150, 0.143])


def test_lumped_override_replaces_value_derived_from_parts(tmp_path):
    text = BASE.replace(
        "  reciprocating: 0.61 kg\n  rotating: 0.38 kg\n",
        "  piston_group: 0.42 kg\n  conrod: 0.55 kg\n  conrod_cg_to_big_end: 38 mm\n",
    ).replace(
        "{throw: 0 deg,   bank: 0 deg, z: 0 mm}",
        "{throw: 0 deg, bank: 0 deg, z: 0 mm, reciprocating: 0.7 kg, piston_group: 0.5 kg}",
    )
    layout = load_layout(write(tmp_path, text))
    assert layout.reciprocating_mass[0] == pytest.approx(0.7)
    # part override re-derives the rest of cylinder 1's masses; others unchanged
    assert layout.reciprocating_mass[1] == pytest.approx(0.42 + 0.55 * 0.038 / 0.143)


def test_expand_round_trip(tmp_path):
    text = BASE.split("cylinders:")[0] + textwrap.dedent("""\
        crank:
          throws: [0, 120, 240]
          spacing: 100 mm
          banks: [-30 deg, 30 deg]
          split: [0 deg, 10 deg]
        firing_order: [1, 2, 3, 4, 5, 6]
        """)
    path = write(tmp_path, text)
    expanded = expand_layout(path)
    assert "cylinders:" in expanded and "crank:" not in expanded
    again = layout_from_text(expanded, "expanded.yaml")
    original = load_layout(path)
    for name in (
        "throw",
        "bank",
        "z",
        "crank_radius",
        "conrod_length",
        "offset",
        "reciprocating_mass",
        "rotating_mass",
    ):
        np.testing.assert_allclose(
            np.cos(getattr(again, name)) if name in ("throw", "bank") else getattr(again, name),
            np.cos(getattr(original, name))
            if name in ("throw", "bank")
            else getattr(original, name),
            rtol=1e-9,
            atol=1e-12,
        )
    assert again.firing_order == original.firing_order
    assert again.speed == pytest.approx(original.speed, rel=1e-9)


@pytest.mark.parametrize("name", builtin_layout_names())
def test_every_builtin_layout_loads_and_expands(name):
    layout = load_layout(name)
    assert layout.n_cylinders >= 1
    assert layout.description and layout.source, "built-in layouts state what they are and why"
    again = layout_from_text(expand_layout(name), f"{name} expanded")
    np.testing.assert_allclose(np.cos(again.throw - layout.throw), 1.0, atol=1e-12)
    np.testing.assert_allclose(again.reciprocating_mass, layout.reciprocating_mass, rtol=1e-9)


def test_builtin_set_is_complete():
    wanted = {
        "single",
        "inline-2-180",
        "inline-2-270",
        "inline-2-360",
        "inline-3",
        "inline-4",
        "inline-5",
        "inline-6",
        "inline-8",
        "boxer-2",
        "boxer-4",
        "boxer-6",
        "v-twin-45",
        "v-twin-60",
        "v-twin-90",
        "v4-narrow",
        "v6-60-split",
        "v6-90",
        "v6-90-split",
        "v6-120",
        "v8-crossplane",
        "v8-flatplane",
        "v10-72",
        "v10-90-split",
        "v12-60",
        "vr6",
        "w12",
        "radial-3",
        "radial-5",
        "radial-7",
        "radial-9",
    }
    assert wanted <= set(builtin_layout_names())


# --- bad input: every class names file, line, column, field and what is valid -----------


def test_unknown_key_with_did_you_mean(tmp_path):
    err = error_of(tmp_path, BASE.replace("  stroke: 86 mm", "  strok: 86 mm"))
    text = str(err)
    assert text.startswith(f"{tmp_path / 'layout.yaml'}:4:3: geometry.strok: unknown key 'strok'")
    assert "did you mean 'stroke'?" in text


def test_unknown_top_level_key(tmp_path):
    err = error_of(tmp_path, BASE + "firing_ordr: [1, 3, 4, 2]\n")
    assert ":14:1: firing_ordr: unknown key" in str(err)
    assert "did you mean 'firing_order'?" in str(err)


def test_missing_field(tmp_path):
    err = error_of(tmp_path, BASE.replace("  conrod_length: 143 mm\n", ""))
    assert ":4:3: geometry.conrod_length: missing 'conrod_length'" in str(err)
    assert "143 mm" in str(err)  # the hint shows what to write


def test_wrong_dimension(tmp_path):
    err = error_of(tmp_path, BASE.replace("stroke: 86 mm", "stroke: 86 kg"))
    assert ":4:11: geometry.stroke: '86 kg' is a mass, not a length" in str(err)
    assert "'86 mm'" in str(err)


def test_speed_in_kg(tmp_path):
    err = error_of(tmp_path, BASE.replace("6000 rpm", "5 kg"))
    assert ":2:8: speed: '5 kg' is a mass, not a speed" in str(err)


def test_impossible_geometry(tmp_path):
    err = error_of(tmp_path, BASE.replace("143 mm", "40 mm"))
    assert str(err).startswith(f"{tmp_path / 'layout.yaml'}:5:18: geometry.conrod_length: ")
    assert (
        "conrod_length '40 mm' is not more than crank_radius (stroke '86 mm' / 2) + |offset| 0 "
        "(not given) (every cylinder)" in str(err)
    )
    assert "conrod_length > crank_radius + |offset|" in str(err)


def test_impossible_geometry_of_one_cylinder_names_its_override(tmp_path):
    text = BASE.replace(
        "  - {throw: 180 deg, bank: 0 deg, z: 91 mm}",
        "  - {throw: 180 deg, bank: 0 deg, z: 91 mm, stroke: 300 mm}",
    ).replace("  conrod_length: 143 mm", "  conrod_length: 143 mm\n  offset: 2 mm")
    err = error_of(tmp_path, text)
    assert err.field == "cylinders[2].stroke"
    assert (err.location.line, err.location.column) == (12, 53)  # the value "300 mm"
    assert (
        "conrod_length '143 mm' is not more than crank_radius (cylinders[2].stroke '300 mm' / 2)"
        " + |offset| '2 mm' (cylinder 2)" in str(err)
    )


def test_impossible_geometry_from_offset_override(tmp_path):
    text = BASE.replace(
        "{throw: 0 deg,   bank: 0 deg, z: 273 mm}",
        "{throw: 0 deg, bank: 0 deg, z: 273 mm, offset: 100 mm}",
    )
    err = error_of(tmp_path, text)
    column = text.splitlines()[12].index("100 mm") + 1
    assert f":13:{column}: cylinders[4].offset:" in str(err)
    assert "(cylinder 4)" in str(err)


@pytest.mark.parametrize(
    ("old", "new", "field"),
    [
        ("reciprocating: 0.61 kg", "reciprocating: 0 kg", "masses.reciprocating"),
        ("reciprocating: 0.61 kg", "reciprocating: -0.61 kg", "masses.reciprocating"),
        ("rotating: 0.38 kg", "rotating: -1 kg", "masses.rotating"),
        ("stroke: 86 mm", "stroke: 0 mm", "geometry.stroke"),
    ],
)
def test_non_positive_values(tmp_path, old, new, field):
    err = error_of(tmp_path, BASE.replace(old, new))
    assert f": {field}: " in str(err)
    assert "must be" in str(err)


def test_zero_rotating_mass_is_allowed(tmp_path):
    layout = load_layout(write(tmp_path, BASE.replace("rotating: 0.38 kg", "rotating: 0 kg")))
    assert np.all(layout.rotating_mass == 0)


def test_duplicate_key(tmp_path):
    err = error_of(
        tmp_path,
        BASE.replace("  conrod_length: 143 mm\n", "  conrod_length: 143 mm\n  stroke: 90 mm\n"),
    )
    assert ":6:3: geometry.stroke: duplicate key 'stroke' (first given on line 4)" in str(err)


def test_both_stroke_and_crank_radius(tmp_path):
    err = error_of(
        tmp_path, BASE.replace("  stroke: 86 mm\n", "  stroke: 86 mm\n  crank_radius: 43 mm\n")
    )
    assert "geometry.stroke: give exactly one of stroke and crank_radius" in str(err)


def test_throw_and_tdc_together(tmp_path):
    line = "  - {throw: 0 deg, tdc: 0 deg, bank: 0 deg, z: 0 mm}"
    err = error_of(tmp_path, BASE.replace("  - {throw: 0 deg,   bank: 0 deg, z: 0 mm}", line))
    column = line.index("0 deg, bank") + 1  # the tdc value
    assert f":10:{column}: cylinders[1].tdc: give exactly one of throw and tdc" in str(err)


def test_lumped_and_parts_mixed(tmp_path):
    err = error_of(
        tmp_path, BASE.replace("  rotating: 0.38 kg\n", "  rotating: 0.38 kg\n  conrod: 0.5 kg\n")
    )
    assert "masses.conrod: 'conrod' given together with lumped masses" in str(err)


def test_mapping_where_list_expected(tmp_path):
    err = error_of(tmp_path, BASE.split("cylinders:")[0] + "cylinders:\n  throw: 0\n")
    assert ":10:3: cylinders: expected a list, got a mapping" in str(err)


def test_list_at_top_level(tmp_path):
    err = error_of(tmp_path, "- 1\n- 2\n")
    assert ":1:1: the document is a list, not a mapping" in str(err)


def test_empty_file(tmp_path):
    err = error_of(tmp_path, "")
    assert "layout.yaml:1:1: the file is empty" in str(err)


def test_yaml_syntax_error(tmp_path):
    err = error_of(tmp_path, BASE.replace("  stroke: 86 mm", "  stroke: [86 mm"))
    assert "layout.yaml:5:" in str(err) and "YAML syntax error" in str(err)


def test_non_utf8_file(tmp_path):
    path = tmp_path / "latin1.yaml"
    path.write_bytes(BASE.replace("Test four", "Moteur à plat").encode("latin-1"))
    with pytest.raises(LayoutError, match=r"latin1.yaml:1:14: byte 0xe0 is not UTF-8"):
        load_layout(path)


def test_binary_file(tmp_path):
    path = tmp_path / "binary.yaml"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00")
    with pytest.raises(LayoutError, match="binary"):
        load_layout(path)


def test_python_tags_are_refused(tmp_path):
    err = error_of(
        tmp_path, BASE.replace("name: Test four", "name: !!python/object/apply:os.system ['true']")
    )
    assert "layout.yaml:1:7" in str(err)


def test_billion_laughs_is_refused_fast(tmp_path, monkeypatch):
    lines = ['a0: &a0 ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    for i in range(1, 10):
        prev = f"*a{i - 1}"
        lines.append(f"a{i}: &a{i} [{', '.join([prev] * 9)}]")
    from balance.io import yamlsource

    converted = [0]
    convert = yamlsource._convert

    def counting(*args):
        converted[0] += 1
        return convert(*args)

    monkeypatch.setattr(yamlsource, "_convert", counting)
    err = error_of(tmp_path, "\n".join(lines) + "\n")
    assert "alias expansion bomb" in str(err)
    # refused after the budget of values, not after expanding 9**10 of them
    assert yamlsource.MAX_NODES < converted[0] <= yamlsource.MAX_NODES + 1


def test_gas_section_without_pressure_is_refused_plainly(tmp_path):
    err = error_of(tmp_path, BASE + "gas:\n  bore: 86 mm\n")
    assert "gas: give exactly one of pressure_trace and model" in str(err)


def test_bad_firing_order(tmp_path):
    err = error_of(tmp_path, BASE + "firing_order: [1, 3, 3, 2]\n")
    assert "firing_order: firing_order [1, 3, 3, 2] is not an ordering of cylinders 1 to 4" in str(
        err
    )


def test_bad_cycle(tmp_path):
    err = error_of(tmp_path, BASE + "cycle: six-stroke\n")
    assert "cycle: 'six-stroke' is not allowed; expected 'four-stroke' or 'two-stroke'" in str(err)


def test_nan_and_infinity(tmp_path):
    assert "not a finite number" in str(error_of(tmp_path, BASE.replace("86 mm", ".nan")))
    assert "not a finite number" in str(error_of(tmp_path, BASE.replace("86 mm", "nan mm")))


def test_missing_file_and_unknown_builtin():
    with pytest.raises(InputError, match="no such file"):
        load_layout("/nonexistent/engine.yaml")
    with pytest.raises(InputError, match="did you mean inline-4"):
        load_layout("inline-44")


def test_crank_unbalance_is_per_throw_and_shared_by_its_rods(tmp_path):
    parts = (
        "  piston_group: 0.42 kg\n  conrod: 0.55 kg\n  conrod_cg_to_big_end: 38 mm\n"
        "  crank_unbalance: 0.20 kg\n"
    )
    v_text = (
        BASE.replace("  reciprocating: 0.61 kg\n  rotating: 0.38 kg\n", parts).split("cylinders:")[
            0
        ]
        + "crank:\n  throws: [0, 90, 270, 180]\n  spacing: 91 mm\n  banks: [-45, 45]\n"
    )
    v8 = load_layout(write(tmp_path, v_text, "v8.yaml"))
    big_end = 0.55 * (1 - 0.038 / 0.143)
    np.testing.assert_allclose(v8.rotating_mass, big_end + 0.10)  # two rods per throw
    # the explicit form: rods with the same throw angle and z share the throw
    explicit = BASE.replace("  reciprocating: 0.61 kg\n  rotating: 0.38 kg\n", parts).split(
        "cylinders:"
    )[0] + (
        "cylinders:\n"
        "  - {throw: 0, bank: -45, z: 0}\n  - {throw: 360, bank: 45, z: 0}\n"
        "  - {throw: 180, bank: -45, z: 90 mm}\n"
    )
    layout = load_layout(write(tmp_path, explicit, "x.yaml"))
    np.testing.assert_allclose(layout.rotating_mass, [big_end + 0.1, big_end + 0.1, big_end + 0.2])


def test_oversized_file_is_refused(tmp_path):
    path = tmp_path / "huge.yaml"
    path.write_text(BASE + "# " + "x" * 1_100_000 + "\n")
    with pytest.raises(LayoutError, match="more than the 1000000 bytes a layout may have"):
        load_layout(path)


def test_deep_nesting_is_refused(tmp_path):
    err = error_of(tmp_path, "a: " + "[" * 200 + "]" * 200 + "\n")
    assert "nested deeper than 32 levels" in str(err)


def test_misspelt_required_key_gets_did_you_mean(tmp_path):
    err = error_of(tmp_path, BASE.replace("conrod_length:", "conrod_lenght:"))
    assert "geometry.conrod_lenght: unknown key 'conrod_lenght'" in str(err)
    assert "did you mean 'conrod_length'?" in str(err)
