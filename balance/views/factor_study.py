"""Views of the ``factor_study`` section: the residual first order against the balance
factor (:func:`balance.core.proposal.factor_study`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from balance.views.fitted import Column, NumberTable
from balance.views.polar import format_number, json_number

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.factor_study import FactorStudy
    from balance.core.result import Result

__all__ = ["json_block", "tables"]

#: The table's note with several crankshafts (docs/several-crankshafts.md).
_GEARED = (
    "several crankshafts: each factor is the proposal with that balance_factor on each "
    "crankshaft's own cylinders, without a balance shaft at +1 or -1; forward and backward: "
    "the residual first order turning with and against crankshaft 1",
)


def _part(result: Result) -> FactorStudy:
    part: FactorStudy = result.part("factor_study")
    return part


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``balance_factor_study``.

    Parameters
    ----------
    result : Result
        An analysis with the ``factor_study`` section.

    Returns
    -------
    dict
        The optimal factor and, per factor, the first-order vertical, horizontal and moment
        peaks [N, N m].
    """
    study = _part(result)
    one = study.equivalents(study.optimal).one_cylinder
    senses = _senses(study)
    return {
        "balance_factor_study": {
            "factor_of": "each-cylinder",
            "optimal_factor": json_number(study.optimal),
            "optimal_factor_one_cylinder": None if one is None else json_number(one),
            "factors": [
                {
                    "factor": float(f),
                    "vertical_peak": json_number(study.vertical_peak[i]),
                    "horizontal_peak": json_number(study.horizontal_peak[i]),
                    "moment_peak": json_number(study.moment_peak[i]),
                    **{key: json_number(values[i]) for key, _, _, values in senses},
                }
                for i, f in enumerate(np.asarray(study.factor))
            ],
        }
    }


def _senses(study: FactorStudy) -> list[tuple[str, str, str, Any]]:
    """Several crankshafts: the residual's first order in each sense, as (JSON key, column,
    unit, values); empty for one crankshaft."""
    out = []
    for key, column, unit in (
        ("force_forward", "forward force", "N"),
        ("force_backward", "backward force", "N"),
        ("moment_forward", "forward moment", "N m"),
        ("moment_backward", "backward moment", "N m"),
    ):
        values = getattr(study, key)
        if values is not None:
            out.append((key, column, unit, values))
    return out


def _render_factor_study(study: FactorStudy) -> list[RenderableType]:
    """Rich renderables of a balance-factor study: the peaks per factor (and, with the
    bearing loads, the largest main load and internal moment) and the best factor."""
    from rich.text import Text

    columns = [
        Column("balance factor", "%", key=True),
        Column("vertical peak", "N"),
        Column("horizontal peak", "N"),
        Column("moment peak", "N m"),
    ]
    values = [study.vertical_peak, study.horizontal_peak, study.moment_peak]
    senses = _senses(study)
    columns += [Column(column, unit) for _, column, unit, _ in senses]
    values += [v for *_, v in senses]
    if study.largest_main_load is not None and study.largest_internal_moment is not None:
        columns += [
            Column("largest main load", "N"),
            Column("largest internal moment", "N m"),
        ]
        values += [study.largest_main_load, study.largest_internal_moment]
    rows = [
        [f"{100 * f:.4g}", *(format_number(float(column[i])) for column in values)]
        for i, f in enumerate(np.asarray(study.factor))
    ]
    best = study.equivalents(study.optimal)
    return [
        NumberTable(
            "Balance factor study: residual first order (rotating masses balanced in full)",
            columns,
            rows,
            notes=(
                "balance factor: the share of each cylinder's reciprocating mass put on the "
                "crank (balance_factor of: each-cylinder)",
                *(_GEARED if senses else ()),
            ),
        ),
        Text(
            f"Factor minimising the larger force peak: {float(study.optimal):.1%} ({best.other()})"
        ),
    ]


def tables(result: Result) -> list[RenderableType]:
    """The section's tables: the first-order peaks per balance factor (with the bearing loads,
    the largest main load and internal moment) and the best factor.

    Parameters
    ----------
    result : Result
        An analysis with the ``factor_study`` section.

    Returns
    -------
    list of rich.console.RenderableType
    """
    return _render_factor_study(_part(result))
