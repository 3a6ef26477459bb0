r"""The speed model's inputs: the load on the crank, the flywheel, their refusals, and the
constant-speed rung's bound on its own error.

The variable-speed analysis (:mod:`balance.core.dynamics`) solves the crank train's
equation of motion (:mod:`balance.core.crank_motion`) under a load, with what turns rigidly
with the crank beyond the layout's masses (docs/dynamics.md).  This module holds what it is
given and what it refuses, and what the constant-speed analysis can say of its own error
from constant-speed data alone (:class:`SpeedBound`: the ladder's second axis).

Inputs
------
- :class:`Flywheel`: everything that turns rigidly with the crank beyond the layout's masses
  (the ``flywheel:`` section), as an inertia :math:`J_f` or as a target speed fluctuation for
  which :math:`J_f` is sized.
- The load on the crank: :class:`MeanLoad` (default), :class:`PropellerLoad`,
  :class:`ConstantLoad`, :class:`PowerLawLoad`; :class:`DynamicsSettings` holds both.

Refusals and warnings
---------------------
Refused by the core (:class:`~balance.core.errors.AnalysisError`, exit 1, one line naming
quantities; the reader need not check these):

- no flywheel given (:func:`settings_of`): the motion needs the inertia that turns with the
  crank beyond the layout's masses;
- a reduced inertia that is zero somewhere over the cycle (nothing turns;
  :func:`balance.core.dynamics.analyse_dynamics`);
- a constant load torque other than the mean gas torque (to 1e-6 of it): above it the
  engine stalls, below it the engine accelerates (:func:`steady_load`);
- a propeller or power-law load with a mean gas torque :math:`\le 0` (a motored or
  misfiring trace): the engine cannot drive the load (:func:`steady_load`);
- without a ``gas:`` section any load but the mean (which is then zero): no gas torque
  (:func:`steady_load`);
- sizing for a speed fluctuation that the layout's masses alone already undercut
  (:func:`balance.core.dynamics.size_flywheel`, reported with that fluctuation).

Refused by the reader or the command line (they concern the request, not the physics):

- the dynamic speed model with the ``series`` or ``textbook`` acceleration model asked for
  explicitly (the dynamic rung samples the exact kinematics whatever the request's model;
  a model that ``--tolerance`` picks is no reason to refuse);
- the dynamic speed model with a sweep, a tolerance study or a proposal (``propose``): not
  in this version; proposals are made at constant speed;
- a ``flywheel:`` section without ``gas:`` must be accepted when the dynamic model is asked
  for (the crank then coasts), and the load values checked where they are read: a
  power law's torque, speed and exponent above zero and finite (:class:`PowerLawLoad`
  refuses them too, with :class:`~balance.core.errors.InputError`).

Warned (:class:`~balance.core.plausibility.PlausibilityWarning` records; they change no
number):

- ``speed_fluctuation``: :math:`\delta` above 20 % (the engine is near stalling);
- ``lowest_speed``: the lowest speed of the cycle below half the mean;
- ``load_speed``: a power-law load whose mean speed lies outside 0.5–2 times the layout's
  speed (a pressure trace belongs to one speed);

  (these three by :func:`balance.core.dynamics.analyse_dynamics`, into the result's
  warnings)
- ``constant_speed_bound``: in the constant-speed analysis with gas and flywheel, the
  constant rung's error bound above 5 % of :math:`\sum m r\omega^2`
  (:func:`constant_speed_warning`, for the caller of the constant-speed analysis).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from balance.core.crank_motion import ConstantTorque, PowerLaw, Propeller, crank_train
from balance.core.engine import Engine
from balance.core.errors import AnalysisError, InputError
from balance.core.plausibility import PlausibilityWarning
from balance.core.speed import rad_per_s_to_rpm
from balance.core.torque import TorqueResult

__all__ = [
    "ConstantLoad",
    "DynamicsSettings",
    "Flywheel",
    "Load",
    "MeanLoad",
    "PowerLawLoad",
    "PropellerLoad",
    "SpeedBound",
    "bound_warning",
    "constant_speed_bound",
    "constant_speed_warning",
    "rpm_text",
    "settings_of",
    "steady_load",
    "warning",
]

#: Relative difference from the mean gas torque within which a constant load is the mean.
MEAN_TORQUE_TOLERANCE = 1e-6
#: The constant-speed rung's error bound, as a share of sum(m r w^2), above which the
#: constant-speed analysis warns.
WARN_CONSTANT_SPEED_BOUND = 0.05


def warning(rule: str, field_name: str, message: str, excess: float) -> PlausibilityWarning:
    """A warning record of the speed model.

    Parameters
    ----------
    rule, field_name, message : str
        As :class:`~balance.core.plausibility.PlausibilityWarning`.
    excess : float
        How far beyond its threshold the value is [1] (at least 1 is recorded).

    Returns
    -------
    PlausibilityWarning
    """
    return PlausibilityWarning(rule, field_name, message, max(float(excess), 1.0))


def rpm_text(speed: float) -> str:
    """A crank speed as messages write it.

    Parameters
    ----------
    speed : float
        [rad/s].

    Returns
    -------
    str
        Four significant digits and the unit, ``800 rpm``.
    """
    return f"{rad_per_s_to_rpm(speed):.4g} rpm"


# --------------------------------------------------------------------------- inputs


@dataclass(frozen=True)
class MeanLoad:
    """A constant load torque equal to the cycle mean of the gas torque (the default)."""

    kind: ClassVar[str] = "mean"


@dataclass(frozen=True)
class PropellerLoad:
    r""":math:`T_L = c\,\omega^2` with :math:`c` such that the mean speed is the layout's."""

    kind: ClassVar[str] = "propeller"


