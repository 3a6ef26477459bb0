r"""The crank train's own motion: reduced inertia, periodic steady state, orders in time.

The crank train is a set of rigid bodies driven by one coordinate, the crank angle
:math:`\theta` (docs/dynamics.md).  Every moving mass of the layout is a point whose place
in the transverse plane is the complex number :math:`z(\theta) = y + ix` (docs/conventions.md):
each rotating mass on its crank pin, each reciprocating mass at its piston pin (offset
included), each link rod's link-pin share on its link pin; every rod's inertia beyond its
two-mass model, :math:`\Delta I`, is a body turning through the angle
:math:`\Gamma(\theta)` of its rod.  With :math:`\omega = \dot\theta` the kinetic energy is
:math:`\tfrac12 J(\theta)\omega^2`,

.. math::

    J(\theta) = J_f + \sum_b m_b |z_b'|^2 + \sum_r \Delta I_r \Gamma_r'^2,

and the crank train obeys Lagrange's equation for one coordinate,

.. math::

    J\dot\omega + \tfrac12 J'\omega^2 = Q(\theta) - T_L(\omega),

:math:`Q` the gas torque and :math:`T_L` the load.  In the energy form,
:math:`E = \tfrac12 J\omega^2` obeys :math:`\mathrm dE/\mathrm d\theta = Q - T_L`, which
:func:`periodic_motion` solves over one working cycle for its periodic solution directly
(in closed form for a constant and a propeller load, each step of Newton's method for a
power law; the integrals term by term of the samples' Fourier series), with the
time-mean speed (cycle angle over cycle time) given or, for a power law, found.

Under that motion a point's acceleration is :math:`a = z''\omega^2 + z'\dot\omega`; the block
receives the shaking force :math:`-\sum m a`, its moment, and the roll

.. math::

    R = \sum_b m_b\left[\operatorname{Re}(\bar z_b' a_b) - \operatorname{Im}(\bar z_b a_b)
        \right] + \sum_r \Delta I_r\,\ddot\Gamma_r(\Gamma_r' - 1) - Q

(the rate of change of the angular momentum about the crank axis, with the work the crank
does on the bodies: :math:`m s''(s' + e)\omega^2` for a piston at constant speed, as in
:func:`balance.core.kinematics.roll_coefficients`; a mass on the crank pin and the flywheel
add nothing).  :func:`orders_in_time` takes their orders at multiples of the mean speed in
time, against the mean crank angle :math:`\bar\theta(t)`.

.. rubric:: References

Lagrange's equation for a machine of one degree of freedom with a variable reduced moment
of inertia, and its energy integral: Biezeno and Grammel, *Engineering Dynamics*, vol. IV
(internal-combustion engines), Blackie 1954, ch. I; Norton, *Design of Machinery*, 5th ed.,
McGraw-Hill 2012, ch. 11 and 13 (flywheels, engine dynamics); Khurmi and Gupta, *Theory of
Machines*, S. Chand 2005, ch. 16 (turning-moment diagrams and flywheels).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.engine import Engine
from balance.core.errors import AnalysisError
from balance.core.kinematics import (
    conrod_angle_derivatives,
    normalised_slider,
    offset_ratio,
    rod_ratio,
)

__all__ = [
    "ConstantTorque",
    "CrankTrain",
    "Motion",
    "PowerLaw",
    "Propeller",
    "crank_train",
    "find_root",
    "orders_in_time",
    "periodic_integral",
    "periodic_linear",
    "periodic_motion",
    "time_over_cycle",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Newton steps of the power-law steady state before it gives up.
NEWTON_STEPS = 100
#: Relative change of the energy below which the power law's Newton iteration has converged.
NEWTON_TOLERANCE = 1e-14
#: Relative change below which a step that is not at least halved from the one before means
#: the iteration has reached the rounding of the closed-form linear solve (1e-14 on most
#: cycles; up to 2e-10 where the exponential of the load's periodic integral spans decades,
#: on cycles hypothesis found): converged as far as floating point allows.
NEWTON_FLOOR = 1e-8


# --------------------------------------------------------------------------- the bodies


@dataclass(frozen=True, eq=False)
class CrankTrain:
    r"""The layout's moving bodies over crank angles, reduced to what the motion needs.

    Point masses :math:`m_b` at :math:`z_b(\theta)` and rotors :math:`\Delta I_r` at
    :math:`\Gamma_r(\theta)` (see the module notes); derivatives with respect to
    :math:`\theta`.  Arrays have the crank angles on the last axis (N).

    Attributes
    ----------
    theta : ndarray
        Crank angle [rad].
    inertia, inertia_slope : ndarray
        The layout's part of the reduced inertia, :math:`J - J_f` [kg m^2], and
        :math:`J'` [kg m^2/rad].
    cylinder_inertia : ndarray
        Each cylinder's part of :attr:`inertia` [kg m^2], shape (cylinders, N): twice the
        kinetic energy of its piston group, rod and crank-pin mass per :math:`\omega^2`.
    force_rate, force_curvature : ndarray of complex
        :math:`\sum m z'` [kg m/rad] and :math:`\sum m z''` [kg m/rad^2]: the shaking force
        is :math:`-(\omega^2\sum m z'' + \dot\omega\sum m z')` [N].
    moment_rate, moment_curvature : ndarray of complex
        The same with each mass times :math:`z_i - z_{ref}` [kg m^2/rad, kg m^2/rad^2].
    roll_rate, roll_curvature : ndarray
        :math:`R_1` [kg m^2] and :math:`R_2` [kg m^2/rad]: the roll without the gas is
        :math:`\omega^2 R_2 + \dot\omega R_1` [N m].
    force_size, moment_size, roll_size : ndarray
        Shape (2, N): the sums of the magnitudes of the terms of the rate and curvature
        sums above (the scale of their rounding).
    piston_rate : ndarray
        :math:`s_i'` of each piston [m/rad], shape (cylinders, N): the gas torque of
        cylinder i is :math:`-P_{g,i} s_i'`.
    velocity_reach, acceleration_reach : float
        :math:`\sum_b m_b \max|z_b'|` [kg m/rad] and :math:`\sum_b m_b\max|z_b''|`
        [kg m/rad^2] over the angles given (the constant-speed rung's error bound).
    points, rotors : int
        How many point masses and rotors the sums hold.
    """

    theta: FloatArray
    inertia: FloatArray
    inertia_slope: FloatArray
    cylinder_inertia: FloatArray
    force_rate: ComplexArray
    force_curvature: ComplexArray
    moment_rate: ComplexArray
    moment_curvature: ComplexArray
    roll_rate: FloatArray
    roll_curvature: FloatArray
    force_size: FloatArray
    moment_size: FloatArray
    roll_size: FloatArray
    piston_rate: FloatArray
    velocity_reach: float
    acceleration_reach: float
    points: int
    rotors: int

    def force(self, speed: ArrayLike, acceleration: ArrayLike) -> ComplexArray:
        r"""The shaking force on the block [N] at crank speed ``speed`` [rad/s] and
        acceleration ``acceleration`` [rad/s^2] (each a number or one per angle)."""
        w = np.asarray(speed, dtype=np.float64)
        return np.asarray(
            -(w * w * self.force_curvature + np.asarray(acceleration) * self.force_rate)
        )

    def moment(self, speed: ArrayLike, acceleration: ArrayLike) -> ComplexArray:
        """The shaking moment about ``reference_z`` [N m], drawn along the force
        (docs/conventions.md)."""
        w = np.asarray(speed, dtype=np.float64)
        return np.asarray(
            -(w * w * self.moment_curvature + np.asarray(acceleration) * self.moment_rate)
        )

    def inertia_roll(self, speed: ArrayLike, acceleration: ArrayLike) -> FloatArray:
        """The roll torque the moving bodies put on the block [N m] (without the gas)."""
        w = np.asarray(speed, dtype=np.float64)
        return np.asarray(w * w * self.roll_curvature + np.asarray(acceleration) * self.roll_rate)


def _turn(angle: ArrayLike) -> ComplexArray:
    return np.asarray(np.exp(1j * np.asarray(angle, dtype=np.float64)))


def crank_train(engine: Engine, theta_deg: ArrayLike) -> CrankTrain:
    r"""The bodies of an engine's crank train at crank angles ``theta_deg``.

    Parameters
    ----------
    engine : Engine
        The engine (plain, offset and link cylinders).
    theta_deg : array_like
        Crank angles :math:`\theta` [deg], shape (N,).

    Returns
    -------
    CrankTrain

    Notes
    -----
    Cylinder i, at :math:`\beta_i = \theta + \varphi_i - \psi_i` from its TDC direction:
    its reciprocating mass at :math:`z = e^{i\psi_i}(s_i + ie_i)` (:math:`s_i` the exact
    slider, :func:`balance.core.kinematics.normalised_slider`), its rotating mass at
    :math:`r e^{i(\theta + \varphi_i)}`, its rod's :math:`\Delta I` at
    :math:`\Gamma = \psi_i - \gamma_i` (:math:`\sin\gamma = (r\sin\beta - e)/l`).  A link
    cylinder (docs/theory.md, link rods) has its link piston's :math:`s` and its link rod's
    angle (:func:`balance.core.links.link_motion`), and its rotating mass is split: the link
    rod's link-pin share (:func:`balance.core.links.pin_masses`) at the link pin
    :math:`r e^{i\psi_j}\Lambda`, the rest on the crank pin.
    """
    th_deg = np.asarray(theta_deg, dtype=np.float64)
    theta = np.radians(th_deg)
    n = engine.n_cylinders
    throw_deg = np.degrees(engine.throw)[:, None]
    bank_deg = np.degrees(engine.bank)[:, None]
    beta = np.radians(np.mod(th_deg[None, :] + throw_deg - bank_deg, 360.0))
    r = engine.crank_radius[:, None]
    e = engine.offset[:, None]
    _, ds, d2s = normalised_slider(
        beta, rod_ratio(r, engine.conrod_length[:, None]), offset_ratio(e, r)
    )
    dg, d2g = conrod_angle_derivatives(
        beta, rod_ratio(r, engine.conrod_length[:, None]), offset_ratio(e, r)
    )
    crank_mass = np.array(engine.rotating_mass, dtype=np.float64)
    pin_mass = np.zeros(n)
    motion = None
    if engine.has_links:
        from balance.core.links import engine_geometry, link_motion, pin_masses

        geometry = engine_geometry(engine)
        j = geometry.cylinder
        motion = link_motion(beta[j], *geometry.columns())
        ds, d2s, dg, d2g = (np.array(a, copy=True) for a in (ds, d2s, dg, d2g))
        ds[j], d2s[j], dg[j], d2g[j] = motion.ds, motion.d2s, motion.drod, motion.d2rod
        pin_mass = pin_masses(engine)
        crank_mass = crank_mass - pin_mass
    # the pistons: along the bore e^{i psi} (s' and s'' in metres), across it by the offset
    along = _turn(engine.bank)[:, None]
    piston_rate = r * ds
    piston_curve = r * d2s
    m_rec = engine.reciprocating_mass[:, None]
    lever = (engine.z - engine.reference_z)[:, None]
    # the crank pins: r e^{i(theta + phi)}, z' = i z, z'' = -z
    crank = r * _turn(theta[None, :] + engine.throw[:, None])
    m_crank = crank_mass[:, None]
    delta_i = engine.conrod_inertia_correction[:, None]
    # rotors turn through Gamma = psi - gamma: Gamma' = -gamma', Gamma'' = -gamma''
    g1 = -dg
    g2 = -d2g
    rec_rate = m_rec * piston_rate
    rec_curve = m_rec * piston_curve
    inertia_terms = rec_rate * piston_rate + m_crank * r**2 + delta_i * g1**2
    slope_terms = 2.0 * (rec_rate * piston_curve + delta_i * g1 * g2)
    rate_terms = along * rec_rate + 1j * m_crank * crank
    curve_terms = along * rec_curve - m_crank * crank
    # roll: a piston gives m s''(s' + e) w^2 and m s'(s' + e) w-dot; a mass on the crank pin
    # nothing; a link pin m [Re(conj z' a) - Im(conj z a)]; a rotor dI Gamma-dd (Gamma' - 1)
    roll_rate_terms = rec_rate * (piston_rate + e) + delta_i * g1 * (g1 - 1.0)
    roll_curve_terms = rec_curve * (piston_rate + e) + delta_i * g2 * (g1 - 1.0)
    size_1 = np.abs(rec_rate) + np.abs(m_crank) * r
    size_2 = np.abs(rec_curve) + np.abs(m_crank) * r
    velocity_reach = float(
        np.sum(np.max(np.abs(rec_rate), axis=1, initial=0.0))
        + np.sum(np.abs(crank_mass) * engine.crank_radius)
    )
    acceleration_reach = float(
        np.sum(np.max(np.abs(rec_curve), axis=1, initial=0.0))
        + np.sum(np.abs(crank_mass) * engine.crank_radius)
    )
    if motion is not None:  # the link rods' link-pin shares, on their link pins
        j = geometry.cylinder
        m_pin = pin_mass[j][:, None]
        bore = _turn(engine.bank[j])[:, None] * r[j]
        place = bore * (motion.pin_y + 1j * motion.pin_x)
        rate = bore * (motion.dpin_y + 1j * motion.dpin_x)
        curve = bore * (motion.d2pin_y + 1j * motion.d2pin_x)
        power = np.real(np.conj(rate) * curve)
        inertia_terms[j] += m_pin * np.abs(rate) ** 2
        slope_terms[j] += 2.0 * m_pin * power
        rate_terms[j] += m_pin * rate
        curve_terms[j] += m_pin * curve
        roll_rate_terms[j] += m_pin * (np.abs(rate) ** 2 - np.imag(np.conj(place) * rate))
        roll_curve_terms[j] += m_pin * (power - np.imag(np.conj(place) * curve))
        size_1[j] += np.abs(m_pin * rate)
        size_2[j] += np.abs(m_pin * curve)
        velocity_reach += float(np.sum(np.max(np.abs(m_pin * rate), axis=1, initial=0.0)))
        acceleration_reach += float(np.sum(np.max(np.abs(m_pin * curve), axis=1, initial=0.0)))
    inertia = np.sum(inertia_terms, axis=0)
    slope = np.sum(slope_terms, axis=0)
    points = 2 * n + int(np.count_nonzero(pin_mass))
    rotors = int(np.count_nonzero(engine.conrod_inertia_correction))
    return CrankTrain(
        theta=theta,
        inertia=np.asarray(inertia, dtype=np.float64),
        inertia_slope=np.asarray(slope, dtype=np.float64),
        cylinder_inertia=np.asarray(inertia_terms, dtype=np.float64),
        force_rate=np.sum(rate_terms, axis=0),
        force_curvature=np.sum(curve_terms, axis=0),
        moment_rate=np.sum(lever * rate_terms, axis=0),
        moment_curvature=np.sum(lever * curve_terms, axis=0),
        roll_rate=np.sum(roll_rate_terms, axis=0),
        roll_curvature=np.sum(roll_curve_terms, axis=0),
        force_size=np.stack([np.sum(size_1, axis=0), np.sum(size_2, axis=0)]),
        moment_size=np.stack(
            [np.sum(np.abs(lever) * size_1, axis=0), np.sum(np.abs(lever) * size_2, axis=0)]
        ),
        roll_size=np.stack(
            [np.sum(np.abs(roll_rate_terms), axis=0), np.sum(np.abs(roll_curve_terms), axis=0)]
        ),
        piston_rate=np.asarray(piston_rate, dtype=np.float64),
        velocity_reach=velocity_reach,
        acceleration_reach=acceleration_reach,
        points=points,
        rotors=rotors,
    )


# --------------------------------------------------------------------------- loads


@dataclass(frozen=True)
class ConstantTorque:
    """A load of constant torque [N m] (the mean load: the cycle mean of the gas torque)."""

    torque: float

    def at(self, speed: FloatArray) -> FloatArray:
        """The load torque [N m] at crank speeds ``speed`` [rad/s]."""
        return np.full(np.shape(speed), self.torque)


@dataclass(frozen=True)
class Propeller:
    r"""A load :math:`T_L = c\,\omega^2` whose coefficient :math:`c` [N m s^2] is found so
    that the mean speed is the one asked for."""

    def at(self, speed: FloatArray, coefficient: float) -> FloatArray:
        """The load torque [N m] at crank speeds ``speed`` [rad/s]."""
        return np.asarray(coefficient * speed * speed)


@dataclass(frozen=True)
class PowerLaw:
    r"""A load :math:`T_L = T_0(\omega/\omega_0)^n` [N m], :math:`T_0 > 0`,
    :math:`\omega_0 > 0` [rad/s], :math:`n > 0`."""

    torque: float
    speed: float
    exponent: float

    def at(self, speed: FloatArray) -> FloatArray:
        """The load torque [N m] at crank speeds ``speed`` [rad/s]."""
        return np.asarray(self.torque * (np.asarray(speed) / self.speed) ** self.exponent)


# --------------------------------------------------------------------------- steady state


@dataclass(frozen=True, eq=False)
class Motion:
    r"""The periodic motion of the crank train over one cycle, on the cycle's grid.

    Attributes
    ----------
    speed, acceleration : ndarray
        :math:`\omega(\theta)` [rad/s] and :math:`\dot\omega(\theta)` [rad/s^2].
    load_torque : ndarray
        :math:`T_L(\omega(\theta))` [N m].
    time : ndarray
        :math:`t(\theta)` [s] from :math:`\theta = 0`.
    period : float
        Time of one cycle [s].
    mean_speed : float
        Cycle angle over cycle time [rad/s].
    coefficient : float
        The propeller load's :math:`c` [N m s^2] (NaN for the other loads).
    """

    speed: FloatArray
    acceleration: FloatArray
    load_torque: FloatArray
    time: FloatArray
    period: float
    mean_speed: float
    coefficient: float = math.nan

    @property
    def speed_fluctuation(self) -> float:
        r""":math:`\delta = (\omega_{max} - \omega_{min})/\omega_{mean}` [1]."""
        return float((self.speed.max() - self.speed.min()) / self.mean_speed)


def periodic_integral(values: FloatArray, cycle: float) -> tuple[float, FloatArray]:
    r"""The integral :math:`\int_0^\theta f\,\mathrm d\theta` of samples on the periodic
    grid of N angles over ``cycle`` [rad], as its mean slope and its periodic part.

    Parameters
    ----------
    values : ndarray
        :math:`f` at :math:`\theta_j = j\,\Theta/N` (any unit u).
    cycle : float
        The period :math:`\Theta` [rad].

    Returns
    -------
    mean : float
        The mean of :math:`f`.
    periodic : ndarray
        :math:`\int_0^\theta (f - \bar f)\,\mathrm d\theta` at the grid's angles.

    Notes
    -----
    Term by term of the discrete Fourier series of the samples: exact for a trigonometric
    polynomial of degree below N/2, spectrally accurate for a smooth periodic function.
    """
    n = values.size
    spectrum = np.fft.rfft(values) / n
    m = np.arange(spectrum.size) * (2.0 * math.pi / cycle)
    integral = np.zeros_like(spectrum)
    integral[1:] = spectrum[1:] / (1j * m[1:])
    if n % 2 == 0:
        integral[-1] = 0.0  # the Nyquist term integrates to a sine through every sample
    periodic = np.fft.irfft(integral * n, n=n)
    return float(spectrum[0].real), np.asarray(periodic - periodic[0])


def periodic_linear(beta: FloatArray, forcing: FloatArray, cycle: float) -> FloatArray:
    r"""The periodic solution of :math:`E' + \beta(\theta)E = q(\theta)` over ``cycle``,
    :math:`\bar\beta > 0`.

    Parameters
    ----------
    beta, forcing : ndarray
        :math:`\beta` [1/rad] and :math:`q` on the periodic grid.
    cycle : float
        The period [rad].

    Returns
    -------
    ndarray
        :math:`E` on the grid.

    Notes
    -----
    With :math:`\tilde B` the periodic part of :math:`\int\beta` (:func:`periodic_integral`)
    and :math:`E = e^{-\tilde B}u`, :math:`u' + \bar\beta u = q\,e^{\tilde B}`, whose
    periodic solution has the Fourier coefficients :math:`\hat u_m = \hat g_m/(\bar\beta +
    im)`: the closed form of the variation-of-constants integral, term by term.
    """
    n = beta.size
    mean, periodic = periodic_integral(beta, cycle)
    if not mean > 0.0:
        raise AnalysisError("the load does not grow with the speed: no periodic solution")
    spectrum = np.fft.rfft(forcing * np.exp(periodic)) / n
    m = np.arange(spectrum.size) * (2.0 * math.pi / cycle)
    u = np.fft.irfft(spectrum / (mean + 1j * m) * n, n=n)
    energy = np.exp(-periodic) * u
    if not np.all(np.isfinite(energy)):
        raise AnalysisError("the load's steady state cannot be formed in double precision")
    return np.asarray(energy)


def _speed_of(energy: FloatArray, inertia: FloatArray) -> FloatArray:
    r""":math:`\omega = \sqrt{2E/J}` (NaN where the energy is not positive)."""
    with np.errstate(invalid="ignore"):
        return np.asarray(np.sqrt(np.where(energy > 0.0, 2.0 * energy / inertia, np.nan)))


def _mean_speed(speed: FloatArray) -> float:
    """Cycle angle over cycle time: the harmonic mean of the speed over the grid; 0 when the
    crank stops somewhere (a speed that is not positive)."""
    if not np.all(speed > 0.0):
        return 0.0
    return float(1.0 / np.mean(1.0 / speed))


def find_root(
    f: Callable[[float], float],
    low: float,
    high: float,
    f_low: float,
    f_high: float,
    *,
    xtol: float = 0.0,
    rtol: float = 4.0 * np.finfo(float).eps,
    steps: int = 200,
) -> float:
    """A root of ``f`` in ``[low, high]`` where ``f_low`` and ``f_high`` differ in sign:
    Brent's method (inverse quadratic interpolation, secant and bisection).

    Parameters
    ----------
    f : callable
        The function (any units).
    low, high : float
        The bracket, in the units of the argument.
    f_low, f_high : float
        ``f(low)`` and ``f(high)``, of opposite signs (or one of them 0).
    xtol, rtol : float
        Absolute and relative tolerance of the root.
    steps : int
        Most evaluations of ``f``.

    Returns
    -------
    float
        The root, within ``xtol/2 + 2 rtol |x|``.

    Raises
    ------
    AnalysisError
        When ``f_low`` and ``f_high`` have the same sign.

    References
    ----------
    Brent, *Algorithms for Minimization without Derivatives*, Prentice-Hall 1973, ch. 4.
    """
    a, b, fa, fb = low, high, f_low, f_high
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0) == (fb > 0):
        raise AnalysisError("no sign change in the bracket: the root cannot be found")
    c, fc = a, fa
    d = e = b - a
    for _ in range(steps):
        if (fb > 0) == (fc > 0):
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 2.0 * rtol * abs(b) + 0.5 * xtol
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:
                p, q = 2.0 * m * s, 1.0 - s
            else:
                q, r = fa / fc, fb / fc
                p = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0:
                q = -q
            else:
                p = -p
            if 2.0 * p < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = m
        else:
            d = e = m
        a, fa = b, fb
        b = b + (d if abs(d) > tol else math.copysign(tol, m))
        fb = f(b)
    return b


def _constant_load(inertia: FloatArray, work: FloatArray, mean_speed: float) -> FloatArray:
    r"""The energy :math:`E = K + E_b` (K the excess work above its least value) whose
    time-mean speed is ``mean_speed``: Newton's method on :math:`E_b`, from below (the
    cycle time :math:`\oint\sqrt{J/2E}\,\mathrm d\theta` is convex and falling in
    :math:`E_b`, so the steps from below stay below and converge)."""
    excess = work - work.min()
    half_j = 0.5 * inertia
    target = 1.0 / mean_speed

    def slowness(base: float) -> tuple[float, float]:
        root = np.sqrt(half_j / (excess + base))
        return float(np.mean(root)) - target, float(-0.5 * np.mean(root / (excess + base)))

    base = float(np.mean(half_j)) * mean_speed * mean_speed
    value, slope = slowness(base)
    while value < 0.0:  # start below the root (too little energy, too slow)
        base *= 0.25
        value, slope = slowness(base)
    for _ in range(200):
        step = -value / slope
        base += step
        value, slope = slowness(base)
        if abs(step) <= 4.0 * np.finfo(float).eps * base:
            break
    return np.asarray(excess + base)


def _propeller(
    inertia: FloatArray, torque: FloatArray, cycle: float, mean_speed: float
) -> tuple[FloatArray, float]:
    """The energy and the coefficient c of the propeller load whose mean speed is
    ``mean_speed`` (:math:`T_L = (2c/J)E`, :func:`periodic_linear` for each c; Brent's
    method on log c)."""

    def energy(log_c: float) -> FloatArray:
        return periodic_linear(2.0 * math.exp(log_c) / inertia, torque, cycle)

    def gap(log_c: float) -> float:
        speed = _mean_speed(_speed_of(energy(log_c), inertia))
        return math.log(max(speed, 1e-300)) - math.log(mean_speed)

    guess = math.log(max(float(np.mean(torque)), 1e-300) / (mean_speed * mean_speed))
    low = high = guess
    f_low = f_high = gap(guess)
    while f_low < 0.0:  # too slow: less load
        low -= math.log(2.0)
        f_low = gap(low)
    while f_high > 0.0:  # too fast: more load
        high += math.log(2.0)
        f_high = gap(high)
    if low == high:
        return energy(low), math.exp(low)
    log_c = find_root(gap, low, high, f_low, f_high, rtol=1e-15)
    return energy(log_c), math.exp(log_c)


def _power_law(inertia: FloatArray, torque: FloatArray, cycle: float, load: PowerLaw) -> FloatArray:
    r"""The periodic energy under :math:`T_L = T_0(\omega/\omega_0)^n`: Newton's method on
    the whole cycle, each step the linearised load :math:`T_L(E_k) + T_L'(E_k)(E - E_k)`
    solved in closed form (:func:`periodic_linear`), from the constant-speed estimate
    (the speed at which the load is the mean torque).  Converged when a full step changes
    the energy by less than :data:`NEWTON_TOLERANCE` of its largest value, or by less than
    :data:`NEWTON_FLOOR` and no less than half the step before (the rounding floor:
    Newton's steps shrink quadratically until then)."""
    mean_torque = float(np.mean(torque))
    speed = load.speed * (mean_torque / load.torque) ** (1.0 / load.exponent)
    _, work = periodic_integral(torque - mean_torque, cycle)
    energy = 0.5 * inertia * speed * speed + work - float(np.mean(work))
    floor = 0.5 * float(np.min(inertia)) * speed * speed * 1e-6
    energy = np.maximum(energy, floor)
    scale = 2.0 / (inertia * load.speed * load.speed)

    def load_of(e: FloatArray) -> tuple[FloatArray, FloatArray]:
        value = load.torque * (scale * e) ** (0.5 * load.exponent)
        return value, 0.5 * load.exponent * value / e

    last = math.inf
    for _ in range(NEWTON_STEPS):
        value, slope = load_of(energy)
        new = periodic_linear(slope, torque - value + slope * energy, cycle)
        change = new - energy
        factor = 1.0
        while np.any(energy + factor * change <= 0.0):
            factor *= 0.5
            if factor < 1e-12:
                raise AnalysisError("the power-law load's steady state was not found")
        energy = energy + factor * change
        size = float(np.max(np.abs(change)) / np.max(energy))
        if factor == 1.0 and (size <= NEWTON_TOLERANCE or NEWTON_FLOOR >= size >= 0.5 * last):
            return np.asarray(energy)
        last = size if factor == 1.0 else math.inf
    raise AnalysisError("the power-law load's steady state did not converge")


def time_over_cycle(speed: FloatArray, cycle: float) -> tuple[FloatArray, float]:
    r"""The time since :math:`\theta = 0` over one cycle, and the cycle's period.

    Parameters
    ----------
    speed : ndarray
        :math:`\omega > 0` [rad/s] on the periodic grid.
    cycle : float
        The cycle angle :math:`\Theta` [rad].

    Returns
    -------
    time : ndarray
        :math:`t(\theta) = \int_0^\theta \mathrm d\theta/\omega` [s]
        (:func:`periodic_integral` of :math:`1/\omega`).
    period : float
        :math:`\oint \mathrm d\theta/\omega` [s].
    """
    mean, periodic = periodic_integral(1.0 / speed, cycle)
    theta = cycle * np.arange(speed.size) / speed.size
    return np.asarray(mean * theta + periodic), mean * cycle


def periodic_motion(
    inertia: FloatArray,
    inertia_slope: FloatArray,
    torque: FloatArray,
    cycle: float,
    load: ConstantTorque | Propeller | PowerLaw,
    mean_speed: float | None = None,
) -> Motion:
    r"""The periodic steady state of :math:`J\dot\omega + \tfrac12 J'\omega^2 = Q - T_L`.

    Parameters
    ----------
    inertia, inertia_slope : ndarray
        :math:`J(\theta) > 0` [kg m^2] and :math:`J'(\theta)` [kg m^2/rad] on the periodic
        grid of N crank angles :math:`\theta_j = j\,\Theta/N`.
    torque : ndarray
        :math:`Q(\theta)` [N m] on the grid.
    cycle : float
        :math:`\Theta` [rad]: :math:`4\pi` four-stroke, :math:`2\pi` two-stroke.
    load : ConstantTorque, Propeller or PowerLaw
        The load.  A constant torque must be the mean of ``torque`` (the caller checks
        it: otherwise there is no periodic solution).
    mean_speed : float, optional
        The time-mean speed [rad/s] (cycle angle over cycle time); needed for a constant
        torque and a propeller, not used for a power law (whose load sets it).

    Returns
    -------
    Motion

    Notes
    -----
    :math:`E = \tfrac12 J\omega^2` obeys :math:`\mathrm dE/\mathrm d\theta = Q - T_L`.
    A constant torque: :math:`E = W + E_b`, :math:`W` the excess work
    (:func:`periodic_integral`), and :math:`E_b` is found by Newton's method so that the
    time-mean speed is ``mean_speed``.  A propeller, :math:`T_L = c\omega^2 = (2c/J)E`: the
    equation is linear and its periodic solution closed in form for each c
    (:func:`periodic_linear`); c is found by Brent's method.  A power law: Newton's method
    over the whole cycle, each step linear.  Then :math:`\omega = \sqrt{2E/J}` and, from
    the equation of motion, :math:`\dot\omega = (Q - T_L - \tfrac12 J'\omega^2)/J`.  The
    integrals are taken term by term of the samples' discrete Fourier series: exact for a
    torque and an inertia that are trigonometric polynomials of degree below N/2.
    """
    coefficient = math.nan
    if isinstance(load, ConstantTorque):
        assert mean_speed is not None
        _, work = periodic_integral(torque - load.torque, cycle)
        energy = _constant_load(inertia, work, mean_speed)
    elif isinstance(load, Propeller):
        assert mean_speed is not None
        energy, coefficient = _propeller(inertia, torque, cycle, mean_speed)
    else:
        energy = _power_law(inertia, torque, cycle, load)
    speed = _speed_of(energy, inertia)
    if not np.all(speed > 0.0):
        raise AnalysisError("the crank stops within the cycle: there is no steady state")
    load_torque = load.at(speed, coefficient) if isinstance(load, Propeller) else load.at(speed)
    acceleration = (torque - load_torque - 0.5 * inertia_slope * speed * speed) / inertia
    time, period = time_over_cycle(speed, cycle)
    return Motion(
        speed=speed,
        acceleration=np.asarray(acceleration),
        load_torque=np.asarray(load_torque, dtype=np.float64),
        time=time,
        period=period,
        mean_speed=cycle / period,
        coefficient=coefficient,
    )


# --------------------------------------------------------------------------- orders in time


def orders_in_time(
    values: ArrayLike,
    motion_speed: FloatArray,
    time: FloatArray,
    period: float,
    orders: ArrayLike,
    cycle: float,
) -> tuple[ComplexArray, ComplexArray]:
    r"""Forward and backward phasors of a signal over the cycle, taken in time.

    Parameters
    ----------
    values : array_like
        The signal on the cycle's grid, shape (..., N) (complex: a force in the transverse
        plane; real: a torque).
    motion_speed, time : ndarray
        :math:`\omega` [rad/s] and :math:`t` [s] on the grid.
    period : float
        The cycle's period T [s].
    orders : array_like
        The orders k (multiples of the mean speed; halves for a four-stroke).
    cycle : float
        The cycle angle :math:`\Theta` [rad].

    Returns
    -------
    forward, backward : ndarray of complex
        :math:`P_k^{\pm} = \frac1T\oint F(t)\,e^{\mp ik\bar\theta(t)}\,\mathrm dt`, shape
        (..., K), with :math:`\bar\theta = \omega_m t + \langle\theta - \omega_m t\rangle`
        the mean crank angle (:math:`\omega_m = \Theta/T`); the integral is the
        trapezoidal rule in :math:`\theta` with :math:`\mathrm dt = \mathrm d\theta/\omega`
        (at constant speed, the discrete Fourier transform of the samples).
        A real signal's amplitude phasor is :math:`2P_k^+`.  At constant speed these are
        the phasors of docs/conventions.md.
    """
    n = motion_speed.size
    k = np.asarray(orders, dtype=np.float64)
    bins = k * cycle / (2.0 * math.pi)
    whole = np.all(np.abs(bins - np.round(bins)) <= 1e-9)
    if np.all(motion_speed == motion_speed[0]) and whole:
        # constant speed: the mean crank angle is the crank angle, and the sums are the
        # discrete Fourier transform of the samples
        spectrum = np.fft.fft(np.asarray(values), axis=-1) / n
        index = np.round(bins).astype(np.intp)
        return np.asarray(spectrum[..., index % n]), np.asarray(spectrum[..., (-index) % n])
    step = cycle / n
    weight = step / motion_speed / period
    theta = cycle * np.arange(n) / n
    mean_speed = cycle / period
    shift = float(np.sum(weight * (theta - mean_speed * time)))
    mean_angle = mean_speed * time + shift
    angle = k[:, None] * mean_angle[None, :]
    weighted = (np.asarray(values) * weight)[..., None, :]
    # summed along the angles by numpy's pairwise sum: the same bits on every machine
    # (a BLAS product's order of summation depends on its threads)
    cosine = np.sum(weighted * np.cos(angle), axis=-1)
    sine = np.sum(weighted * np.sin(angle), axis=-1)
    return np.asarray(cosine - 1j * sine), np.asarray(cosine + 1j * sine)
