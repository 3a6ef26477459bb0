"""The layout file's reader in parts: one translator of validation problems for every
section, one table of numeric fields, models derived from the core's dataclasses, and a
registry of the concern sections that the reader and the writer loop over."""

from __future__ import annotations

import dataclasses
import io
import subprocess
import sys
import textwrap
import tokenize
from pathlib import Path

import pytest

from balance.core.engine import BalanceSettings, ShaftPosition
from balance.core.errors import LayoutError, LayoutErrors
from balance.core.gas import GasModel
from balance.core.sections import SECTIONS
from balance.io import fields, layout_fields, schema, schema_options
from balance.io.layout_fields import FIELDS, layout_field
from balance.io.layout_file import layout_from_text
from balance.io.layout_sections import LAYOUT_SECTIONS, section_reader
from balance.studies import changes

PACKAGE = Path(__file__).resolve().parents[1] / "balance"

# geometry:, bearings: and mounts: in one file, each with the same kinds of value
LAYOUT = textwrap.dedent(
    """\
    name: Inline-4 with its mains and mounts
    speed: 6000 rpm
    geometry:
      stroke: 86 mm
      conrod_length: 139 mm
    masses:
      reciprocating: 0.6 kg
      rotating: 0.5 kg
    crank:
      throws: [0, 180, 180, 0]
      spacing: 90 mm
    bearings:
      mains: [-45 mm, 45 mm, 135 mm, 225 mm, 315 mm]
    mounts:
      mass: 150 kg
      cg: [-40 mm, 60 mm, 230 mm]
      inertia: {xx: 6.0 kg m^2, yy: 5.1 kg m^2, zz: 4.4 kg m^2}
      points:
        - {position: [0 mm, 250 mm, -80 mm], stiffness: [120 N/mm, 250 N/mm, 150 N/mm]}
        - {position: [-40 mm, 200 mm, 560 mm], stiffness: [120 N/mm, 250 N/mm, 150 N/mm]}
        - {position: [250 mm, -150 mm, 250 mm], stiffness: [300 N/mm, 40 N/mm, 40 N/mm]}
        - {position: [-300 mm, -150 mm, 250 mm], stiffness: [300 N/mm, 40 N/mm, 40 N/mm]}
    """
)


def _problems(text: str) -> list[str]:
    with pytest.raises(LayoutError) as info:
        layout_from_text(text, "f.yaml")
    return info.value.lines() if isinstance(info.value, LayoutErrors) else [str(info.value)]


def _at(text: str, written: str, after: str = "") -> str:
    """``line:column`` (1-based) of ``written`` in ``text`` (its first occurrence after
    ``after``)."""
    start = text.index(after) if after else 0
    offset = text.index(written, start)
    line = text.count("\n", 0, offset) + 1
    column = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return f"{line}:{column}"


def test_a_bare_number_reads_the_same_in_every_section():
    text = (
        LAYOUT.replace("stroke: 86 mm", "stroke: 86")
        .replace("mains: [-45 mm, 45 mm", "mains: [-45 mm, 45")
        .replace("mass: 150 kg", "mass: 150")
    )
    assert _problems(text) == [
        f"f.yaml:{_at(text, '86', 'stroke')}: geometry.stroke: 86 has no unit; "
        "give a unit, e.g. '86 mm'",
        f"f.yaml:{_at(text, '45,', 'mains:')}: bearings.mains[2]: 45 has no unit; "
        "give a unit, e.g. '45 mm'",
        f"f.yaml:{_at(text, '150', 'mass')}: mounts.mass: 150 has no unit; "
        "give a unit, e.g. '150 kg'",
    ]


def test_an_unknown_key_reads_the_same_in_every_section():
    """A misspelt key gets a did-you-mean and the keys valid there, located at the key;
    a required key it misspells is not reported missing as well."""
    text = (
        LAYOUT.replace("conrod_length:", "conrod_lenght:")
        .replace("mains:", "mainz:")
        .replace("mass: 150 kg", "mas: 150 kg")
    )
    lines = _problems(text)
    assert lines == [
        f"f.yaml:{_at(text, 'conrod_lenght')}: geometry.conrod_lenght: unknown key "
        "'conrod_lenght'; did you mean 'conrod_length'? valid keys: stroke, crank_radius, "
        "conrod_length, offset, bore",
        f"f.yaml:{_at(text, 'mainz')}: bearings.mainz: unknown key 'mainz'; did you mean "
        "'mains'? valid keys: mains",
        f"f.yaml:{_at(text, 'mas:')}: mounts.mas: unknown key 'mas'; did you mean 'mass'? "
        "valid keys: mass, cg, inertia, points",
    ]
    assert not any("missing" in line for line in lines)


