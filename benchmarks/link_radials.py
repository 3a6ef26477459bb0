"""Numbers for the docs: link cylinders' strokes and free forces of the 5- and 9-cylinder
radials, against the idealised radials (all rods on the crank pin).

Run from the repository root::

    python benchmarks/link_radials.py            # print the Markdown tables

For each radial it prints every cylinder's actual stroke and TDC, and the peak free force of
orders 1-8 (reciprocating, N; order 1 also with the rotating masses) of three engines:
the built-in idealised radial (``radial-N-idealised``: its estimated average rod on the pin),
the built-in radial with master and link rods (``radial-N``), and that same engine with a
zero pin radius (every rod, as it is, on the crank pin: what the articulation alone
changes).
"""

from __future__ import annotations

import dataclasses

import numpy as np

import balance
from balance.core.analysis import compute
from balance.io.request import build_request


def _on_the_pin(engine: balance.api.Engine) -> balance.api.Engine:
    assert engine.links is not None
    links = dataclasses.replace(engine.links, pin_radius=np.zeros(engine.n_cylinders))
    return dataclasses.replace(engine, links=links)


def _peaks(engine: balance.api.Engine) -> tuple[np.ndarray, float]:
    p = compute(engine, build_request(engine, proposal=False, moments=False, roll=False)).phasors
    peak = np.abs(p.force_forward) + np.abs(p.force_backward)
    with_rotating = abs(p.force_forward[0] + p.rotating_force) + abs(p.force_backward[0])
    return peak, with_rotating


def main() -> None:
    for n in (5, 9):
        real = balance.load_layout(f"radial-{n}")
        ideal = balance.load_layout(f"radial-{n}-idealised")
        flat = _on_the_pin(real)
        result = compute(real, build_request(real, orders=(1,), proposal=False))
        dead_centres = result.part("cylinders")
        print(f"\n### {real.name}\n")
        print("| cylinder | rod | stroke [mm] | TDC at [deg] | nominal TDC [deg] |")
        print("|---|---|---|---|---|")
        for i in range(n):
            rod = "master" if i == 0 else "link"
            nominal = np.degrees(real.bank[i] - real.throw[i]) % 360.0
            print(
                f"| {i + 1} | {rod} | {dead_centres.stroke[i] * 1e3:.3f} | "
                f"{np.degrees(dead_centres.tdc[i]):.3f} | {nominal:.3f} |"
            )
        rows = [
            (f"idealised (`radial-{n}-idealised`)", ideal),
            ("same rods on the pin", flat),
            (f"master and link rods (`radial-{n}`)", real),
        ]
        print(
            "\n| engine | "
            + " | ".join(f"order {k}" for k in range(1, 9))
            + " | order 1 with rotating |"
        )
        print("|---" * 10 + "|")
        for label, engine in rows:
            peak, first = _peaks(engine)
            cells = " | ".join(f"{v:.4g}" for v in peak)
            print(f"| {label} | {cells} | {first:.4g} |")


if __name__ == "__main__":
    main()
