"""Speed against accuracy of the piston-acceleration models, and the CLI's start-up time.

Run from the repository root:

    python benchmarks/model_ladder.py                 # print the tables
    python benchmarks/model_ladder.py --write-docs    # and write docs/benchmarks.md + figure

For each model and rod ratio it measures, in one run on one machine:

* the largest error of the normalised acceleration coefficients of orders 1-8 against a
  30-digit mpmath reference (trapezoidal rule, spectrally accurate for this function);
* the time of one analysis (``balance.core.analysis.compute`` of a single cylinder, orders 1-8);
* the time for 10**6 variants of the coefficients (10**6 distinct rod ratios near the given
  one, in chunks of 10**5), except for the ``time`` model, which has no batched path: its
  figure is the per-analysis time times 10**6 and is marked as extrapolated;
* the default analysis of the V12 against building its result Dataset (interleaved rounds,
  medians);
* ``balance analyse inline-4 --format json`` from a cold start against
  ``python -c "import xarray"`` and against the floor of the design's stack
  (``benchmarks/startup_floor.py``), interleaved, medians of 21 runs each, wall and CPU.
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import subprocess
import sys
import time
import timeit
from datetime import date
from pathlib import Path

import mpmath
import numpy as np

import balance
from balance.api import Engine, analyse
from balance.core import kinematics
from balance.core.analysis import compute, compute_phasors
from balance.core.result import Request
from balance.views.dataset import build_dataset

ROOT = Path(__file__).resolve().parent.parent
LAMBDAS = (0.1, 0.25, 0.4, 0.6, 0.8, 0.95)
ORDERS = np.arange(1, 9)
MODELS = (
    ("textbook", {}),
    ("series", {"terms": 3}),
    ("series", {"terms": 8}),
    ("exact", {}),
    ("time", {"samples": 256}),
)


def reference(lam: float) -> np.ndarray:
    """G_k, orders 1-8, at 30 digits (trapezoidal rule with aliasing below 1e-30)."""
    a = math.acosh(1 / lam)
    n = max(64, int(2 * (75 / a + 8)))
    with mpmath.workdps(30):
        lam_mp = mpmath.mpf(lam)
        values = []
        for j in range(n):
            b = 2 * mpmath.pi * j / n
            s, c = mpmath.sin(b), mpmath.cos(b)
            d = mpmath.sqrt(1 - (lam_mp * s) ** 2)
            values.append(c + lam_mp * ((c**2 - s * s) / d + (lam_mp * s * c) ** 2 / d**3))
        out = []
        for k in ORDERS:
            total = mpmath.fsum(
                v * mpmath.expjpi(-2 * k * mpmath.mpf(j) / n) for j, v in enumerate(values)
            )
            out.append(complex(2 * total / n))
    return np.array(out)


def single(lam: float) -> Engine:
    r = 0.04
    return Engine(
        name="single",
        speed=600.0,
        throw=np.zeros(1),
        bank=np.zeros(1),
        z=np.zeros(1),
        crank_radius=np.full(1, r),
        conrod_length=np.full(1, r / lam),
        offset=np.zeros(1),
        reciprocating_mass=np.full(1, 0.5),
        rotating_mass=np.full(1, 0.3),
        conrod_inertia_correction=np.zeros(1),
        reference_z=0.0,
        pitch=math.nan,
    )


def best_time(func, repeat: int = 5, target: float = 0.2) -> float:
    number = max(1, int(target / max(timeit.timeit(func, number=1), 1e-7)))
    return min(timeit.repeat(func, number=number, repeat=repeat)) / number


def per_million(model: str, lam: float, options: dict[str, int]) -> tuple[float, bool]:
    if model == "time":
        return best_time(
            lambda: compute_phasors(
                single(lam), ORDERS, model="time", moments=False, roll=False, **options
            )
        ) * 1e6, True
    rng = np.random.default_rng(1)
    chunk = 100_000
    start = time.perf_counter()
    for _ in range(10):
        ratios = lam * (1 + 1e-3 * rng.random(chunk))
        kinematics.acceleration_coefficients(
            ratios, 0.0, ORDERS, model=model, terms=options.get("terms", 3)
        )
    return time.perf_counter() - start, False


def ladder() -> list[dict[str, object]]:
    rows = []
    for lam in LAMBDAS:
        ref = reference(lam)
        layout = single(lam)
        for model, options in MODELS:
            result = compute_phasors(
                layout, ORDERS, model=model, moments=False, roll=False, **options
            )
            error = float(np.abs(result.coefficients[0] - ref).max())
            per_analysis = best_time(
                lambda m=model, o=options, lay=layout: compute_phasors(
                    lay, ORDERS, model=m, moments=False, roll=False, **o
                )
            )
            million, extrapolated = per_million(model, lam, options)
            label = model + "".join(f" {k}={v}" for k, v in options.items())
            rows.append(
                {
                    "lambda": lam,
                    "model": label,
                    "error": error,
                    "bound": result.model.error_bound,
                    "per_analysis": per_analysis,
                    "per_million": million,
                    "extrapolated": extrapolated,
                }
            )
            print(
                f"  lambda {lam:<5} {label:<18} error {error:9.2e}  "
                f"{per_analysis * 1e6:9.1f} us  {million:8.3f} s/1e6",
                file=sys.stderr,
            )
    return rows


def v12(rounds: int = 30, number: int = 20) -> dict[str, float]:
    """The V12's default analysis, its phasors and building its Dataset, interleaved.

    Each round times ``number`` calls of each in turn, so that the machine's changes of
    speed fall on all alike; the figures are medians over the rounds, and the ratio is the
    median (with 10th and 90th percentile) of the per-round ratios.
    """
    layout = balance.load_layout("v12-60")
    result = compute(layout, Request())
    funcs = {
        "analyse": lambda: analyse(layout),
        "compute": lambda: compute_phasors(layout),
        "dataset": lambda: build_dataset(result),
    }
    times: dict[str, list[float]] = {name: [] for name in funcs}
    for func in funcs.values():
        func()
    for _ in range(rounds):
        for name, func in funcs.items():
            start = time.perf_counter()
            for _ in range(number):
                func()
            times[name].append((time.perf_counter() - start) / number)
    out = {name: statistics.median(values) for name, values in times.items()}
    ratios = sorted(a / b for a, b in zip(times["analyse"], times["dataset"], strict=True))
    deciles = statistics.quantiles(ratios, n=10)
    out |= {
        "ratio": statistics.median(ratios),
        "ratio_p10": deciles[0],
        "ratio_p90": deciles[-1],
    }
    return out


def cold_start(runs: int = 21, callgrind: bool = True) -> dict[str, float]:
    """Medians of wall and CPU time of fresh processes, the three commands interleaved.

    The commands take turns (xarray, floor, balance, xarray, ...) so that a change in the
    machine's speed during the run (a shared virtual machine varies by tens of per cent)
    falls on all three alike; CPU time (user + system of the child) is reported beside
    wall time.  Bytecode caching is allowed (and one warm-up run made), as for any
    installed package: a development environment with PYTHONDONTWRITEBYTECODE set would
    otherwise compile balance's modules at every start while xarray's come precompiled.
    """
    import os

    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    commands = {
        "xarray": [sys.executable, "-c", "import xarray"],
        "floor": [
            sys.executable,
            str(ROOT / "benchmarks" / "startup_floor.py"),
            "analyse",
            str(ROOT / "layouts" / "inline-4.yaml"),
            "--format",
            "json",
        ],
        "floor_json": [
            sys.executable,
            str(ROOT / "benchmarks" / "startup_floor.py"),
            "--without-xarray",
            "analyse",
            str(ROOT / "layouts" / "inline-4.yaml"),
            "--format",
            "json",
        ],
        "imports": [sys.executable, "-c", "import numpy, typer, pydantic, yaml"],
        "cli": [sys.executable, "-m", "balance", "analyse", "inline-4", "--format", "json"],
        "help": [sys.executable, "-m", "balance", "--help"],
    }

    def once(cmd: list[str]) -> tuple[float, float]:
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
        _, status, usage = os.wait4(proc.pid, 0)
        if status != 0:
            raise RuntimeError(f"{cmd} failed ({status})")
        return time.perf_counter() - start, usage.ru_utime + usage.ru_stime

    for cmd in commands.values():
        once(cmd)  # warm-up
    wall: dict[str, list[float]] = {k: [] for k in commands}
    cpu: dict[str, list[float]] = {k: [] for k in commands}
    for _ in range(runs):
        for name, cmd in commands.items():
            w, c = once(cmd)
            wall[name].append(w)
            cpu[name].append(c)
    out = {name: statistics.median(values) for name, values in wall.items()}
    out |= {f"{name}_cpu": statistics.median(values) for name, values in cpu.items()}
    out["runs"] = runs
    if callgrind:
        out |= instructions(commands, env)
    # the spread: ratio of each run to the xarray run just before it
    for name in ("cli", "floor", "floor_json", "imports", "help"):
        pairs = sorted(a / b for a, b in zip(wall[name], wall["xarray"], strict=True))
        deciles = statistics.quantiles(pairs, n=10)
        out[f"{name}_p10"], out[f"{name}_p90"] = deciles[0], deciles[-1]
    return out


def markdown(rows, v12_times, start) -> str:
    lines = [
        "| λ | model | largest error (orders 1–8) | documented bound | per analysis | "
        "per 10⁶ variants |",
        "|---:|---|---:|---:|---:|---:|",
    ]
    for row in rows:
        million = f"{row['per_million']:.3g} s" + (" (extrapolated)" if row["extrapolated"] else "")
        lines.append(
            f"| {row['lambda']} | {row['model']} | {row['error']:.2e} | {row['bound']:.1e} | "
            f"{row['per_analysis'] * 1e6:.0f} µs | {million} |"
        )
    ratio_v12 = v12_times["ratio"]
    lines += [
        "",
        "| measurement | time | ratio | target |",
        "|---|---:|---:|---|",
        f"| V12 default analysis (`balance.analyse`, orders 1–8, with proposal) | "
        f"{v12_times['analyse'] * 1e3:.2f} ms | {ratio_v12:.2f} × building its Dataset "
        f"({v12_times['dataset'] * 1e3:.2f} ms; per round {v12_times['ratio_p10']:.2f}–"
        f"{v12_times['ratio_p90']:.2f} ×) | ≤ 2 × — "
        f"{'met' if ratio_v12 <= 2 else 'NOT met'} |",
        f"| V12 phasors alone (`compute`) | {v12_times['compute'] * 1e3:.2f} ms | | |",
    ]
    return "\n".join(lines) + "\n" + cold_start_table(start)


#: Cold-start targets: the command's median wall time per ``python -c "import xarray"``'s.
COLD_START_TARGETS = {"cli": 0.5, "help": 0.35}


def cold_start_table(start: dict[str, float]) -> str:
    """The cold-start rows (a table of their own, so that ``--cold-start`` can rewrite them)."""
    ratio_cli = start["cli"] / start["xarray"]
    ratio_help = start["help"] / start["xarray"]
    target_cli, target_help = COLD_START_TARGETS["cli"], COLD_START_TARGETS["help"]
    lines = [
        "",
        "| cold start (median of interleaved runs) | time | ratio | target |",
        "|---|---:|---:|---|",
        f"| `balance analyse inline-4 --format json`, wall | {start['cli']:.3f} s | "
        f'{ratio_cli:.2f} × `python -c "import xarray"` ({start["xarray"]:.3f} s; per run '
        f"{start['cli_p10']:.2f}–{start['cli_p90']:.2f} ×) | ≤ {target_cli} × — "
        f"{'met' if ratio_cli <= target_cli else 'NOT met'} |",
        f"| the same, CPU time | {start['cli_cpu']:.3f} s | "
        f"{start['cli_cpu'] / start['xarray_cpu']:.2f} × ({start['xarray_cpu']:.3f} s) | |",
        f"| floor of the stack (`benchmarks/startup_floor.py`: typer + pydantic + PyYAML + "
        f"xarray, no balance), wall | {start['floor']:.3f} s | "
        f"{start['floor'] / start['xarray']:.2f} × | |",
        f"| the floor, CPU time | {start['floor_cpu']:.3f} s | "
        f"{start['floor_cpu'] / start['xarray_cpu']:.2f} × | |",
        f"| floor of the JSON command (`startup_floor.py --without-xarray`: numpy + typer "
        f"+ pydantic + PyYAML, no balance), wall | {start['floor_json']:.3f} s | "
        f"{start['floor_json'] / start['xarray']:.2f} × (per run {start['floor_json_p10']:.2f}–"
        f"{start['floor_json_p90']:.2f} ×) | |",
        f"| that floor, CPU time | {start['floor_json_cpu']:.3f} s | "
        f"{start['floor_json_cpu'] / start['xarray_cpu']:.2f} × | |",
        f'| `python -c "import numpy, typer, pydantic, yaml"` (pydantic\'s lazy top level '
        f"only), wall | {start['imports']:.3f} s | {start['imports'] / start['xarray']:.2f} × | |",
        f"| `balance --help`, wall | {start['help']:.3f} s | {ratio_help:.2f} × (per run "
        f"{start['help_p10']:.2f}–{start['help_p90']:.2f} ×) | ≤ {target_help} × — "
        f"{'met' if ratio_help <= target_help else 'NOT met'} |",
        f"| `balance --help`, CPU time | {start['help_cpu']:.3f} s | "
        f"{start['help_cpu'] / start['xarray_cpu']:.2f} × | |",
    ]
    if "cli_instructions" in start:
        xi = start["xarray_instructions"]
        lines += [
            f"| instructions executed (callgrind): `balance analyse inline-4 --format json` | "
            f"{start['cli_instructions'] / 1e9:.3f} × 10⁹ | "
            f"{start['cli_instructions'] / xi:.2f} × `import xarray` ({xi / 1e9:.3f} × 10⁹) | |",
            f"| instructions executed: the floor | {start['floor_instructions'] / 1e9:.3f} × 10⁹ | "
            f"{start['floor_instructions'] / xi:.2f} × | |",
            f"| instructions executed: the floor of the JSON command | "
            f"{start['floor_json_instructions'] / 1e9:.3f} × 10⁹ | "
            f"{start['floor_json_instructions'] / xi:.2f} × | |",
        ]
    return "\n".join(lines) + "\n"


def figure(rows, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 4.5), layout="constrained")
    ax = fig.add_subplot()
    for model in dict.fromkeys(r["model"] for r in rows):
        pts = [r for r in rows if r["model"] == model]
        ax.loglog(
            [r["per_analysis"] * 1e6 for r in pts],
            [max(r["error"], 1e-17) for r in pts],
            "o-",
            label=model,
        )
        for r in pts:
            ax.annotate(
                f"{r['lambda']}",
                (r["per_analysis"] * 1e6, max(r["error"], 1e-17)),
                fontsize=7,
                xytext=(3, 2),
                textcoords="offset points",
            )
    ax.set_xlabel("time per analysis [µs] (single cylinder, orders 1–8)")
    ax.set_ylabel("largest coefficient error [per m r ω²]")
    ax.set_title("Model ladder: error against time (labels: λ)")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.savefig(path, dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write-docs", action="store_true")
    parser.add_argument(
        "--cold-start",
        action="store_true",
        help="only the cold-start figures (no callgrind); with --write-docs, rewrite only "
        "their section of docs/benchmarks.md",
    )
    parser.add_argument("--runs", type=int, default=21, help="cold-start runs of each command")
    args = parser.parse_args()
    if args.cold_start:
        start = cold_start(args.runs, callgrind=False)
        section = cold_start_section(start)
        print(section)
        if args.write_docs:
            page = ROOT / "docs" / "benchmarks.md"
            text = page.read_text(encoding="utf-8")
            begin, end = text.index(COLD_START_BEGIN), text.index(COLD_START_END)
            page.write_text(
                text[:begin] + section + text[end + len(COLD_START_END) :], encoding="utf-8"
            )
        return
    rows = ladder()
    v12_times = v12()
    start = cold_start()
    table = markdown(rows, v12_times, start)
    print(table)
    print(startup_note(start))
    if args.write_docs:
        static = ROOT / "docs" / "_static"
        static.mkdir(exist_ok=True)
        figure(rows, static / "model_ladder.png")
        page = ROOT / "docs" / "benchmarks.md"
        # what follows the cold-start section (notes, the other benchmarks' sections) stays
        old = page.read_text(encoding="utf-8") if page.exists() else ""
        rest = (
            old[old.index(COLD_START_END) + len(COLD_START_END) :]
            if COLD_START_END in old
            else "\n\n![error against time](_static/model_ladder.png)\n\n"
            "The documented bounds are those of {mod}`balance.core.accuracy`; the tolerance "
            "mode (`--tolerance`) picks the first model down the ladder textbook → series "
            "(up to 12 terms) → exact whose bound meets the tolerance.\n"
        )
        page.write_text(
            "# Benchmarks\n\n"
            "Measured with\n\n```console\n$ python benchmarks/model_ladder.py --write-docs\n```\n\n"
            f"on {date.today().isoformat()}, Python {platform.python_version()}, "
            f"{platform.machine()}, {_cpus()} cores (the project's 2-core machine), "
            "all in one run. Errors are of the normalised acceleration coefficients of "
            "orders 1–8 (a force error per $m_\\mathrm{rec} r\\omega^2$) against a 30-digit "
            "mpmath reference; times are the best of five repeats. See "
            "`benchmarks/model_ladder.py` for exactly what is timed.\n\n"
            + table
            + "\n"
            + cold_start_section(start)
            + rest,
            encoding="utf-8",
        )


def instructions(commands: dict[str, list[str]], env: dict[str, str]) -> dict[str, float]:
    """Instructions each command executes, counted by valgrind's callgrind (one run each,
    about half a minute): unlike time, the count does not depend on what else the machine
    is doing.  Empty when valgrind is not installed."""
    import re
    import shutil
    import tempfile

    if shutil.which("valgrind") is None:
        return {}
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, cmd in commands.items():
            result = subprocess.run(
                ["valgrind", "--tool=callgrind", f"--callgrind-out-file={tmp}/{name}.out", *cmd],
                capture_output=True,
                text=True,
                env=env,
                check=True,
            )
            match = re.search(r"Collected : (\d+)", result.stderr)
            if match:
                out[f"{name}_instructions"] = float(match.group(1))
    return out


COLD_START_BEGIN = "<!-- cold-start -->"
COLD_START_END = "<!-- /cold-start -->"


def cold_start_section(start: dict[str, float]) -> str:
    """The cold-start table and what it says, between markers (``--cold-start`` rewrites it)."""
    return (
        f"{COLD_START_BEGIN}\n"
        "Cold start measured with\n\n"
        f"```console\n$ python benchmarks/model_ladder.py --cold-start --runs {int(start['runs'])}"
        " --write-docs\n```\n\n"
        f"on {date.today().isoformat()}, Python {platform.python_version()}, {_cpus()} cores:"
        "\n" + cold_start_table(start) + "\n" + startup_note(start) + f"\n{COLD_START_END}"
    )


def startup_note(start: dict[str, float]) -> str:
    """What the start-up figures say, from this run's numbers."""
    return (
        f"The start-up ratio is the noisiest figure here. The {int(start['runs'])} runs of "
        "each command were interleaved; the ratio of each `balance` run to the xarray run "
        f"just before it lies between {start['cli_p10']:.2f} and {start['cli_p90']:.2f} × "
        "(10th to 90th percentile), because the speed of this shared virtual machine "
        "changes from one second to the next. Printing a result imports neither xarray nor "
        "pandas, pint or matplotlib (tests/test_result.py checks it); the floor row, a "
        "command line with nothing of balance in it on the stack the command used to need "
        "(typer, pydantic, PyYAML and xarray), takes "
        f"{start['floor'] / start['xarray']:.2f} × (per run {start['floor_p10']:.2f}–"
        f"{start['floor_p90']:.2f} ×): what leaving xarray out of the command saves. "
        "Without xarray the same command line is the floor of `--format json` itself "
        "(numpy, typer parsing eleven options, which in typer 0.29 means pydantic's "
        "TypeAdapters, a pydantic model validated from PyYAML): "
        f"{start['floor_json'] / start['xarray']:.2f} ×, so balance's own code (its "
        "imports, its larger command line, reading and validating the layout, the analysis "
        "and the JSON) adds "
        f"{(start['cli'] - start['floor_json']) / start['xarray']:.2f} ×. "
        '`python -c "import numpy, typer, pydantic, yaml"` '
        f"({start['imports'] / start['xarray']:.2f} ×) is no floor: pydantic imports its "
        "models, fields and TypeAdapter lazily, on first use, and typer's first option uses "
        "them."
        + (
            " Counted in instructions, which no other load on the machine changes, the floor "
            f"is {start['floor_instructions'] / start['xarray_instructions']:.2f} × and "
            f"balance {start['cli_instructions'] / start['xarray_instructions']:.2f} × the "
            "bare xarray import."
            if "cli_instructions" in start
            else ""
        )
    )


def _cpus() -> int:
    import os

    return os.cpu_count() or 1


if __name__ == "__main__":
    main()
