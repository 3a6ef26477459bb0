"""Sweeps: equal to single analyses at grid points, chunking, Dask, CLI errors."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import balance
from balance.analysis import analyse
from balance.cli import app
from balance.errors import InputError
from balance.sweep import chunk_slices, parse_field, sweep, variant

runner = CliRunner()

VARY = {
    "speed": "1000rpm:8000rpm:4",
    "conrod_length": "130mm:160mm:3",
    "cylinders[3].reciprocating": "0.4kg,0.7kg",
    "cylinders.2.z": "0.05,0.1",
}
DIMS = ["speed", "conrod_length", "cylinder3_reciprocating", "cylinder2_z"]
NAMES = ["speed", "conrod_length", "cylinders[3].reciprocating", "cylinders[2].z"]


def _check_point(layout, ds, idx, rtol):
    values = {n: float(ds[d][i]) for n, d, i in zip(NAMES, DIMS, idx, strict=True)}
    ref = analyse(variant(layout, values))
    at = ds.isel(dict(zip(DIMS, idx, strict=True)))
    for name in at.data_vars:
        np.testing.assert_allclose(at[name].values, ref[name].values, rtol=rtol, atol=0)
        # exact zeros stay exact
        assert np.array_equal(at[name].values == 0, ref[name].values == 0)


@pytest.mark.parametrize("name", ["v12-60", "inline-4"])
def test_sweep_equals_single_analyses(name):
    layout = balance.load_layout(name)
    ds = sweep(layout, VARY, chunk_size=5)
    assert ds.reciprocating_force_magnitude.dims == (*DIMS, "order", "rotation")
    for idx in [(0, 0, 0, 0), (3, 2, 1, 1), (1, 1, 0, 1), (2, 0, 1, 0)]:
        _check_point(layout, ds, idx, rtol=1e-12)


def test_sweep_of_throw_and_offset():
    layout = balance.load_layout("v8-crossplane")
    ds = sweep(layout, {"cylinders[2].throw": "80deg,90deg,100deg", "offset": "0mm,2mm"})
    for i in range(3):
        for j in range(2):
            ref = analyse(
                variant(
                    layout,
                    {
                        "cylinders[2].throw": float(ds.cylinder2_throw[i]),
                        "offset": float(ds.offset[j]),
                    },
                )
            )
            at = ds.isel(cylinder2_throw=i, offset=j)
            for name in at.data_vars:
                np.testing.assert_allclose(at[name].values, ref[name].values, rtol=1e-12)


def test_chunking_does_not_change_results():
    layout = balance.load_layout("inline-6")
    a = sweep(layout, VARY, chunk_size=1)
    b = sweep(layout, VARY, chunk_size=10**6)
    xr.testing.assert_identical(a, b)


def test_chunk_slices_cover_the_grid():
    shape = (5, 7, 3)
    seen = np.zeros(shape, int)
    for size in (1, 4, 22, 1000):
        seen[:] = 0
        for where in chunk_slices(shape, size):
            assert seen[where].size <= max(size, 1)
            seen[where] += 1
        assert np.all(seen == 1)


def test_dask_cluster_gives_identical_result(tmp_path):
    import distributed  # a test dependency
    layout = balance.load_layout("v6-90")
    local = sweep(layout, VARY, orders="1-4", chunk_size=7)
    with (
        distributed.LocalCluster(
            n_workers=2, processes=False, threads_per_worker=1, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        remote = sweep(layout, VARY, orders="1-4", chunk_size=7, client=client)
        path = balance.sweep.sweep_to_file(
            layout, VARY, tmp_path / "s.nc", orders="1-4", chunk_size=7, client=client
        )
    xr.testing.assert_identical(local, remote)
    with xr.open_dataset(path) as from_file:
        for name in local.data_vars:
            assert np.array_equal(from_file[name].values, local[name].values)


def test_cli_sweep_writes_netcdf_without_importing_dask(tmp_path):
    out = tmp_path / "sweep.nc"
    code = (
        "import sys\nfrom balance.cli import main\n"
        f"sys.argv=['balance','sweep','inline-4','--vary','speed=1000rpm:8000rpm:5',"
        f"'--vary','conrod_length=130mm,140mm','--orders','1-2','-o',{str(out)!r}]\n"
        "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code\n"
        "assert 'dask' not in sys.modules and 'distributed' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)
    with xr.open_dataset(out) as ds:
        ref = sweep(
            balance.load_layout("inline-4"),
            {"speed": "1000rpm:8000rpm:5", "conrod_length": "130mm,140mm"},
            "1-2",
        )
        for name in ref.data_vars:
            assert np.array_equal(ds[name].values, ref[name].values)
        assert ds.reciprocating_force_peak.attrs["units"] == "N"


@pytest.mark.parametrize(
    ("vary", "message"),
    [
        ("spede=1:2:3", "not a numeric layout field"),
        ("conrod_length=130kg:160mm:3", "is a mass, not a length"),
        ("conrod_length=130mm:160mm", "cannot read range"),
        ("conrod_length=130mm:160mm:x", "not a whole number"),
        ("cylinders[9].z=0,1", "cylinders 1 to 4"),
        ("cylinders[2].colour=0,1", "not a numeric per-cylinder field"),
        ("speed", "write FIELD="),
        ("speed=-5rpm,5rpm", "above zero"),
        ("conrod_length=10mm,140mm", "impossible geometry"),
    ],
)
def test_cli_bad_vary_is_one_line_exit_2(tmp_path, vary, message):
    result = runner.invoke(app, ["sweep", "inline-4", "--vary", vary, "-o", str(tmp_path / "x.nc")])
    assert result.exit_code == 2, result.output
    assert message in result.stderr
    assert result.stderr.count("\n") == 1
    assert not (tmp_path / "x.nc").exists()


def test_parse_field_names():
    layout = balance.load_layout("inline-4")
    assert parse_field("masses.reciprocating", layout).name == "reciprocating"
    assert parse_field("geometry.stroke", layout).attribute == "crank_radius"
    f = parse_field("cylinders[3].throw", layout)
    assert (f.cylinder, f.kind) == (2, "angle")
    with pytest.raises(InputError):
        parse_field("masses.conrod_length", layout)
