"""A self-contained HTML design review of a :class:`~balance.core.result.Result`.

One file, readable offline: inline CSS, figures as inline SVG (:mod:`balance.views.plots`), no
script, no external resource.  The tables read the result's complex phasors (magnitudes with
:func:`numpy.abs`, phases with :func:`balance.views.polar.phase_deg`) and normalise by its
stored references.  Every piece of text that comes from the result is escaped.

Sections (each an ``<section>`` with the ``id`` of :data:`SECTIONS`): the layout and the
assumptions of the analysis, the free forces, the free moments, the rotating force and
couple, the roll torque, the balancing proposal with its residual, and the model used with
its accuracy.
"""

from __future__ import annotations

import html
import math
import os
import re
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.accuracy import series_parameters
from balance.core.catalogue import CONVENTIONS, SCHEMA, speed_rpm
from balance.core.phasors import phase_deg, safe_ratio
from balance.core.sections import names
from balance.views import signals
from balance.views.polar import format_number
from balance.views.sections import VIEWS, view, views_of
from balance.views.signals import Quantity
from balance.views.table import NO_PITCH, format_ratio, pitch_text

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.result import Result

__all__ = [
    "SECTIONS",
    "accuracy_statement",
    "escape",
    "html_facts",
    "html_figure",
    "html_table",
    "render_report",
    "write_report",
]

#: Section ids and headings of the report that every analysis has, in order; the
#: sections of the analysis (the proposal, the mounts, the bearing loads…) come between
#: the roll and the model (:mod:`balance.views.sections`).
SECTIONS: tuple[tuple[str, str], ...] = (
    ("layout", "Layout and assumptions"),
    ("forces", "Free forces"),
    ("moments", "Free moments"),
    ("rotating", "Rotating force and couple"),
    ("roll", "Roll torque"),
    ("model", "Model and accuracy"),
)

_CSS = """
:root { color-scheme: light; }
body { font-family: "DejaVu Sans", "Helvetica Neue", Arial, sans-serif; margin: 0 auto;
  max-width: 1100px; padding: 1.5em 2em 3em; color: #1b1b1b; line-height: 1.45; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.3em; border-bottom: 2px solid #d0d7de; padding-bottom: 0.2em;
  margin-top: 2em; }
h3 { font-size: 1.05em; margin-top: 1.4em; }
p.meta { color: #555; margin-top: 0; }
nav ol { columns: 2; }
table { border-collapse: collapse; margin: 0.6em 0 1em; font-size: 0.9em; }
th, td { border: 1px solid #d0d7de; padding: 0.25em 0.6em; }
th { background: #f3f5f7; font-weight: 600; }
th.group { background: #e6ebf0; text-align: center; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.zero { color: #999; }
dl.facts { display: grid; grid-template-columns: max-content auto; gap: 0.2em 1em; }
dl.facts dt { font-weight: 600; }
dl.facts dd { margin: 0; }
figure { margin: 1em 0 1.6em; }
figure svg { max-width: 100%; height: auto; display: block; }
figcaption { color: #444; font-size: 0.9em; margin-top: 0.3em; }
.note { background: #fff8e1; border-left: 4px solid #f0b400; padding: 0.4em 0.8em; }
ul.notes { list-style: none; }
footer { margin-top: 3em; color: #666; font-size: 0.85em; }
@media print { nav { display: none; } section { break-inside: avoid-page; } }
"""


def escape(text: object) -> str:
    """Text for HTML: ``&``, ``<``, ``>`` and quotes escaped.

    Parameters
    ----------
    text : object
        Anything; its ``str()`` is escaped.

    Returns
    -------
    str
    """
    return html.escape(str(text), quote=True)


def _num(value: Any, scale: float = 1.0) -> str:
    """A number (float or numpy scalar) in compact engineering format."""
    return format_number(float(value) * scale)


def _ratio(value: Any, reference: float) -> str:
    """A normalised value, ``n/a`` where the reference is undefined (no pitch)."""
    return format_ratio(float(value), float(reference))


