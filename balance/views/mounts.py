"""Views of the ``mounts`` section, the engine on its mounts (docs/mounts.md): JSON,
tables, figure, report.

Everything here reads a :class:`~balance.core.mounts.MountsResult` (the section's part, or
its speed sweep from :func:`balance.core.mounts.speed_sweep`).  Amplitudes are magnitudes of
complex amplitudes; the "largest force" of a mount is the largest magnitude of its force
vector over a cycle (:func:`balance.core.mounts.peak_force`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.mounts import COORDINATES, MountsResult
from balance.views.figures import layout_heading
from balance.views.fitted import Column, NumberTable
from balance.views.polar import format_number, json_number, order_value, zero_below_rounding

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure
    from rich.console import RenderableType

    from balance.core.mount_loads import MountsPart
    from balance.core.result import Result

__all__ = [
    "PLOTS",
    "REPORT_TITLE",
    "json_block",
    "plot_mount_sweep",
    "report_section",
    "sweep_csv",
    "sweep_json",
    "sweep_tables",
    "tables",
]


#: What loads the block on its mounts (the note under the response tables, and the figure).
LOADS_NOTE = "loads: the free forces and moments (reciprocating + rotating) and the roll"

#: rad/s to rpm as one factor: 800 rpm prints as 800.0 (speed * 60 / (2 pi) gives
#: 799.9999999999999, so the sweep's speeds stay as they were written)
RPM = 30.0 / math.pi


def _share(value: float) -> str:
    """A percentage of energy, 0 where it is within the rounding of the shares, which add
    up to 100 % over six coordinates (:func:`balance.views.polar.zero_below_rounding`)."""
    return format_number(float(zero_below_rounding(value, 100.0, 6)), 3)


def _printed_response(m: MountsResult) -> tuple[np.ndarray, np.ndarray]:
    r"""The response amplitudes as the tables print them: the CG's translations [m] and
    the rotations [rad] of each order, 0 where they cannot be told from zero.

    The rule of every view (:func:`balance.views.polar.zero_below_rounding`, six terms)
    with one scale per order: the largest motion of that order, a rotation counted at
    :math:`L`, the farthest mount's distance from the CG (a rotation of :math:`\phi`
    moves that mount by :math:`\phi L`): a translation is 0 at most
    :math:`64 \cdot 6\,\varepsilon S` and a rotation at most that over :math:`L`."""
    translation, rotation = m.translation, m.rotation
    reach = float(np.max(np.linalg.norm(m.system.offsets, axis=-1), initial=0.0))
    reach = reach if reach > 0.0 else 1.0
    scale = np.maximum(
        np.max(translation, axis=-1, initial=0.0), reach * np.max(rotation, axis=-1, initial=0.0)
    )[..., None]
    return (
        zero_below_rounding(translation, scale, 6),
        zero_below_rounding(rotation, scale / reach, 6),
    )


def _excited(m: MountsResult) -> np.ndarray:
    """Which orders load the mounts at some speed of ``m`` (an order whose loads are zero,
    a balanced engine's first order say, crosses no mode: it excites none)."""
    largest = np.asarray(m.largest_force).reshape(-1, m.orders.size)
    return np.asarray(np.any(largest > 0.0, axis=0))


# ---------------------------------------------------------------------------------------
# JSON


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``mounts``.

    Parameters
    ----------
    result : Result
        An analysis with the ``mounts`` section.

    Returns
    -------
    dict
        ``{"mounts": ...}`` (docs/conventions.md, "The engine on its mounts").
    """
    return {"mounts": _mounts_json(_part(result).response)}


def _mounts_json(m: MountsResult) -> dict[str, Any]:
    """The ``mounts`` block of the analysis JSON (docs/mounts.md), with extras."""
    modes = [
        {
            "frequency_Hz": json_number(m.modes.frequency[j]),
            "energy_share": {
                c: json_number(m.modes.energy_share[j, i]) for i, c in enumerate(COORDINATES)
            },
        }
        for j in range(6)
    ]
    translation, rotation, forces = m.translation, m.rotation, m.force_amplitude
    peak = m.force_peak
    response = [
        {
            "order": order_value(k),
            "cg_translation_m": [json_number(v) for v in translation[i]],
            "rotation_rad": [json_number(v) for v in rotation[i]],
            "mount_forces_N": [
                [json_number(v) for v in forces[i, n]] for n in range(forces.shape[1])
            ],
            "mount_force_peak_N": [json_number(v) for v in peak[i]],
        }
        for i, k in enumerate(m.orders)
    ]
    return {
        "modes": modes,
        "response": response,
        "with_proposal": bool(m.with_proposal),
        "gas": bool(m.gas),
        "torque_roll_axis": [json_number(v) for v in m.roll_axis],
        "mounts": [
            {
                "position_m": [json_number(v) for v in m.system.positions[n]],
                "distance_to_torque_roll_axis_m": json_number(m.axis_distance[n]),
                "elastic_axis_offsets_m": [json_number(v) for v in m.elastic_offsets[n]],
            }
            for n in range(m.system.n_mounts)
        ],
    }


def _crossings(m: MountsResult) -> list[tuple[float, int, float]]:
    """The mode crossings (:meth:`MountsResult.mode_crossings`) of the orders that load
    the mounts (:func:`_excited`)."""
    excited = {float(k) for k, e in zip(m.orders, _excited(m), strict=True) if e}
    return [c for c in m.mode_crossings() if float(c[0]) in excited]


def _crossing_entries(m: MountsResult) -> list[dict[str, Any]]:
    """Which order crosses which mode at which speed, within a sweep's speed range (the
    orders that load the mounts only)."""
    return [
        {
            "order": order_value(k),
            "mode": j + 1,
            "frequency_Hz": json_number(m.modes.frequency[j]),
            "speed_rpm": json_number(w * RPM),
        }
        for k, j, w in _crossings(m)
    ]


def sweep_json(m: MountsResult, layout: str) -> dict[str, Any]:
    """A speed sweep (``balance mounts``) as plain data: the largest mount force per order
    and speed, the modes and the crossings.

    Parameters
    ----------
    m : MountsResult
        The response over a range of speeds (:func:`balance.core.mounts.speed_sweep`).
    layout : str
        The layout's name.

    Returns
    -------
    dict
        Plain data for ``json.dumps`` (speeds [rpm], forces [N], frequencies [Hz]).
    """
    largest = m.largest_force  # (S, K)
    return {
        "schema": "balance.mounts_sweep/1",
        "layout": layout,
        "with_proposal": bool(m.with_proposal),
        "gas": bool(m.gas),
        "speed_rpm": [json_number(w * RPM) for w in m.speed],
        "orders": [order_value(k) for k in m.orders],
        "modes": _mounts_json(_at_first(m))["modes"],
        "largest_mount_force_N": [[json_number(v) for v in row] for row in largest.T],
        "crossings": _crossing_entries(m),
    }


def _at_first(m: MountsResult) -> MountsResult:
    from dataclasses import replace

    if m.response.ndim == 2:
        return m
    return replace(
        m, speed=m.speed[0], loads=m.loads[0], response=m.response[0], forces=m.forces[0]
    )


def sweep_csv(m: MountsResult) -> str:
    """A speed sweep as CSV: speed, then the largest mount force of each order.

    Parameters
    ----------
    m : MountsResult
        The response over a range of speeds.

    Returns
    -------
    str
        One row per speed: the speed [rpm] and each order's largest mount force [N].
    """
    head = "speed_rpm," + ",".join(f"order_{order_value(k)}_N" for k in m.orders)
    rows = [
        f"{w * RPM:.6g}," + ",".join(f"{v:.6g}" for v in row)
        for w, row in zip(m.speed, m.largest_force, strict=True)
    ]
    return "\n".join([head, *rows]) + "\n"


# ---------------------------------------------------------------------------------------
# tables


def _modes_table(m: MountsResult) -> NumberTable:
    rows = []
    for j in range(6):
        f = float(m.modes.frequency[j])
        shares = [_share(100 * float(v)) for v in m.modes.energy_share[j]]
        rows.append([str(j + 1), format_number(f), format_number(60 * f), *shares])
    return NumberTable(
        "Rigid-body modes on the mounts (undamped): frequency f, energy shares",
        [
            Column("mode", key=True),
            Column("f", "Hz"),
            Column("order 1 at", "rpm"),
            *(Column(c, "%") for c in COORDINATES),
        ],
        rows,
    )


def tables(result: Result) -> list[RenderableType]:
    """The section's tables: the modes with their energy shares, the response per order, the
    torque-roll axis and each mount's distance from it.

    Parameters
    ----------
    result : Result
        An analysis with the ``mounts`` section.

    Returns
    -------
    list of rich.console.RenderableType
    """
    return _mounts_tables(_part(result).response)


def _mounts_tables(m: MountsResult) -> list[RenderableType]:
    """Modes with energy shares, the response per order, the torque-roll axis and each
    mount's distance from it."""
    from rich.text import Text

    parts: list[RenderableType] = [_modes_table(m)]
    what = "with the proposal" if m.with_proposal else "without balancing masses"
    peak = m.force_peak
    translation, rotation = _printed_response(m)
    rows = []
    for i, k in enumerate(m.orders):
        cells = [format_number(1e3 * float(v)) for v in translation[i]]
        cells += [format_number(1e3 * float(v)) for v in rotation[i]]
        n = int(np.argmax(peak[i]))
        where = str(n + 1) if peak[i, n] > 0.0 else "-"
        rows.append([str(order_value(k)), *cells, format_number(float(peak[i, n])), where])
    parts.append(
        NumberTable(
            f"Response on the mounts per order ({what}"
            + (", with the gas torque" if m.gas else "")
            + ")",
            [
                Column("order", key=True),
                Column("CG x", "mm"),
                Column("CG y", "mm"),
                Column("CG z", "mm"),
                Column("rx", "mrad"),
                Column("ry", "mrad"),
                Column("rz", "mrad"),
                Column("largest mount force", "N"),
                Column("at mount"),
            ],
            rows,
            notes=(LOADS_NOTE,),
        )
    )
    axis = zero_below_rounding(m.roll_axis, 1.0, 3)
    tilt = math.degrees(math.acos(min(1.0, abs(float(axis[2])))))
    parts.append(
        Text(f"Torque-roll axis (TRA) through the CG along [{', '.join(f'{v:.4f}' for v in axis)}]")
    )
    parts.append(Text(f"TRA {tilt:.1f} deg from the crank axis"))
    parts.append(
        NumberTable(
            "Mounts and the torque-roll axis (TRA)",
            [
                Column("mount", key=True),
                Column("x", "mm"),
                Column("y", "mm"),
                Column("z", "mm"),
                Column("distance to TRA", "mm"),
                Column("axis 1 off TRA", "mm"),
                Column("axis 2 off TRA", "mm"),
                Column("axis 3 off TRA", "mm"),
            ],
            [
                [
                    str(n + 1),
                    *(format_number(1e3 * float(v)) for v in m.system.positions[n]),
                    format_number(1e3 * float(m.axis_distance[n])),
                    *(format_number(1e3 * float(v)) for v in m.elastic_offsets[n]),
                ]
                for n in range(m.system.n_mounts)
            ],
        )
    )
    return parts