@dataclass(frozen=True)
class ConstantLoad:
    """A constant load torque [N m]; it must equal the mean gas torque (to 1e-6 of it),
    or there is no periodic steady state."""

    torque: float
    kind: ClassVar[str] = "constant"


@dataclass(frozen=True)
class PowerLawLoad:
    r""":math:`T_L = T_0(\omega/\omega_0)^n`: torque :math:`T_0` [N m] at speed
    :math:`\omega_0` [rad/s], exponent :math:`n`, all above zero.  The mean speed is the one
    at which the load absorbs the cycle's work.

    Raises
    ------
    InputError
        For a torque, speed or exponent that is not finite and above zero.
    """

    torque: float
    speed: float
    exponent: float
    kind: ClassVar[str] = "power_law"

    def __post_init__(self) -> None:
        for name, value in (
            ("torque", self.torque),
            ("speed", self.speed),
            ("exponent", self.exponent),
        ):
            if not (math.isfinite(value) and value > 0.0):
                raise InputError(f"power-law load: its {name} must be above zero, got {value:g}")


#: The loads on the crank.
Load = MeanLoad | PropellerLoad | ConstantLoad | PowerLawLoad


@dataclass(frozen=True)
class Flywheel:
    """What turns rigidly with the crank beyond the layout's masses (the ``flywheel:``
    section): its inertia [kg m^2], or the speed fluctuation [1] to size it for.  Exactly
    one is given."""

    inertia: float | None = None
    speed_fluctuation: float | None = None

    @classmethod
    def of(cls, engine: Engine) -> Flywheel | None:
        """The engine's ``flywheel:`` section (a ``Flywheel`` in ``engine.sections``, else
        the one read with its ``gas:`` section), or None."""
        given = engine.section("flywheel")
        if isinstance(given, Flywheel):
            return given
        gas = engine.gas
        if gas is None or (gas.flywheel_inertia is None and gas.speed_fluctuation is None):
            return None
        return cls(gas.flywheel_inertia, gas.speed_fluctuation)


@dataclass(frozen=True)
class DynamicsSettings:
    """The load and the flywheel of a dynamic analysis, resolved (:func:`settings_of`)."""

    load: Load
    flywheel: Flywheel


