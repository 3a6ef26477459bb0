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

Link cylinders (:mod:`balance.core.links`)
    ``textbook`` and ``series`` treat a link piston as a plain slider on the crank pin
    (crank radius r, rod :math:`l_j`, offset :math:`e_j`; the idealised radial) and leave
    out the link pin's motion relative to the crank pin; their bound is the plain one for
    :math:`(\lambda_j, e_j/r)` plus :func:`articulation_bound`, a bound (derived on the
    theory page) on what that leaves out.  ``exact`` is the rounding estimate with
    :math:`x` the larger of the master rod's :math:`\lambda_m(1+|e_m|/r)` and the link
    rod's reach :math:`\max|\lambda_j h|` (:func:`balance.core.links.link_reach`).
    ``time`` uses the plain estimate with :math:`a` the half-width of a strip of the complex
    crank-angle plane in which both rods' square roots stay analytic
    (:func:`link_strip`).  The tests measure all four against the exact coefficients.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import kinematics
from balance.core.errors import AnalysisError

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.engine import Engine
    from balance.core.links import LinkGeometry

__all__ = [
    "MAX_SERIES_TERMS",
    "SERIES_CHEAPER_UP_TO",
    "articulation_bound",
    "choose_model",
    "choose_model_for",
    "engine_error_bound",
    "error_bound",
    "link_strip",
    "series_bound",
    "series_parameters",
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


def _rounding(x: float) -> float:
    r"""The ``exact`` model's rounding estimate :math:`10^{-14}(1-x)^{-3/2}` [1]."""
    return 1e-14 * (1 - x) ** -1.5


def _aliasing(x: float, a: float, samples: int, max_order: int) -> float:
    r"""The ``time`` model's aliasing estimate :math:`10\,(1-x)^{-3/2}\,
    e^{-a(N-k_{max})}/(1-e^{-a})` [1] (see the module notes)."""
    return 10.0 * (1 - x) ** -1.5 * math.exp(-a * (samples - max_order)) / (1 - math.exp(-a))


def error_bound(
    model: str,
    ratio: ArrayLike,
    offset_ratio: ArrayLike = 0.0,
    *,
    terms: int = 3,
    samples: int = 0,
    max_order: int = 8,
) -> float:
    r"""Error bound of the normalised acceleration coefficients for a model (see the module notes).

    Parameters
    ----------
    model : {'textbook', 'series', 'exact', 'time'}
        The piston-acceleration model.
    ratio : array_like
        Rod ratios :math:`\lambda = r/l` of the cylinders [1]; the worst one counts.
    offset_ratio : array_like
        Offset ratios :math:`e/r` of the same cylinders [1] (default 0).
    terms : int
        Binomial terms of the ``series`` model.
    samples : int
        Crank angles per revolution of the ``time`` model (at most ``2 * max_order`` gives an
        infinite bound).
    max_order : int
        Highest order reported; the ``time`` model's aliasing grows with it.

    Returns
    -------
    float
        The bound on :math:`|G_k|` errors [1] (a force error is this times
        :math:`m_{rec} r\omega^2`).

    Raises
    ------
    AnalysisError
        For an unknown model.
    """
    x, lam_eps, a = _worst(ratio, offset_ratio)
    rounding = _rounding(x)
    if model == "textbook":
        return lam_eps + series_bound(1, x)
    if model == "series":
        return series_bound(terms, x) + 1e-15
    if model == "exact":
        return rounding
    if model == "time":
        if samples <= 2 * max_order:
            return math.inf
        return _aliasing(x, a, samples, max_order) + rounding
    raise AnalysisError(f"unknown model {model!r}")


def choose_model(
    tolerance: float, ratio: ArrayLike, offset_ratio: ArrayLike = 0.0
) -> tuple[str, int, float]:
    r"""The cheapest model that meets ``tolerance`` for this geometry.

    Parameters
    ----------
    tolerance : float
        Largest error allowed in the normalised coefficients [1], more than 0.
    ratio : array_like
        Rod ratios :math:`\lambda = r/l` of the cylinders [1].
    offset_ratio : array_like
        Offset ratios :math:`e/r` of the same cylinders [1] (default 0).

    Returns
    -------
    model : str
        ``'textbook'``, ``'series'`` or ``'exact'``.
    terms : int
        Series terms (0 unless the series is chosen).
    bound : float
        The error bound achieved [1].

    Raises
    ------
    AnalysisError
        If no model reaches the tolerance (it is below double precision for the geometry).
    """
    bound = partial(error_bound, ratio=ratio, offset_ratio=offset_ratio)
    return _cheapest(tolerance, bound, long_series=True)


def _cheapest(
    tolerance: float, bound_of: Callable[..., float], *, long_series: bool
) -> tuple[str, int, float]:
    """The ladder of :func:`choose_model`: textbook, series of 1 to
    :data:`SERIES_CHEAPER_UP_TO` terms, exact, then (with ``long_series``) series of up to
    :data:`MAX_SERIES_TERMS` terms; ``bound_of(model, terms=...)`` gives a model's bound."""
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise AnalysisError(f"tolerance must be a positive number, got {tolerance!r}")
    bound = bound_of("textbook")
    if bound <= tolerance:
        return "textbook", 0, bound
    for terms in range(1, SERIES_CHEAPER_UP_TO + 1):
        bound = bound_of("series", terms=terms)
        if bound <= tolerance:
            return "series", terms, bound
    bound = bound_of("exact")
    if bound <= tolerance:
        return "exact", 0, bound
    if long_series:  # below the exact model's rounding estimate, a long series may get there
        for terms in range(SERIES_CHEAPER_UP_TO + 1, MAX_SERIES_TERMS + 1):
            series = bound_of("series", terms=terms)
            if series <= tolerance:
                return "series", terms, series
    raise AnalysisError(
        f"a tolerance of {tolerance:.3g} is below what double precision gives for this "
        f"geometry (best: {bound:.3g} with the exact model)"
    )


# --------------------------------------------------------------------------- link cylinders


def _master_angle_bounds(
    ratio_master: ArrayLike, offset_master: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    r""":math:`\gamma_1 \ge \max|\gamma'|` and :math:`\gamma_2 \ge \max(|\gamma''| +
    \gamma'^2)` of a master rod, from :math:`|\cos\gamma| \ge \sqrt{1 - x_m^2}`."""
    lam = np.asarray(ratio_master, dtype=np.float64)
    x = lam * (1.0 + np.abs(np.asarray(offset_master, dtype=np.float64)))
    d_min = np.sqrt(1.0 - x**2)
    g1 = lam / d_min
    g2 = lam / d_min + lam**2 * x / d_min**3 + g1**2
    return g1, g2


def articulation_bound(geometry: LinkGeometry, mass_ratio: ArrayLike) -> NDArray[np.float64]:
    r"""Bound on what the idealised models leave out of a link cylinder's coefficients [1].

    Parameters
    ----------
    geometry : LinkGeometry
        The link cylinders (:func:`balance.core.links.link_geometry`).
    mass_ratio : array_like
        Link-pin mass over reciprocating mass of each link cylinder, :math:`m_L(1 -
        c/l_j)/m_{rec}`.

    Returns
    -------
    ndarray
        Per link cylinder, a bound on :math:`|G_k^{link} - G_k^{slider}|` (and on the link
        pin's relative force in the same units, :math:`m_{rec} r\omega^2`).

    Notes
    -----
    The link piston's position differs from the plain slider's by
    :math:`\Delta s/r = \kappa w_Y + F(h + \kappa w_X) - F(h)` with :math:`F(h) =
    \sqrt{1 - \lambda_j^2(h-\varepsilon_j)^2}/\lambda_j`, :math:`w = e^{i(\delta -
    \gamma)}`.  Writing the difference as :math:`\int_0^1 F'(h + t\kappa w_X)\kappa w_X\,
    \mathrm dt` and differentiating twice, with :math:`|w'| \le \gamma_1`,
    :math:`|w''| \le \gamma_2`, :math:`|y| \le x_j = \lambda_j(1 + \kappa +
    |\varepsilon_j|)`, :math:`g_1 = 1 + \kappa\gamma_1`, :math:`g_2 = 1 + \kappa\gamma_2`:

    .. math::

        \max|\Delta s''|/r \le \kappa\left[\gamma_2 +
        \frac{3\lambda_j^2x_jg_1^2}{(1-x_j^2)^{5/2}} +
        \frac{\lambda_j(g_2 + 2g_1\gamma_1)}{(1-x_j^2)^{3/2}} +
        \frac{x_j\gamma_2}{\sqrt{1-x_j^2}}\right].

    The link pin's relative acceleration is at most :math:`\kappa\gamma_2 r\omega^2`.
    With :math:`|G_k| \le 2\max|f|` the bound is twice the sum of the two (the second
    times ``mass_ratio``).  It is infinite where :math:`x_j \ge 1` (the estimate does not
    hold, though the geometry may).
    """
    g1, g2 = _master_angle_bounds(geometry.ratio_master, geometry.offset_master)
    kappa = geometry.pin
    lam = geometry.ratio
    x = lam * (1.0 + kappa + np.abs(geometry.offset))
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(1.0 - x**2)
        s1 = 1.0 + kappa * g1
        s2 = 1.0 + kappa * g2
        piston = kappa * (
            g2
            + 3.0 * lam**2 * x * s1**2 / root**5
            + lam * (s2 + 2.0 * s1 * g1) / root**3
            + x * g2 / root
        )
    piston = np.where(x < 1.0, piston, np.inf)
    pin = np.asarray(mass_ratio, dtype=np.float64) * kappa * g2
    return np.asarray(2.0 * (piston + pin), dtype=np.float64)


def link_strip(geometry: LinkGeometry) -> NDArray[np.float64]:
    r"""Half-width :math:`b` of a strip :math:`|\operatorname{Im}\beta| < b` in which a link
    cylinder's functions are analytic [1].

    The master rod's square root is analytic for :math:`b < a_m =
    \operatorname{arccosh}(1/\lambda_m - |\varepsilon_m|)`; the link rod's while
    :math:`\lambda_j|h| < 1`, which holds where :math:`\lambda_j(\cosh b + \kappa M(b) +
    |\varepsilon_j|) < 1` with :math:`M(b) = \sqrt{1 + \lambda_m^2 U^2} + \lambda_m U`,
    :math:`U = \cosh b + |\varepsilon_m|` (bounds of :math:`|\cos\gamma|` and
    :math:`|\sin\gamma|` in the strip).  The largest such :math:`b` below :math:`a_m` is
    found by bisection; 0 where even :math:`b = 0` fails the test.

    Parameters
    ----------
    geometry : LinkGeometry
        The link cylinders (:func:`balance.core.links.link_geometry`).

    Returns
    -------
    ndarray
        :math:`b` of each link cylinder [1] (radians of imaginary crank angle).
    """
    lam_m = np.asarray(geometry.ratio_master, dtype=np.float64)
    eps_m = np.abs(np.asarray(geometry.offset_master, dtype=np.float64))
    kappa = geometry.pin
    lam = geometry.ratio
    eps = np.abs(geometry.offset)
    a_m = np.arccosh(np.maximum(1.0 / lam_m - eps_m, 1.0))

    def fits(b: NDArray[np.float64]) -> NDArray[np.bool_]:
        u = np.cosh(b) + eps_m
        reach = np.sqrt(1.0 + (lam_m * u) ** 2) + lam_m * u
        return np.asarray(lam * (np.cosh(b) + kappa * reach + eps) < 1.0)

    lo = np.zeros_like(a_m)
    hi = a_m.copy()
    ok = fits(lo)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        good = fits(mid)
        lo = np.where(good, mid, lo)
        hi = np.where(good, hi, mid)
    return np.asarray(np.where(ok, lo, 0.0), dtype=np.float64)


def _link_parts(engine: Engine) -> tuple[LinkGeometry, NDArray[np.float64], NDArray[np.intp]]:
    from balance.core.links import engine_geometry, pin_masses

    assert engine.links is not None
    geometry = engine_geometry(engine)
    j = geometry.cylinder
    ratio = pin_masses(engine)[j] / engine.reciprocating_mass[j]
    plain = np.flatnonzero(engine.links.master < 0)
    return geometry, np.asarray(ratio, dtype=np.float64), plain


def _plain_arrays(engine: Engine) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    r = engine.crank_radius
    return kinematics.rod_ratio(r, engine.conrod_length), kinematics.offset_ratio(engine.offset, r)


def series_parameters(engine: Engine) -> tuple[float, float]:
    r"""What the truncated models' errors grow with, for an engine's cylinders.

    Parameters
    ----------
    engine : Engine
        The engine (each cylinder's own crank radius, conrod and offset; a link cylinder's
        link rod as its conrod).

    Returns
    -------
    ratio : float
        The largest rod ratio :math:`\lambda = r/l` [1]: the ``textbook`` model's second
        order is low by about :math:`\lambda^2/4`.
    x : float
        The largest :math:`\lambda(1 + |e|/r)` [1]: the ``series`` model's error falls
        like :math:`x^{2n+1}` with its terms n (:func:`series_bound`).
    """
    lam, eps = _plain_arrays(engine)
    return float(np.max(lam)), float(np.max(lam * (1.0 + np.abs(eps))))


def engine_error_bound(
    model: str, engine: Engine, *, terms: int = 3, samples: int = 0, max_order: int = 8
) -> float:
    """:func:`error_bound` of an engine, link cylinders included (see the module notes).

    For an engine without link rods this is :func:`error_bound` of its rod and offset
    ratios.

    Parameters
    ----------
    model : {'textbook', 'series', 'exact', 'time'}
        The piston-acceleration model.
    engine : Engine
        The engine (each cylinder's crank radius, rod and offset; link rods and pins).
    terms : int
        Binomial terms of the ``series`` model.
    samples : int
        Crank angles per revolution of the ``time`` model.
    max_order : int
        Highest order reported.

    Returns
    -------
    float
        The bound over all cylinders [1]; infinite where the estimate does not hold.

    Raises
    ------
    AnalysisError
        For an unknown model.
    """
    lam, eps = _plain_arrays(engine)
    if not engine.has_links:
        return error_bound(model, lam, eps, terms=terms, samples=samples, max_order=max_order)
    from balance.core.links import link_reach

    geometry, mass_ratio, plain = _link_parts(engine)
    bounds = []
    if plain.size:
        bounds.append(
            error_bound(
                model, lam[plain], eps[plain], terms=terms, samples=samples, max_order=max_order
            )
        )
    reach = np.maximum(
        link_reach(geometry), geometry.ratio_master * (1.0 + np.abs(geometry.offset_master))
    )
    x = float(np.max(reach))
    rounding = _rounding(x) if x < 1 else math.inf
    if model in {"textbook", "series"}:
        idealised = [
            error_bound(model, lam[i], eps[i], terms=terms) for i in geometry.cylinder.tolist()
        ]
        extra = articulation_bound(geometry, mass_ratio)
        bounds.append(float(np.max(np.asarray(idealised) + extra)))
    elif model == "exact":
        bounds.append(rounding)
    elif model == "time":
        if samples <= 2 * max_order:
            return math.inf
        a = float(np.min(link_strip(geometry)))
        if a <= 0 or x >= 1:
            return math.inf
        bounds.append(_aliasing(x, a, samples, max_order) + rounding)
    else:
        raise AnalysisError(f"unknown model {model!r}")
    return float(max(bounds))


def choose_model_for(tolerance: float, engine: Engine) -> tuple[str, int, float]:
    """:func:`choose_model` for an engine, link cylinders included.

    For an engine without link rods this is :func:`choose_model` of its rod and offset
    ratios; with link rods the ladder stops at the exact model (no long series).

    Parameters
    ----------
    tolerance : float
        Largest error allowed in the normalised coefficients [1], more than 0.
    engine : Engine
        The engine.

    Returns
    -------
    model : str
        ``'textbook'``, ``'series'`` or ``'exact'``.
    terms : int
        Series terms (0 unless the series is chosen).
    bound : float
        The error bound achieved [1].

    Raises
    ------
    AnalysisError
        If no model reaches the tolerance.
    """
    bound = partial(engine_error_bound, engine=engine)
    return _cheapest(tolerance, bound, long_series=not engine.has_links)
