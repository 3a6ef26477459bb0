"""The result Dataset: units, names, JSON and CSV as views of it."""

from __future__ import annotations

import json

import numpy as np
import pytest

import balance
from balance.views.csv import to_csv
from balance.views.dataset import phase_deg
from balance.views.json import to_dict


@pytest.fixture(scope="module")
def ds():
    return balance.analyse(balance.load_layout("v8-crossplane"))


def test_every_variable_has_units_and_long_name(ds):
    for name, var in ds.variables.items():
        assert var.attrs.get("units") is not None, name
        assert var.attrs.get("long_name"), name


def test_dataset_records_model_and_schema(ds):
    assert ds.attrs["schema"] == "balance.analysis/1"
    assert ds.attrs["model"] == "exact"


def test_json_is_a_view_of_the_dataset(ds):
    data = to_dict(ds)
    for entry in data["reciprocating"]["moment"]:
        k = entry["order"]
        for rotation in ("forward", "backward"):
            assert entry[rotation]["magnitude"] == float(
                ds.reciprocating_moment_magnitude.sel(order=k, rotation=rotation)
            )
    json.dumps(data, allow_nan=False)


def test_csv_is_a_view_of_the_dataset(ds):
    rows = to_csv(ds).strip().splitlines()
    header = rows[0].split(",")
    first = dict(zip(header, rows[1].split(","), strict=True))
    assert float(first["moment_peak [N m]"]) == float(ds.reciprocating_moment_peak.sel(order=1))


def test_phase_convention():
    # (x, y) -> y + i x: a vector along +x is at 90 deg, along -y at 180 deg, -x at 270 deg
    np.testing.assert_allclose(phase_deg([1j, -1, -1j, 1, 0]), [90, 180, 270, 0, 0])
    assert phase_deg(np.exp(-1e-20j)) == 0.0  # wraps into [0, 360)


def test_import_is_cheap():
    import subprocess
    import sys

    heavy = "('xarray', 'pint', 'matplotlib', 'pydantic', 'dask')"
    code = f"import sys, balance; print(' '.join(m for m in {heavy} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