def html_table(
    headers: Sequence[str],
    rows: Iterable[Sequence[str]],
    caption: str = "",
    groups: Sequence[tuple[str, int]] = (),
) -> str:
    """An HTML table; headers and cells are plain text (escaped here).

    Parameters
    ----------
    headers : sequence of str
        The column headers.
    rows : iterable of sequence of str
        The cells, row by row.
    caption : str
        The table's caption (none when empty).
    groups : sequence of (str, int)
        An optional first header row of (label, number of columns) spans, labelling groups of
        columns (an empty label leaves its columns unlabelled).

    Returns
    -------
    str
        The ``<table>`` element.
    """
    out = ["<table>"]
    if caption:
        out.append(f"<caption>{escape(caption)}</caption>")
    out.append("<thead>")
    if groups:
        spans = "".join(
            f'<th colspan="{n}" class="group">{escape(label)}</th>'
            if n > 1
            else f"<th>{escape(label)}</th>"
            for label, n in groups
        )
        out.append(f"<tr>{spans}</tr>")
    out.append("<tr>" + "".join(f"<th>{escape(h)}</th>" for h in headers) + "</tr></thead>")
    out.append("<tbody>")
    for row in rows:
        cells = []
        for cell in row:
            css = "num zero" if cell in ("0", "-", "n/a") else "num"
            cells.append(f'<td class="{css}">{escape(cell)}</td>')
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</tbody></table>")
    return "\n".join(out)


def html_facts(items: Iterable[tuple[str, str]]) -> str:
    """A list of facts, each a name and its value, as an HTML description list.

    Parameters
    ----------
    items : iterable of (str, str)
        Names and values, plain text (escaped here).

    Returns
    -------
    str
        A ``<dl class="facts">`` element.
    """
    body = "".join(f"<dt>{escape(k)}</dt><dd>{escape(v)}</dd>" for k, v in items)
    return f'<dl class="facts">{body}</dl>'


_XML_PROLOG = re.compile(r"<\?xml[^>]*\?>\s*", re.S)
_DOCTYPE = re.compile(r"<!DOCTYPE[^>]*>\s*", re.S)
_COMMENT = re.compile(r"<!--.*?-->\s*", re.S)
_METADATA = re.compile(r"<metadata>.*?</metadata>\s*", re.S)
_ID = re.compile(r'\bid="([^"]+)"')
# a reference to an id, in the page's two forms; the name ends at the closing quote or
# parenthesis, and only the page's own ids are prefixed
_HREF = re.compile(r'(href="#)([^"]+)(")')
_URL = re.compile(r"(url\(#)([^)]+)(\))")


def _svg_fragment(svg: str, prefix: str) -> str:
    """Make a matplotlib SVG file fit to be inlined in an HTML page.

    Removes the XML prolog, the DOCTYPE (which names an external DTD), comments and
    metadata, and prefixes every ``id`` (and each reference to it) with ``prefix`` so that
    several figures can share one page.

    Parameters
    ----------
    svg : str
        The text of an SVG file.
    prefix : str
        Prefix for the ids, unique in the page.

    Returns
    -------
    str
        An ``<svg>`` element.
    """
    text = _XML_PROLOG.sub("", svg)
    text = _DOCTYPE.sub("", text)
    text = _COMMENT.sub("", text)
    text = _METADATA.sub("", text)
    ids = set(_ID.findall(text))
    if ids:
        text = _ID.sub(lambda m: f'id="{prefix}{m.group(1)}"', text)

        def prefixed(m: re.Match[str]) -> str:
            start, name, end = m.groups()
            return f"{start}{prefix}{name}{end}" if name in ids else m.group(0)

        text = _HREF.sub(prefixed, text)
        text = _URL.sub(prefixed, text)
    start = text.find("<svg")
    return text[start:].strip()


def html_figure(result: Result, kind: str, caption: str, number: int) -> str:
    """A figure of the result as inline SVG in a ``<figure>`` with its caption.

    Parameters
    ----------
    result : Result
        The analysis.
    kind : str
        The figure kind (:func:`balance.views.plots.plot_kind`).
    caption : str
        The caption, also the SVG's accessible label.
    number : int
        A number unique in the report, prefixed to the SVG's ids so that figures do not
        share them.

    Returns
    -------
    str
        The ``<figure>`` element.
    """
    from balance.views.plots import figure_bytes, plot_kind

    fig = plot_kind(kind)(result)
    svg = figure_bytes(fig, "svg").decode("utf-8")
    fragment = _svg_fragment(svg, f"f{number}-")
    label = f'role="img" aria-label="{escape(caption)}" '
    fragment = fragment.replace("<svg ", f"<svg {label}", 1)
    caption_html = f"<figcaption>{escape(caption)}</figcaption>"
    return f'<figure id="figure-{escape(kind)}">{fragment}{caption_html}</figure>'


