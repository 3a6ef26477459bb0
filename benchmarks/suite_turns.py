"""The test suite of two checkouts, run in turns, for an A/B of the suite's time on a
machine whose speed drifts from one minute to the next.

Each checkout runs the README's test command (``python -m pytest``) with its own source
first on ``PYTHONPATH``, so that it tests its own balance, the first checkout then the
second, ``--pairs`` times; each run's wall time and the CPU time of its processes (the
workers included) are printed as a Markdown table, with the medians::

    python benchmarks/suite_turns.py [--pairs N] BEFORE_CHECKOUT AFTER_CHECKOUT

Bytecode is not written (``PYTHONDONTWRITEBYTECODE=1``), so that every run starts as the
first run of a fresh clone does.  A run that fails is reported and ends the comparison.
A pair takes about four minutes on the project's 2-core machine.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path


def run_suite(checkout: Path) -> tuple[float, float]:
    """Wall and CPU seconds of the README's test command in ``checkout``."""
    env = {**os.environ, "PYTHONPATH": str(checkout), "PYTHONDONTWRITEBYTECODE": "1"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"],
        cwd=checkout,
        env=env,
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{checkout}: the suite failed\n{done.stdout[-3000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path, help="the checkout to compare against")
    parser.add_argument("after", type=Path, help="the checkout measured")
    parser.add_argument("--pairs", type=int, default=3, help="runs of each (default 3)")
    args = parser.parse_args()
    rows: list[tuple[float, float, float, float]] = []
    print("| pair | before: wall | CPU | after: wall | CPU |")
    print("|---|---:|---:|---:|---:|")
    for pair in range(1, args.pairs + 1):
        before = run_suite(args.before.resolve())
        after = run_suite(args.after.resolve())
        rows.append((*before, *after))
        print(
            f"| {pair} | {before[0]:.1f} s | {before[1]:.0f} s | {after[0]:.1f} s | "
            f"{after[1]:.0f} s |",
            flush=True,
        )
    medians = [statistics.median(column) for column in zip(*rows, strict=True)]
    print(
        f"| median | {medians[0]:.1f} s | {medians[1]:.0f} s | {medians[2]:.1f} s | "
        f"{medians[3]:.0f} s |"
    )


if __name__ == "__main__":
    main()