def settings_of(
    engine: Engine, load: Load | None = None, flywheel: Flywheel | None = None
) -> DynamicsSettings:
    """The settings of a dynamic analysis: the load given (else the mean load) and the
    flywheel given (else the engine's, :meth:`Flywheel.of`).

    Parameters
    ----------
    engine : Engine
        The engine (its ``flywheel:`` section when no flywheel is given).
    load : Load, optional
        The load on the crank.
    flywheel : Flywheel, optional
        :math:`J_f` [kg m^2] or the speed fluctuation to size it for [1].

    Returns
    -------
    DynamicsSettings

    Raises
    ------
    AnalysisError
        Without a flywheel: the motion needs the inertia that turns with the crank.
    """
    wheel = flywheel if flywheel is not None else Flywheel.of(engine)
    if wheel is None or (wheel.inertia is None and wheel.speed_fluctuation is None):
        raise AnalysisError(
            f"{engine.name}: the variable-speed analysis needs what turns with the crank "
            "beyond the layout's masses: give the flywheel section's inertia (crankshaft, "
            "flywheel, clutch, damper), or a speed fluctuation to size it for"
        )
    return DynamicsSettings(load if load is not None else MeanLoad(), wheel)


def steady_load(
    load: Load, mean_torque: float, speed: float, gas: bool
) -> ConstantTorque | Propeller | PowerLaw:
    """The load of the equation of motion, or the reason there is no steady state.

    Parameters
    ----------
    load : Load
        The load asked for.
    mean_torque : float
        The cycle mean of the gas torque [N m].
    speed : float
        The layout's speed [rad/s] (the mean speed of a constant or propeller load).
    gas : bool
        Whether the engine has gas forces.

    Raises
    ------
    AnalysisError
        A constant torque other than the mean (stall or acceleration); a propeller or power
        law with a mean torque at or below zero; any load but the mean without gas.
    """
    if isinstance(load, MeanLoad):
        return ConstantTorque(mean_torque)
    if not gas:
        if isinstance(load, ConstantLoad) and load.torque == 0.0:
            return ConstantTorque(0.0)
        raise AnalysisError(
            f"no gas torque: the speed falls to zero under a {load.kind.replace('_', '-')} "
            "load; without a gas section only the mean load (zero) has a steady state"
        )
    if isinstance(load, ConstantLoad):
        gap = load.torque - mean_torque
        if abs(gap) <= MEAN_TORQUE_TOLERANCE * abs(mean_torque):
            return ConstantTorque(mean_torque)
        if gap > 0.0:
            raise AnalysisError(
                f"the engine stalls: its mean torque at {rpm_text(speed)} is {mean_torque:.3g} "
                f"N m, the load {load.torque:.3g} N m; the speed falls to zero"
            )
        raise AnalysisError(
            f"no steady state: the engine accelerates (mean torque {mean_torque:.3g} N m > "
            f"load {load.torque:.3g} N m); use the mean load or a speed-dependent load "
            "(propeller, power law)"
        )
    if mean_torque <= 0.0:
        raise AnalysisError(
            f"the engine cannot drive the load: its mean torque is {mean_torque:.3g} N m; "
            "the speed falls to zero"
        )
    if isinstance(load, PropellerLoad):
        return Propeller()
    return PowerLaw(load.torque, load.speed, load.exponent)


# --------------------------------------------------------------------------- the ladder


@dataclass(frozen=True)
class SpeedBound:
    r"""The constant-speed rung's bound on its own error, from constant-speed data alone.

    With :math:`\delta_e = A/(J_{mean}\omega^2)` and
    :math:`\dot\omega_e = \max|M - M_{mean}|/J_{min}`,
    :math:`\varepsilon = 2\delta_e(1 + \delta_e)`,
    :math:`w = \dot\omega_e(1 + 2\delta_e)/\omega^2` and

    .. math::

        |F_{dyn}(\theta) - F_{const}(\theta)| \le \omega^2 \sum_b m_b\left(
        \max|z_b''|\,\varepsilon + \max|z_b'|\,w\right)

    (for a piston :math:`|z''| = |s''|`, :math:`|z'| = |s'|`; for a mass on the crank pin
    both are r).

    Attributes
    ----------
    delta : float
        :math:`\delta_e` [1].
    acceleration : float
        :math:`\dot\omega_e` [rad/s^2].
    epsilon, w : float
        :math:`\varepsilon` and :math:`w` [1].
    force : float
        The bound [N].
    reference : float
        :math:`\sum (m_{rec} + m_{rot}) r\omega^2` [N].
    """

    delta: float
    acceleration: float
    epsilon: float
    w: float
    force: float
    reference: float

    @property
    def ratio(self) -> float:
        """The bound per :attr:`reference` [1] (the ladder's unit)."""
        return self.force / self.reference if self.reference > 0.0 else math.nan

    def speed_model_for(self, tolerance: float) -> str:
        """``"dynamic"`` when the bound exceeds ``tolerance`` (per :attr:`reference`),
        else ``"constant"``."""
        return "dynamic" if self.ratio > tolerance else "constant"


