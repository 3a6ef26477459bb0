"""Time ``compute`` of the V12 (orders 1-8) with and without ``bearings=True``.

Interleaved runs, medians; prints both times and their ratio (issue 15: the bearing loads
should add at most 2x to the analysis time).  Usage: ``python benchmarks/bearing_loads.py
[LAYOUT] [RUNS]``.
"""

import statistics
import sys
import time

from balance.core.analysis import compute
from balance.io.layout_file import load_layout
from balance.io.request import build_request

name = sys.argv[1] if len(sys.argv) > 1 else "v12-60"
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 200
engine = load_layout(name)
plain = build_request(engine, 8)  # the default analysis: proposal, torque, cylinders
with_bearings = build_request(engine, 8, bearings=True)
for _ in range(5):
    compute(engine, plain)
    compute(engine, with_bearings)
a, b = [], []
for _ in range(runs):
    t = time.perf_counter()
    compute(engine, plain)
    a.append(time.perf_counter() - t)
    t = time.perf_counter()
    compute(engine, with_bearings)
    b.append(time.perf_counter() - t)
ma, mb = (statistics.median(x) * 1e3 for x in (a, b))
la, lb = (min(x) * 1e3 for x in (a, b))
print(
    f"{name}, orders 1-8, {runs} interleaved runs, medians: compute {ma:.2f} ms, "
    f"with bearings {mb:.2f} ms: {mb / ma:.2f}x the analysis time "
    f"(bearing loads add {(mb - ma) / ma:.2f}x); "
    f"minima: {la:.2f} ms, {lb:.2f} ms: {lb / la:.2f}x (add {(lb - la) / la:.2f}x)"
)
