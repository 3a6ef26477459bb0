r"""From phasors back to the crank-angle domain: what the plots draw, without drawing.

numpy only (no matplotlib, no xarray): the functions take the complex phasors of a
:class:`~balance.core.result.Result` as they are.  Every function here follows the conventions
(docs/conventions.md, "Frame and angles" and "Phasors"): a transverse vector :math:`(x, y)` is the
complex number :math:`y + i x`, angles are measured from +y in the direction of rotation, and order
:math:`k` of a quantity is

.. math::

    Q_k(\theta) = P_k^{+} e^{+ik\theta} + P_k^{-} e^{-ik\theta}.

The roll torque of order :math:`k` (a scalar) is :math:`\operatorname{Re}(R_k e^{ik\theta})`
with :math:`R_k` its complex phasor.  Crank angles are in degrees here, as everywhere in the
results.

Three *sources* of the force and moment can be taken from a result
(:func:`bundle_of` gives the :class:`~balance.core.phasors.Phasors` of each, whose methods form
their magnitudes and peaks; :func:`phasors_of` its complex phasors):

``reciprocating``
    The inertia of the reciprocating masses only.
``free``
    Everything the moving parts shake the block with: reciprocating plus the centrifugal
    force of the rotating masses (order 1, forward).  This is what a proposal acts on.
``residual``
    What is left with every proposed counterweight and balance-shaft mass (needs a
    proposal).

The peak of an order is :meth:`balance.core.phasors.Phasors.peak` (:func:`peak_of`), never
formed here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.phasors import Phasors
    from balance.core.result import Result

__all__ = [
    "QUANTITIES",
    "SOURCES",
    "Quantity",
    "Source",
    "bundle_of",
    "couple_components",
    "crank_angle_grid",
    "has_moments",
    "has_proposal",
    "has_roll",
    "magnitude_of",
    "peak_of",
    "phasor_signal",
    "phasors_of",
    "roll_of",
    "roll_signal",
    "roll_signal_per_order",
    "roll_span_deg",
    "signal_of",
    "signal_per_order",
    "transverse_components",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

Quantity = Literal["force", "moment"]
Source = Literal["reciprocating", "free", "residual"]

QUANTITIES: tuple[Quantity, ...] = ("force", "moment")
SOURCES: tuple[Source, ...] = ("reciprocating", "free", "residual")


def crank_angle_grid(samples: int = 361, span_deg: float = 360.0) -> FloatArray:
    """Equally spaced crank angles from 0 to ``span_deg`` inclusive [deg].

    Parameters
    ----------
    samples : int
        Number of angles (at least 2).
    span_deg : float
        Last angle [deg]: 360 for one revolution, 720 for a four-stroke cycle.

    Returns
    -------
    ndarray
        Crank angles [deg].
    """
    if samples < 2:
        raise ValueError(f"samples must be at least 2, got {samples}")
    return np.linspace(0.0, float(span_deg), int(samples))


def signal_per_order(
    forward: ArrayLike, backward: ArrayLike, orders: ArrayLike, theta_deg: ArrayLike
) -> ComplexArray:
    r"""Each order's :math:`Q_k(\theta) = P_k^{+}e^{ik\theta} + P_k^{-}e^{-ik\theta}`.

    Parameters
    ----------
    forward, backward : array_like of complex
        :math:`P_k^{+}` and :math:`P_k^{-}` per order [N or N m].
    orders : array_like
        Order :math:`k` of each phasor [1].
    theta_deg : array_like
        Crank angles [deg].

    Returns
    -------
    ndarray of complex, shape (n_orders, n_angles)
        :math:`y + ix` of each order at each crank angle [N or N m].
    """
    fwd = np.atleast_1d(np.asarray(forward, dtype=np.complex128))
    bwd = np.atleast_1d(np.asarray(backward, dtype=np.complex128))
    ks = np.atleast_1d(np.asarray(orders, dtype=np.float64))
    th = np.radians(np.atleast_1d(np.asarray(theta_deg, dtype=np.float64)))
    if not fwd.shape == bwd.shape == ks.shape:
        raise ValueError(
            "phasor_signal: forward, backward and orders must have one entry per order, got "
            f"{fwd.shape}, {bwd.shape} and {ks.shape}"
        )
    angle = ks[:, None] * th[None, :]
    signal = fwd[:, None] * np.exp(1j * angle) + bwd[:, None] * np.exp(-1j * angle)
    return np.asarray(signal, dtype=np.complex128)


def phasor_signal(
    forward: ArrayLike, backward: ArrayLike, orders: ArrayLike, theta_deg: ArrayLike
) -> ComplexArray:
    r"""Sum over orders :math:`Q(\theta) = \sum_k P_k^{+}e^{ik\theta} + P_k^{-}e^{-ik\theta}`.

    Parameters
    ----------
    forward, backward : array_like of complex
        :math:`P_k^{+}` and :math:`P_k^{-}` per order [N or N m].
    orders : array_like
        Order :math:`k` of each phasor [1].
    theta_deg : array_like
        Crank angles [deg].

    Returns
    -------
    ndarray of complex, shape (n_angles,)
        :math:`y + ix` at each crank angle [N or N m]; ``.imag`` is the x component and
        ``.real`` the y component (:func:`transverse_components`).

    Examples
    --------
    A flat-crank inline-4's second order: equal forward and backward phasors at phase 0,
    a vertical force :math:`2P\cos 2\theta`.

    >>> q = phasor_signal([100.0], [100.0], [2], [0.0, 45.0, 90.0])
    >>> np.round(q, 9)
    array([ 200.+0.j,    0.+0.j, -200.+0.j])
    """
    per_order = signal_per_order(forward, backward, orders, theta_deg)
    return np.asarray(per_order.sum(axis=0), dtype=np.complex128)


def transverse_components(signal: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The (x, y) components of complex transverse vectors ``y + i x``.

    Parameters
    ----------
    signal : array_like of complex
        Vectors as ``y + i x`` [N or N m].

    Returns
    -------
    x, y : ndarray
        Horizontal (``x``, towards where the pin goes after +y) and vertical (``y``, up)
        components [N or N m].
    """
    q = np.asarray(signal, dtype=np.complex128)
    return np.asarray(q.imag, dtype=np.float64), np.asarray(q.real, dtype=np.float64)


