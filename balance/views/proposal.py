"""Views of the ``proposal`` section: the counterweights and balance shafts proposed, and
what remains with them (:mod:`balance.core.proposal`): JSON, tables, the report's section
and the figure ``balance``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.errors import InputError
from balance.core.phasors import phase_deg, safe_ratio
from balance.core.shafts import SHAFT_CLEARANCE
from balance.views.json import roll_entries
from balance.views.polar import format_number, json_number

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure
    from rich.console import RenderableType

    from balance.core.balancing import Proposal
    from balance.core.proposal import ProposalResult
    from balance.core.result import Result
    from balance.views.figures import AxesArg

__all__ = [
    "PLOTS",
    "REPORT_ABSENT",
    "REPORT_TITLE",
    "json_block",
    "plot_balance",
    "proposal_summary",
    "report_section",
    "tables",
]


def _part(result: Result) -> ProposalResult:
    part: ProposalResult = result.part("proposal")
    return part


def _proposal_entries(proposal: Proposal) -> dict[str, Any]:
    """The proposal's settings, notes, counterweights and balance shafts as JSON data."""
    counterweights = [
        {
            "z_m": json_number(c.z),
            "mass_kg": json_number(c.mass),
            "radius_m": json_number(c.radius),
            "angle_deg": json_number(c.angle_deg),
        }
        | ({"crankshaft": c.axis} if c.axis is not None else {})
        for c in proposal.counterweights
    ]
    shafts = []
    for s in proposal.shafts:
        unbalance = np.array([u for _, u in s.planes], dtype=np.complex128)
        angle = phase_deg(unbalance)
        planes = [
            {
                "z_m": float(z),
                "unbalance_kgm": json_number(np.abs(unbalance[j])),
                "angle_deg": json_number(angle[j]),
            }
            for j, (z, _) in enumerate(s.planes)
        ]
        shafts.append(
            {
                "speed_ratio": int(s.speed_ratio),
                "x_m": json_number(s.x),
                "y_m": json_number(s.y),
                "position_from": {"x": s.x_from, "y": s.y_from},
                "planes": planes,
            }
        )
    factor = proposal.balance_factor
    given = proposal.factor
    one = given.one_cylinder if given is not None else None
    return {
        "strategy": proposal.strategy,
        "orders": [int(k) for k in proposal.orders],
        "balance_factor": None if factor is None else float(factor),
        "balance_factor_one_cylinder": None if one is None else float(one),
        "balance_factor_of": None if given is None else given.given.of,
        "balance_factor_convention": None if given is None else given.describe(),
        "cancel_roll": bool(proposal.cancel_roll),
        "notes": [n for n in proposal.notes if n],
        "counterweights": counterweights,
        "balance_shafts": shafts,
    }


