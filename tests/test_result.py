"""The Result and its views: the Dataset, JSON, CSV and table read it directly."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import balance
from balance.core.analysis import compute
from balance.core.phasors import phase_deg
from balance.core.result import Request
from balance.views.csv import to_csv
from balance.views.dataset import build_dataset
from balance.views.json import to_dict

HEAVY = ("xarray", "pandas", "pint", "matplotlib")


@pytest.fixture(scope="module")
def result():
    return compute(balance.load_layout("v8-crossplane"), Request())


@pytest.fixture(scope="module")
def ds(result):
    return build_dataset(result)


def test_every_variable_has_units_and_long_name(ds):
    for name, var in ds.variables.items():
        assert var.attrs.get("units") is not None, name
        assert var.attrs.get("long_name"), name


def test_dataset_records_model_and_schema(ds):
    assert ds.attrs["schema"] == "balance.analysis/1"
    assert ds.attrs["model"] == "exact"


def test_api_analyse_is_the_dataset_view_of_compute(ds):
    api = balance.analyse(balance.load_layout("v8-crossplane"))
    assert api.identical(ds)


def test_dataset_uses_the_stored_references(result, ds):
    assert float(ds.reference_force) == result.reference_force
    assert float(ds.reference_moment) == result.reference_moment
    np.testing.assert_array_equal(
        ds.roll_amplitude_normalised.values, np.abs(result.roll) / result.reference_roll
    )


def test_dataset_reports_the_gas_roll_of_the_result():
    result = compute(balance.load_layout("inline-4-gas"), Request())
    ds = build_dataset(result)
    assert result.part("torque") is not None and result.part("proposal").residual_roll is not None
    np.testing.assert_array_equal(ds.roll_order.values, result.roll_orders)
    np.testing.assert_array_equal(
        ds.residual_roll_amplitude.values, np.abs(result.part("proposal").residual_roll)
    )
    assert "with gas forces" in ds.roll_amplitude.attrs["long_name"]


def test_what_was_not_asked_is_not_in_the_views():
    result = compute(balance.load_layout("inline-4"), Request(moments=False, roll=False))
    ds = build_dataset(result)
    assert not any(name.startswith(("roll", "reciprocating_moment")) for name in ds.variables)
    data = to_dict(result)
    assert "roll" not in data and "moment" not in data["reciprocating"]
    assert "proposal" not in data
    assert "moment" not in to_csv(result) and "roll" not in to_csv(result)


def test_json_is_a_view_of_the_result(result, ds):
    data = to_dict(result)
    for entry in data["reciprocating"]["moment"]:
        k = entry["order"]
        for rotation in ("forward", "backward"):
            assert entry[rotation]["magnitude"] == float(
                ds.reciprocating_moment_magnitude.sel(order=k, rotation=rotation)
            )
    json.dumps(data, allow_nan=False)


def test_csv_is_a_view_of_the_result(result, ds):
    rows = to_csv(result).strip().splitlines()
    header = rows[0].split(",")
    first = dict(zip(header, rows[1].split(","), strict=True))
    assert float(first["moment_peak [N m]"]) == float(ds.reciprocating_moment_peak.sel(order=1))


def test_phase_convention():
    # (x, y) -> y + i x: a vector along +x is at 90 deg, along -y at 180 deg, -x at 270 deg
    np.testing.assert_allclose(phase_deg([1j, -1, -1j, 1, 0]), [90, 180, 270, 0, 0])
    assert phase_deg(np.exp(-1e-20j)) == 0.0  # wraps into [0, 360)


def test_import_is_cheap():
    heavy = "('xarray', 'pint', 'matplotlib', 'pydantic', 'dask')"
    code = f"import sys, balance; print(' '.join(m for m in {heavy} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


COMMANDS = [
    ["analyse", "inline-4", "--format", "json"],  # first: what the JSON alone imports
    ["analyse", "inline-4"],
    ["analyse", "inline-4", "--format", "csv"],
    ["analyse", "inline-4-gas", "--format", "json"],
    ["propose", "inline-4"],
    ["propose", "inline-4", "--format", "json"],
]


def test_printing_a_result_imports_no_data_frame_units_or_plot_library():
    """The table, JSON and CSV views read the Result: the command imports none of xarray,
    pandas, pint or matplotlib.  The six commands run one after another in one fresh
    process (one start of Python, not six), which lists after each what is imported so
    far: a heavy module imported by any of them is in every later list too."""
    code = (
        "import json, sys\n"
        "from balance.cli import main\n"
        "for args in json.loads(sys.argv[1]):\n"
        "    sys.argv = ['balance', *args]\n"
        "    try:\n"
        "        main()\n"
        "    except SystemExit as stop:\n"
        "        assert not stop.code, (args, stop.code)\n"
        "    sys.stderr.write('MODULES ' + ' '.join(sorted(sys.modules)) + '\\n')\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code, json.dumps(COMMANDS)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    listings = [line.split()[1:] for line in proc.stderr.splitlines() if line.startswith("MODULES")]
    assert len(listings) == len(COMMANDS)
    for args, imported in zip(COMMANDS, listings, strict=True):
        assert "balance.core.analysis" in imported  # the listing is complete
        heavy = sorted(m for m in imported if m.split(".")[0] in HEAVY)
        assert heavy == [], f"{' '.join(args)} imported {heavy}"
    # a section that has nothing to say about an engine is not imported for it: the
    # inline-4 has no gas forces (no speed model) and one crankshaft; nor is the grammar of
    # --vary, --speed and --load (io.fields), nor arithmetic for quantities like "86 mm", nor
    # the models of the balance:, gas: and flywheel: sections it does not have
    for imported in listings[:3]:
        unused = {
            "balance.core.dynamics",
            "balance.core.crank_motion",
            "balance.core.geared",
            "balance.core.torque",
            "balance.io.fields",
            "balance.io.arithmetic",
            "balance.core.crankshafts",
            "balance.core.gas",
            "balance.io.schema_options",
        }
        assert not unused & set(imported), unused & set(imported)
    # the JSON is written from the sections' json blocks: it imports neither the table's
    # columns (views.fitted, views.table) nor what the figures are drawn from
    views = {f"balance.views.{name}" for name in ("fitted", "table", "figures", "signals")}
    assert "balance.views.json" in listings[0]
    assert not views & set(listings[0]), views & set(listings[0])
    assert "balance.core.dynamics" in listings[3]  # inline-4-gas: its speed model's bound