def couple_components(moment_signal: ArrayLike) -> tuple[FloatArray, FloatArray]:
    r"""Pitch and yaw couples from the moment signal :math:`\sum (z_i - z_{ref}) F_i`.

    The moment phasors are the force-weighted lever arm drawn along the force; the
    physical couple is that vector turned by -90 degrees about z.

    Parameters
    ----------
    moment_signal : array_like of complex
        :math:`\sum (z_i - z_{ref}) F_i` as ``y + i x`` [N m].

    Returns
    -------
    pitch, yaw : ndarray
        :math:`M_x = -\sum \Delta z\,F_y` (about the horizontal axis) and
        :math:`M_y = \sum \Delta z\,F_x` (about the vertical axis) [N m].
    """
    q = np.asarray(moment_signal, dtype=np.complex128)
    return np.asarray(-q.real, dtype=np.float64), np.asarray(q.imag, dtype=np.float64)


def has_proposal(result: Result) -> bool:
    """Whether the result holds a balancing proposal and its residual.

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    bool
    """
    return result.part("proposal") is not None


def has_moments(result: Result) -> bool:
    """Whether the analysis computed the moments (not ``moments=False``).

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    bool
    """
    return bool(result.has_moments)


def has_roll(result: Result) -> bool:
    """Whether the analysis computed the roll torque (not ``roll=False``).

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    bool
    """
    return bool(result.has_roll)


