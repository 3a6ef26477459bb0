"""Sweep, search and tolerance-study speed, measured in one run.

Run from the repository root:

    python benchmarks/sweep.py                 # print the tables
    python benchmarks/sweep.py --write-docs    # and write the benchmark section of docs/sweeps.md

Variants per second of :func:`balance.studies.sweep.sweep_arrays` (in-process, the process pinned to
one core) for the
inline-4 and the V12 at orders 1-2 and 1-8, with moments and roll, against a loop of
:func:`balance.analyse` over variants and against the brute-force time-domain computation
(``compute_phasors(..., model="time")``, 256 crank angles), both timed on a sample of variants.
Two grids: one with speed (speed x conrod_length x engine-wide reciprocating mass, 10**6
points; the unit-speed phasor sums are formed once per (rod, mass) variant and multiplied
by omega**2) and a per-cylinder one (conrod_length x cylinders[1].reciprocating x
cylinders[2].throw, about 2.5 * 10**5 points; every variant has its own sums).  Then the
crank-arrangement searches and a 10**6-sample tolerance study of the cross-plane V8.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from datetime import date
from pathlib import Path

import numpy as np

import balance
from balance.api import analyse
from balance.core.analysis import compute_phasors
from balance.io.orders import parse_orders
from balance.studies.search import search
from balance.studies.sweep import sweep_arrays, variant
from balance.studies.tolerance import tolerance

ROOT = Path(__file__).resolve().parent.parent
SEPARABLE = {
    "speed": "1000rpm:8000rpm:100",
    "conrod_length": "130mm:160mm:100",
    "masses.reciprocating": "0.4kg:0.7kg:100",
}
PER_CYLINDER = {
    "conrod_length": "130mm:160mm:40",
    "cylinders[1].reciprocating": "0.4kg:0.7kg:80",
    "cylinders[2].throw": "170deg:190deg:80",
}


def best_of(func, repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        func()
        times.append(time.perf_counter() - t)
    return min(times)


def loop_rate(layout, orders: str, model: str, count: int) -> float:
    lengths = np.linspace(0.13, 0.16, count)
    analyse(layout, orders)  # warm-up (imports, caches)
    ks = parse_orders(orders)
    t = time.perf_counter()
    for length in lengths:
        v = variant(layout, {"conrod_length": float(length)})
        if model == "time":
            compute_phasors(v, ks, model="time", samples=256)
        else:
            analyse(v, orders)
    return count / (time.perf_counter() - t)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write-docs", action="store_true")
    args = parser.parse_args()
    if hasattr(os, "sched_setaffinity"):  # one core, as the target says
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    rows = []
    for name in ("inline-4", "v12-60"):
        layout = balance.load_layout(name)
        for orders in ("1-2", "1-8"):
            for grid_name, grid in (("with speed", SEPARABLE), ("per-cylinder", PER_CYLINDER)):
                points = int(np.prod([int(v.split(":")[-1]) for v in grid.values()]))
                t = best_of(lambda: sweep_arrays(layout, grid, orders), 2)  # noqa: B023
                rows.append([name, orders, grid_name, points, points / t])
            loop = loop_rate(layout, orders, "exact", 200)
            brute = loop_rate(layout, orders, "time", 200)
            for row in rows[-2:]:
                row += [loop, brute]
    lines = [
        "| layout | orders | grid | variants | sweep variants/s | analyse loop /s | "
        "time-domain /s | × loop | × time-domain |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name, orders, grid, points, rate, loop, brute in rows:
        lines.append(
            f"| {name} | {orders} | {grid} | {points:,} | {rate:.3g} | {loop:.3g} | "
            f"{brute:.3g} | {rate / loop:.0f} | {rate / brute:.0f} |"
        )
    search_lines = [
        "| search | enumerated | distinct evaluated | time | best | firing order |",
        "|---|---:|---:|---:|---|---|",
    ]
    for label, kwargs in (
        ("inline-4, --even-firing", {"cylinders": 4, "even_firing": True}),
        ("inline-6, --even-firing", {"cylinders": 6, "even_firing": True}),
        (
            "90° V8, --even-firing, split pins",
            {"cylinders": 8, "banks": (-45, 45), "even_firing": True},
        ),
        ("inline-6, all (no firing filter)", {"cylinders": 6}),
    ):
        r = search(**kwargs)
        a = r.best[0]
        fo = "-".join(map(str, a.firing_order)) if a.firing_order else "uneven"
        search_lines.append(
            f"| {label} | {r.enumerated:,} | {r.evaluated:,} | {r.seconds:.3f} s | "
            f"throws {'/'.join(f'{t:g}' for t in a.throws)}, score {a.score:.3g} | {fo} |"
        )
    v8 = balance.load_layout("v8-crossplane")
    tol_lines = ["| tolerance study, V8 cross-plane, 10⁶ samples | time |", "|---|---:|"]
    for scatter in (
        ["reciprocating=±3g", "rotating=±3g"],
        ["reciprocating=±3g", "rotating=±3g", "throw=±0.2deg", "z=±0.1mm"],
    ):
        t = time.perf_counter()
        tolerance(v8, scatter, samples=10**6)
        tol_lines.append(
            f"| `{' '.join('--scatter ' + s for s in scatter)}` | {time.perf_counter() - t:.1f} s |"
        )
    header = (
        f"Measured with `python benchmarks/sweep.py --write-docs` on {date.today()}, "
        f"Python {platform.python_version()}, {platform.machine()}, one process pinned to one "
        "core, all in one run. Loops are timed over 200 variants (conrod length varied); the "
        "time-domain rate is `compute_phasors(..., model='time', samples=256)` per variant."
    )
    text = "\n".join([header, "", *lines, "", *search_lines, "", *tol_lines]) + "\n"
    print(text)
    if args.write_docs:
        doc = ROOT / "docs" / "sweeps.md"
        marker = "<!-- benchmark -->"
        body = doc.read_text()
        start = body.index(marker) + len(marker)
        end = body.index(marker, start)
        doc.write_text(body[:start] + "\n" + text + body[end:])
        print(f"wrote {doc}", file=sys.stderr)


if __name__ == "__main__":
    main()