def constant_speed_bound(
    engine: Engine, torque: TorqueResult, flywheel: Flywheel | None = None
) -> SpeedBound | None:
    """The constant-speed rung's error bound (:class:`SpeedBound`) of an engine with gas.

    Parameters
    ----------
    engine : Engine
        The engine at the speed analysed.
    torque : TorqueResult
        Its constant-speed gas analysis (:func:`balance.core.torque.compute_torque`):
        the total torque :math:`M` and its excess work :math:`A`.
    flywheel : Flywheel, optional
        Default the engine's; with a speed fluctuation, :math:`J_f` is the one that gives
        it at constant speed, :math:`A/(\\delta\\omega^2)` less the layout's mean part.

    Returns
    -------
    SpeedBound or None
        None without a flywheel.
    """
    wheel = flywheel if flywheel is not None else Flywheel.of(engine)
    if wheel is None:
        return None
    train = crank_train(engine, torque.crank_angle)
    w2 = engine.speed * engine.speed
    work = torque.excess_work
    if wheel.inertia is not None:
        inertia = float(wheel.inertia)
    else:
        assert wheel.speed_fluctuation is not None
        target = float(wheel.speed_fluctuation)
        inertia = max(work / (target * w2) - float(np.mean(train.inertia)), 0.0)
    j_mean = float(np.mean(train.inertia)) + inertia
    j_min = float(np.min(train.inertia)) + inertia
    delta = work / (j_mean * w2)
    total = torque.engine_torque
    accel = float(np.max(np.abs(total - np.mean(total)))) / j_min
    epsilon = 2.0 * delta * (1.0 + delta)
    w = accel * (1.0 + 2.0 * delta) / w2
    bound = w2 * (train.acceleration_reach * epsilon + train.velocity_reach * w)
    reference = float(
        np.sum((engine.reciprocating_mass + engine.rotating_mass) * engine.crank_radius) * w2
    )
    return SpeedBound(delta, accel, epsilon, w, bound, reference)


def constant_speed_warning(
    engine: Engine, torque: TorqueResult, flywheel: Flywheel | None = None
) -> PlausibilityWarning | None:
    """The warning of a constant-speed analysis with gas and flywheel whose error bound
    (:func:`constant_speed_bound`) exceeds 5 % of :math:`\\sum m r\\omega^2`.

    Parameters
    ----------
    engine, torque, flywheel
        As :func:`constant_speed_bound`.

    Returns
    -------
    PlausibilityWarning or None
        Rule ``constant_speed_bound``, field ``flywheel``; None below 5 % and without a
        flywheel.
    """
    bound = constant_speed_bound(engine, torque, flywheel)
    return None if bound is None else bound_warning(bound)


def bound_warning(bound: SpeedBound) -> PlausibilityWarning | None:
    r"""The constant-speed analysis' warning of a bound above 5 % of
    :math:`\sum m r\omega^2` (:func:`constant_speed_warning`).

    Parameters
    ----------
    bound : SpeedBound
        The constant rung's bound (:func:`constant_speed_bound`).

    Returns
    -------
    PlausibilityWarning or None
        Rule ``constant_speed_bound``, field ``flywheel``; None at 5 % or below.
    """
    if not bound.ratio > WARN_CONSTANT_SPEED_BOUND:
        return None
    return warning(
        "constant_speed_bound",
        "flywheel",
        f"the speed fluctuation (delta ≈ {100 * bound.delta:.2g} %) may change the free "
        f"forces by up to {100 * bound.ratio:.2g} % of sum(m r w^2); the variable-speed "
        "(dynamic) analysis computes them",
        bound.ratio / WARN_CONSTANT_SPEED_BOUND,
    )
