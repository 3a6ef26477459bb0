"""An analysis of a Deltic against the V12's: `balance.analyse` of the built-in `deltic-18`
(36 pistons on three crankshafts), of an 18-piston Deltic (three banks of three bores, the
Deltic 9's size, built here from `deltic-18`'s geometry) and of `v12-60`, the target being
"at most 2 x the V12's time".

Two figures (docs/benchmarks.md, "Several crankshafts"):

- wall time and process (CPU) time, each the best of N rounds of 10 calls, the layouts
  interleaved round by round so that the load of a shared machine falls on all of them
  alike (the process time counts only this process's CPU, not the waits)::

      PYTHONPATH=$PWD python benchmarks/several_crankshafts.py [N]

- instructions executed (valgrind's callgrind), which do not depend on the other load: each
  workload run twice, once with 10 calls and once stopping before them, the difference over
  10 being one call::

      PYTHONPATH=$PWD python benchmarks/several_crankshafts.py --instructions [W1,W2]

  (``--run WORKLOAD 0|1`` is the workload itself, what callgrind runs.)

The Deltics are analysed without their ``gas:`` section (the V12 has none: the same
inertia analysis) and, for `deltic-18`, also with it (the torque section over the 1440
points of the two-stroke cycle on top).
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The workloads, what each analyses.
WORKLOADS = {
    "v12-60": "v12-60, 12 cylinders on one crankshaft",
    "deltic-9": "an 18-piston Deltic: three banks of three bores on three crankshafts, no gas",
    "deltic-18": "deltic-18, 36 pistons on three crankshafts, no gas",
    "deltic-18-gas": "deltic-18 with its gas section (torque over the cycle)",
}
#: Calls of the measured part in an instruction count (``BALANCE_BENCH_CALLS`` to change).
CALLS = int(os.environ.get("BALANCE_BENCH_CALLS", "10"))


def deltic_9():
    """The 18-piston Deltic: `deltic-18` with three throws per bank (0, 120, 240 deg) at
    its spacing, everything else as the built-in."""
    from balance.io.layout_reader import layout_from_text

    text = (ROOT / "layouts" / "deltic-18.yaml").read_text(encoding="utf-8")
    text = text.replace("throws: [0, 120, 240, 180, 300, 60]", "throws: [0, 120, 240]")
    text = text.replace("name: Deltic 18 (Napier)", "name: Deltic 9-sized (Napier)")
    return layout_from_text(text, "deltic-9.yaml")


def engines():
    """Each workload's engine."""
    import balance

    deltic = balance.load_layout("deltic-18")
    return {
        "v12-60": balance.load_layout("v12-60"),
        "deltic-9": replace(deltic_9(), gas=None),
        "deltic-18": replace(deltic, gas=None),
        "deltic-18-gas": deltic,
    }


def run(workload: str, full: bool) -> None:
    """The workload: one analysis (imports, caches), then ``CALLS`` more when ``full``."""
    import balance

    engine = engines()[workload]
    balance.analyse(engine)
    for _ in range(CALLS if full else 0):
        balance.analyse(engine)


def instructions(workload: str, full: bool) -> int:
    """Instructions callgrind counts for one run of the workload (as
    ``benchmarks/instructions.py`` counts its own)."""
    from instructions import instructions as counted

    return counted(sys.executable, workload, full, script=__file__)


def timed(repeats: int) -> dict[str, tuple[float, float]]:
    """Best wall time and best process (CPU) time of one `balance.analyse` per workload [s],
    interleaved, each best over ``repeats`` rounds of 10 calls."""
    import balance

    built = engines()
    for engine in built.values():  # imports and caches
        balance.analyse(engine)
    best = {name: (float("inf"), float("inf")) for name in built}
    for _ in range(repeats):
        for name, engine in built.items():
            wall, cpu = time.perf_counter(), time.process_time()
            for _ in range(10):
                balance.analyse(engine)
            wall, cpu = (time.perf_counter() - wall) / 10, (time.process_time() - cpu) / 10
            best[name] = (min(best[name][0], wall), min(best[name][1], cpu))
    return best


def main() -> None:
    args = sys.argv[1:]
    if args[:1] == ["--run"]:
        run(args[1], args[2] == "1")
        return
    if args[:1] == ["--instructions"]:
        chosen = args[1].split(",") if len(args) > 1 else list(WORKLOADS)
        chosen = ["v12-60", *(w for w in chosen if w != "v12-60")]
        print("| workload | instructions per call | × v12-60 |")
        print("|---|---:|---:|")
        counts = {w: (instructions(w, True) - instructions(w, False)) / CALLS for w in chosen}
        for w, n in counts.items():
            print(f"| {w} | {n / 1e6:.1f} × 10⁶ | {n / counts['v12-60']:.2f} |")
    else:
        repeats = int(args[0]) if args else 10
        best = timed(repeats)
        wall0, cpu0 = best["v12-60"]
        print("| workload | wall [ms] | × v12-60 | process time [ms] | × v12-60 |")
        print("|---|---:|---:|---:|---:|")
        for w, (wall, cpu) in best.items():
            cells = f"{1e3 * wall:.1f} | {wall / wall0:.2f} | {1e3 * cpu:.1f} | {cpu / cpu0:.2f}"
            print(f"| {w} | {cells} |")
    for w, what in WORKLOADS.items():
        print(f"\n{w}: {what}", end="")
    print()


if __name__ == "__main__":
    main()