def accuracy_statement(result: Result) -> str:
    """What the model of the analysis does and how accurate its numbers are.

    Uses the result's error bound (the bound on the normalised acceleration coefficients,
    see :mod:`balance.core.accuracy`) where the analysis recorded one.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.

    Returns
    -------
    str
        Plain text.
    """
    engine = result.engine
    model = str(result.model.name)
    ratio, x = series_parameters(engine)
    if model == "exact":
        text = (
            "Exact crank-slider kinematics: the Fourier coefficients of the piston "
            "acceleration are computed by FFT with the number of samples doubled until the "
            "aliased spectrum is below machine precision, so the phasors are as accurate as "
            "the floating-point arithmetic allows (checked in the test suite against a "
            "brute-force crank-angle computation)."
        )
    elif model == "series":
        terms = int(result.model.terms)
        text = (
            f"Binomial series of the conrod term in λ = r/l truncated after {terms} terms "
            f"(highest power λ^{2 * terms - 1}), with λ(1 + |e|/r) = {x:.4g}; the error "
            f"falls like x^(2n+1) with the number of terms n."
        )
    elif model == "textbook":
        text = (
            "Textbook model cos β + λ cos 2β: only orders 1 and 2, and the second order is "
            f"low by about λ²/4 = {ratio**2 / 4.0:.2%} relative (λ = r/l = {ratio:.4g}); "
            "orders 4, 6, ... and every effect of an offset are missing."
        )
    elif model == "time":
        samples = int(result.model.samples)
        text = (
            f"Crank-angle model: forces, moments and roll sampled at {samples} crank angles "
            "per revolution, summed as vectors and transformed by FFT; orders above half the "
            "samples alias into the reported ones."
        )
    else:
        text = f"Model {model!r}."
    if engine.has_links:
        text += " Link rods hang on master rods (docs/layout-format.md, 'Articulated rods'): " + (
            "their pistons and link pins follow the exact link kinematics."
            if model in ("exact", "time")
            else "this model treats each link piston as a plain slider on the crank pin "
            "and leaves out the link pins' motion (the idealised radial); its bound "
            "includes what that leaves out."
        )
    bound = float(result.model.error_bound)
    if math.isfinite(bound):
        force = bound * float(result.reference_force)
        text += (
            f" Error bound of the normalised acceleration coefficients: {bound:.2g} "
            f"(a force error of about {force:.2g} N per cylinder at m_rec r ω² = "
            f"{_num(result.reference_force)} N)."
        )
    text += (
        " Beyond the model: constant crank speed, rigid parts, inertia only (no gas forces), "
        "and only the listed orders."
    )
    return text


def _contents(result: Result) -> list[tuple[str, str]]:
    """The report's sections, ids and headings, in order: those every analysis has, with
    the analysis' sections (:mod:`balance.views.sections`) before the model: each one the
    result holds, and those that say what their absence means (``REPORT_ABSENT``: a
    design review without a proposal says so)."""
    own = []
    for ident in names():
        views = view(ident) if ident in VIEWS else None
        if views is None or getattr(views, "report_section", None) is None:
            continue
        if ident in result.parts or getattr(views, "REPORT_ABSENT", None) is not None:
            own.append((ident, views.REPORT_TITLE))
    return [*SECTIONS[:-1], *own, SECTIONS[-1]]


def _version() -> str:
    from balance._version import __version__

    return str(__version__)


def _header(result: Result) -> str:
    engine = result.engine
    meta = (
        f"{engine.n_cylinders} cylinders, {speed_rpm(engine.speed):g} "
        f"rpm, {engine.cycle}; model {result.model.name}; "
        f"balance {_version()}, schema {SCHEMA}"
    )
    toc = "".join(f'<li><a href="#{i}">{escape(t)}</a></li>' for i, t in _contents(result))
    return (
        f"<header><h1>Balance design review: {escape(engine.name)}</h1>"
        f'<p class="meta">{escape(meta)}</p></header>'
        f'<nav aria-label="contents"><ol>{toc}</ol></nav>'
    )


