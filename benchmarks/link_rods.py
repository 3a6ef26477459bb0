"""Cost of master and link rods: a 9-cylinder radial with link rods against the same radial
with all rods on one pin (issue 14 asks for at most 3 x).

Run from the repository root:

    python benchmarks/link_rods.py [ROUNDS]              # print the table
    python benchmarks/link_rods.py [ROUNDS] --write-docs # and rewrite its section of
                                                         # docs/benchmarks.md

Timed: ``balance.core.analysis.compute(engine, build_request(engine))`` (orders 1-8,
moments, roll, the proposal, each cylinder's stroke and TDC) of

* ``radial-9``: the built-in radial with master and link rods;
* the same engine with every rod, as it is, on the crank pin (the link cylinders made plain
  cylinders with the link rod's length: same masses, no link table);
* ``radial-9-idealised``: the built-in idealised radial (its average rod on the pin).

The three are timed in interleaved rounds (each round times every engine over 20 calls, in
turn), so that a load on the shared machine falls on all of them alike; the table gives the
medians and minima over the rounds.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import statistics
import sys
import timeit
from datetime import date
from pathlib import Path

import numpy as np

import balance
from balance.core.analysis import compute
from balance.io.request import build_request

ROOT = Path(__file__).resolve().parent.parent
BEGIN = "<!-- link-rods -->"
END = "<!-- /link-rods -->"
CALLS = 20


def engines() -> dict[str, balance.api.Engine]:
    real = balance.load_layout("radial-9")
    on_the_pin = dataclasses.replace(real, links=None, name="radial-9, rods on the pin")
    return {
        "`radial-9` (master and link rods)": real,
        "same rods on the crank pin": on_the_pin,
        "`radial-9-idealised`": balance.load_layout("radial-9-idealised"),
    }


def measure(rounds: int) -> dict[str, list[float]]:
    table = engines()
    requests = {name: build_request(engine) for name, engine in table.items()}
    for name, engine in table.items():
        compute(engine, requests[name])  # warm up: imports and caches
    times: dict[str, list[float]] = {name: [] for name in table}
    for _ in range(rounds):
        for name, engine in table.items():
            request = requests[name]
            seconds = timeit.timeit(lambda e=engine, q=request: compute(e, q), number=CALLS)
            times[name].append(seconds / CALLS)
    return times


def markdown(times: dict[str, list[float]], rounds: int) -> str:
    names = list(times)
    base = names[1]
    lines = [
        "| engine | `compute` median | min | ratio to the same rods on the pin (medians) | "
        "(minima) |",
        "|---|---:|---:|---:|---:|",
    ]
    for name in names:
        med, low = statistics.median(times[name]), min(times[name])
        ratio_med = med / statistics.median(times[base])
        ratio_min = low / min(times[base])
        lines.append(
            f"| {name} | {med * 1e3:.2f} ms | {low * 1e3:.2f} ms | {ratio_med:.2f} × | "
            f"{ratio_min:.2f} × |"
        )
    per_round = np.asarray(times[names[0]]) / np.asarray(times[base])
    lines.append("")
    lines.append(
        f"Per round, the link radial took {per_round.min():.2f}–{per_round.max():.2f} × the "
        f"same rods on the pin ({rounds} rounds of {CALLS} calls each)."
    )
    return "\n".join(lines)


def section(times: dict[str, list[float]], rounds: int) -> str:
    return (
        f"{BEGIN}\n"
        "## Master and link rods\n\n"
        "Measured with\n\n"
        f"```console\n$ python benchmarks/link_rods.py {rounds} --write-docs\n```\n\n"
        f"on {date.today().isoformat()}, Python {platform.python_version()}, numpy "
        f"{np.__version__}, on the shared 2-core development machine, load average "
        f"{os.getloadavg()[0]:.2f} at the end of the run (the rounds are interleaved so that "
        "any other load falls on every engine alike; the minima are the better figure of the "
        "code itself). `compute` at orders 1–8 with the "
        "proposal and the cylinders' strokes and TDCs. Issue 14 asks for the link radial to "
        "cost at most 3 × the same radial with all rods on one pin.\n\n"
        + markdown(times, rounds)
        + "\n\nWhere the time goes in the link radial: the Fourier coefficients (one batched "
        "adaptive FFT of every piston's acceleration and roll functions, the master's among "
        "them, and of the master's link-pin function; converged at 128 samples), the dead "
        "centres of the link pistons (64 samples and Newton), and the error bound's reach of "
        "the link rods (128 samples). The same rods on the pin take the plain path (two "
        "distinct rod ratios).\n"
        f"{END}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("rounds", nargs="?", type=int, default=30)
    parser.add_argument("--write-docs", action="store_true")
    args = parser.parse_args()
    times = measure(args.rounds)
    text = section(times, args.rounds)
    print(text)
    if args.write_docs:
        page = ROOT / "docs" / "benchmarks.md"
        old = page.read_text(encoding="utf-8")
        if BEGIN in old:
            begin, end = old.index(BEGIN), old.index(END) + len(END)
            new = old[:begin] + text + old[end:]
        else:
            new = old.rstrip("\n") + "\n\n" + text + "\n"
        page.write_text(new, encoding="utf-8")


if __name__ == "__main__":
    sys.exit(main())
