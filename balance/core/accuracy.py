r"""Accuracy of the piston-acceleration models, and choosing one for a tolerance.

Errors are those of the normalised Fourier coefficients :math:`G_k` of
:math:`-s''/r` (so a force error is this times :math:`m_{rec} r\omega^2`), for the
worst cylinder of a layout.  With :math:`x = \lambda(1 + |e|/r)`:

``textbook``
    :math:`\lambda|e|/r + B_1`: the offset's first-order sine term it leaves out, and the
    binomial series after its first term.
``series`` with n terms
    :math:`B_n = 8\sum_{m>n} |\binom{1/2}{m}|\, m^2 x^{2m-1}`, from
    :math:`|(u^{2m})''| \le 4m^2 x^{2m-1}/\lambda^{2m-1}` and :math:`|G_k| \le 2\max|f|`.
``exact``
    :math:`10^{-14}(1-x)^{-3/2}`: rounding, which grows with the peak of the acceleration
    as :math:`\lambda \to 1`.
``time`` with N samples
    :math:`10\,(1-x)^{-3/2}\, e^{-a(N-k_{max})}/(1-e^{-a})` (aliasing of the orders above
    N/2, which decay like :math:`e^{-ak}` with :math:`a = \operatorname{arccosh}(1/\lambda
    - |e|/r)`, the distance of the conrod term's branch point from the real axis), plus the
    rounding of ``exact``.

The bounds for ``textbook`` and ``series`` follow from the expansion; those for ``exact``
and ``time`` are estimates.  The tests check all four against 30-digit references over
:math:`\lambda` from :math:`10^{-9}` to 0.999.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from balance.core.errors import AnalysisError

__all__ = [
    "MAX_SERIES_TERMS",
    "SERIES_CHEAPER_UP_TO",
    "choose_model",
    "error_bound",
    "series_bound",
]

#: Most binomial terms the series model takes.
MAX_SERIES_TERMS = 60
#: The tolerance mode prefers the series to the exact model up to this many terms (the
#: series costs grow with the terms: the benchmark page measures the series at 8 terms
#: slower than the exact model, at 3 terms faster).
SERIES_CHEAPER_UP_TO = 4


def _binom_half_abs(m: int) -> float:
    value = 1.0
    for i in range(m):
        value *= abs(0.5 - i) / (i + 1)
    return value


def series_bound(terms: int, x: float) -> float:
    r"""Bound :math:`B_n` on the error of the series truncated after ``terms`` terms.

    Parameters
    ----------
    terms : int
        Number of binomial terms kept, n.
    x : float
        :math:`\lambda(1+|e|/r)`, below 1.
    """
    if x <= 0:
        return 0.0
    if x >= 1:
        return math.inf
    total = 0.0
    m = terms + 1
    coeff = _binom_half_abs(m)
    while m < 200_000:
        term = 8.0 * coeff * m * m * x ** (2 * m - 1)
        total += term
        if term < 1e-20 * max(total, 1e-300) or term < 1e-300:
            break
        coeff *= abs(0.5 - m) / (m + 1)
        m += 1
    return total


def _worst(ratio: ArrayLike, offset_ratio: ArrayLike) -> tuple[float, float, float]:
    lam = np.asarray(ratio, dtype=np.float64)
    eps = np.abs(np.asarray(offset_ratio, dtype=np.float64))
    x = float(np.max(lam * (1 + eps)))
    lam_eps = float(np.max(lam * eps))
    a = float(np.min(np.arccosh(np.maximum(1 / lam - eps, 1.0))))
    return x, lam_eps, a


def error_bound(
    model: str,
    ratio: ArrayLike,
    offset_ratio: ArrayLike = 0.0,
    *,
    terms: int = 3,
    samples: int = 0,
    max_order: int = 8,
) -> float:
    """Error bound of the normalised acceleration coefficients for a model (see module)."""
    x, lam_eps, a = _worst(ratio, offset_ratio)
    rounding = 1e-14 * (1 - x) ** -1.5
    if model == "textbook":
        return lam_eps + series_bound(1, x)
    if model == "series":
        return series_bound(terms, x) + 1e-15
    if model == "exact":
        return rounding
    if model == "time":
        if samples <= 2 * max_order:
            return math.inf
        alias = 10.0 * (1 - x) ** -1.5 * math.exp(-a * (samples - max_order)) / (1 - math.exp(-a))
        return alias + rounding
    raise AnalysisError(f"unknown model {model!r}")


def choose_model(
    tolerance: float, ratio: ArrayLike, offset_ratio: ArrayLike = 0.0
) -> tuple[str, int, float]:
    """The cheapest model that meets ``tolerance`` for this geometry.

    Returns
    -------
    model : str
    terms : int
        Series terms (0 unless the series is chosen).
    bound : float
        The error bound achieved.

    Raises
    ------
    AnalysisError
        If no model reaches the tolerance (it is below double precision for the geometry).
    """
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise AnalysisError(f"tolerance must be a positive number, got {tolerance!r}")
    bound = error_bound("textbook", ratio, offset_ratio)
    if bound <= tolerance:
        return "textbook", 0, bound
    for terms in range(1, SERIES_CHEAPER_UP_TO + 1):
        bound = error_bound("series", ratio, offset_ratio, terms=terms)
        if bound <= tolerance:
            return "series", terms, bound
    bound = error_bound("exact", ratio, offset_ratio)
    if bound <= tolerance:
        return "exact", 0, bound
    # below the exact model's rounding estimate, a long series may still get there
    for terms in range(SERIES_CHEAPER_UP_TO + 1, MAX_SERIES_TERMS + 1):
        series = error_bound("series", ratio, offset_ratio, terms=terms)
        if series <= tolerance:
            return "series", terms, series
    raise AnalysisError(
        f"a tolerance of {tolerance:.3g} is below what double precision gives for this "
        f"geometry (best: {bound:.3g} with the exact model)"
    )
