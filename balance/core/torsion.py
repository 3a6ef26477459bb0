r"""Torsional vibration of the crank train, as a section of an analysis.

The layout's ``torsion:`` section, a mass-elastic table of the crank train, is a
:class:`~balance.core.torsion_train.TorsionTrain` (:mod:`balance.core.torsion_train`: the
table, its checks and warnings).  This module analyses it (:func:`torsion_analysis`, the
section's part :func:`torsion_part`, docs/torsion.md):

- the inertia of each mass as used: a ``crank_inertia`` plus the mean inertia of the moving
  parts of its cylinders (:func:`balance.core.torsion_excitation.moving_parts_inertia`);
- the undamped modes and the relative amplitude (vector) sums of every mode and order;
- the excitation of each cylinder per order
  (:func:`balance.core.torsion_excitation.excitation`);
- the exact steady state of :math:`M\ddot q + C\dot q + (K + i\eta K_s)q = T` for every
  speed and order, in one batched solve (:mod:`balance.core.torsion_response`), and from it
  the free-end angle, each section's torque and nominal shear stress, each damper's power,
  per order and synthesised (half range over the cycle), and the resonances in the speed
  range;

and declares the section's outputs (:data:`OUTPUTS`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.catalogue import Output
from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.phasors import cancel_to_zero
from balance.core.plausibility import PlausibilityWarning
from balance.core.torsion_excitation import (
    Excitation,
    default_orders,
    default_speeds,
    excitation,
    harmonic_numbers,
    major_orders,
    moving_parts_inertia,
    order_problem,
    place_firing_tdc,
    speed_problem,
)
from balance.core.torsion_response import (
    TrainMatrices,
    coupling_power,
    half_range,
    harmonic_response,
    normal_modes,
    vector_sums,
)
from balance.core.torsion_train import (
    Shaft,
    TorsionDamper,
    TorsionMass,
    TorsionTrain,
    TrainProblem,
    by_part_cylinders,
    check_train,
    mass_inertias,
    resolve_mass,
    torsion_warnings,
    train_matrices,
    train_problems,
)

__all__ = [
    "OUTPUTS",
    "Resonance",
    "Shaft",
    "TorsionDamper",
    "TorsionMass",
    "TorsionResult",
    "TorsionTrain",
    "TrainProblem",
    "default_orders",
    "default_speeds",
    "mass_inertias",
    "order_problem",
    "place_firing_tdc",
    "resolve_mass",
    "speed_problem",
    "torsion_analysis",
    "torsion_part",
    "torsion_warnings",
    "train_matrices",
    "train_problems",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass(frozen=True)
class Resonance:
    """An order meeting a natural frequency inside the speed range.

    Attributes
    ----------
    mode : int
        The mode (1-based).
    order : float
        The order.
    speed : float
        The crank speed at which order times speed is the natural frequency [rad/s].
    vector_sum : float
        The relative amplitude sum of that mode and order.
    free_end : float or None
        Amplitude of that order's free-end angle at that speed [rad]; None undamped.
    section : int or None
        The section (1-based) with the largest torque of that order there.
    section_torque : float or None
        Its torque amplitude [N m].
    """

    mode: int
    order: float
    speed: float
    vector_sum: float
    free_end: float | None = None
    section: int | None = None
    section_torque: float | None = None


@dataclass(frozen=True, eq=False)
class TorsionResult:
    """The ``torsion`` section's part: modes, excitation and response (SI, radians).

    Response arrays are None for an undamped train (unbounded at every resonance).

    Attributes
    ----------
    train : TorsionTrain
        The table analysed.
    cycle : str
        ``"four-stroke"`` or ``"two-stroke"``.
    speeds : ndarray, shape (S,)
        Crank speeds [rad/s].
    orders : ndarray, shape (K,)
        Orders.
    inertias : ndarray, shape (n,)
        Each mass's inertia as used [kg m^2].
    moving_inertia : ndarray, shape (c,)
        Mean inertia of each cylinder's moving parts [kg m^2] (added to a
        ``crank_inertia`` mass); NaN for a cylinder with lumped masses.
    cylinder_mass : ndarray of int, shape (c,)
        The mass (0-based) each cylinder is on.
    excitation : Excitation
        Each cylinder's torque per order.
    frequencies : ndarray, shape (m,)
        Undamped natural frequencies [Hz], ascending.
    shapes : ndarray, shape (m, n + t)
        Mode shapes at the masses and the tuned rings, +1 at mass 1.
    stations : tuple of str
        Names of the shape's entries (the masses, then ``"damper r ring"``).
    vector_sums : ndarray, shape (m, K)
        Relative amplitude sums.
    major : ndarray of bool, shape (K,)
        Major orders (every cylinder in phase).
    resonances : tuple of Resonance
        Every mode and order meeting in the speed range, by speed.
    free_end : ndarray of complex, shape (K, S), or None
        Angle of mass 1 per order [rad]: :math:`\\operatorname{Re}(Q e^{ik\\theta})`.
    free_end_synthesis : ndarray, shape (S,), or None
        Half range of the free-end angle over the cycle [rad].
    section_torque : ndarray of complex, shape (J, K, S), or None
        Elastic torque :math:`k_j(q_j - q_{j+1})` per order [N m].
    section_torque_synthesis : ndarray, shape (J, S), or None
        Its half range over the cycle [N m].
    stress_factor : ndarray, shape (J,)
        Nominal shear stress per torque [Pa/(N m)]; NaN without a diameter.
    damper_power : ndarray, shape (D, K, S), or None
        Mean power dissipated in each damper's coupling per order [W].
    warnings : tuple of PlausibilityWarning
        The torsion warnings (:func:`torsion_warnings`).
    reference_speed : float
        The layout's speed [rad/s], the reference of the inertia excitation.
    """

    train: TorsionTrain
    cycle: str
    speeds: FloatArray
    orders: FloatArray
    inertias: FloatArray
    moving_inertia: FloatArray
    cylinder_mass: NDArray[np.intp]
    excitation: Excitation
    frequencies: FloatArray
    shapes: FloatArray
    stations: tuple[str, ...]
    vector_sums: FloatArray
    major: NDArray[np.bool_]
    resonances: tuple[Resonance, ...]
    free_end: ComplexArray | None
    free_end_synthesis: FloatArray | None
    section_torque: ComplexArray | None
    section_torque_synthesis: FloatArray | None
    stress_factor: FloatArray
    damper_power: FloatArray | None
    warnings: tuple[PlausibilityWarning, ...]
    reference_speed: float

    @property
    def damped(self) -> bool:
        """Whether the response was computed (the train has damping)."""
        return self.free_end is not None

    @property
    def section_stress(self) -> FloatArray | None:
        """Nominal shear stress amplitude per section, order and speed [Pa] (NaN without a
        diameter); None undamped."""
        if self.section_torque is None:
            return None
        return np.asarray(np.abs(self.section_torque) * self.stress_factor[:, None, None])

    @property
    def section_stress_synthesis(self) -> FloatArray | None:
        """Half range of the nominal shear stress per section and speed [Pa]; None
        undamped."""
        if self.section_torque_synthesis is None:
            return None
        return np.asarray(self.section_torque_synthesis * self.stress_factor[:, None])

    @property
    def damper_power_total(self) -> FloatArray | None:
        """Each damper's power summed over the orders, per speed [W]; None undamped."""
        if self.damper_power is None:
            return None
        return np.asarray(np.sum(self.damper_power, axis=1))


