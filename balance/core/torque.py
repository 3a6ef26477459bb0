r"""Gas and inertia forces on the crank train, engine torque, roll with half orders, flywheel.

Computed over one working cycle (720 deg four-stroke, 360 deg two-stroke) at constant crank
speed, for a layout with a ``gas:`` section.  Per cylinder, with :math:`\beta` the crank
angle from its nominal TDC direction, :math:`\psi` the conrod angle
(:math:`\sin\psi = (r\sin\beta - e)/l`), :math:`s` the piston pin's distance from the crank
axis and :math:`\Delta I = I_G - m\,a(l - a)` the rod's inertia beyond its two-mass model
(``conrod_inertia_correction``):

.. math::

    P_g &= (p - p_0)A, \qquad P_j = m_\mathrm{rec}\,\omega^2 s''(\beta), \qquad
    P = P_g + P_j \\
    N &= P\tan\psi - \frac{\Delta I\,\omega^2\psi''}{l\cos\psi}, \quad
    S = P\cos\psi + N\sin\psi, \\
    T &= P\sin\beta + N\cos\beta = -P\,\frac{s'(\beta)}{r}
        - \frac{\Delta I\,\omega^2\psi'\psi''}{r}, \quad
    K = P\cos\beta - N\sin\beta, \quad M = T\,r

:math:`P` is positive towards the crank (pushing the rod), :math:`T` in the direction of
rotation, :math:`K` towards the crank axis, :math:`N` (the piston on the wall) towards
:math:`-X` (away from the side the pin moves to after TDC), :math:`S` the rod's compression
at the piston pin.  The rod, its two-mass model plus a massless body of inertia
:math:`\Delta I`, passes the force :math:`(N, -P)` from the piston pin to the crank pin; the
couple that turns :math:`\Delta I` at :math:`\omega^2\psi''` is a force across the bore,
:math:`-\Delta I\omega^2\psi''/(l\cos\psi)`, at the piston pin and its opposite at the crank
pin, so the force is not along the rod.  With :math:`\Delta I = 0` these are the textbook
:math:`N = P\tan\psi`, :math:`S = P/\cos\psi`,
:math:`T = P\sin(\beta+\psi)/\cos\psi`, :math:`K = P\cos(\beta+\psi)/\cos\psi`.
:math:`M` is also the virtual work of the pin force and the rod's spin energy, exact with an
offset; :math:`\Delta I` adds nothing to its mean.  The force balance is
:mod:`balance.core.crank_train`'s (:func:`~balance.core.crank_train.side_thrust` and the
rest), the gas force :func:`balance.core.gas.piston_gas_force`.  A link cylinder's
:math:`M` and :math:`T = M/r` add the rate of its link pin's kinetic energy, and its
:math:`K` is the radial part of what its link rod passes through the master rod to the crank
pin (:func:`balance.core.link_forces.link_rod_forces`); a master's :math:`N` is the whole
wall force, its link rods' push included, and its :math:`T`, :math:`K` its own rod's.  The
engine torque is the sum over cylinders, each at its own firing phase (its actual TDC,
:func:`balance.core.gas.firing_tdc`); the block receives the roll torque

.. math::

    R(\theta) = \sum_i \left[\omega^2\left(m_\mathrm{rec} r^2 g_\mathrm{rec}(\beta_i) +
    \Delta I\,g_\mathrm{rod}(\beta_i)\right) - P_{g,i}\,(-s_i')\right]

(the core's inertia roll, :func:`balance.core.kinematics.roll_coefficients`, plus the reaction to
the gas torque), analysed into orders :math:`k = 1/2, 1, 3/2, \dots` (four-stroke) over the
cycle.

.. rubric:: References

Kolchin and Demidov, *Design of Automotive Engines*, Mir 1984, ch. 8–9 (forces on the pin,
rod and crank, torque summation, speed fluctuation and flywheel); Taylor,
*The Internal Combustion Engine in Theory and Practice*, vol. 2, MIT Press 1985, ch. 8.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from balance.core import crank_train, phasors
from balance.core.catalogue import Output
from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.gas import (
    PistonTravel,
    cylinder_pressure,
    periodic_tables,
    piston_gas_force,
    pressure_tables,
)
from balance.core.kinematics import (
    conrod_angle_derivatives,
    normalised_slider,
    offset_ratio,
    rod_ratio,
)
from balance.core.speed import speed_squared

__all__ = [
    "CYCLE_SAMPLES_PER_DEGREE",
    "OUTPUTS",
    "TorqueResult",
    "compute_torque",
    "engine_pressure_tables",
    "indicated_work",
    "piston_travels",
    "roll_orders",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Crank angles per degree of the cycle grid (0.25 deg).
CYCLE_SAMPLES_PER_DEGREE = 4


@dataclass(frozen=True)
class TorqueResult:
    """Forces, torque and roll over one cycle (SI; angles in degrees).

    Per-cylinder arrays have shape ``(cylinders, angles)``; ``crank_angle`` is the engine's
    crank angle :math:`\\theta` [deg] over the cycle.
    """

    crank_angle: FloatArray
    pressure: FloatArray
    gas_force: FloatArray
    inertia_force: FloatArray
    piston_force: FloatArray
    side_thrust: FloatArray
    rod_force: FloatArray
    tangential_force: FloatArray
    radial_force: FloatArray
    cylinder_torque: FloatArray
    engine_torque: FloatArray
    roll_torque: FloatArray
    roll_orders: FloatArray
    roll: ComplexArray
    firing_tdc: FloatArray
    mean: float
    maximum: float
    minimum: float
    nonuniformity: float
    excess_work: float
    speed_fluctuation: float
    flywheel_inertia: float
    cycle_deg: float


def layout_inertia(layout: Engine, theta_deg: FloatArray) -> float:
    r"""The cycle mean of the reduced moment of inertia of the layout's moving masses
    [kg m^2]: :math:`\langle J_{layout}(\theta)\rangle`, what the crank train adds to a
    flywheel's inertia (:func:`balance.core.crank_motion.crank_train`).

    Parameters
    ----------
    layout : Engine
        The engine.
    theta_deg : ndarray
        The crank angles of the cycle's grid [deg] (equally spaced over the cycle).

    Returns
    -------
    float
        :math:`\sum_i [m_{rot,i} r_i^2 + m_{rec,i}\langle s_i'^2\rangle +
        \Delta I_i \langle\gamma_i'^2\rangle]` (link rods as their motion has it).
    """
    from balance.core.crank_motion import crank_train

    return float(np.mean(crank_train(layout, theta_deg).inertia))


def roll_orders(orders: NDArray[np.intp], cycle: str) -> FloatArray:
    """Roll orders reported with gas: halves up to the highest order for a four-stroke.

    Parameters
    ----------
    orders : ndarray of int
        The orders asked for.
    cycle : {'four-stroke', 'two-stroke'}
        The working cycle.

    Returns
    -------
    ndarray
        0.5, 1, 1.5 … up to the highest order for a four-stroke; the orders themselves for a
        two-stroke.
    """
    top = int(np.max(orders))
    if cycle == "four-stroke":
        return np.arange(1, 2 * top + 1) / 2.0
    return np.asarray(orders, dtype=np.float64)


def compute_torque(
    layout: Engine,
    orders: NDArray[np.intp],
    travels: list[PistonTravel | None] | None = None,
) -> TorqueResult:
    r"""Forces, torque, roll and flywheel of a layout with gas forces.

    Parameters
    ----------
    layout : Engine
        The engine, with a ``gas:`` section (:attr:`Layout.gas`).
    orders : ndarray of int
        The analysis orders; the roll is reported for :func:`roll_orders`.
    travels : list of (PistonTravel or None), optional
        Each cylinder's piston travel for the gas model's volume when it is no plain crank
        slider; default :func:`piston_travels` (an opposed-piston bore's,
        :func:`balance.core.bore_pairs.bore_pair_gas`, is given by the caller).

    Returns
    -------
    TorqueResult

    Raises
    ------
    InputError
        If the layout has no ``gas:`` section.

    Notes
    -----
    The cycle is sampled every 0.25 deg; means are taken by the trapezoidal rule over the
    periodic grid.  Speed fluctuation and flywheel, with :math:`\bar M` the mean torque and
    :math:`E(\theta) = \int_0^\theta (M - \bar M)\,\mathrm{d}\theta` the excess work:

    .. math::

        A = \max E - \min E, \qquad \delta = \frac{\omega_{max}-\omega_{min}}{\omega} =
        \frac{A}{J\omega^2}, \qquad J = \frac{A}{\delta\,\omega^2}

    (from :math:`\tfrac12 J(\omega_{max}^2 - \omega_{min}^2) = A`), with
    :math:`J = J_f + \langle J_{layout}\rangle` the flywheel's inertia and the cycle mean of
    the layout's moving masses' (:func:`layout_inertia`): ``flywheel_inertia`` is
    :math:`J_f`, sized beyond what the layout's masses already give (0 when they give the
    fluctuation asked for by themselves).
    """
    gas = layout.gas
    if gas is None:
        raise InputError(f"{layout.name}: no gas section; the torque needs a pressure trace")
    cycle_deg = gas.cycle_deg
    samples = round(cycle_deg * CYCLE_SAMPLES_PER_DEGREE)
    theta = cycle_deg * np.arange(samples) / samples
    throw_deg = np.degrees(layout.throw)[:, None]
    bank_deg = np.degrees(layout.bank)[:, None]
    beta = np.radians(np.mod(theta[None, :] + throw_deg - bank_deg, 360.0))
    r = layout.crank_radius[:, None]
    length = layout.conrod_length[:, None]
    e = layout.offset[:, None]
    lam = rod_ratio(r, length)
    eps = offset_ratio(e, r)
    w2 = float(speed_squared(layout.speed))
    pressure = cylinder_pressure(
        gas, periodic_tables(engine_pressure_tables(layout, travels), cycle_deg), theta
    )
    _, ds, d2s = normalised_slider(beta, lam, eps)
    sin_psi, cos_psi = crank_train.rod_direction(beta, lam, eps)
    dg, d2g = conrod_angle_derivatives(beta, lam, eps)
    pin_power = np.zeros(beta.shape)
    pin_roll = np.zeros(beta.shape)
    if layout.has_links:
        ds, d2s, sin_psi, cos_psi, dg, d2g, pin_power, pin_roll = _with_links(
            layout, beta, ds, d2s, sin_psi, cos_psi, dg, d2g
        )
    gas_force = piston_gas_force(pressure, gas)
    inertia_force = crank_train.reciprocating_force(layout.reciprocating_mass[:, None], w2, r, d2s)
    piston = crank_train.piston_force(inertia_force, gas_force)
    delta_i = layout.conrod_inertia_correction[:, None]
    # the couple that turns the rod's inertia beyond its two-mass model: a force across the
    # bore at the piston pin (and the opposite one at the rod's lower end)
    couple_force = crank_train.couple_side_force(
        crank_train.rod_inertia_couple(delta_i, w2, d2g), length, cos_psi
    )
    side = crank_train.side_thrust(piston, sin_psi, cos_psi, couple_force)
    # virtual work: the pin force, the rod's spin energy and (link) the link pin's energy
    tangential = crank_train.tangential_force(piston, ds, delta_i, w2, dg, d2g, r)
    if layout.has_links:  # a link pin's kinetic energy changes: the crank supplies it
        tangential = tangential - w2 * r * pin_power
    # the rod's force on the crank pin, (N, -P) across and along the bore
    radial = crank_train.radial_force(piston, side, beta)
    if layout.has_links:  # link rows: their share of the pin force; masters: every wall force
        side, radial = _link_rows(layout, theta, gas_force, side, radial)
    rod = crank_train.rod_force(piston, side, sin_psi, cos_psi)
    cylinder_torque = tangential * r
    engine = cylinder_torque.sum(axis=0)
    inertia_roll = w2 * (
        layout.reciprocating_mass[:, None] * r**2 * d2s * (ds + eps) + delta_i * d2g * (1.0 + dg)
    )
    if layout.has_links:
        inertia_roll = inertia_roll + w2 * r**2 * pin_roll
    gas_torque = -gas_force * ds * r
    per_cylinder_roll = inertia_roll - gas_torque
    roll_t = per_cylinder_roll.sum(axis=0)
    ks = roll_orders(orders, layout.cycle)
    revolutions = cycle_deg / 360.0
    bins = np.round(ks * revolutions).astype(np.intp)
    spectrum = np.fft.fft(roll_t) / samples
    roll = 2.0 * spectrum[bins % samples]
    scale = float(np.sum(np.max(np.abs(per_cylinder_roll), axis=1)))
    roll = phasors.cancel_to_zero(roll, scale, 8 * layout.n_cylinders * int(math.log2(samples)))
    mean = float(np.mean(engine))
    step = math.radians(cycle_deg / samples)
    excess = np.concatenate([[0.0], np.cumsum(0.5 * (engine + np.roll(engine, -1)) - mean) * step])
    excess_work = float(excess.max() - excess.min())
    # the layout's own moving masses turn with the crank too: the cycle mean of their
    # reduced inertia is added to the flywheel's (docs/torque.md, "Speed fluctuation")
    if gas.flywheel_inertia is not None:
        inertia = gas.flywheel_inertia
        delta = excess_work / ((inertia + layout_inertia(layout, theta)) * w2)
    elif gas.speed_fluctuation is not None:
        delta = gas.speed_fluctuation
        inertia = max(excess_work / (delta * w2) - layout_inertia(layout, theta), 0.0)
    else:
        inertia = delta = math.nan
    return TorqueResult(
        crank_angle=theta,
        pressure=pressure,
        gas_force=gas_force,
        inertia_force=inertia_force,
        piston_force=piston,
        side_thrust=side,
        rod_force=rod,
        tangential_force=tangential,
        radial_force=radial,
        cylinder_torque=cylinder_torque,
        engine_torque=engine,
        roll_torque=roll_t,
        roll_orders=ks,
        roll=roll,
        firing_tdc=gas.firing_tdc,
        mean=mean,
        maximum=float(engine.max()),
        minimum=float(engine.min()),
        nonuniformity=float((engine.max() - engine.min()) / mean) if mean != 0 else math.nan,
        excess_work=excess_work,
        speed_fluctuation=float(delta),
        flywheel_inertia=float(inertia),
        cycle_deg=cycle_deg,
    )


def engine_pressure_tables(
    engine: Engine, travels: list[PistonTravel | None] | None = None
) -> list[tuple[FloatArray, FloatArray]]:
    """Each cylinder's pressure table (:func:`balance.core.gas.pressure_tables` of the engine's
    geometry, a link piston's over its own travel, :func:`piston_travels`).

    Parameters
    ----------
    engine : Engine
        An engine with a ``gas:`` section.
    travels : list of (PistonTravel or None), optional
        Each cylinder's travel when it is no plain crank slider; default
        :func:`piston_travels`.

    Returns
    -------
    list of (ndarray, ndarray)
        Per cylinder: cycle angle from firing TDC [deg] and absolute pressure [Pa].
    """
    assert engine.gas is not None
    return pressure_tables(
        engine.gas,
        engine.crank_radius,
        engine.conrod_length,
        engine.offset,
        engine.cycle,
        travels if travels is not None else piston_travels(engine),
    )


def piston_travels(engine: Engine) -> list[PistonTravel | None]:
    """Each link piston's travel against its cycle angle from its actual TDC (for the gas
    model's volume).

    Parameters
    ----------
    engine : Engine
        The engine.

    Returns
    -------
    list of (PistonTravel or None)
        Per cylinder, a :class:`balance.core.gas.PistonTravel` for a link piston, None for the
        other cylinders.
    """
    from balance.core.links import engine_geometry, link_dead_centres, link_motion

    out: list[PistonTravel | None] = [None] * engine.n_cylinders
    if not engine.has_links:
        return out
    geometry = engine_geometry(engine)
    top, s_top, s_bottom = link_dead_centres(geometry)
    cols = geometry.columns()
    for row, j in enumerate(geometry.cylinder.tolist()):
        params = tuple(float(c[row, 0]) for c in cols)
        r = float(engine.crank_radius[j])

        def position(
            alpha_deg: FloatArray,
            params: tuple[float, ...] = params,
            start: float = float(top[row]),
            r: float = r,
        ) -> FloatArray:
            return np.asarray(r * link_motion(start + np.radians(alpha_deg), *params).s)

        out[j] = PistonTravel(
            position, r * float(s_top[row]), r * float(s_bottom[row]), key=(*params, r)
        )
    return out


def _link_rows(
    layout: Engine,
    theta_deg: FloatArray,
    gas_force: FloatArray,
    side: FloatArray,
    radial: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    r"""Side thrust and radial force with link rods.

    A link cylinder's radial force is the radial part of its share of the force on the crank
    pin, what its link rod passes through the master rod
    (:attr:`balance.core.link_forces.LinkRodForces.on_pin`); a master piston's side thrust gains
    what its link rods' push on the master rod adds to its wall force, so that it is the
    whole force between piston and wall.
    """
    from balance.core.link_forces import link_rod_forces

    theta = np.radians(theta_deg)
    forces = link_rod_forces(layout, theta, gas_force)
    j = forces.cylinder
    side = np.array(side, copy=True)
    radial = np.array(radial, copy=True)
    outwards = np.exp(1j * (theta[None, :] + layout.throw[j][:, None]))
    radial[j] = -np.real(forces.on_pin * np.conj(outwards))
    np.add.at(side, forces.master, forces.master_wall)
    return side, radial


def _with_links(
    layout: Engine,
    beta: FloatArray,
    ds: FloatArray,
    d2s: FloatArray,
    sin_psi: FloatArray,
    cos_psi: FloatArray,
    dg: FloatArray,
    d2g: FloatArray,
) -> tuple[FloatArray, ...]:
    r"""The per-cylinder arrays with the link cylinders' rows replaced by their motion
    (:func:`balance.core.links.link_motion`): the link piston's :math:`s'/r`, :math:`s''/r`,
    the link rod's angle and its derivatives, and for the link-pin mass :math:`m` (per
    :math:`m r^2\omega^2`) the rate of its kinetic energy
    :math:`\operatorname{Re}(\bar\Lambda'\Lambda'')` and its roll."""
    from balance.core.links import engine_geometry, link_motion, pin_masses, pin_roll

    geometry = engine_geometry(layout)
    j = geometry.cylinder
    m = link_motion(beta[j], *geometry.columns())
    out = [np.array(a, copy=True) for a in (ds, d2s, sin_psi, cos_psi, dg, d2g)]
    for a, v in zip(out, (m.ds, m.d2s, m.sin_rod, m.cos_rod, m.drod, m.d2rod), strict=True):
        a[j] = v
    share = pin_masses(layout)[j][:, None]
    power = np.zeros(beta.shape)
    roll = np.zeros(beta.shape)
    power[j] = share * (m.dpin_y * m.d2pin_y + m.dpin_x * m.d2pin_x)
    roll[j] = share * pin_roll(m)
    return (*out, power, roll)


# --------------------------------------------------------------------------- the section


def torque_part(engine: Engine, request: Any, result: Any) -> Any:
    """The ``torque`` section (:mod:`balance.core.sections`): the forces and torque over the
    cycle of an engine with gas forces (:func:`compute_torque`), and the roll with them
    (half orders for a four-stroke) in place of the inertia roll.  Without a ``gas:``
    section the result is returned as it is."""
    if engine.gas is None:
        return result
    if engine.geared:
        return _geared_torque(engine, result)
    torque = compute_torque(engine, result.phasors.orders)
    if result.roll is None:  # the roll was not asked for
        return result.with_part("torque", torque)
    return result.with_part("torque", torque, roll_orders=torque.roll_orders, roll=torque.roll)


def _geared_torque(engine: Engine, result: Any) -> Any:
    """Several crankshafts: each cylinder's forces and torque as the one-crank cylinder at
    its crank angle from TDC (in its crank's own sense), the engine torque the output's
    (the sum over the shafts in their own senses), and the roll, each shaft's torque and
    own roll with gas (:func:`balance.core.geared.with_gas`).  The two pistons of an
    opposed-piston bore share its pressure, read from its smallest volume
    (:func:`balance.core.bore_pairs.bore_pair_gas`)."""
    from balance.core.bore_pairs import bore_pair_gas
    from balance.core.geared import with_gas

    table = engine.axis_table()
    forward = engine.forward_equivalent()
    gas, travels = bore_pair_gas(engine, piston_travels(forward))
    forward = replace(forward, gas=gas)
    torque = compute_torque(forward, result.phasors.orders, travels)
    if result.roll is None or result.shafts is None:
        return result.with_part("torque", torque)
    scale = float(np.sum(np.max(np.abs(torque.cylinder_torque), axis=1)))
    shafts, roll, _ = with_gas(
        result.shafts, torque.cylinder_torque, torque.cycle_deg, torque.roll_orders, scale
    )
    mean = -table.output_sense * torque.mean
    theta = np.radians(torque.crank_angle)
    synthesis = mean + np.real(np.exp(1j * theta[:, None] * torque.roll_orders[None, :]) @ roll)
    torque = replace(torque, roll=roll, roll_torque=synthesis)
    return result.with_part(
        "torque", torque, roll_orders=torque.roll_orders, roll=roll, shafts=shafts
    )


def _torque(result: Any) -> TorqueResult:
    part: TorqueResult = result.part("torque")
    return part


def _over_cycle(name: str, units: str, long_name: str) -> Output:
    return Output(
        name, ("cylinder", "crank_angle"), units, long_name, lambda r: getattr(_torque(r), name)
    )


def _summary(name: str, attribute: str, units: str, long_name: str) -> Output:
    return Output(name, (), units, long_name, lambda r: getattr(_torque(r), attribute))


#: The outputs of the ``torque`` section.
OUTPUTS: tuple[Output, ...] = (
    Output(
        "gas_pressure",
        ("cylinder", "crank_angle"),
        "Pa",
        "absolute cylinder pressure",
        lambda r: _torque(r).pressure,
    ),
    _over_cycle("gas_force", "N", "gas force (p - p0) A on the piston, to the crank"),
    _over_cycle(
        "inertia_force", "N", "reciprocating inertia force on the piston pin, to the crank"
    ),
    Output(
        "piston_force",
        ("cylinder", "crank_angle"),
        "N",
        "total force P along the bore on the piston pin, to the crank",
        lambda r: _torque(r).piston_force,
    ),
    _over_cycle(
        "side_thrust",
        "N",
        "side thrust N of the piston on the wall (P tan psi and the rod's inertia couple)",
    ),
    Output(
        "rod_force",
        ("cylinder", "crank_angle"),
        "N",
        "rod force S along the rod at the piston pin (compression +)",
        lambda r: _torque(r).rod_force,
    ),
    _over_cycle("tangential_force", "N", "tangential force T on the crank pin (with rotation +)"),
    _over_cycle("radial_force", "N", "radial force K on the crank pin (to the axis +)"),
    _over_cycle("cylinder_torque", "N m", "torque T r of one cylinder"),
    Output(
        "engine_torque",
        ("crank_angle",),
        "N m",
        "engine torque on the crankshaft (sum)",
        lambda r: _torque(r).engine_torque,
    ),
    Output(
        "roll_torque",
        ("crank_angle",),
        "N m",
        "roll torque on the block with gas forces, positive in the direction of rotation",
        lambda r: _torque(r).roll_torque,
    ),
    Output(
        "firing_tdc",
        ("cylinder",),
        "deg",
        "crank angle of the cylinder's firing TDC",
        lambda r: _torque(r).firing_tdc,
    ),
    _summary("torque_mean", "mean", "N m", "mean engine torque over the cycle"),
    _summary("torque_max", "maximum", "N m", "largest engine torque over the cycle"),
    _summary("torque_min", "minimum", "N m", "smallest engine torque over the cycle"),
    _summary(
        "torque_nonuniformity",
        "nonuniformity",
        "1",
        "torque non-uniformity (M_max - M_min) / M_mean",
    ),
    _summary(
        "excess_work",
        "excess_work",
        "J",
        "largest excess work: max - min of the integral of M - M_mean",
    ),
    _summary(
        "speed_fluctuation",
        "speed_fluctuation",
        "1",
        "speed fluctuation (w_max - w_min) / w_mean",
    ),
    _summary(
        "flywheel_inertia",
        "flywheel_inertia",
        "kg m2",
        "flywheel inertia J_f beyond the layout's moving masses (given, or sized for the "
        "speed fluctuation)",
    ),
    Output(
        "indicated_work",
        (),
        "J",
        "indicated work of the engine per cycle (mean torque times cycle angle)",
        lambda r: indicated_work(_torque(r)),
    ),
    Output(
        "crank_angle",
        ("crank_angle",),
        "deg",
        "crank angle theta over the working cycle",
        lambda r: _torque(r).crank_angle,
        kind="coord",
    ),
    Output(
        "gas_pressure_source",
        (),
        "",
        "gas_pressure_source",
        lambda r: r.engine.gas.source,
        kind="attr",
    ),
)


def indicated_work(torque: TorqueResult) -> float:
    """Indicated work of the engine per cycle: the mean torque times the cycle angle.

    Parameters
    ----------
    torque : TorqueResult
        The engine's torque over the cycle (:func:`compute_torque`).

    Returns
    -------
    float
        The work [J].
    """
    return torque.mean * 2.0 * math.pi * torque.cycle_deg / 360.0
