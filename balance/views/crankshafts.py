"""Views of the ``crankshafts`` section: several crankshafts geared together
(:mod:`balance.core.geared`, docs/several-crankshafts.md).

The JSON keys are those of docs/several-crankshafts.md, "What each crankshaft reports": the
rotating masses' ``backward`` phasors, ``moment_z`` (and its reciprocating and rotating parts),
``output_rotation``, ``crankshafts`` (each one's force, own roll and torque) and
``gear_couple``; every cylinder entry gains ``crankshaft`` and ``opposed``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.phasors import phase_deg, safe_ratio
from balance.views.fitted import Column, NumberTable
from balance.views.json import order_entries, roll_entries
from balance.views.polar import format_number, json_number

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.geared import GearedParts
    from balance.core.phasors import Phasors
    from balance.core.result import Result

__all__ = [
    "PLOTS",
    "REPORT_TITLE",
    "crankshafts_table",
    "csv_columns",
    "drawn",
    "json_block",
    "phasor_layers",
    "plot_crankshaft_forces",
    "report_section",
    "tables",
]


def _part(result: Result) -> GearedParts:
    part: GearedParts = result.part("crankshafts")
    return part


def _crankshaft_of(result: Result) -> list[int]:
    """The crankshaft (0-based) of each cylinder."""
    of = [0] * result.engine.n_cylinders
    for s, members in enumerate(_part(result).members):
        for i in members:
            of[int(i)] = s
    return of


def _rotating_backward(result: Result, quantity: str, reference: float) -> dict[str, Any]:
    p = result.phasors
    forward = p.rotating(quantity)  # type: ignore[arg-type]
    backward = getattr(p, f"rotating_{quantity}_backward")
    peak = float(np.abs(forward) + np.abs(backward))
    return {
        "backward": {
            "magnitude": json_number(np.abs(backward)),
            "phase_deg": json_number(phase_deg(backward)),
        },
        "peak": json_number(peak),
        "peak_normalised": json_number(safe_ratio(peak, reference)),
    }


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON.

    Parameters
    ----------
    result : Result
        An analysis with the ``crankshafts`` section.

    Returns
    -------
    dict
        ``rotating.force.backward`` (and the moment's), ``reciprocating.moment_z``,
        ``rotating.moment_z``, ``moment_z``, ``output_rotation``, ``crankshafts``,
        ``gear_couple`` and the ``cylinders`` entries with ``crankshaft`` and ``opposed``
        (docs/several-crankshafts.md, "What each crankshaft reports").
    """
    part = _part(result)
    orders = result.orders
    rotating: dict[str, Any] = {
        "force": _rotating_backward(result, "force", result.reference_force),
        "moment_z": roll_entries(orders, part.moment_z_rotating),
    }
    if result.has_moments:
        rotating["moment"] = _rotating_backward(result, "moment", result.reference_moment)
    force = part.force.free()
    shafts = []
    of = _crankshaft_of(result)
    for s, name in enumerate(part.names):
        entry: dict[str, Any] = {
            "name": name,
            "x_m": json_number(part.x[s]),
            "y_m": json_number(part.y[s]),
            "rotation": int(part.sense[s]),
            "phase_deg": json_number(math.degrees(float(part.phase[s]))),
            "cylinders": [i + 1 for i, t in enumerate(of) if t == s],
            "force": order_entries(
                orders,
                force.magnitude("force")[s],
                force.phase("force")[s],
                force.peak("force")[s],
                safe_ratio(force.peak("force")[s], result.reference_force),
            ),
        }
        for item in entry["force"]:
            item.pop("peak_normalised")  # a shaft's force has no reference of its own
        if part.force.roll is not None and part.torque is not None:
            entry["roll"] = roll_entries(part.roll_orders, part.force.roll[s])
            entry["torque"] = roll_entries(part.roll_orders, part.torque[s])
        if part.torque_mean is not None:
            entry["torque_mean_Nm"] = json_number(part.torque_mean[s])
        shafts.append(entry)
    block: dict[str, Any] = {
        "reciprocating": {"moment_z": roll_entries(orders, part.moment_z_reciprocating)},
        "rotating": rotating,
        "moment_z": roll_entries(orders, part.moment_z),
        "output_rotation": int(part.output_sense),
        "crankshafts": shafts,
    }
    if part.gear_couple is not None:
        block["gear_couple"] = roll_entries(part.roll_orders, part.gear_couple)
    cylinders = _cylinder_entries(result, of)
    if cylinders is not None:
        block["cylinders"] = cylinders
    return block