def _resonances(
    frequencies: FloatArray, orders: FloatArray, speeds: FloatArray
) -> list[tuple[int, int, float]]:
    """(mode, order index, speed [rad/s]) of every mode and order meeting inside the speed
    range, by speed."""
    low, high = float(np.min(speeds)), float(np.max(speeds))
    meet = 2.0 * math.pi * np.asarray(frequencies)[:, None] / np.asarray(orders)[None, :]
    j, i = np.nonzero((meet >= low) & (meet <= high) & (np.asarray(frequencies) > 0)[:, None])
    found = [(int(a), int(b), float(meet[a, b])) for a, b in zip(j, i, strict=True)]
    found.sort(key=lambda item: (item[2], item[0], item[1]))
    return found


def torsion_analysis(
    engine: Engine,
    train: TorsionTrain,
    speeds: ArrayLike | None = None,
    orders: ArrayLike | None = None,
    *,
    torque: Any = None,
) -> TorsionResult:
    """The torsional vibration of an engine's crank train (docs/torsion.md).

    Parameters
    ----------
    engine : Engine
        The engine, at the reference speed of the inertia excitation.
    train : TorsionTrain
        Its mass-elastic table.
    speeds : array_like, optional
        Crank speeds [rad/s]; default :func:`default_speeds` of the engine's speed.
    orders : array_like, optional
        Orders; default :func:`default_orders` of its cycle.
    torque : TorqueResult, optional
        The engine's gas torque over the cycle, when already computed.

    Returns
    -------
    TorsionResult

    Raises
    ------
    InputError
        For a train that cannot be analysed (:func:`train_problems`), or bad orders or
        speeds.
    """
    check_train(train, engine)
    w = default_speeds(engine.speed) if speeds is None else np.asarray(speeds, dtype=np.float64)
    w = np.asarray(w, dtype=np.float64).reshape(-1)
    k = default_orders(engine.cycle) if orders is None else np.asarray(orders, dtype=np.float64)
    k = np.asarray(k, dtype=np.float64).reshape(-1)
    for problem in (speed_problem(w), order_problem(k, engine.cycle)):
        if problem is not None:
            raise InputError(f"{engine.name}: torsion: {problem}")
    k = np.sort(k)
    firing = (
        np.asarray(train.firing_tdc, dtype=np.float64)
        if train.firing_tdc is not None
        else np.asarray(place_firing_tdc(engine), dtype=np.float64)
    )
    moving = np.where(by_part_cylinders(engine), moving_parts_inertia(engine), np.nan)
    inertias = mass_inertias(engine, train, moving)
    matrices = train_matrices(train, inertias)
    frequencies, shapes = normal_modes(matrices)
    cyl_mass = train.cylinder_masses(engine.n_cylinders)
    sums = vector_sums(shapes, cyl_mass, firing, k)
    exc = excitation(engine, k, firing, torque=torque)
    meets = _resonances(frequencies, k, w)
    stress = np.array([s.stress_factor for s in train.sections], dtype=np.float64)
    stations = tuple(m.name for m in train.masses) + tuple(
        f"damper {r + 1} ring" for r, d in enumerate(train.dampers) if d.kind == "tuned"
    )
    response = _response(engine, train, matrices, exc, w, k, meets) if matrices.damped else None
    resonances = tuple(
        Resonance(j + 1, float(k[i]), wr, float(sums[j, i]))
        if response is None
        else Resonance(
            j + 1,
            float(k[i]),
            wr,
            float(sums[j, i]),
            float(np.abs(response["resonance_free_end"][n])),
            int(response["resonance_section"][n]) + 1,
            float(response["resonance_torque"][n]),
        )
        for n, (j, i, wr) in enumerate(meets)
    )
    warnings = torsion_warnings(engine, train, inertias)
    return TorsionResult(
        train=train,
        cycle=engine.cycle,
        speeds=w,
        orders=k,
        inertias=inertias,
        moving_inertia=moving,
        cylinder_mass=cyl_mass,
        excitation=exc,
        frequencies=frequencies,
        shapes=shapes,
        stations=stations,
        vector_sums=sums,
        major=major_orders(firing, k),
        resonances=resonances,
        free_end=None if response is None else response["free_end"],
        free_end_synthesis=None if response is None else response["free_end_synthesis"],
        section_torque=None if response is None else response["torque"],
        section_torque_synthesis=None if response is None else response["torque_synthesis"],
        stress_factor=stress,
        damper_power=None if response is None else response["power"],
        warnings=warnings,
        reference_speed=float(engine.speed),
    )