def test_a_value_of_the_wrong_type_reads_the_same_in_every_section():
    text = (
        LAYOUT.replace("conrod_length: 139 mm", "conrod_length: [139 mm]")
        .replace("mains: [-45 mm, 45 mm, 135 mm, 225 mm, 315 mm]", "mains: 5")
        .replace("inertia: {xx: 6.0 kg m^2, yy: 5.1 kg m^2, zz: 4.4 kg m^2}", "inertia: 5")
    )
    problems = _problems(text)
    assert problems[0] == (
        f"f.yaml:{_at(text, '[139 mm]')}: geometry.conrod_length: expected length, got a "
        "list; give length with a unit, e.g. '86 mm'"
    )
    assert problems[1:] == [
        f"f.yaml:{_at(text, '5', 'mains:')}: bearings.mains: expected a list, got a whole "
        "number; write a list here",
        f"f.yaml:{_at(text, '5', 'inertia')}: mounts.inertia: expected a mapping, got a whole "
        "number; write a mapping here",
    ]


def test_a_list_of_the_wrong_length_reads_the_same_in_every_section():
    text = LAYOUT.replace("throws: [0, 180, 180, 0]", "throws: []").replace(
        "cg: [-40 mm, 60 mm, 230 mm]", "cg: [-40 mm, 60 mm]"
    )
    assert _problems(text) == [
        f"f.yaml:{_at(text, '[]')}: crank.throws: 0 throws; at least 1 throw",
        f"f.yaml:{_at(text, '[-40 mm, 60 mm]')}: mounts.cg: 2 entries; three values [x, y, z]",
    ]


def test_a_section_builder_s_problem_is_located_like_a_model_s_and_reported_with_the_rest():
    """A main in a crank pin's plane is found by the section's builder, on the engine read
    from the rest of the file; it is reported with the rest's problems, located alike."""
    text = LAYOUT.replace("mains: [-45 mm, 45 mm", "mains: [-45 mm, 90 mm").replace(
        "conrod_length: 139 mm", "conrod_length: 39 mm"
    )
    problems = _problems(text)
    assert len(problems) == 2
    assert problems[0].startswith(f"f.yaml:{_at(text, '39 mm')}: geometry.conrod_length: ")
    assert problems[1] == (
        f"f.yaml:{_at(text, '90 mm', 'mains:')}: bearings.mains[2]: main 2 at 90 mm is in the "
        "plane of the crank pin of cylinder 2; put main bearings between throw planes (or "
        "beyond the end throws)"
    )


def test_a_mounts_file_and_a_mounts_section_give_the_same_problem():
    from balance.io.mounts_section import mounts_from_text

    text = LAYOUT.replace("mass: 150 kg", "mass: 150 m")
    section = text[text.index("mounts:") :]
    (in_layout,) = _problems(text)
    with pytest.raises(LayoutError) as info:
        mounts_from_text(section, "f.yaml")
    line = int(_at(text, "150 m").split(":")[0]) - text[: text.index("mounts:")].count("\n")
    column = _at(text, "150 m").split(":")[1]
    assert str(info.value) == in_layout.replace(_at(text, "150 m"), f"{line}:{column}")


# ---------------------------------------------------------------------------------------
# one table of fields


def test_the_schema_s_models_are_the_table_s_rows():
    def names(place):
        return [f.name for f in layout_fields.placed(place)]

    assert list(schema.GeometrySpec.model_fields) == names(layout_fields.GEOMETRY)
    assert list(schema.MassesSpec.model_fields) == names(layout_fields.MASSES)
    entry = [f.name for f in layout_fields.entry_fields()]
    assert list(schema.CylinderSpec.model_fields) == [
        *entry,
        "throw_id",
        "link",
        "crankshaft",
        "opposed",
    ]
    # the defaults: the row's where it is given engine-wide, None for an override
    assert schema.GeometrySpec.model_fields["offset"].default == 0.0
    assert schema.GeometrySpec.model_fields["conrod_length"].is_required()
    assert schema.CylinderSpec.model_fields["z"].is_required()
    assert schema.CylinderSpec.model_fields["bank"].default == 0.0
    assert schema.CylinderSpec.model_fields["offset"].default is None
    # the engine-wide rows the layout file gives at its top
    for row in layout_fields.placed(layout_fields.ENGINE):
        assert row.name in schema.LayoutSpec.model_fields


def test_a_row_s_kind_is_what_the_schema_reads_and_expand_writes():
    """A bare number in each field's model is refused with its kind's likely unit, and
    ``layout expand`` writes the kind's unit."""
    from pydantic import ValidationError

    models = {
        layout_fields.GEOMETRY: schema.GeometrySpec,
        layout_fields.MASSES: schema.MassesSpec,
        layout_fields.CYLINDER: schema.CylinderSpec,
    }
    likely = {"length": "m", "mass": "g", "inertia": "m^2"}
    checked = 0
    for row in FIELDS:
        if row.place not in models or row.kind not in likely:
            continue
        with pytest.raises(ValidationError) as info:
            models[row.place].model_validate({row.name: "3"})
        (own,) = [e for e in info.value.errors() if e["loc"] == (row.name,)]
        assert own["msg"].endswith("3 has no unit"), own
        assert own["ctx"]["error"].suggestion.endswith(likely[row.kind]), row.name
        checked += 1
    assert checked == 15  # geometry 5, masses 9 (piston_rod and crosshead too), z
    assert layout_fields.written(0.086, layout_field("stroke").kind) == "86 mm"
    assert layout_fields.written(-0.0, layout_field("bank").kind) == "0 deg"
    assert layout_fields.written(0.5, "fraction") == "50 %"


