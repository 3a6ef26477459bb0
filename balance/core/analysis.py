"""The analysis: from a layout to its free forces, moments and roll, order by order.

:func:`compute` does the arithmetic and returns plain complex arrays
(:class:`Phasors`); :func:`analyse` wraps it into the result Dataset
(:mod:`balance.views.dataset`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import accuracy, kinematics, phasors
from balance.core.balancing import proposal_phasors, propose, shaft_roll_phasors
from balance.core.engine import CYLINDER_FIELDS, Engine, Links, ShaftPosition
from balance.core.errors import InputError
from balance.core.plausibility import check_engine
from balance.core.result import Balanced, Phasors, Request, Result
from balance.core.speed import speed_squared

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.torque import TorqueResult

__all__ = [
    "Balanced",
    "FreePhasors",
    "Phasors",
    "balance_engine",
    "compute",
    "compute_phasors",
    "engine_cylinders",
    "first_order_parts",
    "free_phasors",
    "free_phasors_of",
    "speed_squared",
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
) -> Phasors:
    """Phasors of the free forces, moments and roll of a layout.

    Parameters
    ----------
    layout : Engine
        The engine.
    orders : int or sequence of int, optional
        Orders to compute: 1 to N for an int N, default 1 to 8 (spec strings such as
        ``"1-8"`` are read by :func:`balance.io.fields.parse_orders` at the edges).
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
        Compute the moments and the roll (otherwise they are left as NaN and not reported).

    Returns
    -------
    Phasors
    """
    ks = _orders_array(orders)
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
    values = unit.scaled(w2)
    if unit.pin_forward is not None and unit.pin_backward is not None:
        values["link_pin_forward"] = unit.pin_forward * w2
        values["link_pin_backward"] = unit.pin_backward * w2
    return _assemble(
        layout,
        ks,
        values,
        unit.coefficients,
        model=model,
        terms=terms,
        error_bound=bound,
    )


def engine_cylinders(layout: Engine) -> dict[str, Any]:
    """The table of cylinders that :func:`free_phasors_of` reads: the arrays of
    :data:`balance.core.engine.CYLINDER_FIELDS`, and for an engine with link rods the link
    rods' link-pin shares (``link_pin_mass``, :func:`balance.core.links.pin_masses`)."""
    cylinders: dict[str, Any] = {name: getattr(layout, name) for name in CYLINDER_FIELDS}
    if layout.has_links:
        from balance.core.links import pin_masses

        cylinders["link_pin_mass"] = pin_masses(layout)
    return cylinders


def _orders_array(orders: int | Iterable[int] | None) -> NDArray[np.intp]:
    """Orders as a sorted array of distinct orders: ``None`` is 1 to 8, an int N is 1 to N.

    The core assumes the orders are valid (whole numbers of at least 1); the edges check
    what a user wrote (:func:`balance.io.fields.parse_orders`).
    """
    if orders is None:
        orders = 8
    if isinstance(orders, int | np.integer):
        return np.arange(1, int(orders) + 1, dtype=np.intp)
    return np.asarray(sorted({int(k) for k in orders}), dtype=np.intp)