def _response(
    engine: Engine,
    train: TorsionTrain,
    matrices: TrainMatrices,
    exc: Excitation,
    speeds: FloatArray,
    orders: FloatArray,
    meets: list[tuple[int, int, float]],
) -> dict[str, Any]:
    """The steady state at every speed and order and at every resonance, in one solve."""
    n, size = train.n_masses, matrices.size
    cyl_mass = train.cylinder_masses(engine.n_cylinders)
    to_mass = np.zeros((engine.n_cylinders, size))
    to_mass[np.arange(engine.n_cylinders), cyl_mass] = 1.0
    res_speed = np.array([wr for _, _, wr in meets], dtype=np.float64)
    res_order = np.array([i for _, i, _ in meets], dtype=np.intp)
    all_speeds = np.concatenate([speeds, res_speed])
    # each part's torques summed on the masses, once: what cancels on a mass by symmetry
    # is exactly zero (the gas part holds at every speed, the inertia part scales)
    on_mass = [
        None
        if part is None
        else cancel_to_zero(part @ to_mass, np.abs(part) @ to_mass, engine.n_cylinders)
        for part in exc.crank_parts()
    ]  # (K, size) each
    gas, inertia = on_mass
    assert inertia is not None
    forces = inertia[None] * exc.speed_scale(all_speeds)[:, None, None]  # (S + R, K, size)
    if gas is not None:
        forces = forces + gas[None]
    grid_forces = forces[: speeds.size]
    res_forces = forces[speeds.size + np.arange(res_speed.size), res_order]
    grid_freq = np.outer(speeds, orders)  # (S, K)
    res_freq = res_speed * orders[res_order]
    stacked_freq = np.concatenate([grid_freq.reshape(-1), res_freq])
    stacked = np.concatenate([grid_forces.reshape(-1, size), res_forces])
    q = harmonic_response(matrices, stacked_freq, stacked)
    grid = q[: grid_freq.size].reshape(speeds.size, orders.size, size)
    at_res = q[grid_freq.size :]
    k_sec = np.array([s.stiffness for s in train.sections], dtype=np.float64)
    twist = grid[..., : n - 1] - grid[..., 1:n]  # (S, K, J)
    torque = np.transpose(k_sec * twist, (2, 1, 0))  # (J, K, S)
    free_end = grid[..., 0].T  # (K, S)
    harmonics = harmonic_numbers(orders, engine.cycle)
    series = np.concatenate([free_end.T[None], np.transpose(torque, (0, 2, 1))])  # (1+J, S, K)
    synthesis = half_range(series, harmonics)
    free_syn, torque_syn = synthesis[0], synthesis[1:]
    power = np.zeros((len(train.dampers), orders.size, speeds.size))
    for r, damper in enumerate(train.dampers):
        hub, ring = grid[..., damper.at - 1], grid[..., n + r]
        power[r] = coupling_power(grid_freq, damper.damping, hub, ring).T
    res_torque = np.abs(k_sec * (at_res[:, : n - 1] - at_res[:, 1:n]))
    return {
        "free_end": free_end,
        "free_end_synthesis": free_syn,
        "torque": torque,
        "torque_synthesis": torque_syn,
        "power": power,
        "resonance_free_end": at_res[:, 0],
        "resonance_section": np.argmax(res_torque, axis=1) if res_torque.size else [],
        "resonance_torque": np.max(res_torque, axis=1) if res_torque.size else [],
    }


