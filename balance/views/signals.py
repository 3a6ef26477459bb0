r"""From phasors back to the crank-angle domain: what the plots draw, without drawing.

Pure numpy (and xarray to read the result Dataset); no matplotlib.  Every function here
follows the CONTRACT: a transverse vector :math:`(x, y)` is the complex number
:math:`y + i x`, angles are measured from +y in the direction of rotation, and order
:math:`k` of a quantity is

.. math::

    Q_k(\theta) = P_k^{+} e^{+ik\theta} + P_k^{-} e^{-ik\theta}.

Crank angles are in degrees here, as everywhere in the results.

Three *sources* of the force and moment can be synthesised from a result Dataset
(:func:`dataset_phasors`):

``reciprocating``
    The inertia of the reciprocating masses only (``reciprocating_*``).
``free``
    Everything the moving parts shake the block with: reciprocating plus the centrifugal
    force of the rotating masses (order 1, forward).  This is what a proposal acts on.
``residual``
    What is left with every proposed counterweight and balance-shaft mass
    (``residual_*``; needs a proposal).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

__all__ = [
    "QUANTITIES",
    "SOURCES",
    "couple_components",
    "crank_angle_grid",
    "dataset_phasors",
    "dataset_roll",
    "dataset_signal",
    "has_moments",
    "has_proposal",
    "has_roll",
    "peaks",
    "phasor_signal",
    "phasor_signal_per_order",
    "phasors_from_polar",
    "roll_signal",
    "roll_signal_per_order",
    "roll_span_deg",
    "signal_per_order",
    "transverse_components",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

Quantity = Literal["force", "moment"]
Source = Literal["reciprocating", "free", "residual"]

QUANTITIES: tuple[Quantity, ...] = ("force", "moment")
SOURCES: tuple[Source, ...] = ("reciprocating", "free", "residual")


def phasors_from_polar(magnitude: ArrayLike, phase_deg: ArrayLike) -> ComplexArray:
    """Complex phasors from magnitudes and phases.

    Parameters
    ----------
    magnitude : array_like
        Magnitudes [N or N m].
    phase_deg : array_like
        Phases at crank angle 0, from +y in the direction of rotation [deg].

    Returns
    -------
    ndarray of complex
        ``magnitude * exp(i * phase)``, broadcast.
    """
    mag = np.asarray(magnitude, dtype=np.float64)
    phase = np.radians(np.asarray(phase_deg, dtype=np.float64))
    return np.asarray(mag * np.exp(1j * phase), dtype=np.complex128)


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


def phasor_signal_per_order(
    magnitude_fwd: ArrayLike,
    phase_fwd: ArrayLike,
    magnitude_bwd: ArrayLike,
    phase_bwd: ArrayLike,
    orders: ArrayLike,
    theta_deg: ArrayLike,
) -> ComplexArray:
    r"""Each order's :math:`Q_k(\theta) = P_k^{+}e^{ik\theta} + P_k^{-}e^{-ik\theta}`.

    Parameters
    ----------
    magnitude_fwd, phase_fwd : array_like
        Forward phasors per order: magnitude [N or N m] and phase [deg].
    magnitude_bwd, phase_bwd : array_like
        Backward phasors per order, the same way.
    orders : array_like
        Order :math:`k` of each phasor [1].
    theta_deg : array_like
        Crank angles [deg].

    Returns
    -------
    ndarray of complex, shape (n_orders, n_angles)
        :math:`y + ix` of each order at each crank angle [N or N m].
    """
    return signal_per_order(
        phasors_from_polar(magnitude_fwd, phase_fwd),
        phasors_from_polar(magnitude_bwd, phase_bwd),
        orders,
        theta_deg,
    )


def signal_per_order(
    forward: ArrayLike, backward: ArrayLike, orders: ArrayLike, theta_deg: ArrayLike
) -> ComplexArray:
    r"""Each order's :math:`Q_k(\theta)` from complex phasors (as :func:`phasor_signal_per_order`).

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
    magnitude_fwd: ArrayLike,
    phase_fwd: ArrayLike,
    magnitude_bwd: ArrayLike,
    phase_bwd: ArrayLike,
    orders: ArrayLike,
    theta_deg: ArrayLike,
) -> ComplexArray:
    r"""Sum over orders :math:`Q(\theta) = \sum_k P_k^{+}e^{ik\theta} + P_k^{-}e^{-ik\theta}`.

    Parameters
    ----------
    magnitude_fwd, phase_fwd : array_like
        Forward phasors per order: magnitude [N or N m] and phase [deg].
    magnitude_bwd, phase_bwd : array_like
        Backward phasors per order, the same way.
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

    >>> q = phasor_signal([100.0], [0.0], [100.0], [0.0], [2], [0.0, 45.0, 90.0])
    >>> np.round(q, 9)
    array([ 200.+0.j,    0.+0.j, -200.+0.j])
    """
    per_order = phasor_signal_per_order(
        magnitude_fwd, phase_fwd, magnitude_bwd, phase_bwd, orders, theta_deg
    )
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


