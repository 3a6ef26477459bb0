"""The ``mounts:`` section (balance.io.mounts_section): units, validation, located errors."""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest

from balance.core.errors import InputError, LayoutError, LayoutErrors
from balance.core.mounts import MountSystem
from balance.io.mounts_section import load_mounts, mounts_from_dict, mounts_from_text

CONTRACT_EXAMPLE = """\
mass: 160 kg
cg: [0 mm, 60 mm, 140 mm]
inertia: {xx: 7.5 kg m^2, yy: 9 kg m^2, zz: 4 kg m^2,
          xy: 0 kg m^2, xz: 0 kg m^2, yz: 0 kg m^2}
points:
  - {position: [-220 mm, -120 mm, 0 mm],
     stiffness: [250 N/mm, 400 N/mm, 150 N/mm],
     damping: [300 N s/m, 500 N s/m, 200 N s/m],
     axes: [[1, 0, 0], [0, 1, 0]]}
  - {position: [220 mm, -120 mm, 0 mm], stiffness: [250 N/mm, 400 N/mm, 150 N/mm]}
  - {position: [0 mm, -100 mm, 300 mm], stiffness: [200 N/mm, 300 N/mm, 200 N/mm]}
"""


def test_contract_example_reads_in_si():
    system = mounts_from_text(CONTRACT_EXAMPLE)
    assert isinstance(system, MountSystem)
    assert system.mass == 160.0
    np.testing.assert_allclose(system.cg, [0, 0.06, 0.14])
    np.testing.assert_allclose(system.inertia, np.diag([7.5, 9.0, 4.0]))
    first = system.points[0]
    np.testing.assert_allclose(first.position, [-0.22, -0.12, 0.0])
    np.testing.assert_allclose(first.stiffness, [2.5e5, 4.0e5, 1.5e5])
    np.testing.assert_allclose(first.damping, [300, 500, 200])
    np.testing.assert_allclose(first.axes, np.eye(3))
    np.testing.assert_allclose(system.points[1].damping, 0.0)


def test_section_under_a_mounts_key_and_from_a_file(tmp_path):
    nested = "mounts:\n" + textwrap.indent(CONTRACT_EXAMPLE, "  ")
    top = mounts_from_text(CONTRACT_EXAMPLE)
    under = mounts_from_text(nested)
    np.testing.assert_allclose(under.cg, top.cg)
    path = tmp_path / "mounts.yaml"
    path.write_text(nested, encoding="utf-8")
    np.testing.assert_allclose(load_mounts(path).points[2].position, [0, -0.1, 0.3])
    with pytest.raises(InputError, match="no such file"):
        load_mounts(tmp_path / "missing.yaml")


def test_units_of_stiffness_damping_and_inertia():
    data = _data()
    data["points"][0]["stiffness"] = ["1 kN/mm", "2.0e5 N/m", "3e5 N/m"]
    data["points"][0]["damping"] = ["0.3 kN s/m", "0.2 N s/mm", "100 kg/s"]
    data["inertia"]["xy"] = "1000 kg cm^2"
    system = mounts_from_dict(data)
    np.testing.assert_allclose(system.points[0].stiffness, [1e6, 2e5, 3e5])
    np.testing.assert_allclose(system.points[0].damping, [300, 200, 100])
    assert system.inertia[0, 1] == pytest.approx(0.1)


def test_axes_are_orthonormalised():
    data = _data()
    data["points"][0]["axes"] = [[0, 2, 0], [1, 1, 0]]  # axis 1 along y; 2 towards +x
    axes = mounts_from_dict(data).points[0].axes
    np.testing.assert_allclose(axes, [[0, 1, 0], [1, 0, 0], [0, 0, -1]], atol=1e-15)
    np.testing.assert_allclose(axes @ axes.T, np.eye(3), atol=1e-15)


def _data() -> dict:
    return {
        "mass": "160 kg",
        "cg": ["0 mm", "60 mm", "140 mm"],
        "inertia": {"xx": "7.5 kg m^2", "yy": "9 kg m^2", "zz": "4 kg m^2"},
        "points": [
            {"position": ["-220 mm", "-120 mm", "0 mm"], "stiffness": ["250 N/mm"] * 3},
            {"position": ["220 mm", "-120 mm", "0 mm"], "stiffness": ["250 N/mm"] * 3},
            {"position": ["0 mm", "-100 mm", "300 mm"], "stiffness": ["250 N/mm"] * 3},
        ],
    }