# --------------------------------------------------------------------------- the section


def _speeds_option(engine: Engine, speeds: ArrayLike | str | None) -> FloatArray:
    if isinstance(speeds, str) and speeds in ("default", "sweep", "figure"):
        return default_speeds(engine.speed)
    if speeds is None or isinstance(speeds, str):
        if speeds is None or speeds == "analysis":
            return np.array([engine.speed])
        raise InputError(f"torsion speeds {speeds!r}: give speeds [rad/s], 'analysis' or 'sweep'")
    return np.asarray(speeds, dtype=np.float64).reshape(-1)


def torsion_part(
    engine: Engine,
    request: Any,
    result: Any,
    *,
    speeds: ArrayLike | str | None = None,
    orders: ArrayLike | None = None,
) -> Any:
    """The ``torsion`` section: the torsional vibration of the crank train
    (:func:`torsion_analysis`) of the layout's ``torsion:`` section.

    Parameters
    ----------
    engine : Engine
        The engine (at the analysis speed, the reference of the inertia excitation), with
        its ``torsion`` section (a :class:`TorsionTrain`).
    request : Request
        Not read (the section's options come as keywords).
    result : Result
        The analysis so far; its ``torque`` part, when there, gives the gas torque.
    speeds : array_like or str, optional
        Crank speeds [rad/s]; ``"sweep"``: 200 from 20 % to 120 % of the engine's speed
        (:func:`default_speeds`, what ``balance torsion`` and the figures take); default
        (None, ``"analysis"``): the engine's speed alone (``balance analyse``).
    orders : array_like, optional
        Orders; default every half order from 0.5 to 12 (four-stroke), 1 to 12
        (two-stroke).

    Returns
    -------
    Result
        With the part ``torsion`` (:class:`TorsionResult`) and its warnings added to the
        result's.

    Raises
    ------
    InputError
        Without a ``torsion`` section, or for one that cannot be analysed.
    """
    del request
    if engine.geared:  # docs/several-crankshafts.md, "Not in this version"
        raise InputError(
            "torsion: torsional vibration with several crankshafts is not in this version"
        )
    train = engine.section("torsion")
    if train is None:
        where = f" ({engine.path})" if engine.path else ""
        raise InputError(
            f"layout '{engine.name}'{where} has no torsion: section, so its torsional "
            "vibration cannot be computed; add one (docs/torsion.md)"
        )
    part = torsion_analysis(
        engine, train, _speeds_option(engine, speeds), orders, torque=result.part("torque")
    )
    return result.with_part("torsion", part, warnings=tuple(result.warnings) + part.warnings)


