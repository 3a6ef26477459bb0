"""The analysis: from a layout to its free forces, moments and roll, order by order.

:func:`compute_phasors` forms the free forces, moments and roll of one engine with the
model rung asked for (:class:`~balance.core.result.FreeForces`); :func:`free_phasors` is
the same sum at unit speed over any grid of engines, which single analyses, sweeps and
tolerance studies share.  :func:`compute` answers a :class:`~balance.core.result.Request`:
the free forces, then every section asked for (:mod:`balance.core.sections`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import accuracy, kinematics, phasors
from balance.core._numerics import mean
from balance.core.engine import CYLINDER_FIELDS, Engine, Links
from balance.core.errors import InputError
from balance.core.phasors import Phasors
from balance.core.plausibility import check_engine
from balance.core.result import FreeForces, ModelRung, Request, Result
from balance.core.sections import SECTIONS, load
from balance.core.speed import speed_squared

__all__ = [
    "compute",
    "compute_phasors",
    "engine_cylinders",
    "free_phasors",
    "free_phasors_of",
    "reference_force",
]


ComplexArray = NDArray[np.complex128]


def compute_phasors(
    layout: Engine,
    orders: int | Iterable[int] | None = None,
    *,
    model: str = "exact",
    terms: int = 3,
    samples: int | None = None,
    moments: bool = True,
    roll: bool = True,
) -> FreeForces:
    """The free forces, moments and roll of a layout at its speed.

    Parameters
    ----------
    layout : Engine
        The engine.
    orders : int or sequence of int, optional
        Orders to compute: 1 to N for an int N, default 1 to 8 (spec strings such as
        ``"1-8"`` are read by :func:`balance.io.orders.parse_orders` at the edges).
    model : {'exact', 'series', 'textbook', 'time'}
        How the piston acceleration is expanded
        (:func:`balance.core.kinematics.acceleration_coefficients`), or ``time``: forces, moments
        and roll synthesised over ``samples`` crank angles and transformed
        (:mod:`balance.core.sampled`).
    terms : int
        Binomial terms of the ``series`` model.
    samples : int, optional
        Crank angles per revolution of the ``time`` model (default the smallest power of
        two above 8 times the highest order, at least 256).
    moments, roll : bool
        Compute the moments and the roll (otherwise they are None and not reported).

    Returns
    -------
    FreeForces
        The phasors [N, N m], the acceleration coefficients, the model rung with its error
        bound, and the link pins' phasors of an engine with link rods.
    """
    ks = _orders_array(orders)
    if layout.geared:
        return _geared(layout, ks, model, terms, samples, moments=moments, roll=roll)
    if model == "time":
        return _compute_time(layout, ks, samples, moments=moments, roll=roll)
    unit = free_phasors_of(
        engine_cylinders(layout),
        layout.z - layout.reference_z,
        ks,
        model=model,
        terms=terms,
        moments=moments,
        roll=roll,
        links=layout.links if layout.has_links else None,
    )
    w2 = speed_squared(layout.speed)
    bound = accuracy.engine_error_bound(model, layout, terms=terms, max_order=int(ks.max()))
    return FreeForces(
        phasors=unit.phasors.scaled(w2),
        coefficients=unit.coefficients,
        model=ModelRung(model, terms, 0, bound),
        link_pins=None if unit.link_pins is None else unit.link_pins.scaled(w2),
    )


def _geared(
    layout: Engine,
    ks: NDArray[np.intp],
    model: str,
    terms: int,
    samples: int | None,
    *,
    moments: bool,
    roll: bool,
) -> FreeForces:
    """Several crank axes: each analysed as a one-crank engine and combined
    (:func:`balance.core.geared.geared_free_forces`)."""
    from balance.core.geared import geared_free_forces

    def one_crank(engine: Engine) -> FreeForces:
        return compute_phasors(
            engine, ks, model=model, terms=terms, samples=samples, moments=moments, roll=roll
        )

    whole, parts, first = geared_free_forces(layout, one_crank, moments=moments, roll=roll)
    return replace(first, phasors=whole, shafts=parts)


def engine_cylinders(layout: Engine) -> dict[str, Any]:
    """The table of cylinders that :func:`free_phasors_of` reads.

    Parameters
    ----------
    layout : Engine
        The engine.

    Returns
    -------
    dict
        The per-cylinder arrays of :data:`balance.core.engine.CYLINDER_FIELDS` by name (SI,
        radians), and for an engine with link rods the link rods' link-pin shares
        ``link_pin_mass`` [kg] (:func:`balance.core.links.pin_masses`).
    """
    cylinders: dict[str, Any] = {name: getattr(layout, name) for name in CYLINDER_FIELDS}
    if layout.has_links:
        from balance.core.links import pin_masses

        cylinders["link_pin_mass"] = pin_masses(layout)
    return cylinders


def _orders_array(orders: int | Iterable[int] | None) -> NDArray[np.intp]:
    """Orders as a sorted array of distinct orders: ``None`` is 1 to 8, an int N is 1 to N.

    The core assumes the orders are valid (whole numbers of at least 1); the edges check
    what a user wrote (:func:`balance.io.orders.parse_orders`).
    """
    if orders is None:
        orders = 8
    if isinstance(orders, int | np.integer):
        return np.arange(1, int(orders) + 1, dtype=np.intp)
    return np.asarray(sorted({int(k) for k in orders}), dtype=np.intp)


def free_phasors(
    reciprocating_mass: ArrayLike,
    rotating_mass: ArrayLike,
    crank_radius: ArrayLike,
    conrod_length: ArrayLike,
    offset: ArrayLike,
    throw: ArrayLike,
    bank: ArrayLike,
    lever: ArrayLike,
    conrod_inertia_correction: ArrayLike,
    orders: NDArray[np.intp],
    *,
    model: str = "exact",
    terms: int = 3,
    moments: bool = True,
    roll: bool = True,
    links: Links | None = None,
    link_pin_mass: ArrayLike | None = None,
) -> FreeForces:
    r"""Free force, moment and roll phasors at unit crank speed, over any grid of engines.

    Parameters
    ----------
    reciprocating_mass, rotating_mass : array_like
        Per cylinder [kg], cylinders on the last axis; leading axes broadcast (a sweep's
        grid).
    crank_radius, conrod_length, offset : array_like
        Per cylinder [m].
    throw, bank : array_like
        Per cylinder [rad].
    lever : array_like
        :math:`z_i - z_{ref}` per cylinder [m].
    conrod_inertia_correction : array_like
        :math:`\Delta I` per cylinder [kg m²] (roll only).
    orders : ndarray of int
        The K orders.
    model, terms
        Acceleration model (:func:`balance.core.kinematics.acceleration_coefficients`).
    moments, roll : bool
        Whether to form the moment and roll sums.
    links : Links, optional
        Articulated rods (:class:`balance.core.engine.Links`); given, the sums are those of
        :func:`balance.core.links.articulated_free_phasors` (the geometry must then be one
        engine's, 1-D; the masses may carry grid axes).
    link_pin_mass : array_like, optional
        The link rods' link-pin shares per cylinder [kg] (needed with ``links``).

    Returns
    -------
    FreeForces
        At unit crank speed [kg m, kg m²]: :meth:`Phasors.scaled` by :math:`\omega^2` gives
        the forces [N, N m]; its model rung has no error bound (NaN).

    Notes
    -----
    :func:`compute` (one engine) and :func:`balance.studies.sweep.sweep` (a grid) both call this
    function and then multiply by :math:`\omega^2`; each value is formed by the same
    operations in the same order, so the two agree bit for bit.
    """
    if links is not None and np.any(links.master >= 0):
        from balance.core.links import articulated_free_phasors

        assert link_pin_mass is not None, "link engines need the link-pin masses"
        parts = articulated_free_phasors(
            reciprocating_mass=reciprocating_mass,
            rotating_mass=rotating_mass,
            pin_mass=link_pin_mass,
            crank_radius=crank_radius,
            conrod_length=conrod_length,
            offset=offset,
            throw=throw,
            bank=bank,
            lever=lever,
            conrod_inertia_correction=conrod_inertia_correction,
            links=links,
            orders=orders,
            model=model,
            terms=terms,
            moments=moments,
            roll=roll,
        )
        pin_forward, pin_backward = parts["pin_forward"], parts["pin_backward"]
        assert pin_forward is not None and pin_backward is not None
        return FreeForces(
            phasors=Phasors(
                orders=orders,
                force_forward=_given(parts["force_forward"]),
                force_backward=_given(parts["force_backward"]),
                moment_forward=parts.get("moment_forward"),
                moment_backward=parts.get("moment_backward"),
                rotating_force=_given(parts["rotating_force"]),
                rotating_moment=parts.get("rotating_moment"),
                roll=parts.get("roll"),
            ),
            coefficients=_given(parts["coefficients"]),
            model=ModelRung(model, terms, 0, math.nan),
            link_pins=Phasors(
                orders=orders, force_forward=pin_forward, force_backward=pin_backward
            ),
        )
    r = np.asarray(crank_radius, dtype=np.float64)
    ratio = kinematics.rod_ratio(r, conrod_length)
    eps = kinematics.offset_ratio(offset, r)
    coeffs = kinematics.acceleration_coefficients(ratio, eps, orders, model=model, terms=terms)
    m_rec = np.asarray(reciprocating_mass, dtype=np.float64)
    amp = m_rec * r
    f_fwd, f_bwd, m_fwd, m_bwd = phasors.reciprocating_force_and_moment(
        amp, coeffs, throw, bank, orders, lever if moments else None
    )
    assert f_fwd is not None and f_bwd is not None
    rot_amp = np.asarray(rotating_mass, dtype=np.float64) * r
    roll_phasors = None
    if roll:
        g_rec, g_rod = kinematics.roll_coefficients(ratio, eps, orders)
        roll_phasors = phasors.roll_phasors(
            m_rec * r**2, conrod_inertia_correction, g_rec, g_rod, throw, bank, orders
        )
    return FreeForces(
        phasors=Phasors(
            orders=orders,
            force_forward=f_fwd,
            force_backward=f_bwd,
            moment_forward=m_fwd if moments else None,
            moment_backward=m_bwd if moments else None,
            rotating_force=phasors.rotating_phasor(rot_amp, throw),
            rotating_moment=phasors.rotating_phasor(rot_amp, throw, lever) if moments else None,
            roll=roll_phasors,
        ),
        coefficients=coeffs,
        model=ModelRung(model, terms, 0, math.nan),
    )


def _given(value: ComplexArray | None) -> ComplexArray:
    assert value is not None
    return value


def free_phasors_of(
    cylinders: Mapping[str, ArrayLike],
    lever: ArrayLike,
    orders: NDArray[np.intp],
    **options: Any,
) -> FreeForces:
    """:func:`free_phasors` of a table of cylinders.

    Parameters
    ----------
    cylinders : mapping of str to array_like
        The arrays named as :data:`balance.core.engine.CYLINDER_FIELDS` (a layout's, or a
        sweep's grid of them, cylinders on the last axis), and ``link_pin_mass`` [kg] for an
        engine with link rods (:func:`engine_cylinders`).
    lever : array_like
        :math:`z_i - z_{ref}` per cylinder [m].
    orders : ndarray of int
        The orders.
    **options
        The keywords of :func:`free_phasors` (``model``, ``terms``, ``moments``, ``roll``,
        ``links``).

    Returns
    -------
    FreeForces
        At unit crank speed, as :func:`free_phasors`.
    """
    if options.get("links") is not None:
        options = {**options, "link_pin_mass": cylinders["link_pin_mass"]}
    return free_phasors(
        cylinders["reciprocating_mass"],
        cylinders["rotating_mass"],
        cylinders["crank_radius"],
        cylinders["conrod_length"],
        cylinders["offset"],
        cylinders["throw"],
        cylinders["bank"],
        lever,
        cylinders["conrod_inertia_correction"],
        orders,
        **options,
    )


def reference_force(layout: Engine) -> float:
    r""":math:`F_1 = m_{rec} r \omega^2` with the engine means of mass and radius.

    Parameters
    ----------
    layout : Engine
        The engine (its reciprocating masses, crank radii and speed).

    Returns
    -------
    float
        The first-order reciprocating force of one mean cylinder [N], the unit of the
        normalised forces (docs/conventions.md, "Normalisation and ``pitch``").
    """
    return float(
        mean(layout.reciprocating_mass) * mean(layout.crank_radius) * speed_squared(layout.speed)
    )


def _rotating(layout: Engine, moments: bool) -> tuple[ComplexArray, ComplexArray | None]:
    """Rotating force and (if asked) moment phasors, order 1 forward [N, N m]."""
    w2 = speed_squared(layout.speed)
    amplitude = layout.rotating_mass * layout.crank_radius
    force = phasors.rotating_phasor(amplitude, layout.throw) * w2
    if not moments:
        return force, None
    lever = layout.z - layout.reference_z
    return force, phasors.rotating_phasor(amplitude, layout.throw, lever) * w2


def _compute_time(
    layout: Engine, ks: NDArray[np.intp], samples: int | None, *, moments: bool, roll: bool
) -> FreeForces:
    """The ``time`` model: sample, sum as vectors, transform."""
    from balance.core import sampled

    k_max = int(ks.max())
    if samples is None:
        samples = max(256, 1 << math.ceil(math.log2(8 * k_max + 1)))
    if samples <= 2 * k_max:
        raise InputError(
            f"samples: {samples} crank angles resolve orders up to {(samples - 1) // 2}, "
            f"not {k_max}; give more than {2 * k_max}"
        )
    theta = sampled.crank_angles(samples)
    omega2 = speed_squared(layout.speed)
    r = layout.crank_radius
    ratio = kinematics.rod_ratio(r, layout.conrod_length)
    eps = kinematics.offset_ratio(layout.offset, r)
    amp = layout.reciprocating_mass * r * omega2
    n = layout.n_cylinders
    force_scale = float(np.sum(amp))
    if layout.has_links:  # the link pins' relative motion: at most m r w^2 (rho/r) gamma_2
        from balance.core.links import pin_masses

        pin = layout.links.pin_radius if layout.links is not None else 0.0
        force_scale += float(np.sum(pin_masses(layout) * pin * omega2))
    rotating_force, rotating_moment = _rotating(layout, moments)
    force, moment = sampled.reciprocating_samples(layout, theta)
    f_fwd, f_bwd = sampled.phasors_from_samples(force, ks)
    bundle = Phasors(
        orders=ks,
        force_forward=phasors.cancel_to_zero(f_fwd, force_scale, n * 4),
        force_backward=phasors.cancel_to_zero(f_bwd, force_scale, n * 4),
        rotating_force=rotating_force,
        rotating_moment=rotating_moment,
    )
    if moments:
        lever = layout.z - layout.reference_z
        moment_scale = float(np.sum(amp * np.abs(lever)))
        m_fwd, m_bwd = sampled.phasors_from_samples(moment, ks)
        bundle = replace(
            bundle,
            moment_forward=phasors.cancel_to_zero(m_fwd, moment_scale, n * 4),
            moment_backward=phasors.cancel_to_zero(m_bwd, moment_scale, n * 4),
        )
    if roll:
        roll_scale = float(
            np.sum(layout.reciprocating_mass * r**2 + np.abs(layout.conrod_inertia_correction))
            * omega2
        )
        bundle = replace(
            bundle,
            roll=phasors.cancel_to_zero(
                sampled.roll_phasors_from_samples(sampled.roll_newton_euler(layout, theta), ks),
                roll_scale,
                n * 8,
            ),
        )
    link_pins = None
    beta = theta[None, :]
    bound = accuracy.engine_error_bound("time", layout, samples=samples, max_order=k_max)
    if layout.has_links:
        assert layout.links is not None
        j = layout.links.link_indices
        plain = layout.links.master < 0
        per_cylinder = np.zeros((n, samples))
        per_cylinder[plain] = kinematics.normalised_acceleration(
            beta, ratio[plain, None], eps[plain, None]
        )
        # sampled at theta: shift to the cylinder's own beta_j = theta + phi - psi_j
        ahead = theta[None, :] - (layout.throw[j] - layout.bank[j])[:, None]
        per_cylinder[j] = -sampled.link_piston_acceleration_at(layout, ahead)
        pins = np.zeros((n, samples), dtype=np.complex128)
        pins[j] = sampled.link_pin_force_samples(layout, theta)
        pin_fwd, pin_bwd = sampled.phasors_from_samples(pins, ks)
        link_pins = Phasors(orders=ks, force_forward=pin_fwd, force_backward=pin_bwd)
    else:
        per_cylinder = kinematics.normalised_acceleration(beta, ratio[:, None], eps[:, None])
    coeffs = 2.0 * np.fft.rfft(per_cylinder, axis=-1)[:, ks] / samples
    return FreeForces(
        phasors=bundle,
        coefficients=coeffs,
        model=ModelRung("time", 0, samples, bound),
        link_pins=link_pins,
    )


def compute(engine: Engine, request: Request) -> Result:
    """Analyse an engine: what the request asks for, and nothing else.

    Parameters
    ----------
    engine : Engine
        The engine (:func:`balance.load_layout`).
    request : Request
        Orders, model and the sections to compute (:class:`balance.core.result.Request`;
        :func:`balance.io.request.build_request` builds one from what a user gives).

    Returns
    -------
    Result
        The free forces, moments and roll as complex phasors with their references, the
        plausibility warnings of the engine at the speed analysed
        (:mod:`balance.core.plausibility`), and a part for every section asked for
        (:mod:`balance.core.sections`), computed in section order.
    """
    if request.speed is not None:
        engine = engine.with_speed(request.speed)
    model, terms = request.model, request.terms
    if request.tolerance is not None:
        model, terms, _ = accuracy.choose_model_for(request.tolerance, engine)
        request = replace(request, model=model, terms=terms)
    ks = np.asarray(request.orders, dtype=np.intp)
    free = compute_phasors(
        engine,
        ks,
        model=model,
        terms=terms,
        samples=request.samples,
        moments=request.moments,
        roll=request.roll,
    )
    f1 = reference_force(engine)
    pitch = engine.pitch
    radius = request.options("proposal").get("counterweight_radius")
    result = Result(
        engine=engine,
        request=request,
        phasors=free.phasors,
        coefficients=free.coefficients,
        model=free.model,
        link_pins=free.link_pins,
        shafts=free.shafts,
        roll_orders=ks.astype(np.float64),
        roll=free.phasors.roll,
        reference_force=f1,
        pitch=pitch,
        reference_moment=f1 * pitch if math.isfinite(pitch) else math.nan,
        reference_roll=float(mean(engine.reciprocating_mass) * mean(engine.crank_radius) ** 2)
        * float(speed_squared(engine.speed)),
        warnings=check_engine(engine, radius),
    )
    for section in SECTIONS:
        options = request.sections.get(section.name)
        if options is None:  # not asked for
            continue
        if section.needed is None or section.needed(engine, request, result, options):
            result = load(section.part)(engine, request, result, **options)
    return result
