"""Numbers as the views print them: JSON numbers, orders, compact formatting, and zero
where rounding cannot tell a value from zero.

numpy and the standard library only, so that the JSON, CSV and table views need no
xarray.  Phases and normalised values are formed by the phasor type
(:func:`balance.core.phasors.phase_deg`, :func:`balance.core.phasors.safe_ratio`).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.phasors import Phasors, rounding_threshold

__all__ = [
    "format_number",
    "free_phasors",
    "json_number",
    "order_value",
    "zero_below_rounding",
]


def json_number(value: Any) -> float | None:
    """A number as the JSON views write it: a float, or None (null) where it is not finite.

    Parameters
    ----------
    value : number
        Any real number (numpy scalars included).

    Returns
    -------
    float or None
    """
    number = float(value)
    return number if math.isfinite(number) else None


def order_value(order: float) -> float | int:
    """An order as JSON writes it: a whole number as an int, a half order as a float.

    Parameters
    ----------
    order : float
        The order.

    Returns
    -------
    int or float
    """
    return int(order) if float(order).is_integer() else float(order)


def zero_below_rounding(values: ArrayLike, scale: ArrayLike, n_terms: int) -> NDArray[np.float64]:
    r"""Magnitudes as printed: 0 where a value cannot be told from zero.

    The one rule of every printed view (docs/conventions.md, "Zero by symmetry"): that of
    :func:`balance.core.phasors.cancel_to_zero`, which every phasor sum of the analysis
    follows: a sum of ``n_terms`` terms whose magnitudes add up to ``scale`` is zero where
    it is at most :func:`balance.core.phasors.rounding_threshold` of them.  The tables,
    the figures' labels and the values they draw use it for the quantities that are formed
    after the phasor sums (the free order 1, bearing loads, the response on the mounts, a
    balance-factor study, the signals over a revolution), so that a load of ``4.8e-12`` N
    next to loads of 10 kN prints as 0 like the phasors do.

    Parameters
    ----------
    values : array_like
        Magnitudes (or signed components) [any unit].
    scale : array_like
        :math:`S`, a bound on the sum of the magnitudes of the terms summed into each value,
        in the unit of ``values``; broadcasts against ``values`` (a scale per row).
    n_terms : int
        Number of terms of each sum.

    Returns
    -------
    ndarray of float
        ``values`` with every entry of magnitude at most the threshold set to 0.
    """
    out = np.array(values, dtype=np.float64, copy=True)
    threshold = np.broadcast_to(rounding_threshold(scale, n_terms), out.shape)
    out[np.isfinite(threshold) & (np.abs(out) <= threshold)] = 0.0
    return out


def free_phasors(phasors: Phasors, n_terms: int) -> Phasors:
    r"""The free force and moment as the views show them: :meth:`Phasors.free
    <balance.core.phasors.Phasors.free>` (the rotating masses added to order 1 forward),
    with a sum that cancels to rounding set to 0 (:func:`zero_below_rounding`'s rule).

    Parameters
    ----------
    phasors : Phasors
        The reciprocating inertia and the rotating masses of an analysis.
    n_terms : int
        Number of terms of each of the two sums added (the cylinders).

    Returns
    -------
    Phasors
        The free bundle; its order-1 forward phasor is 0 where
        :math:`|P_1^{+} + P_{rot}| \le 64 \cdot 2n\,\varepsilon (|P_1^{+}| + |P_{rot}|)`.
    """
    free = phasors.free()
    first = np.asarray(phasors.orders) == 1
    if not first.any():
        return free
    changes: dict[str, Any] = {}
    for quantity in ("force", "moment"):
        forward = phasors.pair(quantity)[0]
        rotating = phasors.rotating(quantity)
        total = free.pair(quantity)[0]
        if forward is None or rotating is None:
            continue
        scale = np.abs(np.asarray(forward)[..., first]) + np.abs(np.asarray(rotating))[..., None]
        threshold = rounding_threshold(scale, 2 * n_terms)
        cleaned = np.array(total, dtype=np.complex128, copy=True)
        part = cleaned[..., first]
        part[np.abs(part) <= threshold] = 0.0
        cleaned[..., first] = part
        changes[f"{quantity}_forward"] = cleaned
    return replace(free, **changes)


def format_number(value: float, digits: int = 4) -> str:
    """Compact engineering formatting: 0 stays 0, NaN shows as a dash.

    Parameters
    ----------
    value : float
        The number, in the unit of its column.
    digits : int
        Significant digits.

    Returns
    -------
    str
        ``"0"``, ``"-"`` (not finite), or the number to ``digits`` significant digits.
    """
    if not math.isfinite(value):
        return "-"
    if value == 0.0:
        return "0"
    return f"{value:.{digits}g}"
