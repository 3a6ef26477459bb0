r"""The force balance of one crank slider: piston, rod and crank pin.

Pure functions of numpy arrays (any shapes that broadcast, typically (cylinders, angles)),
used by :mod:`balance.core.torque` (forces and torque over the cycle),
:mod:`balance.core.bearings` (the big ends' forces on the crank pins),
:mod:`balance.core.links` (a link rod on its link pin, the master rod that carries it) and
:mod:`balance.core.sampled` (the ``time`` model's reciprocating forces).

Notation and signs
------------------
In a cylinder's frame, :math:`X` across the bore towards the side the crank pin moves to
after TDC and :math:`Y` along the bore away from the crank; :math:`\beta` is the crank
angle from the cylinder's TDC direction, the crank pin is :math:`C = r(\sin\beta,
\cos\beta)`, the piston pin :math:`(e, s)` and the rod angle :math:`\psi` has
:math:`\sin\psi = (r\sin\beta - e)/l` (the big end towards :math:`+X` for :math:`\psi > 0`);
primes are derivatives with respect to :math:`\beta` (:math:`\times\omega^2` for
accelerations at constant speed :math:`\omega`).  The rod is its two-mass model (the
reciprocating mass :math:`m_\mathrm{rec}` at the piston pin, the rest at the crank pin) plus
a massless body of inertia :math:`\Delta I = I_G - m_c a(l - a)` (``conrod_inertia_correction``),
which is exact for every force here.

* :math:`P` (:func:`piston_force`): along the bore, towards the crank, pushing the rod:
  gas :math:`P_g = (p - p_0)A` plus reciprocating inertia :math:`P_j = m_\mathrm{rec}
  \omega^2 s''`;
* :math:`N` (:func:`side_thrust`): the piston on the wall towards :math:`-X`, which is the
  wall's force on the piston along :math:`+X`;
* :math:`S` (:func:`rod_force`): the rod's compression at the piston pin;
* :math:`T`, :math:`K` (:func:`tangential_force`, :func:`radial_force`): the rod's force on
  the crank pin in the direction of rotation and towards the crank axis;
  :func:`pin_force` gives it as a vector in the engine frame, with the centrifugal force of
  the masses at the pin.

The rod's moment balance about its big end (the piston pushes it with :math:`(N, -P)` at
the piston pin, :math:`d = (-l\sin\psi, l\cos\psi)` from the big end) with a couple
:math:`M` on the rod (counter-clockwise in :math:`X, Y`, i.e. against the rotation):
:math:`d_X(-P) - d_Y N + M = 0`, so

.. math::

    N = P\tan\psi + \frac{M}{l\cos\psi}, \qquad M = -\Delta I\,\omega^2\psi''

for the rod's own inertia (:func:`rod_inertia_couple`, :func:`couple_side_force`);
:math:`M` also carries what link rods hung on a master rod put on it (:func:`hung_load`,
with :func:`rod_on_piston` and :func:`rod_point_inertia` for the link rod and its link pin;
:func:`balance.core.link_forces.link_rod_forces`).

.. rubric:: References

C. F. Taylor, *The Internal-Combustion Engine in Theory and Practice*, vol. 2, 2nd ed., MIT
Press 1985, ch. 8 (forces of the crank train; the two-mass connecting rod); A. Kolchin and
V. Demidov, *Design of Automotive Engines*, Mir 1984, ch. 8–9 (gas and inertia force on the
piston, side thrust, rod force, tangential and radial force on the crank pin:
:math:`N = P\tan\psi`, :math:`S = P/\cos\psi`, :math:`T = P\sin(\beta+\psi)/\cos\psi`,
:math:`K = P\cos(\beta+\psi)/\cos\psi`); J. P. Den Hartog, *Mechanical Vibrations*, 4th ed.,
McGraw-Hill 1956 (the connecting rod as two masses, and the moment of inertia that this
misses); C. B. Biezeno and R. Grammel, *Engineering Dynamics*, vol. IV, *Internal-Combustion
Engines*, Blackie 1954 (the crank train's dynamics with the rod as a rigid body).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "couple_side_force",
    "hung_load",
    "pin_force",
    "piston_force",
    "radial_force",
    "reciprocating_force",
    "rod_direction",
    "rod_force",
    "rod_inertia_couple",
    "rod_on_piston",
    "rod_point_inertia",
    "side_thrust",
    "side_thrust_moment_balance",
    "tangential_force",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


_FLOAT = np.dtype(np.float64)


def _f(values: ArrayLike) -> FloatArray:
    return np.asarray(values, _FLOAT)  # a dtype, not a type: a third cheaper per call


def rod_direction(
    beta: ArrayLike,
    ratio: ArrayLike,
    offset_ratio: ArrayLike = 0.0,
    *,
    sin_beta: ArrayLike | None = None,
) -> tuple[FloatArray, FloatArray]:
    r"""Sine and cosine of the rod angle :math:`\psi` from the bore axis [1].

    Parameters
    ----------
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    ratio : array_like
        :math:`\lambda = r/l` [1].
    offset_ratio : array_like
        :math:`\varepsilon = e/r` [1].
    sin_beta : array_like, optional
        :math:`\sin\beta` [1], where the caller has it already (:func:`pin_force` needs it
        too).

    Returns
    -------
    sin_psi, cos_psi : ndarray
        :math:`\sin\psi = \lambda(\sin\beta - \varepsilon)` and
        :math:`\cos\psi = \sqrt{1 - \sin^2\psi}` [1].

    Notes
    -----
    :math:`r\sin\beta - e = l\sin\psi`: the crank pin and the piston pin, :math:`e` off the
    bore axis, are the rod's length apart (Taylor 1985, ch. 8).
    """
    sin_b = np.sin(_f(beta)) if sin_beta is None else _f(sin_beta)
    sin_psi = _f(ratio) * (sin_b - _f(offset_ratio))
    return sin_psi, np.sqrt(1.0 - sin_psi**2)


def reciprocating_force(
    mass: ArrayLike, speed_squared: ArrayLike, radius: ArrayLike, acceleration: ArrayLike
) -> FloatArray:
    r"""Reciprocating inertia force on the piston pin, towards the crank [N].

    Parameters
    ----------
    mass : array_like
        Reciprocating mass :math:`m_\mathrm{rec}` [kg].
    speed_squared : array_like
        :math:`\omega^2` [rad^2/s^2].
    radius : array_like
        Crank radius :math:`r` [m].
    acceleration : array_like
        :math:`s''/r` [1/rad^2], the piston pin's acceleration away from the crank per
        :math:`r\omega^2`.

    Returns
    -------
    ndarray
        :math:`P_j = m_\mathrm{rec}\,\omega^2\,r\,(s''/r)` [N].

    Notes
    -----
    d'Alembert's force :math:`-m_\mathrm{rec}\,\omega^2 s''` along :math:`+Y` is
    :math:`m_\mathrm{rec}\,\omega^2 s''` towards the crank (Taylor 1985, ch. 8).
    """
    return np.asarray(_f(mass) * _f(speed_squared) * _f(radius) * _f(acceleration))


def piston_force(inertia_force: ArrayLike, gas_force: ArrayLike | None = None) -> FloatArray:
    r"""Force along the bore on the piston pin, towards the crank [N].

    Parameters
    ----------
    inertia_force : array_like
        :math:`P_j` [N] (:func:`reciprocating_force`).
    gas_force : array_like, optional
        :math:`P_g = (p - p_0)A` [N] (:func:`balance.core.gas.piston_gas_force`); none
        without gas.

    Returns
    -------
    ndarray
        :math:`P = P_g + P_j` [N] (Kolchin and Demidov 1984).
    """
    if gas_force is None:
        return _f(inertia_force)
    return np.asarray(_f(gas_force) + _f(inertia_force))


def rod_inertia_couple(
    inertia_correction: ArrayLike, speed_squared: ArrayLike, d2psi: ArrayLike
) -> FloatArray:
    r"""Inertia couple of the rod beyond its two-mass model [N m].

    Parameters
    ----------
    inertia_correction : array_like
        :math:`\Delta I = I_G - m_c a(l - a)` [kg m^2].
    speed_squared : array_like
        :math:`\omega^2` [rad^2/s^2].
    d2psi : array_like
        :math:`\psi''` [1/rad] (:func:`balance.core.kinematics.conrod_angle_derivatives`).

    Returns
    -------
    ndarray
        :math:`M = -\Delta I\,\omega^2\psi''` [N m], counter-clockwise in :math:`X, Y`.

    Notes
    -----
    The two masses :math:`m_c a/l` at the piston pin and :math:`m_c(1 - a/l)` at the crank
    pin keep the rod's mass and centre of gravity but have the moment of inertia
    :math:`m_c a(l - a)` about it; the rest, :math:`\Delta I`, turning at
    :math:`\omega^2\psi''`, asks for this couple (Den Hartog 1956; Taylor 1985, ch. 8).
    """
    return np.asarray(-_f(inertia_correction) * _f(speed_squared) * _f(d2psi))


def couple_side_force(couple: ArrayLike, length: ArrayLike, cos_psi: ArrayLike) -> FloatArray:
    r"""Force across the bore that carries a couple on the rod [N].

    Parameters
    ----------
    couple : array_like
        :math:`M` [N m], on the rod about its big end, counter-clockwise in :math:`X, Y`
        (:func:`rod_inertia_couple`, or what link rods put on a master rod).
    length : array_like
        Rod length :math:`l` [m].
    cos_psi : array_like
        :math:`\cos\psi` [1] (:func:`rod_direction`).

    Returns
    -------
    ndarray
        :math:`M/(l\cos\psi)` [N]: added to the side thrust :math:`N` at the piston pin,
        and taken off the force on the crank pin across the bore.
    """
    return np.asarray(_f(couple) / (_f(length) * _f(cos_psi)))


def side_thrust(
    piston: ArrayLike, sin_psi: ArrayLike, cos_psi: ArrayLike, couple_force: ArrayLike
) -> FloatArray:
    r"""Side thrust of the piston on the wall [N], towards :math:`-X`.

    Parameters
    ----------
    piston : array_like
        :math:`P` [N] (:func:`piston_force`).
    sin_psi, cos_psi : array_like
        The rod angle's sine and cosine [1] (:func:`rod_direction`).
    couple_force : array_like
        :math:`M/(l\cos\psi)` [N] (:func:`couple_side_force`).

    Returns
    -------
    ndarray
        :math:`N = P\sin\psi/\cos\psi + M/(l\cos\psi)` [N], also the wall's force on the
        piston along :math:`+X`.

    Notes
    -----
    The rod's moment balance about its big end (module notes); with :math:`M = 0` the
    textbook :math:`N = P\tan\psi` (Kolchin and Demidov 1984; Taylor 1985, ch. 8).  The
    same :math:`N` as :func:`side_thrust_moment_balance`, formed in another order: the two
    differ in the last bits.
    """
    return np.asarray(_f(piston) * _f(sin_psi) / _f(cos_psi) + _f(couple_force))


def side_thrust_moment_balance(
    piston: ArrayLike,
    sin_psi: ArrayLike,
    cos_psi: ArrayLike,
    length: ArrayLike,
    inertia_correction: ArrayLike,
    speed_squared: ArrayLike,
    d2psi: ArrayLike,
) -> FloatArray:
    r""":func:`side_thrust` with the rod's inertia couple, written as the moment balance [N].

    Parameters
    ----------
    piston : array_like
        :math:`P` [N] (:func:`piston_force`).
    sin_psi, cos_psi : array_like
        The rod angle's sine and cosine [1] (:func:`rod_direction`).
    length : array_like
        Rod length :math:`l` [m].
    inertia_correction : array_like
        :math:`\Delta I` [kg m^2].
    speed_squared : array_like
        :math:`\omega^2` [rad^2/s^2].
    d2psi : array_like
        :math:`\psi''` [1/rad].

    Returns
    -------
    ndarray
        :math:`N = -(\Delta I\,\omega^2\psi'' + d_X P)/d_Y` [N] with
        :math:`d = (-l\sin\psi, l\cos\psi)`, the wall's force on the piston along
        :math:`+X`.

    Notes
    -----
    The moment balance of the massless rod of inertia :math:`\Delta I` about the big end,
    :math:`\Delta I\,\omega^2\psi'' = d \times (N, -P)` (module notes; Biezeno and Grammel
    1954).  Algebraically :func:`side_thrust` with
    :func:`couple_side_force` of :func:`rod_inertia_couple`; the bits differ, so each caller
    keeps the order it has always used (bearing loads and link rods this one, the torque
    model :func:`side_thrust`).
    """
    d_x = -_f(length) * _f(sin_psi)
    d_y = _f(length) * _f(cos_psi)
    return np.asarray(
        -(_f(inertia_correction) * _f(speed_squared) * _f(d2psi) + d_x * _f(piston)) / d_y
    )


def rod_force(
    piston: ArrayLike, side: ArrayLike, sin_psi: ArrayLike, cos_psi: ArrayLike
) -> FloatArray:
    r"""Force along the rod at the piston pin, compression positive [N].

    Parameters
    ----------
    piston : array_like
        :math:`P` [N].
    side : array_like
        :math:`N` [N] (:func:`side_thrust`).
    sin_psi, cos_psi : array_like
        The rod angle's sine and cosine [1].

    Returns
    -------
    ndarray
        :math:`S = P\cos\psi + N\sin\psi` [N]: the piston's push :math:`(N, -P)` on the rod
        along its axis; :math:`P/\cos\psi` without the couple (Kolchin and Demidov 1984).
    """
    return np.asarray(_f(piston) * _f(cos_psi) + _f(side) * _f(sin_psi))


def tangential_force(
    piston: ArrayLike,
    ds: ArrayLike,
    inertia_correction: ArrayLike,
    speed_squared: ArrayLike,
    dpsi: ArrayLike,
    d2psi: ArrayLike,
    radius: ArrayLike,
) -> FloatArray:
    r"""Force of the rod on the crank pin in the direction of rotation [N].

    Parameters
    ----------
    piston : array_like
        :math:`P` [N].
    ds : array_like
        :math:`s'/r` [1] (:func:`balance.core.kinematics.normalised_slider`).
    inertia_correction : array_like
        :math:`\Delta I` [kg m^2].
    speed_squared : array_like
        :math:`\omega^2` [rad^2/s^2].
    dpsi, d2psi : array_like
        :math:`\psi'` [1] and :math:`\psi''` [1/rad].
    radius : array_like
        Crank radius :math:`r` [m].

    Returns
    -------
    ndarray
        :math:`T = -P\,(s'/r) - \Delta I\,\omega^2\psi'\psi''/r` [N]; :math:`T r` is the
        cylinder's torque on the crank.

    Notes
    -----
    Virtual work: the pin force does the work of the piston force along :math:`s` and of
    the couple along :math:`\psi` (the rod's spin energy); it equals
    :math:`P\sin\beta + N\cos\beta` and, with :math:`\Delta I = 0`, the textbook
    :math:`T = P\sin(\beta + \psi)/\cos\psi` (Kolchin and Demidov 1984; Taylor 1985,
    ch. 8), exact with an offset.
    """
    return np.asarray(
        -_f(piston) * _f(ds)
        - _f(inertia_correction) * _f(speed_squared) * _f(dpsi) * _f(d2psi) / _f(radius)
    )


def radial_force(piston: ArrayLike, side: ArrayLike, beta: ArrayLike) -> FloatArray:
    r"""Force of the rod on the crank pin towards the crank axis [N].

    Parameters
    ----------
    piston : array_like
        :math:`P` [N].
    side : array_like
        :math:`N` [N].
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].

    Returns
    -------
    ndarray
        :math:`K = P\cos\beta - N\sin\beta` [N]: the rod passes :math:`(N, -P)` to the pin;
        with :math:`\Delta I = 0`, :math:`K = P\cos(\beta + \psi)/\cos\psi` (Kolchin and
        Demidov 1984).
    """
    b = _f(beta)
    return np.asarray(_f(piston) * np.cos(b) - _f(side) * np.sin(b))


def pin_force(
    piston: ArrayLike,
    side: ArrayLike,
    centrifugal: ArrayLike,
    beta: ArrayLike,
    bank: ArrayLike,
    *,
    sin_beta: ArrayLike | None = None,
) -> ComplexArray:
    r"""Force of the big end on its crank pin, in the engine frame [N].

    Parameters
    ----------
    piston : array_like
        :math:`P` [N].
    side : array_like
        :math:`N` [N] (:func:`side_thrust_moment_balance`).
    centrifugal : array_like
        :math:`m\,\omega^2 r` [N] of the mass that turns with the pin (the rod's big-end
        share).
    beta : array_like
        Crank angle from the cylinder's TDC direction [rad].
    bank : array_like
        Bank angle :math:`\psi_b` of the cylinder [rad].
    sin_beta : array_like, optional
        :math:`\sin\beta` [1], where the caller has it already (:func:`rod_direction`).

    Returns
    -------
    ndarray of complex
        :math:`(F_Y + \mathrm{i}F_X)\,e^{\mathrm{i}\psi_b}` (:math:`y + \mathrm{i}x`,
        docs/conventions.md, "Frame and angles") with :math:`F = (N, -P) + m\omega^2 r(\sin\beta,
        \cos\beta)` in the cylinder's frame: the rod passes the piston's push to the pin, and the
        mass at the pin pulls outwards.  Its components along and across the throw are :math:`-K`
        and :math:`T` plus the centrifugal force.
    """
    b = _f(beta)
    c = _f(centrifugal)
    f_x = _f(side) + c * (np.sin(b) if sin_beta is None else _f(sin_beta))
    f_y = -_f(piston) + c * np.cos(b)
    return np.asarray((f_y + 1j * f_x) * np.exp(1j * _f(bank)), dtype=np.complex128)


def rod_point_inertia(
    sin_psi: ArrayLike, cos_psi: ArrayLike, dpsi: ArrayLike, d2psi: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    r"""Inertia force of a point fixed on the rod, relative to the big end, per
    :math:`m\rho\,\omega^2` [1].

    Parameters
    ----------
    sin_psi, cos_psi : array_like
        The rod angle's sine and cosine [1] (:func:`rod_direction`).
    dpsi, d2psi : array_like
        :math:`\psi'` [1] and :math:`\psi''` [1/rad].

    Returns
    -------
    re, im : ndarray
        Real and imaginary parts of :math:`q = e^{-\mathrm{i}\psi}(\psi'^2 +
        \mathrm{i}\psi'')`, as :math:`Y + \mathrm{i}X` in the frame that the rod has at
        :math:`\psi = 0`.

    Notes
    -----
    A point at :math:`\rho\,e^{\mathrm{i}(\delta - \psi)}` from the big end (as
    :math:`Y + \mathrm{i}X`; a master rod's link pin, :mod:`balance.core.links`) moves
    relative to it with the second derivative :math:`\rho\,e^{\mathrm{i}(\delta - \psi)}
    (-\mathrm{i}\psi'' - \psi'^2)`; a mass :math:`m` there takes the inertia force
    :math:`m\rho\,\omega^2 e^{\mathrm{i}\delta} q` besides the centrifugal force of the
    crank pin's circle (Taylor 1985, ch. 8; the link pin of an articulated rod: Fearn,
    "The articulated connecting rod", J. Royal Aeronautical Society, 1927).
    """
    s, c = _f(sin_psi), _f(cos_psi)
    d1, d2 = _f(dpsi), _f(d2psi)
    return np.asarray(c * d1**2 + s * d2), np.asarray(c * d2 - s * d1**2)


def rod_on_piston(piston: ArrayLike, side: ArrayLike, bank: ArrayLike) -> ComplexArray:
    r"""Force of the rod on its piston pin, in the engine frame [N].

    Parameters
    ----------
    piston : array_like
        :math:`P` [N].
    side : array_like
        :math:`N` [N], the wall's force on the piston along :math:`+X`.
    bank : array_like
        Bank angle :math:`\psi_b` of the cylinder [rad].

    Returns
    -------
    ndarray of complex
        :math:`(P - \mathrm{i}N)\,e^{\mathrm{i}\psi_b}`: the piston, pushed by :math:`P`
        towards the crank and by the wall, is held by the rod with :math:`(-N, P)`
        (:math:`X, Y`); the rod's lower end takes the opposite.
    """
    return np.asarray((_f(piston) - 1j * _f(side)) * np.exp(1j * _f(bank)), dtype=np.complex128)


def hung_load(
    reaction: ArrayLike,
    point: ArrayLike,
    crank_pin: ArrayLike,
    length: ArrayLike,
    cos_psi: ArrayLike,
    bank: ArrayLike,
) -> tuple[FloatArray, ComplexArray]:
    r"""What a body hung on the rod at a point (a link rod on a master rod's link pin) adds
    to the side thrust and passes to the crank pin [N].

    Parameters
    ----------
    reaction : array_like of complex
        :math:`F_L`, the force the rod puts on the hung body at the point [N], engine frame
        (:math:`y + \mathrm{i}x`); the rod takes :math:`-F_L` there.
    point, crank_pin : array_like of complex
        The point and the crank pin [m], engine frame.
    length : array_like
        The rod's length :math:`l` [m].
    cos_psi : array_like
        :math:`\cos\psi` of the rod [1].
    bank : array_like
        Bank angle :math:`\psi_b` of the rod's cylinder [rad].

    Returns
    -------
    side : ndarray
        :math:`\Delta N = M/(l\cos\psi)` [N], added to the wall's force on the piston along
        :math:`+X`, with :math:`M = \operatorname{Im}(\overline{(L - C)}F_L)` the moment of
        :math:`-F_L` about the crank pin against the rotation (:func:`couple_side_force`).
    on_pin : ndarray of complex
        :math:`\mathrm{i}\,\Delta N e^{\mathrm{i}\psi_b} - F_L` [N]: the rest of
        :math:`-F_L`, which the rod passes to the crank pin.

    Notes
    -----
    The rod (its own mass in its two-mass model) is in balance under :math:`-F_L` at
    :math:`L`, the piston's :math:`(-\Delta N, 0)` at the piston pin and the pin's force:
    the moment about the crank pin gives :math:`\Delta N`, the forces the rest
    (Fearn 1927; the module notes).
    """
    load = np.asarray(reaction, dtype=np.complex128)
    arm = np.asarray(point, dtype=np.complex128) - np.asarray(crank_pin, dtype=np.complex128)
    side = couple_side_force(np.imag(np.conj(arm) * load), length, cos_psi)
    return side, np.asarray(1j * side * np.exp(1j * _f(bank)) - load, dtype=np.complex128)
