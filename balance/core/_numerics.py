r"""Numerical helpers of the core: Fourier series, extremum searches, quadrature rules.

Private to :mod:`balance.core`; each helper is generic (arrays and callables in, arrays out)
and carries no physics.

* **Fourier series** :math:`F(\theta) = \sum_k c_k e^{\mathrm{i}k\theta}`, one per row of
  coefficients: from samples of a periodic function (:func:`fourier_series`, FFT on a grid
  doubled to rounding), at given angles (:func:`series_values`, Horner's scheme) or on a
  uniform grid (:func:`series_on_grid`, inverse FFT).
* **Stationary points** by Newton's method on the derivative
  (:func:`newton_stationary`; of :math:`|F|^2` of a series: :func:`series_stationary`),
  started from the vertex of the parabola through three samples
  (:func:`parabola_vertex`, :func:`sampled_vertex`); a bound of a sampled maximum
  (:func:`sampled_max_bound`).
* **Golden-section searches** for the minimum of a quantity in a bracket
  (:func:`golden_section_min`) and for the maxima of sampled quantities
  (:func:`golden_section_max`).
* **Gauss–Legendre rules**: panels between given edges (:func:`gauss_panels`), graded
  geometrically towards points (:func:`graded_periodic_rule`, :func:`graded_segments`).
* **Largest value and mean of** :math:`|F|` over a period: of a Fourier series
  (:func:`series_stats`), or of any quantity from the nodes of a piecewise rule
  (:func:`node_stats`).
* **Mean** of an engine's per-cylinder values (:func:`mean`).
* **Rows**: a linear combination summed row by row, so that a column's bits do not depend
  on the other columns (:func:`ordered_combination`); the distinct rows of an array in
  order of first appearance (:func:`unique_rows`).

.. rubric:: References

Press, Teukolsky, Vetterling and Flannery, *Numerical Recipes*, 3rd ed., Cambridge 2007,
sec. 4.6 (Gauss–Legendre quadrature), 9.4 (Newton–Raphson) and 10.2 (golden-section
search); Trefethen and Weideman, "The exponentially convergent trapezoidal rule", SIAM
Review 56 (2014) (the uniform rule of a periodic function, and its slow convergence near a
kink).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

_EPS = float(np.finfo(np.float64).eps)

#: Uniform grid of the mean of a magnitude (trapezoidal rule), checked on twice as many.
START_GRID = 1024
#: Change of a mean between the two grids, relative to the quantity's maximum, below which
#: the trapezoidal rule has converged; otherwise the graded rule integrates that quantity.
MEAN_TOLERANCE = 1e-13
#: Newton iterations of a maximum (or minimum) from the sampled one.
NEWTON_ITERATIONS = 8
#: Newton step [rad] after which an extremum has converged (quadratic convergence: the
#: next step would be of the order of its square).
NEWTON_DONE = 1e-9
#: Graded Gauss–Legendre rule of a near-singular mean: nodes per panel, ratio, levels.
GRADED_NODES = 16
GRADED_RATIO = 0.25
GRADED_LEVELS = 26
#: Sampled local minima of a slow quantity below this share of its maximum are graded to.
GRADE_BELOW = 0.1
#: Gauss–Legendre nodes per interval of the piecewise rule of :func:`node_stats`.
GAUSS_NODES = 4
#: Candidate local maxima refined per quantity.
CANDIDATES = 3
#: Golden-section iterations (bracket shrinks by 0.618 each).
GOLDEN_ITERATIONS = 64


@dataclass(frozen=True)
class RowStats:
    """Largest value, its angle and the mean of each row's quantity over a period.

    ``samples`` is the number of points behind the means (the uniform grid, or the nodes of
    the piecewise rule).
    """

    maximum: FloatArray
    argmax: FloatArray
    mean: FloatArray
    samples: int


# --------------------------------------------------------------------------- Fourier series


def series_values(k: NDArray[np.intp], coeffs: ComplexArray, theta: ArrayLike) -> ComplexArray:
    """:math:`\\sum_k c_k e^{ik\\theta}` of each row of ``coeffs`` at the angles ``theta``.

    ``theta`` has shape (angles,) (every row at every angle) or (rows, ...) (each row at its
    own angles); Horner's scheme in :math:`e^{i\\theta}` over the orders k (consecutive).
    """
    th = np.asarray(theta, dtype=np.float64)
    order = np.argsort(k)
    ks, cs = k[order], coeffs[:, order]
    if th.ndim == 1:
        z = np.exp(1j * th)[None, :]
        cs = cs[:, :, None]
    else:
        z = np.exp(1j * th)
        cs = cs.reshape(cs.shape[:2] + (1,) * (th.ndim - 1))
    acc = np.zeros(np.broadcast_shapes(z.shape, cs[:, 0].shape), dtype=np.complex128)
    for j in range(ks.size - 1, -1, -1):
        acc = acc * z + cs[:, j]
    return np.asarray(acc * z ** int(ks[0]))


def fourier_series(
    f: Callable[[FloatArray], ComplexArray], start: int, largest: int
) -> tuple[NDArray[np.intp], ComplexArray]:
    r"""Orders k and coefficients :math:`c_k` of the rows of a smooth periodic
    :math:`f(\theta) = \sum_k c_k e^{ik\theta}` (period :math:`2\pi`).

    FFT of ``f`` on a uniform grid of ``start`` points, doubled (up to ``largest``) until
    the top quarter of the spectrum is below :math:`16\varepsilon` of its largest
    coefficient; the orders :math:`|k| < n/4` are kept (the rest is below rounding: the
    coefficients of an analytic function fall geometrically).
    """
    n = start
    while True:
        theta = 2.0 * np.pi * np.arange(n) / n
        spectrum = np.fft.fft(f(theta), axis=1) / n
        k = np.rint(np.fft.fftfreq(n) * n).astype(np.intp)
        mag = np.abs(spectrum)
        scale = float(mag.max()) if mag.size else 0.0
        tail = float(mag[:, np.abs(k) >= n // 4].max()) if mag.size else 0.0
        if tail <= 16.0 * _EPS * scale or n >= largest:
            break
        n *= 2
    keep = np.abs(k) < n // 4  # the rest is below rounding
    return k[keep], spectrum[:, keep]


def ordered_combination(shares: FloatArray, values: ComplexArray) -> ComplexArray:
    r""":math:`\sum_j S_{mj} F_j` at every column, shape (rows of ``shares``, columns).

    Summed row of ``values`` by row, in order, so that a column's result has the same bits
    whatever other columns are evaluated with it (a matrix product's kernel, and so its
    rounding, depends on the number of columns): a search that evaluates one angle at a time
    then compares exactly with the values on a grid.
    """
    out = np.zeros((shares.shape[0], values.shape[1]), dtype=np.complex128)
    for j in range(shares.shape[1]):
        out += shares[:, j : j + 1] * values[j]
    return out


def series_on_grid(k: NDArray[np.intp], coeffs: ComplexArray, n: int) -> ComplexArray:
    """The series on the uniform grid of ``n`` points per revolution (inverse FFT)."""
    spectrum = np.zeros((coeffs.shape[0], n), dtype=np.complex128)
    np.add.at(spectrum.T, k % n, coeffs.T)
    return np.asarray(np.fft.ifft(spectrum, axis=1) * n)


# --------------------------------------------------------------------------- extrema


def newton_stationary(
    derivatives: Callable[[FloatArray], tuple[FloatArray, FloatArray]],
    start: ArrayLike,
    iterations: int,
    tolerance: float,
    *,
    max_step: float | None = None,
    extra_step: bool = False,
) -> FloatArray:
    r"""Stationary points of a function near ``start``, by Newton's method on its derivative.

    Parameters
    ----------
    derivatives : callable
        :math:`x \mapsto (f'(x), f''(x))`, elementwise over an array of points.
    start : array_like
        Starting points (any shape).
    iterations : int
        Largest number of steps.
    tolerance : float
        Largest step (every point's) after which the iteration has converged.
    max_step : float, optional
        Limit of each step; a point where :math:`f'' = 0` then takes no step.  Without it
        the step is :math:`f'/f''` as it is.
    extra_step : bool
        Take one more step after convergence (quadratic convergence puts it below
        rounding).

    Returns
    -------
    ndarray
        :math:`x_{n+1} = x_n - f'(x_n)/f''(x_n)` at the last step.
    """
    x = np.array(start, dtype=np.float64)
    converged = False
    for _ in range(iterations):
        d1, d2 = derivatives(x)
        if max_step is None:
            step = d1 / d2
        else:
            with np.errstate(divide="ignore", invalid="ignore"):
                step = np.clip(
                    np.nan_to_num(np.where(d2 != 0.0, d1 / d2, 0.0)), -max_step, max_step
                )
        x = x - step
        if converged:
            break
        converged = bool(np.max(np.abs(step), initial=0.0) <= tolerance)
        if converged and not extra_step:
            break
    return x


def series_stationary(
    k: NDArray[np.intp], coeffs: ComplexArray, theta: FloatArray, step: float
) -> tuple[FloatArray, FloatArray]:
    """Stationary points of :math:`|F|^2` near ``theta`` (one row of angles per quantity).

    Newton on :math:`g = \\mathrm{Re}(\\bar F F')`, with
    :math:`g' = |F'|^2 + \\mathrm{Re}(\\bar F F'')`, each step limited to ``step``
    (:func:`newton_stationary`); returns the angles and :math:`|F|` there.
    """
    ik = 1j * k
    c0 = coeffs.reshape(coeffs.shape[:1] + (1,) * (np.ndim(theta) - 1) + coeffs.shape[1:])
    c1, c2 = ik * c0, ik * ik * c0

    def derivatives(th: FloatArray) -> tuple[FloatArray, FloatArray]:
        # each row at its own few angles: the terms directly (cheaper than Horner here)
        e = np.exp(1j * th[..., None] * k)
        f, d1, d2 = (e * c0).sum(axis=-1), (e * c1).sum(axis=-1), (e * c2).sum(axis=-1)
        g = np.real(np.conj(f) * d1)
        dg = np.abs(d1) ** 2 + np.real(np.conj(f) * d2)
        return g, dg

    th = newton_stationary(derivatives, theta, NEWTON_ITERATIONS, NEWTON_DONE, max_step=step)
    return th, np.abs((np.exp(1j * th[..., None] * k) * c0).sum(axis=-1))


def parabola_vertex(before: ArrayLike, at: ArrayLike, after: ArrayLike) -> FloatArray:
    r"""Vertex of the parabola through three equally spaced samples, in grid steps from the
    middle one, within :math:`\pm 1/2` (0 where the samples are in line).

    :math:`\tfrac12 (f_{-1} - f_{+1}) / (f_{-1} - 2f_0 + f_{+1})`: where Newton's method
    (or a search) starts, close to the extremum that the middle sample stands for.
    """
    fm, f0, fp = (np.asarray(v, dtype=np.float64) for v in (before, at, after))
    curvature = fm - 2.0 * f0 + fp
    with np.errstate(divide="ignore", invalid="ignore"):
        shift = np.where(curvature != 0.0, 0.5 * (fm - fp) / curvature, 0.0)
    return np.asarray(np.clip(np.nan_to_num(shift), -0.5, 0.5))


def sampled_max_bound(values: FloatArray, second: FloatArray) -> FloatArray:
    r"""Bound of :math:`\max|f|` over one period from :math:`f` and :math:`f''` sampled on a
    uniform grid of :math:`N` points (last axis): :math:`\max|f_j| + \max|f''_j|\,
    (\pi/N)^2/2`.

    Between two samples :math:`h = 2\pi/N` apart, :math:`|f|` exceeds the larger of them by
    at most :math:`\max|f''|\,h^2/8` (the error of linear interpolation).
    """
    n = values.shape[-1]
    top = np.max(np.abs(values), axis=-1)
    curvature = np.max(np.abs(second), axis=-1)
    return np.asarray(top + curvature * (np.pi / n) ** 2 / 2.0)


def sampled_vertex(values: FloatArray, picks: NDArray[np.intp]) -> FloatArray:
    r"""Where the extrema that samples ``picks`` stand for lie, by :func:`parabola_vertex`:
    ``values`` on the uniform grid :math:`2\pi j/n` of one period (last axis), ``picks``
    indices into it (along the last axis); returns angles [rad], the shape of ``picks``."""
    n = values.shape[-1]
    grid = 2.0 * np.pi * np.arange(n) / n
    before = np.take_along_axis(values, (picks - 1) % n, -1)
    after = np.take_along_axis(values, (picks + 1) % n, -1)
    at = np.take_along_axis(values, picks, -1)
    return np.asarray(grid[picks] + 2.0 * np.pi / n * parabola_vertex(before, at, after))


def _best_peaks(values: FloatArray, count: int) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """The ``count`` largest sampled local maxima of each row (periodic): their indices
    (best first; non-maxima after the maxima when a row has fewer) and whether each is one."""
    before, after = np.roll(values, 1, axis=1), np.roll(values, -1, axis=1)
    peaks = (values >= before) & (values >= after)
    ranked = np.where(peaks, values, -np.inf)
    cand = np.argsort(-ranked, axis=1)[:, :count]
    return cand, np.take_along_axis(peaks, cand, 1)


def _dips(values: FloatArray) -> NDArray[np.bool_]:
    """Sampled local minima of each row (periodic)."""
    return np.asarray(
        (values <= np.roll(values, 1, axis=1)) & (values <= np.roll(values, -1, axis=1))
    )


def golden_section_min(
    f: Callable[[FloatArray], FloatArray], rows: NDArray[np.intp], lo: FloatArray, hi: FloatArray
) -> FloatArray:
    """Golden-section search for the minimum of row ``rows[d]`` of ``f`` in
    ``[lo[d], hi[d]]``, for every d at once (each search the same steps as alone)."""
    r = (math.sqrt(5.0) - 1.0) / 2.0
    cols = np.arange(rows.size)

    def g(t: FloatArray) -> FloatArray:
        return f(t)[rows, cols]

    x1, x2 = hi - r * (hi - lo), lo + r * (hi - lo)
    g1, g2 = g(x1), g(x2)
    for _ in range(GOLDEN_ITERATIONS):
        left = g1 <= g2  # the minimum is in [lo, x2]: shift left, else in [x1, hi]
        lo, hi = np.where(left, lo, x1), np.where(left, x2, hi)
        fresh_x = np.where(left, hi - r * (hi - lo), lo + r * (hi - lo))
        fresh = g(fresh_x)
        x1, x2 = np.where(left, fresh_x, x2), np.where(left, x1, fresh_x)
        g1, g2 = np.where(left, fresh, g2), np.where(left, g1, fresh)
    return np.where(g1 <= g2, x1, x2)


def golden_section_max(
    f: Callable[[FloatArray], FloatArray], theta: FloatArray, values: FloatArray, period: float
) -> tuple[FloatArray, FloatArray]:
    """Golden-section refinement of the best sampled local maxima of each row of ``values``.

    ``theta`` is increasing over one period; row q of ``f(t)`` is quantity q at angles t.
    Returns each row's largest value and its angle in [0, period).
    """
    n_q, n = values.shape
    k = min(CANDIDATES, n)
    idx, _ = _best_peaks(values, k)  # (q, k)
    ext = np.concatenate([theta[-1:] - period, theta, theta[:1] + period])
    lo, hi = ext[idx], ext[idx + 2]  # the neighbours (ext is shifted by one)
    rows = np.repeat(np.arange(n_q), k)

    def at(t: FloatArray) -> FloatArray:
        # quantity q at its own angles: evaluate all quantities at all angles, keep the diagonal
        return f(t.ravel())[rows, np.arange(rows.size)].reshape(n_q, k)

    g = (math.sqrt(5.0) - 1.0) / 2.0
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = at(x1), at(x2)
    for _ in range(GOLDEN_ITERATIONS):
        left = f1 >= f2  # the maximum is in [lo, x2]: shift left, else in [x1, hi]
        lo, hi = np.where(left, lo, x1), np.where(left, x2, hi)
        x1, x2 = np.where(left, hi - g * (hi - lo), x2), np.where(left, x1, lo + g * (hi - lo))
        f1, f2 = np.where(left, np.nan, f2), np.where(left, f1, np.nan)
        fresh = at(np.where(left, x1, x2))
        f1, f2 = np.where(left, fresh, f1), np.where(left, f2, fresh)
    best_x = np.where(f1 >= f2, x1, x2)
    best_f = np.maximum(f1, f2)
    sampled = np.take_along_axis(values, idx, 1)
    best_f, best_x = (
        np.where(best_f >= sampled, best_f, sampled),
        np.where(best_f >= sampled, best_x, theta[idx]),
    )
    pick = np.argmax(best_f, axis=1)
    rows_q = np.arange(n_q)
    return best_f[rows_q, pick], np.mod(best_x[rows_q, pick], period)


# --------------------------------------------------------------------------- quadrature


@functools.cache
def gauss_legendre(n: int) -> tuple[FloatArray, FloatArray]:
    """Nodes and weights of the ``n``-point Gauss–Legendre rule on [-1, 1]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return np.asarray(x), np.asarray(w)


def gauss_panels(edges: FloatArray, n: int) -> tuple[FloatArray, FloatArray]:
    """Nodes and weights of the ``n``-point Gauss–Legendre rule on every interval between
    consecutive ``edges`` (increasing), ``n`` per interval in order."""
    x, w = gauss_legendre(n)
    lo, hi = edges[:-1, None], edges[1:, None]
    return (0.5 * (lo + hi) + 0.5 * (hi - lo) * x).ravel(), (0.5 * (hi - lo) * w).ravel()


def graded_periodic_rule(
    points: FloatArray, top_order: int, depth: int = GRADED_LEVELS
) -> tuple[FloatArray, FloatArray]:
    """Gauss–Legendre nodes and weights over one period, graded towards ``points``.

    Between consecutive points (cyclically), panels no longer than :math:`h` with
    :math:`k_{max} h \\le 8`; the panels touching a point are subdivided geometrically
    (ratio :data:`GRADED_RATIO`, ``depth`` levels, at most :data:`GRADED_LEVELS`) towards it.
    """
    p = np.sort(np.mod(points, 2.0 * np.pi))
    p = np.concatenate([p, [p[0] + 2.0 * np.pi]])
    h_max = 8.0 / max(top_order, 1)
    levels = GRADED_RATIO ** np.arange(1, depth + 1)
    edges_all = []
    for a, b in itertools.pairwise(p):
        length = b - a
        if length <= 0.0:
            continue
        n = max(2, math.ceil(length / h_max))
        h = length / n
        inner = a + h * np.arange(1, n)
        edges_all.append(np.concatenate([[a], a + h * levels[::-1], inner, b - h * levels]))
    edges = np.concatenate([*edges_all, [p[-1]]])
    return gauss_panels(edges, GRADED_NODES)


def graded_segments(breaks: FloatArray, toward: float) -> tuple[FloatArray, FloatArray]:
    """Gauss nodes and weights on the segments between ``breaks``, those touching
    ``toward`` graded geometrically towards it."""
    levels = GRADED_RATIO ** np.arange(1, GRADED_LEVELS + 1)
    edges = []
    for a, b in itertools.pairwise(breaks):
        if b <= a:
            continue
        if a == toward:
            edges.append(np.concatenate([[a], a + (b - a) * levels[::-1]]))
        elif b == toward:
            edges.append(np.concatenate([[a], b - (b - a) * levels]))
        else:
            edges.append(np.array([a]))
    return gauss_panels(np.concatenate([*edges, breaks[-1:]]), GRADED_NODES)


# --------------------------------------------------------------------------- max and mean


def series_stats(
    k: NDArray[np.intp], coeffs: ComplexArray, mean_wanted: NDArray[np.bool_] | None = None
) -> RowStats:
    """Refined maximum and mean of :math:`|F|` for each row of Fourier coefficients.

    ``mean_wanted`` (a mask over the rows, default all) names the rows whose mean is
    reported; the others get the sampled mean only, without the graded refinement near a
    zero of :math:`|F|` (a quantity whose maximum alone is used).

    Notes
    -----
    The mean is the trapezoidal rule on :data:`START_GRID` points (at least four per
    term), converged when the rule on every other point agrees to :data:`MEAN_TOLERANCE`
    of the maximum; otherwise (a near-zero of :math:`|F|`, where it is nearly a kink) the
    Gauss–Legendre rule of :func:`graded_periodic_rule`, graded towards the refined minima.
    The maximum is Newton's (:func:`series_stationary`) from the :data:`CANDIDATES` best
    sampled local maxima, each started at the vertex of the parabola through its samples.
    """
    n_q = coeffs.shape[0]
    n = max(START_GRID, 4 * k.size)
    values = np.abs(series_on_grid(k, coeffs, n))
    mean = values.mean(axis=1)
    top = values.max(axis=1)
    # the trapezoidal rule converges geometrically: when the rule on every other point
    # agrees with the full one, the full one is converged further still
    coarser = values[:, ::2].mean(axis=1)
    converged = np.abs(coarser - mean) <= MEAN_TOLERANCE * top
    # maximum: Newton from the best sampled local maxima (a parabola through the three
    # samples around each for the start, so that two or three steps reach rounding)
    theta = 2.0 * np.pi * np.arange(n) / n
    cand, is_peak = _best_peaks(values, CANDIDATES)
    h = 2.0 * np.pi / n
    start = sampled_vertex(values, cand)
    # fewer local maxima than candidates: the spare ones repeat the best (a start that is
    # no peak would wander, limited to a step per iteration, and never converge)
    start = np.where(is_peak, start, start[:, :1])
    th, val = series_stationary(k, coeffs, start, h)
    sampled = np.take_along_axis(values, cand, 1)
    val = np.where(val >= sampled, val, sampled)
    th = np.where(val >= sampled, th, theta[cand])
    pick = np.argmax(val, axis=1)
    rows = np.arange(n_q)
    maximum, argmax = val[rows, pick], np.mod(th[rows, pick], 2.0 * np.pi)
    # near-singular quantities: graded Gauss-Legendre from the minimum of |F|
    wanted = np.ones(n_q, dtype=bool) if mean_wanted is None else mean_wanted
    slow = np.flatnonzero(~converged & (top > 0) & wanted)
    dips = _dips(values)
    top_order = int(np.max(np.abs(k)))
    for row in slow:
        near = np.flatnonzero(dips[row] & (values[row] <= GRADE_BELOW * top[row]))
        if near.size == 0:
            near = np.array([int(np.argmin(values[row]))])
        starts = theta[near][None, :]
        th_min, f_min = series_stationary(k, coeffs[row : row + 1], starts, h)
        # |F| is smooth on the scale m/|F'| around a minimum m; |F'| <= k_max max|F|
        # (Bernstein), so grading down to that scale (two levels more) is enough
        scale = max(float(np.min(f_min)), _EPS * top[row]) / (max(top_order, 1) * top[row])
        depth = math.ceil(math.log(scale * max(top_order, 1) / 8.0) / math.log(GRADED_RATIO))
        t, w = graded_periodic_rule(th_min[0], top_order, min(GRADED_LEVELS, max(4, depth + 2)))
        f = np.abs(series_values(k, coeffs[row : row + 1], t[None, :]))[0]
        mean[row] = _quadrature(f, w) / (2.0 * np.pi)
    return RowStats(maximum, argmax, mean, n)


def _quadrature(values: FloatArray, weights: FloatArray) -> FloatArray:
    r""":math:`\sum_i v_i w_i` over the last axis, summed by numpy's own loop: a BLAS
    product (``values @ weights``) splits a long sum between its threads, so that its last
    bits would depend on the machine's number of cores."""
    return np.asarray(np.einsum("...i,i->...", values, weights), dtype=np.float64)


def node_stats(
    f: Callable[[FloatArray], FloatArray],
    nodes: FloatArray,
    weights: FloatArray,
    edges: FloatArray,
    period: float,
    mean_wanted: bool = True,
) -> RowStats:
    """Max and mean of the rows of ``f`` from Gauss nodes between kink ``edges``.

    ``nodes`` and ``weights`` are :data:`GAUSS_NODES` per interval between consecutive
    ``edges`` (:func:`gauss_panels`), over one ``period``.  Where a quantity dips towards
    zero (a sampled local minimum below :data:`GRADE_BELOW` of its maximum) its integral over
    the three intervals around the dip is taken again, split at the refined minimum
    (:func:`golden_section_min`) and graded towards it (:func:`graded_segments`).  Without
    ``mean_wanted`` (only the maximum is used) the dips are not refined and the mean is the
    Gauss rule's alone.  The maximum is :func:`golden_section_max`'s.

    ``f`` must give each angle's values independently of the other angles it is given (the
    searches evaluate one angle per dip, the rules many at once); every dip is searched and
    integrated at once, each exactly as it would be alone.
    """
    values = f(nodes)
    integral = _quadrature(values, weights)
    top = values.max(axis=1)
    dips = _dips(values)
    dips &= values <= GRADE_BELOW * top[:, None]
    n_int = edges.size - 1
    ext = np.concatenate([edges[-2:-1] - period, edges, edges[1:2] + period])
    done: set[tuple[int, int]] = set()
    found: list[tuple[int, int, int]] = []  # (row, interval, node) of each dip refined
    for row, i in zip(*np.nonzero(dips), strict=True) if mean_wanted else ():
        j = int(i) // GAUSS_NODES
        if (int(row), j) in done or top[row] == 0.0:
            continue
        done.update((int(row), q) for q in ((j - 1) % n_int, j, (j + 1) % n_int))
        found.append((int(row), j, int(i)))
    if found:
        rows = np.array([r for r, _, _ in found])
        at = np.array([i for _, _, i in found])
        lo_t = nodes[(at - 1) % nodes.size] - np.where(at == 0, period, 0.0)
        hi_t = nodes[(at + 1) % nodes.size] + np.where(at == nodes.size - 1, period, 0.0)
        t_min = golden_section_min(f, rows, lo_t, hi_t)
        pieces = []
        for (_, j, _), t0 in zip(found, t_min, strict=True):
            breaks = np.sort(np.array([ext[j], ext[j + 1], ext[j + 2], ext[j + 3], t0]))
            pieces.append(graded_segments(breaks, float(t0)))
        graded = f(np.concatenate([t for t, _ in pieces]))
        first = 0
        for (row, j, _), (t, w) in zip(found, pieces, strict=True):
            span = [(j - 1) % n_int, j, (j + 1) % n_int]
            old = sum(
                _quadrature(
                    values[row, q * GAUSS_NODES : (q + 1) * GAUSS_NODES],
                    weights[q * GAUSS_NODES : (q + 1) * GAUSS_NODES],
                )
                for q in span
            )
            integral[row] += _quadrature(graded[row, first : first + t.size], w) - old
            first += t.size
    maximum, argmax = golden_section_max(f, nodes, values, period)
    return RowStats(maximum, argmax, integral / period, nodes.size)


# --------------------------------------------------------------------------- rows


def unique_rows(values: FloatArray) -> tuple[FloatArray, NDArray[np.intp]]:
    """The distinct rows (in order of first appearance) and each row's index among them."""
    seen: dict[tuple[float, ...], int] = {}
    inverse = np.empty(values.shape[0], dtype=np.intp)
    for i, row in enumerate(values.tolist()):
        inverse[i] = seen.setdefault(tuple(row), len(seen))
    unique = np.array(list(seen), dtype=np.float64).reshape(len(seen), values.shape[1])
    return unique, inverse


def mean(values: FloatArray) -> float:
    """``float(np.mean(values))``, of a float array at a third of its cost: numpy's mean is
    the same pairwise sum over the count, in one division (the same bits)."""
    if type(values) is np.ndarray and values.dtype.type is np.float64 and values.size:
        return float(values.sum()) / values.size
    return float(np.mean(values))
