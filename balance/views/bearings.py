"""Views of the ``bearings`` section: crank-pin and main-bearing loads
(:class:`balance.core.bearing_loads.Bearings`, docs/bearings.md).

Every function reads a :class:`~balance.core.result.Result` (or the loads of its section)
and nothing else: the JSON block, the rich tables, the three figures (crank-pin load in
the crank-fixed frame, each main's load in the engine frame, internal moment along the
crank), the report section and the side-by-side comparison of the two counterweight
strategies.  The Dataset variables are in the output catalogue
(:data:`balance.core.bearings.OUTPUTS`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.bearing_loads import GEAR_NOTE, Bearings
from balance.views.figures import grid_figure, layout_heading, placeholder, title_text
from balance.views.polar import format_number

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from rich.console import RenderableType

    from balance.core.result import Result

__all__ = [
    "PLOTS",
    "REPORT_TITLE",
    "json_block",
    "report_section",
    "tables",
]

#: What to add to an analysis for the bearing loads.
ASK = "ask for them (or give the layout a bearings: section)"


def _loads(result: Result) -> Bearings | None:
    """The loads of the result's section (None when it has none)."""
    part = result.part("bearings")
    return None if part is None else part.loads


def _mm(value: float) -> str:
    return f"{value * 1e3:.4g}"


def _rounding(b: Bearings) -> tuple[float, float, int]:
    """The scale [N] of the terms of every load of ``b``, the length [m] their moments' levers
    reach, and the number of terms (:func:`_printed`)."""
    scale = float(
        np.sum(b.pin_max)
        + np.max(b.main_max, initial=0.0)
        + np.max(b.main_max_with_proposal, initial=0.0)
    )
    span = float(np.ptp(np.concatenate([b.main_z, b.pin_z]))) if b.main_z.size else 0.0
    n = b.pin_z.size + len(b.counterweights) + 2
    return scale, span, n


def _printed(b: Bearings) -> dict[str, np.ndarray]:
    """The loads [N] and moments [N m] as tables and figures print them: what is below the
    rounding of their sums is 0 (:func:`balance.views.polar.zero_below_rounding`).

    Each main's load is a lever-rule sum of the throw loads (pin loads, crank unbalance and
    counterweights), so the scale of its terms is at most the sum of the largest pin loads
    and the largest main loads; a moment's terms are those loads times levers up to the
    length of the crank.
    """
    from balance.views.polar import zero_below_rounding

    scale, span, n = _rounding(b)
    out = {}
    for name in (
        "pin_max",
        "pin_mean",
        "main_max",
        "main_mean",
        "main_max_with_proposal",
        "main_mean_with_proposal",
    ):
        out[name] = zero_below_rounding(getattr(b, name), scale, n)
    for name in ("moment_max", "moment_max_with_proposal"):
        out[name] = zero_below_rounding(getattr(b, name), scale * span, n)
    return out


def _printed_curve(b: Bearings, load: np.ndarray) -> np.ndarray:
    """A load over the cycle [N, complex] as the figures draw it: each component 0 where it
    cannot be told from zero (the rule of :func:`_printed`)."""
    from balance.views.polar import zero_below_rounding

    scale, _, n = _rounding(b)
    return np.asarray(
        zero_below_rounding(load.real, scale, n) + 1j * zero_below_rounding(load.imag, scale, n)
    )


#: The columns of the main-bearing loads and of the internal moments, after number and z.
_LOADS = ("main_max", "main_mean", "main_max_with_proposal", "main_mean_with_proposal")
_MOMENTS = ("moment_max", "moment_max_with_proposal")


def _shaft_names(b: Bearings, which: np.ndarray | None) -> list[str] | None:
    """The crank axis's name of each pin or main (``which``: ``b.pin_axis`` or
    ``b.main_axis``), None with one crank."""
    if which is None:
        return None
    return [b.axis_names[int(a)] for a in which]


def _shaft_column(b: Bearings) -> list[Any]:
    """The tables' ``crankshaft`` column with several crank axes (none with one)."""
    from balance.views.fitted import Column

    return [] if b.pin_axis is None else [Column("crankshaft", justify="left")]