def bundle_of(result: Result, source: Source = "free") -> Phasors:
    """The :class:`~balance.core.phasors.Phasors` of a source of a result.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    source : {'free', 'reciprocating', 'residual'}
        What to include (see the module notes): ``result.phasors.free()`` (its order 1
        set to 0 where it cancels to rounding, :func:`balance.views.polar.free_phasors`),
        ``result.phasors`` or the proposal's residual.

    Returns
    -------
    Phasors
        The bundle; its magnitudes, phases and peaks are its own methods
        (:meth:`~balance.core.phasors.Phasors.peak`, the one place a peak is formed).

    Raises
    ------
    ValueError
        For an unknown source, or ``residual`` without a proposal.
    """
    if source not in SOURCES:
        raise ValueError(f"source must be one of {', '.join(SOURCES)}, got {source!r}")
    if source == "residual":
        part = result.part("proposal")
        if part is None:
            raise ValueError(
                "this result has no balancing proposal (no residual); "
                "analyse with the proposal asked for (with moments and roll)"
            )
        bundle: Phasors = part.residual
        return bundle
    if source == "free":
        from balance.views.polar import free_phasors

        return free_phasors(result.phasors, result.engine.n_cylinders)
    return result.phasors


def phasors_of(
    result: Result, quantity: Quantity = "force", source: Source = "free"
) -> tuple[NDArray[np.intp], ComplexArray, ComplexArray]:
    """Complex forward and backward phasors per order of a result.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    quantity : {'force', 'moment'}
        The shaking force [N] or the moment about ``reference_z`` [N m].
    source : {'free', 'reciprocating', 'residual'}
        What to include (see the module notes).

    Returns
    -------
    orders : ndarray of int
        The result's orders.
    forward, backward : ndarray of complex
        Phasors per order [N or N m]; NaN where the analysis did not compute them (moments
        with ``moments=False``).

    Raises
    ------
    ValueError
        For an unknown quantity or source, or ``residual`` without a proposal.
    """
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {', '.join(QUANTITIES)}, got {quantity!r}")
    orders = np.asarray(result.phasors.orders, dtype=np.intp)
    forward, backward = bundle_of(result, source).pair(quantity)
    if forward is None or backward is None:  # moments not computed: NaN phasors
        forward = backward = np.full(orders.size, np.nan + 0j)
    return orders, np.asarray(forward, np.complex128), np.asarray(backward, np.complex128)


def peak_of(result: Result, quantity: Quantity = "force", source: Source = "free") -> FloatArray:
    """Peak over a revolution of each order of a source's force or moment.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    quantity : {'force', 'moment'}
        The shaking force [N] or the moment about ``reference_z`` [N m].
    source : {'free', 'reciprocating', 'residual'}
        What to include (see the module notes).

    Returns
    -------
    ndarray
        :meth:`Phasors.peak <balance.core.phasors.Phasors.peak>` of the source's bundle,
        ``|P+| + |P-|`` per order [N or N m]; NaN where the analysis did not compute the
        quantity (moments with ``moments=False``).
    """
    bundle = bundle_of(result, source)
    if not bundle.has(quantity):
        return np.full(np.asarray(bundle.orders).size, np.nan)
    return bundle.peak(quantity)


def magnitude_of(
    result: Result, quantity: Quantity = "force", source: Source = "free"
) -> FloatArray:
    """``|P+|`` and ``|P-|`` per order of a source's force or moment.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    quantity : {'force', 'moment'}
        The shaking force [N] or the moment about ``reference_z`` [N m].
    source : {'free', 'reciprocating', 'residual'}
        What to include (see the module notes).

    Returns
    -------
    ndarray, shape (orders, 2)
        :meth:`Phasors.magnitude <balance.core.phasors.Phasors.magnitude>` of the
        source's bundle, forward then backward [N or N m]; NaN where the analysis did not
        compute the quantity.
    """
    bundle = bundle_of(result, source)
    if not bundle.has(quantity):
        return np.full((np.asarray(bundle.orders).size, 2), np.nan)
    return bundle.magnitude(quantity)


