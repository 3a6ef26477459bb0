"""Sweeps: equal to single analyses at grid points, chunking, Dask, CLI errors."""

from __future__ import annotations

import json
import subprocess
import sys
from typing import Any

import numpy as np
import pytest
import xarray as xr
from helpers import needs
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import balance
from balance.api import analyse
from balance.cli import app
from balance.core.errors import InputError
from balance.io.fields import parse_field
from balance.io.layout_file import builtin_layout_path
from balance.studies.sweep import chunk_slices, sweep, variant

runner = CliRunner()

VARY = {
    "speed": "1000rpm:8000rpm:4",
    "conrod_length": "130mm:160mm:3",
    "cylinders[3].reciprocating": "0.4kg,0.7kg",
    "cylinders.2.z": "0.05m,0.1m",
}
DIMS = ["speed", "conrod_length", "cylinder3_reciprocating", "cylinder2_z"]
NAMES = ["speed", "conrod_length", "cylinders[3].reciprocating", "cylinders[2].z"]


def _assert_same_bits(at, ref):
    """Every sweep variable at a grid point equals analyse's, bit for bit."""
    for name in at.data_vars:
        a = at[name].values
        b = ref[name].values
        assert a.shape == b.shape, name
        assert np.array_equal(a, b), (name, np.max(np.abs(a - b)))


def _check_point(layout, ds, idx):
    values = {n: float(ds[d][i]) for n, d, i in zip(NAMES, DIMS, idx, strict=True)}
    ref = analyse(variant(layout, values), proposal=False)
    _assert_same_bits(ds.isel(dict(zip(DIMS, idx, strict=True))), ref)


@pytest.mark.parametrize("name", ["v12-60", "inline-4", "v8-crossplane", "inline-5"])
def test_sweep_equals_single_analyses(name):
    """The issue asks for equality with single analyses 'exactly': every grid point."""
    layout = balance.load_layout(name)
    ds = sweep(layout, VARY, chunk_size=5)
    assert ds.reciprocating_force_magnitude.dims == (*DIMS, "order", "rotation")
    for idx in np.ndindex(*(ds.sizes[d] for d in DIMS)):
        _check_point(layout, ds, idx)


def test_sweep_of_throw_bank_and_offset():
    layout = balance.load_layout("v8-crossplane")
    vary = {
        "cylinders[2].throw": "80deg,90deg,100deg",
        "cylinders[5].bank": "40deg,45deg",
        "offset": "0mm,2mm",
    }
    ds = sweep(layout, vary)
    for i, j, k in np.ndindex(3, 2, 2):
        at = ds.isel(cylinder2_throw=i, cylinder5_bank=j, offset=k)
        point = {
            "cylinders[2].throw": float(at.cylinder2_throw),
            "cylinders[5].bank": float(at.cylinder5_bank),
            "offset": float(at.offset),
        }
        _assert_same_bits(at, analyse(variant(layout, point), proposal=False))


@pytest.mark.parametrize(("model", "terms"), [("series", 2), ("series", 5), ("textbook", 3)])
def test_sweep_equals_single_analyses_for_every_model(model, terms):
    layout = balance.load_layout("v6-90")
    vary = {"stroke": "70mm:90mm:3", "masses.rotating": "0.5kg,0.9kg"}
    ds = sweep(layout, vary, "1-6", model=model, terms=terms)
    for i, j in np.ndindex(3, 2):
        at = ds.isel(stroke=i, rotating=j)
        point = {"stroke": float(at.stroke), "masses.rotating": float(at.rotating)}
        ref = analyse(variant(layout, point), "1-6", model=model, terms=terms, proposal=False)
        _assert_same_bits(at, ref)


_SWEEPABLE = [
    "inline-3",
    "inline-4",
    "inline-6",
    "v6-90",
    "v8-crossplane",
    "v12-60",
    "boxer-4",
    "v6-60-split",
]
_FIELDS = [
    ("speed", 100.0, 1500.0),
    ("conrod_length", 0.13, 0.2),
    ("stroke", 0.06, 0.1),
    ("offset", -0.003, 0.003),
    ("masses.reciprocating", 0.1, 2.0),
    ("masses.rotating", 0.1, 2.0),
    ("cylinders[1].throw", 0.0, 360.0),
    ("cylinders[2].z", -0.1, 0.4),
    ("cylinders[1].reciprocating", 0.1, 2.0),
    ("cylinders[2].conrod_length", 0.13, 0.2),
    ("masses.piston_group", 0.2, 0.8),
    ("masses.conrod_cg_to_big_end", 0.02, 0.06),
    ("cylinders[1].conrod", 0.3, 0.9),
]


