r"""Crank-pin and main-bearing loads, and the crankshaft's internal moments at the mains.

Every load here is a force that the crankshaft (or a big end) puts on a bearing, in the engine
frame, as a complex number :math:`y + \mathrm{i}x` (docs/conventions.md, "Frame and angles"),
sampled over one revolution (inertia only) or over the working cycle (with a ``gas:`` section,
whose forces are then included).  The steps, each a function of arrays over cylinders and crank
angles:

1. :func:`big_end_forces`: the force each big end puts on its crank pin, from the
   Newton–Euler equations of the piston and of the conrod as a rigid body;
2. :func:`pin_groups`: the rods that share a crank pin (one throw, angle and plane) and
   their summed load, the crank-pin load;
3. the throw load: the pin load plus the centrifugal force of the throw's
   ``crank_unbalance`` (and of counterweights, given as ``(z, unbalance)`` pairs);
4. :func:`lever_shares`: the main-bearing loads, by the lever rule of a crankshaft cut at
   every main (statically determinate);
5. :func:`moment_arms`: the internal bending moment at each main from the throw loads on
   its side of smaller z, inertia only;
6. :func:`bearing_loads`: all of the above over the cycle, with the largest magnitude
   refined beyond the sampling and the mean of the magnitude integrated to rounding
   (:class:`LoadModel` holds the matrices; an analysis's loads without and with its
   proposal are :func:`balance.core.bearing_loads.analysis_bearings`).

Two-mass fallback
-----------------
The rod's real inertia enters through the engine's lumped masses, which are *exactly*
equivalent for these forces: a rod of mass :math:`m_c`, centre of gravity :math:`a` from
the big end and inertia :math:`I_G` moves like the point masses :math:`m_c a/l` at the
piston pin and :math:`m_c(1 - a/l)` at the crank pin plus a massless rod of inertia
:math:`\Delta I = I_G - m_c a (l - a)` (static equivalence keeps the mass and centre of
gravity, :math:`\Delta I` restores the moment of inertia; the tests check this against a
rigid-body solution).  With masses given by part, :math:`\Delta I` is the engine's
``conrod_inertia_correction`` and the crank's own unbalance is kept out of the pin load.
With **lumped** masses the rod's inertia is not known: the model is the two-mass one,
:math:`m_{rec}` at the piston pin and :math:`m_{rot}` at the crank pin (:math:`\Delta I =
0`), and the pin load then includes the whole rotating mass, crank unbalance and all (the
throw and main loads do not depend on this split).  Without ``conrod_inertia`` a by-part
rod is likewise taken with the two-mass inertia :math:`m_c a (l - a)`.

.. rubric:: References

C. F. Taylor, *The Internal-Combustion Engine in Theory and Practice*, vol. 2, 2nd ed., MIT
Press 1985, ch. 8 (inertia forces of the reciprocating and rotating parts, the two-mass
conrod).  A. Kolchin and V. Demidov, *Design of Automotive Engines*, Mir 1984 (forces on
the crank pin and the main journals, the polar diagram of the crank-pin load, gas force
:math:`P_g = (p - p_0)F_p`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import crank_train
from balance.core._numerics import (
    GAUSS_NODES,
    fourier_series,
    gauss_panels,
    node_stats,
    ordered_combination,
    series_on_grid,
    series_stats,
)
from balance.core.balancing import Proposal
from balance.core.engine import Engine
from balance.core.gas import cylinder_pressure, periodic_tables, piston_gas_force
from balance.core.kinematics import conrod_angle_derivatives, normalised_slider
from balance.core.speed import speed_squared
from balance.core.throws import crank_pins, crank_throws, group_least, throw_spans
from balance.core.torque import engine_pressure_tables

__all__ = [
    "BearingLoads",
    "LoadModel",
    "bearing_loads",
    "big_end_forces",
    "counterweights_of",
    "crank_frame",
    "crank_unbalance_share",
    "default_mains",
    "engine_default_mains",
    "engine_mains",
    "gas_forces",
    "gas_nodes",
    "lever_shares",
    "loads_at",
    "moment_arms",
    "pin_groups",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Crank angles per revolution of the first grid for the Fourier series of the pin loads.
SERIES_START = 128
#: Largest such grid (a geometry within a hair of l = r + |e| may need it).
SERIES_MAX = 2**14
#: Largest interval of the gas grid [deg] (each interval between the kinks of the
#: interpolated pressure traces gets :data:`balance.core._numerics.GAUSS_NODES` nodes).
GAS_MAX_STEP_DEG = 0.5


# --------------------------------------------------------------------------- geometry


def default_mains(
    z: ArrayLike,
    pitch: float = math.nan,
    stroke: float = math.nan,
    throws: ArrayLike | None = None,
) -> FloatArray:
    r"""Default main-bearing positions [m]: one between neighbouring throws, one half a
    pitch beyond each end throw.

    Parameters
    ----------
    z : array_like
        Axial positions of the cylinders' rods [m] (repeats allowed).
    pitch : float
        Throw pitch [m] used for a single throw without neighbours (the layout's ``pitch``);
        NaN if none.
    stroke : float
        Stroke [m]; a single throw without a pitch gets mains one stroke either side.
    throws : array_like of int, optional
        The crank throw of each cylinder (:func:`balance.core.throws.crank_throws`); the
        rods of one throw are never split by a main.  Default: every plane of rods is a
        throw of its own.

    Returns
    -------
    ndarray
        Strictly increasing main positions [m].

    Notes
    -----
    The throws take the stretches :math:`[a_j, b_j]` of the crank, from the first to the
    last plane of their rods (:func:`balance.core.throws.throw_spans`; one plane,
    :math:`a_j = b_j`, without staggered rods), in order along it.  With more than one
    stretch the mains are :math:`a_1 - (a_2 - b_1)/2`, the midpoints
    :math:`(a_{j+1} + b_j)/2` and :math:`b_n + (a_n - b_{n-1})/2`: each end main is half
    the neighbouring gap beyond the end throw (half a pitch for evenly spaced throws in one
    plane each).  A single stretch gets mains at :math:`a_1 - p/2` and :math:`b_1 + p/2`
    with the layout's pitch :math:`p`, or one stroke either side.
    """
    planes = np.asarray(z, dtype=np.float64)
    if throws is None:
        lo = hi = np.unique(np.round(planes, 12))
    else:
        lo, hi = throw_spans(planes, throws)
    if lo.size == 1:
        half = 0.5 * pitch if math.isfinite(pitch) and pitch > 0 else stroke
        return np.array([lo[0] - half, hi[0] + half])
    middle = 0.5 * (lo[1:] + hi[:-1])
    first = lo[0] - 0.5 * (lo[1] - hi[0])
    last = hi[-1] + 0.5 * (lo[-1] - hi[-2])
    return np.concatenate([[first], middle, [last]])


def engine_default_mains(engine: Engine) -> FloatArray:
    """:func:`default_mains` of an engine (its throws, pitch and largest stroke).

    Parameters
    ----------
    engine : Engine
        The engine.

    Returns
    -------
    ndarray
        Strictly increasing main positions [m].
    """
    return default_mains(
        engine.z, engine.pitch, float(2.0 * np.max(engine.crank_radius)), crank_throws(engine)
    )


def engine_mains(engine: Engine) -> FloatArray:
    """The engine's main positions: its ``bearings:`` section's, else the defaults.

    Parameters
    ----------
    engine : Engine
        The engine.

    Returns
    -------
    ndarray
        Strictly increasing main positions [m] (:func:`engine_default_mains` without a
        section).
    """
    mains = engine.section("bearings")
    if mains is not None:
        return np.asarray(mains, dtype=np.float64)
    return engine_default_mains(engine)


def lever_shares(load_z: ArrayLike, mains: ArrayLike) -> FloatArray:
    r"""Share of each point load carried by each main bearing [1], shape (mains, loads).

    Parameters
    ----------
    load_z : array_like
        Axial positions of the loads (throw planes, counterweights) [m].
    mains : array_like
        Main-bearing positions [m], strictly increasing, at least two.

    Returns
    -------
    ndarray
        :math:`S_{mj}` such that main :math:`m` carries :math:`\sum_j S_{mj} F_j`.

    Notes
    -----
    The crankshaft is cut at every main, so each span is a simply supported beam.  A load at
    :math:`z` between mains :math:`z_a < z_b` goes to them by the lever rule,

    .. math::

        S_a = \frac{z_b - z}{z_b - z_a}, \qquad S_b = \frac{z - z_a}{z_b - z_a},

    and a load beyond the outermost main is a cantilever on the two nearest mains: the same
    formulas, now with :math:`S > 1` on the near main and :math:`S < 0` on the far one
    (the far main holds the shaft down).  A load exactly on a main goes wholly to it.  The
    shares of every load sum to 1 (force balance) and
    :math:`\sum_m S_{mj} z_m = z_j` (moment balance).
    """
    zs = np.asarray(load_z, dtype=np.float64)
    zm = np.asarray(mains, dtype=np.float64)
    span = np.clip(np.searchsorted(zm, zs, side="right") - 1, 0, zm.size - 2)
    za, zb = zm[span], zm[span + 1]
    near = (zb - zs) / (zb - za)
    far = (zs - za) / (zb - za)
    shares = np.zeros((zm.size, zs.size))
    cols = np.arange(zs.size)
    shares[span, cols] += near
    shares[span + 1, cols] += far
    return shares


def moment_arms(load_z: ArrayLike, mains: ArrayLike) -> FloatArray:
    r"""Lever arms of the internal moment [m], shape (mains, loads).

    Parameters
    ----------
    load_z : array_like
        Axial positions of the loads (throw planes, counterweights) [m].
    mains : array_like
        Main-bearing positions [m].

    Returns
    -------
    ndarray
        :math:`A_{mj} = z_m - z_j` where :math:`z_j < z_m`, else 0, so that the internal moment at
        main :math:`m` is :math:`\sum_j A_{mj} F_j` (docs/conventions.md, "Crank-pin and
        main-bearing loads": the bending moment of the loads on the side of smaller z, drawn like
        the moment phasors).
    """
    zs = np.asarray(load_z, dtype=np.float64)
    zm = np.asarray(mains, dtype=np.float64)
    arm = zm[:, None] - zs[None, :]
    return np.where(arm > 0.0, arm, 0.0)


def pin_groups(engine: Engine) -> tuple[NDArray[np.intp], FloatArray, tuple[tuple[int, ...], ...]]:
    """The crank pins: rods of one crank throw at one throw angle and in one plane
    (:func:`balance.core.throws.crank_pins`).

    Parameters
    ----------
    engine : Engine
        The engine (throws, ``z`` and crank throws,
        :func:`balance.core.throws.crank_pins`).

    Returns
    -------
    group : ndarray of int
        Pin index of each cylinder.
    z : ndarray
        Plane of each pin [m].
    cylinders : tuple of tuple of int
        Cylinder numbers (1-based) on each pin.
    """
    group = crank_pins(engine)
    n = int(group.max()) + 1
    z = group_least(engine.z, group)
    cylinders = tuple(tuple(int(i) + 1 for i in np.flatnonzero(group == g)) for g in range(n))
    return group, z, cylinders


def crank_unbalance_share(engine: Engine) -> FloatArray:
    """Each cylinder's share of its throw's ``crank_unbalance``.

    Zero for lumped masses (the unbalance is then inside the rotating mass) and for a
    cylinder whose rotating mass is given lumped.

    Parameters
    ----------
    engine : Engine
        The engine (its masses by part, if any).

    Returns
    -------
    ndarray
        Per cylinder [kg, at the crank radius].
    """
    parts = engine.mass_parts
    if parts is None:
        return np.zeros(engine.n_cylinders)
    share = np.nan_to_num(parts.crank_unbalance) / parts.rods_per_throw
    return np.asarray(np.where(np.isnan(parts.rotating_given), share, 0.0), dtype=np.float64)


def counterweights_of(proposal: Proposal | None) -> tuple[tuple[float, complex], ...]:
    r"""The counterweights of a proposal as the pairs the loads take.

    Parameters
    ----------
    proposal : Proposal or None
        The proposal (None: no counterweights).

    Returns
    -------
    tuple of (float, complex)
        ``(z [m], unbalance [kg m])`` of each counterweight, the unbalance at
        :math:`\theta = 0`.
    """
    if proposal is None:
        return ()
    return tuple((cw.z, complex(cw.unbalance)) for cw in proposal.counterweights)


def crank_frame(load: ArrayLike, theta: ArrayLike, throw: ArrayLike) -> ComplexArray:
    r"""A pin load seen from the crank: :math:`F\,e^{-\mathrm{i}(\theta + \varphi)}`.

    Its real part is along the throw (outwards), its imaginary part along the direction of
    rotation: the frame of the textbook polar diagram of the crank-pin load.

    Parameters
    ----------
    load : array_like of complex
        The load :math:`F` in the engine frame [N].
    theta, throw : array_like
        Crank angle :math:`\theta` and the pin's throw angle :math:`\varphi` [rad],
        broadcasting against ``load``.

    Returns
    -------
    ndarray of complex
        The load in the crank's frame [N].
    """
    return np.asarray(
        np.asarray(load) * np.exp(-1j * (np.asarray(theta) + np.asarray(throw))),
        dtype=np.complex128,
    )


# --------------------------------------------------------------------------- forces


def big_end_forces(
    engine: Engine, theta: ArrayLike, gas_force: ArrayLike | None = None
) -> ComplexArray:
    r"""Force each big end puts on its crank pin [N], engine frame, shape (cylinders, angles).

    Parameters
    ----------
    engine : Engine
        The engine at its crank speed (constant).
    theta : array_like
        Crank angles [rad], shape (angles,).
    gas_force : array_like, optional
        Gas force on each piston towards the crank, :math:`G = (p - p_0)A` [N], shape
        (cylinders, angles).

    Returns
    -------
    ndarray of complex
        :math:`y + \mathrm{i}x` components of the force on the pin.

    Notes
    -----
    In each cylinder's frame (:math:`X` across the bore towards where the pin goes after
    TDC, :math:`Y` along the bore) the crank pin is :math:`C = r(\sin\beta, \cos\beta)`, the
    piston pin :math:`P = (e, s)`, and :math:`d = P - C = (-l\sin\gamma, l\cos\gamma)`.
    The piston (mass :math:`m_{rec}`, the two-mass equivalent, see the module notes) takes
    the rod force :math:`F_{RP}`, the wall force :math:`(N, 0)` and the gas force
    :math:`(0, -G)`:

    .. math::

        m_{rec} a_P = F_{RP} + (N, -G), \qquad a_P = (0, \omega^2 s'').

    The massless rod of inertia :math:`\Delta I` (turning at :math:`\ddot\vartheta =
    \omega^2\gamma''`, counter-clockwise in :math:`X, Y`) carries :math:`-F_{RP}` at
    :math:`P` and the pin's force at :math:`C`; its moment balance about :math:`C` is
    :math:`\Delta I\,\ddot\vartheta = d\times(-F_{RP})`.  With
    :math:`Q = (0, m_{rec}\omega^2 s'' + G)`:

    .. math::

        N = -\frac{\Delta I\,\omega^2\gamma'' + d_X Q_Y}{d_Y}, \qquad
        F_\mathrm{pin} = (N,\ -Q_Y) + m_\mathrm{pin}\,\omega^2 C,

    where :math:`m_\mathrm{pin}` is the rotating mass less the crank's own unbalance
    (:func:`crank_unbalance_share`).  Without :math:`\Delta I` and :math:`e`, :math:`N =
    Q_Y\tan\gamma` and the rod force is :math:`Q_Y/\cos\gamma`: Kolchin and Demidov's
    :math:`P\tan\beta` and :math:`P/\cos\beta`.  In the engine frame,
    :math:`F = (F_Y + \mathrm{i}F_X)\,e^{\mathrm{i}\psi}`.  These are
    :func:`balance.core.crank_train.side_thrust_moment_balance` and
    :func:`balance.core.crank_train.pin_force`.

    With link rods (docs/layout-format.md, "Articulated rods") a link cylinder's row is 0 and its
    master's row is the force of the master rod carrying its link rods
    (:func:`balance.core.link_forces.articulated_big_end_forces`), so the pin loads of
    :func:`pin_groups` are the sums that docs/conventions.md, "Crank-pin and main-bearing
    loads" asks for.
    """
    th = np.asarray(theta, dtype=np.float64)[None, :]
    col = _column
    r, length, e = col(engine.crank_radius), col(engine.conrod_length), col(engine.offset)
    lam = r / length
    beta = th + col(engine.throw) - col(engine.bank)
    _, _, d2s = normalised_slider(beta, lam, e / r)
    _, d2g = conrod_angle_derivatives(beta, lam, e / r)
    w2 = float(speed_squared(engine.speed))
    sin_b = np.sin(beta)  # the rod's direction and the pin's mass both need it
    sin_psi, cos_psi = crank_train.rod_direction(beta, lam, e / r, sin_beta=sin_b)
    gas = None if gas_force is None else np.asarray(gas_force, dtype=np.float64)
    q_y = crank_train.piston_force(
        crank_train.reciprocating_force(col(engine.reciprocating_mass), w2, r, d2s), gas
    )
    delta_i = col(engine.conrod_inertia_correction)
    wall = crank_train.side_thrust_moment_balance(q_y, sin_psi, cos_psi, length, delta_i, w2, d2g)
    m_pin = col(engine.rotating_mass - crank_unbalance_share(engine)) * w2 * r
    forces = crank_train.pin_force(q_y, wall, m_pin, beta, col(engine.bank), sin_beta=sin_b)
    # master rods carry their link rods (docs/conventions.md, "Crank-pin and main-bearing loads")
    if engine.has_links:
        from balance.core.link_forces import articulated_big_end_forces

        return articulated_big_end_forces(engine, theta, forces, gas_force)
    return forces


_FLOAT = np.dtype(np.float64)  # np.asarray(x, _FLOAT): a third cheaper than dtype=np.float64


def _column(values: FloatArray) -> FloatArray:
    return np.asarray(values, _FLOAT)[:, None]


def gas_forces(
    engine: Engine, theta: ArrayLike, tables: list[tuple[FloatArray, FloatArray]] | None = None
) -> FloatArray:
    r"""Gas force on each piston towards the crank [N], shape (cylinders, angles).

    :math:`G_i(\theta) = (p_i(\alpha) - p_0)\,\pi B^2/4`
    (:func:`balance.core.gas.piston_gas_force`) with the cycle angle
    :math:`\alpha = \theta - \theta_{TDC,i}` (mod the cycle), the pressure interpolated
    linearly in the trace (or the model's table) by :func:`balance.core.gas.cylinder_pressure`,
    as :mod:`balance.core.torque` does.

    Parameters
    ----------
    engine : Engine
        An engine with a ``gas:`` section.
    theta : array_like
        Crank angles [rad].
    tables : list of (ndarray, ndarray), optional
        Each cylinder's pressure table, cycle angle [deg] and absolute pressure [Pa]; default
        :func:`balance.core.torque.engine_pressure_tables`.

    Returns
    -------
    ndarray
        :math:`G_i(\theta)` [N].
    """
    gas = engine.gas
    assert gas is not None, "gas_forces needs an engine with a gas section"
    tables = tables if tables is not None else engine_pressure_tables(engine)
    return _gas_forces(engine, theta, periodic_tables(tables, gas.cycle_deg))


def _gas_forces(
    engine: Engine, theta: ArrayLike, periodic: list[tuple[FloatArray, FloatArray]]
) -> FloatArray:
    """:func:`gas_forces` from the tables of :func:`balance.core.gas.periodic_tables`."""
    gas = engine.gas
    assert gas is not None
    pressure = cylinder_pressure(gas, periodic, np.degrees(np.asarray(theta, dtype=np.float64)))
    return piston_gas_force(pressure, gas)


# --------------------------------------------------------------------------- result


@dataclass(frozen=True, eq=False)
class BearingLoads:
    """Crank-pin loads, main-bearing loads and internal moments over the cycle (SI).

    Sampled curves are complex (:math:`y + \\mathrm{i}x`), shape (bearings, angles), on the
    uniform grid ``theta`` [rad] (over ``cycle`` [rad]: :math:`2\\pi`, or :math:`4\\pi` for
    a four-stroke with gas) for plots; the statistics come from the finer computation of
    :func:`bearing_loads`.

    Attributes
    ----------
    theta : ndarray
        Crank angles of the curves [rad].
    cycle : float
        Length of the cycle [rad].
    gas : bool
        Whether gas forces are included (pins and mains; never the internal moments).
    pin_z : ndarray
        Plane of each crank pin [m].
    pin_cylinders : tuple of tuple of int
        Cylinder numbers on each pin.
    pin_throw : ndarray
        Throw angle of each pin [rad].
    pin_load, main_load : ndarray of complex
        Crank-pin loads and main-bearing loads [N].
    main_z : ndarray
        Main-bearing positions [m].
    moment_theta : ndarray
        Crank angles of the internal-moment curves [rad] (one revolution).
    internal_moment : ndarray of complex
        Internal moment at each main [N m], inertia only.
    pin_max, pin_mean, main_max, main_mean, moment_max, moment_mean : ndarray
        Largest magnitude over the cycle (refined) and mean magnitude [N, N m].
    pin_max_angle, main_max_angle, moment_max_angle : ndarray
        Crank angle of each maximum [rad], in [0, cycle).
    samples : int
        Points behind the means of the pin and main loads (the last uniform grid, or the
        Gauss nodes over the cycle with gas).
    series_terms : int
        Fourier terms of the inertia loads.
    """

    theta: FloatArray
    cycle: float
    gas: bool
    pin_z: FloatArray
    pin_cylinders: tuple[tuple[int, ...], ...]
    pin_throw: FloatArray
    pin_load: ComplexArray
    main_z: FloatArray
    main_load: ComplexArray
    moment_theta: FloatArray
    internal_moment: ComplexArray
    pin_max: FloatArray
    pin_mean: FloatArray
    pin_max_angle: FloatArray
    main_max: FloatArray
    main_mean: FloatArray
    main_max_angle: FloatArray
    moment_max: FloatArray
    moment_mean: FloatArray
    moment_max_angle: FloatArray
    samples: int
    series_terms: int


class LoadModel:
    """Precomputed matrices: crank angles in, pin/main loads and internal moments out.

    What :func:`bearing_loads`, :func:`loads_at` and
    :func:`balance.core.bearing_loads.analysis_bearings` evaluate: the pins of
    :func:`pin_groups`, the throws' crank unbalance, the lever shares (:func:`lever_shares`)
    and moment arms (:func:`moment_arms`) of the pins and of the counterweights, and with gas
    the cylinders' pressure tables.

    Parameters
    ----------
    engine : Engine
        The engine.
    mains : ndarray
        Main-bearing positions [m].
    counterweights : sequence of (float, complex)
        ``(z [m], unbalance [kg m])`` of masses turning with the crank.
    with_gas : bool
        Include the gas forces (the engine must have a ``gas:`` section).
    tables : list of (ndarray, ndarray), optional
        Each cylinder's pressure table (default
        :func:`balance.core.torque.engine_pressure_tables`): a crank axis of an engine with
        several takes its cylinders' tables from the whole engine's, where the two pistons
        of an opposed bore share one.
    """

    def __init__(
        self,
        engine: Engine,
        mains: FloatArray,
        counterweights: Sequence[tuple[float, complex]],
        with_gas: bool,
        tables: list[tuple[FloatArray, FloatArray]] | None = None,
    ) -> None:
        self.engine = engine
        group, pin_z, cylinders = pin_groups(engine)
        n_pins = pin_z.size
        self.pin_z, self.cylinders = pin_z, cylinders
        self.pin_throw = group_least(engine.throw, group)
        self.sum_pins = np.zeros((n_pins, engine.n_cylinders))
        self.sum_pins[group, np.arange(engine.n_cylinders)] = 1.0
        w2 = float(speed_squared(engine.speed))
        # centrifugal force of each cylinder's share of the crank unbalance, at theta = 0
        unbalance = crank_unbalance_share(engine) * engine.crank_radius * w2
        self.throw_extra = self.sum_pins @ (unbalance * np.exp(1j * engine.throw))
        cw_z = np.array([z for z, _ in counterweights], dtype=np.float64)
        cw_u = np.array([u for _, u in counterweights], dtype=np.complex128) * w2
        self.mains = mains
        self.main_pins = lever_shares(pin_z, mains)
        self.main_cw = lever_shares(cw_z, mains) @ cw_u if cw_z.size else np.zeros(mains.size)
        self.moment_pins = moment_arms(pin_z, mains)
        self.moment_cw = moment_arms(cw_z, mains) @ cw_u if cw_z.size else np.zeros(mains.size)
        self.with_gas = with_gas
        if with_gas and tables is None:
            tables = engine_pressure_tables(engine)
        self.tables = tables if with_gas else None
        self.periodic = (
            periodic_tables(self.tables, engine.gas.cycle_deg)
            if self.tables is not None and engine.gas is not None
            else None
        )

    def pins(self, theta: FloatArray, gas: bool) -> ComplexArray:
        g = _gas_forces(self.engine, theta, self.periodic) if gas and self.periodic else None
        return np.asarray(self.sum_pins @ big_end_forces(self.engine, theta, g))

    def throws(self, pins: ComplexArray, theta: FloatArray) -> ComplexArray:
        return np.asarray(pins + self.throw_extra[:, None] * np.exp(1j * theta)[None, :])

    def mains_of(self, throws: ComplexArray, theta: FloatArray) -> ComplexArray:
        turning = np.exp(1j * theta)[None, :]
        return ordered_combination(self.main_pins, throws) + self.main_cw[:, None] * turning

    def moments_of(self, throws: ComplexArray, theta: FloatArray) -> ComplexArray:
        turning = np.exp(1j * theta)[None, :]
        return ordered_combination(self.moment_pins, throws) + self.moment_cw[:, None] * turning

    def cycle_loads(self, theta: FloatArray) -> tuple[ComplexArray, ComplexArray]:
        """Pin and main loads (with gas if asked)."""
        pins = self.pins(theta, self.with_gas)
        return pins, self.mains_of(self.throws(pins, theta), theta)

    def inertia_series(self) -> tuple[NDArray[np.intp], ComplexArray]:
        """Orders k and Fourier coefficients of the inertia-only pins, mains and moments,
        stacked in that order (rows), each row :math:`F(\\theta) = \\sum c_k e^{ik\\theta}`."""
        k, pins = fourier_series(lambda t: self.pins(t, False), SERIES_START, SERIES_MAX)
        one = np.zeros(k.size)
        one[k == 1] = 1.0
        throws = pins + self.throw_extra[:, None] * one
        mains = self.main_pins @ throws + self.main_cw[:, None] * one
        moments = self.moment_pins @ throws + self.moment_cw[:, None] * one
        return k, np.concatenate([pins, mains, moments], axis=0)


def loads_at(
    engine: Engine,
    theta: ArrayLike,
    mains: ArrayLike | None = None,
    counterweights: Iterable[tuple[float, complex]] = (),
    gas: bool = True,
) -> tuple[ComplexArray, ComplexArray, ComplexArray]:
    """Pin loads, main loads and internal moments at the crank angles ``theta``.

    Evaluated directly from :func:`big_end_forces` (no series).  The pin and main loads
    include the gas forces when the engine has them and ``gas`` is true; the internal moments
    never do.

    Parameters
    ----------
    engine, mains, counterweights, gas
        As for :func:`bearing_loads`.
    theta : array_like
        Crank angles [rad].

    Returns
    -------
    pins, mains, moments : ndarray of complex
        Pin loads [N], shape (pins, angles); main loads [N] and internal moments [N m], shape
        (mains, angles).
    """
    th = np.asarray(theta, dtype=np.float64)
    zm = engine_mains(engine) if mains is None else np.asarray(mains, dtype=np.float64)
    cws = tuple((float(z), complex(u)) for z, u in counterweights)
    model = LoadModel(engine, zm, cws, gas and engine.gas is not None)
    pins, main = model.cycle_loads(th)
    moments = model.moments_of(model.throws(model.pins(th, False), th), th)
    return pins, main, moments


def bearing_loads(
    engine: Engine,
    mains: ArrayLike | None = None,
    counterweights: Iterable[tuple[float, complex]] = (),
    gas: bool = True,
    curve_samples: int = 360,
) -> BearingLoads:
    r"""Crank-pin loads, main-bearing loads and internal moments of an engine.

    Parameters
    ----------
    engine : Engine
        The engine; with a ``gas:`` section (and ``gas=True``) the pin and main loads include
        the gas forces, over the working cycle.
    mains : array_like, optional
        Main-bearing positions [m], strictly increasing, at least two; default
        :func:`engine_default_mains`.
    counterweights : iterable of (float, complex)
        ``(z [m], unbalance [kg m])`` of masses turning with the crank, the unbalance at
        :math:`\theta = 0` (e.g. :func:`counterweights_of` of a proposal).  They load the
        mains and the internal moments, not the pins.
    gas : bool
        Include the gas forces when the engine has them.
    curve_samples : int
        Crank angles per revolution of the returned curves (statistics do not depend on it).

    Returns
    -------
    BearingLoads

    Notes
    -----
    Throw load of pin :math:`j`: :math:`F_j = F_{\mathrm{pin},j} + \sum_{i \in j}
    u_i r_i\omega^2 e^{\mathrm{i}(\theta + \varphi_i)}`; counterweights add
    :math:`U_c\omega^2 e^{\mathrm{i}\theta}` at their planes.  Main loads
    :math:`\sum_j S_{mj}F_j` (:func:`lever_shares`), internal moments
    :math:`\sum_{z_j < z_m}(z_m - z_j)F_j` (:func:`moment_arms`), inertia only.

    *Inertia only* every load is a smooth periodic function of the crank angle; it is
    represented exactly by its Fourier series :math:`F(\theta) = \sum_k c_k
    e^{\mathrm{i}k\theta}`, whose coefficients come from an FFT of the pin loads on a grid
    doubled (from 64 points) until the top quarter of the spectrum is below
    :math:`16\varepsilon` of its largest coefficient (the series converges geometrically,
    like the piston acceleration's).  Mains and moments are linear in the throw loads, so
    their coefficients follow by matrix products.  Then

    * the **maximum** of :math:`|F|` starts from the best sampled local maxima on a grid
      of at least 1024 points and is refined by Newton's method on
      :math:`g = \tfrac12 (|F|^2)' = \mathrm{Re}(\bar F F')`, with
      :math:`g' = |F'|^2 + \mathrm{Re}(\bar F F'')`, all from the series (quadratic
      convergence, to rounding);
    * the **mean** of :math:`|F|` is the trapezoidal rule on a uniform periodic grid
      (geometric convergence for a smooth periodic integrand), evaluated by zero-padded
      inverse FFT on 1024 (at least four times the terms) and twice as many points; it has
      converged when the two differ by less than
      :data:`~balance.core._numerics.MEAN_TOLERANCE` of the quantity's maximum.  A load that
      passes through (or very near) zero makes :math:`|F|` (nearly) non-smooth there and
      the uniform rule slow; such a quantity is integrated instead between its minima of
      :math:`|F|` (found by the same Newton iteration; every sampled local minimum below a
      tenth of the maximum) over the period with 16-point Gauss–Legendre panels, short
      enough for the series' highest order and graded geometrically (ratio 1/4) towards
      those points, which converges geometrically whatever the distance to the zero.

    *With gas* the pressure is linear between the trace's points, so the loads are smooth
    only between its kinks (each trace angle shifted by each cylinder's firing TDC): the
    mean is a 4-point Gauss–Legendre rule on every interval between kinks (no longer than
    0.5 deg), exact to rounding for such a piecewise-smooth integrand; where a load dips
    towards zero (a sampled local minimum below a tenth of its maximum) the three intervals
    around the dip are integrated again, split at the minimum (golden-section search) and
    graded towards it; the maximum is refined from the best sampled local maxima by
    golden-section search between the neighbouring nodes (64 steps), which converges for
    any continuous function unimodal in the bracket, a kink at the peak included.

    These searches and rules are the generic ones of :mod:`balance.core._numerics`
    (:func:`~balance.core._numerics.series_stats` and
    :func:`~balance.core._numerics.node_stats`).
    """
    cws = tuple((float(z), complex(u)) for z, u in counterweights)
    zm = engine_mains(engine) if mains is None else np.asarray(mains, dtype=np.float64)
    with_gas = gas and engine.gas is not None
    model = LoadModel(engine, zm, cws, with_gas)
    n_pins, n_mains = model.pin_z.size, zm.size

    k, coeffs = model.inertia_series()  # pins, mains, moments stacked
    inertia = series_stats(k, coeffs)
    theta_rev = 2.0 * np.pi * np.arange(curve_samples) / curve_samples
    moment_curve = series_on_grid(k, coeffs[n_pins + n_mains :], curve_samples)
    p_m = slice(0, n_pins)
    m_m = slice(n_pins, n_pins + n_mains)
    t_m = slice(n_pins + n_mains, None)
    if with_gas:
        assert engine.gas is not None
        cycle = math.radians(engine.gas.cycle_deg)
        nodes, weights, edges = gas_nodes(engine, model)
        stats = node_stats(
            lambda t: _magnitudes(model.cycle_loads(t)), nodes, weights, edges, cycle
        )
        maximum, mean, argmax = stats.maximum, stats.mean, stats.argmax
        samples = nodes.size
        n_curve = round(curve_samples * engine.gas.cycle_deg / 360.0)
        theta = cycle * np.arange(n_curve) / n_curve
        pin_curve, main_curve = model.cycle_loads(theta)
    else:
        cycle = 2.0 * np.pi
        maximum, mean, argmax = inertia.maximum, inertia.mean, inertia.argmax
        samples = inertia.samples
        theta = theta_rev
        curves = series_on_grid(k, coeffs[: n_pins + n_mains], curve_samples)
        pin_curve, main_curve = curves[p_m], curves[m_m]
    return BearingLoads(
        theta=theta,
        cycle=cycle,
        gas=with_gas,
        pin_z=model.pin_z,
        pin_cylinders=model.cylinders,
        pin_throw=model.pin_throw,
        pin_load=pin_curve,
        main_z=zm,
        main_load=main_curve,
        moment_theta=theta_rev,
        internal_moment=moment_curve,
        pin_max=maximum[p_m],
        pin_mean=mean[p_m],
        pin_max_angle=argmax[p_m],
        main_max=maximum[m_m],
        main_mean=mean[m_m],
        main_max_angle=argmax[m_m],
        moment_max=inertia.maximum[t_m],
        moment_mean=inertia.mean[t_m],
        moment_max_angle=inertia.argmax[t_m],
        samples=samples,
        series_terms=k.size,
    )


# --------------------------------------------------------------------------- statistics


def _magnitudes(parts: tuple[ComplexArray, ...]) -> FloatArray:
    return np.abs(np.concatenate(parts, axis=0))


def gas_nodes(engine: Engine, model: LoadModel) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Gauss–Legendre nodes and weights over the cycle, between the pressure traces' kinks.

    Parameters
    ----------
    engine : Engine
        An engine with a ``gas:`` section.
    model : LoadModel
        Its load model with gas (the pressure tables).

    Returns
    -------
    nodes, weights : ndarray
        The nodes [rad] and their weights [rad], :data:`balance.core._numerics.GAUSS_NODES`
        per interval of at most :data:`GAS_MAX_STEP_DEG`.
    edges : ndarray
        The interval edges [rad], the last one period after the first.
    """
    gas = engine.gas
    assert gas is not None and model.tables is not None
    cycle = gas.cycle_deg
    kinks = [
        np.mod(angle + tdc, cycle)
        for (angle, _), tdc in zip(model.tables, gas.firing_tdc, strict=True)
    ]
    steps = max(1, math.ceil(cycle / GAS_MAX_STEP_DEG))
    edges = np.concatenate([*kinks, cycle * np.arange(steps) / steps])
    edges = np.unique(np.round(edges, 9))
    edges = np.concatenate([edges, [edges[0] + cycle]])
    nodes, weights = gauss_panels(edges, GAUSS_NODES)
    return np.radians(nodes), np.radians(weights), np.radians(edges)