def test_the_command_line_s_fields_and_the_studies_rules_read_the_table():
    rows = {f.name: f for f in FIELDS}
    for name, (attribute, kind) in fields.CYLINDER_FIELDS.items():
        assert rows[name].per_cylinder and (rows[name].attribute, rows[name].kind) == (
            attribute,
            kind,
        )
    engine_wide = list(fields.ENGINE_FIELDS)
    assert (engine_wide[0], engine_wide[-1]) == ("speed", "reference_z")
    assert set(fields.ENGINE_FIELDS) == {
        f.name for f in FIELDS if f.attribute and f.place != layout_fields.CYLINDER
    }
    lumped = {"reciprocating_mass", "rotating_mass"}
    geometry = {"throw", "bank", "z", "crank_radius", "conrod_length", "offset"}
    assert lumped == changes.LUMPED
    assert geometry == changes.LINK_GEOMETRY


# ---------------------------------------------------------------------------------------
# models derived from the core's dataclasses


@pytest.mark.parametrize(
    ("spec", "core"),
    [
        (schema_options.BalanceSpec, BalanceSettings),
        (schema_options.ShaftSpec, ShaftPosition),
        (schema_options.GasModelSpec, GasModel),
    ],
)
def test_a_core_section_s_model_has_the_dataclass_s_fields_and_defaults(spec, core):
    assert list(spec.model_fields) == [f.name for f in dataclasses.fields(core)]
    for f in dataclasses.fields(core):
        info = spec.model_fields[f.name]
        if f.default is dataclasses.MISSING:
            assert info.is_required(), f.name
        else:
            assert info.default == f.default, f.name


def test_a_core_section_s_model_gives_its_dataclass():
    spec = schema_options.BalanceSpec.model_validate(
        {"orders": [1, 2], "balance_factor": "50 %", "shafts": [{"speed_ratio": 2, "x": "10 mm"}]}
    )
    assert spec.to_core() == BalanceSettings(
        balance_factor=0.5, orders=(1, 2), shafts=(ShaftPosition(2, 0.01),)
    )


# ---------------------------------------------------------------------------------------
# the registry of concern sections


def test_each_registered_section_is_a_concern_section_of_the_core():
    layout_keys = {s.layout_key: s.name for s in SECTIONS if s.layout_key}
    for key in LAYOUT_SECTIONS:
        assert layout_keys.get(key) == key
        assert section_reader(key).key == key


def _identifiers(path: Path) -> set[str]:
    tokens = tokenize.tokenize(io.BytesIO(path.read_bytes()).readline)
    return {t.string.lower() for t in tokens if t.type == tokenize.NAME}


@pytest.mark.parametrize(
    "module", ["layout_file", "layout_reader", "layout_expand", "schema", "located"]
)
def test_the_reader_and_the_writer_name_no_concern_section(module):
    names = _identifiers(PACKAGE / "io" / f"{module}.py")
    for key in LAYOUT_SECTIONS:
        stem = key.rstrip("s")
        assert not {n for n in names if stem in n}, (module, key)


def test_no_module_of_io_is_over_a_thousand_lines():
    for path in sorted((PACKAGE / "io").glob("*.py")):
        assert len(path.read_text(encoding="utf-8").splitlines()) <= 1000, path.name


def test_the_front_of_layout_files_keeps_its_names():
    from balance.io import layout_expand, layout_file, layout_reader, layouts

    assert layout_file.load_layout is layout_reader.load_layout
    assert layout_file.layout_from_text is layout_reader.layout_from_text
    assert layout_file.layout_from_dict is layout_reader.layout_from_dict
    assert layout_file.expand_layout is layout_expand.expand_layout
    assert layout_file.builtin_layout_names is layouts.builtin_layout_names
    assert layout_file.builtin_layout_path is layouts.builtin_layout_path


def test_layout_model_used_alone_reads_its_optional_sections():
    """LayoutSpec names the models of balance:, gas: and flywheel:, which a layout
    without them does not import (io.schema_options): used alone, in a fresh process,
    it imports them on first use and reads those sections, SI after validation."""
    code = (
        "from balance.io.schema import LayoutSpec\n"
        "spec = LayoutSpec.model_validate({'name': 'x', 'speed': '6000 rpm', "
        "'geometry': {'stroke': '86 mm', 'conrod_length': '143 mm', 'bore': '86 mm'}, "
        "'masses': {'reciprocating': '0.5 kg', 'rotating': '0.6 kg'}, "
        "'crank': {'throws': [0, 180, 180, 0], 'spacing': '90 mm'}, "
        "'balance': {'balance_factor': '50 %'}, 'flywheel': {'inertia': '0.1 kg m^2'}, "
        "'gas': {'model': {'compression_ratio': 10.5, 'peak_pressure': '75 bar'}}})\n"
        "print(spec.balance.balance_factor.value, spec.flywheel.inertia, "
        "spec.gas.model.peak_pressure)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["0.5", "0.1", "7500000.0"]
