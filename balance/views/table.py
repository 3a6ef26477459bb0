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
from balance.views.polar import format_number, free_phasors

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.engine import Engine
    from balance.core.result import Result

__all__ = [
    "BORE_PITCH",
    "NO_BORE_PITCH",
    "NO_PITCH",
    "format_ratio",
    "pitch_note",
    "pitch_text",
    "render",
]

#: Why a moment has no normalised value: the pitch is undefined (every cylinder in one
#: plane; :func:`pitch_text` gives the reason of an engine).
NO_PITCH = "n/a (all cylinders in one plane)"

#: Why a moment has no normalised value when the cylinders are in several planes but no
#: bank has two of them (a boxer twin, a staggered V-twin): no bore pitch.
NO_BORE_PITCH = "n/a (one cylinder per bank: no bore pitch; set pitch: in the layout)"

#: What the pitch of a layout without ``pitch:`` is (docs/conventions.md, "Normalisation
#: and ``pitch``").
BORE_PITCH = "bore pitch: between neighbouring cylinders of one bank"


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


def _no_pitch(engine: Engine | None) -> str:
    """Why an engine has no pitch (:data:`NO_PITCH` without an engine)."""
    if engine is None or np.unique(np.round(np.asarray(engine.z), 12)).size < 2:
        return NO_PITCH
    return NO_BORE_PITCH


def pitch_text(pitch: float, engine: Engine | None = None) -> str:
    """The pitch as printed: ``90 mm`` (with an engine, and what it is: the layout's own,
    or the bore pitch), or ``n/a`` and why.

    Parameters
    ----------
    pitch : float
        The pitch [m]; NaN when the layout has none.
    engine : Engine, optional
        The engine: the text then says where the pitch comes from.

    Returns
    -------
    str
    """
    if not math.isfinite(pitch):
        return _no_pitch(engine)
    text = f"{format_number(pitch * 1e3)} mm"
    if engine is None:
        return text
    return f"{text} ({'set in the layout' if engine.pitch_given else BORE_PITCH})"


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
    reason = _no_pitch(result.engine).removeprefix("n/a (").removesuffix(")").split(";")[0]
    return (f"n/a: no pitch a ({reason}), so no moment per F1 a",)


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
    pitch = f"pitch a = {pitch_text(float(result.pitch), engine)}"
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


#: The titles of the free force and moment tables: the quantity each row holds.
FREE_TITLES = {
    "force": "Free forces per order: reciprocating inertia; at order 1 also rotating and free",
    "moment": "Free moments about reference_z: reciprocating; order 1 also rotating and free",
}

#: The note under them: what the rows of order 1 are.
FREE_NOTE = "1 rot.: the rotating masses; 1 free = reciprocating + rotating (as drawn)"


def _free_tables(result: Result) -> list[RenderableType]:
    """The free forces and moments per order (reciprocating inertia, and at order 1 the
    rotating masses and their sum, the free force the figures draw), and the roll."""
    p = result.phasors
    free = free_phasors(p, result.engine.n_cylinders)
    parts: list[RenderableType] = []
    kinds = [("force", "N", "F1", result.reference_force)]
    if result.has_moments:
        kinds.append(("moment", "N m", "F1 a", result.reference_moment))
    for what, unit, per, reference in kinds:
        forward, backward = p.pair(what)  # type: ignore[arg-type]
        free_forward, free_backward = free.pair(what)  # type: ignore[arg-type]
        rotating = complex(p.rotating(what))  # type: ignore[arg-type]
        # masses turning backward: on a counter-rotating crankshaft (several-crankshafts.md)
        turning_back = getattr(p, f"rotating_{what}_backward")
        rotating_back = 0j if turning_back is None else complex(turning_back)
        rows = []
        if 1 not in p.orders:
            rows.append(_phasor_row("1 rot.", rotating, rotating_back, reference))
        for i, k in enumerate(p.orders):
            rows.append(_phasor_row(str(int(k)), forward[i], backward[i], reference))
            if k == 1:
                rows.append(_phasor_row("1 rot.", rotating, rotating_back, reference))
                rows.append(_phasor_row("1 free", free_forward[i], free_backward[i], reference))
        notes: tuple[str, ...] = (FREE_NOTE,) if 1 in p.orders else (FREE_NOTE.split(";")[0],)
        if what == "moment":
            notes += pitch_note(result)
        parts.append(
            NumberTable(
                FREE_TITLES[what],
                [
                    Column("order", key=True),
                    Column("forward", unit),
                    Column("phase", "deg"),
                    Column("backward", unit),
                    Column("phase", "deg"),
                    Column("peak", unit),
                    # (F1 a) without spaces: the moments table fits 100 columns
                    Column(f"peak / {per}" if what == "force" else f"peak/({per})"),
                ],
                rows,
                notes=notes,
            )
        )
    if result.roll is not None:
        parts.append(_roll_table(result))
    return parts


def _phasor_row(label: str, forward: complex, backward: complex, reference: float) -> list[str]:
    """A row of the free force or moment table: the forward and backward phasors'
    magnitudes and phases, the peak and the peak per ``reference``."""
    pair = np.array([forward, backward], dtype=np.complex128)
    size, phase = np.abs(pair), phase_deg(pair)
    peak = float(size.sum())
    return [
        label,
        format_number(float(size[0])),
        format_number(float(phase[0])),
        format_number(float(size[1])),
        format_number(float(phase[1])),
        format_number(peak),
        format_ratio(float(safe_ratio(peak, reference)), float(reference)),
    ]


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