def signal_of(
    result: Result,
    theta_deg: ArrayLike,
    quantity: Quantity = "force",
    source: Source = "free",
    per_order: bool = False,
) -> ComplexArray:
    """Force or moment of a result at the given crank angles.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    theta_deg : array_like
        Crank angles [deg].
    quantity : {'force', 'moment'}
        Shaking force [N] or moment about ``reference_z`` [N m].
    source : {'free', 'reciprocating', 'residual'}
        What to include (see the module notes).
    per_order : bool
        Return one row per order instead of the sum.

    Returns
    -------
    ndarray of complex
        ``y + i x`` at each angle, shape (n_angles,) or (n_orders, n_angles).
    """
    orders, fwd, bwd = phasors_of(result, quantity, source)
    signal = signal_per_order(fwd, bwd, orders, theta_deg)
    return signal if per_order else np.asarray(signal.sum(axis=0), dtype=np.complex128)


def roll_of(result: Result, residual: bool = False) -> tuple[FloatArray, ComplexArray]:
    """Roll orders and complex roll phasors [N m] of a result.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    residual : bool
        The roll with the proposed balance shafts instead of the engine's own.

    Returns
    -------
    orders, roll : ndarray
        Orders (halves for a four-stroke with gas forces) and phasors; both empty when the
        analysis did not compute the roll (``roll=False``).

    Raises
    ------
    ValueError
        For ``residual`` without a proposal.
    """
    part = result.part("proposal")
    if residual and part is None:
        raise ValueError("this result has no balancing proposal (no residual roll)")
    roll = part.residual_roll if residual else result.roll
    if roll is None:
        return np.zeros(0, dtype=np.float64), np.zeros(0, dtype=np.complex128)
    return (
        np.asarray(result.roll_orders, dtype=np.float64),
        np.asarray(roll, dtype=np.complex128),
    )


def roll_signal_per_order(roll: ArrayLike, orders: ArrayLike, theta_deg: ArrayLike) -> FloatArray:
    r"""Each order's roll torque :math:`\operatorname{Re}(R_k e^{ik\theta})` [N m].

    Parameters
    ----------
    roll : array_like of complex
        :math:`R_k = a_k e^{i\varphi_k}` per order [N m]: the torque is
        :math:`a_k \cos(k\theta + \varphi_k)`.
    orders : array_like
        Orders :math:`k`, possibly halves [1].
    theta_deg : array_like
        Crank angles [deg].

    Returns
    -------
    ndarray, shape (n_orders, n_angles)
        Torque on the block about the crank axis, positive with the rotation [N m].
    """
    r = np.atleast_1d(np.asarray(roll, dtype=np.complex128))
    ks = np.atleast_1d(np.asarray(orders, dtype=np.float64))
    th = np.radians(np.atleast_1d(np.asarray(theta_deg, dtype=np.float64)))
    if r.shape != ks.shape:
        raise ValueError(
            f"roll_signal: roll and orders must have one entry per order, got {r.shape} "
            f"and {ks.shape}"
        )
    return np.asarray((r[:, None] * np.exp(1j * ks[:, None] * th[None, :])).real, np.float64)


def roll_signal(roll: ArrayLike, orders: ArrayLike, theta_deg: ArrayLike) -> FloatArray:
    r"""Roll torque :math:`\sum_k \operatorname{Re}(R_k e^{ik\theta})` at each crank angle.

    Parameters
    ----------
    roll : array_like of complex
        :math:`R_k = a_k e^{i\varphi_k}` per order [N m].
    orders : array_like
        Orders :math:`k`, possibly halves [1].
    theta_deg : array_like
        Crank angles [deg].

    Returns
    -------
    ndarray
        Torque on the block about the crank axis, positive with the rotation [N m], one value
        per crank angle.
    """
    return np.asarray(roll_signal_per_order(roll, orders, theta_deg).sum(axis=0), dtype=np.float64)


def roll_span_deg(orders: ArrayLike) -> float:
    """Crank angle over which the roll repeats: 360 deg, or 720 deg with half orders.

    Parameters
    ----------
    orders : array_like
        The roll orders.

    Returns
    -------
    float
        The span [deg].
    """
    ks = np.asarray(orders, dtype=np.float64)
    return 720.0 if np.any(np.abs(ks - np.round(ks)) > 1e-9) else 360.0
