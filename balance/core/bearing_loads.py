"""The crank-pin and main-bearing loads as a section of an analysis.

:func:`analysis_bearings` computes the loads of an engine without and with a proposal's
counterweights in one pass (:class:`Bearings`), and :func:`largest_loads` the largest main
load and internal moment for many sets of counterweights (a balance-factor study).
:func:`bearings_part` computes the loads of an analysed engine with the proposal's
counterweights, and on request with each counterweight strategy's and each balance
factor's; :data:`OUTPUTS` declares what it adds to the output catalogue
(:mod:`balance.core.catalogue`).  The physics (big-end forces, lever rule, the series and
the statistics of each load) is in :mod:`balance.core.bearings`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core._numerics import node_stats, series_on_grid, series_stats
from balance.core.bearings import (
    LoadModel,
    counterweights_of,
    crank_frame,
    engine_mains,
    gas_nodes,
    lever_shares,
    moment_arms,
)
from balance.core.catalogue import Output
from balance.core.engine import STRATEGIES, Engine
from balance.core.speed import speed_squared

__all__ = [
    "GEAR_NOTE",
    "OUTPUTS",
    "Bearings",
    "BearingsPart",
    "analysis_bearings",
    "axes_bearings",
    "axes_largest_loads",
    "axis_engine",
    "axis_mains",
    "bearings_part",
    "largest_loads",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


# --------------------------------------------------------------- the analysis's bearings


@dataclass(frozen=True, eq=False)
class Bearings:
    r"""Bearing loads of an analysis, without and with the proposed counterweights (SI).

    What :attr:`balance.core.result.Result.bearings` holds (docs/conventions.md,
    "Crank-pin and main-bearing loads").  The ``*_with_proposal``
    arrays add the proposal's counterweights (balance shafts run in their own bearings and do
    not load the mains); without a proposal, or with one without counterweights, they equal
    the arrays without.  Curves are complex (:math:`y + \mathrm{i}x`), shape
    (bearings, angles).

    Attributes
    ----------
    theta : ndarray
        Crank angles of the pin and main curves [rad], uniform over ``cycle``.
    cycle : float
        Length of the cycle [rad]: :math:`2\pi`, or :math:`4\pi` for a four-stroke with gas.
    gas : bool
        Whether the pin and main loads include gas forces (the internal moments never do).
    pin_z, pin_throw : ndarray
        Plane [m] and throw angle [rad] of each crank pin.
    pin_cylinders : tuple of tuple of int
        Cylinder numbers (1-based) on each pin.
    pin_max, pin_mean : ndarray
        Largest and mean magnitude of each crank-pin load [N].
    pin_max_angle : ndarray
        Crank angle of each pin's largest load [rad].
    main_z : ndarray
        Main-bearing positions [m].
    main_max, main_mean, main_max_with_proposal, main_mean_with_proposal : ndarray
        Largest and mean magnitude of each main-bearing load [N].
    moment_max, moment_max_with_proposal : ndarray
        Largest magnitude of the internal moment at each main [N m] (inertia only).
    pin_load : ndarray of complex
        Crank-pin loads [N] at ``theta``, engine frame.
    main_load, main_load_with_proposal : ndarray of complex
        Main-bearing loads [N] at ``theta``, engine frame.
    moment_theta : ndarray
        Crank angles of the internal-moment curves [rad] (one revolution).
    internal_moment, internal_moment_with_proposal : ndarray of complex
        Internal moment at each main [N m] at ``moment_theta``.
    counterweights : tuple of (float, complex)
        The ``(z [m], unbalance [kg m])`` of the proposal's counterweights used.
    axis_names : tuple of str
        With several crank axes (:func:`axes_bearings`): their names; empty for one.
    pin_axis, main_axis : ndarray of int or None
        With several crank axes: the axis (0-based) of each pin and of each main.  Each
        axis's pin throws are those of its one-crank engine (mirrored for a
        counter-rotating axis, docs/several-crankshafts.md, "Bearing loads").
    axis_sense : ndarray or None
        With several crank axes: each axis's sense [1].
    """

    theta: FloatArray
    cycle: float
    gas: bool
    pin_z: FloatArray
    pin_throw: FloatArray
    pin_cylinders: tuple[tuple[int, ...], ...]
    pin_max: FloatArray
    pin_mean: FloatArray
    pin_max_angle: FloatArray
    main_z: FloatArray
    main_max: FloatArray
    main_mean: FloatArray
    main_max_with_proposal: FloatArray
    main_mean_with_proposal: FloatArray
    moment_max: FloatArray
    moment_max_with_proposal: FloatArray
    pin_load: ComplexArray
    main_load: ComplexArray
    main_load_with_proposal: ComplexArray
    moment_theta: FloatArray
    internal_moment: ComplexArray
    internal_moment_with_proposal: ComplexArray
    counterweights: tuple[tuple[float, complex], ...] = ()
    axis_names: tuple[str, ...] = ()
    pin_axis: NDArray[np.intp] | None = None
    main_axis: NDArray[np.intp] | None = None
    axis_sense: FloatArray | None = None

    @property
    def pin_load_crank_frame(self) -> ComplexArray:
        """:attr:`pin_load` seen from the crank (:func:`~balance.core.bearings.crank_frame`):
        real part along the throw, imaginary part in the direction of its crank's own
        rotation [N]."""
        load = self.pin_load
        if self.pin_axis is not None and self.axis_sense is not None:
            back = self.axis_sense[self.pin_axis][:, None] < 0
            load = np.where(back, np.conj(load), load)  # the mirror's, whose throw is pin_throw
        return crank_frame(load, self.theta[None, :], self.pin_throw[:, None])


def analysis_bearings(
    engine: Engine,
    counterweights: Iterable[tuple[float, complex]] = (),
    mains: ArrayLike | None = None,
    gas: bool = True,
    curve_samples: int = 360,
    tables: list[tuple[FloatArray, FloatArray]] | None = None,
) -> Bearings:
    r"""Bearing loads without and with counterweights, in one pass (:class:`Bearings`).

    Parameters
    ----------
    engine : Engine
        The engine; its ``mains`` (a ``bearings:`` section) unless ``mains`` is given, else
        :func:`~balance.core.bearings.engine_default_mains`.
    counterweights : iterable of (float, complex)
        ``(z [m], unbalance [kg m])`` of the proposal's counterweights
        (:func:`~balance.core.bearings.counterweights_of`).
    mains : array_like, optional
        Main-bearing positions [m] instead of the engine's.
    gas : bool
        Include the gas forces when the engine has them.
    curve_samples : int
        Crank angles per revolution of the curves.
    tables : list of (ndarray, ndarray), optional
        Each cylinder's pressure table (:class:`~balance.core.bearings.LoadModel`).

    Returns
    -------
    Bearings
        The loads without and with the counterweights.

    Notes
    -----
    The same numbers as two calls of :func:`~balance.core.bearings.bearing_loads` (without and with
    the counterweights), computed once: counterweights turn with the crank, so they add only to the
    order-1 Fourier coefficient of the main loads and internal moments,
    :math:`\sum_c S_{mc} U_c\omega^2` and :math:`\sum_c A_{mc} U_c\omega^2`; the pin loads,
    which do not see them, are computed once.  With gas the loads are evaluated at the same
    nodes for both variants.
    """
    cws = tuple((float(z), complex(u)) for z, u in counterweights)
    zm = engine_mains(engine) if mains is None else np.asarray(mains, dtype=np.float64)
    with_gas = gas and engine.gas is not None
    model = LoadModel(engine, zm, (), with_gas, tables)
    n_pins, n_mains = model.pin_z.size, zm.size
    w2 = float(speed_squared(engine.speed))
    cw_z = np.array([z for z, _ in cws], dtype=np.float64)
    cw_u = np.array([u for _, u in cws], dtype=np.complex128) * w2
    has_cw = bool(cw_z.size) and bool(np.any(cw_u != 0))
    cw_main = lever_shares(cw_z, zm) @ cw_u if has_cw else np.zeros(n_mains, complex)
    cw_moment = moment_arms(cw_z, zm) @ cw_u if has_cw else np.zeros(n_mains, complex)

    k, coeffs = model.inertia_series()  # pins, mains, moments
    one = (k == 1).astype(np.float64)
    mains_c, moments_c = coeffs[n_pins : n_pins + n_mains], coeffs[n_pins + n_mains :]
    rows = [coeffs[:n_pins], mains_c, moments_c]
    if has_cw:
        rows += [mains_c + cw_main[:, None] * one, moments_c + cw_moment[:, None] * one]
    series = np.concatenate(rows, axis=0)
    b0, b1, b2 = n_pins, n_pins + n_mains, n_pins + 2 * n_mains
    moments_with = slice(b2 + n_mains, b2 + 2 * n_mains) if has_cw else slice(b1, b2)
    mains_with = slice(b2, b2 + n_mains) if has_cw else slice(b0, b1)
    theta_rev = 2.0 * np.pi * np.arange(curve_samples) / curve_samples
    if with_gas:
        assert engine.gas is not None
        moment_rows = (
            series[b1:b2]
            if not has_cw
            else np.concatenate([series[b1:b2], series[moments_with]], axis=0)
        )
        moment_stats = series_stats(k, moment_rows, np.zeros(moment_rows.shape[0], dtype=bool))
        moment_max = moment_stats.maximum[:n_mains]
        moment_max_with = moment_stats.maximum[n_mains:] if has_cw else moment_max
        cycle = math.radians(engine.gas.cycle_deg)

        def loads(t: FloatArray) -> tuple[ComplexArray, ...]:
            pins = model.pins(t, True)
            main = model.mains_of(model.throws(pins, t), t)
            if not has_cw:
                return pins, main
            return pins, main, main + cw_main[:, None] * np.exp(1j * t)[None, :]

        nodes, weights, edges = gas_nodes(engine, model)
        stats = node_stats(
            lambda t: np.abs(np.concatenate(loads(t), axis=0)), nodes, weights, edges, cycle
        )
        n_curve = round(curve_samples * engine.gas.cycle_deg / 360.0)
        theta = cycle * np.arange(n_curve) / n_curve
        curves = loads(theta)
        pin_curve, main_curve = curves[0], curves[1]
        main_curve_with = curves[2] if has_cw else main_curve
        maximum, mean, argmax = stats.maximum, stats.mean, stats.argmax
        main_max_with = maximum[b1 : b1 + n_mains] if has_cw else maximum[b0:b1]
        main_mean_with = mean[b1 : b1 + n_mains] if has_cw else mean[b0:b1]
    else:
        mean_wanted = np.zeros(series.shape[0], dtype=bool)
        mean_wanted[:b1] = True
        mean_wanted[mains_with] = True
        stats = series_stats(k, series, mean_wanted)
        maximum, mean, argmax = stats.maximum, stats.mean, stats.argmax
        cycle = 2.0 * np.pi
        theta = theta_rev
        curves_all = series_on_grid(k, series, curve_samples)
        pin_curve, main_curve = curves_all[:b0], curves_all[b0:b1]
        main_curve_with = curves_all[mains_with]
        moment_max = maximum[b1:b2]
        moment_max_with = maximum[moments_with]
        main_max_with, main_mean_with = maximum[mains_with], mean[mains_with]
    moment_curves = series_on_grid(k, series[b1:b2], curve_samples)
    moment_curves_with = (
        series_on_grid(k, series[moments_with], curve_samples) if has_cw else moment_curves
    )
    by_z = np.argsort(model.pin_z, kind="stable")  # pins in the order of their planes
    return Bearings(
        theta=theta,
        cycle=cycle,
        gas=with_gas,
        pin_z=model.pin_z[by_z],
        pin_throw=model.pin_throw[by_z],
        pin_cylinders=tuple(model.cylinders[j] for j in by_z),
        pin_max=maximum[:b0][by_z],
        pin_mean=mean[:b0][by_z],
        pin_max_angle=argmax[:b0][by_z],
        main_z=zm,
        main_max=maximum[b0:b1],
        main_mean=mean[b0:b1],
        main_max_with_proposal=main_max_with,
        main_mean_with_proposal=main_mean_with,
        moment_max=moment_max,
        moment_max_with_proposal=moment_max_with,
        pin_load=pin_curve[by_z],
        main_load=main_curve,
        main_load_with_proposal=main_curve_with,
        moment_theta=theta_rev,
        internal_moment=moment_curves,
        internal_moment_with_proposal=moment_curves_with,
        counterweights=cws,
    )


#: What the main-bearing loads of an engine with several crank axes leave out.
GEAR_NOTE = (
    "the gear mesh forces are not in the main-bearing loads: each crankshaft's loads are "
    "those of its own cylinders, rods and counterweights"
)


def axis_engine(engine: Engine, axis: int) -> Engine:
    r"""The one-crank engine of one crank axis of an engine with several.

    Its cylinders are the axis's, at their crank angles from TDC: on a co-rotating axis
    the cylinders themselves turned by the axis's phase (throw :math:`\text{throw} +
    \varphi_s`), on a counter-rotating one their mirror image across the frame's ``y``
    axis (throw :math:`\text{throw} - \varphi_s`, bank and link-pin angle negated), which
    turns forward (docs/several-crankshafts.md, "Bearing loads"); its link rods renumbered
    with its cylinders.  Its axis is the frame's ``z`` axis: its loads are relative to its
    own axis.

    Parameters
    ----------
    engine : Engine
        An engine with several crank axes (:attr:`Engine.geared`).
    axis : int
        The axis (0-based).

    Returns
    -------
    Engine
        The axis's cylinders as a one-crank engine (its pitch the layout's, else its own
        bore pitch; no firing order; the layout's sections except ``bearings``).
    """
    from balance.core.engine import CYLINDER_FIELDS, bore_pitch

    table = engine.axis_table()
    idx = np.flatnonzero(table.axis == axis).astype(np.intp)
    arrays = {name: getattr(engine, name)[idx] for name in CYLINDER_FIELDS}
    phase, sense = float(table.phase[axis]), float(table.rotation[axis])
    throw, bank = engine.throw[idx], engine.bank[idx]
    arrays["throw"] = throw + phase if sense > 0 else throw - phase
    arrays["bank"] = bank if sense > 0 else -bank
    links = engine.links.reordered(idx) if engine.has_links and engine.links is not None else None
    if links is not None and sense < 0:  # the mirror turns the link pins too
        links = replace(links, pin_angle=-links.pin_angle)
    throws = None
    if engine.throw_index is not None:
        throws = np.unique(engine.throw_index[idx], return_inverse=True)[1].astype(np.intp)
    pitch = engine.pitch if engine.pitch_given else bore_pitch(arrays["z"], arrays["bank"])
    sections = {k: v for k, v in engine.sections.items() if k != "bearings"}
    return replace(
        engine.forward_equivalent(),  # one crank axis, at the origin
        firing_order=None,
        gas=engine.gas.reordered(idx) if engine.gas is not None else None,
        mass_parts=engine.mass_parts.reordered(idx) if engine.mass_parts is not None else None,
        links=links,
        throw_index=throws,
        sections=sections,
        pitch=pitch,
        **arrays,
    )


def axis_mains(engine: Engine, axis: int, one_crank: Engine | None = None) -> FloatArray:
    """The main positions of one crank axis: its list in the ``bearings:`` section, else
    the default mains of its own throws.

    Parameters
    ----------
    engine : Engine
        An engine with several crank axes; its ``bearings`` section, if any, a mapping from
        axis name to mains [m] (a plain list is the first axis's).
    axis : int
        The axis (0-based).
    one_crank : Engine, optional
        The axis's one-crank engine (:func:`axis_engine`), if already made.

    Returns
    -------
    ndarray
        Strictly increasing main positions [m].
    """
    from balance.core.bearings import engine_default_mains

    given = engine.section("bearings")
    name = engine.axis_table().names[axis]
    if isinstance(given, Mapping):
        given = given.get(name)
    elif given is not None and axis != 0:
        given = None
    if given is not None:
        return np.asarray(given, dtype=np.float64)
    return engine_default_mains(one_crank if one_crank is not None else axis_engine(engine, axis))


def axes_bearings(engine: Engine, proposal: Any = None) -> Bearings:
    r"""Crank-pin and main-bearing loads of an engine with several crank axes, axis by axis.

    Each axis's loads are those of its one-crank engine (:func:`axis_engine`) with its own
    counterweights of the proposal, :func:`analysis_bearings`; a counter-rotating axis's
    are mirrored back across the frame's ``y`` axis (:math:`F \to \bar F` in the
    :math:`y + \mathrm{i}x` convention), so every load is in the engine frame.  Gear mesh
    forces are not included (:data:`GEAR_NOTE`).

    Parameters
    ----------
    engine : Engine
        An engine with several crank axes (:attr:`Engine.geared`).
    proposal : Proposal or None
        The proposal whose counterweights (each on its ``axis``) load the mains "with
        proposal".

    Returns
    -------
    Bearings
        The pins and mains of every axis, axis by axis, with :attr:`Bearings.pin_axis`,
        :attr:`Bearings.main_axis`, :attr:`Bearings.axis_names` and
        :attr:`Bearings.axis_sense`.
    """
    table = engine.axis_table()
    engine, tables = _with_bore_gas(engine)
    parts: list[Bearings] = []
    for s, name in enumerate(table.names):
        idx = np.flatnonzero(table.axis == s)
        one = axis_engine(engine, s)
        sense = float(table.rotation[s])
        own = _axis_counterweights(proposal, name, s, sense)
        theirs = [tables[i] for i in idx] if tables is not None else None
        b = analysis_bearings(one, own, axis_mains(engine, s, one), tables=theirs)
        if sense < 0:
            b = replace(
                b,
                pin_load=np.conj(b.pin_load),
                main_load=np.conj(b.main_load),
                main_load_with_proposal=np.conj(b.main_load_with_proposal),
                internal_moment=np.conj(b.internal_moment),
                internal_moment_with_proposal=np.conj(b.internal_moment_with_proposal),
                counterweights=tuple((z, u.conjugate()) for z, u in b.counterweights),
            )
        numbers = idx + 1
        b = replace(
            b, pin_cylinders=tuple(tuple(int(numbers[c - 1]) for c in p) for p in b.pin_cylinders)
        )
        parts.append(b)
    first = parts[0]

    def joined(name: str) -> Any:
        return np.concatenate([getattr(b, name) for b in parts], axis=0)

    arrays = [
        "pin_z",
        "pin_throw",
        "pin_max",
        "pin_mean",
        "pin_max_angle",
        "main_z",
        "main_max",
        "main_mean",
        "main_max_with_proposal",
        "main_mean_with_proposal",
        "moment_max",
        "moment_max_with_proposal",
        "pin_load",
        "main_load",
        "main_load_with_proposal",
        "internal_moment",
        "internal_moment_with_proposal",
    ]
    return replace(
        first,
        **{name: joined(name) for name in arrays},
        pin_cylinders=tuple(c for b in parts for c in b.pin_cylinders),
        counterweights=tuple(cw for b in parts for cw in b.counterweights),
        axis_names=tuple(table.names),
        pin_axis=np.concatenate([np.full(b.pin_z.size, s, np.intp) for s, b in enumerate(parts)]),
        main_axis=np.concatenate([np.full(b.main_z.size, s, np.intp) for s, b in enumerate(parts)]),
        axis_sense=np.asarray(table.rotation, dtype=np.float64),
    )


def _with_bore_gas(engine: Engine) -> tuple[Engine, Any]:
    """An engine with several crank axes with each bore's gas (opposed pistons share one
    pressure), and each cylinder's pressure table; the engine as it is without gas."""
    from balance.core.bore_pairs import bore_pair_gas
    from balance.core.torque import engine_pressure_tables, piston_travels

    if engine.gas is None:
        return engine, None
    forward = engine.forward_equivalent()
    gas, travels = bore_pair_gas(engine, piston_travels(forward))
    return replace(engine, gas=gas), engine_pressure_tables(replace(forward, gas=gas), travels)


def _axis_counterweights(
    proposal: Any, name: str, s: int, sense: float
) -> list[tuple[float, complex]]:
    """The ``(z, unbalance)`` of a proposal's counterweights on axis ``s`` in its one-crank
    engine's frame (mirrored on a counter-rotating axis, :func:`axes_bearings`)."""
    weights = proposal.counterweights if proposal is not None else ()
    return [
        (float(cw.z), complex(cw.unbalance) if sense > 0 else complex(cw.unbalance).conjugate())
        for cw in weights
        if cw.axis == name or (cw.axis is None and s == 0)
    ]


def axes_largest_loads(engine: Engine, proposals: Sequence[Any]) -> tuple[FloatArray, FloatArray]:
    """Largest main-bearing load and internal moment with each proposal's counterweights, for
    an engine with several crank axes: :func:`largest_loads` axis by axis (each axis's
    one-crank engine, as :func:`axes_bearings` loads it), the largest over the axes.

    Parameters
    ----------
    engine : Engine
        An engine with several crank axes (:attr:`Engine.geared`).
    proposals : sequence of Proposal or None
        One set of counterweights each (each on its ``axis``).

    Returns
    -------
    main_max, moment_max : ndarray
        Shape (proposals,): the largest over all mains of every axis of the largest magnitude
        over the cycle [N, N m].
    """
    table = engine.axis_table()
    engine, tables = _with_bore_gas(engine)
    main_max = np.zeros(len(proposals))
    moment_max = np.zeros(len(proposals))
    for s, name in enumerate(table.names):
        idx = np.flatnonzero(table.axis == s)
        one = axis_engine(engine, s)
        sense = float(table.rotation[s])
        sets = [_axis_counterweights(p, name, s, sense) for p in proposals]
        theirs = [tables[i] for i in idx] if tables is not None else None
        mains, moments = largest_loads(one, sets, axis_mains(engine, s, one), tables=theirs)
        main_max = np.maximum(main_max, mains)
        moment_max = np.maximum(moment_max, moments)
    return main_max, moment_max


def largest_loads(
    engine: Engine,
    counterweight_sets: Sequence[Iterable[tuple[float, complex]]],
    mains: ArrayLike | None = None,
    gas: bool = True,
    tables: list[tuple[FloatArray, FloatArray]] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Largest main-bearing load and internal moment for each set of counterweights.

    One pass for every set (a balance-factor study: one proposal per factor): the pin loads
    are computed once and each set adds its order-1 term (:func:`analysis_bearings`).

    Parameters
    ----------
    engine, mains, gas
        As for :func:`~balance.core.bearings.bearing_loads`.
    counterweight_sets : sequence of iterable of (float, complex)
        The ``(z [m], unbalance [kg m])`` of each set's counterweights.
    tables : list of (ndarray, ndarray), optional
        Each cylinder's pressure table (:class:`~balance.core.bearings.LoadModel`).

    Returns
    -------
    main_max, moment_max : ndarray
        Shape (sets,): the largest over all mains of the largest magnitude over the cycle
        [N, N m].
    """
    zm = engine_mains(engine) if mains is None else np.asarray(mains, dtype=np.float64)
    with_gas = gas and engine.gas is not None
    model = LoadModel(engine, zm, (), with_gas, tables)
    n_pins, n_mains, n_sets = model.pin_z.size, zm.size, len(counterweight_sets)
    w2 = float(speed_squared(engine.speed))
    cw_main = np.zeros((n_sets, n_mains), dtype=np.complex128)
    cw_moment = np.zeros((n_sets, n_mains), dtype=np.complex128)
    for s, cws in enumerate(counterweight_sets):
        pairs = [(float(z), complex(u)) for z, u in cws]
        if pairs:
            cz = np.array([z for z, _ in pairs])
            cu = np.array([u for _, u in pairs]) * w2
            cw_main[s] = lever_shares(cz, zm) @ cu
            cw_moment[s] = moment_arms(cz, zm) @ cu
    k, coeffs = model.inertia_series()
    one = (k == 1).astype(np.float64)
    mains_c, moments_c = coeffs[n_pins : n_pins + n_mains], coeffs[n_pins + n_mains :]
    moment_rows = (moments_c[None] + cw_moment[:, :, None] * one).reshape(-1, k.size)
    if with_gas:
        assert engine.gas is not None
        cycle = math.radians(engine.gas.cycle_deg)

        def loads(t: FloatArray) -> FloatArray:
            pins = model.pins(t, True)
            main = model.mains_of(model.throws(pins, t), t)
            turning = np.exp(1j * t)[None, None, :]
            return np.abs(main[None] + cw_main[:, :, None] * turning).reshape(-1, t.size)

        nodes, weights, edges = gas_nodes(engine, model)
        main_max = node_stats(loads, nodes, weights, edges, cycle, mean_wanted=False).maximum
        moment_max = series_stats(
            k, moment_rows, np.zeros(moment_rows.shape[0], dtype=bool)
        ).maximum
    else:
        main_rows = (mains_c[None] + cw_main[:, :, None] * one).reshape(-1, k.size)
        rows = np.concatenate([main_rows, moment_rows], axis=0)
        stats = series_stats(k, rows, np.zeros(rows.shape[0], dtype=bool))
        main_max, moment_max = (
            stats.maximum[: main_rows.shape[0]],
            stats.maximum[main_rows.shape[0] :],
        )
    return (
        main_max.reshape(n_sets, n_mains).max(axis=1),
        moment_max.reshape(n_sets, n_mains).max(axis=1),
    )


@dataclass(frozen=True)
class BearingsPart:
    """The ``bearings`` section's part of a result.

    Attributes
    ----------
    loads : Bearings
        Crank-pin and main-bearing loads and internal moments, without and with the
        proposed counterweights.
    strategies : tuple of (str, Bearings)
        With the option ``strategies``: the loads with each counterweight strategy's
        proposal (the other settings as the request's), in :data:`STRATEGIES` order.
    """

    loads: Bearings
    strategies: tuple[tuple[str, Bearings], ...] = ()


def bearings_part(engine: Engine, request: Any, result: Any, *, strategies: bool = False) -> Any:
    """The ``bearings`` section (:mod:`balance.core.sections`).

    The loads with the result's proposal (:func:`analysis_bearings`); with ``strategies``,
    also with the proposal of each counterweight strategy; and, when the result holds a
    balance-factor study, the largest main-bearing load and internal moment with each
    factor's proposal.

    Parameters
    ----------
    engine : Engine
        The analysed engine (its ``bearings:`` section's mains, else the defaults).
    request : Request
        The request (its ``proposal`` options, for the strategies and the factor study).
    result : Result
        The result so far, with its ``proposal`` and ``factor_study`` parts if asked.
    strategies : bool
        Also compute the loads with each counterweight strategy's proposal.

    Returns
    -------
    Result
        ``result`` with the ``bearings`` part (:class:`BearingsPart`) added, and the factor
        study's largest loads filled in.
    """
    from balance.core.analysis import compute

    if engine.geared:  # each crankshaft's loads: docs/several-crankshafts.md, "Bearing loads"

        def loads_with(proposal: Any) -> Bearings:
            return axes_bearings(engine, proposal)

        def largest(proposals: list[Any]) -> tuple[FloatArray, FloatArray]:
            return axes_largest_loads(engine, proposals)

    else:

        def loads_with(proposal: Any) -> Bearings:
            return analysis_bearings(engine, counterweights_of(proposal))

        def largest(proposals: list[Any]) -> tuple[FloatArray, FloatArray]:
            return largest_loads(engine, [counterweights_of(p) for p in proposals])

    proposal = result.part("proposal")
    loads = loads_with(proposal.proposal if proposal else None)
    by_strategy: list[tuple[str, Bearings]] = []
    if strategies:
        asked = request.only("proposal")
        for strategy in STRATEGIES:
            options = {**asked.options("proposal"), "strategy": strategy}
            other = replace(asked.with_sections(proposal=options), roll=True)
            theirs = compute(engine, other).part("proposal")
            by_strategy.append((strategy, loads_with(theirs.proposal if theirs else None)))
    study = result.part("factor_study")
    if study is not None:  # each factor's proposal
        settings = request.options("proposal")
        proposals = [
            _factor_proposal(engine, factor, settings)
            for factor in np.asarray(study.factor, dtype=np.float64)
        ]
        main_max, moment_max = largest(proposals)
        study = replace(study, largest_main_load=main_max, largest_internal_moment=moment_max)
        result = result.with_part("factor_study", study)
    return result.with_part("bearings", BearingsPart(loads, tuple(by_strategy)))


def _factor_proposal(engine: Engine, factor: float, settings: Mapping[str, Any]) -> Any:
    """The proposal made at ``factor`` with the request's ``strategy`` and
    ``counterweight_radius`` (the rest as the engine's ``balance:`` section, else the
    defaults); None where none is made."""
    from balance.core.analysis import compute
    from balance.core.result import Request

    proposal = {
        "balance_factor": float(factor),
        "strategy": settings.get("strategy"),
        "counterweight_radius": settings.get("counterweight_radius"),
    }
    part = compute(engine, Request(orders=(1, 2), sections={"proposal": proposal})).part("proposal")
    return part.proposal if part is not None else None


def _loads(result: Any) -> Bearings:
    part: BearingsPart = result.part("bearings")
    return part.loads


def _with_gas(result: Any) -> str:
    return " (with gas forces)" if _loads(result).gas else ""


def _output(name: str, dims: tuple[str, ...], units: str, long_name: Any, get: Any) -> Output:
    if isinstance(long_name, str) and "{gas}" in long_name:
        text = long_name
        long_name = lambda r: text.format(gas=_with_gas(r))  # noqa: E731
    return Output(name, dims, units, long_name, lambda r: get(_loads(r)))


def _curves(
    name: str, attribute: str, dims: tuple[str, ...], units: str, what: str
) -> tuple[Output, ...]:
    """A complex curve (the loads' ``attribute``) as its y and x components, ``name_y``
    and ``name_x`` (netCDF has no complex numbers)."""
    return (
        _output(
            f"{name}_y",
            dims,
            units,
            f"{what}, y component (engine frame)",
            lambda b: getattr(b, attribute).real,
        ),
        _output(
            f"{name}_x",
            dims,
            units,
            f"{what}, x component (engine frame)",
            lambda b: getattr(b, attribute).imag,
        ),
    )


def _shaft_names(b: Bearings, which: NDArray[np.intp] | None) -> list[str]:
    """The crank axis's name of each pin or main."""
    assert which is not None
    return [b.axis_names[int(a)] for a in which]


_PIN, _MAIN = ("crank_pin",), ("main_bearing",)
_PIN_CURVE = ("crank_pin", "bearing_crank_angle")
_MAIN_CURVE = ("main_bearing", "bearing_crank_angle")
_MOMENT_CURVE = ("main_bearing", "moment_crank_angle")

#: The outputs of the ``bearings`` section.
OUTPUTS: tuple[Output, ...] = (
    _output("crank_pin_z", _PIN, "m", "axial position of the crank pin", lambda b: b.pin_z),
    _output(
        "crank_pin_cylinders",
        _PIN,
        "1",
        "cylinders whose rods act on the crank pin",
        lambda b: [" ".join(map(str, c)) for c in b.pin_cylinders],
    ),
    _output("crank_pin_max_load", _PIN, "N", "largest crank-pin load{gas}", lambda b: b.pin_max),
    _output(
        "crank_pin_mean_load",
        _PIN,
        "N",
        "mean magnitude of the crank-pin load{gas}",
        lambda b: b.pin_mean,
    ),
    _output(
        "crank_pin_max_angle",
        _PIN,
        "deg",
        "crank angle of the largest crank-pin load",
        lambda b: np.degrees(b.pin_max_angle),
    ),
    Output(
        "crank_pin_crankshaft",
        _PIN,
        "1",
        "crankshaft of the crank pin",
        lambda r: _shaft_names(_loads(r), _loads(r).pin_axis),
        when=lambda r: _loads(r).pin_axis is not None,
    ),
    _output("main_bearing_z", _MAIN, "m", "axial position of the main bearing", lambda b: b.main_z),
    Output(
        "main_bearing_crankshaft",
        _MAIN,
        "1",
        "crankshaft of the main bearing",
        lambda r: _shaft_names(_loads(r), _loads(r).main_axis),
        when=lambda r: _loads(r).main_axis is not None,
    ),
    _output(
        "main_bearing_max_load", _MAIN, "N", "largest main-bearing load{gas}", lambda b: b.main_max
    ),
    _output(
        "main_bearing_mean_load",
        _MAIN,
        "N",
        "mean magnitude of the main-bearing load{gas}",
        lambda b: b.main_mean,
    ),
    _output(
        "main_bearing_max_load_with_proposal",
        _MAIN,
        "N",
        "largest main-bearing load with the proposed counterweights{gas}",
        lambda b: b.main_max_with_proposal,
    ),
    _output(
        "main_bearing_mean_load_with_proposal",
        _MAIN,
        "N",
        "mean magnitude of the main-bearing load with the proposed counterweights{gas}",
        lambda b: b.main_mean_with_proposal,
    ),
    _output(
        "internal_moment_max",
        _MAIN,
        "N m",
        "largest internal bending moment of the crankshaft at the main",
        lambda b: b.moment_max,
    ),
    _output(
        "internal_moment_max_with_proposal",
        _MAIN,
        "N m",
        "largest internal bending moment at the main with the proposed counterweights",
        lambda b: b.moment_max_with_proposal,
    ),
    *_curves("crank_pin_load", "pin_load", _PIN_CURVE, "N", "crank-pin load"),
    *_curves("main_bearing_load", "main_load", _MAIN_CURVE, "N", "main-bearing load"),
    *_curves(
        "main_bearing_load_with_proposal",
        "main_load_with_proposal",
        _MAIN_CURVE,
        "N",
        "main-bearing load with the proposed counterweights",
    ),
    *_curves("internal_moment", "internal_moment", _MOMENT_CURVE, "N m", "internal moment"),
    *_curves(
        "internal_moment_with_proposal",
        "internal_moment_with_proposal",
        _MOMENT_CURVE,
        "N m",
        "internal moment with the proposed counterweights",
    ),
    Output(
        "crank_pin",
        _PIN,
        "1",
        "crank pin number",
        lambda r: np.arange(1, _loads(r).pin_z.size + 1),
        kind="coord",
    ),
    Output(
        "main_bearing",
        _MAIN,
        "1",
        "main bearing number",
        lambda r: np.arange(1, _loads(r).main_z.size + 1),
        kind="coord",
    ),
    Output(
        "bearing_crank_angle",
        ("bearing_crank_angle",),
        "deg",
        "crank angle theta of the bearing-load curves",
        lambda r: np.degrees(_loads(r).theta),
        kind="coord",
    ),
    Output(
        "moment_crank_angle",
        ("moment_crank_angle",),
        "deg",
        "crank angle theta of the internal-moment curves",
        lambda r: np.degrees(_loads(r).moment_theta),
        kind="coord",
    ),
)
