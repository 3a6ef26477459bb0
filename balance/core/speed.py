r"""Crank speed: :math:`\omega^2` and the conversions between rpm and rad/s.

Every place that needs one of these numbers calls these functions, so that each is formed
by the same operations everywhere (a sweep and a single analysis agree bit for bit).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["RAD_PER_S_PER_RPM", "rad_per_s_to_rpm", "rpm_to_rad_per_s", "speed_squared"]

#: Radians per second in one revolution per minute.
RAD_PER_S_PER_RPM = 2.0 * math.pi / 60.0


def speed_squared(speed: ArrayLike) -> NDArray[np.float64]:
    r""":math:`\omega^2` as ``speed * speed``.

    Written as a product, not a power: ``x ** 2`` on a Python float calls the C library's
    ``pow``, which need not round like the product that numpy computes for an array, and
    a sweep and a single analysis must scale by the same number.

    Parameters
    ----------
    speed : array_like
        Crank speed :math:`\omega` [rad/s].

    Returns
    -------
    ndarray
        :math:`\omega^2` [rad²/s²].
    """
    w = np.asarray(speed, dtype=np.float64)
    return np.asarray(w * w)


def rpm_to_rad_per_s(rpm: float) -> float:
    """A crank speed in rpm as rad/s.

    Parameters
    ----------
    rpm : float
        Crank speed [rpm].

    Returns
    -------
    float
        Crank speed [rad/s].
    """
    return rpm * RAD_PER_S_PER_RPM


def rad_per_s_to_rpm(speed: float) -> float:
    """A crank speed in rad/s as rpm (``speed * 60 / (2 pi)``).

    Parameters
    ----------
    speed : float
        Crank speed [rad/s].

    Returns
    -------
    float
        Crank speed [rpm].
    """
    return speed * 60.0 / (2.0 * math.pi)
