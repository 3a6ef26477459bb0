r"""Phasor sums over cylinders: free forces, free moments and roll, order by order.

A quantity of order k that depends on the crank angle :math:`\theta` is written as

.. math::

    Q_k(\theta) = P_k^{+} e^{+ik\theta} + P_k^{-} e^{-ik\theta}

in the complex transverse plane (a vector :math:`(x, y)` is :math:`y + ix`).  Cylinder
:math:`i` with throw :math:`\varphi_i`, bank :math:`\psi_i` and axial position :math:`z_i`
is at :math:`\beta_i = \theta + \varphi_i - \psi_i` from its own TDC, and its
reciprocating inertia acts along its bore, :math:`e^{i\psi_i}`.

All functions take per-cylinder arrays on the last axis (leading axes broadcast, so a
sweep is one call) and return complex arrays with the orders on the last axis.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "CANCELLATION_FACTOR",
    "QUANTITIES",
    "Phasors",
    "Quantity",
    "cancel_to_zero",
    "phase_deg",
    "reciprocating_force_and_moment",
    "reciprocating_phasors",
    "roll_phasors",
    "rotating_phasor",
    "rounding_threshold",
    "safe_ratio",
    "sum_over_cylinders",
    "weighted_phasor_sum",
]

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]

#: A sum is exactly zero when its magnitude is below
#: ``CANCELLATION_FACTOR * n_terms * eps * sum(|terms|)``.
CANCELLATION_FACTOR = 64.0
_EPS = float(np.finfo(np.float64).eps)
_TINY = float(np.finfo(np.float64).tiny)  # the smallest normal number
#: Largest array (elements) summed over its cylinders in one call (see
#: :func:`sum_over_cylinders`); larger ones are summed one cylinder at a time.
_SMALL = 1 << 16


def rounding_threshold(scale: ArrayLike, n_terms: int) -> FloatArray:
    r"""The largest magnitude that a sum cannot tell from zero.

    Parameters
    ----------
    scale : array_like
        :math:`S = \sum_i |t_i|`, the sum of the magnitudes of the terms of each sum (or a
        bound on it), in the sum's units.
    n_terms : int
        Number of terms in each sum.

    Returns
    -------
    ndarray of float
        :math:`64\, n\, \epsilon (S + t_{min})`, in the units of ``scale``: a sum whose
        magnitude is at most this is exactly zero (:func:`cancel_to_zero`; the views and
        studies use the same rule for the magnitudes they form).

    Notes
    -----
    Rounding in a sum of n terms of size up to :math:`S` is bounded by about
    :math:`n\epsilon S`; the factor 64 covers the rounding of the terms themselves (sines,
    cosines of multiples of the throw angles).  Anything below this cannot be told from
    zero in double precision, so reporting it as, say, 3e-13 N would be noise.

    Below the smallest normal number :math:`t_{min}` (2.2e-308) rounding is absolute, not
    relative: the subnormal numbers are evenly spaced :math:`\epsilon\, t_{min}` (4.9e-324)
    apart, so a result there is off by up to half that whatever its size (Goldberg, "What
    every computer scientist should know about floating-point arithmetic", *ACM Computing
    Surveys* 23(1), 1991, §2.2.4, "Denormalized numbers").  Hence
    :math:`\epsilon (S + t_{min})`: a moment about a ``reference_z`` of 2e-311 m has terms
    of 1e-313 N m (per unit of ω²), whose sum keeps one subnormal unit of rounding that
    :math:`\epsilon S` alone (1e-326, below that unit) would call a couple.
    """
    return np.asarray(
        CANCELLATION_FACTOR * max(n_terms, 1) * _EPS * (np.asarray(scale) + _TINY),
        dtype=np.float64,
    )


def cancel_to_zero(total: ComplexArray, term_scale: ArrayLike, n_terms: int) -> ComplexArray:
    r"""Set sums that cancel by symmetry to exactly zero.

    Parameters
    ----------
    total : ndarray of complex
        The phasor sums.
    term_scale : array_like
        :math:`\sum_i |t_i|`, the sum of the magnitudes of the terms of each sum.
    n_terms : int
        Number of terms in each sum.

    Returns
    -------
    ndarray of complex
        ``total`` with every entry whose magnitude is at most
        :func:`rounding_threshold` of ``term_scale`` and ``n_terms`` replaced by 0.
    """
    threshold = rounding_threshold(term_scale, n_terms)
    out = np.array(total, dtype=np.complex128, copy=True)
    out[np.abs(out) <= threshold] = 0.0
    return out


def sum_over_cylinders(terms: NDArray[Any]) -> NDArray[Any]:
    r"""Sum over axis -2 in cylinder order, one cylinder at a time.

    ``numpy.sum`` picks its summation order from the memory layout (pairwise blocks of
    eight along a contiguous axis, plain accumulation otherwise), so the same terms could
    round differently alone and inside a sweep's grid.  Here the order is fixed:
    :math:`((t_1 + t_2) + t_3) + \dots`, whatever the leading axes.

    Parameters
    ----------
    terms : ndarray
        Terms of shape ``(..., n, K)``: cylinders on axis -2, any unit.

    Returns
    -------
    ndarray
        The sums, shape ``(..., K)``, in the unit of ``terms``.
    """
    n = terms.shape[-2]
    if n == 0:
        return np.zeros(terms.shape[:-2] + terms.shape[-1:], dtype=terms.dtype)
    if terms.size <= _SMALL:  # one call; a running sum has this order too
        return np.add.accumulate(terms, axis=-2)[..., -1, :]
    total = terms[..., 0, :].copy()
    for i in range(1, n):
        total += terms[..., i, :]
    return total


def _weighted_sum(terms: ComplexArray, lever: FloatArray | None) -> ComplexArray:
    """Sum over the cylinder axis (-2) with zero-cleaning."""
    if lever is not None:
        terms = terms * lever[..., :, None]
    n = terms.shape[-2]
    total = sum_over_cylinders(terms)
    return cancel_to_zero(total, sum_over_cylinders(np.abs(terms)), n)


def reciprocating_phasors(
    amplitude: ArrayLike,
    coefficients: ArrayLike,
    throw: ArrayLike,
    bank: ArrayLike,
    orders: ArrayLike,
    lever: ArrayLike | None = None,
) -> tuple[ComplexArray, ComplexArray]:
    r"""Forward and backward phasors of the reciprocating inertia force (or moment).

    Parameters
    ----------
    amplitude : array_like
        :math:`m_{rec}\, r\, \omega^2` per cylinder [N], shape ``(..., n)``.
    coefficients : array_like of complex
        :math:`G_k` of :math:`-s''/r` per cylinder and order, shape ``(..., n, K)``
        (:func:`balance.core.kinematics.acceleration_coefficients`).
    throw, bank : array_like
        Throw and bank angle per cylinder [rad], shape ``(..., n)``.
    orders : array_like of int
        The K orders.
    lever : array_like, optional
        :math:`z_i - z_{ref}` per cylinder [m]; given, the result is the moment [N m].

    Returns
    -------
    forward, backward : ndarray of complex
        :math:`P_k^{+}` and :math:`P_k^{-}`, shape ``(..., K)`` [N or N m].

    Notes
    -----
    With :math:`c_k = G_k/2`,

    .. math::

        P_k^{+} = \sum_i m_i r_i \omega^2 c_{k,i}\, e^{+ik(\varphi_i-\psi_i)} e^{i\psi_i},
        \qquad
        P_k^{-} = \sum_i m_i r_i \omega^2 \bar c_{k,i}\, e^{-ik(\varphi_i-\psi_i)}
        e^{i\psi_i}

    (times :math:`z_i - z_{ref}` for moments).  A force :math:`F\cos k\beta` along a fixed
    axis is two phasors of half its amplitude turning in opposite senses.

    References
    ----------
    Taylor, *The Internal Combustion Engine in Theory and Practice*, vol. 2, 2nd ed., MIT
    Press 1985, ch. 8 (engine balance).  The split into two counter-rotating halves is
    Euler's formula.
    """
    forward, backward, m_fwd, m_bwd = reciprocating_force_and_moment(
        amplitude, coefficients, throw, bank, orders, lever, force=lever is None
    )
    if lever is not None:
        forward, backward = m_fwd, m_bwd
    assert forward is not None and backward is not None
    return forward, backward


def _dot_over_cylinders(weight: FloatArray, values: FloatArray) -> FloatArray:
    """:math:`\\sum_i w_i v_i` over axis -2, in cylinder order (see :func:`sum_over_cylinders`).

    Small arrays (one engine) form every product and take the last entry of their running
    sum (``numpy.add.accumulate``), one call whatever the number of cylinders; large ones
    (a sweep's chunk) form the products one cylinder at a time, so that no array of every
    term is built.  Both add :math:`((w_1 v_1 + w_2 v_2) + w_3 v_3) + \\dots` in this
    order, so they give the same bits.
    """
    shape = np.broadcast_shapes(weight.shape, values.shape)
    if math.prod(shape) <= _SMALL:
        return np.add.accumulate(weight * values, axis=-2)[..., -1, :]
    n = shape[-2]

    def at(a: FloatArray, i: int) -> FloatArray:
        return a[..., i if a.shape[-2] > 1 else 0, :]

    total = at(weight, 0) * at(values, 0)
    if n > 1:
        product = np.empty_like(total)
        for i in range(1, n):
            np.multiply(at(weight, i), at(values, i), out=product)
            total += product
    return total


def _complex_dot(
    terms: list[tuple[FloatArray, FloatArray, FloatArray]], scale: FloatArray, n: int
) -> ComplexArray:
    """:math:`\\sum_j \\sum_i w_{j,i} (x_{j,i} + i y_{j,i})` for ``terms`` of (w, x, y),
    cleaned of rounding noise against ``scale`` (:func:`cancel_to_zero`)."""
    real: FloatArray | None = None
    imag: FloatArray | None = None
    for weight, x, y in terms:
        sx = _dot_over_cylinders(weight, x)
        sy = _dot_over_cylinders(weight, y)
        real = sx if real is None else real + sx
        imag = sy if imag is None else imag + sy
    assert real is not None and imag is not None
    total = np.empty(np.broadcast_shapes(real.shape, imag.shape), dtype=np.complex128)
    total.real = real
    total.imag = imag
    return cancel_to_zero(total, scale, n)


def weighted_phasor_sum(terms: Sequence[tuple[ArrayLike, ArrayLike]]) -> ComplexArray:
    r"""A cleaned sum of weighted complex terms over cylinders: :math:`\sum_j\sum_i w_{j,i}
    u_{j,i,k}`.

    Parameters
    ----------
    terms : list of (weight, unit)
        ``weight`` per cylinder, shape ``(..., n_j)`` (leading axes broadcast, a sweep's
        grid); ``unit`` complex per cylinder and order, shape ``(n_j, K)`` or
        ``(..., n_j, K)``.  Each term may have its own cylinders (``n_j``).

    Returns
    -------
    ndarray of complex
        Shape ``(..., K)``, summed in cylinder order (:func:`sum_over_cylinders`) and
        cleaned against :math:`\sum|w||u|` over every term (:func:`cancel_to_zero`).
    """
    parts = []
    scale: FloatArray | None = None
    n = 0
    for weight, unit in terms:
        w = np.asarray(weight, dtype=np.float64)[..., None]
        u = np.asarray(unit, dtype=np.complex128)
        if u.shape[-2] == 0:
            continue
        parts.append((w, u.real, u.imag))
        size = _dot_over_cylinders(np.abs(w), np.abs(u))
        scale = size if scale is None else scale + size
        n += u.shape[-2]
    assert parts and scale is not None, "at least one term with cylinders"
    return _complex_dot(parts, scale, n)


def reciprocating_force_and_moment(
    amplitude: ArrayLike,
    coefficients: ArrayLike,
    throw: ArrayLike,
    bank: ArrayLike,
    orders: ArrayLike,
    lever: ArrayLike | None = None,
    *,
    force: bool = True,
) -> tuple[ComplexArray | None, ComplexArray | None, ComplexArray | None, ComplexArray | None]:
    r"""Forward and backward phasors of the reciprocating inertia force and moment at once.

    Parameters
    ----------
    amplitude, coefficients, throw, bank, orders, lever
        As :func:`reciprocating_phasors`; the moment is formed when ``lever`` [m] is given.
    force : bool
        Form the force (otherwise its phasors are None).

    Returns
    -------
    force_forward, force_backward, moment_forward, moment_backward : ndarray of complex or None
        :math:`P_k^{\pm}` [N] and :math:`M_k^{\pm}` [N m], shape ``(..., K)``; None for what is
        not formed.

    Notes
    -----
    The factor that does not depend on the amplitude, :math:`u_{k,i} = c_{k,i}
    e^{ik(\varphi_i-\psi_i)} e^{i\psi_i}` (and its backward twin), is formed once over
    the grid of coefficients and angles; the sums :math:`\sum_i a_i\,\mathrm{Re}\,u`
    and :math:`\sum_i a_i\,\mathrm{Im}\,u` are then real dot products over the
    cylinders.  Sums below the rounding of their terms are set to zero
    (:func:`cancel_to_zero`, with :math:`|t_i| = |a_i|\,|c_{k,i}|`).
    """
    amp = np.asarray(amplitude, dtype=np.float64)[..., None]
    c = 0.5 * np.asarray(coefficients, dtype=np.complex128)
    if c.ndim < 2:  # the same coefficients for every cylinder
        c = c[None, :]
    phi = np.asarray(throw, dtype=np.float64)[..., None]
    psi = np.asarray(bank, dtype=np.float64)[..., None]
    k = np.asarray(orders, dtype=np.float64)
    along_bore = np.exp(1j * psi)
    turn = c * np.exp(1j * k * (phi - psi))
    forward_unit = turn * along_bore
    backward_unit = np.conj(turn) * along_bore
    parts = [
        (forward_unit.real, forward_unit.imag),
        (backward_unit.real, backward_unit.imag),
    ]
    size = np.abs(c)
    n = max(amp.shape[-2], forward_unit.shape[-2])

    def sums(weight: FloatArray) -> list[ComplexArray]:
        scale = _dot_over_cylinders(np.abs(weight), size)
        return [_complex_dot([(weight, re, im)], scale, n) for re, im in parts]

    f_fwd = f_bwd = m_fwd = m_bwd = None
    if force:
        f_fwd, f_bwd = sums(amp)
    if lever is not None:
        m_fwd, m_bwd = sums(amp * np.asarray(lever, dtype=np.float64)[..., None])
    return f_fwd, f_bwd, m_fwd, m_bwd


def rotating_phasor(
    amplitude: ArrayLike, throw: ArrayLike, lever: ArrayLike | None = None
) -> ComplexArray:
    r"""Forward first-order phasor of the rotating (centrifugal) force or moment.

    :math:`P^{+} = \sum_i m_{rot,i} r_i \omega^2 e^{i\varphi_i}` (times
    :math:`z_i - z_{ref}` for the moment).  There is no backward part.

    Parameters
    ----------
    amplitude : array_like
        :math:`m_{rot} r\omega^2` per cylinder on the last axis [N].
    throw : array_like
        Throw angle per cylinder [rad].
    lever : array_like, optional
        :math:`z_i - z_{ref}` per cylinder [m]; given, the result is the moment.

    Returns
    -------
    ndarray of complex
        :math:`P^{+}` [N, or N m with ``lever``], the leading axes of ``amplitude``.
    """
    amp = np.asarray(amplitude, dtype=np.float64)
    phi = np.asarray(throw, dtype=np.float64)
    terms = (amp * np.exp(1j * phi))[..., None]
    lev = None if lever is None else np.asarray(lever, dtype=np.float64)
    return _weighted_sum(terms, lev)[..., 0]


def roll_phasors(
    reciprocating_amplitude: ArrayLike,
    conrod_amplitude: ArrayLike,
    reciprocating_coefficients: ArrayLike,
    conrod_coefficients: ArrayLike,
    throw: ArrayLike,
    bank: ArrayLike,
    orders: ArrayLike,
) -> ComplexArray:
    r"""Roll torque phasors of the engine, one per order.

    Parameters
    ----------
    reciprocating_amplitude : array_like
        :math:`m_{rec} r^2 \omega^2` per cylinder [N m].
    conrod_amplitude : array_like
        :math:`\Delta I\, \omega^2` per cylinder [N m].
    reciprocating_coefficients, conrod_coefficients : array_like of complex
        :math:`G_k` of :math:`g_{rec}` and :math:`g_{rod}`
        (:func:`balance.core.kinematics.roll_coefficients`), shape ``(..., n, K)``.
    throw, bank : array_like
        [rad] per cylinder.
    orders : array_like of int

    Returns
    -------
    ndarray of complex
        :math:`R_k` such that the roll torque the block receives is
        :math:`\sum_k \mathrm{Re}(R_k e^{ik\theta}) = \sum_k |R_k|\cos(k\theta + \arg R_k)`
        [N m], positive in the direction of rotation.
    """
    a_rec = np.asarray(reciprocating_amplitude, dtype=np.float64)[..., None]
    a_rod = np.asarray(conrod_amplitude, dtype=np.float64)[..., None]
    phi = np.asarray(throw, dtype=np.float64)[..., None]
    psi = np.asarray(bank, dtype=np.float64)[..., None]
    k = np.asarray(orders, dtype=np.float64)
    turn = np.exp(1j * k * (phi - psi))
    g_rec = np.asarray(reciprocating_coefficients, dtype=np.complex128)
    g_rod = np.asarray(conrod_coefficients, dtype=np.complex128)
    if g_rec.ndim < 2:
        g_rec, g_rod = g_rec[None, :], g_rod[None, :]
    u_rec = g_rec * turn
    u_rod = g_rod * turn
    n = max(a_rec.shape[-2], a_rod.shape[-2], u_rec.shape[-2])
    scale = _dot_over_cylinders(np.abs(a_rec), np.abs(g_rec)) + _dot_over_cylinders(
        np.abs(a_rod), np.abs(g_rod)
    )
    return _complex_dot(
        [(a_rec, u_rec.real, u_rec.imag), (a_rod, u_rod.real, u_rod.imag)], scale, 2 * n
    )


#: The two quantities a :class:`Phasors` bundle holds per order.
QUANTITIES = ("force", "moment")
Quantity = Literal["force", "moment"]


def phase_deg(phasor: ArrayLike) -> FloatArray:
    """Phase of complex phasors in degrees, in [0, 360), to 1e-9 deg; 0 where the
    magnitude is 0, NaN where the phasor is NaN (not computed).

    Rounded to 1e-9 deg so that rounding noise (1e-14 deg) does not show as a phase.

    Parameters
    ----------
    phasor : array_like of complex
        The phasors (docs/conventions.md, "Phasors").

    Returns
    -------
    ndarray
        The phases [deg], the shape of ``phasor``.
    """
    z = np.asarray(phasor, dtype=np.complex128)
    flat = z.reshape(-1)  # a fresh 1-d array below is set in place (a Dataset has 9 phases)
    deg = np.mod(np.degrees(np.arctan2(flat.imag, flat.real)), 360.0).round(9)
    deg[deg >= 360.0] = 0.0
    deg[np.abs(flat) == 0.0] = 0.0
    deg[np.isnan(flat)] = np.nan
    deg += 0.0  # turns -0.0 into 0.0
    return deg.reshape(z.shape)


def safe_ratio(values: Any, scale: float) -> Any:
    """``values / scale``: NaN where the scale is zero or not finite, and inf (without a
    warning) where the ratio lies beyond the float range (a normalising force of a few
    1e-300 N, as a layout with a 1e-308 kg piston has).

    Parameters
    ----------
    values : array_like
        What is normalised (a force [N], a moment [N m] ...).
    scale : float
        The reference in the unit of ``values`` (:func:`balance.core.analysis.reference_force`,
        times the pitch for moments).

    Returns
    -------
    ndarray
        The ratios [1], the shape of ``values``.
    """
    if not math.isfinite(scale) or scale == 0.0:
        return np.full(np.shape(values), np.nan)
    if abs(scale) >= 1.0:  # no finite ratio can overflow: spare the error state's cost
        return np.asarray(values) / scale
    with np.errstate(over="ignore"):
        return np.asarray(values) / scale


def _pair(forward: NDArray[Any], backward: NDArray[Any]) -> NDArray[Any]:
    """``np.stack([forward, backward], axis=-1)`` of two arrays of one shape, at a third of
    its cost for the small arrays of an analysis."""
    out = np.empty((*forward.shape, 2), dtype=np.result_type(forward, backward))
    out[..., 0] = forward
    out[..., 1] = backward
    return out


@dataclass(frozen=True, eq=False)
class Phasors:
    r"""Forward and backward phasors per order of a force and its moment, and the roll.

    The one bundle of phasors in balance: the free forces of an analysis, the masses a
    proposal adds, the residual, a sweep's grid and a tolerance study's samples are each
    one :class:`Phasors`.  Leading axes (a grid of engines, or cylinders) broadcast;
    the orders are on the last axis.

    Attributes
    ----------
    orders : ndarray of int
        The K orders, ascending.
    force_forward, force_backward : ndarray of complex
        :math:`P_k^{+}` and :math:`P_k^{-}` of the force, shape ``(..., K)`` [N].
    moment_forward, moment_backward : ndarray of complex or None
        The same of the moment about ``reference_z`` [N m]; None when not computed.
    rotating_force, rotating_moment : ndarray of complex or complex
        The order-1 forward phasor of the rotating (centrifugal) masses, shape ``(...)``,
        kept apart from the reciprocating ``force_forward`` (0 where the bundle has no
        rotating masses of its own; ``rotating_moment`` None without moments).
    roll : ndarray of complex or None
        Roll phasors :math:`R_k` per order, shape ``(..., K)`` [N m]; None when not
        computed.
    rotating_force_backward, rotating_moment_backward : ndarray of complex or None
        The order-1 backward phasor of rotating masses that turn against the crank (on a
        counter-rotating crankshaft, docs/several-crankshafts.md); None: there are none.

    Notes
    -----
    Order k of a quantity is :math:`P_k^{+} e^{ik\theta} + P_k^{-} e^{-ik\theta}`
    (docs/conventions.md, "Phasors"); its peak over a revolution is
    :math:`|P_k^{+}| + |P_k^{-}|` (:meth:`peak`), and the whole free force adds the
    rotating masses to order 1 forward (:meth:`free`).
    """

    orders: NDArray[np.intp]
    force_forward: ComplexArray
    force_backward: ComplexArray
    moment_forward: ComplexArray | None = None
    moment_backward: ComplexArray | None = None
    rotating_force: ComplexArray | complex = 0j
    rotating_moment: ComplexArray | complex | None = None
    roll: ComplexArray | None = None
    rotating_force_backward: ComplexArray | complex | None = None
    rotating_moment_backward: ComplexArray | complex | None = None

    def replaced(self, **changes: Any) -> Phasors:
        """The bundle with some of its fields changed: ``dataclasses.replace`` at a fifth of
        its cost (an analysis forms a few bundles from others; a bundle has no
        ``__post_init__``), and without the magnitudes formed of the old values.

        Parameters
        ----------
        **changes
            New values of fields, by name (``force_forward=...``).

        Returns
        -------
        Phasors

        Raises
        ------
        TypeError
            For a name that is no field.
        """
        if not changes.keys() <= _FIELDS:
            unknown = changes.keys() - _FIELDS
            raise TypeError(f"Phasors has no field {', '.join(sorted(unknown))}")
        return _changed(self, changes)

    def has(self, quantity: Quantity) -> bool:
        """Whether the bundle holds ``quantity`` ('force' or 'moment')."""
        return self.pair(quantity)[0] is not None

    def pair(self, quantity: Quantity) -> tuple[Any, Any]:
        """The forward and backward phasors of ``quantity`` ('force' or 'moment'), each
        None when not computed."""
        if quantity == "force":
            return self.force_forward, self.force_backward
        if quantity == "moment":
            return self.moment_forward, self.moment_backward
        raise ValueError(f"quantity must be one of {', '.join(QUANTITIES)}, got {quantity!r}")

    def rotating(self, quantity: Quantity) -> Any:
        """The rotating masses' order-1 forward phasor of ``quantity`` (None: not computed)."""
        self.pair(quantity)  # checks the name
        return self.rotating_force if quantity == "force" else self.rotating_moment

    def free(self) -> Phasors:
        r"""The whole free force and moment: the rotating masses added to order 1 forward
        (and those turning backward, on a counter-rotating crankshaft, to order 1 backward).

        :math:`P_1^{+} + P_{rot}`; the result's rotating phasors are 0 (they are inside).
        This is the one place where "free = reciprocating + rotating at order 1" is
        written.
        """
        memo = self._memo()
        free: Phasors | None = memo.get("free")
        if free is not None:  # an analysis' mounts and proposal both read it
            return free
        first = (self.orders == 1).astype(np.float64)
        values = self.__dict__
        changes: dict[str, Any] = {}
        for name, rotating_name in _FREE_PAIRS:
            rotating = values[rotating_name]
            if rotating is None:
                continue  # nothing to add, nothing to zero
            if type(rotating) is np.ndarray:  # one per engine of a grid: zeros of its shape
                changes[rotating_name] = np.zeros(rotating.shape, dtype=rotating.dtype)
                rotating = rotating[..., None]  # along the orders
            else:  # a scalar: a zero of its type
                changes[rotating_name] = type(rotating)(0)
            forward = values[name]
            if forward is not None:
                changes[name] = forward + first * rotating
        free = memo["free"] = _changed(self, changes)
        return free

    def magnitude(self, quantity: Quantity) -> FloatArray:
        """:math:`|P^{+}|` and :math:`|P^{-}|` of ``quantity``, shape ``(..., K, 2)``."""
        return _pair(*self._magnitudes(quantity))

    def peak(self, quantity: Quantity) -> FloatArray:
        r"""Peak of ``quantity`` over a revolution, per order: :math:`|P^{+}| + |P^{-}|`
        [N or N m].  The one place where a peak is formed."""
        forward, backward = self._magnitudes(quantity)
        return np.asarray(forward + backward, dtype=np.float64)

    def _magnitudes(self, quantity: Quantity) -> tuple[FloatArray, FloatArray]:
        """:math:`|P^{+}|` and :math:`|P^{-}|`, formed once per bundle (a Dataset or a
        sweep's chunk reads the magnitudes and the peaks, each also normalised)."""
        cache = self._memo()
        if quantity not in cache:
            forward, backward = self._computed(quantity)
            cache[quantity] = (np.abs(forward), np.abs(backward))
        magnitudes: tuple[FloatArray, FloatArray] = cache[quantity]
        return magnitudes

    def _memo(self) -> dict[str, Any]:
        """The bundle's private memo (a frozen bundle's): its magnitudes per quantity
        (:meth:`_magnitudes`) and its :meth:`free` bundle, formed once each."""
        memo: dict[str, Any] | None = self.__dict__.get("_formed")
        if memo is None:
            memo = {}
            object.__setattr__(self, "_formed", memo)
        return memo

    def phase(self, quantity: Quantity) -> FloatArray:
        """Phases of :math:`P^{+}` and :math:`P^{-}` at crank angle 0 [deg], shape
        ``(..., K, 2)`` (:func:`phase_deg`)."""
        return phase_deg(_pair(*self._computed(quantity)))

    def normalised(self, values: ArrayLike, reference: float) -> Any:
        """``values`` (a magnitude or peak of this bundle) per ``reference`` (NaN without
        one, :func:`safe_ratio`)."""
        return safe_ratio(values, reference)

    def scaled(self, factor: ArrayLike) -> Phasors:
        r"""Every phasor times ``factor`` (:math:`\omega^2` for a bundle formed at unit
        speed).  ``factor`` broadcasts against the leading axes with a trailing axis of
        size one for the orders (its last entry along that axis scales the rotating
        phasors)."""
        f = np.asarray(factor, dtype=np.float64)
        f_scalar = f[..., 0] if f.ndim else f

        def times(value: Any, by: Any) -> Any:
            return None if value is None else value * by

        return self.replaced(
            force_forward=times(self.force_forward, f),
            force_backward=times(self.force_backward, f),
            moment_forward=times(self.moment_forward, f),
            moment_backward=times(self.moment_backward, f),
            rotating_force=times(self.rotating_force, f_scalar),
            rotating_moment=times(self.rotating_moment, f_scalar),
            roll=times(self.roll, f),
            rotating_force_backward=times(self.rotating_force_backward, f_scalar),
            rotating_moment_backward=times(self.rotating_moment_backward, f_scalar),
        )

    def __add__(self, other: Phasors) -> Phasors:
        """The sum of two bundles over the same orders (what is None in either is None)."""
        if self.orders is not other.orders and not np.array_equal(self.orders, other.orders):
            raise ValueError("phasors of different orders cannot be added")

        def plus(a: Any, b: Any) -> Any:
            return None if a is None or b is None else a + b

        def either(a: Any, b: Any) -> Any:  # None is zero: masses that no bundle has
            return b if a is None else a if b is None else a + b

        return _bundle(
            {
                "orders": self.orders,
                "force_forward": plus(self.force_forward, other.force_forward),
                "force_backward": plus(self.force_backward, other.force_backward),
                "moment_forward": plus(self.moment_forward, other.moment_forward),
                "moment_backward": plus(self.moment_backward, other.moment_backward),
                "rotating_force": plus(self.rotating_force, other.rotating_force),
                "rotating_moment": plus(self.rotating_moment, other.rotating_moment),
                "roll": plus(self.roll, other.roll),
                "rotating_force_backward": either(
                    self.rotating_force_backward, other.rotating_force_backward
                ),
                "rotating_moment_backward": either(
                    self.rotating_moment_backward, other.rotating_moment_backward
                ),
            }
        )

    def at(self, orders: ArrayLike) -> Phasors:
        """The bundle at some of its orders (each must be one of :attr:`orders`)."""
        pick = self.orders.searchsorted(np.asarray(orders, dtype=np.intp))

        def take(value: Any) -> Any:  # one engine's orders are indexed at a third of the cost
            return None if value is None else value[pick] if value.ndim == 1 else value[..., pick]

        return self.replaced(
            orders=self.orders[pick],
            force_forward=take(self.force_forward),
            force_backward=take(self.force_backward),
            moment_forward=take(self.moment_forward),
            moment_backward=take(self.moment_backward),
            roll=take(self.roll),
        )

    def _computed(self, quantity: Quantity) -> tuple[ComplexArray, ComplexArray]:
        forward, backward = self.pair(quantity)
        if forward is None or backward is None:
            raise ValueError(f"the {quantity} was not computed")
        return forward, backward


#: The names of the fields of a :class:`Phasors` bundle (what :meth:`Phasors.replaced` may
#: change).
_FIELDS = frozenset(f.name for f in fields(Phasors))


#: Each forward phasor and the rotating masses' phasor :meth:`Phasors.free` adds to it.
_FREE_PAIRS = (
    ("force_forward", "rotating_force"),
    ("moment_forward", "rotating_moment"),
    ("force_backward", "rotating_force_backward"),
    ("moment_backward", "rotating_moment_backward"),
)


def _changed(bundle: Phasors, changes: dict[str, Any]) -> Phasors:
    """``bundle`` with the fields in ``changes`` (names checked by the caller), without its
    memo (:meth:`Phasors._memo`, formed of the old values)."""
    new = object.__new__(type(bundle))
    values = new.__dict__
    values.update(bundle.__dict__)
    values.pop("_formed", None)
    values.update(changes)
    return new


def _bundle(values: dict[str, Any]) -> Phasors:
    """A :class:`Phasors` of every field in ``values``, without the dataclass's
    ``__init__`` (ten frozen assignments, a third of :meth:`Phasors.__add__`'s cost)."""
    new = object.__new__(Phasors)
    new.__dict__.update(values)
    return new
