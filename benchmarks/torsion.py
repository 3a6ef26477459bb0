"""Speed of the torsional response: 200 speeds x 24 orders of a 12-mass V8 train.

Run from the repository root:

    python benchmarks/torsion.py

The layout is the built-in ``v8-crossplane-gas`` (gas forces from the parametric model)
with a 12-mass torsion train added in Python: pulley with a tuned rubber damper, timing
gear, four throws of two cylinders, flywheel, gearbox, propshaft, differential, wheels and
vehicle (illustrative values).  Timed, best of several interleaved rounds:

- ``balance analyse`` of the layout in process: :func:`balance.core.analysis.compute` of
  the default request (free forces, gas torque, proposal) with the torsion section turned
  off (the layout's section would add it, at the analysis speed alone);
- the ``torsion`` section's part, :func:`balance.core.torsion.torsion_part`, on that
  result: 200 speeds from 20 % to 120 % of the layout's speed, every half order from 0.5
  to 12 (24 orders), the modes, the resonances and the synthesis;
- the two together (what ``balance torsion`` computes).

The issue's target: the torsion part in at most 3 x the time of the analysis.
"""

from __future__ import annotations

import platform
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from balance.core.analysis import compute
from balance.core.torsion import torsion_part
from balance.io.layout_file import load_layout
from balance.io.request import build_request

# the 12-mass V8 train is the one tests/test_torsion.py checks (tests/torsion_trains.py)
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from torsion_trains import v8_train

ROUNDS, REPEATS = 7, 10


def best(func: Callable[[], object]) -> float:
    """The best of :data:`REPEATS` runs [s]."""
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    engine = load_layout("v8-crossplane-gas").with_section("torsion", v8_train())
    # the analysis without the torsion section (which the layout's section would turn on,
    # at the analysis speed): free forces, gas torque, proposal
    request = build_request(engine, None, torsion=False)
    result = compute(engine, request)
    part = torsion_part(engine, request, result, speeds="sweep").part("torsion")
    assert part.section_torque is not None
    assert part.section_torque.shape == (11, 24, 200)  # sections, orders, speeds
    analyse, torsion, both = [], [], []
    for _ in range(ROUNDS):  # interleaved, so that a busy machine slows all alike
        analyse.append(best(lambda: compute(engine, request)))
        torsion.append(best(lambda: torsion_part(engine, request, result, speeds="sweep")))
        both.append(
            best(lambda: torsion_part(engine, request, compute(engine, request), speeds="sweep"))
        )
    a, t, b = min(analyse), min(torsion), min(both)
    ratios = np.array(torsion) / np.array(analyse)
    print(f"{platform.python_version()}, {platform.machine()}")
    print(f"{'balance analyse (compute, in process)':48s} {a * 1e3:8.2f} ms")
    print(
        f"{'torsion part, 200 speeds x 24 orders, 12 masses':48s} {t * 1e3:8.2f} ms"
        f"   {t / a:.2f} x analyse (per round {ratios.min():.2f}-{ratios.max():.2f} x)"
    )
    print(f"{'analyse + torsion (balance torsion)':48s} {b * 1e3:8.2f} ms   {b / a:.2f} x analyse")
    print("target: torsion part <= 3 x analyse:", "met" if t <= 3 * a else "NOT met")


if __name__ == "__main__":
    main()