def sweep_tables(m: MountsResult, layout: str) -> list[RenderableType]:
    """A speed sweep: the modes, the largest mount force per order against speed (a row
    every few speeds), and the crossings.

    Parameters
    ----------
    m : MountsResult
        The response over a range of speeds.
    layout : str
        The layout's name, for the titles.

    Returns
    -------
    list of rich.console.RenderableType
    """
    from rich.text import Text

    what = "with the proposal" if m.with_proposal else "without balancing masses"
    parts: list[RenderableType] = [
        Text(str(layout), style="bold"),
        Text(f"On its mounts, {what}"),
        _modes_table(m),
    ]
    step = max(1, m.speed.size // 25)
    shown = list(range(0, m.speed.size, step))
    if shown[-1] != m.speed.size - 1:
        shown.append(m.speed.size - 1)  # the top speed is always a row
    notes = (
        [
            f"rows: one per {step} speeds and the top speed; all {m.speed.size} with "
            "--format csv or json"
        ]
        if step > 1
        else []
    )
    largest = m.largest_force
    parts.append(
        NumberTable(
            "Largest mount force against speed, per order",
            [
                Column("speed", "rpm", key=True),
                *(Column(f"order {order_value(k)}", "N") for k in m.orders),
            ],
            [
                [
                    format_number(float(m.speed[s]) * RPM, 5),
                    *(format_number(float(v)) for v in largest[s]),
                ]
                for s in shown
            ],
            notes=notes,
        )
    )
    found = _crossing_entries(m)
    if found:
        parts.append(
            NumberTable(
                "Orders crossing modes in the speed range",
                [
                    Column("order", key=True),
                    Column("mode"),
                    Column("frequency", "Hz"),
                    Column("speed", "rpm"),
                ],
                [
                    [
                        str(c["order"]),
                        str(c["mode"]),
                        format_number(c["frequency_Hz"]),
                        format_number(c["speed_rpm"], 5),
                    ]
                    for c in found
                ],
            )
        )
    else:
        parts.append(Text("No order that loads the mounts crosses a mode in the speed range."))
    if m.gas:
        parts.append(
            Text(
                "With gas: the inertia loads scale with speed squared; the gas torque is "
                "the same pressure trace at every speed."
            )
        )
    return parts


# ---------------------------------------------------------------------------------------
# figure


def _part(result: Result) -> MountsPart:
    part: MountsPart = result.part("mounts")
    return part


def plot_mount_sweep(m: MountsResult, *, title: str | None = None, layout: str = "") -> Figure:
    """Largest mount force of each order against speed, with each order's mode crossings
    (dotted lines at 60 f_j / k rpm) and the mode frequencies in the legend.

    Parameters
    ----------
    m : MountsResult
        The response over a range of speeds.
    title : str, optional
        The figure's title; default one naming the layout.
    layout : str
        The layout's name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 5.0), layout="constrained")
    ax = fig.subplots()
    rpm = np.asarray(m.speed) * RPM
    largest = m.largest_force
    for i, k in enumerate(m.orders):
        if np.max(largest[:, i]) <= 0:
            continue
        ax.semilogy(rpm, largest[:, i], label=f"order {order_value(k)}", color=f"C{i % 10}")
    _crossing_marks(ax, m, rpm)
    modes = ", ".join(f"{f:.3g}" for f in m.modes.frequency)
    ax.set_xlabel("crank speed [rpm]")
    ax.set_ylabel("largest mount force [N]")
    ax.set_title(f"modes [Hz]: {modes}; dotted: order k meets mode j at 60 f_j / k rpm", fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="best", ncols=2, fontsize=8)
    what = "with the proposal" if m.with_proposal else "without balancing masses"
    import textwrap

    span = f"{format_number(float(rpm.min()), 5)}-{format_number(float(rpm.max()), 5)} rpm"
    text = (
        title
        if title is not None
        else f"{layout}: mount forces against speed, {span} ({what}; loads: free forces "
        "and moments, roll)"
    )
    fig.suptitle(textwrap.fill(text, 80))
    return fig


def _crossing_marks(ax: Any, m: MountsResult, rpm: np.ndarray) -> None:
    """A dotted line at each crossing of an order that loads the mounts (:func:`_crossings`)
    with its label ``k×mj`` at the top, in the order's colour; a label that would overlap
    the one before it goes one row lower."""
    low, high = float(rpm.min()), float(rpm.max())
    width = max(high - low, 1e-300)
    # a label's width as a share of the axes: 7 pt characters on 8 in wide axes, about
    label_share = 0.012
    rows: list[float] = []  # the right end (axes fraction) of the last label of each row
    for k, j, w in _crossings(m):
        i = int(np.searchsorted(m.orders, k))
        x = w * RPM
        ax.axvline(x, color=f"C{i % 10}", linestyle=":", linewidth=0.8)
        text = f"{order_value(k)}×m{j + 1}"
        start = (x - low) / width
        row = next((r for r, end in enumerate(rows) if start > end), len(rows))
        if row == len(rows):
            rows.append(0.0)
        rows[row] = start + label_share * (len(text) + 1)
        ax.annotate(
            text,
            (x, 1.0 - 0.05 * row),
            xycoords=("data", "axes fraction"),
            xytext=(2, -2),
            textcoords="offset points",
            fontsize=7,
            va="top",
            ha="left",
            color=f"C{i % 10}",
            bbox={"boxstyle": "square,pad=0.1", "facecolor": "white", "edgecolor": "none"},
            zorder=5,
        )
    if rows and ax.get_yscale() == "log":  # room above the curves for the rows of labels
        bottom, top = (math.log10(v) for v in ax.get_ylim())
        free = 1.0 - 0.05 * (len(rows) + 0.5)
        ax.set_ylim(top=10.0 ** (bottom + (top - bottom) / free))


def _plot_mounts(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``mounts``: mount force against speed (over the speeds the mounts section
    was asked for; the figure's are :func:`balance.core.mount_loads.figure_speeds`, 0.15 to
    1.3 times the analysis speed) with the mode lines.  Without mounts in the result, or
    without their speed sweep, the figure says so (like the other kinds without what they
    draw)."""
    part = result.part("mounts")
    if part is None or part.sweep is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(8.0, 5.0), layout="constrained")
        ax = fig.subplots()
        ax.set_axis_off()
        ax.text(
            0.5,
            0.5,
            "no mounts in this analysis: give a mounts: section or a mounts file"
            if part is None
            else "the mounts were analysed at one speed only: no speed sweep to draw",
            ha="center",
            va="center",
            transform=ax.transAxes,
        )
        fig.suptitle(title if title is not None else f"{layout_heading(result)}: mounts")
        return fig
    return plot_mount_sweep(part.sweep, title=title, layout=str(result.engine.name))