def _main_rows(b: Bearings, v: dict[str, np.ndarray], names: Sequence[str]) -> list[list[str]]:
    """One row of text per main (tables and report): number, (crankshaft,) z, then the
    _printed values ``v`` (:func:`_printed`) of ``names``, in that order."""
    shaft = _shaft_names(b, b.main_axis)
    return [
        [
            str(m + 1),
            *([] if shaft is None else [shaft[m]]),
            _mm(float(b.main_z[m])),
            *(format_number(float(v[name][m])) for name in names),
        ]
        for m in range(b.main_z.size)
    ]


def _pin_rows(b: Bearings, v: dict[str, np.ndarray], angle: bool) -> list[list[str]]:
    """One row of text per crank pin: number, z, cylinders, the _printed values ``v``
    (:func:`_printed`) of the largest load, its crank angle (with ``angle``) and the mean
    load."""
    rows = []
    shaft = _shaft_names(b, b.pin_axis)
    for j in range(b.pin_z.size):
        row = [
            str(j + 1),
            *([] if shaft is None else [shaft[j]]),
            _mm(float(b.pin_z[j])),
            " ".join(map(str, b.pin_cylinders[j])),
            format_number(float(v["pin_max"][j])),
        ]
        if angle:
            row.append(f"{round(math.degrees(float(b.pin_max_angle[j])), 1) % 360.0:.1f}")
        row.append(format_number(float(v["pin_mean"][j])))
        rows.append(row)
    return rows


# --------------------------------------------------------------------------- JSON


def _entry(value: Any) -> Any:
    """One value of a JSON record: a list of a tuple, a string as it is, else a float."""
    if isinstance(value, tuple):
        return list(value)
    return value if isinstance(value, str) else float(value)


