"""The speed/accuracy trade of the variable-speed rung: what the constant-speed analysis
misses, and what the dynamic one costs.

Run from the repository root:

    python benchmarks/dynamics.py [ROUNDS]              # print the tables
    python benchmarks/dynamics.py [ROUNDS] --write-docs # and rewrite their sections of
                                                        # docs/benchmarks.md and
                                                        # docs/dynamics.md

Measured:

* the constant-speed error at idle and at rated speed of a single (the built-in KTM 690
  geometry and masses), an inline-4 (``inline-4-gas``) and a V8 (``v8-crossplane-gas``): the
  exact speed fluctuation and its constant-speed estimate, the constant rung's error bound
  and the largest difference of the whole free force over the cycle, both per
  :math:`\\sum m r\\omega^2`, and per order the difference of the free force and of the roll
  (the dynamic analysis against the constant-speed one at the same mean speed, mean load);
* the time of a dynamic analysis (``compute`` with the gas forces, then
  ``balance.core.dynamics.dynamics_part``) against the constant-speed gas analysis
  (``compute``), in interleaved rounds, medians and minima (the target is at most 10 x).

Idle is a part load of the parametric gas model (``balance.core.gas``) at 1500 rpm (the
single), 800 rpm (the inline-4) and 700 rpm (the V8): intake 0.4 bar, the compression ratio
of the engine's full-load model (12.7 for the single), the heat released per cylinder and
cycle found so that the indicated mean effective pressure is 2 bar.  Rated: the single at
7500 rpm with intake 1 bar and 13 bar IMEP (KTM's 70 PS at 7500 rpm is about 12 bar brake),
the inline-4 and the V8 as their built-in layouts (7000 and 4000 rpm, full load).
Flywheels: the single 0.05 kg m^2 (an estimate for a big single's crank and magneto rotor),
the inline-4 its layout's 0.12 kg m^2, the V8 the inertia its layout sizes for 1 % at
4000 rpm, kept at idle.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import timeit
from datetime import date
from pathlib import Path
from typing import Any

import numpy as np
import yaml

import balance
from balance.core.analysis import compute
from balance.core.dynamics import dynamics_part
from balance.core.result import Request
from balance.core.speed_model import Flywheel, constant_speed_bound
from balance.io.layout_file import layout_from_dict

ROOT = Path(__file__).resolve().parent.parent
REQUEST = Request.of(range(1, 9))
MARKS = {
    "benchmarks.md": ("<!-- dynamics -->", "<!-- /dynamics -->"),
    "dynamics.md": ("<!-- dynamics-benchmark -->", "<!-- /dynamics-benchmark -->"),
}
CALLS = 5


def _data(name: str) -> dict[str, Any]:
    text = (ROOT / "layouts" / f"{name}.yaml").read_text(encoding="utf-8")
    data: dict[str, Any] = yaml.safe_load(text)
    return data


def _with_model(
    data: dict[str, Any], speed: str, intake: str, heat_kj: float, ratio: float
) -> balance.api.Engine:
    out = {**data, "speed": speed}
    gas = {
        "model": {
            "compression_ratio": ratio,
            "intake_pressure": intake,
            "exhaust_pressure": "1.05 bar",
            "heat_released": f"{heat_kj!r} kJ",
        },
        "crankcase_pressure": "1 bar",
    }
    out["gas"] = gas
    out.pop("flywheel", None)
    out["flywheel"] = {"inertia": "1 kg m^2"}  # replaced by the case's (the reader needs one)
    return layout_from_dict(out)


def _imep(engine: balance.api.Engine) -> float:
    torque = compute(engine, Request.of([1])).part("torque")
    return float(torque.mean * 4 * np.pi / engine.displacement)


def _for_imep(
    data: dict[str, Any], speed: str, intake: str, ratio: float, target: float
) -> tuple[balance.api.Engine, float]:
    """The engine whose heat release gives the indicated mean effective pressure ``target``
    [Pa] (bisection on the heat)."""
    low, high = 0.0, 5.0
    for _ in range(40):
        mid = 0.5 * (low + high)
        if _imep(_with_model(data, speed, intake, mid, ratio)) < target:
            low = mid
        else:
            high = mid
    heat = round(0.5 * (low + high), 4)
    return _with_model(data, speed, intake, heat, ratio), heat


def cases() -> dict[str, tuple[balance.api.Engine, Flywheel, str]]:
    """Each case: the engine, its flywheel and a note on its gas forces."""
    single = _data("single")
    single["geometry"] = {**single["geometry"]}
    single.setdefault("cycle", "four-stroke")
    i4 = _data("inline-4-gas")
    v8 = _data("v8-crossplane-gas")
    out: dict[str, tuple[balance.api.Engine, Flywheel, str]] = {}
    engine, heat = _for_imep(single, "1500 rpm", "0.4 bar", 12.7, 2e5)
    out["single, idle 1500 rpm"] = (engine, Flywheel(0.05), f"model, {heat} kJ, IMEP 2 bar")
    engine, heat = _for_imep(single, "7500 rpm", "1.0 bar", 12.7, 13e5)
    out["single, rated 7500 rpm"] = (engine, Flywheel(0.05), f"model, {heat} kJ, IMEP 13 bar")
    engine, heat = _for_imep(i4, "800 rpm", "0.4 bar", 11.0, 2e5)
    out["inline-4, idle 800 rpm"] = (engine, Flywheel(0.12), f"model, {heat} kJ, IMEP 2 bar")
    out["inline-4, rated 7000 rpm"] = (
        balance.load_layout("inline-4-gas"),
        Flywheel(0.12),
        "built-in trace, IMEP 13.2 bar",
    )
    v8_rated = balance.load_layout("v8-crossplane-gas")
    sized = compute(v8_rated, REQUEST)
    sized = dynamics_part(v8_rated, REQUEST, sized)
    inertia = sized.part("dynamics").flywheel_inertia
    engine, heat = _for_imep(v8, "700 rpm", "0.4 bar", 10.5, 2e5)
    out["V8, idle 700 rpm"] = (engine, Flywheel(inertia), f"model, {heat} kJ, IMEP 2 bar")
    out["V8, rated 4000 rpm"] = (v8_rated, Flywheel(inertia), "built-in model, 2.0 kJ")
    return out


def errors(table: dict[str, tuple[balance.api.Engine, Flywheel, str]]) -> dict[str, Any]:
    """Per case: the motion, the bound and the differences."""
    out = {}
    for name, (engine, wheel, note) in table.items():
        result = compute(engine, REQUEST)
        part = dynamics_part(engine, REQUEST, result, flywheel=wheel).part("dynamics")
        bound = constant_speed_bound(engine, result.part("torque"), wheel)
        assert bound is not None
        measured = float(np.max(np.abs(part.force - part.force_constant))) / bound.reference
        out[name] = {
            "note": note,
            "flywheel": wheel.inertia,
            "mean_torque": part.load_torque,
            "delta": part.speed_fluctuation,
            "estimate": part.speed_fluctuation_constant_speed,
            "bound": bound.ratio,
            "measured": measured,
            "orders": part.orders,
            "force": part.difference("force") / bound.reference,
            "force_peak": part.constant_peak("force") / bound.reference,
            "roll": part.difference("roll"),
            "roll_top": float(np.max(part.constant_peak("roll"))),
            "largest_force": part.largest_difference("force"),
            "largest_roll": part.largest_difference("roll"),
        }
    return out


def timing(rounds: int) -> dict[str, dict[str, list[float]]]:
    """Seconds per analysis, constant and dynamic, in interleaved rounds."""
    engines = {
        "`inline-4-gas` (J_f given)": (balance.load_layout("inline-4-gas"), None),
        "`v8-crossplane-gas` (J_f sized for 1 %)": (balance.load_layout("v8-crossplane-gas"), None),
        "`single` with gas, idle (J_f given)": (
            _with_model(_data("single"), "1500 rpm", "0.4 bar", 0.37, 12.7),
            Flywheel(0.05),
        ),
    }

    def dynamic(engine: Any, wheel: Any) -> None:
        dynamics_part(engine, REQUEST, compute(engine, REQUEST), flywheel=wheel)

    out: dict[str, dict[str, list[float]]] = {}
    for name, (engine, wheel) in engines.items():
        compute(engine, REQUEST)
        dynamic(engine, wheel)
        out[name] = {"constant": [], "dynamic": []}
    for _ in range(rounds):
        for name, (engine, wheel) in engines.items():
            t_const = timeit.timeit(lambda e=engine: compute(e, REQUEST), number=CALLS) / CALLS
            t_dyn = timeit.timeit(lambda e=engine, w=wheel: dynamic(e, w), number=CALLS) / CALLS
            out[name]["constant"].append(t_const)
            out[name]["dynamic"].append(t_dyn)
    return out


def _g(value: float, digits: int = 3) -> str:
    return "0" if value == 0 else f"{value:.{digits}g}"


def error_tables(found: dict[str, Any]) -> str:
    names = list(found)
    lines = [
        "| case | gas | J_f [kg m²] | mean torque [N m] | δ exact | δ estimate | "
        "bound / Σmrω² | measured / Σmrω² | measured / bound |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in names:
        f = found[name]
        lines.append(
            f"| {name} | {f['note']} | {_g(f['flywheel'])} | {f['mean_torque']:.1f} | "
            f"{100 * f['delta']:.2f} % | {100 * f['estimate']:.2f} % | "
            f"{100 * f['bound']:.2f} % | {100 * f['measured']:.2f} % | "
            f"{f['measured'] / f['bound']:.2f} |"
        )
    orders = found[names[0]]["orders"]
    head = "| order | " + " | ".join(names) + " |"
    rule = "|---:|" + "---:|" * len(names)
    lines += [
        "",
        "Difference of the whole free force per order, |ΔP⁺| + |ΔP⁻| per Σ m r ω² [%] "
        "(in brackets: the constant-speed peak, same unit; orders where both are zero left "
        "out):",
        "",
        head,
        rule,
    ]
    for i, k in enumerate(orders):
        cells = []
        if all(found[n]["force"][i] == 0 and found[n]["force_peak"][i] == 0 for n in names):
            continue
        for n in names:
            cells.append(
                f"{_g(100 * found[n]['force'][i], 2)} ({_g(100 * found[n]['force_peak'][i], 2)})"
            )
        lines.append(f"| {k:g} | " + " | ".join(cells) + " |")
    lines += [
        "",
        "Difference of the roll per order, |ΔR| per the largest constant-speed roll amplitude [%]:",
        "",
        head,
        rule,
    ]
    for i, k in enumerate(orders):
        if all(found[n]["roll"][i] == 0 for n in names):
            continue
        cells = [_g(100 * found[n]["roll"][i] / found[n]["roll_top"], 2) for n in names]
        lines.append(f"| {k:g} | " + " | ".join(cells) + " |")
    lines += [
        "",
        "Largest difference over the orders per the largest constant-speed value (the JSON's "
        "`largest_difference`): "
        + "; ".join(
            f"{n}: force {100 * found[n]['largest_force']:.2g} %, roll "
            f"{100 * found[n]['largest_roll']:.2g} %"
            for n in names
        )
        + ".",
    ]
    return "\n".join(lines)


def timing_table(times: dict[str, dict[str, list[float]]], rounds: int) -> str:
    lines = [
        "| engine | constant-speed gas analysis (median, min) | dynamic analysis (median, min) "
        "| ratio (medians) | ratio (minima) | target |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for name, t in times.items():
        cm, cl = statistics.median(t["constant"]), min(t["constant"])
        dm, dl = statistics.median(t["dynamic"]), min(t["dynamic"])
        met = "met" if dm / cm <= 10.0 else "NOT met"
        lines.append(
            f"| {name} | {cm * 1e3:.1f} ms, {cl * 1e3:.1f} ms | {dm * 1e3:.1f} ms, "
            f"{dl * 1e3:.1f} ms | {dm / cm:.2f} × | {dl / cl:.2f} × | ≤ 10 × — {met} |"
        )
    lines.append("")
    lines.append(f"({rounds} interleaved rounds of {CALLS} calls each.)")
    return "\n".join(lines)


def section(found: dict[str, Any], times: dict[str, dict[str, list[float]]], rounds: int) -> str:
    return (
        "## The variable-speed rung\n\n"
        "Measured with\n\n"
        f"```console\n$ python benchmarks/dynamics.py {rounds} --write-docs\n```\n\n"
        f"on {date.today().isoformat()}, Python {platform.python_version()}, numpy "
        f"{np.__version__}, on the shared 2-core development machine (load average "
        f"{os.getloadavg()[0]:.2f} at the end of the run). What the constant-speed analysis "
        "misses at idle and at rated speed (mean load; the dynamic analysis against the "
        "constant-speed one at the same mean speed, docs/dynamics.md), and the constant "
        "rung's bound on it, from constant-speed data alone:\n\n"
        + error_tables(found)
        + "\n\nThe time of a dynamic analysis (orders 1–8, the proposal, the gas forces, "
        "then the steady state and its orders in time; the V8 sizes its flywheel for the "
        "exact 1 %, a root search over the steady state) against the constant-speed gas "
        "analysis:\n\n" + timing_table(times, rounds) + "\n"
    )


def _write(page: str, text: str) -> None:
    path = ROOT / "docs" / page
    begin, end = MARKS[page]
    old = path.read_text(encoding="utf-8")
    block = f"{begin}\n{text}{end}"
    if begin in old:
        new = old[: old.index(begin)] + block + old[old.index(end) + len(end) :]
    else:
        new = old.rstrip("\n") + "\n\n" + block + "\n"
    path.write_text(new, encoding="utf-8")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("rounds", nargs="?", type=int, default=15)
    parser.add_argument("--write-docs", action="store_true")
    args = parser.parse_args()
    found = errors(cases())
    times = timing(args.rounds)
    text = section(found, times, args.rounds)
    print(text)
    if args.write_docs:
        _write("benchmarks.md", text)
        _write("dynamics.md", text.replace("## The variable-speed rung", "## Measured trade", 1))


if __name__ == "__main__":
    sys.exit(main())
