"""Write what every built-in layout prints, to compare two versions of balance bit for bit.

Run it before and after a change that must not move a number, then compare the folders::

    python benchmarks/snapshot_outputs.py /tmp/before
    ... change the code ...
    python benchmarks/snapshot_outputs.py /tmp/after
    diff -r /tmp/before /tmp/after && echo identical

For each built-in layout it writes the contract JSON (orders 1-8, with the proposal, with
gas forces where the layout has a ``gas:`` section), the CSV, the table, the proposal
(``balance propose``) and the netCDF Dataset dumped as text with every float written by
``float.hex`` (so that two files differ exactly when a bit differs); and the same with the
bearing loads (``--bearings``): the JSON, the Dataset (pins, mains with and without the
proposal, internal moments, their curves) and the Dataset of ``propose --factor-study
--bearings`` (the largest loads of every balance factor).  JSON numbers are written by
``repr``, the shortest text that reads back to the same float, so they too differ exactly
when a bit does.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

DUMP = r"""
import sys
import numpy as np
import xarray as xr
ds = xr.open_dataset(sys.argv[1]).load()

def hexed(values):
    flat = np.asarray(values).ravel()
    if flat.dtype.kind == "f":
        return " ".join(float(v).hex() for v in flat)
    return " ".join(map(str, flat.tolist()))

for name in sorted(ds.attrs):
    if name != "balance_version":
        print("attr", name, repr(ds.attrs[name]))
for name in sorted(ds.variables):
    var = ds.variables[name]
    print(name, var.dims, sorted(var.attrs.items()), hexed(var.values))
"""


def run(args: list[str]) -> str:
    done = subprocess.run(
        [sys.executable, "-m", "balance", *args], capture_output=True, text=True, check=False
    )
    return f"exit {done.returncode}\n{done.stdout}\n--- stderr\n{done.stderr}"


def snapshot(name: str, out: Path) -> None:
    (out / f"{name}.json").write_text(run(["analyse", name, "--format", "json"]))
    (out / f"{name}.csv").write_text(run(["analyse", name, "--format", "csv"]))
    (out / f"{name}.table").write_text(run(["analyse", name]))
    (out / f"{name}.propose").write_text(run(["propose", name, "--factor-study"]))
    (out / f"{name}.bearings.json").write_text(
        run(["analyse", name, "--format", "json", "--bearings"])
    )
    dataset(["analyse", name], out / f"{name}.nc.txt")
    dataset(["analyse", name, "--bearings"], out / f"{name}.bearings.nc.txt")
    dataset(
        ["propose", name, "--factor-study", "--bearings"], out / f"{name}.propose-bearings.nc.txt"
    )


def dataset(command: list[str], path: Path) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        nc = Path(tmp) / "result.nc"
        status = run([*command, "--format", "netcdf", "-o", str(nc)])
        dump = subprocess.run(
            [sys.executable, "-c", DUMP, str(nc)], capture_output=True, text=True, check=False
        )
        path.write_text(status.split("\n")[0] + "\n" + dump.stdout)


def main() -> None:
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    listing = subprocess.run(
        [sys.executable, "-c", "import balance; print(*balance.builtin_layout_names())"],
        capture_output=True,
        text=True,
        check=True,
    )
    names = listing.stdout.split()
    with ThreadPoolExecutor(max_workers=2) as pool:
        list(pool.map(lambda n: snapshot(n, out), names))
    print(f"{len(names)} layouts written to {out}")


if __name__ == "__main__":
    main()
