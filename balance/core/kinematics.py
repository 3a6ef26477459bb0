r"""Kinematics of the crank slider, with offset (desaxé).

All functions are pure, take numpy arrays (broadcast against each other) and return SI
floats.  ``beta`` is the crank angle from the cylinder's own top dead centre [rad] (the
crank pin on the bore axis direction); derivatives are with respect to ``beta``.  At
constant crank speed :math:`\omega` the time derivatives are :math:`\omega s'` and
:math:`\omega^2 s''`.

The Fourier coefficients of the normalised piston acceleration are the heart of the
analysis; three models give them:

``exact``
    FFT of the exact acceleration, with the number of samples doubled until the aliased
    spectrum is below machine precision (default).
``series``
    The binomial series of the conrod term in :math:`\lambda`, truncated after a chosen
    number of terms (the classical :math:`A_2, A_4, A_6` expansion).
``textbook``
    :math:`\cos\beta + \lambda\cos 2\beta`.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Iterator, Sequence
from contextvars import ContextVar
from math import comb
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.errors import AnalysisError
from balance.core.speed import speed_squared

#: While :func:`shared_coefficients` is active: the coefficients computed so far, by their
#: function and inputs (None otherwise).
_SHARED: ContextVar[dict[tuple[Any, ...], Any] | None] = ContextVar("_SHARED", default=None)


@contextlib.contextmanager
def shared_coefficients() -> Iterator[None]:
    """Within the block, :func:`acceleration_coefficients` and :func:`roll_coefficients` of
    inputs seen before return what they returned then (the same arrays, not to be changed):
    for analyses that repeat one geometry with other masses (several crank axes).

    Yields
    ------
    None
    """
    token = _SHARED.set({})
    try:
        yield
    finally:
        _SHARED.reset(token)


def _shared(key: tuple[Any, ...], compute: Callable[[], Any]) -> Any:
    """``compute()``, or what it gave for ``key`` within :func:`shared_coefficients`."""
    cache = _SHARED.get()
    if cache is None:
        return compute()
    if key not in cache:
        cache[key] = compute()
    return cache[key]


def _key(name: str, *arrays: NDArray[Any], extra: tuple[Any, ...] = ()) -> tuple[Any, ...]:
    return (name, *((a.shape, a.dtype.str, a.tobytes()) for a in arrays), *extra)


__all__ = [
    "MODELS",
    "acceleration_coefficients",
    "conrod_angle",
    "conrod_angle_derivatives",
    "fourier_coefficients",
    "normalised_acceleration",
    "normalised_slider",
    "offset_ratio",
    "piston_acceleration",
    "piston_position",
    "piston_velocity",
    "rod_ratio",
    "roll_coefficients",
    "rounding_floor",
    "series_coefficients_centred",
    "shared_coefficients",
    "textbook_slider",
    "unique_pairs",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

MODELS = ("exact", "series", "textbook")

#: Largest number of samples the exact FFT model may use.
MAX_SAMPLES = 2**21
_EPS = float(np.finfo(np.float64).eps)


def rod_ratio(crank_radius: ArrayLike, conrod_length: ArrayLike) -> FloatArray:
    r"""The rod ratio :math:`\lambda = r / l` (crank radius over conrod length).

    Every place that needs :math:`\lambda` forms it here, by the one division, so that a
    sweep, a single analysis and a view agree bit for bit.  Precondition: ``conrod_length``
    is positive (checked where the layout is read).

    Parameters
    ----------
    crank_radius, conrod_length : array_like
        :math:`r` and :math:`l` [m], broadcasting.

    Returns
    -------
    ndarray
        :math:`\lambda` [1].
    """
    return np.asarray(
        np.asarray(crank_radius, dtype=np.float64) / np.asarray(conrod_length, dtype=np.float64)
    )


def offset_ratio(offset: ArrayLike, crank_radius: ArrayLike) -> FloatArray:
    r"""The offset (desaxé) ratio :math:`\varepsilon = e / r` (pin offset over crank radius).

    Precondition: ``crank_radius`` is positive (checked where the layout is read).

    Parameters
    ----------
    offset, crank_radius : array_like
        :math:`e` and :math:`r` [m], broadcasting.

    Returns
    -------
    ndarray
        :math:`\varepsilon` [1].
    """
    return np.asarray(
        np.asarray(offset, dtype=np.float64) / np.asarray(crank_radius, dtype=np.float64)
    )


def _conrod_terms(
    beta: ArrayLike, ratio: ArrayLike, offset_ratio: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    b = np.asarray(beta, dtype=np.float64)
    lam = np.asarray(ratio, dtype=np.float64)
    eps = np.asarray(offset_ratio, dtype=np.float64)
    sin_b, cos_b = np.sin(b), np.cos(b)
    u = sin_b - eps
    D = np.sqrt(1.0 - (lam * u) ** 2)
    return sin_b, cos_b, u, D, lam


def normalised_slider(
    beta: ArrayLike, ratio: ArrayLike, offset_ratio: ArrayLike = 0.0
) -> tuple[FloatArray, FloatArray, FloatArray]:
    r"""Piston position and its first two derivatives, divided by the crank radius.

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    ratio : array_like
        :math:`\lambda = r/l`, crank radius over conrod length [1].
    offset_ratio : array_like
        :math:`\varepsilon = e/r`, offset over crank radius [1].

    Returns
    -------
    s, ds, d2s : ndarray
        :math:`s/r`, :math:`s'/r` [1/rad] and :math:`s''/r` [1/rad^2].

    Notes
    -----
    With :math:`u = \sin\beta - \varepsilon` and :math:`D = \sqrt{1-\lambda^2u^2}`:

    .. math::

        s/r &= \cos\beta + D/\lambda \\
        s'/r &= -\sin\beta - \lambda u\cos\beta / D \\
        s''/r &= -\cos\beta - \lambda\left[\frac{\cos^2\beta - u\sin\beta}{D}
                 + \frac{\lambda^2u^2\cos^2\beta}{D^3}\right]

    written without differences of large terms, so that they stay accurate as
    :math:`\lambda \to 0`.

    References
    ----------
    Heywood, *Internal Combustion Engine Fundamentals*, McGraw-Hill 1988, sec. 2.2, eq. (2.4)
    (position, e = 0); Taylor, *The Internal Combustion Engine in Theory and Practice*,
    vol. 2, 2nd ed., MIT Press 1985, ch. 8 (piston velocity and acceleration).
    """
    sin_b, cos_b, u, D, lam = _conrod_terms(beta, ratio, offset_ratio)
    s = cos_b + D / lam
    ds = -sin_b - lam * u * cos_b / D
    d2s = -cos_b - lam * ((cos_b**2 - u * sin_b) / D + (lam * u * cos_b) ** 2 / D**3)
    return s, ds, d2s


def textbook_slider(beta: ArrayLike, ratio: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    r"""The two-term approximation of the crank slider (no offset), divided by the crank radius.

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    ratio : array_like
        :math:`\lambda = r/l` [1].

    Returns
    -------
    s, ds, d2s : ndarray
        :math:`s/r = \cos\beta + 1/\lambda - \tfrac{\lambda}{4}(1 - \cos 2\beta)`,
        :math:`s'/r = -(\sin\beta + \tfrac{\lambda}{2}\sin 2\beta)` and
        :math:`s''/r = -(\cos\beta + \lambda\cos 2\beta)`.

    Notes
    -----
    The first binomial term of the conrod's projection,
    :math:`\sqrt{1-\lambda^2\sin^2\beta} \approx 1 - \tfrac{\lambda^2}{2}\sin^2\beta`.
    These are the formulas of most textbook kinematic tables (Kolchin and Demidov, *Design
    of Automotive Engines*, Mir 1984; the VAZ-2108 table 3 of Makushev, Polyakova and
    Batrakov, "Determination of piston velocity and acceleration by means of derivatives",
    2010, in Russian, eqs. (19)–(21), is computed with them); the error in acceleration is
    of order :math:`\lambda^3`.
    """
    b = np.asarray(beta, dtype=np.float64)
    lam = np.asarray(ratio, dtype=np.float64)
    s = np.cos(b) + 1.0 / lam - 0.25 * lam * (1.0 - np.cos(2 * b))
    ds = -(np.sin(b) + 0.5 * lam * np.sin(2 * b))
    d2s = -(np.cos(b) + lam * np.cos(2 * b))
    return s, ds, d2s


def normalised_acceleration(
    beta: ArrayLike, ratio: ArrayLike, offset_ratio: ArrayLike = 0.0
) -> FloatArray:
    r"""Normalised reciprocating inertia :math:`-s''(\beta)/r` (see :func:`normalised_slider`).

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    ratio : array_like
        :math:`\lambda = r/l` [1].
    offset_ratio : array_like
        :math:`\varepsilon = e/r` [1].

    Returns
    -------
    ndarray
        :math:`-s''/r` [1/rad^2], broadcast over the arguments.
    """
    sin_b, cos_b, u, D, lam = _conrod_terms(beta, ratio, offset_ratio)
    return cos_b + lam * ((cos_b**2 - u * sin_b) / D + (lam * u * cos_b) ** 2 / D**3)


def _slider(
    beta: ArrayLike, r: FloatArray, conrod_length: ArrayLike, offset: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """:func:`normalised_slider` of a crank radius, conrod length and offset in metres."""
    return normalised_slider(beta, rod_ratio(r, conrod_length), offset_ratio(offset, r))


def piston_position(
    beta: ArrayLike, crank_radius: ArrayLike, conrod_length: ArrayLike, offset: ArrayLike = 0.0
) -> FloatArray:
    r"""Distance of the piston pin from the crank centre along the bore.

    :math:`s(\beta) = r\cos\beta + \sqrt{l^2 - (r\sin\beta - e)^2}`.

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    crank_radius, conrod_length, offset : array_like
        :math:`r`, :math:`l` and :math:`e` [m].

    Returns
    -------
    ndarray
        :math:`s` [m].
    """
    r = np.asarray(crank_radius, dtype=np.float64)
    s, _, _ = _slider(beta, r, conrod_length, offset)
    return r * s


def piston_velocity(
    beta: ArrayLike,
    crank_radius: ArrayLike,
    conrod_length: ArrayLike,
    offset: ArrayLike = 0.0,
    speed: ArrayLike = 1.0,
) -> FloatArray:
    r"""Piston velocity along the bore, away from the crank positive.

    :math:`v = \omega\, s'(\beta)`; with ``speed=1`` this is :math:`s'` [m/rad].

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    crank_radius, conrod_length, offset : array_like
        :math:`r`, :math:`l` and :math:`e` [m].
    speed : array_like
        Crank speed :math:`\omega` [rad/s].

    Returns
    -------
    ndarray
        :math:`v` [m/s].
    """
    r = np.asarray(crank_radius, dtype=np.float64)
    _, ds, _ = _slider(beta, r, conrod_length, offset)
    return np.asarray(speed) * r * ds


def piston_acceleration(
    beta: ArrayLike,
    crank_radius: ArrayLike,
    conrod_length: ArrayLike,
    offset: ArrayLike = 0.0,
    speed: ArrayLike = 1.0,
) -> FloatArray:
    r"""Piston acceleration along the bore at constant crank speed.

    :math:`a = \omega^2 s''(\beta)`; with ``speed=1`` this is :math:`s''` [m/rad^2].

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    crank_radius, conrod_length, offset : array_like
        :math:`r`, :math:`l` and :math:`e` [m].
    speed : array_like
        Crank speed :math:`\omega` [rad/s].

    Returns
    -------
    ndarray
        :math:`a` [m/s^2].
    """
    r = np.asarray(crank_radius, dtype=np.float64)
    _, _, d2s = _slider(beta, r, conrod_length, offset)
    return speed_squared(speed) * r * d2s


def conrod_angle(
    beta: ArrayLike, crank_radius: ArrayLike, conrod_length: ArrayLike, offset: ArrayLike = 0.0
) -> FloatArray:
    r"""Angle of the conrod from the bore axis.

    :math:`\sin\gamma = (r\sin\beta - e)/l`, positive when the big end is on the side the
    pin moves to after TDC.

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    crank_radius, conrod_length, offset : array_like
        :math:`r`, :math:`l` and :math:`e` [m].

    Returns
    -------
    ndarray
        :math:`\gamma` [rad].
    """
    r = np.asarray(crank_radius, dtype=np.float64)
    return np.arcsin(
        (r * np.sin(np.asarray(beta)) - np.asarray(offset)) / np.asarray(conrod_length)
    )


def conrod_angle_derivatives(
    beta: ArrayLike, ratio: ArrayLike, offset_ratio: ArrayLike = 0.0
) -> tuple[FloatArray, FloatArray]:
    r"""First and second derivative of the conrod angle with respect to crank angle.

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    ratio : array_like
        :math:`\lambda = r/l` [1].
    offset_ratio : array_like
        :math:`\varepsilon = e/r` [1].

    Returns
    -------
    dgamma, d2gamma : ndarray
        :math:`\gamma' = \lambda\cos\beta/D` [1] and
        :math:`\gamma'' = -\lambda\sin\beta/D + \lambda^3 u\cos^2\beta/D^3` [1/rad].
    """
    sin_b, cos_b, u, D, lam = _conrod_terms(beta, ratio, offset_ratio)
    dgamma = lam * cos_b / D
    d2gamma = -lam * sin_b / D + lam**3 * u * cos_b**2 / D**3
    return dgamma, d2gamma


# ---------------------------------------------------------------------------------------
# Fourier coefficients


def fourier_coefficients(
    sample: Callable[[FloatArray], FloatArray],
    orders: Sequence[int] | NDArray[np.integer],
    batch_shape: tuple[int, ...] = (),
    min_samples: int = 64,
    max_samples: int = MAX_SAMPLES,
    noise_floor: ArrayLike = 0.0,
) -> tuple[ComplexArray, int]:
    r"""Complex Fourier coefficients of a smooth periodic function, to machine precision.

    Parameters
    ----------
    sample : callable
        ``sample(beta)`` with ``beta`` of shape ``(N,)`` returns values of shape
        ``batch_shape + (N,)``.
    orders : sequence of int
        Orders :math:`k \ge 1` wanted.
    batch_shape : tuple of int
        Leading shape of what ``sample`` returns.
    min_samples, max_samples : int
        Range of the number of samples per revolution (powers of two).
    noise_floor : array_like
        The accuracy the samples allow (broadcast against ``batch_shape``): near the
        geometric limit the function is so ill-conditioned that its rounding, not the
        resolution, sets the error; once the wanted orders change by less than this from
        one doubling to the next, they are taken.

    Returns
    -------
    coefficients : ndarray of complex
        :math:`G_k = a_k - i b_k` for :math:`f(\beta) = a_0 + \sum_k (a_k\cos k\beta +
        b_k\sin k\beta)`, shape ``batch_shape + (len(orders),)``.
    samples : int
        The largest number of samples used.

    Notes
    -----
    The trapezoidal rule is spectrally accurate for analytic periodic functions: the error
    in order k is the aliased content of orders :math:`N \pm k`, which falls geometrically.
    The number of samples is doubled until the top quarter of the resolved spectrum is
    below :math:`8\epsilon` of the larger of its largest coefficient and the rms of the
    samples (the rounding floor of the samples themselves), or, very near the geometric
    limit where the tail meets that floor first, until the wanted orders change by less
    than eight times the floor from one doubling to the next.  Real and imaginary parts
    below :math:`16\epsilon` of that scale are returned as exactly 0: they cannot be told
    from rounding (an unoffset slider has no odd orders above 1 and no sine terms).

    Each function of the batch is decided on by itself: its coefficients are those of the
    first resolution at which it converges, whatever the other functions need.  A
    function therefore gets the same coefficients, bit for bit, alone or in any batch;
    this is what lets a sweep reproduce a single analysis exactly.
    """
    orders_arr = np.asarray(orders, dtype=np.intp)
    k_max = int(orders_arr.max()) if orders_arr.size else 1
    n = max(int(min_samples), 8)
    while n < 4 * (k_max + 1):
        n *= 2
    size = math.prod(batch_shape)
    noise = np.broadcast_to(np.asarray(noise_floor, dtype=np.float64), batch_shape).ravel()
    # each function is taken at the first resolution at which it converges on its own, so
    # its coefficients do not depend on what else is in the batch (a sweep and a single
    # analysis agree bit for bit)
    wanted_out = np.zeros((size, orders_arr.size), dtype=np.complex128)
    scale_out = np.zeros(size)
    pending = np.ones(size, dtype=bool)
    previous: ComplexArray | None = None
    used = n
    while True:
        beta = 2.0 * np.pi * np.arange(n) / n
        values = np.asarray(sample(beta), dtype=np.float64).reshape(size, n)
        spectrum = np.fft.rfft(values, axis=-1) / n
        # the floor is set by rounding in the samples themselves: a sharp peak (lambda
        # near 1) makes its rms much larger than the coefficients
        scale = np.maximum(
            np.max(np.abs(spectrum), axis=-1, initial=0.0),
            np.sqrt(np.mean(values**2, axis=-1)),
        )
        floor = 8.0 * _EPS * np.maximum(scale, np.finfo(float).tiny)
        tail = np.max(np.abs(spectrum[:, n // 4 :]), axis=-1, initial=0.0)
        wanted = spectrum[:, orders_arr]
        converged = tail <= floor
        if previous is not None:
            # very near the geometric limit the tail sinks into the rounding of the samples
            # before it falls below the floor: accept once the wanted orders stop changing
            change = np.max(np.abs(wanted - previous), axis=-1, initial=0.0)
            converged |= change <= np.maximum(8.0 * floor, 2.0 * noise)
        take = pending & converged
        wanted_out[take] = wanted[take]
        scale_out[take] = scale[take]
        pending &= ~converged
        used = n
        if not pending.any() or n >= max_samples:
            break
        previous = wanted
        n *= 2
    if pending.any():
        raise AnalysisError(
            f"the Fourier series did not converge with {n} samples per revolution; the "
            "geometry is too close to its limit (conrod_length = crank_radius + |offset|)"
        )
    coefficients = (2.0 * wanted_out).reshape(*batch_shape, orders_arr.size)
    # components below the rounding floor of the samples cannot be told from zero (an
    # unoffset slider's odd orders and sine terms, for example): report them as 0
    floor_out = (16.0 * _EPS * scale_out).reshape(*batch_shape, 1)
    real = np.where(np.abs(coefficients.real) <= floor_out, 0.0, coefficients.real)
    imag = np.where(np.abs(coefficients.imag) <= floor_out, 0.0, coefficients.imag)
    return real + 1j * imag, used


def rounding_floor(ratio: ArrayLike, offset_ratio: ArrayLike) -> FloatArray:
    r"""Estimated rounding error of the exact coefficients, :math:`10^{-14}(1-x)^{-3/2}`
    with :math:`x = \lambda(1+|e|/r)` (see :mod:`balance.core.accuracy`).

    Parameters
    ----------
    ratio, offset_ratio : array_like
        :math:`\lambda = r/l` and :math:`\varepsilon = e/r` [1], broadcasting.

    Returns
    -------
    ndarray
        The estimate [1], relative to the coefficients' scale.
    """
    x = np.asarray(ratio, dtype=np.float64) * (1 + np.abs(np.asarray(offset_ratio)))
    return np.asarray(1e-14 * (1.0 - x) ** -1.5, dtype=np.float64)


def unique_pairs(
    ratio: FloatArray, offset_ratio: FloatArray
) -> tuple[FloatArray, NDArray[np.intp]]:
    r"""The distinct (ratio, offset ratio) pairs and, for each entry, the index of its pair.

    Each pair's coefficients depend on that pair alone (:func:`fourier_coefficients`
    decides per function), so computing them once per distinct pair changes no bit.

    Parameters
    ----------
    ratio : ndarray
        :math:`\lambda = r/l` per entry [1] (any shape).
    offset_ratio : ndarray
        :math:`\varepsilon = e/r` per entry [1], shaped as ``ratio``.

    Returns
    -------
    unique : ndarray
        The distinct pairs, shape (pairs, 2): :math:`\lambda` then :math:`\varepsilon`.
    inverse : ndarray of int
        For each entry (``ratio`` flattened), the row of its pair in ``unique``.
    """
    lam = np.asarray(ratio, dtype=np.float64).ravel()
    eps = np.asarray(offset_ratio, dtype=np.float64).ravel()
    if lam.size and np.all(lam == lam[0]) and np.all(eps == eps[0]):  # one geometry
        return np.array([[lam[0], eps[0]]]), np.zeros(lam.size, dtype=np.intp)
    unique, inverse = np.unique(np.stack([lam, eps], axis=-1), axis=0, return_inverse=True)
    return unique, inverse.ravel()


def _exact(ratio: FloatArray, offset_ratio: FloatArray, orders: NDArray[np.intp]) -> ComplexArray:
    unique, inverse = unique_pairs(ratio, offset_ratio)
    lam_u = unique[:, :1]
    eps_u = unique[:, 1:]
    coeffs, _ = fourier_coefficients(
        lambda b: normalised_acceleration(b, lam_u, eps_u),
        orders,
        (unique.shape[0],),
        noise_floor=rounding_floor(unique[:, 0], unique[:, 1]),
    )
    return coeffs[inverse.ravel()].reshape(*ratio.shape, orders.size)


def series_coefficients_centred(ratio: ArrayLike, terms: int, order: int) -> FloatArray:
    r"""Closed-form series coefficient :math:`A_k` of :math:`\cos k\beta` for zero offset.

    :math:`A_1 = 1`, odd orders above 1 vanish, and for :math:`k = 2j`

    .. math::

        A_{2j} = \sum_{n=j}^{N} \frac{8 j^2 (-1)^{j+n}}{4^n}\binom{2n}{n-j}
                 \binom{1/2}{n}\lambda^{2n-1}

    from the binomial expansion of :math:`\sqrt{1-\lambda^2\sin^2\beta}`, giving
    :math:`A_2 = \lambda + \lambda^3/4 + 15\lambda^5/128 + \dots`,
    :math:`A_4 = -\lambda^3/4 - 3\lambda^5/16 - \dots`, :math:`A_6 = 9\lambda^5/128 + \dots`.

    Parameters
    ----------
    ratio : array_like
        :math:`\lambda = r/l` [1].
    terms : int
        Binomial terms :math:`N` kept.
    order : int
        The order :math:`k`, 1 or more.

    Returns
    -------
    ndarray
        :math:`A_k` [1], the shape of ``ratio``.

    References
    ----------
    Taylor, *The Internal Combustion Engine in Theory and Practice*, vol. 2, MIT Press 1985,
    ch. 8 (the piston acceleration as a series of even harmonics).  The coefficients above
    follow from the binomial series; the test suite checks them against their closed forms
    and the truncated series against the exact motion.
    """
    lam = np.asarray(ratio, dtype=np.float64)
    if order == 1:
        return np.ones_like(lam)
    if order % 2:
        return np.zeros_like(lam)
    j = order // 2
    total = np.zeros_like(lam)
    for n in range(j, terms + 1):
        binom_half = _binom_half(n)
        total = total + (
            8
            * j
            * j
            * (-1) ** (j + n)
            * comb(2 * n, n - j)
            / 4**n
            * binom_half
            * lam ** (2 * n - 1)
        )
    return total


def _binom_half(n: int) -> float:
    value = 1.0
    for i in range(n):
        value *= (0.5 - i) / (i + 1)
    return value


def _series(
    ratio: FloatArray, offset_ratio: FloatArray, orders: NDArray[np.intp], terms: int
) -> ComplexArray:
    """Coefficients of the truncated binomial series (with offset), sampled exactly."""
    if terms < 1:
        raise AnalysisError("the series model needs at least one term")
    lam = ratio[..., None]
    eps = offset_ratio[..., None]
    k_max = int(orders.max())
    n = 8
    while n <= 2 * max(2 * terms, k_max) + 2:
        n *= 2
    beta = 2.0 * np.pi * np.arange(n) / n
    sin_b, cos_b = np.sin(beta), np.cos(beta)
    u = sin_b - eps
    total = np.broadcast_to(cos_b, np.broadcast_shapes(u.shape, lam.shape)).copy()
    for m in range(1, terms + 1):
        c_m = _binom_half(m) * (-1) ** m
        d2 = 2 * m * (2 * m - 1) * u ** (2 * m - 2) * cos_b**2 - 2 * m * u ** (2 * m - 1) * sin_b
        total = total - c_m * lam ** (2 * m - 1) * d2
    spectrum = np.fft.rfft(total, axis=-1) / n
    return 2.0 * spectrum[..., orders]


def acceleration_coefficients(
    ratio: ArrayLike,
    offset_ratio: ArrayLike,
    orders: Sequence[int] | NDArray[np.integer],
    model: str = "exact",
    terms: int = 3,
) -> ComplexArray:
    r"""Fourier coefficients of the normalised reciprocating inertia :math:`-s''/r`.

    Parameters
    ----------
    ratio : array_like
        :math:`\lambda = r/l` per cylinder [1].
    offset_ratio : array_like
        :math:`\varepsilon = e/r` per cylinder [1].
    orders : sequence of int
        Orders :math:`k \ge 1`.
    model : {'exact', 'series', 'textbook'}
        How the coefficients are obtained (see the module notes).
    terms : int
        Number of binomial terms of the ``series`` model (highest power
        :math:`\lambda^{2\,\mathrm{terms}-1}`).

    Returns
    -------
    ndarray of complex
        :math:`G_k = a_k - i b_k` where :math:`-s''/r = \sum_k a_k\cos k\beta +
        b_k\sin k\beta`; shape ``broadcast(ratio, offset_ratio).shape + (len(orders),)``.
        The force phasors use :math:`c_k = G_k/2` (forward) and its conjugate (backward).

    Notes
    -----
    For zero offset :math:`a_1 = 1`, :math:`a_2 = A_2 = \lambda + \lambda^3/4 + \dots` and
    all :math:`b_k = 0`; an offset adds odd orders above 1 and sine terms.
    """
    lam, eps = np.broadcast_arrays(
        np.asarray(ratio, dtype=np.float64), np.asarray(offset_ratio, dtype=np.float64)
    )
    orders_arr = np.asarray(orders, dtype=np.intp).ravel()
    if orders_arr.size and orders_arr.min() < 1:
        raise AnalysisError("orders start at 1")
    _check_geometry(lam, eps)
    if model == "exact":
        return _shared(_key("exact", lam, eps, orders_arr), lambda: _exact(lam, eps, orders_arr))
    if model == "series":
        return _shared(
            _key("series", lam, eps, orders_arr, extra=(terms,)),
            lambda: _series(lam, eps, orders_arr, terms),
        )
    if model == "textbook":
        out = np.zeros((*lam.shape, orders_arr.size), dtype=np.complex128)
        out[..., orders_arr == 1] = 1.0
        out[..., orders_arr == 2] = lam[..., None]
        return out
    raise AnalysisError(f"unknown model {model!r}; valid models: {', '.join(MODELS)}")


def _check_geometry(ratio: FloatArray, offset_ratio: FloatArray) -> None:
    """Refuse a crank slider at or past its limit l = r + |e| (or with lambda <= 0)."""
    reach = ratio * (1.0 + np.abs(offset_ratio))
    if not np.all(np.isfinite(reach)) or np.any(ratio <= 0) or np.any(reach >= 1.0):
        worst = float(np.nanmax(reach)) if np.any(np.isfinite(reach)) else float("nan")
        raise AnalysisError(
            f"the crank slider cannot move: (r + |e|)/l = {worst:.6g}; it must be below 1 "
            "(conrod_length > crank_radius + |offset|) and above 0"
        )


def roll_coefficients(
    ratio: ArrayLike, offset_ratio: ArrayLike, orders: Sequence[int] | NDArray[np.integer]
) -> tuple[ComplexArray, ComplexArray]:
    r"""Fourier coefficients of the two normalised roll-torque functions of one cylinder.

    Parameters
    ----------
    ratio : array_like
        :math:`\lambda = r/l` per cylinder [1].
    offset_ratio : array_like
        :math:`\varepsilon = e/r` per cylinder [1].
    orders : sequence of int
        The orders.

    Returns
    -------
    reciprocating, conrod : ndarray of complex
        :math:`G_k = a_k - i b_k` of :math:`g_{rec}(\beta) = (s''/r)(s'/r + \varepsilon)` and
        :math:`g_{rod}(\beta) = \gamma''(1+\gamma')`; the roll torque the block receives is
        :math:`\omega^2[m_{rec} r^2 g_{rec} + \Delta I\, g_{rod}]`.  Shape: that of
        ``ratio`` and one axis of orders.

    Notes
    -----
    From the balance of angular momentum of the moving parts about the crank axis (see the
    theory page): the block receives minus the inertia torque on the crank, plus the moment
    of the shaking force whose line is displaced by the offset, plus the spin of the conrod
    beyond its two-mass model.
    """
    lam, eps = np.broadcast_arrays(
        np.asarray(ratio, dtype=np.float64), np.asarray(offset_ratio, dtype=np.float64)
    )
    orders_arr = np.asarray(orders, dtype=np.intp).ravel()
    _check_geometry(lam, eps)
    return _shared(
        _key("roll", lam, eps, orders_arr), lambda: _roll_coefficients(lam, eps, orders_arr)
    )


def _roll_coefficients(
    lam: FloatArray, eps: FloatArray, orders_arr: NDArray[np.intp]
) -> tuple[ComplexArray, ComplexArray]:
    """:func:`roll_coefficients` of checked, broadcast inputs."""
    unique, inverse = unique_pairs(lam, eps)
    lam_u = unique[:, :1]
    eps_u = unique[:, 1:]

    def sample(beta: FloatArray) -> FloatArray:
        _, ds, d2s = normalised_slider(beta, lam_u, eps_u)
        dg, d2g = conrod_angle_derivatives(beta, lam_u, eps_u)
        return np.stack([d2s * (ds + eps_u), d2g * (1.0 + dg)])

    coeffs, _ = fourier_coefficients(
        sample,
        orders_arr,
        (2, unique.shape[0]),
        # the roll functions carry one more factor 1/D than the acceleration
        noise_floor=rounding_floor(unique[:, 0], unique[:, 1])
        / np.sqrt(1.0 - unique[:, 0] * (1 + np.abs(unique[:, 1]))),
    )
    rec = coeffs[0][inverse.ravel()].reshape(*lam.shape, orders_arr.size)
    rod = coeffs[1][inverse.ravel()].reshape(*lam.shape, orders_arr.size)
    return rec, rod
