"""Text and figures of the studies' results: a crank-arrangement search
(:mod:`balance.studies.search`) and a tolerance study (:mod:`balance.studies.tolerance`).

The results are read by their attributes (a view never imports a study).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["search_text", "tolerance_histogram", "tolerance_text"]


def search_text(result: Any) -> str:
    """The lines ``balance search`` prints: a summary, then the best arrangements ranked.

    ``result`` is a :class:`balance.studies.search.SearchResult`.
    """
    lines = [
        f"{result.enumerated} arrangements enumerated, {result.evaluated} distinct evaluated "
        f"in {result.seconds:.3f} s; objective {result.objective}, orders "
        f"{','.join(map(str, result.orders))} (normalised, after counterweights)\n"
    ]
    for rank, a in enumerate(result.best, 1):
        throws = "/".join(f"{t:g}" for t in a.throws)
        split = "" if not any(a.splits) else " split " + "/".join(f"{s:g}" for s in a.splits)
        firing = "-".join(map(str, a.firing_order)) if a.firing_order else "uneven"
        peaks = " ".join(
            f"F{k}={f:.3g} M{k}={m:.3g}"
            for k, f, m in zip(result.orders, a.force_peaks, a.moment_peaks, strict=True)
        )
        lines.append(
            f"{rank}. throws {throws}{split}: score {a.score:.4g}, shafts {a.shafts}, "
            f"{peaks}, firing {firing}\n"
        )
    return "".join(lines)


def tolerance_text(result: Any, percentiles: Sequence[float]) -> str:
    """The lines ``balance tolerance`` prints: percentiles of the residual peaks per
    quantity and order.

    ``result`` is a :class:`balance.studies.tolerance.ToleranceResult`.
    """
    table = result.percentiles(percentiles)
    lines = [
        f"{result.samples} samples in {result.seconds:.2f} s; peaks per order, percentiles "
        f"{', '.join(f'{q:g}' for q in percentiles)}\n"
    ]
    for key, values in table.items():
        unit = "N" if key.startswith("force") else "N m"
        for col, k in enumerate(result.orders):
            cells = " ".join(f"{v:10.4g}" for v in values[:, col])
            lines.append(f"{key:16s} order {int(k)} [{unit}]: {cells}\n")
    return "".join(lines)


def tolerance_histogram(result: Any, *, bins: int = 60) -> Figure:
    """Histograms of the residual peaks with balancing, one panel per quantity and order.

    ``result`` is a :class:`balance.studies.tolerance.ToleranceResult`.

    Returns
    -------
    matplotlib.figure.Figure
        Built with the object-oriented API (no pyplot).
    """
    from matplotlib.figure import Figure

    K = result.orders.size
    fig = Figure(figsize=(4.0 * K, 6.0), layout="constrained")
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
    fig.suptitle(f"tolerance study, {result.samples} samples")
    return fig