def _layout_section(result: Result, figures: bool) -> str:
    engine = result.engine
    facts = [
        ("speed", f"{speed_rpm(engine.speed):g} rpm ({_num(engine.speed)} rad/s)"),
        ("cycle", str(engine.cycle)),
        ("firing order", ",".join(map(str, engine.firing_order or ())) or "not given"),
        ("moments about", f"z = {_num(engine.reference_z, 1e3)} mm on the crank axis"),
        ("cylinder pitch a", pitch_text(float(result.pitch))),
        ("F1 = m_rec r ω²", f"{_num(result.reference_force)} N"),
        (
            "F1 a",
            f"{_num(result.reference_moment)} N m"
            if math.isfinite(float(result.reference_moment))
            else "n/a (no pitch)",
        ),
        ("source file", str(engine.path or "") or "-"),
    ]
    headers = [
        "cylinder",
        "throw [deg]",
        "bank [deg]",
        "z [mm]",
        "crank radius [mm]",
        "conrod [mm]",
        "offset [mm]",
        "m_rec [kg]",
        "m_rot [kg]",
        "rod inertia corr. [kg m²]",
    ]
    # the columns the sections add (each cylinder's dead centres), then the link rods
    columns = [
        column
        for _, views in views_of(result)
        for column in getattr(views, "report_columns", lambda result: [])(result)
    ]
    headers += [header for header, _ in columns]
    links = engine.links
    if links is not None:
        headers.append("link rod")
    throw = np.degrees(np.asarray(engine.throw, dtype=np.float64))
    bank = np.degrees(np.asarray(engine.bank, dtype=np.float64))
    rows = []
    for i in range(engine.n_cylinders):
        rows.append(
            [
                str(i + 1),
                _num(throw[i]),
                _num(bank[i]),
                _num(engine.z[i], 1e3),
                _num(engine.crank_radius[i], 1e3),
                _num(engine.conrod_length[i], 1e3),
                _num(engine.offset[i], 1e3),
                _num(engine.reciprocating_mass[i]),
                _num(engine.rotating_mass[i]),
                _num(engine.conrod_inertia_correction[i]),
            ]
        )
        rows[-1] += [cells[i] for _, cells in columns]
        if links is not None:
            m = int(links.master[i])
            rows[-1].append(
                f"on cylinder {m + 1}'s rod: pin {_num(links.pin_radius[i], 1e3)} mm at "
                f"{_num(np.degrees(links.pin_angle[i]))} deg, "
                f"rod {_num(engine.conrod_length[i], 1e3)} mm"
                if m >= 0
                else "-"
            )
    assumptions = [
        "Constant crank speed; crank, conrods and block rigid.",
        "Each conrod is split into a reciprocating mass at the piston pin and a rotating "
        "mass at the crank pin (static equivalence, exact for the forces); the roll torque "
        "adds the difference between the rod's real moment of inertia and that model's.",
        "Inertia forces only: gas pressure does not shake the block as a whole and is not "
        "part of these free forces and moments.",
        "Shaking forces are those the moving parts put on the block (-m a); angles are "
        "measured from +y (up) in the direction of rotation, crank angle 0 with throw 1 at "
        "+y; a transverse vector (x, y) is the complex number y + i x.",
        f"Orders {_orders_text(result.orders)} are reported; higher ones are left out.",
    ]
    items = "".join(f"<li>{escape(a)}</li>" for a in assumptions)
    out = [
        html_facts(facts),
        "<h3>Cylinders</h3>",
        html_table(headers, rows),
        f"<h3>Assumptions</h3><ul>{items}</ul>",
    ]
    if figures:
        out.append(
            html_figure(
                result,
                "crank_star",
                "Crank star seen from the front (+y up, +x right, crank turning clockwise): "
                "throws with the cylinders on them, and the banks.",
                1,
            )
        )
    return "\n".join(out)


def _orders_text(orders: Iterable[float]) -> str:
    values = [float(k) for k in orders]
    if not values:
        return "none"
    return (
        f"{values[0]:g} to {values[-1]:g}"
        if len(values) > 2
        else ", ".join(f"{k:g}" for k in values)
    )


NOT_COMPUTED = (
    '<p class="note">{what} not computed in this analysis ({option}); '
    "the figures leave them out.</p>"
)


