"""A sweep over a field of the ``balance:`` section: the residual with the proposal.

The free forces do not depend on the balancing settings, so a sweep that varies
``balance.balance_factor`` also writes what a designer varies it for: the residual forces,
moments and roll with the balancing proposal (:mod:`balance.core.proposal`) at every grid
point.  A proposal is designed for one engine at a time, so these are computed point by
point: each grid point's engine is the variant :func:`balance.studies.changes.apply_changes`
gives, analysed by :func:`balance.core.analysis.compute` with the proposal as its one section,
exactly as ``balance analyse`` analyses the layout file with those values written in (without
its other sections: a sweep's values are the inertia forces').  That costs an analysis per
grid point (about 250 a second), where the rest of a sweep costs microseconds; see
docs/sweeps.md.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from balance.core.analysis import compute
from balance.core.catalogue import Output
from balance.core.engine import Engine
from balance.core.proposal import OUTPUTS
from balance.core.sections import SECTIONS
from balance.io.fields import Vary
from balance.io.request import build_request
from balance.studies.changes import apply_changes

__all__ = ["RESIDUAL_OUTPUTS", "balance_varied", "residual_outputs", "residual_point"]

FloatArray = NDArray[np.float64]

#: The proposal's outputs a sweep over a ``balance:`` field writes, by name.
RESIDUAL_OUTPUTS: tuple[str, ...] = (
    "residual_force_magnitude",
    "residual_force_peak",
    "residual_moment_magnitude",
    "residual_moment_peak",
    "residual_roll_amplitude",
)


def balance_varied(varies: Sequence[Vary]) -> bool:
    """Whether a sweep varies a field of the ``balance:`` section.

    Parameters
    ----------
    varies : sequence of Vary
        The varied fields.

    Returns
    -------
    bool
    """
    return any(v.field.attribute.startswith("balance.") for v in varies)


def residual_outputs() -> list[Output]:
    """The catalogue entries of :data:`RESIDUAL_OUTPUTS` (:data:`balance.core.proposal.OUTPUTS`).

    Returns
    -------
    list of Output
    """
    by_name = {output.name: output for output in OUTPUTS}
    return [by_name[name] for name in RESIDUAL_OUTPUTS]


def residual_point(
    layout: Engine,
    varies: Sequence[Vary],
    index: tuple[int, ...],
    orders: NDArray[np.intp],
    model: str,
    terms: int,
) -> dict[str, FloatArray]:
    """The residual with the proposal at one grid point.

    Parameters
    ----------
    layout : Engine
        The layout swept.
    varies : sequence of Vary
        The varied fields.
    index : tuple of int
        The grid point (one index per varied field).
    orders : ndarray of int
        The orders.
    model : str
        Piston acceleration model.
    terms : int
        Terms of the ``series`` model.

    Returns
    -------
    dict of ndarray
        Each of :data:`RESIDUAL_OUTPUTS` for this variant [N, N m].
    """
    changes = [
        (v.field, float(v.field.to_layout_units(v.values[i])))
        for v, i in zip(varies, index, strict=True)
    ]
    engine = apply_changes(layout, changes, problem=_CG_BEYOND_ROD)
    sections: dict[str, Any] = {s.name: s.name == "proposal" for s in SECTIONS}
    request = build_request(engine, orders, model=model, terms=terms, **sections)
    result = compute(engine, request)
    return {o.name: np.asarray(o.get(result), dtype=np.float64) for o in residual_outputs()}


_CG_BEYOND_ROD = (
    "vary: the conrod's centre of gravity would lie beyond its small end "
    "(conrod_cg_to_big_end > conrod_length); keep it between the two ends"
)
