"""Sweeps over the fields of the compact crank: form and the balance: section (issue 22):
each grid point equals the analysis of the layout file edited by hand, bit for bit."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

import balance
from balance.api import analyse
from balance.cli import app
from balance.core.errors import InputError
from balance.io.layout_file import builtin_layout_path, load_layout
from balance.studies.sweep import sweep, variant

runner = CliRunner()


def _edited(tmp_path: Path, name: str, edit: dict, tag: str) -> Path:
    """The built-in layout ``name`` with some keys of its sections rewritten, as a designer
    would edit the file (``{"crank": {"spacing": "105 mm"}}``)."""
    data = yaml.safe_load(builtin_layout_path(name).read_text(encoding="utf-8"))
    for section, values in edit.items():
        data.setdefault(section, {}).update(values)
    path = tmp_path / f"{name}-{tag}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def _assert_point_is_the_edited_layout(at, path: Path, proposal: bool = False) -> None:
    reference = analyse(load_layout(path), "1-8", proposal=proposal)
    assert at.data_vars
    for name in at.data_vars:
        a, b = at[name].values, reference[name].values
        assert a.shape == b.shape, name
        assert np.array_equal(a, b), (name, path.name, np.max(np.abs(a - b)))


def test_spacing_and_bank_stagger(tmp_path):
    """crank.spacing x crank.bank_stagger x speed over the cross-plane V8: every point."""
    layout = balance.load_layout("v8-crossplane")
    spacings, staggers = ["100mm", "111.76mm", "125mm"], ["0mm", "21.5mm"]
    ds = sweep(
        layout,
        {
            "crank.spacing": ",".join(spacings),
            "crank.bank_stagger": ",".join(staggers),
            "speed": "3000rpm,6500rpm",
        },
        "1-8",
    )
    assert ds.reciprocating_moment_magnitude.dims[:3] == (
        "crank_spacing",
        "crank_bank_stagger",
        "speed",
    )
    for i, j, k in np.ndindex(3, 2, 2):
        speed = ["3000 rpm", "6500 rpm"][k]
        spacing, stagger = (t.replace("mm", " mm") for t in (spacings[i], staggers[j]))
        path = _edited(
            tmp_path,
            "v8-crossplane",
            {"crank": {"spacing": spacing, "bank_stagger": stagger}},
            f"{i}{j}{k}",
        )
        path.write_text(path.read_text().replace("speed: 5000 rpm", f"speed: {speed}"))
        assert f"speed: {speed}" in path.read_text()
        _assert_point_is_the_edited_layout(
            ds.isel(crank_spacing=i, crank_bank_stagger=j, speed=k), path
        )
    # the stagger moves the second bank's rods along the crank: each bank's fourth-order
    # forces (in phase on the four throws) no longer act in one plane, a moment appears
    m4 = ds.reciprocating_moment_peak.sel(order=4).isel(crank_spacing=1, speed=0).values
    assert m4[0] == 0.0 and m4[1] > 1.0


@pytest.mark.parametrize(
    ("name", "field", "values", "banks"),
    [
        # the bank angle of one bank: the second bank of the 90° V-twin from 45° to 15°, 75°
        ("v-twin-90", "crank.banks[2]", "15,75deg", [["-45 deg", "15 deg"], ["-45 deg", "75 deg"]]),
        # the V angle of the cross-plane V8 (banks [45, -45]): each bank keeps its side
        (
            "v8-crossplane",
            "crank.v_angle",
            "60,72deg",
            [["30 deg", "-30 deg"], ["36 deg", "-36 deg"]],
        ),
        # and of a V-twin, with an exact angle
        ("v-twin-90", "crank.v_angle", "360/7", [["-180/7 deg", "180/7 deg"]]),
    ],
)
def test_bank_angles(tmp_path, name, field, values, banks):
    layout = balance.load_layout(name)
    ds = sweep(layout, {field: values}, "1-8")
    dim = ds.reciprocating_force_magnitude.dims[0]
    for i, edited in enumerate(banks):
        path = _edited(tmp_path, name, {"crank": {"banks": edited}}, str(i))
        _assert_point_is_the_edited_layout(ds.isel({dim: i}), path)
    assert not np.array_equal(
        ds.reciprocating_force_magnitude.isel({dim: 0}).values,
        analyse(layout, "1-8").reciprocating_force_magnitude.values,
    )


def test_balance_factor_gives_the_residual_with_the_proposal(tmp_path):
    """balance.balance_factor=30%:100%:15 (the issue's example) over the single: the free
    forces do not move, the residual with the proposal does, and each point is the analysis
    of the file with balance: {balance_factor: ...} written in."""
    layout = balance.load_layout("single")
    ds = sweep(layout, {"balance.balance_factor": "30%:100%:15"}, "1-8")
    assert ds.balance_factor.values[0] == 0.3 and ds.balance_factor.values[-1] == 1.0
    assert ds.balance_factor.attrs["units"] == "1"
    free = ds.reciprocating_force_magnitude.values
    assert all(np.array_equal(free[0], f) for f in free)
    first = ds.residual_force_magnitude.sel(order=1, rotation="forward").values
    assert len(set(first.tolist())) > 10  # the residual first order follows the factor
    for i in (0, 7, 14):
        factor = f"{float(ds.balance_factor[i]) * 100!r} %"
        path = _edited(tmp_path, "single", {"balance": {"balance_factor": factor}}, str(i))
        assert load_layout(path).balance.balance_factor == float(ds.balance_factor[i])
        _assert_point_is_the_edited_layout(ds.isel(balance_factor=i), path, proposal=True)


def test_balance_factor_sweep_keeps_the_files_convention(tmp_path):
    """A layout giving its factor as a share of one cylinder's first order
    (balance: {balance_factor: {of: one-cylinder, value: ...}}) is swept in that convention:
    each point is the file with that value written in the same convention, and on the 90 deg
    V-twin 100 % of one cylinder is 50 % of each (docs/theory.md), so the point at 100 %
    leaves no forward first order of the whole free force."""
    one = {"balance": {"balance_factor": {"of": "one-cylinder", "value": "60 %"}}}
    layout = load_layout(_edited(tmp_path, "v-twin-90", one, "base"))
    ds = sweep(layout, {"balance.balance_factor": "60%:100%:5"}, "1-8")
    for i in (0, 4):
        value = {"of": "one-cylinder", "value": f"{float(ds.balance_factor[i]) * 100!r} %"}
        path = _edited(tmp_path, "v-twin-90", {"balance": {"balance_factor": value}}, str(i))
        _assert_point_is_the_edited_layout(ds.isel(balance_factor=i), path, proposal=True)
    full = ds.isel(balance_factor=4).residual_force_magnitude.sel(order=1, rotation="forward")
    scale = float(ds.isel(balance_factor=0).residual_force_magnitude.sel(order=1).max())
    assert (
        float(full)
        < 1e-12 * scale
        < float(ds.isel(balance_factor=0).residual_force_magnitude.sel(order=1, rotation="forward"))
    )


def test_balance_factor_with_speed_and_a_crank_field(tmp_path):
    layout = balance.load_layout("v-twin-90")
    ds = sweep(
        layout,
        {"balance.balance_factor": "0.4,0.6", "crank.v_angle": "60,90", "speed": "5000rpm"},
        "1-8",
    )
    for i, j in np.ndindex(2, 2):
        banks = [["-30 deg", "30 deg"], ["-45 deg", "45 deg"]][j]
        path = _edited(
            tmp_path,
            "v-twin-90",
            {"crank": {"banks": banks}, "balance": {"balance_factor": [0.4, 0.6][i]}},
            f"{i}{j}",
        )
        path.write_text(path.read_text().replace("speed: 9000 rpm", "speed: 5000 rpm"))
        at = ds.isel(balance_factor=i, crank_v_angle=j, speed=0)
        _assert_point_is_the_edited_layout(at, path, proposal=True)


def test_variant_of_crank_fields_is_the_edited_layout(tmp_path):
    layout = balance.load_layout("v8-crossplane")
    got = variant(layout, {"crank.spacing": 0.1, "crank.bank_stagger": 0.02, "crank.banks[2]": -30})
    path = _edited(
        tmp_path,
        "v8-crossplane",
        {"crank": {"spacing": "0.1 m", "bank_stagger": "0.02 m", "banks": ["45 deg", "-30 deg"]}},
        "v",
    )
    want = load_layout(path)
    for attribute in ("throw", "bank", "z", "crank_radius", "reciprocating_mass"):
        assert np.array_equal(getattr(got, attribute), getattr(want, attribute)), attribute
    assert got.reference_z == want.reference_z


@pytest.mark.parametrize(
    ("name", "field", "message"),
    [
        (
            "radial-7",
            "crank.spacing=1mm,2mm",
            "--vary: crank.spacing: layout 'Radial-7 (Continental W670)' gives its cylinders one "
            "by one (no crank: section); vary cylinders[N].z or cylinders[N].bank instead",
        ),
        (
            "inline-4",
            "crank.v_angle=60,90",
            "--vary: 'crank.v_angle': a V angle needs two banks, the layout has 1; vary "
            "crank.banks[N]",
        ),
        ("v6-90", "crank.banks[3]=10,20", "--vary: 'crank.banks[3]': the layout has banks 1 to 2"),
        (
            "v6-90",
            "crank.spacin=1mm,2mm",
            "--vary: 'crank.spacin' is not a field of the crank: section a sweep varies; did you "
            "mean 'crank.spacing'? valid: crank.spacing, crank.bank_stagger, crank.banks[N], "
            "crank.v_angle",
        ),
        (
            "v6-90",
            "balance.balance_factor=30%:300%:3",
            "--vary: balance.balance_factor: 300% is outside 0 % to 200 % (the share of the "
            "reciprocating mass put on the crank)",
        ),
    ],
)
def test_refused_crank_and_balance_fields(name, field, message, tmp_path):
    result = runner.invoke(app, ["sweep", name, "--vary", field, "-o", str(tmp_path / "s.nc")])
    assert result.exit_code == 2
    assert result.stderr == f"balance: {message}\n"


def test_balance_field_needs_moments_and_roll(tmp_path):
    result = runner.invoke(
        app,
        ["sweep", "v6-90", "--vary", "balance.balance_factor=0.5,0.6", "--no-roll", "-o",
         str(tmp_path / "s.nc")],
    )  # fmt: skip
    assert result.exit_code == 2
    assert result.stderr == (
        "balance: --vary balance.balance_factor: the residual with the proposal needs the "
        "moments and the roll; drop --no-moments and --no-roll\n"
    )
    with pytest.raises(InputError, match="compute both"):
        sweep(balance.load_layout("v6-90"), {"balance.balance_factor": "0.5"}, roll=False)


def test_a_changed_engine_is_not_swept_by_its_file():
    layout = balance.load_layout("v6-90")
    moved = replace(layout, z=layout.z + 0.001)
    with pytest.raises(InputError, match="differ from its file's crank: section"):
        sweep(moved, {"crank.spacing": "90mm,100mm"})


def test_crank_fields_cannot_be_scattered():
    result = runner.invoke(app, ["tolerance", "v6-90", "--scatter", "crank.spacing=±1mm"])
    assert result.exit_code == 2
    assert "'crank.spacing' is not a part or geometry field of a cylinder" in result.stderr


def test_sweep_command_writes_a_crank_sweep(tmp_path):
    out = tmp_path / "v.nc"
    result = runner.invoke(
        app,
        ["sweep", "v-twin-90", "--vary", "crank.v_angle=45:90:4", "--vary",
         "balance.balance_factor=50%,70%", "-o", str(out)],
    )  # fmt: skip
    assert result.exit_code == 0, result.stderr
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert ds.sizes["crank_v_angle"] == 4 and ds.sizes["balance_factor"] == 2
        assert ds.crank_v_angle.attrs["units"] == "deg"
        assert "residual_force_peak" in ds


@pytest.mark.parametrize(
    ("name", "vary", "at", "edit"),
    [
        # throw spacing: the cross-plane V8's throws from 100 mm to 125 mm apart
        ("v8-crossplane", "crank.spacing=100mm:125mm:6", 3, {"crank": {"spacing": "115 mm"}}),
        # the stagger of the second bank's rods along the crank
        (
            "v8-crossplane",
            "crank.bank_stagger=0mm:30mm:4",
            2,
            {"crank": {"bank_stagger": "20 mm"}},
        ),
        # the bank angle of one bank: the V-twin's second bank from 45 deg to 75 deg
        (
            "v-twin-90",
            "crank.banks[2]=45deg:75deg:3",
            2,
            {"crank": {"banks": ["-45 deg", "75 deg"]}},
        ),
        # the V angle, with exact arithmetic: 360/7 opens the V-twin to 51.43 deg
        (
            "v-twin-90",
            "crank.v_angle=360/7,90",
            0,
            {"crank": {"banks": ["-180/7 deg", "180/7 deg"]}},
        ),
        # the balance factor (the example): 30 %, 35 %, ... 100 %
        (
            "single",
            "balance.balance_factor=30%:100%:15",
            4,
            {"balance": {"balance_factor": "50 %"}},
        ),
    ],
)
def test_each_field_through_the_command_line(tmp_path, name, vary, at, edit):
    """``balance sweep LAYOUT --vary FIELD=...``: the point ``at`` of the written file equals
    the analysis of the built-in file with that value written in, every variable, bit for
    bit (the residual with the proposal too, for the balance factor)."""
    import xarray as xr

    out = tmp_path / "s.nc"
    result = runner.invoke(app, ["sweep", name, "--vary", vary, "-o", str(out)])
    assert result.exit_code == 0, result.stderr
    path = _edited(tmp_path, name, edit, "cli")
    with xr.open_dataset(out) as ds:
        dim = ds.reciprocating_force_magnitude.dims[0]
        point = ds.isel({dim: at}).load()
    proposal = vary.startswith("balance.")
    assert ("residual_force_peak" in point) == proposal
    _assert_point_is_the_edited_layout(point, path, proposal=proposal)