def _cylinder_entries(result: Result, of: list[int]) -> list[dict[str, Any]] | None:
    """The ``cylinders`` entries of the cylinders section with ``crankshaft`` (name) and
    ``opposed`` (number or null) added; None without that section."""
    if result.part("cylinders") is None:
        return None
    from balance.views.sections import view

    entries: list[dict[str, Any]] = view("cylinders").json_block(result)["cylinders"]
    names = _part(result).names
    shafts = result.engine.crankshafts
    opposed = shafts.opposed if shafts is not None else np.full(len(of), -1)
    for entry, s, partner in zip(entries, of, opposed, strict=True):
        entry["crankshaft"] = names[s]
        entry["opposed"] = int(partner) + 1 if partner >= 0 else None
    return entries


def crankshafts_table(result: Result) -> NumberTable:
    """Each crankshaft's place and sense, and per order its free-force peak, own roll and
    torque amplitudes, with the engine's moment about ``z`` and gear couple.

    Parameters
    ----------
    result : Result
        An analysis with the ``crankshafts`` section.

    Returns
    -------
    NumberTable
    """
    part = _part(result)
    peak = part.force.free().peak("force")
    columns = [Column("order", key=True)]
    for name in part.names:
        columns.append(Column(f"{name} force peak", "N"))
        if part.torque is not None:
            columns += [Column(f"{name} roll", "N m"), Column(f"{name} torque", "N m")]
    columns.append(Column("moment about z", "N m"))
    if part.gear_couple is not None:
        columns.append(Column("gear couple", "N m"))
    roll_at = {float(k): i for i, k in enumerate(part.roll_orders)}
    rows = []
    for j, k in enumerate(result.orders):
        at = roll_at.get(float(k))
        row = [str(int(k))]
        for s in range(part.count):
            row.append(format_number(float(peak[s, j])))
            if part.torque is not None and part.force.roll is not None:
                row += [
                    _amplitude(part.force.roll[s], at),
                    _amplitude(part.torque[s], at),
                ]
        row.append(format_number(float(np.abs(part.moment_z[j]))))
        if part.gear_couple is not None:
            row.append(_amplitude(part.gear_couple, at))
        rows.append(row)
    senses = ", ".join(
        f"{name} at ({format_number(float(x) * 1e3)}, {format_number(float(y) * 1e3)}) mm "
        f"{'same' if sense > 0 else 'opposite'}"
        for name, x, y, sense in zip(part.names, part.x, part.y, part.sense, strict=True)
    )
    output = "same" if part.output_sense > 0 else "opposite"
    return NumberTable(f"Crankshafts: {senses}; output turns {output}", columns, rows)


def _amplitude(values: Any, at: int | None) -> str:
    return "-" if at is None else format_number(float(np.abs(values[at])))


def tables(result: Result) -> list[RenderableType]:
    """The section's table: :func:`crankshafts_table`.

    Parameters
    ----------
    result : Result
        An analysis with the ``crankshafts`` section.

    Returns
    -------
    list of rich.console.RenderableType
    """
    return [crankshafts_table(result)]


def csv_columns(result: Result) -> list[tuple[str, dict[float, float]]]:
    """The section's columns of the per-order CSV: the moment about ``z``, the gear couple
    and each crankshaft's force peak, own roll and torque amplitudes.

    Parameters
    ----------
    result : Result
        An analysis with the ``crankshafts`` section.

    Returns
    -------
    list of (str, dict)
        Each column's header (with its unit) and its values by order of the result (NaN
        where a roll order is not one of them).
    """
    part = _part(result)
    orders = result.orders
    roll_at = {float(k): i for i, k in enumerate(part.roll_orders)}

    def on_orders(values: Any) -> list[float]:
        out = []
        for k in orders:
            at = roll_at.get(float(k))
            out.append(math.nan if at is None else float(np.abs(values[at])))
        return out

    columns = [
        ("moment_z_amplitude [N m]", [float(v) for v in np.abs(part.moment_z)]),
        ("moment_z_phase [deg]", [float(v) for v in phase_deg(part.moment_z)]),
    ]
    if part.gear_couple is not None:
        columns.append(("gear_couple_amplitude [N m]", on_orders(part.gear_couple)))
    peak = part.force.free().peak("force")
    for s, name in enumerate(part.names):
        columns.append((f"{name}_force_peak [N]", [float(v) for v in peak[s]]))
        if part.force.roll is not None and part.torque is not None:
            columns.append((f"{name}_roll_amplitude [N m]", on_orders(part.force.roll[s])))
            columns.append((f"{name}_torque_amplitude [N m]", on_orders(part.torque[s])))
    keys = [float(k) for k in orders]
    return [(header, dict(zip(keys, values, strict=True))) for header, values in columns]


