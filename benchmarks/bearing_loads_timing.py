"""Time bearing loads of the V12 against its analysis (orders 1-8), interleaved, medians."""

import statistics
import sys
import time

from balance.core.analysis import compute
from balance.core.bearings import bearing_loads
from balance.core.result import Request
from balance.io.layout_file import load_layout

name = sys.argv[1] if len(sys.argv) > 1 else "v12-60"
e = load_layout(name)
req = Request(orders=tuple(range(1, 9)))
res = compute(e, req)
bearing_loads(e)
cws = (
    tuple((cw.z, cw.unbalance) for cw in res.balanced.proposal.counterweights)
    if getattr(res, "balanced", None)
    else ()
)
a, b, c = [], [], []
for _ in range(30):
    t = time.perf_counter()
    compute(e, req)
    a.append(time.perf_counter() - t)
    t = time.perf_counter()
    bearing_loads(e)
    b.append(time.perf_counter() - t)
    t = time.perf_counter()
    bearing_loads(e, counterweights=cws)
    c.append(time.perf_counter() - t)
ma, mb, mc = (statistics.median(x) * 1e3 for x in (a, b, c))
print(
    f"{name}: compute {ma:.2f} ms, bearing_loads {mb:.2f} ms ({mb / ma:.2f}x), "
    f"with {len(cws)} counterweights {mc:.2f} ms; "
    f"both (without+with) {(mb + mc) / ma:.2f}x of compute"
)