def _records(columns: dict[str, Any]) -> list[dict[str, Any]]:
    """Rows of a JSON list from equal-length columns, in the order of the keys: numbers as
    ``float``, tuples (cylinder numbers) as lists."""
    n = len(next(iter(columns.values())))
    return [{k: _entry(v[i]) for k, v in columns.items()} for i in range(n)]


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``bearings``.

    Parameters
    ----------
    result : Result
        An analysis with the ``bearings`` section.

    Returns
    -------
    dict
        ``{"bearings": ...}``: crank pins, mains and internal moments (docs/conventions.md,
        "Crank-pin and main-bearing loads").
    """
    loads = _loads(result)
    assert loads is not None
    return {"bearings": _bearings_json(loads)}


def _bearings_json(b: Bearings) -> dict[str, Any]:
    """The ``"bearings"`` block of the JSON result (docs/bearings.md); with several crank
    axes each entry names its ``crankshaft`` and a ``note`` says what is left out
    (docs/several-crankshafts.md, "Bearing loads")."""
    pin_shaft, main_shaft = _shaft_names(b, b.pin_axis), _shaft_names(b, b.main_axis)
    pin_key = {} if pin_shaft is None else {"crankshaft": pin_shaft}
    main_key = {} if main_shaft is None else {"crankshaft": main_shaft}
    block: dict[str, Any] = {
        "crank_pins": _records(
            {
                **pin_key,
                "z_m": b.pin_z,
                "cylinders": b.pin_cylinders,
                "max_N": b.pin_max,
                "mean_N": b.pin_mean,
            }
        ),
        "mains": _records(
            {
                **main_key,
                "z_m": b.main_z,
                "max_N": b.main_max,
                "mean_N": b.main_mean,
                "max_with_proposal_N": b.main_max_with_proposal,
                "mean_with_proposal_N": b.main_mean_with_proposal,
            }
        ),
        "internal_moment": _records(
            {
                **main_key,
                "z_m": b.main_z,
                "max_Nm": b.moment_max,
                "max_with_proposal_Nm": b.moment_max_with_proposal,
            }
        ),
    }
    if b.pin_axis is not None:
        block["note"] = GEAR_NOTE
    return block


# --------------------------------------------------------------------------- tables


def tables(result: Result) -> list[RenderableType]:
    """The section's tables: crank-pin loads, main-bearing loads and internal moments, each
    without and with the proposed counterweights; when the counterweight strategies were
    compared, the largest loads with each.

    Parameters
    ----------
    result : Result
        An analysis with the ``bearings`` section.

    Returns
    -------
    list of rich.console.RenderableType
    """
    part = result.part("bearings")
    out = _bearings_tables(part.loads)
    if part.strategies:
        out += _strategy_table(part.strategies)
    return out


def _bearings_tables(b: Bearings) -> list[RenderableType]:
    """Tables: crank-pin loads; main-bearing loads; internal moments; each without and with
    the proposed counterweights."""
    from rich.text import Text

    from balance.views.fitted import Column, NumberTable

    v = _printed(b)
    gas = "with gas forces, over the cycle" if b.gas else "inertia only"
    pins = NumberTable(
        f"Crank-pin loads ({gas})",
        [
            Column("pin", key=True),
            *_shaft_column(b),
            Column("z", "mm"),
            Column("cylinders"),
            Column("max", "N"),
            Column("at theta", "deg"),
            Column("mean", "N"),
        ],
        _pin_rows(b, v, angle=True),
    )
    mains = NumberTable(
        f"Main-bearing loads ({gas}), without / with the proposed counterweights",
        [
            Column("main", key=True),
            *_shaft_column(b),
            Column("z", "mm"),
            Column("max", "N"),
            Column("mean", "N"),
            Column("max with proposal", "N"),
            Column("mean with proposal", "N"),
        ],
        _main_rows(b, v, _LOADS),
    )
    moments = NumberTable(
        "Internal moment of the crankshaft at the mains (inertia only)",
        [
            Column("main", key=True),
            *_shaft_column(b),
            Column("z", "mm"),
            Column("moment max", "N m"),
            Column("moment max with proposal", "N m"),
        ],
        _main_rows(b, v, _MOMENTS),
    )
    none = "" if b.counterweights else " (the proposal has no counterweights)"
    notes = [
        Text(
            f"Largest main load {format_number(float(np.max(v['main_max'])))} N, with proposal "
            f"{format_number(float(np.max(v['main_max_with_proposal'])))} N{none}"
        ),
        Text(
            f"Largest internal moment {format_number(float(np.max(v['moment_max'])))} N m, with "
            f"proposal {format_number(float(np.max(v['moment_max_with_proposal'])))} N m"
        ),
    ]
    if b.pin_axis is not None:
        notes.append(Text(f"Note: {GEAR_NOTE}."))
    return [pins, mains, moments, *notes]


def _strategy_table(rows: Sequence[tuple[str, Bearings]]) -> list[RenderableType]:
    """The counterweight strategies side by side: largest main load and internal moment
    with each one's counterweights (``rows``: strategy name and its bearing loads)."""
    from balance.views.fitted import Column, NumberTable

    cells = []
    if rows:
        base = _printed(rows[0][1])
        cells.append(
            [
                "none",
                "0",
                format_number(float(np.max(base["main_max"]))),
                format_number(float(np.max(base["moment_max"]))),
            ]
        )
    for name, b in rows:
        v = _printed(b)
        cells.append(
            [
                name,
                str(len(b.counterweights)),
                format_number(float(np.max(v["main_max_with_proposal"]))),
                format_number(float(np.max(v["moment_max_with_proposal"]))),
            ]
        )
    table = NumberTable(
        "Counterweight strategies: largest main-bearing load and internal moment",
        [
            Column("strategy", key=True, justify="left"),
            Column("counterweights"),
            Column("largest main load", "N"),
            Column("largest internal moment", "N m"),
        ],
        cells,
    )
    return [table]


# --------------------------------------------------------------------------- figures


def _not_computed(result: Result, kind: str, title: str | None) -> Figure:
    """A figure that says the bearing loads were not asked for."""
    return placeholder(result, kind, title, f"no bearing loads in this result:\n{ASK}")


def _polar_diagram(
    ax: Axes, curves: Sequence[tuple[np.ndarray, str, str]], x_label: str, y_label: str
) -> None:
    """Loads as x-y curves through the origin, equal scales, in kN (a load that is zero at
    every crank angle: a note that says so, on axes of 1 kN)."""
    for load, style, label in curves:
        closed = np.concatenate([load, load[:1]]) / 1e3
        ax.plot(closed.imag, closed.real, style, lw=1.2, label=label)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.plot([0.0], [0.0], "k+", ms=6)
    if all(not np.any(load) for load, _, _ in curves):
        ax.text(
            0.5, 0.75, "0 at every crank angle", transform=ax.transAxes, ha="center", color="0.4"
        )
        ax.set_xlim(-1.0, 1.0)
        ax.set_ylim(-1.0, 1.0)
        ax.set_aspect("equal", adjustable="box")
    else:
        ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)