def _residual_peaks(result: Result, quantity: Any, reference: float) -> list[dict[str, Any]]:
    residual = _part(result).residual
    peak = residual.peak(quantity)
    normalised = safe_ratio(peak, reference)
    return [
        {
            "order": int(k),
            "peak": json_number(peak[i]),
            "peak_normalised": json_number(normalised[i]),
        }
        for i, k in enumerate(np.asarray(residual.orders))
    ]


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``proposal`` with its ``residual``.

    Parameters
    ----------
    result : Result
        An analysis with the ``proposal`` section.

    Returns
    -------
    dict
        The counterweights, balance shafts and notes, and the residual force and moment peaks
        and roll per order.
    """
    part = _part(result)
    residual: dict[str, Any] = {
        "force": _residual_peaks(result, "force", result.reference_force),
        "moment": _residual_peaks(result, "moment", result.reference_moment),
        "roll": roll_entries(result.roll_orders, part.residual_roll),
    }
    if part.residual_moment_z is not None:  # several crankshafts
        residual["moment_z"] = [
            {"order": int(k), "peak": json_number(abs(part.residual_moment_z[i]))}
            for i, k in enumerate(np.asarray(part.residual.orders))
        ]
    return {
        "proposal": _proposal_entries(part.proposal)
        | {
            "orders_left": [int(k) for k in part.left],
            "shaft_default_axes": _default_rule(result),
            "residual": residual,
        }
    }


def _default_rule(result: Result) -> str | None:
    """Where the default shaft axes are and why, when a shaft has a coordinate there (None
    otherwise; :func:`balance.core.shafts.default_axes`)."""
    if not any("default" in (s.x_from, s.y_from) for s in _part(result).proposal.shafts):
        return None
    r = float(np.mean(result.engine.crank_radius))
    c = SHAFT_CLEARANCE * r
    return (
        f"default axes: {c * 1e3:.4g} mm ({SHAFT_CLEARANCE:g} r) from the crank axis, below it, "
        f"a pair 30° either side of straight down (x = ∓{r * 1e3:.4g} mm): within the crank "
        "train's reach; to place them elsewhere, give their axes in the layout's balance: shafts:"
    )


def _listed(orders: Any) -> str:
    return ",".join(map(str, orders))


def _cancelled(part: ProposalResult) -> str:
    """The orders asked for and, where the residual keeps some of them, which."""
    asked = _listed(part.proposal.orders)
    if not part.left:
        return f"cancelling orders {asked}"
    plural = "orders" if len(part.proposal.orders) != 1 else "order"
    which = "order" if len(part.left) == 1 else "orders"
    return (
        f"asked to cancel {plural} {asked}; {which} {_listed(part.left)} not cancelled in full "
        "(see the notes)"
    )


def _roll_choice(proposal: Proposal) -> str:
    """What ``cancel_roll`` did, in a few words ("" where it was not asked)."""
    if not proposal.cancel_roll:
        return ""
    placed = sum("cancel-roll" in (s.x_from, s.y_from) for s in proposal.shafts)
    if placed:
        return f"cancel_roll: {placed} shaft{'s' if placed != 1 else ''} placed for the roll"
    return "cancel_roll: no shaft moved (see the notes)"


def _choices(part: ProposalResult) -> str:
    """The proposal's header: strategy, the orders (and those left), the balance factor
    with its convention, what cancel_roll did."""
    proposal = part.proposal
    text = f"strategy {proposal.strategy}, {_cancelled(part)}"
    if proposal.factor is not None:
        text += f", balance factor {proposal.factor.stated()}"
    roll = _roll_choice(proposal)
    return f"{text}, {roll}" if roll else text


def _render_proposal(result: Result) -> list[RenderableType]:
    """Rich renderables of the balancing proposal and its residual: a line of the choices,
    the proposal's notes (one line each), the counterweights, the balance shafts and the
    residual."""
    from rich.text import Text

    from balance.views.fitted import Column, NumberTable
    from balance.views.table import format_ratio, pitch_note

    part = _part(result)
    proposal = part.proposal
    out: list[RenderableType] = [Text(f"Proposal: {_choices(part)}", style="bold")]
    out.extend(Text(f"Note: {note}") for note in proposal.notes if note)
    cws = proposal.counterweights
    shafts = proposal.shafts
    if not cws and not shafts:
        out.append(Text("Nothing to cancel: no counterweights or balance shafts are needed."))
    if cws:
        geared = any(c.axis is not None for c in cws)
        columns = [
            Column("z", "mm"),
            Column("mass", "kg"),
            Column("radius", "mm"),
            Column("angle", "deg"),
            Column("m R", "kg mm"),
        ]
        rows = [
            [
                format_number(float(c.z) * 1e3),
                format_number(float(c.mass)),
                format_number(float(c.radius) * 1e3),
                format_number(float(c.angle_deg)),
                format_number(abs(c.unbalance) * 1e3),
            ]
            for c in cws
        ]
        title = "Counterweights (turn with the crank; angle at theta = 0)"
        if geared:  # each on its crankshaft, turning with it
            columns.insert(0, Column("crankshaft", justify="left"))
            rows = [[str(c.axis), *row] for c, row in zip(cws, rows, strict=True)]
            title = "Counterweights (turn with their crankshaft; engine-frame angle at theta = 0)"
        out.append(NumberTable(title, columns, rows))
    if shafts:
        rows = []
        for i, shaft in enumerate(shafts):
            unbalance = np.array([u for _, u in shaft.planes], dtype=np.complex128)
            angle = phase_deg(unbalance)
            for j, (z, _) in enumerate(shaft.planes):
                first = j == 0
                rows.append(
                    [
                        str(i + 1) if first else "",
                        f"{int(shaft.speed_ratio):+d}" if first else "",
                        format_number(float(shaft.x) * 1e3) if first else "",
                        format_number(float(shaft.y) * 1e3) if first else "",
                        format_number(float(z) * 1e3),
                        format_number(float(np.abs(unbalance[j])) * 1e3),
                        format_number(float(angle[j])),
                    ]
                )
        out.append(
            NumberTable(
                "Balance shafts (eccentric mass at angle + speed ratio x theta)",
                [
                    Column("shaft", key=True),
                    Column("speed ratio"),
                    Column("x", "mm"),
                    Column("y", "mm"),
                    Column("plane z", "mm"),
                    Column("m e", "kg mm"),
                    Column("angle", "deg"),
                ],
                rows,
                notes=tuple(n for n in [_default_rule(result)] if n),
            )
        )
    force_peak = part.residual.peak("force")
    moment_peak = part.residual.peak("moment")
    force_normalised = safe_ratio(force_peak, result.reference_force)
    moment_normalised = safe_ratio(moment_peak, result.reference_moment)
    roll_at = {float(k): i for i, k in enumerate(result.roll_orders)}
    assert part.residual_roll is not None  # a proposal is made with the roll
    roll_amplitude = np.abs(part.residual_roll)
    moment_z = part.residual_moment_z
    rows = []
    for i, k in enumerate(result.phasors.orders):
        at = roll_at.get(float(k))
        row = [
            str(int(k)),
            format_number(float(force_peak[i])),
            format_ratio(float(force_normalised[i]), float(result.reference_force)),
            format_number(float(moment_peak[i])),
            format_ratio(float(moment_normalised[i]), float(result.reference_moment)),
        ]
        if moment_z is not None:
            row.append(format_number(float(abs(moment_z[i]))))
        row.append("-" if at is None else format_number(float(roll_amplitude[at])))
        rows.append(row)
    columns = [
        Column("order", key=True),
        Column("force peak", "N"),
        Column("force peak / F1"),
        Column("moment peak", "N m"),
        Column("moment peak / (F1 a)"),
        *([Column("moment z peak", "N m")] if moment_z is not None else []),
        Column("roll", "N m"),
    ]
    out.append(
        NumberTable(
            "Residual with the proposal: free (reciprocating + rotating) + proposal; roll",
            columns,
            rows,
            notes=pitch_note(result),
        )
    )
    return out


def tables(result: Result) -> list[RenderableType]:
    """The section's tables: a line of the choices, the proposal's notes, the counterweights,
    the balance shafts and the residual.

    Parameters
    ----------
    result : Result
        An analysis with the ``proposal`` section.

    Returns
    -------
    list of rich.console.RenderableType
    """
    return _render_proposal(result)


#: The heading of the section in the HTML report.
REPORT_TITLE = "Balancing proposal and residual"

#: What the report says where the analysis has no proposal.
REPORT_ABSENT = "No balancing proposal in this result (analysed without one)."


def _num(value: Any, scale: float = 1.0) -> str:
    """A number (float or numpy scalar) as the report prints it."""
    return format_number(float(value) * scale)


def _ratio(value: Any, reference: float) -> str:
    """A normalised value, ``n/a`` where the reference is undefined (no pitch)."""
    from balance.views.table import format_ratio

    return format_ratio(float(value), float(reference))


def report_section(result: Result, figures: bool) -> str:
    """HTML of the report's proposal section: its settings, notes, masses and the residual.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`, with the ``proposal`` section.
    figures : bool
        Include the ``balance`` figure (inline SVG).

    Returns
    -------
    str
        HTML of the section's body (:func:`balance.views.report.render_report` adds its
        heading).
    """
    from balance.views.report import escape, html_facts, html_figure, html_table
    from balance.views.signals import roll_of

    part = _part(result)
    proposal = part.proposal
    factor = proposal.factor
    facts = [
        ("strategy", str(proposal.strategy)),
        ("orders to cancel", _listed(proposal.orders)),
        (
            "orders not cancelled in full",
            _listed(part.left) + " (see the notes)" if part.left else "none",
        ),
        ("balance factor", "-" if factor is None else factor.describe()),
        ("roll", _roll_choice(proposal) or "cancel_roll not asked"),
    ]
    out = [html_facts(facts)]
    notes = [note for note in proposal.notes if note]
    if notes:  # the proposal's remarks, one per line
        items = "".join(f"<li>{escape(note)}</li>" for note in notes)
        out.append(f'<ul class="note notes">{items}</ul>')
    out.append("<h3>Counterweights (turn with the crank)</h3>")
    if proposal.counterweights:
        rows = [
            [
                _num(c.z, 1e3),
                _num(c.mass),
                _num(c.radius, 1e3),
                _num(c.angle_deg),
                _num(abs(c.unbalance), 1e3),
            ]
            for c in proposal.counterweights
        ]
        head = ["z [mm]", "mass [kg]", "radius [mm]", "angle at θ = 0 [deg]", "m R [kg mm]"]
        if any(c.axis is not None for c in proposal.counterweights):  # several crankshafts
            head = ["crankshaft", *head]
            rows = [
                [str(c.axis), *row] for c, row in zip(proposal.counterweights, rows, strict=True)
            ]
        out.append(html_table(head, rows))
    else:
        out.append("<p>None needed.</p>")
    out.append("<h3>Balance shafts</h3>")
    if proposal.shafts:
        rows = []
        for i, shaft in enumerate(proposal.shafts):
            for j, (z, unbalance) in enumerate(shaft.planes):
                first = j == 0
                rows.append(
                    [
                        str(i + 1) if first else "",
                        f"{float(shaft.speed_ratio):+g}" if first else "",
                        _num(shaft.x, 1e3) if first else "",
                        _num(shaft.y, 1e3) if first else "",
                        _num(z, 1e3),
                        _num(abs(unbalance), 1e3),
                        _num(phase_deg(unbalance)),
                    ]
                )
        out.append(
            html_table(
                [
                    "shaft",
                    "speed ratio",
                    "x [mm]",
                    "y [mm]",
                    "plane z [mm]",
                    "m e [kg mm]",
                    "angle at θ = 0 [deg]",
                ],
                rows,
            )
        )
        rule = _default_rule(result)
        if rule:
            out.append(f'<p class="note">{escape(rule)}</p>')
    else:
        out.append("<p>None needed.</p>")
    out.append("<h3>Residual with the proposal</h3>")
    orders = result.phasors.orders
    free = result.phasors.free()
    free_force, free_moment = free.peak("force"), free.peak("moment")
    residual_force, residual_moment = part.residual.peak("force"), part.residual.peak("moment")
    force_per = safe_ratio(residual_force, result.reference_force)
    moment_per = safe_ratio(residual_moment, result.reference_moment)
    roll_orders, roll = roll_of(result)
    _, residual_roll = roll_of(result, residual=True)
    at = {float(k): j for j, k in enumerate(roll_orders)}
    rows = []
    for i, k in enumerate(orders):
        r = at.get(float(k))
        rows.append(
            [
                str(int(k)),
                _num(free_force[i]),
                _num(residual_force[i]),
                _ratio(force_per[i], float(result.reference_force)),
                _num(free_moment[i]),
                _num(residual_moment[i]),
                _ratio(moment_per[i], float(result.reference_moment)),
                _num(abs(roll[r])) if r is not None else "-",
                _num(abs(residual_roll[r])) if r is not None else "-",
            ]
        )
    out.append(
        "<p>Peaks per order before (free: reciprocating + rotating) and after the proposal "
        "(residual: with every proposed mass), and the roll amplitude without and with the "
        "balance shafts.</p>"
    )
    out.append(
        html_table(
            [
                "order",
                "force before [N]",
                "force after [N]",
                "after / F1",
                "moment before [N m]",
                "moment after [N m]",
                "after / (F1 a)",
                "roll before [N m]",
                "roll after [N m]",
            ],
            rows,
        )
    )
    if figures:
        out.append(
            html_figure(
                result,
                "balance",
                "Before (free: reciprocating + rotating) and after the proposal (residual).",
                7,
            )
        )
    return "\n".join(out)


# --------------------------------------------------------------------------- figures


def plot_balance(
    result: Result,
    *,
    ax: AxesArg = None,
    normalised: bool = False,
    samples: int = 721,
    title: str | None = None,
) -> Figure:
    """The free force, moment and roll before and after the proposed balancing.

    Top: the size of the force and moment vectors and the roll torque over a revolution
    (before dashed grey, after solid); bottom: the peak of each order before and after.
    "Before" is the free force and moment (reciprocating + rotating); "after" the residual
    with every proposed counterweight and balance-shaft mass.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute` with a proposal (``proposal=True``).
    ax : sequence of 6 Axes, optional
        Axes in two rows of three (force, moment, roll); a new figure otherwise.
    normalised : bool
        Force and moment per ``reference_force`` and ``reference_moment`` [1].
    samples : int
        Crank angles over the revolution.
    title : str, optional
        Figure title; by default the layout name and the proposal.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        If the result holds no proposal.
    """
    from balance.views import signals
    from balance.views.figures import (
        BEFORE_COLOUR,
        axis_label,
        degree_axis,
        denoise,
        finish,
        layout_heading,
        new_figure,
        order_bars,
        scale_of,
        styled,
    )

    if not signals.has_proposal(result):
        raise InputError(
            "plot_balance: this result has no balancing proposal; analyse with the proposal "
            "enabled (Request(proposal=True), the default, with moments and roll)"
        )
    theta = signals.crank_angle_grid(samples)
    with styled():
        fig, axes_list, owned = new_figure(ax, 6, (13.0, 7.6), nrows=2, kind="balance")
        for col, quantity in enumerate(signals.QUANTITIES):
            divisor, unit, _ = scale_of(result, quantity, normalised)
            ks, bf, bb = signals.phasors_of(result, quantity, "free")
            _, af, ab = signals.phasors_of(result, quantity, "residual")
            before_peak = signals.peak_of(result, quantity, "free")
            after_peak = signals.peak_of(result, quantity, "residual")
            reference = float(np.nansum(before_peak)) / divisor
            n_terms = 2 * ks.size
            before = denoise(signals.phasor_signal(bf, bb, ks, theta) / divisor, reference, n_terms)
            after = denoise(signals.phasor_signal(af, ab, ks, theta) / divisor, reference, n_terms)
            name = "force |F|" if quantity == "force" else "moment |Σ Δz·F|"
            top = axes_list[col]
            degree_axis(top)
            top.plot(
                theta,
                np.abs(before),
                color=BEFORE_COLOUR,
                ls="--",
                lw=1.8,
                label="before (free)",
                zorder=3,
            )
            top.plot(theta, np.abs(after), color=f"C{col}", lw=2.2, label="after (residual)")
            top.set_ylim(bottom=0.0)
            top.set_title(name)
            top.set_ylabel(axis_label(name, unit))
            top.legend(loc="upper right")
            bottom = axes_list[3 + col]
            order_bars(
                bottom,
                ks,
                [
                    (before_peak / divisor, BEFORE_COLOUR, "before"),
                    (after_peak / divisor, f"C{col}", "after"),
                ],
            )
            bottom.set_ylabel(axis_label("peak", unit))
            bottom.legend(loc="upper right")
        rk, roll = signals.roll_of(result)
        _, residual_roll = signals.roll_of(result, residual=True)
        ra, qa = np.abs(roll), np.abs(residual_roll)
        span = signals.roll_span_deg(rk)
        roll_theta = signals.crank_angle_grid(samples, span)
        top = axes_list[2]
        degree_axis(top, span)
        roll_reference = float(np.nansum(ra))
        top.plot(
            roll_theta,
            denoise(signals.roll_signal(roll, rk, roll_theta), roll_reference, rk.size),
            color=BEFORE_COLOUR,
            ls="--",
            lw=1.8,
            label="before",
            zorder=3,
        )
        top.plot(
            roll_theta,
            denoise(signals.roll_signal(residual_roll, rk, roll_theta), roll_reference, rk.size),
            color="C4",
            lw=2.2,
            label="after (with shafts)",
        )
        top.set_title("roll torque")
        top.set_ylabel("roll torque [N m]")
        top.legend(loc="upper right")
        order_bars(axes_list[5], rk, [(ra, BEFORE_COLOUR, "before"), (qa, "C4", "after")])
        axes_list[5].set_ylabel("roll amplitude [N m]")
        axes_list[5].legend(loc="upper right")
        return finish(fig, owned, title, f"{layout_heading(result)}: {proposal_summary(result)}")


def proposal_summary(result: Result) -> str:
    """One line describing the proposal of a result (strategy, orders, masses), as the
    ``balance`` figure's title and the docs' gallery give it.

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    str
        ``"no balancing proposal"`` when the result has none.
    """
    part = result.part("proposal")
    if part is None:
        return "no balancing proposal"
    proposal = part.proposal
    n_cw = len(proposal.counterweights)
    n_shaft = len(proposal.shafts)
    parts = [
        f"{n_cw} counterweight{'s' if n_cw != 1 else ''}",
        f"{n_shaft} balance shaft{'s' if n_shaft != 1 else ''}",
    ]
    orders = _listed(proposal.orders)
    if part.left:
        orders += f" ({_listed(part.left)} in part)"
    factor = "" if proposal.factor is None else f", balance factor {proposal.factor.stated()}"
    roll = _roll_choice(proposal)
    roll = f", {roll}" if roll else ""
    return f"balancing {proposal.strategy}, orders {orders}{factor}{roll}: {' and '.join(parts)}"


#: The figure kinds of the section.
PLOTS = {"balance": plot_balance}