def _error(text: str) -> LayoutError:
    with pytest.raises(LayoutError) as info:
        mounts_from_text(textwrap.dedent(text), "m.yaml")
    return info.value


def test_negative_stiffness_is_located():
    err = _error(CONTRACT_EXAMPLE.replace("[200 N/mm, 300 N/mm", "[200 N/mm, -300 N/mm"))
    assert err.field == "points[3].stiffness[2]"
    assert err.location.line == 11
    assert "zero or more" in (err.valid or "")


def test_stiffness_needs_a_stiffness_unit():
    err = _error(CONTRACT_EXAMPLE.replace("150 N/mm]", "150 N]", 1))
    assert err.field == "points[1].stiffness[3]"
    assert "N/mm" in (err.valid or "")


def test_parallel_axes_are_refused():
    err = _error(CONTRACT_EXAMPLE.replace("[[1, 0, 0], [0, 1, 0]]", "[[1, 0, 0], [-2, 0, 0]]"))
    assert err.field == "points[1].axes[2]"
    assert "parallel" in err.message


def test_inertia_must_be_a_body_s():
    err = _error(CONTRACT_EXAMPLE.replace("zz: 4 kg m^2", "zz: 20 kg m^2"))
    assert err.field == "inertia"
    assert "triangle" in (err.valid or "")
    err = _error(CONTRACT_EXAMPLE.replace("xy: 0 kg m^2", "xy: 9 kg m^2"))
    assert "positive definite" in err.message


def test_mounts_that_do_not_hold_the_engine_are_refused():
    data = _data()
    data["points"] = data["points"][:2]  # two point mounts: free to turn about their line
    with pytest.raises(LayoutError, match="moves freely, mostly about x") as info:
        mounts_from_dict(data)
    assert info.value.field == "points"


def test_unknown_key_gets_a_hint():
    err = _error(CONTRACT_EXAMPLE.replace("damping:", "dampng:"))
    assert err.field == "points[1].dampng"
    assert "did you mean 'damping'" in (err.valid or "")
    err = _error("mounts:\n" + textwrap.indent(CONTRACT_EXAMPLE, "  ") + "name: x\n")
    assert "beside 'mounts'" in err.message


def test_missing_and_short_fields():
    err = _error(CONTRACT_EXAMPLE.replace("cg: [0 mm, 60 mm, 140 mm]\n", ""))
    assert err.field == "cg"
    assert "centre of gravity" in (err.valid or "")
    err = _error(CONTRACT_EXAMPLE.replace("[0 mm, 60 mm, 140 mm]", "[0 mm, 60 mm]"))
    assert err.field == "cg"
    assert math.isfinite(err.location.line or math.nan)


def test_a_bare_stiffness_is_refused_with_the_likely_unit():
    data = _data()
    data["points"][0]["stiffness"] = ["250 N/mm", 400, "0"]
    with pytest.raises(LayoutError, match=r"give a unit, e\.g\. '400 N/mm'"):
        mounts_from_dict(data)
    data["points"][0]["stiffness"] = ["250 N/mm", "400 N/mm", 0]
    data["points"][0]["damping"] = ["300", "0 N s/m", 0]
    with pytest.raises(LayoutError, match=r"give a unit, e\.g\. '300 N s/m'"):
        mounts_from_dict(data)


def test_bare_mass_and_lengths_and_a_thousands_separator_are_refused_together():
    """Every problem of a mounts file at once; the powertrain's mass is proposed in kg."""
    text = (
        CONTRACT_EXAMPLE.replace("mass: 160 kg", "mass: 160")
        .replace("cg: [0 mm, 60 mm, 140 mm]", "cg: [0, 60, 140 mm]")
        .replace(
            "stiffness: [250 N/mm, 400 N/mm, 150 N/mm],\n",
            "stiffness: [250 000 N/m, 400 N/mm, 150 N/mm],\n",
            1,
        )
    )
    with pytest.raises(LayoutErrors) as info:
        mounts_from_text(text, "m.yaml")
    assert info.value.lines() == [
        "m.yaml:1:7: mass: 160 has no unit; give a unit, e.g. '160 kg'",
        "m.yaml:2:9: cg[2]: 60 has no unit; give a unit, e.g. '60 mm'",
        "m.yaml:7:18: points[1].stiffness[1]: '250 000 N/m' has a thousands separator; write the "
        "number without it, e.g. '250000 N/m'",
    ]
