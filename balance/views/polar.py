"""Polar form for the views that print: phases in degrees, safe normalisation, rpm.

numpy and the standard library only, so that the JSON, CSV and table views need no
xarray (:mod:`balance.views.dataset` imports these for the Dataset as well).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.phasors import rounding_threshold
from balance.core.speed import rad_per_s_to_rpm

__all__ = [
    "CONVENTIONS",
    "SCHEMA",
    "format_number",
    "json_number",
    "order_value",
    "phase_deg",
    "safe_ratio",
    "speed_rpm",
    "zero_below_rounding",
]

#: Schema name of the analysis JSON and the result Dataset.
SCHEMA = "balance.analysis/1"

#: The frame and sign conventions, as the result Dataset's ``conventions`` attribute and
#: the report state them.
CONVENTIONS = (
    "balance CONTRACT: frame z crank axis, y up, angles from +y in the "
    "direction of rotation; (x, y) as y + i x"
)


def phase_deg(phasor: ArrayLike) -> NDArray[np.float64]:
    """Phase of complex phasors in degrees, in [0, 360), to 1e-9 deg; 0 where the magnitude is 0."""
    z = np.asarray(phasor, dtype=np.complex128)
    # rounded to 1e-9 deg so that rounding noise (1e-14 deg) does not show as a phase
    deg = np.round(np.mod(np.degrees(np.angle(z)), 360.0), 9)
    deg = np.where(deg >= 360.0, 0.0, deg)
    deg = np.where(np.abs(z) == 0.0, 0.0, deg)
    deg = np.where(np.isnan(z), np.nan, deg)
    return np.asarray(deg + 0.0, dtype=np.float64)  # + 0.0 turns -0.0 into 0.0


def safe_ratio(values: Any, scale: float) -> Any:
    """``values / scale``: NaN where the scale is zero or not finite, and inf (without a
    warning) where the ratio lies beyond the float range (a normalising force of a few
    1e-300 N, as a layout with a 1e-308 kg piston has)."""
    if not math.isfinite(scale) or scale == 0.0:
        return np.full(np.shape(values), np.nan)
    with np.errstate(over="ignore"):
        return np.asarray(values) / scale


def speed_rpm(speed: float) -> float:
    """Crank speed [rad/s] in rpm as reported, to 12 significant digits (8000 rpm read from
    a file stays 8000, not 7999.999999999999)."""
    return float(f"{rad_per_s_to_rpm(speed):.12g}")


def json_number(value: Any) -> float | None:
    """A number as the JSON views write it: a float, or None (null) where it is not finite."""
    number = float(value)
    return number if math.isfinite(number) else None


def order_value(order: float) -> float | int:
    """An order as JSON writes it: a whole number as an int, a half order as a float."""
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
    """Compact engineering formatting: 0 stays 0, NaN shows as a dash."""
    if not math.isfinite(value):
        return "-"
    if value == 0.0:
        return "0"
    return f"{value:.{digits}g}"