def _phasor_section(result: Result, quantity: Quantity, figures: bool) -> str:
    if quantity == "moment" and not signals.has_moments(result):
        return NOT_COMPUTED.format(what="Moments were", option="moments=False")
    unit = "N" if quantity == "force" else "N m"
    per = "F1" if quantity == "force" else "F1 a"
    reference = float(result.reference_force if quantity == "force" else result.reference_moment)
    bundle = result.phasors  # the reciprocating inertia; free() adds the rotating masses
    orders = bundle.orders
    size, phase = bundle.magnitude(quantity), bundle.phase(quantity)
    peak = bundle.peak(quantity)
    free_peak = bundle.free().peak(quantity)
    norm_peak = safe_ratio(peak, reference)
    norm_free = safe_ratio(free_peak, reference)
    headers = [
        "order",
        f"forward [{unit}]",
        "phase [deg]",
        f"backward [{unit}]",
        "phase [deg]",
        f"peak [{unit}]",
        f"peak / {per}",
        f"peak [{unit}]",
        f"peak / {per}",
    ]
    rows = [
        [
            str(int(k)),
            _num(size[i, 0]),
            _num(phase[i, 0]),
            _num(size[i, 1]),
            _num(phase[i, 1]),
            _num(peak[i]),
            _ratio(norm_peak[i], reference),
            _num(free_peak[i]),
            _ratio(norm_free[i], reference),
        ]
        for i, k in enumerate(orders)
    ]
    groups = [
        ("", 1),
        ("reciprocating inertia", 6),
        ("free: reciprocating + rotating (the figures)", 2),
    ]
    what = (
        "Reciprocating inertia forces on the block, per order"
        if quantity == "force"
        else "Reciprocating inertia moments Σ (z_i − z_ref) F_i about reference_z, per order "
        "(drawn along the force; the couple is this turned by −90° about z)"
    )
    reference_text = (
        f"{_num(reference)} {unit}"
        if math.isfinite(reference) and reference != 0.0
        else f"n/a: pitch a = {NO_PITCH}"
    )
    out = [
        f"<p>{escape(what)}. Forward phasors turn with the crank, backward ones against it; "
        f"the peak over a revolution is |forward| + |backward|. The free {quantity} adds "
        f"the centrifugal {quantity} of the rotating masses to order 1 (forward); the "
        f"figures draw the free {quantity}. {escape(per)} = {escape(reference_text)}.</p>",
        html_table(headers, rows, groups=groups),
    ]
    if figures and quantity == "force":
        out.append(
            html_figure(
                result,
                "spectrum",
                "Peak free force and moment per order (reciprocating + rotating).",
                2,
            )
        )
        out.append(
            html_figure(
                result,
                "locus",
                "Path of the free force and moment vectors over a revolution, seen from the "
                "front: per order (ellipses) and total; o marks crank angle 0.",
                3,
            )
        )
    # the phasor and crank-angle figures go with the moments, or with the forces without them
    if figures and (quantity == "moment" or not signals.has_moments(result)):
        out.append(
            html_figure(
                result,
                "phasors",
                "Phasors at crank angle 0 (0° up, clockwise = direction of rotation) of the "
                "free force and moment (reciprocating + rotating), one panel per order, each "
                "on its own scale: forward wide, backward dashed.",
                4,
            )
        )
        out.append(
            html_figure(
                result,
                "crank_angle",
                "Free force components and pitch/yaw couples over a revolution, total and "
                "per order.",
                5,
            )
        )
    return "\n".join(out)


def _rotating_section(result: Result) -> str:
    p = result.phasors
    rows = [
        [
            "force [N]",
            _num(abs(p.rotating_force)),
            _num(phase_deg(p.rotating_force)),
            _num(safe_ratio(abs(p.rotating_force), result.reference_force)),
        ],
    ]
    if signals.has_moments(result):
        rows.append(
            [
                "moment [N m]",
                _num(abs(p.rotating("moment"))),
                _num(phase_deg(p.rotating("moment"))),
                _ratio(
                    safe_ratio(abs(p.rotating("moment")), result.reference_moment),
                    float(result.reference_moment),
                ),
            ]
        )
    return "\n".join(
        [
            "<p>Centrifugal force of the rotating masses (order 1, forward only): a mass turning "
            "with the crank (a counterweight) can cancel it.</p>",
            html_table(
                ["quantity [unit]", "magnitude", "phase [deg]", "per F1 (force) / F1 a (moment)"],
                rows,
            ),
        ]
    )


