r"""What the cylinders put into a torsional model of the crank train: inertia and excitation.

Two things come from the cylinders (docs/torsion.md):

- the **mean inertia of the moving parts** of each cylinder (piston group and rod), added
  to a mass given by its ``crank_inertia``: the mean over a revolution of their kinetic
  energy at constant speed divided by :math:`\omega^2/2`,

  .. math::

      J_c = m_{big} r^2 + m_{rec}\langle s'^2\rangle + \Delta I\,\langle\psi'^2\rangle
          = m_{big} r^2 + m_{rec} r^2\left(\tfrac12 + \tfrac{\lambda^2}{8}
            + \tfrac{\lambda^4}{16} + \dots\right) + \Delta I\left(\tfrac{\lambda^2}{2}
            + \dots\right)

  (series without offset) with the exact kinematics of
  :mod:`balance.core.kinematics` (offsets) and :mod:`balance.core.links` (link rods: the
  link rod's lower end moves on the master rod's link pin, :math:`m_{pin} r^2
  \langle|\Lambda'|^2\rangle`);
- the **excitation**: each cylinder's tangential torque on its crank pin over the working
  cycle, as computed for the gas torque (:func:`balance.core.torque.compute_torque`), split
  into the moving parts' part (the same computation with no gas force; it scales with the
  speed squared) and the gas part (the rest; the pressure trace or model holds at every
  speed), each analysed into orders in the cylinder's own angle :math:`\alpha` from its
  firing TDC: :math:`M(\alpha) = M_0 + \sum_k a_k\cos(k\alpha + \varphi_k)`.  A cylinder
  firing at crank angle :math:`\theta_c` puts :math:`M(\theta - \theta_c)` on its mass: its
  order k lags by :math:`k\theta_c`.

The orders (halves for a four-stroke) and speeds of a torsional analysis are checked here
too (:func:`order_problem`, :func:`speed_problem`).

.. rubric:: References

W. K. Wilson, *Practical Solution of Torsional Vibration Problems*, vol. 1, 3rd ed., Chapman
& Hall 1956, ch. on the equivalent inertia of the reciprocating parts and the harmonic
analysis of the turning moment; N. Nestorides, *A Handbook on Torsional Vibration*,
B.I.C.E.R.A., Cambridge University Press 1958 (harmonic components of the tangential
pressure, the moving parts' inertia); Den Hartog, *Mechanical Vibrations*, 4th ed. 1956,
ch. 5 (multicylinder engines).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.crank_motion import crank_train
from balance.core.engine import Engine
from balance.core.gas import GasInput, cycle_degrees, firing_tdc
from balance.core.speed import speed_squared

__all__ = [
    "INERTIA_SAMPLES",
    "MAX_ORDER",
    "Excitation",
    "default_orders",
    "default_speeds",
    "excitation",
    "harmonic_numbers",
    "instantaneous_inertia",
    "major_orders",
    "moving_parts_inertia",
    "order_problem",
    "place_firing_tdc",
    "speed_problem",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Crank angles per revolution over which the moving parts' kinetic energy is averaged
#: (the trapezoidal rule on a periodic analytic function: the error falls geometrically
#: and is at rounding long before this).
INERTIA_SAMPLES = 256
#: Highest order of the default orders.
MAX_ORDER = 12
#: Default speeds: this many, from the first to the second fraction of the layout's speed.
DEFAULT_SPEEDS = (0.2, 1.2, 200)


# --------------------------------------------------------------------------- orders, speeds


def default_orders(cycle: str) -> FloatArray:
    """The default orders: every half order from 0.5 to 12 for a four-stroke, 1 to 12 for a
    two-stroke.

    Parameters
    ----------
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle (anything but ``"four-stroke"`` has whole orders only).

    Returns
    -------
    ndarray, shape (K,)
        The orders [multiples of the crank speed], rising, up to :data:`MAX_ORDER`.
    """
    step = 0.5 if cycle == "four-stroke" else 1.0
    return np.asarray(np.arange(1, round(MAX_ORDER / step) + 1) * step, dtype=np.float64)


def default_speeds(speed: float) -> FloatArray:
    """The default speeds [rad/s]: 200 from 20 % to 120 % of ``speed`` [rad/s].

    Parameters
    ----------
    speed : float
        The engine's speed [rad/s].

    Returns
    -------
    ndarray, shape (200,)
        Crank speeds [rad/s], evenly spaced, both ends included (:data:`DEFAULT_SPEEDS`).
    """
    low, high, count = DEFAULT_SPEEDS
    return np.linspace(low * speed, high * speed, count)


def order_problem(orders: ArrayLike, cycle: str) -> str | None:
    """What is wrong with the orders of a torsional analysis (None when nothing is).

    Orders must be positive multiples of 0.5, given once each; a two-stroke (whose cycle is
    one revolution) has whole orders only.

    Parameters
    ----------
    orders : array_like
        The orders [multiples of the crank speed] (flattened).
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle.

    Returns
    -------
    str or None
        The first problem found, one line (none given; one not finite or not above zero;
        one not a multiple of 0.5; a half order on a two-stroke; one given twice), or None
        when the orders can be analysed.
    """
    k = np.asarray(orders, dtype=np.float64).reshape(-1)
    if k.size == 0:
        return "no orders: give at least one (e.g. '0.5-12')"
    if not np.all(np.isfinite(k)) or np.any(k <= 0):
        return "orders must be positive"
    twice = 2.0 * k
    if np.any(twice != np.round(twice)):
        bad = k[twice != np.round(twice)][0]
        return f"order {bad:g} is not a multiple of 0.5"
    if cycle == "two-stroke" and np.any(k != np.round(k)):
        bad = k[k != np.round(k)][0]
        return f"order {bad:g}: a two-stroke fires every revolution, so it has whole orders only"
    if np.unique(k).size != k.size:
        return "an order is given twice"
    return None


def speed_problem(speeds: ArrayLike) -> str | None:
    """What is wrong with the speeds [rad/s] of a torsional analysis (None when nothing is):
    at least one, each finite and above zero.

    Parameters
    ----------
    speeds : array_like
        Crank speeds [rad/s] (flattened).

    Returns
    -------
    str or None
        The problem, one line (none given, or one not finite or not above zero), or None
        when the speeds can be analysed.
    """
    w = np.asarray(speeds, dtype=np.float64).reshape(-1)
    if w.size == 0:
        return "no speeds: give at least one"
    if not np.all(np.isfinite(w)) or np.any(w <= 0):
        return "a speed must be above zero"
    return None


def harmonic_numbers(orders: ArrayLike, cycle: str) -> NDArray[np.intp]:
    """Each order as the number of its periods in one working cycle (2k for a four-stroke,
    k for a two-stroke).

    Parameters
    ----------
    orders : array_like
        The orders [multiples of the crank speed] (multiples of 0.5; whole for a
        two-stroke: :func:`order_problem`).
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle.

    Returns
    -------
    ndarray of int, shape of ``orders``
        The harmonic numbers [periods per cycle], rounded to the nearest whole number: the
        index of each order in a spectrum over one working cycle.
    """
    per_cycle = cycle_degrees(cycle) / 360.0
    return np.asarray(np.round(np.asarray(orders, dtype=np.float64) * per_cycle), dtype=np.intp)


def major_orders(firing: ArrayLike, orders: ArrayLike) -> NDArray[np.bool_]:
    r"""Which orders are *major*: every cylinder's order-k excitation in phase,
    :math:`k\theta_c` equal modulo 360 deg for all cylinders (for an even-firing engine of z
    firings a cycle, the multiples of :math:`z \cdot 360/\text{cycle}`).

    Parameters
    ----------
    firing : array_like, shape (c,)
        Crank angle :math:`\theta_c` of each cylinder's firing TDC [deg]
        (:func:`place_firing_tdc`).
    orders : array_like, shape (K,)
        The orders [multiples of the crank speed].

    Returns
    -------
    ndarray of bool, shape (K,)
        True where :math:`|\sum_c e^{-ik\theta_c}|` reaches the number of cylinders (to a
        relative 1e-9); all False without cylinders.
    """
    theta = np.radians(np.asarray(firing, dtype=np.float64))
    k = np.asarray(orders, dtype=np.float64)
    if theta.size == 0:
        return np.zeros(k.shape, dtype=bool)
    total = np.abs(np.sum(np.exp(-1j * k[:, None] * theta[None, :]), axis=1))
    return np.asarray(total >= theta.size * (1.0 - 1e-9))


# --------------------------------------------------------------------------- firing TDCs


def place_firing_tdc(
    engine: Engine, tdc_given: list[float | None] | None = None
) -> FloatArray | str:
    """Crank angle of each cylinder's firing TDC [deg], or what is missing to place them.

    The engine's own with a ``gas:`` section; otherwise placed as the gas section would
    place them (:func:`balance.core.gas.firing_tdc`, at the actual TDC: offsets and link
    rods shift it): from the firing order, or from every cylinder's nominal ``tdc`` angle
    when the layout gives them (``tdc_given``, [deg]; only the layout reader knows them).

    Parameters
    ----------
    engine : Engine
        The engine.
    tdc_given : list of float or None, optional
        Each cylinder's ``tdc`` as written in the layout [deg], None where not given.

    Returns
    -------
    ndarray or str
        Angles in [0, cycle) [deg]; a string (the problem, one line) when they cannot be
        placed (a four-stroke without a firing order, or one that does not fit the throws).
    """
    if engine.gas is not None:
        return np.asarray(engine.gas.firing_tdc, dtype=np.float64)
    from balance.core.cylinders import dead_centre_lag

    lag = dead_centre_lag(
        engine.crank_radius, engine.conrod_length, engine.offset, engine.bank, engine.links
    )
    placed = firing_tdc(
        np.degrees(engine.throw),
        np.degrees(engine.bank),
        engine.cycle,
        engine.firing_order,
        tdc_given,
        tdc_lag=np.degrees(lag),
    )
    if isinstance(placed, str):
        return placed.replace("with gas forces", "with a torsion section")
    return placed


# --------------------------------------------------------------------------- inertia


def _crank_share(engine: Engine) -> FloatArray:
    """Each cylinder's share of its throw's ``crank_unbalance`` [kg] (0 with lumped
    masses): part of ``rotating_mass`` that belongs to the crank, not to the rod."""
    parts = engine.mass_parts
    if parts is None:
        return np.zeros(engine.n_cylinders)
    return np.asarray(np.nan_to_num(parts.crank_unbalance) / parts.rods_per_throw)


def instantaneous_inertia(engine: Engine, theta: ArrayLike) -> FloatArray:
    r"""Twice the kinetic energy of each cylinder's piston group and rod at constant speed,
    per :math:`\omega^2`, at crank angles ``theta`` [kg m^2].

    Parameters
    ----------
    engine : Engine
        The engine (masses by part for a meaningful big-end mass: lumped ``rotating``
        masses hold the crank's own unbalance too).
    theta : array_like, shape (N,)
        Crank angles :math:`\theta` [rad].

    Returns
    -------
    ndarray, shape (cylinders, N)
        :math:`m_{big} r^2 + m_{rec} s'^2 + \Delta I\,\psi'^2` (a link cylinder:
        :math:`m_{pin} r^2 |\Lambda'|^2 + m_{rec} s'^2 + \Delta I\,\psi_l'^2`), with
        :math:`m_{big}` the rod's big-end share (``rotating_mass`` less the crank's share).

    Notes
    -----
    The terms are the crank train's own (:func:`balance.core.crank_motion.crank_train`,
    ``cylinder_inertia``), less the crank's share of the rotating mass, which the torsion
    model counts in the crank throw's rigid inertia.
    """
    th = np.asarray(theta, dtype=np.float64)
    train = crank_train(engine, np.degrees(th))
    crank_own = _crank_share(engine) * engine.crank_radius**2
    return np.asarray(train.cylinder_inertia - crank_own[:, None], dtype=np.float64)


def moving_parts_inertia(engine: Engine) -> FloatArray:
    r"""Mean inertia of each cylinder's moving parts about the crank axis [kg m^2]:
    the mean over a revolution of :func:`instantaneous_inertia` (the kinetic energy at
    constant speed per :math:`\omega^2/2`), on :data:`INERTIA_SAMPLES` crank angles.

    Parameters
    ----------
    engine : Engine
        The engine (masses by part for a meaningful value: lumped ``rotating`` masses hold
        the crank's own unbalance too, see :func:`instantaneous_inertia`).

    Returns
    -------
    ndarray, shape (cylinders,)
        Each cylinder's mean moving-parts inertia [kg m^2].
    """
    theta = 2.0 * math.pi * np.arange(INERTIA_SAMPLES) / INERTIA_SAMPLES
    return np.asarray(np.mean(instantaneous_inertia(engine, theta), axis=1), dtype=np.float64)


# --------------------------------------------------------------------------- excitation


@dataclass(frozen=True, eq=False)
class Excitation:
    r"""Each cylinder's tangential torque per order, in its own angle from its firing TDC.

    A component is :math:`\operatorname{Re}(G e^{ik\alpha}) = |G|\cos(k\alpha + \arg G)`.

    Attributes
    ----------
    orders : ndarray, shape (K,)
        The orders.
    firing_tdc : ndarray, shape (c,)
        Crank angle :math:`\theta_c` of each cylinder's firing TDC [deg].
    inertia : ndarray of complex, shape (c, K)
        The moving parts' part at :attr:`reference_speed` [N m] (exactly 0 at half orders).
    gas : ndarray of complex, shape (c, K), or None
        The gas part [N m], the same at every speed; None without a ``gas:`` section.
    reference_speed : float
        The speed of :attr:`inertia` [rad/s].
    tangential_pressure : ndarray, shape (c, K), or None
        :math:`|G_{gas}|/(A r)`, the gas part per piston area and crank radius [Pa].
    cycle : str
        ``"four-stroke"`` or ``"two-stroke"``.
    """

    orders: FloatArray
    firing_tdc: FloatArray
    inertia: ComplexArray
    gas: ComplexArray | None
    reference_speed: float
    tangential_pressure: FloatArray | None
    cycle: str

    def crank_parts(self) -> tuple[ComplexArray | None, ComplexArray]:
        r"""The gas part (None without gas) and the moving parts' part at the reference
        speed of each cylinder's torque per order in the crank angle :math:`\theta`,
        :math:`G\,e^{-ik\theta_c}`, each of shape (K, c) [N m]."""
        lag = np.exp(-1j * np.outer(self.orders, np.radians(self.firing_tdc)))  # (K, c)
        inertia = np.asarray(self.inertia.T * lag, dtype=np.complex128)
        gas = None if self.gas is None else np.asarray(self.gas.T * lag, dtype=np.complex128)
        return gas, inertia

    def speed_scale(self, speeds: ArrayLike) -> FloatArray:
        r""":math:`(\Omega/\Omega_{ref})^2` of each speed [rad/s]: the inertia part's
        factor."""
        w = np.asarray(speeds, dtype=np.float64).reshape(-1)
        return np.asarray(speed_squared(w) / float(speed_squared(self.reference_speed)))

    def at_crank(self, speeds: ArrayLike) -> ComplexArray:
        r"""Each cylinder's torque per order in the crank angle :math:`\theta`, at each
        speed: :math:`F = (G_{gas} + (\Omega/\Omega_{ref})^2 G_{inertia})\,e^{-ik\theta_c}`.

        Parameters
        ----------
        speeds : array_like, shape (S,)
            Crank speeds [rad/s].

        Returns
        -------
        ndarray of complex, shape (S, K, c) [N m]
        """
        gas, inertia = self.crank_parts()
        total = inertia[None] * self.speed_scale(speeds)[:, None, None]
        if gas is not None:
            total = total + gas[None]
        return np.asarray(total, dtype=np.complex128)


def _null_gas(engine: Engine, firing: FloatArray) -> GasInput:
    """A gas section whose pressure is the crankcase's everywhere: no gas force."""
    return GasInput(
        angle=np.zeros(1),
        pressure=np.zeros(1),
        model=None,
        crankcase_pressure=0.0,
        bore=1.0,
        firing_tdc=np.asarray(firing, dtype=np.float64),
        cycle_deg=cycle_degrees(engine.cycle),
    )


def _spectrum(torque: FloatArray, harmonics: NDArray[np.intp]) -> ComplexArray:
    """:math:`F_h` of :math:`\\sum_h \\operatorname{Re}(F_h e^{i h 2\\pi n/N})` sampled on a
    periodic grid of N points (rows: cylinders)."""
    n = torque.shape[-1]
    return np.asarray(2.0 * np.fft.rfft(torque, axis=-1)[:, harmonics] / n, dtype=np.complex128)


def excitation(
    engine: Engine,
    orders: ArrayLike,
    firing: ArrayLike,
    *,
    torque: Any = None,
) -> Excitation:
    """Each cylinder's excitation per order (:class:`Excitation`) at the engine's speed.

    Parameters
    ----------
    engine : Engine
        The engine, at the reference speed of the inertia part.
    orders : array_like, shape (K,)
        The orders (multiples of 0.5; whole for a two-stroke).
    firing : array_like, shape (c,)
        Each cylinder's firing TDC [deg] (:func:`place_firing_tdc`).
    torque : TorqueResult, optional
        :func:`balance.core.torque.compute_torque` of this engine, if already computed
        (the ``torque`` section's part); computed here when the engine has gas and it is
        not given.

    Returns
    -------
    Excitation

    Notes
    -----
    The cylinder torques come from :func:`balance.core.torque.compute_torque`, sampled
    every 0.25 deg of the cycle: once as they are (gas and moving parts) and once with the
    pressure equal to the crankcase pressure (the moving parts alone, which scale with the
    speed squared).  Their difference is the gas part.  The moving parts' torque repeats
    every revolution, so its half orders are exactly zero.  Orders in the crank angle are
    turned into the cylinder's own angle by :math:`e^{+ik\\theta_c}`.
    """
    from balance.core.torque import compute_torque

    k = np.asarray(orders, dtype=np.float64).reshape(-1)
    tdc = np.asarray(firing, dtype=np.float64)
    harmonics = harmonic_numbers(k, engine.cycle)
    base = np.ones(1, dtype=np.intp)
    bare = compute_torque(replace(engine, gas=_null_gas(engine, tdc)), base)
    moving = np.asarray(bare.cylinder_torque, dtype=np.float64)
    turn = np.exp(1j * np.outer(np.radians(tdc), k))  # (c, K): crank angle -> own angle
    inertia = _spectrum(moving, harmonics) * turn
    whole = (harmonics * 360) % round(cycle_degrees(engine.cycle)) == 0  # whole orders
    inertia[:, ~whole] = 0.0
    gas = pressure = None
    if engine.gas is not None:
        if torque is None:
            torque = compute_torque(engine, base)
        with_gas = np.asarray(torque.cylinder_torque, dtype=np.float64)
        gas = _spectrum(with_gas - moving, harmonics) * turn
        area = engine.gas.piston_area
        pressure = np.abs(gas) / (area * engine.crank_radius[:, None])
    return Excitation(
        orders=k,
        firing_tdc=tdc,
        inertia=np.asarray(inertia, dtype=np.complex128),
        gas=gas,
        reference_speed=float(engine.speed),
        tangential_pressure=pressure,
        cycle=engine.cycle,
    )
