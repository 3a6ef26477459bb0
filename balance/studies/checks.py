"""Plausibility warnings of a study: once per study, not once per grid point or sample.

A sweep or a tolerance study analyses many variants of one engine.  Checking each would
print the same warning thousands of times and cost as much as the study; instead the
variants at the corners of the study's box are checked (every combination of each varied
field's smallest and largest value, or of each scattered field's ±TOL), and each rule's
warning is reported once, with how many corners break it
(:func:`balance.core.plausibility.summarise`).  Every rule of
:mod:`balance.core.plausibility` is monotone in each field it reads (speed, stroke, crank
radius, conrod length, masses, inertia), so a value beyond a threshold anywhere in the box
shows at one of its corners.  With more than :data:`MAX_CORNERS` corners (more than six
fields), the ends of each field are checked one field at a time, the others at the base
layout's values.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np

from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.plausibility import PlausibilityWarning, check_engine, summarise
from balance.io.fields import Field, Scatter, Vary, check_varies, parse_scatter, parse_vary
from balance.studies.changes import apply_changes

__all__ = ["MAX_CORNERS", "sweep_warnings", "tolerance_warnings"]

#: Most corners checked; beyond, each field's ends are checked one field at a time.
MAX_CORNERS = 64


def sweep_warnings(base: Engine, vary: Sequence[Vary | str]) -> tuple[PlausibilityWarning, ...]:
    """The plausibility warnings of a sweep's grid, one per rule and field.

    Parameters
    ----------
    base : Engine
        The layout swept.
    vary : sequence of Vary or str
        The varied fields (``conrod_length=130mm:160mm:31``...), as for
        :func:`balance.studies.sweep.sweep`.

    Raises
    ------
    InputError
        For a field or values that the sweep itself would refuse.
    """
    varies = check_varies([v if isinstance(v, Vary) else parse_vary(v, base) for v in vary])
    ends = [(v.field, (float(np.min(v.values)), float(np.max(v.values)))) for v in varies]
    return _corner_warnings(base, ends, add=False, where="corners of the sweep grid")


def tolerance_warnings(
    base: Engine, scatter: Sequence[Scatter | str]
) -> tuple[PlausibilityWarning, ...]:
    """The plausibility warnings of a tolerance study: the base layout with each scattered
    field at ±TOL, one warning per rule and field.

    Parameters
    ----------
    base : Engine
        The layout scattered.
    scatter : sequence of Scatter or str
        The scattered fields (``reciprocating=±3g``...), as for
        :func:`balance.studies.tolerance.tolerance`.

    Returns
    -------
    tuple of PlausibilityWarning
        The warnings (:func:`balance.core.plausibility.check_engine`) at the corners of the
        scatter, each rule once.

    Raises
    ------
    InputError
        For a field or tolerance that the study itself would refuse.
    """
    items = [s if isinstance(s, Scatter) else parse_scatter(s, base) for s in scatter]
    ends = [(s.field, (-s.tolerance, s.tolerance)) for s in items]
    return _corner_warnings(base, ends, add=True, where="corners of the scatter")


def _corner_warnings(
    base: Engine, ends: list[tuple[Field, tuple[float, float]]], *, add: bool, where: str
) -> tuple[PlausibilityWarning, ...]:
    if not ends:
        return check_engine(base)
    if 2 ** len(ends) <= MAX_CORNERS:
        corners = list(itertools.product(*[pair for _, pair in ends]))
        fields = [field for field, _ in ends]
        points = [list(zip(fields, corner, strict=True)) for corner in corners]
    else:
        points = [[(field, value)] for field, pair in ends for value in pair]
    found = []
    for point in points:
        changes = [(field, float(field.to_layout_units(value))) for field, value in point]
        try:
            engine = apply_changes(base, changes, add=add)
        except InputError:  # a corner the study refuses itself, with its own message
            continue
        reach = np.asarray(engine.crank_radius) + np.abs(np.asarray(engine.offset))
        if not np.all(reach < np.asarray(engine.conrod_length)):
            continue  # an impossible crank slider: refused by the study itself
        found.append(check_engine(engine))
    return summarise(found, where)