@settings(max_examples=25, deadline=None, derandomize=True)
@given(
    name=st.sampled_from(_SWEEPABLE),
    picks=st.lists(st.sampled_from(range(len(_FIELDS))), min_size=1, max_size=3, unique=True),
    data=st.data(),
)
def test_any_sweep_point_is_a_single_analysis_bit_for_bit(name, picks, data):
    """Property: whatever fields vary, a grid point is the analysis of that variant."""
    layout = balance.load_layout(name)
    vary = {}
    for i in picks:
        field, lo, hi = _FIELDS[i]
        if layout.mass_parts is None and ("piston" in field or "conrod_cg" in field):
            continue
        if layout.mass_parts is None and field.endswith("].conrod"):
            continue
        values = data.draw(
            st.lists(st.floats(lo, hi, allow_nan=False), min_size=1, max_size=3, unique=True)
        )
        vary[field] = np.array(values)
    if not vary:
        vary["speed"] = np.array([100.0, 1000.0])
    orders = data.draw(st.sampled_from(["1-2", "1-8", "2,4,6"]))
    ds = sweep(layout, vary, orders, chunk_size=data.draw(st.integers(1, 20)))
    dims = list(ds.reciprocating_force_magnitude.dims[: len(vary)])
    idx = tuple(data.draw(st.integers(0, ds.sizes[d] - 1)) for d in dims)
    at = ds.isel(dict(zip(dims, idx, strict=True)))
    point = {f: float(vary[f][i]) for f, i in zip(vary, idx, strict=True)}
    _assert_same_bits(at, analyse(variant(layout, point), orders, proposal=False))


def test_cli_sweep_equals_cli_analyse_bit_for_bit(tmp_path):
    """From the shell: a netCDF sweep against `balance analyse --format json` of variants."""
    sweep_file = tmp_path / "sweep.nc"
    result = runner.invoke(
        app,
        [
            "sweep",
            "inline-4",
            "--vary",
            "speed=1000rpm:8000rpm:3",
            "--vary",
            "conrod_length=130mm:160mm:3",
            "--orders",
            "1-4",
            "-o",
            str(sweep_file),
        ],
    )
    assert result.exit_code == 0, result.output
    text = builtin_layout_path("inline-4").read_text()
    with xr.open_dataset(sweep_file) as ds:
        for i, j in [(0, 0), (1, 2), (2, 1)]:
            at = ds.isel(speed=i, conrod_length=j)
            variant_file = tmp_path / f"variant-{i}-{j}.yaml"
            length = f"{float(at.conrod_length)!r} m"
            variant_file.write_text(_set_conrod_length(text, length))
            out = runner.invoke(
                app,
                [
                    "analyse",
                    str(variant_file),
                    "--speed",
                    f"{float(at.speed)!r}rad/s",
                    "--orders",
                    "1-4",
                    "--format",
                    "json",
                ],
            )
            assert out.exit_code == 0, out.output
            doc = json.loads(out.stdout)
            for row in doc["reciprocating"]["force"]:
                k = row["order"]
                got = at.reciprocating_force_magnitude.sel(order=k).values
                assert got[0] == row["forward"]["magnitude"]
                assert got[1] == row["backward"]["magnitude"]
                assert float(at.reciprocating_force_peak.sel(order=k)) == row["peak"]


@pytest.mark.parametrize(
    ("field", "values", "where", "unit"),
    [
        ("masses.piston_group", [0.35, 0.5], ("masses", "piston_group"), "kg"),
        ("masses.conrod_inertia", [1.0e-3, 2.2e-3], ("masses", "conrod_inertia"), "kg m^2"),
        ("masses.crank_unbalance", [0.0, 0.6], ("masses", "crank_unbalance"), "kg"),
        ("conrod_length", [0.12, 0.16], ("geometry", "conrod_length"), "m"),
        ("masses.conrod_cg_to_big_end", [0.03, 0.05], ("masses", "conrod_cg_to_big_end"), "m"),
    ],
)
def test_sweep_of_parts_equals_the_edited_layout_file(field, values, where, unit):
    """A by-part layout: the sweep lumps the parts again exactly as loading the file does."""
    import yaml

    from balance.io.layout_file import layout_from_dict

    name = "v6-60-split"
    data = yaml.safe_load(builtin_layout_path(name).read_text())
    layout = balance.load_layout(name)
    ds = sweep(layout, {field: np.array(values)}, "1-4")
    dim = ds.reciprocating_force_magnitude.dims[0]
    for i, value in enumerate(values):
        edited = json.loads(json.dumps(data))
        edited[where[0]][where[1]] = f"{value!r} {unit}"  # SI: read back bit for bit
        ref = analyse(layout_from_dict(edited), "1-4", proposal=False)
        _assert_same_bits(ds.isel({dim: i}), ref)
    # the lumped masses really changed with the part (not only the coordinate)
    first, second = ds.isel({dim: 0}), ds.isel({dim: 1})
    assert any(not np.array_equal(first[v].values, second[v].values) for v in ds.data_vars)


def test_part_fields_need_a_by_part_layout():
    layout = balance.load_layout("v8-flatplane")
    assert layout.mass_parts is None
    with pytest.raises(InputError, match=r"gives them lumped; vary masses\.reciprocating"):
        sweep(layout, {"masses.piston_group": "0.3kg,0.4kg"})


def _set_conrod_length(text, length):
    lines = []
    for line in text.splitlines():
        if line.strip().startswith("conrod_length:"):
            indent = line[: len(line) - len(line.lstrip())]
            line = f"{indent}conrod_length: {length}"
        lines.append(line)
    assert any(line.strip() == f"conrod_length: {length}" for line in lines)
    return "\n".join(lines) + "\n"


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


