r"""Cylinder pressure: a measured trace (CSV) or a parametric model, and firing TDCs.

The pressure of a cylinder is a function of its *cycle angle* :math:`\alpha` [deg], the crank
angle since its firing top dead centre, periodic over the cycle (720 deg four-stroke, 360 deg
two-stroke).  It comes either from a CSV file (``gas: pressure_trace:``, read by
:mod:`balance.io.traces`) or from the parametric model of :func:`model_pressure`
(``gas: model:``).

The parametric model
--------------------
Cylinder volume :math:`V(\alpha) = V_c + A\,(s_{max} - s(\alpha))` with :math:`s` the piston
pin's distance from the crank axis (offset included), :math:`s_{max} = \sqrt{(l+r)^2-e^2}`,
swept volume :math:`V_s = A(s_{max}-s_{min})` and clearance :math:`V_c = V_s/(\varepsilon-1)`.
The cycle angle :math:`\alpha` is counted from the cylinder's actual top dead centre (its
piston farthest out, :func:`firing_tdc`), offset or link rod included; the model's strokes
are 180 deg of crank angle each.

* intake stroke (four-stroke only, :math:`-360 \le \alpha < -180`): :math:`p = p_{in}`;
* compression from bottom dead centre, polytropic: :math:`p = p_{in}(V_{BDC}/V)^{n_1}`;
* from the start of combustion :math:`\alpha_s` the first law with a polytropic exponent
  :math:`n_2` (heat loss lumped into it), :math:`\mathrm{d}(pV^{n_2}) =
  (n_2-1)V^{n_2-1}\,\mathrm{d}Q`, with the Wiebe burnt fraction
  :math:`x_b = 1 - \exp(-a\,((\alpha-\alpha_s)/\Delta\alpha)^{m+1})`, :math:`Q = Q_{tot} x_b`;
* at bottom dead centre (exhaust opens) the pressure falls to :math:`p_{ex}` for the exhaust
  stroke (four-stroke); a two-stroke's cycle closes at bottom dead centre.

:math:`Q_{tot}` is given (``heat_released``) or found by bisection so that the largest
pressure equals ``peak_pressure``.

.. rubric:: References

Heywood, *Internal Combustion Engine Fundamentals*, McGraw-Hill 1988, sec. 9.2 (Wiebe
function, single-zone heat release) and 5.7; Wiebe, *Brennverlauf und Kreisprozess von
Verbrennungsmotoren*, VEB Verlag Technik 1970; Kolchin and Demidov, *Design of Automotive
Engines*, Mir 1984 (indicator diagram, gas force :math:`P_g = (p - p_0)F_p`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.kinematics import normalised_slider, offset_ratio, rod_ratio

__all__ = [
    "GasInput",
    "GasModel",
    "PistonTravel",
    "cycle_degrees",
    "cylinder_pressure",
    "cylinder_volume",
    "firing_tdc",
    "model_pressure",
    "periodic_tables",
    "piston_gas_force",
    "pressure_at",
    "pressure_tables",
]

FloatArray = NDArray[np.float64]

#: Step of the model's pressure table [deg].
MODEL_STEP_DEG = 0.05


def cycle_degrees(cycle: str) -> float:
    """Crank angle of one working cycle: 720 four-stroke, 360 two-stroke.

    Parameters
    ----------
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle.

    Returns
    -------
    float
        The cycle [deg].
    """
    return 720.0 if cycle == "four-stroke" else 360.0


@dataclass(frozen=True)
class GasModel:
    """Parameters of the parametric cylinder pressure (``gas: model:``), SI units.

    Angles are crank angles from firing TDC [deg]; pressures absolute [Pa]; exactly one of
    ``heat_released`` [J per cylinder and cycle] and ``peak_pressure`` [Pa] is given.
    """

    compression_ratio: float
    intake_pressure: float = 1.0e5
    exhaust_pressure: float = 1.1e5
    polytropic_compression: float = 1.35
    polytropic_expansion: float = 1.28
    combustion_start: float = -15.0
    combustion_duration: float = 55.0
    wiebe_a: float = 5.0
    wiebe_m: float = 2.0
    heat_released: float | None = None
    peak_pressure: float | None = None


@dataclass(frozen=True, eq=False)
class GasInput:
    """The ``gas:`` and ``flywheel:`` sections, resolved (SI units, angles in degrees).

    Attributes
    ----------
    angle, pressure : ndarray or None
        The pressure trace: cycle angle from firing TDC [deg], strictly increasing over less
        than one cycle, and absolute pressure [Pa]; None with the parametric model.
    model : GasModel or None
        The parametric model's parameters.
    crankcase_pressure : float
        Pressure under the piston, :math:`p_0` [Pa].
    bore : float
        Bore [m].
    firing_tdc : ndarray
        Crank angle :math:`\\theta` at which each cylinder is at its firing TDC [deg], in
        [0, cycle).
    cycle_deg : float
        720 (four-stroke) or 360 (two-stroke) [deg].
    flywheel_inertia, speed_fluctuation : float or None
        The ``flywheel:`` section: inertia of the rotating assembly [kg m^2] or the allowed
        speed fluctuation :math:`\\delta` [1].
    source : str
        The trace file, or ``"model"``.
    """

    angle: FloatArray | None
    pressure: FloatArray | None
    model: GasModel | None
    crankcase_pressure: float
    bore: float
    firing_tdc: FloatArray
    cycle_deg: float
    flywheel_inertia: float | None = None
    speed_fluctuation: float | None = None
    source: str = "model"

    @property
    def piston_area(self) -> float:
        """Piston area :math:`\\pi B^2/4` [m^2]."""
        return math.pi / 4.0 * self.bore**2

    def reordered(self, idx: NDArray[np.intp]) -> GasInput:
        """The same input with the cylinders renumbered."""
        return replace(self, firing_tdc=self.firing_tdc[idx])


# --------------------------------------------------------------------------- firing TDC


def firing_tdc(
    throw_deg: FloatArray,
    bank_deg: FloatArray,
    cycle: str,
    firing_order: tuple[int, ...] | None,
    tdc_given: list[float | None] | None,
    tdc_lag: FloatArray | None = None,
) -> FloatArray | str:
    r"""Crank angle of each cylinder's firing TDC [deg], or a message saying what is missing.

    A cylinder's cycle starts at its actual top dead centre, where its piston pin is farthest from
    the crank axis (where the cylinder volume is smallest, and where a measured trace's crank angle
    is counted from): :math:`\theta = \psi_i - \varphi_i + \beta_{TDC,i}` (mod 360), with
    :math:`\beta_{TDC,i}` (``tdc_lag``, in (-180, 180]) how far it lies after the nominal TDC
    :math:`\theta + \varphi_i - \psi_i = 0` of docs/conventions.md, "Frame and angles":
    :math:`\arcsin(e/(l + r))` for an offset plain cylinder, the link piston's own for a link
    cylinder (:func:`balance.core.cylinders.dead_centre_lag`), 0 without offset or link.  A
    two-stroke fires at every TDC.  A four-stroke fires at one of two TDCs 360 deg apart: the first
    cylinder of ``firing_order`` at its TDC in [0, 360), each next one at its first TDC after the
    one before; without a firing order, each cylinder's ``tdc`` angle (mod 720) when every cylinder
    gives one.  A ``tdc`` given in the layout is the nominal TDC (it defines the throw, ``throw =
    bank - tdc``, docs/layout-format.md, "Explicit form"); the cylinder then fires at ``tdc`` +
    :math:`\beta_{TDC}`.

    Parameters
    ----------
    throw_deg, bank_deg : ndarray
        Each cylinder's throw :math:`\varphi_i` and bank :math:`\psi_i` [deg].
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle.
    firing_order : tuple of int or None
        Cylinder numbers (1-based) in firing order, if the layout gives one.
    tdc_given : list of (float or None), optional
        Each cylinder's ``tdc`` from the layout [deg] (None where it gives a ``throw``).
    tdc_lag : ndarray, optional
        :math:`\beta_{TDC,i}` [deg]; default 0 for every cylinder.

    Returns
    -------
    ndarray or str
        Angles in [0, cycle) [deg]; a string (the problem) when they cannot be placed.
    """
    base = np.mod(np.asarray(bank_deg) - np.asarray(throw_deg), 360.0)
    base = np.where(np.isclose(base, 360.0, rtol=0, atol=1e-9), 0.0, base)
    shift = np.zeros(base.shape)
    if tdc_lag is not None:
        shift = np.mod(np.asarray(tdc_lag, dtype=np.float64) + 180.0, 360.0) - 180.0
        base = np.mod(base + shift, 360.0)
        base = np.where(np.isclose(base, 360.0, rtol=0, atol=1e-9), 0.0, base)
    if cycle == "two-stroke":
        return np.asarray(base, dtype=np.float64)
    n = base.size
    if firing_order is not None:
        out = np.zeros(n)
        first = firing_order[0] - 1
        previous = float(base[first])
        out[first] = previous
        for cyl in firing_order[1:]:
            i = cyl - 1
            candidate = previous + np.mod(base[i] - previous, 360.0)
            if candidate <= previous + 1e-9:
                candidate += 360.0
            out[i] = candidate
            previous = candidate
        if previous >= out[first] + 720.0 - 1e-9:
            order = "-".join(map(str, firing_order))
            return (
                f"firing order {order} does not fit in one 720 deg cycle with these throws "
                f"(cylinder {firing_order[-1]} would fire {previous - out[first]:g} deg after "
                f"cylinder {firing_order[0]})"
            )
        return np.asarray(np.mod(out, 720.0), dtype=np.float64)
    if tdc_given is not None and all(t is not None for t in tdc_given):
        return np.asarray(np.mod(np.asarray(tdc_given, dtype=np.float64) + shift, 720.0))
    return (
        "a four-stroke with gas forces needs the firing order, to tell the firing TDC from "
        "the TDC 360 deg away"
    )


# --------------------------------------------------------------------------- model


@dataclass(frozen=True)
class PistonTravel:
    """Where a piston pin is against its cycle angle, for a cylinder that is no plain crank
    slider (a link piston, :func:`balance.core.torque.piston_travels`).

    Attributes
    ----------
    position : callable
        Cycle angle from the cylinder's (actual) top dead centre [deg] -> the piston pin's
        distance from the crank axis [m].
    top, bottom : float
        That distance at the top and bottom dead centres [m].
    key : tuple of float
        The geometry the travel depends on: equal keys, equal travels (for caching).
    """

    position: Callable[[FloatArray], FloatArray]
    top: float
    bottom: float
    key: tuple[float, ...] = ()


def cylinder_volume(
    alpha_deg: FloatArray,
    bore: float,
    radius: float,
    length: float,
    offset: float,
    ratio: float,
    travel: PistonTravel | None = None,
) -> FloatArray:
    r"""Cylinder volume at cycle angle ``alpha_deg`` for compression ratio ``ratio``.

    :math:`V = V_s/(\varepsilon - 1) + A(s_{max} - s)`, :math:`V_s = A(s_{max} - s_{min})`;
    with ``travel`` (a link piston) :math:`s`, :math:`s_{max}` and :math:`s_{min}` are its.
    The cycle angle is counted from the actual top dead centre: a plain cylinder's crank
    angle from its nominal TDC direction is :math:`\beta = \alpha + \arcsin(e/(l + r))`, so
    that the volume is smallest at :math:`\alpha = 0` with an offset too.

    Parameters
    ----------
    alpha_deg : ndarray
        Cycle angles from the actual top dead centre [deg].
    bore, radius, length, offset : float
        Bore, crank radius, conrod length and offset of the cylinder [m].
    ratio : float
        Compression ratio :math:`\varepsilon` [1], more than 1.
    travel : PistonTravel, optional
        The piston's travel when it is no plain crank slider (a link piston).

    Returns
    -------
    ndarray
        :math:`V` [m^3], the shape of ``alpha_deg``.
    """
    area = math.pi / 4.0 * bore**2
    if travel is not None:
        swept = area * (travel.top - travel.bottom)
        position = np.asarray(travel.position(np.asarray(alpha_deg, dtype=np.float64)))
        return np.asarray(swept / (ratio - 1.0) + area * (travel.top - position))
    s_max = math.sqrt((length + radius) ** 2 - offset**2)
    s_min = math.sqrt((length - radius) ** 2 - offset**2)
    beta = np.radians(alpha_deg) + math.asin(offset / (length + radius))
    s, _, _ = normalised_slider(beta, rod_ratio(radius, length), offset_ratio(offset, radius))
    swept = area * (s_max - s_min)
    return np.asarray(swept / (ratio - 1.0) + area * (s_max - radius * s))


def _volumes(
    spec: GasModel,
    bore: float,
    radius: float,
    length: float,
    offset: float,
    cycle_deg: float,
    travel: PistonTravel | None = None,
) -> tuple[FloatArray, FloatArray, float, float]:
    """The model's grid of cycle angles [deg], the volume on it, at bottom dead centre and
    at the start of combustion [m^3]: what does not depend on the heat released."""
    half = cycle_deg / 2.0
    alpha = np.arange(-half, half, MODEL_STEP_DEG)
    ratio = spec.compression_ratio
    volume = cylinder_volume(alpha, bore, radius, length, offset, ratio, travel)
    v_bdc = float(
        cylinder_volume(np.array([-180.0]), bore, radius, length, offset, ratio, travel)[0]
    )
    start = np.array([spec.combustion_start])
    v_start = float(cylinder_volume(start, bore, radius, length, offset, ratio, travel)[0])
    return alpha, volume, v_bdc, v_start


def _model_table(
    spec: GasModel,
    cycle_deg: float,
    heat: float,
    volumes: tuple[FloatArray, FloatArray, float, float],
) -> tuple[FloatArray, FloatArray]:
    """Pressure of the model on a fine grid of cycle angles, for a heat release [J]
    (``volumes``: the cylinder's :func:`_volumes`, computed once for a search)."""
    alpha, volume, v_bdc, v_start = volumes
    p = np.full(alpha.shape, spec.exhaust_pressure)
    closed = (alpha >= -180.0) & (alpha <= 180.0)
    start = spec.combustion_start
    before = closed & (alpha < start)
    p[before] = spec.intake_pressure * (v_bdc / volume[before]) ** spec.polytropic_compression
    if cycle_deg > 360.0:
        p[alpha < -180.0] = spec.intake_pressure
    after = closed & (alpha >= start)
    a_after = alpha[after]
    v_after = volume[after]
    n2 = spec.polytropic_expansion
    p_start = spec.intake_pressure * (v_bdc / v_start) ** spec.polytropic_compression
    fraction = np.clip((a_after - start) / spec.combustion_duration, 0.0, 1.0)
    burnt = 1.0 - np.exp(-spec.wiebe_a * fraction ** (spec.wiebe_m + 1.0))
    q = heat * burnt
    # d(p V^n) = (n - 1) V^(n-1) dQ, integrated by the trapezoidal rule from the start
    integrand = (n2 - 1.0) * v_after ** (n2 - 1.0)
    dq = np.diff(q, prepend=0.0)
    mid = 0.5 * (integrand + np.concatenate([[integrand[0]], integrand[:-1]]))
    pvn = p_start * v_start**n2 + np.cumsum(mid * dq)
    p[after] = pvn / v_after**n2
    return alpha, p


def model_pressure(
    spec: GasModel,
    bore: float,
    radius: float,
    length: float,
    offset: float,
    cycle: str,
    travel: PistonTravel | None = None,
) -> tuple[FloatArray, FloatArray]:
    """The parametric model's pressure trace (see the module notes).

    Parameters
    ----------
    spec : GasModel
        The ``gas: model:`` parameters.
    bore, radius, length, offset : float
        Bore, crank radius, conrod length and offset of the cylinder [m].
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle.
    travel : PistonTravel, optional
        The piston's travel when it is no plain crank slider (a link piston): the volume is
        then its, the cycle angle counted from its actual top dead centre; the strokes of
        the model stay 180 deg of crank angle each.

    Returns
    -------
    angle, pressure : ndarray
        Cycle angle from firing TDC [deg], every 0.05 deg over one cycle, and absolute
        pressure [Pa].
    """
    cycle_deg = cycle_degrees(cycle)
    volumes = _volumes(spec, bore, radius, length, offset, cycle_deg, travel)
    if spec.heat_released is not None:
        return _model_table(spec, cycle_deg, spec.heat_released, volumes)
    target = float(spec.peak_pressure)  # type: ignore[arg-type]

    def table(heat: float) -> tuple[FloatArray, FloatArray]:
        return _model_table(spec, cycle_deg, heat, volumes)

    def peak(heat: float) -> float:
        return float(table(heat)[1].max())

    low, high = 0.0, 100.0
    if peak(low) >= target:
        return table(0.0)
    while peak(high) < target:
        high *= 2.0
    for _ in range(60):
        mid = 0.5 * (low + high)
        if peak(mid) < target:
            low = mid
        else:
            high = mid
        if high - low <= 1e-10 * high:
            break
    return table(0.5 * (low + high))


def pressure_tables(
    gas: GasInput,
    radius: FloatArray,
    length: FloatArray,
    offset: FloatArray,
    cycle: str,
    travels: Sequence[PistonTravel | None] | None = None,
) -> list[tuple[FloatArray, FloatArray]]:
    """Each cylinder's pressure table: cycle angle from firing TDC and absolute pressure.

    The trace for every cylinder, or the model's table (:func:`model_pressure`) of the
    cylinder's crank radius, conrod length and offset, computed once for each distinct
    geometry; a link piston's (an entry of ``travels`` that is not None) is its own, once
    for each distinct travel.

    Parameters
    ----------
    gas : GasInput
        The ``gas:`` section (a trace, or the model's parameters and the bore).
    radius, length, offset : ndarray
        Crank radius, conrod length and offset of each cylinder [m].
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle.
    travels : sequence of (PistonTravel or None), optional
        Each cylinder's piston travel when it is no plain crank slider.

    Returns
    -------
    list of (ndarray, ndarray)
        Per cylinder: cycle angle from firing TDC [deg] and absolute pressure [Pa].
    """
    n = len(radius)
    if gas.angle is not None and gas.pressure is not None:
        return [(gas.angle, gas.pressure)] * n
    assert gas.model is not None
    tables: dict[tuple[float, float, float], tuple[FloatArray, FloatArray]] = {}
    link_tables: dict[tuple[float, ...], tuple[FloatArray, FloatArray]] = {}
    out = []
    for i in range(n):
        key = (float(radius[i]), float(length[i]), float(offset[i]))
        travel = travels[i] if travels is not None else None
        if travel is not None:  # a link piston: its own volume curve
            if travel.key not in link_tables:
                link_tables[travel.key] = model_pressure(gas.model, gas.bore, *key, cycle, travel)
            out.append(link_tables[travel.key])
            continue
        if key not in tables:
            tables[key] = _plain_model_pressure(gas.model, gas.bore, *key, cycle)
        out.append(tables[key])
    return out


@functools.lru_cache(maxsize=16)
def _plain_model_pressure(
    spec: GasModel, bore: float, radius: float, length: float, offset: float, cycle: str
) -> tuple[FloatArray, FloatArray]:
    """:func:`model_pressure` of a plain crank slider, kept for the geometries last asked
    (an analysis asks for the same table for its torque and its bearing loads, a sweep at
    every speed); the arrays are read-only, since every caller shares them."""
    angle, pressure = model_pressure(spec, bore, radius, length, offset, cycle)
    angle.flags.writeable = False
    pressure.flags.writeable = False
    return angle, pressure


def periodic_tables(
    tables: Sequence[tuple[FloatArray, FloatArray]], period: float
) -> list[tuple[FloatArray, FloatArray]]:
    """Each table as ``np.interp(..., period=period)`` prepares it on every call: angles
    reduced to the period and sorted, one point repeated beyond either end.

    Done once per table (a table shared by several cylinders is prepared once), so that
    :func:`cylinder_pressure` interpolates with the same arithmetic as ``np.interp`` with a
    period, without sorting the table again at every call (the searches of
    :func:`balance.core.bearings.bearing_loads` call it many times).

    Parameters
    ----------
    tables : sequence of (ndarray, ndarray)
        Angle [deg] and pressure [Pa] of each table (:func:`pressure_tables`).
    period : float
        The cycle [deg].

    Returns
    -------
    list of (ndarray, ndarray)
        The prepared tables, in the order given.
    """
    # keyed by both objects' ids (alive in ``tables`` meanwhile); a key folded into one int
    # (id(angle) ^ id(pressure) << 1) could give two tables one key, and one cylinder
    # another's pressures, as memory addresses fell
    prepared: dict[tuple[int, int], tuple[FloatArray, FloatArray]] = {}
    out = []
    for angle, pressure in tables:
        key = (id(angle), id(pressure))
        if key not in prepared:
            xp = np.asarray(angle, dtype=np.float64) % period
            fp = np.asarray(pressure, dtype=np.float64)
            order = np.argsort(xp)
            xp, fp = xp[order], fp[order]
            prepared[key] = (
                np.concatenate((xp[-1:] - period, xp, xp[0:1] + period)),
                np.concatenate((fp[-1:], fp, fp[0:1])),
            )
        out.append(prepared[key])
    return out


def _interpolate(
    tables: Sequence[tuple[FloatArray, FloatArray]], alpha_deg: FloatArray, period: float
) -> FloatArray:
    """Row i of ``alpha_deg`` [deg] interpolated linearly in table i of
    :func:`periodic_tables`."""
    out = np.empty(alpha_deg.shape)
    for i, (xp, fp) in enumerate(tables):
        out[i] = np.interp(alpha_deg[i] % period, xp, fp)
    return out


def cylinder_pressure(
    gas: GasInput, tables: Sequence[tuple[FloatArray, FloatArray]], theta_deg: ArrayLike
) -> FloatArray:
    r"""Absolute pressure [Pa] of each cylinder at the engine's crank angles, shape
    (cylinders, angles).

    Parameters
    ----------
    gas : GasInput
        The ``gas:`` section (firing TDCs and cycle).
    tables : sequence of (ndarray, ndarray)
        Each cylinder's pressure table as :func:`periodic_tables` prepares it.
    theta_deg : array_like
        Crank angles :math:`\theta` [deg], shape (angles,).

    Notes
    -----
    Cylinder i is at its cycle angle :math:`\alpha = \theta - \theta_{TDC,i}` (mod the
    cycle); its pressure is interpolated linearly in its table, periodic over the cycle.
    """
    th = np.asarray(theta_deg, dtype=np.float64)
    alpha = np.mod(th[None, :] - gas.firing_tdc[:, None], gas.cycle_deg)
    return _interpolate(tables, alpha, gas.cycle_deg)


def piston_gas_force(pressure: ArrayLike, gas: GasInput) -> FloatArray:
    r"""Gas force on the piston towards the crank [N]: :math:`P_g = (p - p_0)A`.

    Parameters
    ----------
    pressure : array_like
        Absolute cylinder pressure :math:`p` [Pa] (any shape, e.g. that of
        :func:`cylinder_pressure`).
    gas : GasInput
        Gives the crankcase pressure :math:`p_0` [Pa] under the piston and the piston area
        :math:`A = \pi B^2/4` [m^2].

    Returns
    -------
    ndarray
        :math:`P_g` [N], the shape of ``pressure``; positive pushes the piston towards the
        crank.

    References
    ----------
    Kolchin and Demidov, *Design of Automotive Engines*, Mir 1984 (the gas force on the
    piston, :math:`P_g = (p_g - p_0)F_p`, from the indicator diagram).
    """
    return np.asarray((np.asarray(pressure) - gas.crankcase_pressure) * gas.piston_area)


def pressure_at(
    gas: GasInput,
    alpha_deg: FloatArray,
    radius: FloatArray,
    length: FloatArray,
    offset: FloatArray,
    cycle: str,
    travels: list[PistonTravel | None] | None = None,
) -> FloatArray:
    """Absolute pressure of each cylinder at cycle angles ``alpha_deg``.

    Linear interpolation, periodic over the cycle, in the trace or the model's table (a link
    piston's own, from its entry of ``travels``; :func:`pressure_tables`), as
    :func:`cylinder_pressure` does at crank angles.

    Parameters
    ----------
    gas : GasInput
        The ``gas:`` section.
    alpha_deg : ndarray
        Cycle angles from firing TDC [deg], shape (cylinders, N).
    radius, length, offset : ndarray
        Crank radius, conrod length and offset of each cylinder [m].
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle.
    travels : list of (PistonTravel or None), optional
        Each cylinder's piston travel when it is no plain crank slider.

    Returns
    -------
    ndarray
        Pressure [Pa], shape (cylinders, N).
    """
    alpha = np.asarray(alpha_deg, dtype=np.float64)
    tables = pressure_tables(gas, radius, length, offset, cycle, travels)
    return _interpolate(periodic_tables(tables, gas.cycle_deg), alpha, gas.cycle_deg)