@dataclass(frozen=True)
class FreePhasors:
    r"""Phasor sums of one engine (or a grid of engines) at unit crank speed.

    Every inertia force is proportional to :math:`\omega^2`; these are the sums with
    :math:`\omega = 1` rad/s [kg m, kg m², kg m²]; :meth:`scaled` multiplies them by
    :math:`\omega^2`.  Shapes: leading grid axes, then the orders (the rotating phasors
    have no order axis).  Phasors not asked for are None.  ``pin_forward`` and
    ``pin_backward`` (engines with link rods only) hold each cylinder's link-pin phasors,
    shape ``(..., cylinders, orders)`` (:func:`balance.core.links.articulated_free_phasors`).
    """

    force_forward: ComplexArray
    force_backward: ComplexArray
    rotating_force: ComplexArray
    coefficients: ComplexArray
    moment_forward: ComplexArray | None = None
    moment_backward: ComplexArray | None = None
    rotating_moment: ComplexArray | None = None
    roll: ComplexArray | None = None
    pin_forward: ComplexArray | None = None
    pin_backward: ComplexArray | None = None

    def scaled(self, omega_squared: ArrayLike) -> dict[str, ComplexArray | None]:
        r"""The phasors at :math:`\omega^2` [N, N m]; ``omega_squared`` broadcasts against
        the grid axes (give it a trailing axis of size one for the order axis)."""
        w2 = np.asarray(omega_squared, dtype=np.float64)
        w2_scalar = w2[..., 0] if w2.ndim else w2
        out: dict[str, ComplexArray | None] = {}
        for name in (
            "force_forward",
            "force_backward",
            "moment_forward",
            "moment_backward",
            "roll",
        ):
            value = getattr(self, name)
            out[name] = None if value is None else value * w2
        out["rotating_force"] = self.rotating_force * w2_scalar
        out["rotating_moment"] = (
            None if self.rotating_moment is None else self.rotating_moment * w2_scalar
        )
        return out


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
) -> FreePhasors:
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
    FreePhasors

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
        force_forward, force_backward = parts["force_forward"], parts["force_backward"]
        rotating_force, coefficients = parts["rotating_force"], parts["coefficients"]
        assert force_forward is not None and force_backward is not None
        assert rotating_force is not None and coefficients is not None
        return FreePhasors(
            force_forward=force_forward,
            force_backward=force_backward,
            rotating_force=rotating_force,
            coefficients=coefficients,
            moment_forward=parts.get("moment_forward"),
            moment_backward=parts.get("moment_backward"),
            rotating_moment=parts.get("rotating_moment"),
            roll=parts.get("roll"),
            pin_forward=parts.get("pin_forward"),
            pin_backward=parts.get("pin_backward"),
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
    out = FreePhasors(
        force_forward=f_fwd,
        force_backward=f_bwd,
        rotating_force=phasors.rotating_phasor(rot_amp, throw),
        coefficients=coeffs,
    )
    if moments:
        out = replace(
            out,
            moment_forward=m_fwd,
            moment_backward=m_bwd,
            rotating_moment=phasors.rotating_phasor(rot_amp, throw, lever),
        )
    if roll:
        g_rec, g_rod = kinematics.roll_coefficients(ratio, eps, orders)
        out = replace(
            out,
            roll=phasors.roll_phasors(
                m_rec * r**2, conrod_inertia_correction, g_rec, g_rod, throw, bank, orders
            ),
        )
    return out


def free_phasors_of(
    cylinders: Mapping[str, ArrayLike],
    lever: ArrayLike,
    orders: NDArray[np.intp],
    **options: Any,
) -> FreePhasors:
    """:func:`free_phasors` of a table of cylinders: a mapping with the arrays named as
    :data:`balance.io.layout_file.CYLINDER_FIELDS` (a layout's, or a sweep's grid of them),
    and ``link_pin_mass`` for an engine with link rods (:func:`engine_cylinders`)."""
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


def _assemble(
    layout: Engine,
    ks: NDArray[np.intp],
    values: dict[str, ComplexArray | None],
    coefficients: ComplexArray,
    *,
    model: str,
    terms: int,
    error_bound: float,
    samples: int = 0,
) -> Phasors:
    """A :class:`Phasors` from the scaled phasors (None → NaN, not computed)."""
    nan = np.full(ks.size, np.nan + 0j)

    def get(name: str) -> ComplexArray:
        value = values.get(name)
        return nan if value is None else np.asarray(value, dtype=np.complex128)

    def get_scalar(name: str) -> complex:
        value = values.get(name)
        return complex(np.nan, np.nan) if value is None else complex(value)

    pin_fwd = values.get("link_pin_forward")
    pin_bwd = values.get("link_pin_backward")
    return Phasors(
        link_pin_forward=pin_fwd,
        link_pin_backward=pin_bwd,
        orders=ks,
        force_forward=get("force_forward"),
        force_backward=get("force_backward"),
        moment_forward=get("moment_forward"),
        moment_backward=get("moment_backward"),
        rotating_force=get_scalar("rotating_force"),
        rotating_moment=get_scalar("rotating_moment"),
        roll=get("roll"),
        acceleration_coefficients=coefficients,
        model=model,
        terms=terms,
        reference_force=_reference_force(layout),
        reference_z=layout.reference_z,
        samples=samples,
        error_bound=error_bound,
    )


def _reference_force(layout: Engine) -> float:
    r""":math:`F_1 = m_{rec} r \omega^2` with the engine means of mass and radius [N]."""
    return float(
        np.mean(layout.reciprocating_mass)
        * np.mean(layout.crank_radius)
        * speed_squared(layout.speed)
    )


def _rotating(layout: Engine, moments: bool) -> dict[str, ComplexArray | None]:
    """Rotating force and (if asked) moment phasors, order 1 forward [N, N m]."""
    w2 = speed_squared(layout.speed)
    amplitude = layout.rotating_mass * layout.crank_radius
    force = phasors.rotating_phasor(amplitude, layout.throw) * w2
    if not moments:
        return {"rotating_force": force}
    lever = layout.z - layout.reference_z
    return {
        "rotating_force": force,
        "rotating_moment": phasors.rotating_phasor(amplitude, layout.throw, lever) * w2,
    }


def _compute_time(
    layout: Engine, ks: NDArray[np.intp], samples: int | None, *, moments: bool, roll: bool
) -> Phasors:
    """The ``time`` model: sample, sum as vectors, transform."""
    from balance.core import sampled as timedomain

    k_max = int(ks.max())
    if samples is None:
        samples = max(256, 1 << math.ceil(math.log2(8 * k_max + 1)))
    if samples <= 2 * k_max:
        raise InputError(
            f"samples: {samples} crank angles resolve orders up to {(samples - 1) // 2}, "
            f"not {k_max}; give more than {2 * k_max}"
        )
    theta = timedomain.crank_angles(samples)
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
    values = _rotating(layout, moments)
    force, moment = timedomain.reciprocating_samples(layout, theta)
    f_fwd, f_bwd = timedomain.phasors_from_samples(force, ks)
    values["force_forward"] = phasors.cancel_to_zero(f_fwd, force_scale, n * 4)
    values["force_backward"] = phasors.cancel_to_zero(f_bwd, force_scale, n * 4)
    if moments:
        lever = layout.z - layout.reference_z
        moment_scale = float(np.sum(amp * np.abs(lever)))
        m_fwd, m_bwd = timedomain.phasors_from_samples(moment, ks)
        values["moment_forward"] = phasors.cancel_to_zero(m_fwd, moment_scale, n * 4)
        values["moment_backward"] = phasors.cancel_to_zero(m_bwd, moment_scale, n * 4)
    if roll:
        roll_scale = float(
            np.sum(layout.reciprocating_mass * r**2 + np.abs(layout.conrod_inertia_correction))
            * omega2
        )
        values["roll"] = phasors.cancel_to_zero(
            timedomain.roll_phasors_from_samples(timedomain.roll_newton_euler(layout, theta), ks),
            roll_scale,
            n * 8,
        )
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
        per_cylinder[j] = -timedomain.link_piston_acceleration_at(layout, ahead)
        pins = np.zeros((n, samples), dtype=np.complex128)
        pins[j] = timedomain.link_pin_force_samples(layout, theta)
        pin_fwd, pin_bwd = timedomain.phasors_from_samples(pins, ks)
        values["link_pin_forward"] = pin_fwd
        values["link_pin_backward"] = pin_bwd
    else:
        per_cylinder = kinematics.normalised_acceleration(beta, ratio[:, None], eps[:, None])
    coeffs = 2.0 * np.fft.rfft(per_cylinder, axis=-1)[:, ks] / samples
    return _assemble(
        layout,
        ks,
        values,
        coeffs,
        model="time",
        terms=0,
        samples=samples,
        error_bound=bound,
    )


def balance_engine(
    layout: Engine,
    result: Phasors,
    *,
    cancel: Iterable[int] | None = None,
    strategy: str | None = None,
    balance_factor: float | None = None,
    counterweight_radius: float | None = None,
    cancel_roll: bool = False,
    fixed_shafts: Sequence[ShaftPosition] | None = None,
) -> Balanced:
    """Propose counterweights and shafts for an analysed layout and form the residual.

    Settings not given here come from the layout's ``balance:`` section (``fixed_shafts``:
    its ``shafts``), then from the defaults of :func:`balance.core.balancing.propose` (orders 1
    and 2, two-plane counterweights at the crank ends, counterweight radius = crank radius,
    shafts where they are needed at their default places).
    """
    settings = layout.balance
    if cancel is None and settings is not None and settings.orders is not None:
        cancel = settings.orders
    wanted = sorted({int(k) for k in (cancel if cancel is not None else (1, 2))})
    if strategy is None:
        strategy = settings.strategy if settings is not None else "two-plane"
    if balance_factor is None and settings is not None:
        balance_factor = settings.balance_factor
    if counterweight_radius is None and settings is not None:
        counterweight_radius = settings.counterweight_radius
    if fixed_shafts is None and settings is not None:
        fixed_shafts = settings.shafts
    # the phasors of the orders to cancel (computed again only if not already there)
    needed = np.asarray(wanted, dtype=np.intp)
    if (
        np.all(np.isin(needed, result.orders))
        and not np.isnan(result.moment_forward).any()
        and not np.isnan(result.roll).any()
    ):
        source = result
    else:
        source = compute_phasors(
            layout,
            needed,
            model=result.model,
            terms=result.terms,
            samples=result.samples or None,
        )
    pick = np.searchsorted(source.orders, needed)
    first_order = (
        source.acceleration_coefficients[:, int(np.searchsorted(source.orders, 1))]
        if 1 in wanted
        else np.ones(layout.n_cylinders, dtype=np.complex128)
    )
    if 1 in wanted and source.link_pin_forward is not None:
        first_order = first_order + _link_pin_first_order(layout, source)
    proposal = propose(
        layout,
        first_order,
        source.force_forward[pick],
        source.force_backward[pick],
        source.moment_forward[pick],
        source.moment_backward[pick],
        needed,
        cancel=wanted,
        strategy=strategy,
        balance_factor=balance_factor,
        counterweight_radius=counterweight_radius,
        fixed_shafts=fixed_shafts,
        cancel_roll=cancel_roll,
        roll=source.roll[pick],
    )
    added = proposal_phasors(proposal, layout, result.orders)
    ks = result.orders
    w2 = float(speed_squared(layout.speed))
    first = (ks == 1).astype(np.float64)
    lever = np.abs(layout.z - layout.reference_z)
    # scale of the terms that meet in each residual sum, for the zero-by-symmetry threshold
    force_scale = float(
        np.sum((layout.reciprocating_mass + layout.rotating_mass) * layout.crank_radius) * w2
    )
    force_scale += sum(abs(c.unbalance) for c in proposal.counterweights) * w2
    force_scale += sum(abs(u) * s.speed_ratio**2 for s in proposal.shafts for _, u in s.planes) * w2
    span = float(
        max(
            lever.max(),
            *(abs(c.z - layout.reference_z) for c in proposal.counterweights),
            *(abs(z - layout.reference_z) for s in proposal.shafts for z, _ in s.planes),
            0.0,
        )
    )
    n_terms = 2 * layout.n_cylinders + len(proposal.counterweights) + 2 * len(proposal.shafts)

    def clean(values: ComplexArray, scale: float) -> ComplexArray:
        return phasors.cancel_to_zero(values, scale, n_terms)

    roll_scale = float(np.sum(layout.reciprocating_mass * layout.crank_radius**2) * w2)
    roll_scale += float(np.sum(np.abs(layout.conrod_inertia_correction)) * w2)
    roll_scale += sum(  # each shaft's own roll: a placed pair's two cancel each other
        float(np.abs(shaft_roll_phasors([s], layout.speed, [abs(s.speed_ratio)])[0]))
        for s in proposal.shafts
    )
    return Balanced(
        proposal=proposal,
        force_forward=clean(
            result.force_forward + first * result.rotating_force + added.force_forward,
            force_scale,
        ),
        force_backward=clean(result.force_backward + added.force_backward, force_scale),
        moment_forward=clean(
            result.moment_forward + first * result.rotating_moment + added.moment_forward,
            force_scale * span,
        ),
        moment_backward=clean(result.moment_backward + added.moment_backward, force_scale * span),
        roll=clean(result.roll + added.roll, roll_scale),
    )


def _link_pin_first_order(layout: Engine, source: Phasors) -> ComplexArray:
    r"""What each link pin's relative motion adds to its cylinder's :math:`G_1` as the
    counterweights see it: :math:`2P^{+}_1/(m_{rec} r\omega^2 e^{i\varphi})`, so that the
    counterweight targets (:func:`balance.core.balancing.counterweight_targets`) hold the
    whole forward first order of every cylinder."""
    assert source.link_pin_forward is not None
    at = int(np.searchsorted(source.orders, 1))
    carrier = (
        layout.reciprocating_mass
        * layout.crank_radius
        * speed_squared(layout.speed)
        * np.exp(1j * layout.throw)
    )
    return np.asarray(2.0 * source.link_pin_forward[:, at] / carrier, dtype=np.complex128)


def first_order_parts(
    layout: Engine,
) -> tuple[ComplexArray, tuple[ComplexArray, ComplexArray] | None]:
    r"""What the balance-factor study needs of each cylinder's first order, from one
    analysis.

    Returns
    -------
    g1 : ndarray of complex
        :math:`G_1` of each cylinder's :math:`-s''/r` (exact; a link piston's in
        :math:`\beta_j`).
    pins : tuple of ndarray of complex, or None
        Forward and backward first-order phasors of each cylinder's link pin moving relative
        to its crank pin, at the engine's speed [N] (None without link rods).
    """
    if not layout.has_links:
        r = layout.crank_radius
        ratio = kinematics.rod_ratio(r, layout.conrod_length)
        eps = kinematics.offset_ratio(layout.offset, r)
        return np.asarray(kinematics.acceleration_coefficients(ratio, eps, [1])[..., 0]), None
    p = compute_phasors(layout, [1], moments=False, roll=False)
    assert p.link_pin_forward is not None and p.link_pin_backward is not None
    g1 = np.asarray(p.acceleration_coefficients[:, 0])
    return g1, (p.link_pin_forward[:, 0], p.link_pin_backward[:, 0])


def compute(engine: Engine, request: Request) -> Result:
    """Analyse an engine: what the request asks for, and nothing else.

    Parameters
    ----------
    engine : Engine
        The engine (:func:`balance.load_layout`).
    request : Request
        Orders, model and which quantities to compute (:class:`balance.core.result.Request`).

    Returns
    -------
    Result
        Complex phasors with their references, the proposal and residual if asked, the
        gas torque and roll if the engine has gas forces, and the plausibility warnings
        of the engine at the speed analysed (:mod:`balance.core.plausibility`).
    """
    if request.speed is not None:
        engine = engine.with_speed(request.speed)
    model, terms = request.model, request.terms
    if request.tolerance is not None:
        model, terms, _ = accuracy.choose_model_for(request.tolerance, engine)
        request = replace(request, model=model, terms=terms)
    ks = np.asarray(request.orders, dtype=np.intp)
    phasors_ = compute_phasors(
        engine,
        ks,
        model=model,
        terms=terms,
        samples=request.samples,
        moments=request.moments,
        roll=request.roll,
    )
    balanced = None
    if request.proposal and request.moments and request.roll:
        balanced = balance_engine(
            engine,
            phasors_,
            cancel=request.cancel,
            strategy=request.strategy,
            balance_factor=request.balance_factor,
            counterweight_radius=request.counterweight_radius,
            cancel_roll=request.cancel_roll,
        )
    torque = None
    if engine.gas is not None and request.torque:
        from balance.core.torque import compute_torque

        torque = compute_torque(engine, phasors_.orders)
    roll_orders = ks.astype(np.float64)
    roll_ = residual_roll = None
    if request.roll:
        roll_ = phasors_.roll
        residual_roll = balanced.roll if balanced is not None else None
        if torque is not None:
            roll_orders, roll_, residual_roll = _roll_with_gas(torque, phasors_, balanced)
    f1 = phasors_.reference_force
    pitch = engine.pitch
    result = Result(
        engine=engine,
        request=request,
        phasors=phasors_,
        balanced=balanced,
        torque=torque,
        roll_orders=roll_orders,
        roll=roll_,
        residual_roll=residual_roll,
        reference_force=f1,
        pitch=pitch,
        reference_moment=f1 * pitch if math.isfinite(pitch) else math.nan,
        reference_roll=float(np.mean(engine.reciprocating_mass) * np.mean(engine.crank_radius) ** 2)
        * float(speed_squared(engine.speed)),
        warnings=check_engine(engine, request.counterweight_radius),
    )
    if request.cylinders:
        from balance.core.links import engine_dead_centres

        stroke, tdc = engine_dead_centres(engine)
        result = replace(result, cylinder_stroke=stroke, cylinder_tdc=tdc)
    if request.mounts:
        from balance.core.mount_loads import mounts_of

        result = replace(result, mounts=mounts_of(result, request.mounts_with_proposal))
    if request.bearings:
        from balance.core.bearings import analysis_bearings, counterweights_of

        proposal = balanced.proposal if balanced is not None else None
        result = replace(result, bearings=analysis_bearings(engine, counterweights_of(proposal)))
    return result


def _roll_with_gas(
    torque: TorqueResult, result: Phasors, balanced: Balanced | None
) -> tuple[NDArray[np.float64], ComplexArray, ComplexArray | None]:
    """The roll with gas forces (half orders for a four-stroke) and, with a proposal, with
    the shafts' roll (integer orders only) added."""
    ks = torque.roll_orders
    roll = torque.roll
    if balanced is None:
        return ks, roll, None
    residual = roll.copy()
    shafts = balanced.roll - result.roll  # the shafts' roll, integer orders only
    for j, k in enumerate(result.orders):
        at = np.flatnonzero(np.isclose(ks, float(k)))
        if at.size:
            residual[at[0]] += shafts[j]
    scale = float(np.sum(np.abs(roll)) + np.sum(np.abs(shafts)))
    return ks, roll, phasors.cancel_to_zero(residual, scale, 64)
