"""A readable table of a :class:`~balance.core.result.Result`, for the terminal.

Reads the Result's phasors and references directly; no xarray.  Every table is a
:class:`~balance.views.fitted.NumberTable`: its title on a line of its own, a unit in
brackets in every column header of a quantity, and a layout chosen when it is printed so
that no number is ever cut (see :mod:`balance.views.fitted`).  A value the computation
cannot tell from zero (below the rounding threshold of its sums,
:func:`balance.core.phasors.cancel_to_zero`) prints as 0; a ratio that has no reference
(a moment per pitch when every cylinder is in one plane) prints as ``n/a`` with the reason
below its table.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from balance.core.catalogue import speed_rpm
from balance.core.phasors import phase_deg, safe_ratio
from balance.views.fitted import Column, NumberTable
from balance.views.polar import format_number

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.result import Result

__all__ = [
    "NO_PITCH",
    "format_ratio",
    "pitch_note",
    "pitch_text",
    "render",
]

#: Why a moment has no normalised value: the pitch is undefined.
NO_PITCH = "n/a (all cylinders in one plane)"


def format_ratio(value: float, reference: float) -> str:
    """A normalised value, or ``n/a`` where its reference is undefined (NaN or zero).

    Parameters
    ----------
    value : float
        The normalised value [1].
    reference : float
        The reference it was divided by (:math:`F_1` [N], or :math:`F_1 a` [N m]).

    Returns
    -------
    str
    """
    if not (math.isfinite(reference) and reference != 0.0):
        return "n/a"
    return format_number(value)


def pitch_text(pitch: float) -> str:
    """The cylinder pitch as printed: ``90 mm``, or ``n/a`` and why.

    Parameters
    ----------
    pitch : float
        The pitch [m]; NaN when the layout has none.

    Returns
    -------
    str
    """
    return f"{format_number(pitch * 1e3)} mm" if math.isfinite(pitch) else NO_PITCH


def pitch_note(result: Result) -> tuple[str, ...]:
    """The note under a table with moments per F1 a, when there is no pitch.

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    tuple of str
        The note, or nothing when the layout has a pitch.
    """
    if math.isfinite(float(result.reference_moment)) and float(result.reference_moment) != 0:
        return ()
    return ("n/a: no pitch a (all cylinders in one plane), so no moment per F1 a",)


def _heading(result: Result) -> list[RenderableType]:
    """The first lines of an analysis: the layout, its speed and model, the references."""
    from rich.text import Text

    engine = result.engine
    bound = float(result.model.error_bound)
    summary = (
        f"{engine.n_cylinders} cylinder{'s' if engine.n_cylinders != 1 else ''} at "
        f"{speed_rpm(engine.speed):.0f} rpm; model {result.model.name}"
        + (f" (coefficient error below {bound:.1g})" if math.isfinite(bound) else "")
    )
    norm = (
        f"F1 = m_rec r w^2 = {format_number(float(result.reference_force))} N; "
        f"moments about z = {format_number(float(engine.reference_z) * 1e3)} mm"
    )
    pitch = f"pitch a = {pitch_text(float(result.pitch))}"
    return [Text(str(engine.name), style="bold"), Text(summary), Text(norm), Text(pitch)]


def render(result: Result, only: tuple[str, ...] | None = None) -> RenderableType:
    """Rich renderable of a result: the heading, free forces and moments per order,
    rotating masses and roll, then the tables of every section it holds (the proposal,
    torque, mounts, bearing loads…, :mod:`balance.views.sections`), and the warnings.

    Parameters
    ----------
    result : Result
        The analysis.
    only : tuple of str, optional
        Section names: a short heading (the layout and its speed) and the tables of those
        sections alone (``balance propose``).

    Returns
    -------
    rich.console.RenderableType
        A group of tables and notes.
    """
    from rich.console import Group
    from rich.text import Text

    from balance.views.sections import views_of

    if only is None:
        parts = _heading(result) + _free_tables(result)
    else:
        engine = result.engine
        parts = [
            Text(str(engine.name), style="bold"),
            Text(
                f"{engine.n_cylinders} cylinder{'s' if engine.n_cylinders != 1 else ''} at "
                f"{speed_rpm(engine.speed):.0f} rpm"
            ),
        ]
    for _, views in views_of(result, only):
        tables = getattr(views, "tables", None)
        if tables is not None:
            parts.extend(tables(result))
    parts.extend(_render_warnings(result))
    return Group(*parts)


def _free_tables(result: Result) -> list[RenderableType]:
    """The free forces and moments per order, the rotating masses and the roll."""
    from rich.text import Text

    p = result.phasors
    parts: list[RenderableType] = []
    kinds = [("force", "N", "F1", result.reference_force)]
    if result.has_moments:
        kinds.append(("moment", "N m", "F1 a", result.reference_moment))
    for what, unit, per, reference in kinds:
        mag = p.magnitude(what)  # type: ignore[arg-type]
        phase = p.phase(what)  # type: ignore[arg-type]
        peak = p.peak(what)  # type: ignore[arg-type]
        normalised = safe_ratio(peak, reference)
        rows = [
            [
                str(int(k)),
                format_number(float(mag[i, 0])),
                format_number(float(phase[i, 0])),
                format_number(float(mag[i, 1])),
                format_number(float(phase[i, 1])),
                format_number(float(peak[i])),
                format_ratio(float(normalised[i]), float(reference)),
            ]
            for i, k in enumerate(p.orders)
        ]
        title = (
            "Reciprocating inertia: free forces per order"
            if what == "force"
            else "Reciprocating inertia: free moments per order, about reference_z"
        )
        parts.append(
            NumberTable(
                title,
                [
                    Column("order", key=True),
                    Column("forward", unit),
                    Column("phase", "deg"),
                    Column("backward", unit),
                    Column("phase", "deg"),
                    Column("peak", unit),
                    Column(f"peak / {per}" if what == "force" else f"peak / ({per})"),
                ],
                rows,
                notes=pitch_note(result) if what == "moment" else (),
            )
        )
    for what, unit in (("force", "N"), ("moment", "N m"))[: len(kinds)]:
        rotating = p.rotating(what)  # type: ignore[arg-type]
        parts.append(
            Text(
                f"Rotating masses (order 1, forward): {what} "
                f"{format_number(float(np.abs(rotating)))} {unit} at "
                f"{format_number(float(phase_deg(rotating)))} deg"
            )
        )
    if result.roll is not None:
        parts.append(_roll_table(result))
    return parts


def _render_warnings(result: Result) -> list[RenderableType]:
    """The plausibility warnings as the table's footer, one line each (none: nothing)."""
    from rich.text import Text

    return [Text(f"warning: {w.field}: {w.message}", style="yellow") for w in result.warnings]


def _roll_table(result: Result) -> NumberTable:
    assert result.roll is not None
    amplitude = np.abs(result.roll)
    phase = phase_deg(result.roll)
    normalised = safe_ratio(amplitude, result.reference_roll)
    rows = [
        [
            f"{k:g}",
            format_number(float(amplitude[i])),
            format_number(float(phase[i])),
            format_ratio(float(normalised[i]), float(result.reference_roll)),
        ]
        for i, k in enumerate(np.asarray(result.roll_orders, dtype=np.float64))
    ]
    return NumberTable(
        "Roll torque on the block: sum of a_k cos(k theta + phase_k)",
        [
            Column("order", key=True),
            Column("amplitude a_k", "N m"),
            Column("phase_k", "deg"),
            Column("a_k / (m_rec r^2 w^2)"),
        ],
        rows,
    )