def has_proposal(ds: xr.Dataset) -> bool:
    """Whether the Dataset holds a balancing proposal and its residual."""
    return "residual_force_magnitude" in ds.data_vars


def has_moments(ds: xr.Dataset) -> bool:
    """Whether the analysis computed the moments (not ``moments=False``)."""
    name = "reciprocating_moment_magnitude"
    return name in ds.data_vars and not bool(np.isnan(ds[name].values).all())


def has_roll(ds: xr.Dataset) -> bool:
    """Whether the analysis computed the roll torque (not ``roll=False``)."""
    return "roll_amplitude" in ds.data_vars and not bool(np.isnan(ds["roll_amplitude"]).all())


def dataset_phasors(
    ds: xr.Dataset, quantity: Quantity = "force", source: Source = "free"
) -> tuple[NDArray[np.int64], ComplexArray, ComplexArray]:
    """Complex forward and backward phasors per order from a result Dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        The result of :func:`balance.analyse`.
    quantity : {'force', 'moment'}
        The shaking force [N] or the moment about ``reference_z`` [N m].
    source : {'free', 'reciprocating', 'residual'}
        What to include (see the module notes).

    Returns
    -------
    orders : ndarray of int
        The Dataset's orders.
    forward, backward : ndarray of complex
        Phasors per order [N or N m].

    Raises
    ------
    ValueError
        For an unknown quantity or source, or ``residual`` without a proposal.

    Notes
    -----
    Phasors the analysis did not compute (moments with ``moments=False``, whose variables
    are then absent or NaN) are returned as NaN.
    """
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {', '.join(QUANTITIES)}, got {quantity!r}")
    if source not in SOURCES:
        raise ValueError(f"source must be one of {', '.join(SOURCES)}, got {source!r}")
    prefix = "residual" if source == "residual" else "reciprocating"
    if source == "residual" and not has_proposal(ds):
        raise ValueError(
            "the Dataset has no balancing proposal (no residual_* variables); "
            "analyse with proposal=True"
        )
    orders = np.asarray(ds["order"].values, dtype=np.int64)
    if f"{prefix}_{quantity}_magnitude" not in ds.data_vars:  # not computed (moments=False)
        missing = np.full(orders.shape, np.nan + 0j)
        return orders, missing, missing.copy()
    magnitude = ds[f"{prefix}_{quantity}_magnitude"]
    phase = ds[f"{prefix}_{quantity}_phase"]
    forward = phasors_from_polar(
        magnitude.sel(rotation="forward").values, phase.sel(rotation="forward").values
    )
    backward = phasors_from_polar(
        magnitude.sel(rotation="backward").values, phase.sel(rotation="backward").values
    )
    if source == "free":
        rotating = complex(
            phasors_from_polar(
                float(ds[f"rotating_{quantity}_magnitude"]), float(ds[f"rotating_{quantity}_phase"])
            )
        )
        forward = forward + np.where(orders == 1, rotating, 0.0)
    # NaN phasors (moments not computed) stay NaN
    return orders, np.asarray(forward, np.complex128), np.asarray(backward, np.complex128)


