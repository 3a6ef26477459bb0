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

import multiprocessing
import os
import sys
import tempfile
from pathlib import Path

#: Layouts snapshotted at once (each in a process forked from the first).
WORKERS = 2

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
    """Exit status, stdout and stderr of ``balance ARGS``.

    The command runs in a process forked from this one, which has imported balance and the
    libraries it draws on, so that each of the many commands does not pay for a start-up;
    the child writes to its own pipes and ends with the command's exit status, as a
    separate ``python -m balance`` would.
    """
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        pid = os.fork()
        if pid == 0:  # the child: run the command as the entry point does
            os.dup2(out.fileno(), 1)
            os.dup2(err.fileno(), 2)
            code = 1
            try:
                sys.argv = ["balance", *args]
                from balance.cli import main as balance_main

                balance_main()
                code = 0
            except SystemExit as exc:
                code = exc.code if isinstance(exc.code, int) else 1
            finally:
                sys.stdout.flush()
                sys.stderr.flush()
                os._exit(code)
        _, status = os.waitpid(pid, 0)
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read().decode(), err.read().decode()
    return f"exit {os.waitstatus_to_exitcode(status)}\n{stdout}\n--- stderr\n{stderr}"


def dump(path: Path) -> str:
    """A netCDF file as text, every float in hex (run in a forked child, as :func:`run`)."""
    with tempfile.TemporaryFile() as out:
        pid = os.fork()
        if pid == 0:
            os.dup2(out.fileno(), 1)
            try:
                sys.argv = ["dump", str(path)]
                exec(DUMP, {"__name__": "__dump__"})
            finally:
                sys.stdout.flush()
                os._exit(0)
        os.waitpid(pid, 0)
        out.seek(0)
        return out.read().decode()


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
    for model in ("series", "textbook", "time"):
        (out / f"{name}.{model}.json").write_text(
            run(["analyse", name, "--format", "json", "--model", model, "--orders", "1-6"])
        )
    (out / f"{name}.tolerance.json").write_text(
        run(["analyse", name, "--format", "json", "--tolerance", "1e-4"])
    )
    (out / f"{name}.expand.yaml").write_text(run(["layout", "expand", name]))
    if name in MOUNTED:
        mounts(name, out)


#: Built-in layouts with a ``mounts:`` section.
MOUNTED = ("inline-4-mounts", "single-mounts")


def mounts(name: str, out: Path) -> None:
    """The engine on its mounts: ``analyse`` with the mounts, bare and with the proposal,
    and the ``mounts`` speed sweep in every format."""
    for extra, tag in (([], ""), (["--with-proposal"], ".with-proposal")):
        on = [*MOUNTS_FLAG, *extra]
        for fmt in ("json", "csv", "table"):
            (out / f"{name}.mounts{tag}.{fmt}").write_text(
                run(["analyse", name, *on, "--format", fmt, "--bearings"])
            )
        dataset(["analyse", name, *on], out / f"{name}.mounts{tag}.nc.txt")
        for fmt in ("json", "csv", "table"):
            (out / f"{name}.mounts-sweep{tag}.{fmt}").write_text(
                run(["mounts", name, *extra, "--speed", "800rpm:8000rpm:25", "--format", fmt])
            )


#: What turns the mounts on in ``analyse``: the layout's ``mounts:`` section does by itself;
#: ``--on-mounts`` is kept as an accepted no-op so that older versions snapshot alike.
MOUNTS_FLAG: list[str] = ["--on-mounts"]


def dataset(command: list[str], path: Path) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        nc = Path(tmp) / "result.nc"
        status = run([*command, "--format", "netcdf", "-o", str(nc)])
        path.write_text(status.split("\n")[0] + "\n" + dump(nc))


def main() -> None:
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    import importlib
    import pkgutil

    import matplotlib
    import netCDF4  # noqa: F401
    import rich.console  # noqa: F401
    import xarray  # noqa: F401

    import balance

    # every module of the package, imported once here rather than in every forked command
    for part in ("core", "io", "views", "studies"):
        package = importlib.import_module(f"balance.{part}")
        for module in pkgutil.iter_modules(package.__path__):
            importlib.import_module(f"balance.{part}.{module.name}")
    importlib.import_module("balance.cli")
    matplotlib.use("Agg")
    names = list(balance.builtin_layout_names())
    with multiprocessing.get_context("fork").Pool(WORKERS) as pool:
        pool.starmap(snapshot, [(name, out) for name in names])
    (out / "compare.table").write_text(run(["compare", "--all", "--orders", "1-4"]))
    for name in ("inline-4", "v8-crossplane", "radial-5"):
        sweep(name, out / f"{name}.sweep.nc.txt")
    print(f"{len(names)} layouts written to {out}")


def sweep(name: str, path: Path) -> None:
    """A small sweep over speed and rod length, its file dumped like :func:`dataset`'s."""
    with tempfile.TemporaryDirectory() as tmp:
        nc = Path(tmp) / "sweep.nc"
        grid = ["--vary", "speed=1000rpm:8000rpm:5", "--vary", "conrod_length=130mm:160mm:3"]
        status = run(["sweep", name, *grid, "--no-progress", "-o", str(nc)])
        path.write_text(status.split("\n")[0] + "\n" + dump(nc))


if __name__ == "__main__":
    main()