def _plot_pin_load(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``pin_load``: polar diagram of each crank-pin load in the crank-fixed frame
    (up: outwards along the throw; right: in the direction of rotation), the textbook chart,
    with the largest load marked (a line from the origin, labelled with its crank angle)."""
    b = _loads(result)
    if b is None:
        return _not_computed(result, "pin_load", title)
    crank = b.pin_load_crank_frame
    v = _printed(b)
    # pins with the same diagram (a V's or an inline's equal throws) are drawn once
    shown: list[int] = []
    for j in range(crank.shape[0]):
        scale = max(float(np.max(np.abs(crank[j]))), 1e-300)
        if not any(np.max(np.abs(crank[j] - crank[i])) <= 1e-9 * scale for i in shown):
            shown.append(j)
    ncols = min(3, len(shown))
    size = (4.2 * ncols, 4.2 * math.ceil(len(shown) / ncols) + 0.4)
    fig, axes = grid_figure(len(shown), size, ncols)
    for ax, j in zip(axes, shown, strict=True):
        same = [
            i + 1
            for i in range(crank.shape[0])
            if np.max(np.abs(crank[i] - crank[j]))
            <= 1e-9 * max(float(np.max(np.abs(crank[j]))), 1e-300)
        ]
        _polar_diagram(
            ax,
            [(_printed_curve(b, crank[j]), "C0-", "pin load over the cycle")],
            "along rotation [kN]",
            "along the throw, outwards [kN]",
        )
        peak = int(np.argmax(np.abs(crank[j])))
        theta = round(math.degrees(float(b.pin_max_angle[j])), 1) % 360.0
        ax.plot(
            [0.0, crank[j][peak].imag / 1e3],
            [0.0, crank[j][peak].real / 1e3],
            "C3-",
            lw=0.8,
            label=f"largest load (θ = {theta:.1f}°)",
        )
        cyl = ", ".join(" ".join(map(str, b.pin_cylinders[i - 1])) for i in same)
        ax.set_title(
            f"pin{'s' if len(same) > 1 else ''} {', '.join(map(str, same))} (cyl. {cyl}): "
            f"max {format_number(float(v['pin_max'][j]) / 1e3)} kN",
            fontsize=9,
        )
        ax.legend(fontsize=7, loc="lower right")
    gas = "with gas forces" if b.gas else "inertia only"
    fig.suptitle(
        title_text(
            fig.get_figwidth(),
            title or f"{layout_heading(result)}: crank-pin load in the crank-fixed frame ({gas})",
        )
    )
    return fig


def _plot_main_loads(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``main_loads``: polar diagram of each main bearing's load in the engine
    frame (up: +y, right: +x), without and with the proposed counterweights."""
    b = _loads(result)
    if b is None:
        return _not_computed(result, "main_loads", title)
    n = b.main_z.size
    ncols = min(4, n)
    fig, axes = grid_figure(n, (3.6 * ncols, 3.6 * math.ceil(n / ncols)), ncols)
    with_cw = bool(b.counterweights)
    v = _printed(b)
    for m, ax in enumerate(axes):
        curves = [(_printed_curve(b, b.main_load[m]), "C0-", "without counterweights")]
        if with_cw:
            curves.append(
                (_printed_curve(b, b.main_load_with_proposal[m]), "C1--", "with the proposal")
            )
        _polar_diagram(ax, curves, "x [kN]", "y [kN]")
        z_mm, top = _mm(float(b.main_z[m])), format_number(float(v["main_max"][m]) / 1e3)
        shaft = "" if b.main_axis is None else f" ({b.axis_names[int(b.main_axis[m])]})"
        text = f"main {m + 1}{shaft}, z = {z_mm} mm: max {top}"
        if with_cw:
            text += f" / {format_number(float(v['main_max_with_proposal'][m]) / 1e3)}"
        ax.set_title(text + " kN", fontsize=9)
    if with_cw:
        axes[0].legend(fontsize=7, loc="best")
    gas = "with gas forces" if b.gas else "inertia only"
    fig.suptitle(
        title_text(
            fig.get_figwidth(),
            title or f"{layout_heading(result)}: main-bearing loads in the engine frame ({gas})",
        )
    )
    return fig


def _plot_internal_moment(result: Result, *, title: str | None = None) -> Figure:
    """Plot kind ``internal_moment``: the largest internal bending moment at each main along
    the crank, without and with the proposed counterweights, and the throw planes."""
    b = _loads(result)
    if b is None:
        return _not_computed(result, "internal_moment", title)
    fig, (ax,) = grid_figure(1, (7.0, 4.2), 1)
    z = b.main_z * 1e3
    v = _printed(b)
    # one line per crank axis (its mains along its own crank), named with several
    which = np.zeros(z.size, dtype=np.intp) if b.main_axis is None else b.main_axis
    for k in np.unique(which):
        on = which == k
        name = "" if b.main_axis is None else f" ({b.axis_names[int(k)]})"
        ax.plot(z[on], v["moment_max"][on], f"C{2 * k}o-", label=f"without counterweights{name}")
        if b.counterweights:
            ax.plot(
                z[on],
                v["moment_max_with_proposal"][on],
                f"C{2 * k + 1}s--",
                label=f"with the proposal{name}",
            )
    for zp in np.unique(np.round(b.pin_z, 9)):
        ax.axvline(zp * 1e3, color="0.8", lw=0.8)
    ax.set_xlabel("z of the main bearing [mm] (grey: throw planes)")
    ax.set_ylabel("largest internal moment [N m]")
    ax.set_ylim(bottom=0.0)
    ax.legend(fontsize=8)
    fig.suptitle(
        title_text(
            fig.get_figwidth(),
            title or f"{layout_heading(result)}: internal bending moment of the crankshaft",
        )
    )
    return fig


# --------------------------------------------------------------------------- report


#: The figure kinds of the section.
PLOTS = {
    "pin_load": _plot_pin_load,
    "main_loads": _plot_main_loads,
    "internal_moment": _plot_internal_moment,
}

#: The heading of the section in the HTML report.
REPORT_TITLE = "Crank-pin and main-bearing loads"


def report_section(result: Result, figures: bool) -> str:
    """HTML of the report's bearings section, with its three figures.

    Parameters
    ----------
    result : Result
        An analysis with the ``bearings`` section.
    figures : bool
        Include the figures (inline SVG).

    Returns
    -------
    str
    """
    from balance.views.report import escape, html_figure, html_table

    loads = _loads(result)
    assert loads is not None
    html = _bearings_report_section(loads, html_table, escape)
    if figures:
        html += "\n" + "\n".join(
            html_figure(result, kind, caption, 95 + n)
            for n, (kind, caption) in enumerate(
                (
                    ("pin_load", "Crank-pin load in the crank-fixed frame"),
                    ("main_loads", "Main-bearing loads in the engine frame"),
                    ("internal_moment", "Internal moment of the crankshaft at the mains"),
                )
            )
        )
    return html


def _bearings_report_section(
    b: Bearings,
    table: Callable[..., str],
    escape: Callable[[object], str],
) -> str:
    """HTML of the report's bearings section (``table(headers, rows, caption)`` and
    ``escape(text)`` are the report's own helpers)."""
    v = _printed(b)
    gas = "with gas forces over the working cycle" if b.gas else "inertia only"
    shaft = [] if b.pin_axis is None else ["crankshaft"]
    pins = table(
        ["pin", *shaft, "z [mm]", "cylinders", "max [N]", "mean [N]"],
        _pin_rows(b, v, angle=False),
        f"Crank-pin loads ({gas})",
    )
    mains = table(
        [
            "main",
            *shaft,
            "z [mm]",
            "max [N]",
            "mean [N]",
            "max with proposal [N]",
            "mean with proposal [N]",
        ],
        _main_rows(b, v, _LOADS),
        f"Main-bearing loads ({gas})",
    )
    moments = table(
        ["main", *shaft, "z [mm]", "moment max [N m]", "moment max with proposal [N m]"],
        _main_rows(b, v, _MOMENTS),
        "Internal moments of the crankshaft at the mains (inertia only)",
    )
    text = (
        "Loads are the forces the crankshaft puts on each bearing; the mains share each "
        "throw's load by the lever rule of a crankshaft cut at every main; the internal "
        "moment at a main is that of the throw loads on its side of smaller z. "
        "'With proposal' adds the proposed counterweights (balance shafts run in their own "
        "bearings)."
    )
    if b.pin_axis is not None:
        text += f" Note: {GEAR_NOTE}."
    return f"<p>{escape(text)}</p>\n{pins}\n{mains}\n{moments}"
