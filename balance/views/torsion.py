"""Views of the ``torsion`` section, torsional vibration of the crank train (docs/torsion.md):
JSON, CSV, tables, figures, report.

Everything here reads the section's part, a :class:`~balance.core.torsion.TorsionResult`,
and the layout's name; nothing is computed but units and formats (angles in degrees,
stresses in MPa, speeds in rpm).  The response is absent (``null``) for a train without
any damping.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.catalogue import speed_rpm
from balance.core.phasors import phase_deg
from balance.views.figures import grid_figure, placeholder, styled, title_text
from balance.views.polar import format_number, json_number, order_value

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure
    from rich.console import RenderableType

    from balance.core.result import Result
    from balance.core.torsion import TorsionResult

__all__ = [
    "PLOTS",
    "REPORT_TITLE",
    "SCHEMA",
    "json_block",
    "report_section",
    "tables",
    "torsion_csv",
    "torsion_document",
    "torsion_text",
]

#: Schema name of the document of ``balance torsion --format json``.
SCHEMA = "balance.torsion/1"
#: Rows of the speed table beyond which the speeds are thinned.
TABLE_SPEEDS = 25
#: Modes drawn in the mode-shape figure.
SHAPES_DRAWN = 5
#: The response figure names the orders of the largest peaks, at most this many (one colour
#: each); the others are drawn thin and grey.
ORDERS_NAMED = 8
#: Resonances labelled with their order and vector sum in the Campbell diagram (the
#: largest vector sums).
LABELLED = 8
#: Share of the largest order below which an order is not named in the response figure
#: (its curve lies on the axis; it is drawn grey with the others).
DRAWN_SHARE = 0.02


def _part(result: Result) -> TorsionResult:
    part: TorsionResult = result.part("torsion")
    return part


def _rpm(speeds: Any) -> list[float]:
    return [speed_rpm(float(w)) for w in np.atleast_1d(speeds)]


def _nums(values: Any) -> list[Any]:
    """Nested lists of JSON numbers (null where not finite)."""
    array = np.asarray(values, dtype=np.float64)
    if array.ndim == 0:
        return json_number(array)  # type: ignore[return-value]
    return [_nums(v) for v in array]


def _warnings(warnings: Sequence[Any]) -> list[dict[str, str]]:
    return [{"rule": w.rule, "field": w.field, "message": w.message} for w in warnings]


def _stress_sections(t: TorsionResult) -> list[int]:
    """The sections (0-based) with a diameter."""
    return [j for j, f in enumerate(t.stress_factor) if math.isfinite(float(f))]


def _loaded_section(t: TorsionResult) -> tuple[int, bool]:
    """The most loaded section (0-based) over the speeds: by its synthesised stress where
    sections have a diameter, else by its synthesised torque; and whether by stress."""
    syn = t.section_torque_synthesis
    assert syn is not None
    stressed = _stress_sections(t)
    if stressed:
        stress = t.section_stress_synthesis
        assert stress is not None
        j = max(stressed, key=lambda s: float(np.max(stress[s])))
        return j, True
    return int(np.argmax(np.max(syn, axis=1))), False


# --------------------------------------------------------------------------- JSON


def _torsion_json(t: TorsionResult, warnings: Sequence[Any] | None = None) -> dict[str, Any]:
    """The torsion object of docs/torsion.md without ``schema`` and ``layout``: speeds,
    orders, masses, sections, dampers, excitation, modes, vector sums, resonances, response
    (``None`` undamped) and warnings (the part's own unless given)."""
    train = t.train
    exc = t.excitation
    masses = [
        {
            "number": i + 1,
            "name": m.name,
            "inertia_kgm2": json_number(t.inertias[i]),
            "cylinders": list(m.cylinders),
            "damping_Nms_per_rad": json_number(m.damping),
        }
        for i, m in enumerate(train.masses)
    ]
    sections = [
        {
            "number": j + 1,
            "between": [j + 1, j + 2],
            "stiffness_Nm_per_rad": json_number(s.stiffness),
            "damping_Nms_per_rad": json_number(s.damping),
            "diameter_m": None if s.diameter is None else json_number(s.diameter),
            "bore_m": json_number(s.bore),
        }
        for j, s in enumerate(train.sections)
    ]
    dampers = [
        {
            "number": r + 1,
            "at": d.at,
            "type": d.kind,
            "inertia_kgm2": json_number(d.inertia),
            "stiffness_Nm_per_rad": json_number(d.stiffness),
            "damping_Nms_per_rad": json_number(d.damping),
            "own_frequency_Hz": json_number(d.own_frequency) if d.kind == "tuned" else None,
        }
        for r, d in enumerate(train.dampers)
    ]
    return {
        "cycle": t.cycle,
        "speed_rpm": _rpm(t.speeds),
        "orders": [order_value(k) for k in t.orders],
        "loss_factor": json_number(train.loss_factor),
        "masses": masses,
        "sections": sections,
        "dampers": dampers,
        "excitation": _excitation_json(t, exc),
        "modes": [
            {
                "mode": j + 1,
                "frequency_Hz": json_number(f),
                "shape": _nums(t.shapes[j]),
            }
            for j, f in enumerate(t.frequencies)
        ],
        "stations": list(t.stations),
        "vector_sums": [
            {
                "mode": j + 1,
                "order": order_value(k),
                "relative_amplitude_sum": json_number(t.vector_sums[j, i]),
            }
            for j in range(t.frequencies.size)
            for i, k in enumerate(t.orders)
        ],
        "major_orders": [
            order_value(k) for k, major in zip(t.orders, t.major, strict=True) if major
        ],
        "resonances": [
            {
                "mode": r.mode,
                "order": order_value(r.order),
                "speed_rpm": speed_rpm(r.speed),
                "relative_amplitude_sum": json_number(r.vector_sum),
                "free_end_deg": None
                if r.free_end is None
                else json_number(math.degrees(r.free_end)),
                "section": r.section,
                "section_torque_Nm": None
                if r.section_torque is None
                else json_number(r.section_torque),
            }
            for r in t.resonances
        ],
        "response": _response_json(t) if t.damped else None,
        "warnings": _warnings(t.warnings if warnings is None else warnings),
    }


def _excitation_json(t: TorsionResult, exc: Any) -> dict[str, Any]:
    cylinders = []
    for c in range(exc.firing_tdc.size):
        orders = []
        for i, k in enumerate(exc.orders):
            entry: dict[str, Any] = {"order": order_value(k)}
            if exc.gas is not None:
                entry["gas"] = {
                    "amplitude_Nm": json_number(abs(exc.gas[c, i])),
                    "phase_deg": json_number(phase_deg(exc.gas[c, i])),
                }
            entry["inertia"] = {
                "amplitude_Nm": json_number(abs(exc.inertia[c, i])),
                "phase_deg": json_number(phase_deg(exc.inertia[c, i])),
            }
            if exc.tangential_pressure is not None:
                entry["tangential_pressure_bar"] = json_number(exc.tangential_pressure[c, i] / 1e5)
            orders.append(entry)
        cylinders.append(
            {
                "number": c + 1,
                "mass": int(t.cylinder_mass[c]) + 1,
                "firing_tdc_deg": json_number(exc.firing_tdc[c]),
                "moving_inertia_kgm2": json_number(t.moving_inertia[c]),
                "orders": orders,
            }
        )
    return {"reference_speed_rpm": speed_rpm(t.reference_speed), "cylinders": cylinders}


def _response_json(t: TorsionResult) -> dict[str, Any]:
    assert t.free_end is not None and t.free_end_synthesis is not None
    torque = t.section_torque
    torque_syn = t.section_torque_synthesis
    stress = t.section_stress
    stress_syn = t.section_stress_synthesis
    power = t.damper_power
    total = t.damper_power_total
    assert torque is not None and torque_syn is not None
    assert stress is not None and stress_syn is not None
    assert power is not None and total is not None
    sections = []
    for j, factor in enumerate(t.stress_factor):
        sections.append(
            {
                "number": j + 1,
                "torque_Nm": {
                    "amplitude": _nums(np.abs(torque[j])),
                    "synthesis": _nums(torque_syn[j]),
                },
                "stress_MPa": {
                    "amplitude": _nums(stress[j] / 1e6),
                    "synthesis": _nums(stress_syn[j] / 1e6),
                }
                if math.isfinite(float(factor))
                else None,
            }
        )
    return {
        "free_end_deg": {
            "amplitude": _nums(np.degrees(np.abs(t.free_end))),
            "phase_deg": _nums(phase_deg(t.free_end)),
            "synthesis": _nums(np.degrees(t.free_end_synthesis)),
        },
        "sections": sections,
        "dampers": [
            {"number": r + 1, "power_W": {"orders": _nums(power[r]), "total": _nums(total[r])}}
            for r in range(power.shape[0])
        ],
    }


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``torsion``, the ``balance.torsion/1``
    object without ``schema`` (``layout``, then :func:`_torsion_json`) at the speeds
    analysed, with the part's own warnings.

    Parameters
    ----------
    result : Result
        An analysis with the ``torsion`` section.

    Returns
    -------
    dict
        ``{"torsion": {"layout": ..., ...}}`` (docs/torsion.md).
    """
    return {"torsion": {"layout": result.engine.name, **_torsion_json(_part(result))}}


def torsion_document(result: Result) -> dict[str, Any]:
    """The ``balance.torsion/1`` document of ``balance torsion --format json``: ``schema``,
    ``layout``, then :func:`_torsion_json` with every warning of the result.

    Parameters
    ----------
    result : Result
        An analysis with the ``torsion`` section.

    Returns
    -------
    dict
        The document as plain data (speeds in rpm, angles in degrees; null where a
        number is not finite, and the response null for a train without damping).
    """
    return {
        "schema": SCHEMA,
        "layout": result.engine.name,
        **_torsion_json(_part(result), result.warnings),
    }


def torsion_text(result: Result, indent: int | None = 2) -> str:
    """The ``balance.torsion/1`` document as JSON text.

    Parameters
    ----------
    result : Result
        An analysis with the ``torsion`` section.
    indent : int or None
        Indentation of the JSON text [spaces]; None: one line.

    Returns
    -------
    str
        :func:`torsion_document` as JSON, ending in a newline.
    """
    return json.dumps(torsion_document(result), indent=indent, allow_nan=False) + "\n"


def torsion_csv(result: Result) -> str:
    """One row per speed: the free-end synthesis [deg], each section's torque synthesis
    [N m] and each damper's total power [W] (empty cells undamped).

    Parameters
    ----------
    result : Result
        An analysis with the ``torsion`` section.

    Returns
    -------
    str
        CSV text: a header (``speed_rpm``, ``free_end_deg``, ``section_j_torque_Nm``,
        ``damper_r_power_W``), then one line per speed [rpm], each line ending in a
        newline.
    """
    t = _part(result)
    n_sec, n_damp = t.stress_factor.size, len(t.train.dampers)
    head = ["speed_rpm", "free_end_deg"]
    head += [f"section_{j + 1}_torque_Nm" for j in range(n_sec)]
    head += [f"damper_{r + 1}_power_W" for r in range(n_damp)]
    rows = [",".join(head)]
    for s, rpm in enumerate(_rpm(t.speeds)):
        cells = [f"{rpm:.12g}"]
        if t.damped:
            assert t.free_end_synthesis is not None and t.section_torque_synthesis is not None
            total = t.damper_power_total
            assert total is not None
            cells.append(f"{math.degrees(float(t.free_end_synthesis[s])):.6g}")
            cells += [f"{float(t.section_torque_synthesis[j, s]):.6g}" for j in range(n_sec)]
            cells += [f"{float(total[r, s]):.6g}" for r in range(n_damp)]
        else:
            cells += [""] * (1 + n_sec + n_damp)
        rows.append(",".join(cells))
    return "\n".join(rows) + "\n"


# --------------------------------------------------------------------------- tables


def _largest_sums(t: TorsionResult, j: int, count: int = 3) -> str:
    order = np.argsort(-t.vector_sums[j], kind="stable")[:count]
    return ", ".join(
        f"{order_value(t.orders[i])}: {format_number(float(t.vector_sums[j, i]), 3)}" for i in order
    )


def tables(result: Result) -> list[RenderableType]:
    """The section's tables (:func:`_torsion_tables`).

    Parameters
    ----------
    result : Result
        An analysis with the ``torsion`` section.

    Returns
    -------
    list of rich.console.RenderableType
        The layout's name; the masses and sections; the modes with their largest vector
        sums; the resonances; the synthesis against (a thinned list of) the speeds, or
        without damping a line saying the response is not given; then the warnings.
    """
    return _torsion_tables(_part(result), str(result.engine.name))


def _shown_speeds(size: int) -> tuple[list[int], int]:
    step = max(1, math.ceil(size / TABLE_SPEEDS))
    shown = list(range(0, size, step))
    if shown[-1] != size - 1:
        shown.append(size - 1)  # the top speed is always a row
    return shown, step


def _torsion_tables(t: TorsionResult, layout: str = "") -> list[RenderableType]:
    """The masses and sections; the modes with their largest vector sums; the resonances;
    the free-end and largest-stress synthesis over (a thinned list of) the speeds."""
    from rich.text import Text

    from balance.views.fitted import Column, NumberTable

    parts: list[RenderableType] = []
    if layout:
        parts.append(Text(layout, style="bold"))
    parts.append(_masses_table(t))
    parts.append(
        NumberTable(
            "Torsional modes (undamped; rigid-body mode left out)",
            [
                Column("mode", key=True),
                Column("f", "Hz"),
                Column("largest vector sums (order: sum)", justify="left"),
            ],
            [
                [str(j + 1), format_number(float(f)), _largest_sums(t, j)]
                for j, f in enumerate(t.frequencies)
            ],
        )
    )
    parts.append(_resonance_table(t))
    if not t.damped:
        parts.append(Text("No damping: the response is unbounded at every resonance, not given."))
        parts += [Text(w.message) for w in t.warnings if w.rule != "torsion_damping"]
        return parts
    parts.append(_speed_table(t))
    parts += [Text(f"warning: {w.message}") for w in t.warnings]
    return parts


def _masses_table(t: TorsionResult) -> Any:
    from balance.views.fitted import Column, NumberTable

    rows = []
    sections = t.train.sections
    for i, m in enumerate(t.train.masses):
        shaft = sections[i] if i < len(sections) else None
        rows.append(
            [
                str(i + 1),
                m.name,
                format_number(float(t.inertias[i])),
                " ".join(map(str, m.cylinders)) or "-",
                "-" if shaft is None else format_number(shaft.stiffness),
                "-"
                if shaft is None or shaft.diameter is None
                else format_number(1e3 * shaft.diameter),
            ]
        )
    damper_notes = [
        f"damper {r + 1} ({d.kind}) at mass {d.at}: ring {format_number(d.inertia)} kg m^2"
        + (f", {format_number(d.stiffness)} N m/rad" if d.kind == "tuned" else "")
        + f", {format_number(d.damping)} N m s/rad"
        for r, d in enumerate(t.train.dampers)
    ]
    return NumberTable(
        "Mass-elastic table, free end first (inertia as used: moving parts added to a crank)",
        [
            Column("mass", key=True),
            Column("name", justify="left"),
            Column("inertia", "kg m^2"),
            Column("cylinders"),
            Column("shaft to next", "N m/rad"),
            Column("diameter", "mm"),
        ],
        rows,
        notes=damper_notes,
    )


def _resonance_table(t: TorsionResult) -> Any:
    from rich.text import Text

    from balance.views.fitted import Column, NumberTable

    if t.speeds.size == 1:
        return Text(
            "Resonances: one speed analysed, so none is looked for (balance torsion sweeps "
            "the speed range)."
        )
    if not t.resonances:
        return Text("No order meets a natural frequency in the speed range.")
    rows = []
    for r in t.resonances:
        torque = "-" if r.section_torque is None else format_number(r.section_torque)
        stress = "-"
        if r.section is not None and r.section_torque is not None:
            factor = float(t.stress_factor[r.section - 1])
            stress = (
                format_number(r.section_torque * factor / 1e6) if math.isfinite(factor) else "-"
            )
        rows.append(
            [
                str(r.mode),
                str(order_value(r.order)),
                format_number(speed_rpm(r.speed), 5),
                format_number(r.vector_sum, 3),
                "-" if r.free_end is None else format_number(math.degrees(r.free_end)),
                "-" if r.section is None else str(r.section),
                torque,
                stress,
            ]
        )
    columns = [
        Column("mode", key=True),
        Column("order", key=True),
        Column("speed", "rpm"),
        Column("vector sum"),
        Column("free end", "deg"),
        Column("section"),
        Column("torque", "N m"),
        Column("stress", "MPa"),
    ]
    if not _stress_sections(t):  # no section has a diameter: no stress column
        columns, rows = columns[:-1], [row[:-1] for row in rows]
    return NumberTable(
        "Resonances in the speed range: order k meets mode j at 60 f_j / k rpm", columns, rows
    )


def _speed_table(t: TorsionResult) -> Any:
    from balance.views.fitted import Column, NumberTable

    shown, step = _shown_speeds(t.speeds.size)
    j, by_stress = _loaded_section(t)
    assert t.free_end_synthesis is not None and t.section_torque_synthesis is not None
    stress = t.section_stress_synthesis
    total = t.damper_power_total
    columns = [
        Column("speed", "rpm", key=True),
        Column("free end", "deg"),
        Column(f"section {j + 1} torque", "N m"),
    ]
    if by_stress:
        columns.append(Column(f"section {j + 1} stress", "MPa"))
    columns += [Column(f"damper {r + 1} power", "W") for r in range(len(t.train.dampers))]
    rows = []
    rpm = _rpm(t.speeds)
    for s in shown:
        row = [
            format_number(rpm[s], 5),
            format_number(math.degrees(float(t.free_end_synthesis[s]))),
            format_number(float(t.section_torque_synthesis[j, s])),
        ]
        if by_stress:
            assert stress is not None
            row.append(format_number(float(stress[j, s]) / 1e6))
        if total is not None:
            row += [format_number(float(total[r, s])) for r in range(total.shape[0])]
        rows.append(row)
    notes = (
        [
            f"rows: one per {step} speeds and the top speed; all {t.speeds.size} with "
            "--format csv or json"
        ]
        if step > 1
        else []
    )
    return NumberTable(
        "Synthesis (half range over the cycle, all orders) against speed"
        + (f"; section {j + 1} carries the largest " + ("stress" if by_stress else "torque")),
        columns,
        rows,
        notes=notes,
    )


# --------------------------------------------------------------------------- figures


def _range_text(t: TorsionResult) -> str:
    rpm = _rpm(t.speeds)
    if len(rpm) == 1:
        return f"at {format_number(rpm[0], 5)} rpm"
    return f"{format_number(min(rpm), 5)}-{format_number(max(rpm), 5)} rpm"


def _not_computed(result: Result, kind: str, title: str | None, text: str) -> Figure:
    """A figure that says why there is no torsion to draw."""
    return placeholder(result, kind, title, text)


_ABSENT = "not computed: no torsion in this result (a layout with a torsion: section has it)"


def _labels(t: TorsionResult, width: float, height: float) -> list[tuple[float, float, str]]:
    """The resonances labelled in the Campbell diagram: the :data:`LABELLED` largest vector
    sums, each skipped where it would overlap one labelled before it."""
    placed: list[tuple[float, float, str]] = []
    for r in sorted(t.resonances, key=lambda r: -r.vector_sum):
        if len(placed) == LABELLED or r.vector_sum <= 0:
            break
        n_r, f_r = speed_rpm(r.speed), float(t.frequencies[r.mode - 1])
        if any(abs(n_r - n) < 0.07 * width and abs(f_r - f) < 0.04 * height for n, f, _ in placed):
            continue
        placed.append((n_r, f_r, f"{order_value(r.order)}: {format_number(r.vector_sum, 3)}"))
    return placed


def _plot_campbell(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``torsion_campbell``: the Campbell (interference) diagram, natural
    frequencies against crank speed with the order lines :math:`f = k n / 60` (major orders
    heavier) and each resonance in the speed range marked with its vector sum."""
    t = result.part("torsion")
    if t is None:
        return _not_computed(result, "torsion_campbell", title, _ABSENT)
    rpm = np.asarray(_rpm(t.speeds))
    low, high = float(rpm.min()), float(rpm.max())
    top_speed = 1.1 * high
    top_freq = float(np.max(t.orders)) * top_speed / 60.0
    with styled():
        fig, (ax,) = grid_figure(1, (9.0, 6.0))
        ax.axvspan(low, high, color="0.93", zorder=0, label="speed range")
        n = np.array([0.0, top_speed])
        for k, major in zip(t.orders, t.major, strict=True):
            ax.plot(
                n,
                k * n / 60.0,
                color="0.15" if major else "0.6",
                lw=1.6 if major else 0.6,
                zorder=1,
            )
            end = min(top_speed, top_freq * 60.0 / k)
            ax.annotate(
                str(order_value(k)),
                (end, k * end / 60.0),
                fontsize=7 if major else 6,
                color="0.15" if major else "0.5",
                ha="right",
                va="bottom",
            )
        shown = [j for j, f in enumerate(t.frequencies) if f <= top_freq]
        for j in shown:
            f = float(t.frequencies[j])
            ax.axhline(f, color=f"C{j % 10}", lw=1.2, label=f"mode {j + 1}: {format_number(f)} Hz")
        sums = np.array([r.vector_sum for r in t.resonances])
        largest = float(sums.max()) if sums.size else 1.0
        for r in t.resonances:
            size = 20.0 + 120.0 * (r.vector_sum / largest if largest > 0 else 0.0)
            ax.scatter(
                [speed_rpm(r.speed)],
                [float(t.frequencies[r.mode - 1])],
                s=size,
                color=f"C{(r.mode - 1) % 10}",
                zorder=3,
                edgecolor="k",
            )
        for n_r, f_r, text in _labels(t, top_speed, top_freq):
            ax.annotate(text, (n_r, f_r), textcoords="offset points", xytext=(3, 4), fontsize=7)
        hidden = len(t.frequencies) - len(shown)
        ax.set_xlim(0.0, top_speed)
        ax.set_ylim(0.0, top_freq)
        ax.set_xlabel("crank speed [rpm]")
        ax.set_ylabel("frequency [Hz]")
        note = f"; {hidden} mode{'s' if hidden != 1 else ''} above {top_freq:.0f} Hz not shown"
        ax.set_title(
            "order lines f = k n / 60 (heavy: major orders); dots: resonances, "
            "labelled order: vector sum" + (note if hidden else ""),
            fontsize=8,
        )
        ax.legend(loc="upper left", fontsize=7)
        default = f"{result.engine.name}: Campbell diagram, {_range_text(t)}"
        fig.suptitle(title_text(fig.get_figwidth(), title or default))
        return fig


def _plot_modes(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``torsion_modes``: the shapes of the lowest modes (undamped, +1 at mass 1)
    at the masses and the tuned rings."""
    t = result.part("torsion")
    if t is None:
        return _not_computed(result, "torsion_modes", title, _ABSENT)
    count = min(SHAPES_DRAWN, t.frequencies.size)
    with styled():
        fig, (ax,) = grid_figure(1, (9.0, 5.0))
        x = np.arange(1, len(t.stations) + 1)
        for j in range(count):
            ax.plot(
                x,
                t.shapes[j],
                "o-",
                color=f"C{j % 10}",
                label=f"mode {j + 1}: {format_number(float(t.frequencies[j]))} Hz",
            )
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_xticks(x)
        ax.set_xticklabels(t.stations, rotation=40, ha="right", fontsize=8)
        rings = len(t.stations) - len(t.train.masses)
        ax.set_xlabel(
            "mass (free end first), then the tuned damper rings"
            if rings
            else "mass (free end first)"
        )
        ax.set_ylabel("relative amplitude [1] (+1 at mass 1)")
        if count:
            ax.legend(fontsize=8)
        shown = (
            f"the lowest {count} of {t.frequencies.size} modes"
            if count < t.frequencies.size
            else "torsional mode shapes"
        )
        default = f"{result.engine.name}: {shown} (undamped; the same at every speed)"
        fig.suptitle(title_text(fig.get_figwidth(), title or default))
        return fig


def _plot_response(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``torsion_response``: against crank speed, the free end's angle and the
    most loaded section's stress (its torque when no section has a diameter), per order
    (thin) and synthesised (heavy: half range over the cycle)."""
    t = result.part("torsion")
    if t is None:
        return _not_computed(result, "torsion_response", title, _ABSENT)
    if not t.damped:
        return _not_computed(
            result,
            "torsion_response",
            title,
            "not computed: the torsion train has no damping, so its response is unbounded "
            "at every resonance",
        )
    assert t.free_end is not None and t.free_end_synthesis is not None
    assert t.section_torque is not None and t.section_torque_synthesis is not None
    rpm = np.asarray(_rpm(t.speeds))
    j, by_stress = _loaded_section(t)
    if by_stress:
        per_order = np.abs(t.section_torque[j]) * t.stress_factor[j] / 1e6
        synthesis = t.section_torque_synthesis[j] * t.stress_factor[j] / 1e6
        label = f"section {j + 1} nominal shear stress [MPa]"
    else:
        per_order = np.abs(t.section_torque[j])
        synthesis = t.section_torque_synthesis[j]
        label = f"section {j + 1} torque [N m]"
    panels = (
        (np.degrees(np.abs(t.free_end)), np.degrees(t.free_end_synthesis), "free-end angle [deg]"),
        (per_order, synthesis, label),
    )
    marker = "o" if rpm.size == 1 else None
    with styled():
        fig, axes = grid_figure(2, (9.0, 7.5))
        for ax, (values, total, ylabel) in zip(axes, panels, strict=True):
            peaks = np.max(values, axis=1) if values.size else np.zeros(0)
            largest = float(np.max(peaks)) if peaks.size else 0.0
            drawn = [
                int(i)
                for i in np.argsort(-peaks, kind="stable")[:ORDERS_NAMED]
                if largest > 0 and peaks[i] >= DRAWN_SHARE * largest
            ]
            others = [i for i in range(t.orders.size) if i not in drawn and peaks[i] > 0]
            for n, i in enumerate(others):
                ax.plot(
                    rpm,
                    values[i],
                    lw=0.6,
                    marker=marker,
                    color="0.7",
                    label=f"{len(others)} other orders" if n == 0 else None,
                )
            for rank, i in enumerate(sorted(drawn, key=lambda i: float(t.orders[i]))):
                ax.plot(
                    rpm,
                    values[i],
                    lw=1.8 if t.major[i] else 1.0,
                    marker=marker,
                    color=f"C{rank % 10}",
                    label=f"order {order_value(t.orders[i])}",
                )
            ax.plot(rpm, total, color="k", lw=2.2, marker=marker, label="synthesis")
            ax.set_ylabel(ylabel)
            ax.set_xlabel("crank speed [rpm]")
            ax.set_ylim(bottom=0.0)
            ax.legend(fontsize=7, ncols=3, loc="upper left")
        what = "gas and inertia" if t.excitation.gas is not None else "inertia only"
        default = f"{result.engine.name}: torsional response, {_range_text(t)} ({what})"
        fig.suptitle(title_text(fig.get_figwidth(), title or default))
        return fig


#: The figure kinds of the section.
PLOTS: dict[str, Callable[..., Figure]] = {
    "torsion_campbell": _plot_campbell,
    "torsion_modes": _plot_modes,
    "torsion_response": _plot_response,
}


# --------------------------------------------------------------------------- report


#: The heading of the section in the HTML report.
REPORT_TITLE = "Torsional vibration of the crank train"


def report_section(result: Result, figures: bool) -> str:
    """HTML of the report's torsion section: the masses, the modes, the resonances and the
    synthesis against speed, with the three figures.

    Parameters
    ----------
    result : Result
        An analysis with the ``torsion`` section.
    figures : bool
        Include the three figures (inline SVG).

    Returns
    -------
    str
        HTML of the section's body (the synthesis table only for a damped train).
    """
    from balance.views.report import escape, html_figure, html_table

    t = _part(result)
    masses = html_table(
        ["mass", "name", "inertia [kg m^2]", "cylinders", "shaft to next [N m/rad]"],
        [
            [
                str(i + 1),
                m.name,
                format_number(float(t.inertias[i])),
                " ".join(map(str, m.cylinders)) or "-",
                format_number(m.shaft.stiffness) if m.shaft is not None else "-",
            ]
            for i, m in enumerate(t.train.masses)
        ],
        "Mass-elastic table, free end first (inertia as used)",
    )
    modes = html_table(
        ["mode", "frequency [Hz]", "largest vector sums (order: sum)"],
        [
            [str(j + 1), format_number(float(f)), _largest_sums(t, j)]
            for j, f in enumerate(t.frequencies)
        ],
        "Torsional modes (undamped)",
    )
    resonances = html_table(
        ["mode", "order", "speed [rpm]", "vector sum", "free end [deg]", "section", "torque [N m]"],
        [
            [
                str(r.mode),
                str(order_value(r.order)),
                format_number(speed_rpm(r.speed), 5),
                format_number(r.vector_sum, 3),
                "-" if r.free_end is None else format_number(math.degrees(r.free_end)),
                "-" if r.section is None else str(r.section),
                "-" if r.section_torque is None else format_number(r.section_torque),
            ]
            for r in t.resonances
        ],
        "Resonances in the speed range",
    )
    text = (
        "Mass-elastic model from the free end to the driven end; steady state of every "
        "order at every speed solved exactly (docs/torsion.md). "
        + (
            "The inertia excitation scales with speed squared; the gas torque is the same "
            "pressure trace at every speed."
            if t.excitation.gas is not None
            else "Excitation by the moving parts only (no gas: section)."
        )
    )
    html = f"<p>{escape(text)}</p>\n{masses}\n{modes}\n{resonances}"
    if t.damped:
        shown, _ = _shown_speeds(t.speeds.size)
        assert t.free_end_synthesis is not None and t.section_torque_synthesis is not None
        j, _ = _loaded_section(t)
        rpm = _rpm(t.speeds)
        html += "\n" + html_table(
            ["speed [rpm]", "free end [deg]", f"section {j + 1} torque [N m]"],
            [
                [
                    format_number(rpm[s], 5),
                    format_number(math.degrees(float(t.free_end_synthesis[s]))),
                    format_number(float(t.section_torque_synthesis[j, s])),
                ]
                for s in shown
            ],
            "Synthesis against speed (half range over the cycle)",
        )
    else:
        html += "\n<p>" + escape("No damping: the response is not computed.") + "</p>"
    if figures:
        html += "\n" + "\n".join(
            html_figure(result, kind, caption, 100 + n)
            for n, (kind, caption) in enumerate(
                (
                    ("torsion_campbell", "Campbell diagram"),
                    ("torsion_modes", "Torsional mode shapes"),
                    ("torsion_response", "Free-end angle and section stress against speed"),
                )
            )
        )
    return html