def peaks(forward: ArrayLike, backward: ArrayLike) -> FloatArray:
    """Peak over a revolution of each order, ``|P+| + |P-|`` [N or N m]."""
    return np.asarray(np.abs(forward) + np.abs(backward), dtype=np.float64)


def dataset_signal(
    ds: xr.Dataset,
    theta_deg: ArrayLike,
    quantity: Quantity = "force",
    source: Source = "free",
    per_order: bool = False,
) -> ComplexArray:
    """Force or moment of a result Dataset at the given crank angles.

    Parameters
    ----------
    ds : xarray.Dataset
        The result of :func:`balance.analyse`.
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
    orders, fwd, bwd = dataset_phasors(ds, quantity, source)
    signal = signal_per_order(fwd, bwd, orders, theta_deg)
    return signal if per_order else np.asarray(signal.sum(axis=0), dtype=np.complex128)


def dataset_roll(
    ds: xr.Dataset, residual: bool = False
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Roll orders, amplitudes [N m] and phases [deg] of a result Dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        The result of :func:`balance.analyse`.
    residual : bool
        The roll with the proposed balance shafts (``residual_roll_*``) instead of the
        engine's own.

    Returns
    -------
    orders, amplitude, phase_deg : ndarray
        Empty when the analysis did not compute the roll (``roll=False``).
    """
    prefix = "residual_roll" if residual else "roll"
    if residual and not has_proposal(ds):
        raise ValueError("the Dataset has no balancing proposal (no residual_roll_* variables)")
    if f"{prefix}_amplitude" not in ds.data_vars:
        empty = np.zeros(0, dtype=np.float64)
        return empty, empty.copy(), empty.copy()
    return (
        np.asarray(ds["roll_order"].values, dtype=np.float64),
        np.asarray(ds[f"{prefix}_amplitude"].values, dtype=np.float64),
        np.asarray(ds[f"{prefix}_phase"].values, dtype=np.float64),
    )


def roll_signal_per_order(
    amplitude: ArrayLike, phase_deg: ArrayLike, orders: ArrayLike, theta_deg: ArrayLike
) -> FloatArray:
    r"""Each order's roll torque :math:`a_k \cos(k\theta + \varphi_k)` [N m].

    Parameters
    ----------
    amplitude : array_like
        :math:`a_k` per order [N m].
    phase_deg : array_like
        :math:`\varphi_k` per order [deg].
    orders : array_like
        Orders :math:`k`, possibly halves [1].
    theta_deg : array_like
        Crank angles [deg].

    Returns
    -------
    ndarray, shape (n_orders, n_angles)
        Torque on the block about the crank axis, positive with the rotation [N m].
    """
    amp = np.atleast_1d(np.asarray(amplitude, dtype=np.float64))
    phase = np.radians(np.atleast_1d(np.asarray(phase_deg, dtype=np.float64)))
    ks = np.atleast_1d(np.asarray(orders, dtype=np.float64))
    th = np.radians(np.atleast_1d(np.asarray(theta_deg, dtype=np.float64)))
    return np.asarray(
        amp[:, None] * np.cos(ks[:, None] * th[None, :] + phase[:, None]), dtype=np.float64
    )


def roll_signal(
    amplitude: ArrayLike, phase_deg: ArrayLike, orders: ArrayLike, theta_deg: ArrayLike
) -> FloatArray:
    r"""Roll torque :math:`\sum_k a_k \cos(k\theta + \varphi_k)` at each crank angle [N m].

    Parameters are those of :func:`roll_signal_per_order`.
    """
    return np.asarray(
        roll_signal_per_order(amplitude, phase_deg, orders, theta_deg).sum(axis=0),
        dtype=np.float64,
    )


def roll_span_deg(orders: ArrayLike) -> float:
    """Crank angle over which the roll repeats: 360 deg, or 720 deg with half orders."""
    ks = np.asarray(orders, dtype=np.float64)
    return 720.0 if np.any(np.abs(ks - np.round(ks)) > 1e-9) else 360.0