@needs("zarr", "zarr")
@needs("distributed", "distributed")
def test_dask_cluster_gives_identical_result(tmp_path):
    """A real local cluster (worker processes): the same bits in memory, netCDF and Zarr.

    The three runs scatter the same plan on one client; each must do so under a key of its
    own.  With the plan's hash as its key (Dask's default) a run could scatter the key while
    the previous run's release of it was still on its way to the scheduler, which then
    dropped the new copy: "lost dependencies", about one run in twenty."""
    import distributed  # a test dependency

    layout = balance.load_layout("v6-90")
    local = sweep(layout, VARY, orders="1-4", chunk_size=7)
    with (
        distributed.LocalCluster(
            n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        scattered: list[str] = []
        scatter = client.scatter

        def recording_scatter(*args: Any, **kwargs: Any) -> Any:
            future = scatter(*args, **kwargs)
            scattered.append(future.key)
            return future

        client.scatter = recording_scatter  # type: ignore[method-assign]
        remote = sweep(layout, VARY, orders="1-4", chunk_size=7, client=client)
        nc = balance.studies.sweep.sweep_to_file(
            layout, VARY, tmp_path / "s.nc", orders="1-4", chunk_size=7, client=client
        )
        store = balance.studies.sweep.sweep_to_file(
            layout, VARY, tmp_path / "s.zarr", orders="1-4", chunk_size=7, client=client
        )
    assert len(scattered) == 3 and len(set(scattered)) == 3, scattered
    xr.testing.assert_identical(local, remote)
    with xr.open_dataset(nc) as from_netcdf, xr.open_zarr(store) as from_zarr:
        for name in local.data_vars:
            assert np.array_equal(from_netcdf[name].values, local[name].values)
            assert np.array_equal(from_zarr[name].values, local[name].values)


@needs("zarr", "zarr")
def test_zarr_store_is_the_sweep_dataset(tmp_path):
    layout = balance.load_layout("v12-60")
    vary = {"speed": "1000rpm:8000rpm:7", "cylinders[4].throw": "100deg,120deg,140deg"}
    ref = sweep(layout, vary, "1-8")
    store = balance.studies.sweep.sweep_to_file(
        layout, vary, tmp_path / "v12.zarr", "1-8", chunk_size=4
    )
    with xr.open_zarr(store) as ds:
        xr.testing.assert_identical(ds.load(), ref)
        # one Zarr chunk per sweep chunk: 4 grid points of the trailing dimension fit
        assert ds.reciprocating_force_magnitude.encoding["chunks"] == (1, 3, 8, 2)
    # --force replaces a store; without it the old one is kept
    with pytest.raises(InputError, match="exists and replacing it was not asked for"):
        balance.studies.sweep.sweep_to_file(layout, vary, store, "1-2")
    balance.studies.sweep.sweep_to_file(layout, vary, store, "1-2", force=True)
    with xr.open_zarr(store) as ds:
        assert ds.sizes["order"] == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["v12.zarr"]


@needs("zarr", "zarr")
def test_zarr_write_that_fails_keeps_the_old_store(tmp_path, monkeypatch):
    layout = balance.load_layout("inline-4")
    store = balance.studies.sweep.sweep_to_file(
        layout, {"speed": "1000rpm,2000rpm"}, tmp_path / "a.zarr"
    )
    before = sorted(str(p.relative_to(store)) for p in store.rglob("*"))

    def broken(*args):
        raise RuntimeError("worker lost")

    monkeypatch.setattr(balance.studies.sweep, "_chunk", broken)
    with pytest.raises(RuntimeError, match="worker lost"):
        balance.studies.sweep.sweep_to_file(layout, {"speed": "1000rpm,3000rpm"}, store, force=True)
    assert sorted(str(p.relative_to(store)) for p in store.rglob("*")) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.zarr"]


@needs("zarr", "zarr")
def test_sweep_refuses_to_replace_a_directory_that_is_not_a_store(tmp_path):
    precious = tmp_path / "results.zarr"
    precious.mkdir()
    (precious / "notes.txt").write_text("mine")
    result = runner.invoke(
        app,
        ["sweep", "inline-4", "--vary", "speed=1000rpm,2000rpm", "-o", str(precious), "--force"],
    )
    assert result.exit_code == 2
    assert "is a directory that is not a Zarr store" in result.output
    assert (precious / "notes.txt").read_text() == "mine"
    result = runner.invoke(
        app, ["sweep", "inline-4", "--vary", "speed=1000rpm,2000rpm", "-o", str(tmp_path / "x.h5")]
    )
    assert result.exit_code == 2
    assert "name it .nc (netCDF) or .zarr (Zarr)" in result.output


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
        ("conrod_length=42mm,140mm", "impossible geometry"),
        ("conrod_length=30mm,140mm", "centre of gravity would lie beyond its small end"),
        ("masses.conrod_cg_to_big_end=150mm", "centre of gravity would lie beyond"),
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
