"""Tables and figures of the studies' results: a crank-arrangement search
(:mod:`balance.studies.search`) and a tolerance study (:mod:`balance.studies.tolerance`).

The results are read by their attributes (a view never imports a study).  The tables are
:class:`~balance.views.fitted.NumberTable`: no number is ever cut, whatever the width.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from balance.views.fitted import Column, NumberTable
from balance.views.table import format_number

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure
    from rich.console import RenderableType

__all__ = [
    "figure_metadata",
    "search_tables",
    "tolerance_histogram",
    "tolerance_tables",
]

#: Units of the scattered values as the study holds them (SI; degrees for angles).
_UNITS = {"mass": "kg", "length": "m", "angle": "deg", "speed": "rad/s"}


def search_tables(result: Any) -> list[RenderableType]:
    """What ``balance search`` prints: a summary, then the best arrangements ranked.

    Peaks are normalised (per :math:`F_1` and :math:`F_1 a`), after counterweights.

    Parameters
    ----------
    result : SearchResult
        The search (:func:`balance.studies.search.search`).

    Returns
    -------
    list of rich.console.RenderableType
    """
    from rich.text import Text

    orders = list(result.orders)
    split = any(any(a.splits) for a in result.best)
    columns = [Column("rank", key=True), Column("throws", "deg", justify="left")]
    if split:
        columns.append(Column("split", "deg", justify="left"))
    columns += [Column("score"), Column("shafts")]
    for k in orders:
        columns += [Column(f"order {k} force", "F1"), Column(f"order {k} moment", "F1 a")]
    columns.append(Column("firing order", justify="left"))
    rows = []
    for rank, a in enumerate(result.best, 1):
        row = [str(rank), "/".join(f"{t:g}" for t in a.throws)]
        if split:
            row.append("/".join(f"{s:g}" for s in a.splits))
        row += [format_number(a.score), str(a.shafts)]
        for f, m in zip(a.force_peaks, a.moment_peaks, strict=True):
            row += [format_number(f), format_number(m)]
        row.append("-".join(map(str, a.firing_order)) if a.firing_order else "uneven")
        rows.append(row)
    return [
        Text(
            f"{result.enumerated} arrangements enumerated, {result.evaluated} distinct "
            f"evaluated in {result.seconds:.3f} s"
        ),
        Text(
            f"Objective {result.objective}, orders {','.join(map(str, orders))} "
            "(normalised peaks, after counterweights)"
        ),
        NumberTable("Best crank arrangements", columns, rows),
    ]


def _scatter_text(result: Any) -> list[str]:
    """Each scattered field as the study drew it: ``reciprocating ±0.003 kg (every
    cylinder, independently)``.

    ``result`` is a :class:`balance.studies.tolerance.ToleranceResult`."""
    out = []
    for s in result.scatter:
        field = s.field
        unit = _UNITS.get(field.kind, field.unit)
        where = (
            "every cylinder, independently"
            if field.cylinder is None
            else f"cylinder {field.cylinder + 1}"
        )
        out.append(f"{field.text.strip()} ±{s.tolerance:.6g} {unit} ({where})")
    return out


def _tolerance_setup(result: Any) -> str:
    """What a tolerance study drew, in one line: the sample count, the distribution, the
    seed and the scatter of each field (:func:`_scatter_text`)."""
    return f"{_drawn(result)}; scatter {'; '.join(_scatter_text(result))}"


def _drawn(result: Any) -> str:
    distribution = (
        "uniform over ±TOL"
        if result.distribution == "uniform"
        else "normal, standard deviation TOL/3"
    )
    seed = "" if result.seed is None else f", seed {result.seed}"
    return f"{result.samples} samples, {distribution}{seed}"


def tolerance_tables(result: Any, percentiles: Sequence[float]) -> list[RenderableType]:
    """What ``balance tolerance`` prints: what was drawn, then the percentiles of the free
    force and moment peaks per order, without and with the nominal engine's balancing.

    Parameters
    ----------
    result : ToleranceResult
        The study (:func:`balance.studies.tolerance.tolerance`).
    percentiles : sequence of float
        The percentiles to show [%].

    Returns
    -------
    list of rich.console.RenderableType
    """
    from rich.text import Text

    table = result.percentiles(percentiles)
    out: list[RenderableType] = [
        Text(f"Tolerance study: {_drawn(result)}; {result.seconds:.2f} s"),
        *(Text(f"Scatter: {text}") for text in _scatter_text(result)),
    ]
    for what, unit in (("force", "N"), ("moment", "N m")):
        rows = []
        for col, k in enumerate(result.orders):
            for key, label in (("free", "without"), ("balanced", "with")):
                values = table[f"{what}_{key}"][:, col]
                rows.append([str(int(k)), label, *(format_number(float(v)) for v in values)])
        out.append(
            NumberTable(
                f"Free {what} (reciprocating + rotating) peak per order: percentiles",
                [
                    Column("order", key=True),
                    Column("balancing", key=True, justify="left"),
                    *(Column("largest" if q == 100 else f"P{q:g}", unit) for q in percentiles),
                ],
                rows,
                notes=("balancing: the proposal designed for the nominal engine",)
                if what == "moment"
                else (),
            )
        )
    return out


def tolerance_histogram(result: Any, *, bins: int = 60) -> Figure:
    """Histograms of the residual peaks with balancing, one panel per quantity and order.

    The title states the sample count, the distribution and the scatter
    (:func:`_tolerance_setup`).

    Parameters
    ----------
    result : ToleranceResult
        The study (:func:`balance.studies.tolerance.tolerance`).
    bins : int
        Bins of each histogram.

    Returns
    -------
    matplotlib.figure.Figure
        Built with the object-oriented API (no pyplot).
    """
    import textwrap

    from matplotlib.figure import Figure

    K = result.orders.size
    fig = Figure(figsize=(max(4.0 * K, 8.0), 6.5), layout="constrained")
    axes = fig.subplots(2, K, squeeze=False)
    for row, (what, table, unit) in enumerate(
        (("force", result.force, "N"), ("moment", result.moment, "N m"))
    ):
        for col, k in enumerate(result.orders):
            ax = axes[row][col]
            values = table["balanced"][:, col]
            ax.hist(values, bins=bins, color="tab:blue")
            ax.set_title(f"order {int(k)}: residual {what} with balancing")
            ax.set_xlabel(f"peak {what} [{unit}]")
            ax.set_ylabel("samples")
    width = max(40, int(fig.get_figwidth() * 100.0 / 9.0))
    fig.suptitle(textwrap.fill(f"Tolerance study: {_tolerance_setup(result)}", width), fontsize=10)
    return fig


def figure_metadata(result: Any, fmt: str) -> dict[str, str]:
    """File metadata of a tolerance figure: what was drawn (:func:`_tolerance_setup`) as the
    PNG or SVG ``Description`` or the PDF ``Subject``, so the file says it without being
    opened.

    Parameters
    ----------
    result : ToleranceResult
        The study.
    fmt : {'png', 'svg', 'pdf'}
        The file format.

    Returns
    -------
    dict of str
        The metadata for ``Figure.savefig(metadata=...)``.
    """
    key = "Subject" if fmt == "pdf" else "Description"
    return {key: f"balance tolerance study: {_tolerance_setup(result)}"}