# --------------------------------------------------------------------------- outputs


def _part(result: Any) -> TorsionResult:
    part: TorsionResult = result.part("torsion")
    return part


def _damped(result: Any) -> bool:
    return _part(result).damped


def _has_dampers(result: Any) -> bool:
    return bool(_part(result).train.dampers)


def _has_gas(result: Any) -> bool:
    return _part(result).excitation.gas is not None


def _rpm(speed: ArrayLike) -> FloatArray:
    from balance.core.catalogue import speed_rpm

    return np.array([speed_rpm(float(w)) for w in np.atleast_1d(speed)], dtype=np.float64)


def _out(
    name: str, dims: tuple[str, ...], units: str, long_name: str, get: Any, when: Any = None
) -> Output:
    return Output(name, dims, units, long_name, lambda r: get(_part(r)), when=when)


def _coord(name: str, units: str, long_name: str, get: Any, when: Any = None) -> Output:
    return Output(name, (name,), units, long_name, lambda r: get(_part(r)), kind="coord", when=when)


def _amplitude_deg(values: ComplexArray | None) -> FloatArray:
    assert values is not None
    return np.asarray(np.degrees(np.abs(values)))


def _phase_deg(values: ComplexArray | None) -> FloatArray:
    from balance.core.phasors import phase_deg

    assert values is not None
    return phase_deg(values)


def _resonance_field(name: str) -> Any:
    def get(t: TorsionResult) -> FloatArray:
        values = [getattr(r, name) for r in t.resonances]
        return np.array([math.nan if v is None else v for v in values], dtype=np.float64)

    return get


_SPEED = "torsion_speed"
_ORDER = "torsion_order"
_SECTION = "torsion_section"
_DAMPER = "torsion_damper"
_MODE = "torsion_mode"
_RES = "torsion_resonance"


