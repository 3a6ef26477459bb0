"""Time drawing each figure kind and the HTML report, as users draw them.

For each layout and each kind that applies (:func:`balance.views.plots.applicable_kinds`), the
time to draw the figure and write it as PNG (what ``balance plot`` and ``save_plots``
write) and as SVG (what the report inlines), and the time of ``render_report``.  Times are
the CPU time of this process (:func:`time.process_time`), the best of ``RUNS`` repeats: on
a shared machine the least disturbed run is the figure of the code itself.  Usage::

    python benchmarks/figures.py [RUNS] [LAYOUT ...]

Defaults: 5 runs; ``inline-4``, ``inline-3`` and ``v8-crossplane``.  To compare two
versions of the code, run this file under each (for the old one from a checkout of it,
``cd /tmp && PYTHONPATH=<checkout> python <this file>``), alternating a few times, and
keep the smaller figure of each cell.
"""

import sys
import time
from collections.abc import Callable

import balance
from balance.core.analysis import compute
from balance.core.result import Result
from balance.io.request import build_request
from balance.views import plots
from balance.views.report import render_report

args = sys.argv[1:]
runs = int(args.pop(0)) if args and args[0].isdigit() else 5
names = args or ["inline-4", "inline-3", "v8-crossplane"]


def best(function: Callable[[], object], repeats: int) -> float:
    """The least CPU time of ``repeats`` calls [s]."""
    times = []
    for _ in range(repeats):
        start = time.process_time()
        function()
        times.append(time.process_time() - start)
    return min(times)


def drawn(result: Result, kind: str, fmt: str) -> Callable[[], bytes]:
    return lambda: plots.figure_bytes(plots.plot_kind(kind)(result), fmt)


print(f"CPU time [ms], best of {runs} runs")
print(f"{'layout':16s} {'kind':14s} {'png':>7s} {'svg':>7s}")
for name in names:
    result = compute(
        balance.load_layout(name), build_request(balance.load_layout(name), range(1, 9))
    )
    kinds = plots.applicable_kinds(result)
    drawn(result, "spectrum", "png")()  # the font cache and the backends, loaded once
    for kind in kinds:
        png, svg = (best(drawn(result, kind, fmt), runs) for fmt in ("png", "svg"))
        print(f"{name:16s} {kind:14s} {1e3 * png:7.0f} {1e3 * svg:7.0f}")
    report = best(lambda r=result: render_report(r), max(1, runs // 2))
    print(f"{name:16s} {'report':14s} {'':>7s} {1e3 * report:7.0f}")
