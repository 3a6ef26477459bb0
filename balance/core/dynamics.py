r"""The variable-speed rung: the crank train's own motion over the working cycle.

Every other analysis takes the crank speed as constant.  This section solves the rigid crank
train's equation of motion (:mod:`balance.core.crank_motion`) for its periodic steady state
under a load (:mod:`balance.core.speed_model`), and reports the crank speed over the cycle,
its exact fluctuation, and the free forces, moments and roll that the varying motion puts on
the block, beside the constant-speed answer at the same mean speed (docs/dynamics.md).  What
it refuses and warns about is listed in :mod:`balance.core.speed_model`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from balance.core import phasors
from balance.core.catalogue import Output
from balance.core.crank_motion import (
    ConstantTorque,
    CrankTrain,
    Motion,
    PowerLaw,
    Propeller,
    crank_train,
    find_root,
    orders_in_time,
    periodic_motion,
)
from balance.core.engine import Engine
from balance.core.errors import AnalysisError, InputError
from balance.core.gas import cycle_degrees
from balance.core.phasors import Phasors, phase_deg
from balance.core.plausibility import PlausibilityWarning
from balance.core.speed import rad_per_s_to_rpm
from balance.core.speed_model import (
    DynamicsSettings,
    Flywheel,
    Load,
    PowerLawLoad,
    SpeedBound,
    bound_warning,
    constant_speed_bound,
    rpm_text,
    settings_of,
    steady_load,
    warning,
)
from balance.core.torque import CYCLE_SAMPLES_PER_DEGREE, TorqueResult, roll_orders

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.result import Request, Result

__all__ = ["OUTPUTS", "DynamicsResult", "analyse_dynamics", "dynamics_part", "size_flywheel"]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Speed fluctuation above which a warning is given: the engine is near stalling.
WARN_FLUCTUATION = 0.20
#: Lowest speed of the cycle, as a share of the mean, below which a warning is given.
WARN_LOWEST_SPEED = 0.5
#: A power-law load's mean speed, as a multiple of the layout's, outside which a warning is
#: given (a pressure trace belongs to the speed it was taken at).
LOAD_SPEED_RANGE = (0.5, 2.0)
#: Relative tolerance of the sized flywheel inertia.
SIZING_TOLERANCE = 1e-12


# --------------------------------------------------------------------------- the result


@dataclass(frozen=True, eq=False)
class DynamicsResult:
    r"""The periodic motion of the crank train and what it puts on the block.

    Arrays over the cycle are on its grid (every 0.25 deg, :attr:`crank_angle`);
    :meth:`samples` takes every degree of them.

    Attributes
    ----------
    load : Load
        The load asked for.
    load_torque : float
        The load's torque [N m]: the mean gas torque for the mean and a constant load, the
        cycle mean (in crank angle) of :math:`T_L` for the others.
    load_coefficient : float
        The propeller's :math:`c` [N m s^2] (NaN for the other loads).
    flywheel_inertia : float
        :math:`J_f` [kg m^2], given or sized.
    flywheel_sized : bool
        Whether :attr:`flywheel_inertia` was sized for a speed fluctuation.
    cycle_deg : float
        720 (four-stroke) or 360 (two-stroke) [deg].
    crank_angle : ndarray
        The cycle's grid [deg].
    inertia : ndarray
        :math:`J(\theta)` [kg m^2], :math:`J_f` included.
    gas_torque : ndarray
        :math:`Q(\theta)` [N m] (zeros without gas).
    motion : Motion
        Speed, acceleration, load torque and time over the cycle.
    orders : ndarray
        The orders of the phasors (halves for a four-stroke).
    dynamic, constant : Phasors
        Whole free force and moment (reciprocating and rotating) and roll per order, under
        the varying speed and at the constant mean speed [N, N m]; ``moment_*`` and
        ``roll`` None when not asked.
    force, force_constant : ndarray of complex
        The whole free force over the cycle under each speed model [N].
    excess_work : float
        :math:`A`: the largest excess work of the constant-speed torque (gas and inertia)
        at the mean speed [J].
    warnings : tuple of PlausibilityWarning
        What the steady state warns about.
    bound : SpeedBound or None
        The constant-speed rung's bound on its own error (:class:`SpeedBound`), with gas
        forces; None without them.
    """

    load: Load
    load_torque: float
    load_coefficient: float
    flywheel_inertia: float
    flywheel_sized: bool
    cycle_deg: float
    crank_angle: FloatArray
    inertia: FloatArray
    gas_torque: FloatArray
    motion: Motion
    orders: FloatArray
    dynamic: Phasors
    constant: Phasors
    force: ComplexArray
    force_constant: ComplexArray
    excess_work: float
    warnings: tuple[PlausibilityWarning, ...] = field(default=())
    bound: SpeedBound | None = None

    speed_model: ClassVar[str] = "dynamic"

    @property
    def mean_speed(self) -> float:
        """Cycle angle over cycle time [rad/s]."""
        return self.motion.mean_speed

    @property
    def speed_min(self) -> float:
        """Lowest crank speed of the cycle [rad/s]."""
        return float(self.motion.speed.min())

    @property
    def speed_max(self) -> float:
        """Highest crank speed of the cycle [rad/s]."""
        return float(self.motion.speed.max())

    @property
    def speed_fluctuation(self) -> float:
        r"""Exact :math:`\delta = (\omega_{max} - \omega_{min})/\omega_{mean}` [1]."""
        return self.motion.speed_fluctuation

    @property
    def speed_fluctuation_constant_speed(self) -> float:
        r"""The constant-speed estimate :math:`A/(J_{mean}\omega^2)` [1], with
        :math:`J_{mean}` the cycle mean of :math:`J(\theta)` (flywheel included)."""
        return float(self.excess_work / (np.mean(self.inertia) * self.mean_speed**2))

    def samples(self) -> dict[str, FloatArray]:
        """Every degree of the cycle: ``crank_angle`` [deg], ``speed`` [rad/s],
        ``acceleration`` [rad/s^2], ``time`` [s], ``inertia`` [kg m^2], ``gas_torque``
        [N m]."""
        pick = slice(None, None, CYCLE_SAMPLES_PER_DEGREE)
        return {
            "crank_angle": self.crank_angle[pick],
            "speed": self.motion.speed[pick],
            "acceleration": self.motion.acceleration[pick],
            "time": self.motion.time[pick],
            "inertia": self.inertia[pick],
            "gas_torque": self.gas_torque[pick],
        }

    def has(self, quantity: str) -> bool:
        """Whether ``quantity`` ('force', 'moment', 'roll') was computed."""
        if quantity == "roll":
            return self.dynamic.roll is not None
        return self.dynamic.has(quantity)  # type: ignore[arg-type]

    def difference(self, quantity: str) -> FloatArray:
        """Size of the vector difference from the constant-speed answer per order:
        :math:`|\\Delta P^+| + |\\Delta P^-|` (force [N], moment [N m]) or :math:`|\\Delta R|`
        (roll [N m])."""
        change = self.dynamic + self.constant.scaled(-1.0)
        if quantity == "roll":
            assert change.roll is not None
            return np.asarray(np.abs(change.roll))
        return change.peak(quantity)  # type: ignore[arg-type]

    def peak(self, quantity: str, constant: bool = False) -> FloatArray:
        """The peak (force [N], moment [N m]) or amplitude (roll [N m]) per order under the
        varying speed, or with ``constant`` at the constant mean speed."""
        bundle = self.constant if constant else self.dynamic
        if quantity == "roll":
            assert bundle.roll is not None
            return np.asarray(np.abs(bundle.roll))
        return bundle.peak(quantity)  # type: ignore[arg-type]

    def constant_peak(self, quantity: str) -> FloatArray:
        """The constant-speed peak (force, moment) or amplitude (roll) per order."""
        return self.peak(quantity, constant=True)

    def largest_difference(self, quantity: str) -> float:
        """The largest :meth:`difference` over the orders per the largest constant-speed
        peak (amplitude) over the orders [1] (NaN where that is 0)."""
        top = float(np.max(self.constant_peak(quantity), initial=0.0))
        value = float(np.max(self.difference(quantity), initial=0.0))
        return value / top if top > 0.0 else math.nan


# --------------------------------------------------------------------------- the analysis


def _cycle(engine: Engine) -> float:
    return engine.gas.cycle_deg if engine.gas is not None else cycle_degrees(engine.cycle)


def _grid(engine: Engine) -> FloatArray:
    cycle = _cycle(engine)
    samples = round(cycle * CYCLE_SAMPLES_PER_DEGREE)
    return np.asarray(cycle * np.arange(samples) / samples)


def _gas_torque(train: CrankTrain, torque: TorqueResult | None) -> FloatArray:
    r""":math:`Q = \sum_i -P_{g,i} s_i'` over the grid [N m] (the gas forces of
    :func:`balance.core.torque.compute_torque`; zeros without gas)."""
    if torque is None:
        return np.zeros(train.theta.shape)
    return np.asarray(np.sum(-torque.gas_force * train.piston_rate, axis=0))


def _excess_work(total: FloatArray, step: float) -> float:
    """The largest excess work of a torque over the periodic grid [J] (the trapezoidal
    rule of balance.core.torque)."""
    mean = float(np.mean(total))
    excess = np.concatenate([[0.0], np.cumsum(0.5 * (total + np.roll(total, -1)) - mean) * step])
    return float(excess.max() - excess.min())


def _solve(
    train: CrankTrain,
    flywheel_inertia: float,
    gas: FloatArray,
    load: Any,
    speed: float,
    cycle: float,
) -> Motion:
    inertia = train.inertia + flywheel_inertia
    return periodic_motion(inertia, train.inertia_slope, gas, cycle, load, speed)


def size_flywheel(
    inertia: FloatArray,
    inertia_slope: FloatArray,
    gas_torque: FloatArray,
    load: ConstantTorque | Propeller | PowerLaw,
    speed: float,
    cycle: float,
    target: float,
) -> float:
    r"""The flywheel inertia :math:`J_f` [kg m^2] whose steady state has the exact speed
    fluctuation ``target`` (:math:`\delta` falls monotonically with :math:`J_f`; Brent's
    method on :math:`J_f`).

    Parameters
    ----------
    inertia, inertia_slope : ndarray
        The layout's part of :math:`J(\theta)` [kg m^2] and :math:`J'` [kg m^2/rad] on the
        cycle's grid (:class:`balance.core.crank_motion.CrankTrain`).
    gas_torque : ndarray
        :math:`Q` on the grid [N m].
    load : ConstantTorque, Propeller or PowerLaw
        The load (:func:`steady_load`).
    speed : float
        Mean speed [rad/s].
    cycle : float
        Cycle angle [rad].
    target : float
        :math:`\delta` [1].

    Returns
    -------
    float
        :math:`J_f` [kg m^2], to a relative 1e-12.

    Raises
    ------
    AnalysisError
        When the layout's masses alone (:math:`J_f = 0`) give less than ``target``.
    """

    def gap(flywheel: float) -> float:
        motion = periodic_motion(inertia + flywheel, inertia_slope, gas_torque, cycle, load, speed)
        return motion.speed_fluctuation - target

    work = _excess_work(gas_torque - 0.5 * inertia_slope * speed * speed, cycle / gas_torque.size)
    guess = max(work / (target * speed * speed) - float(np.mean(inertia)), 1e-12)
    if float(np.min(inertia)) > 0.0:
        low, f_low = 0.0, gap(0.0)
        if f_low <= 0.0:
            if f_low == 0.0:
                return 0.0
            raise AnalysisError(
                f"a speed fluctuation of {100 * target:.3g} % needs no flywheel: with the "
                f"layout's masses alone (flywheel inertia 0) the crank speed varies by "
                f"{100 * (f_low + target):.3g} %; give a larger fluctuation or the inertia"
            )
    else:  # nothing of the layout turns: the fluctuation grows without bound as J_f -> 0
        low = guess
        f_low = gap(low)
        while f_low <= 0.0:
            low *= 0.5
            f_low = gap(low)
    high = max(guess, low)
    f_high = gap(high) if high != low else f_low
    while f_high > 0.0:
        high *= 2.0
        f_high = gap(high)
    return find_root(gap, low, high, f_low, f_high, rtol=SIZING_TOLERANCE)


def analyse_dynamics(
    engine: Engine,
    orders: NDArray[np.intp],
    settings: DynamicsSettings,
    torque: TorqueResult | None = None,
    *,
    moments: bool = True,
    roll: bool = True,
) -> DynamicsResult:
    """The periodic steady state of an engine's crank train and its free forces.

    Parameters
    ----------
    engine : Engine
        The engine, at its mean speed [rad/s] (``engine.speed``; a power law sets its own).
    orders : ndarray of int
        The analysis orders; the phasors are given at :func:`balance.core.torque.roll_orders`
        (halves up to the highest for a four-stroke).
    settings : DynamicsSettings
        The load and the flywheel (:func:`settings_of`).
    torque : TorqueResult, optional
        The gas forces (:func:`balance.core.torque.compute_torque`); computed here for an
        engine with gas when not given.
    moments, roll : bool
        Whether to form the moments and the roll.

    Returns
    -------
    DynamicsResult

    Raises
    ------
    AnalysisError
        The refusals of the module notes.
    """
    if torque is None and engine.gas is not None:
        from balance.core.torque import compute_torque

        torque = compute_torque(engine, orders)
    grid = torque.crank_angle if torque is not None else _grid(engine)
    cycle_deg = _cycle(engine)
    cycle = math.radians(cycle_deg)
    train = crank_train(engine, grid)
    gas = _gas_torque(train, torque)
    flywheel = settings.flywheel
    if float(np.min(train.inertia)) + (flywheel.inertia or 0.0) <= 0.0:
        raise AnalysisError(
            f"{engine.name}: nothing turns with the crank (the reduced inertia is 0 over "
            "part of the cycle); give the flywheel section's inertia"
        )
    mean_torque = float(np.mean(gas))
    load = steady_load(settings.load, mean_torque, engine.speed, engine.gas is not None)
    if flywheel.inertia is not None:
        inertia, sized = float(flywheel.inertia), False
    else:
        assert flywheel.speed_fluctuation is not None
        inertia = size_flywheel(
            train.inertia,
            train.inertia_slope,
            gas,
            load,
            engine.speed,
            cycle,
            float(flywheel.speed_fluctuation),
        )
        sized = True
    motion = _solve(train, inertia, gas, load, engine.speed, cycle)
    ks = roll_orders(np.asarray(orders, dtype=np.intp), engine.cycle)
    w_mean = motion.mean_speed
    dynamic, force = _phasors(train, gas, motion, ks, cycle, moments, roll)
    steady = _constant_motion(motion, cycle)
    constant, force_constant = _phasors(train, gas, steady, ks, cycle, moments, roll)
    excess = _excess_work(gas - 0.5 * train.inertia_slope * w_mean * w_mean, cycle / gas.size)
    part = DynamicsResult(
        load=settings.load,
        load_torque=load.torque
        if isinstance(load, ConstantTorque)
        else float(np.mean(motion.load_torque)),
        load_coefficient=motion.coefficient,
        flywheel_inertia=inertia,
        flywheel_sized=sized,
        cycle_deg=cycle_deg,
        crank_angle=np.asarray(grid, dtype=np.float64),
        inertia=train.inertia + inertia,
        gas_torque=gas,
        motion=motion,
        orders=ks,
        dynamic=dynamic,
        constant=constant,
        force=force,
        force_constant=force_constant,
        excess_work=excess,
    )
    return _with_warnings(part, engine)


def _constant_motion(motion: Motion, cycle: float) -> Motion:
    """The constant-speed motion at the same mean speed, on the same grid."""
    n = motion.speed.size
    w = motion.mean_speed
    return Motion(
        speed=np.full(n, w),
        acceleration=np.zeros(n),
        load_torque=motion.load_torque,
        time=cycle * np.arange(n) / n / w,
        period=cycle / w,
        mean_speed=w,
    )


def _phasors(
    train: CrankTrain,
    gas: FloatArray,
    motion: Motion,
    orders: FloatArray,
    cycle: float,
    moments: bool,
    roll: bool,
) -> tuple[Phasors, ComplexArray]:
    """The whole free force, moment and roll per order under ``motion`` (orders taken in
    time, :func:`balance.core.crank_motion.orders_in_time`, all three in one pass), sums
    below their rounding set to zero, and the force over the cycle."""
    w, dw = motion.speed, motion.acceleration
    force = train.force(w, dw)
    signals = [force]
    sizes = [w * w * train.force_size[1] + np.abs(dw) * train.force_size[0]]
    if moments:
        signals.append(train.moment(w, dw))
        sizes.append(w * w * train.moment_size[1] + np.abs(dw) * train.moment_size[0])
    if roll:
        signals.append((train.inertia_roll(w, dw) - gas).astype(np.complex128))
        sizes.append(w * w * train.roll_size[1] + np.abs(dw) * train.roll_size[0] + np.abs(gas))
    forward, backward = orders_in_time(
        np.stack(signals), w, motion.time, motion.period, orders, cycle
    )
    n_terms = 8 * (train.points + train.rotors + 1) * math.ceil(math.log2(w.size))
    weight = (cycle / w.size) / w / motion.period
    scales = [float(np.sum(weight * size)) for size in sizes]

    def clean(values: ComplexArray, i: int, factor: float = 1.0) -> ComplexArray:
        return phasors.cancel_to_zero(factor * values, factor * scales[i], n_terms)

    roll_phasors = None
    if roll:
        roll_phasors = np.asarray(clean(forward[-1], len(signals) - 1, 2.0))
    bundle = Phasors(
        orders=np.asarray(orders),
        force_forward=clean(forward[0], 0),
        force_backward=clean(backward[0], 0),
        moment_forward=clean(forward[1], 1) if moments else None,
        moment_backward=clean(backward[1], 1) if moments else None,
        roll=roll_phasors,
    )
    return bundle, force


def _with_warnings(part: DynamicsResult, engine: Engine) -> DynamicsResult:
    """The part with what its steady state warns about (module notes)."""
    found = []
    delta = part.speed_fluctuation
    low = f"{rad_per_s_to_rpm(part.speed_min):.4g}"
    high = f"{rad_per_s_to_rpm(part.speed_max):.4g}"
    if delta > WARN_FLUCTUATION:
        found.append(
            warning(
                "speed_fluctuation",
                "flywheel",
                f"the crank speed varies by {100 * delta:.3g} % ({low}–{high} rpm): the "
                "engine is near stalling with this flywheel at this speed",
                delta / WARN_FLUCTUATION,
            )
        )
    if part.speed_min < WARN_LOWEST_SPEED * part.mean_speed:
        found.append(
            warning(
                "lowest_speed",
                "flywheel",
                f"the lowest crank speed of the cycle, {low} rpm, is below half the mean speed "
                f"({rpm_text(part.mean_speed)})",
                WARN_LOWEST_SPEED * part.mean_speed / part.speed_min,
            )
        )
    if isinstance(part.load, PowerLawLoad):
        ratio = part.mean_speed / engine.speed
        lo, hi = LOAD_SPEED_RANGE
        if not lo <= ratio <= hi:
            found.append(
                warning(
                    "load_speed",
                    "dynamics.load",
                    f"the load absorbs the cycle's work at a mean speed of "
                    f"{rpm_text(part.mean_speed)}, {ratio:.3g} times the layout's speed "
                    f"({rpm_text(engine.speed)}) at which its pressure trace belongs",
                    max(ratio / hi, lo / ratio),
                )
            )
    return replace(part, warnings=tuple(found))


@dataclass(frozen=True)
class ConstantSpeed:
    """The section's part of a constant-speed analysis with gas forces and a flywheel: the
    constant rung's bound on its own error (the speed/accuracy ladder's second axis).

    Attributes
    ----------
    bound : SpeedBound
        :func:`balance.core.speed_model.constant_speed_bound`.
    """

    bound: SpeedBound

    speed_model: ClassVar[str] = "constant"


def dynamics_part(
    engine: Engine,
    request: Request,
    result: Result,
    *,
    speed_model: str | None = None,
    load: Load | None = None,
    flywheel: Flywheel | None = None,
    figures: bool = False,
) -> Result:
    r"""The ``dynamics`` section: the speed model, the second axis of the speed/accuracy
    ladder (docs/dynamics.md).

    With the constant speed model and gas forces and a flywheel, the constant rung's bound
    on its own error (:class:`ConstantSpeed`, and its warning above 5 % of
    :math:`\sum m r\omega^2`); with the dynamic one, the crank train's periodic motion
    and its free forces (:func:`analyse_dynamics`), its warnings added to the result's.  A
    request with a tolerance takes the dynamic model where the constant rung's bound
    exceeds it.  Without gas forces or a flywheel and without the dynamic model asked for,
    the result is returned as it is.

    Parameters
    ----------
    engine : Engine
        The engine at the request's speed (the mean speed).
    request : Request
        Its orders, its tolerance, and whether moments and roll are wanted.
    result : Result
        The analysis so far; its ``torque`` part (gas forces) is used when present.
    speed_model : {'constant', 'dynamic'}, optional
        Default: ``dynamic`` for a layout with a ``dynamics:`` section, else ``constant``
        (or what the request's tolerance needs).
    load : Load, optional
        The load (default: the layout's ``dynamics:`` section's, else the mean load).
    flywheel : Flywheel, optional
        The flywheel (default: the engine's ``flywheel:`` section).
    figures : bool
        What the figures and the report ask for: without a speed model given, the dynamic
        one wherever it can run (gas forces and a flywheel), so that a design review shows
        what the constant-speed assumption costs.

    Returns
    -------
    Result
        With the part ``dynamics`` (:class:`DynamicsResult` or :class:`ConstantSpeed`).
    """
    given = engine.section("dynamics")
    able = result.part("torque") is not None and (
        flywheel is not None or Flywheel.of(engine) is not None
    )
    if speed_model is None:
        speed_model = "dynamic" if given is not None or (figures and able) else "constant"
    if engine.geared:  # docs/several-crankshafts.md, "Not in this version"
        if speed_model == "dynamic":
            raise InputError(
                "speed_model: the dynamic speed model with several crankshafts is not in this "
                "version"
            )
        return result  # the constant rung's own error bound is one crankshaft's
    if load is None and given is not None:
        load = given
    torque = result.part("torque")
    bound = constant_speed_bound(engine, torque, flywheel) if torque is not None else None
    if speed_model == "constant" and request.tolerance is not None and bound is not None:
        speed_model = bound.speed_model_for(request.tolerance)
    if speed_model == "constant":
        if bound is None:
            return result
        found = bound_warning(bound)
        return result.with_part(
            "dynamics",
            ConstantSpeed(bound),
            warnings=(*result.warnings, *(() if found is None else (found,))),
        )
    settings = settings_of(engine, load, flywheel)
    part = analyse_dynamics(
        engine,
        np.asarray(request.orders, dtype=np.intp),
        settings,
        torque,
        moments=request.moments,
        roll=request.roll,
    )
    part = replace(part, bound=bound)
    return result.with_part("dynamics", part, warnings=(*result.warnings, *part.warnings))


# --------------------------------------------------------------------------- outputs


def _part(result: Any) -> DynamicsResult:
    part: DynamicsResult = result.part("dynamics")
    return part


def _dynamic(result: Any) -> bool:
    """Whether the result holds the dynamic model's solution (not only the bound)."""
    return isinstance(result.part("dynamics"), DynamicsResult)


def _bound(result: Any) -> float:
    bound = result.part("dynamics").bound
    return math.nan if bound is None else float(bound.ratio)


def _moments(result: Any) -> bool:
    return _part(result).has("moment")


def _roll(result: Any) -> bool:
    return _part(result).has("roll")


def _sample(name: str, units: str, long_name: str) -> Output:
    return Output(
        f"dynamics_{name}",
        ("cycle_angle",),
        units,
        long_name,
        lambda r: _part(r).samples()[name],
    )


def _scalar(name: str, units: str, long_name: str, get: Any, **options: Any) -> Output:
    return Output(f"dynamics_{name}", (), units, long_name, lambda r: get(_part(r)), **options)


def _order_outputs(quantity: str) -> tuple[Output, ...]:
    unit = "N" if quantity == "force" else "N m"
    when = _moments if quantity == "moment" else None
    what = "whole free force" if quantity == "force" else "free moment about reference_z"
    return (
        Output(
            f"dynamics_{quantity}_magnitude",
            ("dynamics_order", "rotation"),
            unit,
            f"magnitude of the {what} phasor under the varying crank speed (orders in time)",
            lambda r: _part(r).dynamic.magnitude(quantity),  # type: ignore[arg-type]
            when=when,
        ),
        Output(
            f"dynamics_{quantity}_phase",
            ("dynamics_order", "rotation"),
            "deg",
            f"phase of the {what} phasor against the mean crank angle",
            lambda r: _part(r).dynamic.phase(quantity),  # type: ignore[arg-type]
            when=when,
        ),
        Output(
            f"dynamics_{quantity}_peak",
            ("dynamics_order",),
            unit,
            f"peak {what} per order under the varying crank speed",
            lambda r: _part(r).dynamic.peak(quantity),  # type: ignore[arg-type]
            when=when,
        ),
        Output(
            f"dynamics_{quantity}_peak_constant_speed",
            ("dynamics_order",),
            unit,
            f"peak {what} per order at the constant mean speed",
            lambda r: _part(r).constant_peak(quantity),
            when=when,
        ),
        Output(
            f"dynamics_{quantity}_difference",
            ("dynamics_order",),
            unit,
            "|dP+| + |dP-|: size of the difference from the constant-speed phasors",
            lambda r: _part(r).difference(quantity),
            when=when,
        ),
        Output(
            f"dynamics_largest_{quantity}_difference",
            (),
            "1",
            f"largest {quantity} difference over the orders per the largest constant-speed peak",
            lambda r: _part(r).largest_difference(quantity),
            when=when,
        ),
    )


def _only_dynamic(output: Output) -> Output:
    """An output of the dynamic model's solution: absent from a constant-speed result."""
    when = output.when
    return replace(output, when=lambda r: _dynamic(r) and (when is None or bool(when(r))))


#: The outputs of the dynamic model's solution.
_SOLUTION: tuple[Output, ...] = (
    _scalar("load_kind", "", "dynamics_load_kind", lambda p: p.load.kind, kind="attr"),
    _scalar("load_torque", "N m", "load torque on the crank (cycle mean)", lambda p: p.load_torque),
    _scalar(
        "load_coefficient",
        "N m s2",
        "propeller load coefficient c of T = c w^2",
        lambda p: p.load_coefficient,
        when=lambda r: _part(r).load.kind == "propeller",
    ),
    _scalar("mean_speed", "rad/s", "time-mean crank speed", lambda p: p.mean_speed),
    _scalar("speed_min", "rad/s", "lowest crank speed over the cycle", lambda p: p.speed_min),
    _scalar("speed_max", "rad/s", "highest crank speed over the cycle", lambda p: p.speed_max),
    _scalar(
        "speed_fluctuation",
        "1",
        "speed fluctuation (w_max - w_min)/w_mean of the periodic steady state",
        lambda p: p.speed_fluctuation,
    ),
    _scalar(
        "speed_fluctuation_constant_speed",
        "1",
        "constant-speed estimate A/(J_mean w^2) of the speed fluctuation",
        lambda p: p.speed_fluctuation_constant_speed,
    ),
    _scalar(
        "flywheel_inertia",
        "kg m2",
        "flywheel inertia J_f beyond the layout's masses (given or sized)",
        lambda p: p.flywheel_inertia,
    ),
    _scalar(
        "inertia_min",
        "kg m2",
        "least reduced inertia J over the cycle",
        lambda p: float(np.min(p.inertia)),
    ),
    _scalar(
        "inertia_max",
        "kg m2",
        "largest reduced inertia J over the cycle",
        lambda p: float(np.max(p.inertia)),
    ),
    _scalar(
        "inertia_mean",
        "kg m2",
        "cycle mean of the reduced inertia J",
        lambda p: float(np.mean(p.inertia)),
    ),
    _sample("speed", "rad/s", "crank speed over the cycle"),
    _sample("acceleration", "rad/s2", "crank angular acceleration over the cycle"),
    _sample("time", "s", "time since crank angle 0"),
    _sample("inertia", "kg m2", "reduced inertia J of the crank train (flywheel included)"),
    _sample("gas_torque", "N m", "gas torque Q on the crank"),
    Output(
        "cycle_angle",
        ("cycle_angle",),
        "deg",
        "crank angle over the working cycle, every degree",
        lambda r: _part(r).samples()["crank_angle"],
        kind="coord",
    ),
    Output(
        "dynamics_order",
        ("dynamics_order",),
        "1",
        "order: multiple of the mean crank speed (halves for a four-stroke)",
        lambda r: _part(r).orders,
        kind="coord",
    ),
    *_order_outputs("force"),
    *_order_outputs("moment"),
    Output(
        "dynamics_roll_amplitude",
        ("dynamics_order",),
        "N m",
        "amplitude of the roll torque on the block under the varying crank speed",
        lambda r: _part(r).peak("roll"),
        when=_roll,
    ),
    Output(
        "dynamics_roll_phase",
        ("dynamics_order",),
        "deg",
        "phase of the roll torque against the mean crank angle",
        lambda r: phase_deg(np.asarray(_part(r).dynamic.roll)),
        when=_roll,
    ),
    Output(
        "dynamics_roll_amplitude_constant_speed",
        ("dynamics_order",),
        "N m",
        "amplitude of the roll torque at the constant mean speed",
        lambda r: _part(r).constant_peak("roll"),
        when=_roll,
    ),
    Output(
        "dynamics_roll_difference",
        ("dynamics_order",),
        "N m",
        "|dR|: size of the difference from the constant-speed roll phasor",
        lambda r: _part(r).difference("roll"),
        when=_roll,
    ),
    Output(
        "dynamics_largest_roll_difference",
        (),
        "1",
        "largest roll difference over the orders per the largest constant-speed amplitude",
        lambda r: _part(r).largest_difference("roll"),
        when=_roll,
    ),
)

#: The outputs of the ``dynamics`` section: the speed model and its bound always, the
#: solution's with the dynamic model.
OUTPUTS: tuple[Output, ...] = (
    _scalar("speed_model", "", "dynamics_speed_model", lambda p: p.speed_model, kind="attr"),
    Output(
        "dynamics_speed_bound",
        (),
        "1",
        "bound of the constant-speed model's force error per sum(m r w^2)",
        _bound,
    ),
    *(_only_dynamic(output) for output in _SOLUTION),
)
