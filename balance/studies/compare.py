"""Comparing layouts side by side: every layout analysed the same way.

Every layout is analysed with the same orders and model (:func:`compare_results`); the
view :mod:`balance.views.compare` stacks the results along a ``layout`` dimension and prints
them.  Layouts of different size compare fairly when scaled to one displacement
(geometric similarity) and run at one speed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from balance.core.analysis import compute
from balance.core.catalogue import compared_sections
from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.result import Result
from balance.io.orders import parse_orders
from balance.io.request import build_request

__all__ = ["COMPARED", "Compared", "compare_results", "scale_layout"]

#: The sections of each analysis that a comparison shows beside the free forces and the
#: columns that sections declare (:func:`balance.core.catalogue.compared_sections`): a
#: section that a layout turns on but the comparison does not show is not computed, and
#: layouts are compared at constant speed.
COMPARED = ("cylinders", "torque", "proposal")


def scale_layout(layout: Engine, factor: float) -> Engine:
    """A geometrically similar engine: lengths times ``factor``, masses times its cube.

    Moments of inertia scale with the fifth power.  Forces at the same speed then scale
    with ``factor**4`` and moments with ``factor**5``.

    Parameters
    ----------
    layout : Engine
        The engine.
    factor : float
        The length scale [1], more than zero.

    Returns
    -------
    Engine
        The scaled engine, at the same speed.
    """
    if not (math.isfinite(factor) and factor > 0):
        raise InputError(f"scale factor must be a positive number, got {factor!r}")
    balance = layout.balance
    if balance is not None and balance.counterweight_radius is not None:
        balance = replace(balance, counterweight_radius=balance.counterweight_radius * factor)
    return replace(
        layout,
        z=layout.z * factor,
        crank_radius=layout.crank_radius * factor,
        conrod_length=layout.conrod_length * factor,
        offset=layout.offset * factor,
        reciprocating_mass=layout.reciprocating_mass * factor**3,
        rotating_mass=layout.rotating_mass * factor**3,
        conrod_inertia_correction=layout.conrod_inertia_correction * factor**5,
        reference_z=layout.reference_z * factor,
        pitch=layout.pitch * factor,
        bore=layout.bore * factor,
        balance=balance,
        mass_parts=layout.mass_parts.scaled(factor) if layout.mass_parts is not None else None,
    )


def _label(given: str, taken: set[str]) -> str:
    base = given
    label, i = base, 2
    while label in taken:
        label = f"{base} ({i})"
        i += 1
    taken.add(label)
    return label


@dataclass(frozen=True)
class Compared:
    """One layout of a comparison.

    Attributes
    ----------
    label : str
        Its label, unique within the comparison.
    scale_factor : float
        Length scale applied to reach the common displacement (1 without one).
    result : Result
        The analysis of the (scaled) layout.
    """

    label: str
    scale_factor: float
    result: Result


def compare_results(
    layouts: Sequence[Engine],
    names: Sequence[str] | None = None,
    orders: int | str | Sequence[int] | NDArray[np.integer] | None = "1-4",
    *,
    speed: float | None = None,
    displacement: float | None = None,
    model: str = "exact",
    terms: int = 3,
    pitch: float | None = None,
) -> list[Compared]:
    """Analyse several layouts the same way (with a balancing proposal each, and on its
    mounts where a layout has a ``mounts:`` section).

    Parameters
    ----------
    layouts : sequence of Engine
    names : sequence of str, optional
        Labels (default the layout names), made unique.
    orders : int, str or sequence of int
        Orders of every analysis (default 1 to 4).
    speed : float, optional
        Common crank speed [rad/s], finite and above zero; default each layout's own.
    displacement : float, optional
        Scale every layout to this total displacement [m^3] (geometric similarity, see
        :func:`scale_layout`); needs each layout's ``bore``.
    model, terms
        Piston acceleration model (see :func:`balance.analyse`).
    pitch : float, optional
        One pitch :math:`a` [m], finite and above zero, for the normalised moments of
        every layout (after any scaling to ``displacement``); default each layout's own
        (its ``pitch``, else its bore pitch: docs/conventions.md, "Normalisation and
        ``pitch``").

    Returns
    -------
    list of Compared
        In the order given; :func:`balance.views.compare.comparison_dataset` stacks them.
    """
    if not layouts:
        raise InputError("compare: give at least one layout")
    ks = parse_orders(orders)
    if pitch is not None and not (math.isfinite(pitch) and pitch > 0):
        raise InputError(f"pitch must be a length above zero, got {pitch!r} m")
    labels = list(names) if names is not None else [lay.name for lay in layouts]
    taken: set[str] = set()
    out = []
    for layout, given in zip(layouts, labels, strict=True):
        factor = 1.0
        if displacement is not None:
            if not math.isfinite(layout.bore):
                raise InputError(
                    f"{given}: scaling to a displacement needs geometry.bore in the layout"
                )
            factor = (displacement / layout.displacement) ** (1.0 / 3.0)
            layout = scale_layout(layout, factor)
        if pitch is not None:
            layout = replace(layout, pitch=float(pitch), pitch_given=True)
        request = build_request(
            layout, ks, speed=speed, model=model, terms=terms, speed_model="constant"
        )
        request = request.only(*COMPARED, *compared_sections())
        out.append(Compared(_label(given, taken), factor, compute(layout, request)))
    return out
