"""Instructions executed by the sweep engine and the ``analyse`` loop, for an A/B of two
versions of balance on a machine whose speed changes from one second to the next.

Timed rates on a shared virtual machine move by 20-30 % between runs of the same code;
the count of instructions executed (valgrind's callgrind) does not depend on the other
load.  Each workload is run twice under callgrind, once in full and once stopping before
the part measured, and the difference is what the part costs::

    python benchmarks/instructions.py [--only W1,W2] PYTHON [PYTHON ...]

where each ``PYTHON`` is an interpreter that imports the version of balance to measure
(for instance ``/path/to/old-venv/bin/python`` and ``.venv/bin/python``).  It prints one
Markdown row per interpreter.  Called with ``--run WORKLOAD N`` it is the workload itself
(what callgrind runs).  Needs valgrind; a run takes a few minutes.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile

#: The workloads: what is measured, and how many of it a full run does.
WORKLOADS = {
    "i4-sweep": "inline-4 speed grid, orders 1-2 (199 900 variants beyond the first 100)",
    "v12-sweep": "V12 per-cylinder grid, orders 1-8 (24 960 variants beyond the first 40)",
    "i4-analyse": "inline-4 analyse loop, orders 1-2 (40 variants)",
    "v12-analyse": "V12 analyse loop, orders 1-8 (40 variants)",
    "v12-default": "V12 default analysis with its Dataset, `balance.analyse` (20 calls)",
    "v12-bearings": "V12 default analysis with bearing loads, `compute` (20 calls)",
    "mounts": "inline-4-mounts analysis with the mounts, `compute` (20 calls)",
    "mounts-sweep": "inline-4-mounts speed sweep, 200 speeds x 8 orders (20 calls)",
}
#: How many of the measured part a full run does (the figure is per one of them).
CALLS = {
    "i4-analyse": 40,
    "v12-analyse": 40,
    "v12-default": 20,
    "v12-bearings": 20,
    "mounts": 20,
    "mounts-sweep": 20,
}


def _request(engine, **sections):
    """The default request at orders 1-8 with ``sections`` on, in this version's API
    (``build_request`` since the concern sections, ``Request(...)`` before)."""
    try:
        from balance.io.request import build_request
    except ImportError:  # a version before the sections
        from balance.core.result import Request

        return Request(orders=tuple(range(1, 9)), **sections)
    return build_request(engine, 8, **sections)


def run_section(workload: str, full: bool) -> None:
    """The workloads of one layout's analysis with a section, and the mount sweep."""
    import numpy as np

    import balance
    from balance.core.analysis import compute

    calls = range(CALLS[workload] if full else 0)
    if workload == "v12-default":
        layout = balance.load_layout("v12-60")
        balance.analyse(layout)
        for _ in calls:
            balance.analyse(layout)
        return
    if workload == "v12-bearings":
        layout = balance.load_layout("v12-60")
        request = _request(layout, bearings=True)
    else:
        layout = balance.load_layout("inline-4-mounts")
        request = _request(layout, mounts=True)
    result = compute(layout, request)
    if workload != "mounts-sweep":
        for _ in calls:
            compute(layout, request)
        return
    from balance.core.mounts import speed_sweep

    # the sweep's base: the mounts part's response since the sections, the part before
    base = result.part("mounts").response if hasattr(result, "part") else result.mounts
    speeds = np.linspace(800, 8000, 200) * np.pi / 30
    speed_sweep(base, speeds)
    for _ in calls:
        speed_sweep(base, speeds)


def run(workload: str, full: bool) -> None:
    """The workload: with ``full`` False it stops before the part measured."""
    if workload in ("v12-default", "v12-bearings", "mounts", "mounts-sweep"):
        run_section(workload, full)
        return
    import numpy as np

    import balance

    if workload.endswith("-sweep"):
        from balance.studies.sweep import sweep_arrays

        if workload == "i4-sweep":
            layout = balance.load_layout("inline-4")
            vary = [
                "speed=1000rpm:8000rpm:100",
                "conrod_length=130mm:160mm:100",
                "masses.reciprocating=0.4kg:0.6kg:20",
            ]
            orders = [1, 2]
        else:
            layout = balance.load_layout("v12-60")
            vary = [
                "conrod_length=130mm:160mm:40",
                "cylinders[1].reciprocating=0.4kg:0.6kg:25",
                "cylinders[2].throw=170deg:190deg:25",
            ]
            orders = list(range(1, 9))
        sweep_arrays(layout, vary if full else vary[:1], orders)
        return
    from balance.api import analyse
    from balance.studies.sweep import variant

    layout = balance.load_layout("inline-4" if workload == "i4-analyse" else "v12-60")
    orders = "1-2" if workload == "i4-analyse" else "1-8"
    analyse(layout, orders)
    for length in np.linspace(0.13, 0.16, 40) if full else []:
        analyse(variant(layout, {"conrod_length": float(length)}), orders)


def instructions(python: str, workload: str, full: bool, script: str = __file__) -> int:
    """Instructions callgrind counts for one run of the workload: ``script --run WORKLOAD
    1|0`` under ``python`` (this file's workloads by default)."""
    env = {**os.environ, "PYTHONHASHSEED": "0", "OPENBLAS_NUM_THREADS": "1"}
    with tempfile.TemporaryDirectory() as tmp:
        done = subprocess.run(
            [
                "valgrind",
                "--tool=callgrind",
                f"--callgrind-out-file={tmp}/out",
                python,
                os.path.abspath(script),
                "--run",
                workload,
                "1" if full else "0",
            ],
            capture_output=True,
            text=True,
            env=env,
            check=True,
            cwd=tmp,  # not the checkout: each interpreter imports its own balance
        )
    match = re.search(r"Collected : (\d+)", done.stderr)
    if match is None:
        raise SystemExit(f"no instruction count from valgrind:\n{done.stderr}")
    return int(match.group(1))


def main() -> None:
    if sys.argv[1:2] == ["--run"]:
        run(sys.argv[2], sys.argv[3] == "1")
        return
    args = sys.argv[1:]
    workloads = dict(WORKLOADS)
    if args[:1] == ["--only"]:
        workloads = {name: WORKLOADS[name] for name in args[1].split(",")}
        args = args[2:]
    pythons = args
    if not pythons:
        raise SystemExit(__doc__)
    print("| interpreter | " + " | ".join(workloads) + " |")
    print("|---|" + "---:|" * len(workloads))
    for python in pythons:
        cells = []
        for workload in workloads:
            part = instructions(python, workload, True) - instructions(python, workload, False)
            per = CALLS.get(workload, 1)
            unit = " per variant" if workload.endswith("-analyse") else " per call"
            cells.append(f"{part / per / 1e6:.2f} × 10⁶" + (unit if per > 1 else ""))
        print(f"| `{python}` | " + " | ".join(cells) + " |")
    for workload, what in workloads.items():
        print(f"\n{workload}: {what}", end="")
    print()


if __name__ == "__main__":
    main()