def plot_crankshaft_forces(result: Result, **options: Any) -> Any:
    """The figure ``crankshaft_forces``: each crankshaft's free force over a revolution at
    its axis (:func:`balance.views.axes_plots.plot_axis_forces`).

    Parameters
    ----------
    result : Result
        An analysis with the ``crankshafts`` section.
    **options
        ``ax``, ``title``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from balance.views.axes_plots import plot_axis_forces
    from balance.views.figures import placeholder

    if not drawn(result):
        text = "not computed: one crankshaft, whose free force is the engine's (locus, phasors)"
        return placeholder(result, "crankshaft_forces", options.get("title"), text)
    return plot_axis_forces(result, **options)


def drawn(result: Result) -> bool:
    """Whether the section's figure has something to draw: several crankshafts.

    Parameters
    ----------
    result : Result
        An analysis.

    Returns
    -------
    bool
    """
    return result.part("crankshafts") is not None


def phasor_layers(result: Result, source: str) -> tuple[str, list[tuple[str, Phasors]]] | None:
    r"""Each crankshaft's phasors, which add up to the engine's: what the ``phasors`` figure
    draws head to tail in each order's panel (:func:`balance.views.phasor_plots.plot_phasors`).

    A shaft's force is that of its pistons, rods and masses; its moment is
    :math:`\sum (z_i - z_{ref}) F_i` over its cylinders, about the engine's reference plane
    and the frame's ``x`` and ``y`` axes through the origin, which a transverse force's
    place in ``x`` and ``y`` does not change: the shafts' moments add up to the engine's
    as their forces do (the moment about ``z``, which depends on where each shaft sits, is
    in the section's table).

    Parameters
    ----------
    result : Result
        An analysis with the ``crankshafts`` section.
    source : {'free', 'reciprocating', 'residual'}
        Which phasors (:mod:`balance.views.signals`): ``free`` with each shaft's rotating
        masses at order 1 (forward, or backward on a counter-rotating shaft; a sum that
        cancels to rounding set to 0 as for the engine's,
        :func:`balance.views.polar.free_phasors`), ``reciprocating`` without them.

    Returns
    -------
    (str, list of (str, Phasors)) or None
        The legend's heading and each shaft's name and phasors (orders of the result's);
        None for ``residual`` (the proposal's residual is not split by shaft).
    """
    from balance.views.polar import free_phasors

    part = _part(result)
    if source == "residual":
        return None
    force = part.force
    if source == "free":
        force = free_phasors(force, result.engine.n_cylinders)
    layers = []
    for s, name in enumerate(part.names):
        layers.append((name, _one_shaft(force, s)))
    return "crankshafts,\nhead to tail:", layers


def _one_shaft(bundle: Phasors, s: int) -> Phasors:
    """The phasors of shaft ``s`` of a bundle with a leading axis of shafts."""
    from dataclasses import fields, replace

    changes = {}
    for field in fields(bundle):
        value = getattr(bundle, field.name)
        if field.name != "orders" and value is not None and np.ndim(value) > 0:
            changes[field.name] = np.asarray(value)[s]
    return replace(bundle, **changes)


PLOTS = {"crankshaft_forces": plot_crankshaft_forces}

REPORT_TITLE = "Several crankshafts"


def report_section(result: Result, figures: bool) -> str:
    """HTML of the report's crankshafts section: the table of the crankshafts
    (:func:`crankshafts_table`) and each shaft's free force at its axis (the report's crank
    star draws every shaft where it sits).

    Parameters
    ----------
    result : Result
        An analysis with the ``crankshafts`` section.
    figures : bool
        Include the figures.

    Returns
    -------
    str
    """
    from balance.views.report import escape, html_figure, html_table

    table = crankshafts_table(result)
    html = f"<p>{escape(table.title)}.</p>\n" + html_table(
        [c.header for c in table.columns],
        table.rows,
        "Per order: each crankshaft's free-force peak, own roll and torque; the moment about "
        "z and the gear couple",
    )
    if figures:
        html += "\n" + html_figure(
            result,
            "crankshaft_forces",
            "Each crankshaft's free force over a revolution, drawn at its axis",
            111,
        )
    return html