#: The outputs of the ``torsion`` section (docs/torsion.md).
OUTPUTS: tuple[Output, ...] = (
    _out(
        "torsion_mass_inertia",
        ("torsion_mass",),
        "kg m2",
        "inertia of each mass as used (crank_inertia plus the mean of the moving parts)",
        lambda t: t.inertias,
    ),
    _out(
        "torsion_mass_name",
        ("torsion_mass",),
        "",
        "name of each mass of the torsion table, free end first",
        lambda t: np.array([m.name for m in t.train.masses]),
    ),
    _out(
        "torsion_moving_inertia",
        ("cylinder",),
        "kg m2",
        "mean inertia of each cylinder's piston group and rod about the crank axis "
        "(NaN with lumped masses)",
        lambda t: t.moving_inertia,
    ),
    _out(
        "torsion_section_stiffness",
        (_SECTION,),
        "N m/rad",
        "torsional stiffness of the shaft section from mass j to mass j + 1",
        lambda t: np.array([s.stiffness for s in t.train.sections]),
    ),
    _out(
        "torsion_section_diameter",
        (_SECTION,),
        "m",
        "outer diameter of the shaft section for the nominal stress (NaN: none given)",
        lambda t: np.array(
            [math.nan if s.diameter is None else s.diameter for s in t.train.sections]
        ),
    ),
    _out(
        "torsion_mode_frequency",
        (_MODE,),
        "Hz",
        "undamped natural frequency of the torsion train (rigid-body mode left out)",
        lambda t: t.frequencies,
    ),
    _out(
        "torsion_mode_shape",
        (_MODE, "torsion_station"),
        "1",
        "mode shape at the masses and the tuned damper rings, +1 at mass 1",
        lambda t: t.shapes,
    ),
    _out(
        "torsion_vector_sum",
        (_MODE, _ORDER),
        "1",
        "relative amplitude (vector) sum |sum_c phi(mass of c) exp(-i k theta_c)|",
        lambda t: t.vector_sums,
    ),
    _out(
        "torsion_major_order",
        (_ORDER,),
        "1",
        "1 where every cylinder's excitation of the order is in phase (a major order)",
        lambda t: t.major.astype(np.int64),
    ),
    _out(
        "torsion_firing_tdc",
        ("cylinder",),
        "deg",
        "crank angle of each cylinder's firing TDC",
        lambda t: t.excitation.firing_tdc,
    ),
    _out(
        "torsion_excitation_inertia_amplitude",
        ("cylinder", _ORDER),
        "N m",
        "amplitude of the moving parts' tangential torque per order at the reference speed",
        lambda t: np.abs(t.excitation.inertia),
    ),
    _out(
        "torsion_excitation_inertia_phase",
        ("cylinder", _ORDER),
        "deg",
        "phase of the moving parts' torque per order in the angle from the firing TDC",
        lambda t: _phase_deg(t.excitation.inertia),
    ),
    _out(
        "torsion_excitation_gas_amplitude",
        ("cylinder", _ORDER),
        "N m",
        "amplitude of the gas part of the tangential torque per order (every speed)",
        lambda t: np.abs(t.excitation.gas),
        when=_has_gas,
    ),
    _out(
        "torsion_excitation_gas_phase",
        ("cylinder", _ORDER),
        "deg",
        "phase of the gas torque per order in the angle from the firing TDC",
        lambda t: _phase_deg(t.excitation.gas),
        when=_has_gas,
    ),
    _out(
        "torsion_tangential_pressure",
        ("cylinder", _ORDER),
        "bar",
        "gas torque amplitude per piston area and crank radius",
        lambda t: t.excitation.tangential_pressure / 1e5,
        when=_has_gas,
    ),
    _out(
        "torsion_free_end_amplitude",
        (_ORDER, _SPEED),
        "deg",
        "amplitude a of the free end's angle a cos(k theta + phase) per order",
        lambda t: _amplitude_deg(t.free_end),
        when=_damped,
    ),
    _out(
        "torsion_free_end_phase",
        (_ORDER, _SPEED),
        "deg",
        "phase of the free end's angle per order (0 where the amplitude is 0)",
        lambda t: _phase_deg(t.free_end),
        when=_damped,
    ),
    _out(
        "torsion_free_end_synthesis",
        (_SPEED,),
        "deg",
        "half range (max - min)/2 over the cycle of the free end's angle, all orders",
        lambda t: np.degrees(t.free_end_synthesis),
        when=_damped,
    ),
    _out(
        "torsion_section_torque_amplitude",
        (_SECTION, _ORDER, _SPEED),
        "N m",
        "amplitude of the elastic torque in each shaft section per order",
        lambda t: np.abs(t.section_torque),
        when=_damped,
    ),
    _out(
        "torsion_section_torque_synthesis",
        (_SECTION, _SPEED),
        "N m",
        "half range over the cycle of the elastic torque in each section, all orders",
        lambda t: t.section_torque_synthesis,
        when=_damped,
    ),
    _out(
        "torsion_section_stress_amplitude",
        (_SECTION, _ORDER, _SPEED),
        "MPa",
        "amplitude of the nominal shear stress 16 T d / (pi (d^4 - d_i^4)) per order",
        lambda t: t.section_stress / 1e6,
        when=_damped,
    ),
    _out(
        "torsion_section_stress_synthesis",
        (_SECTION, _SPEED),
        "MPa",
        "half range over the cycle of the nominal shear stress, all orders",
        lambda t: t.section_stress_synthesis / 1e6,
        when=_damped,
    ),
    _out(
        "torsion_damper_power",
        (_DAMPER, _ORDER, _SPEED),
        "W",
        "mean power dissipated in each damper's coupling per order",
        lambda t: t.damper_power,
        when=lambda r: _damped(r) and _has_dampers(r),
    ),
    _out(
        "torsion_damper_power_total",
        (_DAMPER, _SPEED),
        "W",
        "mean power dissipated in each damper's coupling, all orders",
        lambda t: t.damper_power_total,
        when=lambda r: _damped(r) and _has_dampers(r),
    ),
    _out(
        "torsion_resonance_mode",
        (_RES,),
        "1",
        "mode of each resonance (order times speed equal to the natural frequency)",
        lambda t: np.array([r.mode for r in t.resonances], dtype=np.int64),
    ),
    _out(
        "torsion_resonance_order",
        (_RES,),
        "1",
        "order of each resonance",
        lambda t: np.array([r.order for r in t.resonances], dtype=np.float64),
    ),
    _out(
        "torsion_resonance_speed",
        (_RES,),
        "rpm",
        "crank speed of each resonance, 60 f / k",
        lambda t: _rpm([r.speed for r in t.resonances]) if t.resonances else np.zeros(0),
    ),
    _out(
        "torsion_resonance_vector_sum",
        (_RES,),
        "1",
        "relative amplitude sum of each resonance's mode and order",
        _resonance_field("vector_sum"),
    ),
    _out(
        "torsion_resonance_free_end",
        (_RES,),
        "deg",
        "free end's amplitude of the resonance's order at its speed (NaN undamped)",
        lambda t: np.degrees(_resonance_field("free_end")(t)),
    ),
    _out(
        "torsion_resonance_section",
        (_RES,),
        "1",
        "section with the largest torque of the order at the resonance (NaN undamped)",
        _resonance_field("section"),
    ),
    _out(
        "torsion_resonance_section_torque",
        (_RES,),
        "N m",
        "that section's torque amplitude at the resonance (NaN undamped)",
        _resonance_field("section_torque"),
    ),
    _out(
        "torsion_reference_speed",
        (),
        "rpm",
        "the layout's speed: the inertia excitation is given at it, scaling with speed^2",
        lambda t: float(_rpm(t.reference_speed)[0]),
    ),
    _coord(_SPEED, "rpm", "crank speed of the torsion response", lambda t: _rpm(t.speeds)),
    _coord(_ORDER, "1", "order of the torsional excitation", lambda t: t.orders),
    _coord(
        "torsion_mass",
        "1",
        "mass number, free end first",
        lambda t: np.arange(1, t.train.n_masses + 1),
    ),
    _coord(
        _SECTION,
        "1",
        "shaft section number (section j joins masses j and j + 1)",
        lambda t: np.arange(1, t.train.n_masses),
    ),
    _coord(_MODE, "1", "torsional mode number", lambda t: np.arange(1, t.frequencies.size + 1)),
    _coord(
        "torsion_station",
        "",
        "mass or tuned damper ring of a mode shape",
        lambda t: np.array(t.stations),
    ),
    _coord(
        _DAMPER,
        "1",
        "damper number",
        lambda t: np.arange(1, len(t.train.dampers) + 1),
        when=_has_dampers,
    ),
    _coord(_RES, "1", "resonance number, by speed", lambda t: np.arange(1, len(t.resonances) + 1)),
)
