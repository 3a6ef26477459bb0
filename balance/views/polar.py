"""Numbers as the views print them: JSON numbers, orders, compact formatting, and zero
where rounding cannot tell a value from zero.

numpy and the standard library only, so that the JSON, CSV and table views need no
xarray.  Phases and normalised values are formed by the phasor type
(:func:`balance.core.phasors.phase_deg`, :func:`balance.core.phasors.safe_ratio`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.phasors import rounding_threshold

__all__ = [
    "format_number",
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


def zero_below_rounding(values: ArrayLike, scale: float, n_terms: int) -> NDArray[np.float64]:
    r"""Magnitudes as printed: 0 where a value cannot be told from zero.

    The rule of :func:`balance.core.phasors.cancel_to_zero`, which every phasor sum of the
    analysis follows: a sum of ``n_terms`` terms whose magnitudes add up to ``scale`` is
    zero where it is at most :func:`balance.core.phasors.rounding_threshold` of them.  For
    the quantities that are formed elsewhere (bearing loads, a balance-factor study), so
    that a load of ``4.8e-12`` N next to loads of 10 kN prints as 0 like the phasors do.

    Parameters
    ----------
    values : array_like
        Non-negative magnitudes.
    scale : float
        :math:`S`, a bound on the sum of the magnitudes of the terms summed into each value.
    n_terms : int
        Number of terms of each sum.
    """
    out = np.array(values, dtype=np.float64, copy=True)
    threshold = float(rounding_threshold(scale, n_terms))
    if math.isfinite(threshold):
        out[np.abs(out) <= threshold] = 0.0
    return out


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