#: The figure kinds of the section.
PLOTS = {"mounts": _plot_mounts}


# ---------------------------------------------------------------------------------------
# report


#: The heading of the section in the HTML report.
REPORT_TITLE = "The engine on its mounts"


def report_section(result: Result, figures: bool) -> str:
    """HTML of the report's mounts section, with the mount-force figure.

    Parameters
    ----------
    result : Result
        An analysis with the ``mounts`` section.
    figures : bool
        Include the figure.

    Returns
    -------
    str
    """
    from balance.views.report import escape, html_figure, html_table

    html = _mounts_report_section(_part(result).response, html_table, escape)
    if figures:
        html += "\n" + html_figure(
            result, "mounts", "Largest mount force against speed, with the mode lines", 90
        )
    return html


def _mounts_report_section(m: MountsResult, table: Any, escape: Any) -> str:
    """HTML of the report's mounts section (``table(headers, rows, caption)`` and
    ``escape(text)`` are the report's own helpers)."""
    modes = table(
        ["mode", "frequency [Hz]", *(f"{c} [%]" for c in COORDINATES)],
        [
            [
                str(j + 1),
                format_number(float(m.modes.frequency[j])),
                *(_share(100 * float(v)) for v in m.modes.energy_share[j]),
            ]
            for j in range(6)
        ],
        "Rigid-body modes on the mounts (undamped) and their kinetic-energy shares",
    )
    peak = m.force_peak
    response = table(
        [
            "order",
            "CG x [mm]",
            "CG y [mm]",
            "CG z [mm]",
            "rx [mrad]",
            "ry [mrad]",
            "rz [mrad]",
            "largest mount force [N]",
        ],
        [
            [
                str(order_value(k)),
                *(format_number(1e3 * float(v)) for v in m.translation[i]),
                *(format_number(1e3 * float(v)) for v in m.rotation[i]),
                format_number(float(peak[i].max())),
            ]
            for i, k in enumerate(m.orders)
        ],
        "Response per order" + (" with the proposal" if m.with_proposal else ""),
    )
    mounts = table(
        ["mount", "x [mm]", "y [mm]", "z [mm]", "distance to torque-roll axis [mm]"],
        [
            [
                str(n + 1),
                *(format_number(1e3 * float(v)) for v in m.system.positions[n]),
                format_number(1e3 * float(m.axis_distance[n])),
            ]
            for n in range(m.system.n_mounts)
        ],
        "Mounts and the torque-roll axis",
    )
    axis = ", ".join(f"{v:.4f}" for v in m.roll_axis)
    text = escape(f"Torque-roll axis through the CG along [{axis}] (engine axes).")
    return f"<p>{text}</p>\n{modes}\n{response}\n{mounts}"