def _roll_section(result: Result, figures: bool) -> str:
    if not signals.has_roll(result):
        return NOT_COMPUTED.format(what="The roll torque was", option="roll=False")
    proposal = signals.has_proposal(result)
    headers = ["order", "amplitude [N m]", "phase [deg]", "per m_rec r² ω²"]
    if proposal:
        headers += ["with shafts [N m]", "phase [deg]"]
    orders, roll = signals.roll_of(result)
    amplitude, phase = np.abs(roll), phase_deg(roll)
    normalised = safe_ratio(amplitude, result.reference_roll)
    if proposal:
        _, residual = signals.roll_of(result, residual=True)
        residual_amplitude, residual_phase = np.abs(residual), phase_deg(residual)
    rows = []
    for i, k in enumerate(orders):
        row = [
            f"{float(k):g}",
            _num(amplitude[i]),
            _num(phase[i]),
            _ratio(normalised[i], float(result.reference_roll)),
        ]
        if proposal:
            row += [_num(residual_amplitude[i]), _num(residual_phase[i])]
        rows.append(row)
    out = [
        "<p>Torque about the crank axis that the block receives from the inertia of the "
        "pistons and conrods, positive in the direction of rotation: Σ a_k cos(k θ + phase_k)."
        "</p>",
        html_table(headers, rows),
    ]
    if figures:
        out.append(html_figure(result, "roll", "Roll torque over a revolution and per order.", 6))
    return "\n".join(out)


def _model_section(result: Result) -> str:
    model = str(result.model.name)
    facts = [("piston acceleration model", model)]
    if model == "series":
        facts.append(("series terms", str(int(result.model.terms))))
    facts += [
        ("conventions", CONVENTIONS),
        ("result schema", SCHEMA),
        ("balance version", _version()),
    ]
    return f"{html_facts(facts)}\n<p>{escape(accuracy_statement(result))}</p>"


def render_report(result: Result, *, figures: bool = True) -> str:
    """The design review of a result as one self-contained HTML page.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    figures : bool
        Include the figures (inline SVG); without them the report is tables only.

    Returns
    -------
    str
        An HTML5 document: inline CSS and SVG, no script, no external resource.
    """
    name = str(result.engine.name)
    shown = _contents(result)
    bodies = {
        "layout": _layout_section(result, figures),
        "forces": _phasor_section(result, "force", figures),
        "moments": _phasor_section(result, "moment", figures),
        "rotating": _rotating_section(result),
        "roll": _roll_section(result, figures),
        "model": _model_section(result),
    }
    for ident, _ in shown:
        if ident not in bodies:
            views = view(ident)
            bodies[ident] = (
                views.report_section(result, figures)
                if ident in result.parts
                else f'<p class="note">{escape(views.REPORT_ABSENT)}</p>'
            )
    sections = "\n".join(
        f'<section id="{ident}">\n<h2>{n}. {escape(heading)}</h2>\n{bodies[ident]}\n</section>'
        for n, (ident, heading) in enumerate(shown, start=1)
    )
    return (
        "<!DOCTYPE html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>Balance design review: {escape(name)}</title>\n"
        f"<style>{_CSS}</style>\n</head>\n<body>\n"
        f"{_header(result)}\n<main>\n{sections}\n</main>\n"
        f"<footer>Generated by balance {escape(_version())} from the "
        "analysis result; all values in SI units unless stated, angles in degrees.</footer>\n"
        "</body>\n</html>\n"
    )


def write_report(
    result: Result, path: str | os.PathLike[str], *, force: bool = False, figures: bool = True
) -> Path:
    """Write the HTML design review of a result to ``path``, atomically.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    path : path
        The HTML file to write.
    force : bool
        Replace an existing file.
    figures : bool
        Include the figures.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    InputError
        If the file exists (without ``force``) or its directory cannot be written.
    """
    from balance.io.atomic import check_target, write_atomic

    target = Path(path)
    check_target(target, force)  # fail before the figures are drawn
    data = render_report(result, figures=figures).encode("utf-8")
    return write_atomic(target, data, force)
