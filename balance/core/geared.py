r"""Several crank axes geared together: free forces, moments, the moment about ``z`` and the roll.

An engine whose cylinders sit on several crank axes (docs/several-crankshafts.md) is
analysed one axis at a time, each as a one-crank engine of the model ladder:

- a cylinder on an axis of sense :math:`\sigma` and phase :math:`\varphi_s` is at
  :math:`\beta = \theta + \text{throw} + \sigma(\varphi_s - \text{bank})` from its TDC.  The
  one-crank cylinder with the same bank and that :math:`\beta`
  (:func:`balance.core.crankshafts.forward_throw`) is its mirror image across its bore line
  when :math:`\sigma = -1` (and the cylinder itself turned by :math:`\varphi_s` when
  :math:`\sigma = +1`).  Its piston and the resultant of its rod's inertia move along the
  bore line, so its reciprocating force and moment are those of that one-crank cylinder;
  its roll about its own axis changes sign with the mirror (:math:`\sigma` times it), and
  the torque its rod puts on its crank, in the crank's own sense, does not;
- rotating masses turn at :math:`\varphi_s + \sigma(\theta + \text{angle})`: forward for
  :math:`\sigma = +1`, backward for :math:`\sigma = -1`;
- about the frame's ``z`` axis, the free force :math:`F_s` of axis ``s`` at
  :math:`(x_s, y_s)` has the moment :math:`y_s F_{x,s} - x_s F_{y,s}` (``moment_z``), and
  the gears pass each axis's torque :math:`M_s` on with the output's sense: the block
  receives :math:`\sum_s (\sigma_s - \sigma_o) M_s` (the gear couple), so that

  .. math:: R = \sum_s R_s + M_z + \sum_s (\sigma_s - \sigma_o) M_s.

:func:`geared_free_forces` forms the totals and each axis's part (:class:`GearedParts`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from balance.core import phasors
from balance.core.catalogue import Output
from balance.core.errors import InputError
from balance.core.kinematics import (
    conrod_angle_derivatives,
    fourier_coefficients,
    normalised_slider,
    offset_ratio,
    rod_ratio,
    shared_coefficients,
    unique_pairs,
)
from balance.core.phasors import Phasors
from balance.core.speed import speed_squared

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.engine import Engine
    from balance.core.result import FreeForces

__all__ = [
    "OUTPUTS",
    "GearedParts",
    "geared_free_forces",
    "geared_part",
    "moment_about_z",
    "torque_coefficients",
    "with_gas",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass(frozen=True, eq=False)
class GearedParts:
    """What each crank axis of an engine with several gives (SI: N, N m).

    Attributes
    ----------
    names : tuple of str
        The axes' names.
    x, y : ndarray
        Each axis's position [m].
    sense, phase : ndarray
        Each axis's sense :math:`\\sigma` [1] and phase [rad].
    output_sense : float
        :math:`\\sigma_o` [1].
    members : tuple of ndarray of int
        The cylinders (0-based) of each axis.
    force : Phasors
        Per axis (leading axis): the reciprocating force phasors (``force_forward``,
        ``force_backward``, shape (axes, orders)), the rotating masses' order-1 forward and
        backward phasors (shape (axes,)) and the axis's own roll
        :math:`R_s = -\\dot\\Lambda_s - \\sigma_s M_s` in crankshaft 1's sense (None without
        the roll).
    torque : ndarray of complex or None
        :math:`M_s` per axis and order, the torque its rods put on it in its own sense
        [N m] (roll convention: :math:`\\mathrm{Re}(M e^{ik\\theta})`); None without the
        roll.
    moment_z_reciprocating, moment_z_rotating : ndarray of complex
        :math:`\\sum_s (y_s F_{x,s} - x_s F_{y,s})` per order of the reciprocating and the
        rotating forces [N m] (roll convention).
    gear_couple : ndarray of complex or None
        :math:`\\sum_s (\\sigma_s - \\sigma_o) M_s` per order [N m]; None without the roll.
    roll_orders : ndarray
        The orders of :attr:`torque`, the own rolls and :attr:`gear_couple` (halves with
        gas forces on a four-stroke).
    torque_mean : ndarray or None
        With gas forces: each axis's mean torque in its own sense [N m].
    """

    names: tuple[str, ...]
    x: FloatArray
    y: FloatArray
    sense: FloatArray
    phase: FloatArray
    output_sense: float
    members: tuple[NDArray[np.intp], ...]
    force: Phasors
    torque: ComplexArray | None
    moment_z_reciprocating: ComplexArray
    moment_z_rotating: ComplexArray
    gear_couple: ComplexArray | None
    roll_orders: FloatArray
    torque_mean: FloatArray | None = None

    @property
    def moment_z(self) -> ComplexArray:
        """The whole moment about the frame's ``z`` axis per order [N m]."""
        return self.moment_z_reciprocating + self.moment_z_rotating

    @property
    def count(self) -> int:
        """Number of axes."""
        return len(self.names)


def torque_coefficients(
    ratio: FloatArray, offset: FloatArray, orders: NDArray[np.intp]
) -> tuple[ComplexArray, ComplexArray]:
    r"""Fourier coefficients of the two normalised crank-torque functions of one cylinder.

    Parameters
    ----------
    ratio : ndarray
        :math:`\lambda = r/l` per cylinder [1].
    offset : ndarray
        :math:`\varepsilon = e/r` per cylinder [1].
    orders : ndarray of int
        The orders.

    Returns
    -------
    reciprocating, conrod : ndarray of complex
        :math:`G_k` of :math:`(s''/r)(s'/r)` and :math:`\gamma'\gamma''`, shape
        (cylinders, orders): the inertia torque a cylinder's rod puts on its crank is
        :math:`M = -\omega^2[m_{rec} r^2 (s''/r)(s'/r) + \Delta I\,\gamma'\gamma'']`
        (:func:`balance.core.crank_train.tangential_force` times :math:`r`).
    """
    # once per distinct geometry: each function's coefficients do not depend on the batch
    # it is computed in (:func:`balance.core.kinematics.fourier_coefficients`)
    unique, inverse = unique_pairs(ratio, offset)
    lam = unique[:, :1]
    eps = unique[:, 1:]

    def sample(beta: FloatArray) -> FloatArray:
        _, ds, d2s = normalised_slider(beta, lam, eps)
        dg, d2g = conrod_angle_derivatives(beta, lam, eps)
        return np.stack([d2s * ds, dg * d2g])

    coeffs, _ = fourier_coefficients(sample, orders, (2, lam.shape[0]))
    return coeffs[0][inverse], coeffs[1][inverse]


def moment_about_z(
    x: FloatArray, y: FloatArray, forward: ComplexArray, backward: ComplexArray
) -> ComplexArray:
    r"""The moment about the frame's ``z`` axis of forces acting on displaced axes.

    Parameters
    ----------
    x, y : ndarray
        Each axis's position [m], shape (axes,).
    forward, backward : ndarray of complex
        Each axis's force phasors :math:`P^\pm_{k,s}` [N], shape (axes, orders).

    Returns
    -------
    ndarray of complex
        :math:`Z_k` per order such that :math:`\sum_s (y_s F_{x,s} - x_s F_{y,s}) =
        \sum_k \mathrm{Re}(Z_k e^{ik\theta})` [N m], summed over the axes in order and
        cleaned of rounding (:func:`balance.core.phasors.cancel_to_zero`).

    Notes
    -----
    With :math:`p = y + ix` and :math:`F = F_y + iF_x`, :math:`yF_x - xF_y =
    \mathrm{Im}(\bar p F)`, and :math:`\mathrm{Im}(A e^{ik\theta} + B e^{-ik\theta}) =
    \mathrm{Re}((-iA + i\bar B) e^{ik\theta})`.
    """
    p = (np.asarray(y) + 1j * np.asarray(x))[:, None]
    terms = -1j * np.conj(p) * forward + 1j * p * np.conj(backward)
    return _clean_sum(terms)


def _clean_sum(terms: ComplexArray) -> ComplexArray:
    """Sum over axis 0 in order, set to zero below the rounding of the terms."""
    total = phasors.sum_over_cylinders(np.moveaxis(terms, 0, -2))
    scale = phasors.sum_over_cylinders(np.moveaxis(np.abs(terms), 0, -2))
    return phasors.cancel_to_zero(total, scale, max(terms.shape[0], 1) * 4)


def _axis_engine(base: Engine, layout: Engine, on: NDArray[np.bool_]) -> Engine:
    """The forward one-crank engine with the masses of the cylinders ``on`` one axis only."""
    return replace(
        base,
        reciprocating_mass=np.where(on, layout.reciprocating_mass, 0.0),
        conrod_inertia_correction=np.where(on, layout.conrod_inertia_correction, 0.0),
    )


def _axis_cylinders(forward: Engine, idx: NDArray[np.intp]) -> Engine:
    """Some cylinders of a one-crank engine as an engine of their own, link rods renumbered
    (:meth:`Links.reordered`)."""
    from balance.core.engine import CYLINDER_FIELDS

    arrays = {name: getattr(forward, name)[idx] for name in CYLINDER_FIELDS}
    throws = None
    if forward.throw_index is not None:
        throws = np.unique(forward.throw_index[idx], return_inverse=True)[1].astype(np.intp)
    return replace(
        forward,
        firing_order=None,
        gas=None,
        mass_parts=forward.mass_parts.reordered(idx) if forward.mass_parts is not None else None,
        links=forward.links.reordered(idx) if forward.links is not None else None,
        throw_index=throws,
        **arrays,
    )


def _mirrored(bundle: Phasors | None) -> Phasors | None:
    r"""Force and moment phasors mirrored across the frame's ``y`` axis: :math:`F \to \bar F`
    (:math:`y + ix`), so :math:`P^+ \to \overline{P^-}` and :math:`P^- \to \overline{P^+}`."""
    if bundle is None:
        return None

    def conj(value: ComplexArray | None) -> ComplexArray | None:
        return None if value is None else np.conj(value)

    return replace(
        bundle,
        force_forward=np.conj(bundle.force_backward),
        force_backward=np.conj(bundle.force_forward),
        moment_forward=conj(bundle.moment_backward),
        moment_backward=conj(bundle.moment_forward),
    )


def _link_axes(
    layout: Engine, phasors_of: Callable[[Engine], FreeForces], *, roll: bool
) -> tuple[list[FreeForces], list[ComplexArray] | None, FreeForces]:
    r"""The axes of an engine with link rods, each its cylinders as a one-crank engine.

    Each axis's cylinders of :meth:`Engine.forward_equivalent` (a counter-rotating axis
    mirrored across the frame's ``y`` axis as a whole, so that its masters and link rods
    stay one mechanism), link rods renumbered; a mirrored axis's forces and moments are
    mirrored back (:func:`_mirrored`), its roll left in its own sense as a forward axis's.

    Returns
    -------
    free_of : list of FreeForces
        Per axis, its one-crank analysis with the forces in the engine frame.
    torque : list of ndarray of complex, or None
        Per axis, :math:`M_s` per order [N m] (with ``roll``).
    first : FreeForces
        The engine's acceleration coefficients and link pins per cylinder (each from its
        axis's analysis, in the engine frame) and the model rung with the largest error
        bound of the axes.
    """
    from balance.core.links import engine_geometry, link_torque_coefficients, pin_masses

    assert layout.links is not None
    table = layout.axis_table()
    linked = layout.links.linked
    master_axis = table.axis[np.maximum(layout.links.master, 0)]
    if np.any(linked & (master_axis != table.axis)):
        i = int(np.flatnonzero(linked & (master_axis != table.axis))[0])
        raise InputError(
            f"links: link cylinder {i + 1} hangs on a master rod of another crankshaft; "
            "a link rod hangs on a master rod of its own crankshaft"
        )
    forward = layout.forward_equivalent()
    w2 = speed_squared(layout.speed)
    out: list[FreeForces] = []
    torques: list[ComplexArray] = []
    coefficients: ComplexArray | None = None
    pins: list[tuple[NDArray[np.intp], Phasors]] = []
    bounds: list[float] = []
    for s in range(len(table.names)):
        idx = np.flatnonzero(table.axis == s).astype(np.intp)
        one = _axis_cylinders(forward, idx)
        free = phasors_of(one)
        mirror = float(table.rotation[s]) < 0
        bundle = _mirrored(free.phasors) if mirror else free.phasors
        assert bundle is not None
        out.append(replace(free, phasors=bundle))
        if coefficients is None:
            coefficients = np.zeros((layout.n_cylinders, free.coefficients.shape[-1]), complex)
        coefficients[idx] = free.coefficients
        if free.link_pins is not None:
            pin = _mirrored(free.link_pins) if mirror else free.link_pins
            assert pin is not None
            pins.append((idx, pin))
        bounds.append(free.model.error_bound)
        if not roll:
            continue
        ks = free.phasors.orders
        ratio = rod_ratio(one.crank_radius, one.conrod_length)
        eps = offset_ratio(one.offset, one.crank_radius)
        g_rec = np.zeros((one.n_cylinders, ks.size), dtype=np.complex128)
        g_rod = np.zeros_like(g_rec)
        g_pin = np.zeros_like(g_rec)
        a_pin = np.zeros(one.n_cylinders)
        plain = np.ones(one.n_cylinders, dtype=bool)
        if one.has_links:
            geometry = engine_geometry(one)
            j = geometry.cylinder
            plain[j] = False
            g_rec[j], g_pin[j], g_rod[j] = link_torque_coefficients(geometry, ks)
            a_pin[j] = pin_masses(one)[j] * one.crank_radius[j] ** 2
        if np.any(plain):
            g_rec[plain], g_rod[plain] = torque_coefficients(ratio[plain], eps[plain], ks)
        turn = np.exp(1j * ks.astype(np.float64) * (one.throw - one.bank)[:, None])
        m_r2 = one.reciprocating_mass * one.crank_radius**2
        torques.append(
            phasors.weighted_phasor_sum(
                [
                    (-m_r2, g_rec * turn),
                    (-one.conrod_inertia_correction, g_rod * turn),
                    (-a_pin, g_pin * turn),
                ]
            )
            * w2
        )
    assert coefficients is not None
    first = out[0]
    link_pins = None
    if pins:
        shape = (layout.n_cylinders, first.phasors.orders.size)
        fwd, bwd = np.zeros(shape, complex), np.zeros(shape, complex)
        for idx, pin in pins:
            fwd[idx], bwd[idx] = pin.force_forward, pin.force_backward
        link_pins = Phasors(orders=first.phasors.orders, force_forward=fwd, force_backward=bwd)
    whole = replace(
        first,
        coefficients=coefficients,
        model=replace(first.model, error_bound=float(np.max(bounds))),
        link_pins=link_pins,
    )
    return out, torques if roll else None, whole


def geared_free_forces(
    layout: Engine, phasors_of: Callable[[Engine], FreeForces], *, moments: bool, roll: bool
) -> tuple[Phasors, GearedParts, FreeForces]:
    r"""Free forces, moments, moment about ``z`` and roll of an engine with several crank
    axes, with each axis's part.

    Parameters
    ----------
    layout : Engine
        The engine (:attr:`Engine.geared`).
    phasors_of : callable
        ``phasors_of(engine) -> FreeForces``: the one-crank analysis at the engine's speed
        in the model rung asked for (:func:`balance.core.analysis.compute_phasors`).
    moments, roll : bool
        Whether the moments and the roll are formed.

    Returns
    -------
    phasors : Phasors
        The whole engine's phasors about the frame's origin [N, N m]: reciprocating force
        and moment, rotating forward and backward, and the roll
        :math:`\sum_s R_s + M_z + \sum_s(\sigma_s - \sigma_o)M_s`.
    parts : GearedParts
        Each axis's force, own roll and torque, the moment about ``z`` and the gear
        couple.
    first : FreeForces
        The first axis's one-crank analysis (its acceleration coefficients and model rung
        are the engine's: they do not depend on the masses).

    Raises
    ------
    InputError
        For a link rod whose master is on another crank axis.
    """
    table = layout.axis_table()
    n_axes = len(table.names)
    base = layout.forward_equivalent()
    throw = base.throw
    w2 = speed_squared(layout.speed)
    base = replace(base, rotating_mass=np.zeros_like(throw))
    lever = layout.z - layout.reference_z
    amp_rot = layout.rotating_mass * layout.crank_radius
    # where each rotating mass is at theta = 0, in its axis's sense of turning
    angle = table.axis_phase + table.sense * layout.throw
    ratio = rod_ratio(layout.crank_radius, layout.conrod_length)
    eps = offset_ratio(layout.offset, layout.crank_radius)
    first: FreeForces | None = None
    keys = ("force_forward", "force_backward", "moment_forward", "moment_backward")
    stacks: dict[str, list[Any]] = {k: [] for k in (*keys, "roll", "torque")}
    rot: dict[str, list[Any]] = {k: [] for k in ("ff", "fb", "mf", "mb")}
    members = []
    coeffs = None
    link_torque = None
    if layout.has_links:  # each axis's cylinders a one-crank engine of their own
        free_of, link_torque, whole_first = _link_axes(layout, phasors_of, roll=roll)
        first = whole_first
    else:
        # the axes' one-crank analyses differ in their masses only: their coefficients are
        # computed once (bit for bit the same arrays)
        with shared_coefficients():
            free_of = [
                phasors_of(_axis_engine(base, layout, table.axis == s)) for s in range(n_axes)
            ]
    for s in range(n_axes):
        on = table.axis == s
        members.append(np.flatnonzero(on).astype(np.intp))
        free = free_of[s]
        first = free if first is None else first
        p = free.phasors
        for k in keys:
            stacks[k].append(getattr(p, k))
        forward = float(table.rotation[s]) > 0
        amp = np.where(on, amp_rot, 0.0)
        zero = np.zeros((), dtype=np.complex128)
        force_rot = phasors.rotating_phasor(amp, angle) * w2
        moment_rot = phasors.rotating_phasor(amp, angle, lever) * w2
        rot["ff"].append(force_rot if forward else zero)
        rot["fb"].append(zero if forward else force_rot)
        rot["mf"].append(moment_rot if forward else zero)
        rot["mb"].append(zero if forward else moment_rot)
        if roll:
            assert p.roll is not None
            stacks["roll"].append(p.roll if forward else -p.roll)
            if link_torque is not None:
                stacks["torque"].append(link_torque[s])
                continue
            if coeffs is None:
                coeffs = torque_coefficients(ratio, eps, p.orders)
            m_r2 = np.where(on, layout.reciprocating_mass * layout.crank_radius**2, 0.0)
            d_i = np.where(on, layout.conrod_inertia_correction, 0.0)
            stacks["torque"].append(
                phasors.roll_phasors(
                    -m_r2, -d_i, coeffs[0], coeffs[1], throw, layout.bank, p.orders
                )
                * w2
            )
    assert first is not None
    orders = first.phasors.orders

    def stack(name: str) -> Any:
        values = stacks[name]
        return None if not values or values[0] is None else np.stack(values)

    per_axis = Phasors(
        orders=orders,
        force_forward=stack("force_forward"),
        force_backward=stack("force_backward"),
        moment_forward=stack("moment_forward") if moments else None,
        moment_backward=stack("moment_backward") if moments else None,
        rotating_force=np.asarray(rot["ff"]),
        rotating_moment=np.asarray(rot["mf"]) if moments else None,
        rotating_force_backward=np.asarray(rot["fb"]),
        rotating_moment_backward=np.asarray(rot["mb"]) if moments else None,
        roll=stack("roll") if roll else None,
    )
    moment_z_rec = moment_about_z(table.x, table.y, per_axis.force_forward, per_axis.force_backward)
    first_order = (orders == 1).astype(np.float64)
    moment_z_rot = moment_about_z(
        table.x,
        table.y,
        np.asarray(rot["ff"])[:, None] * first_order,
        np.asarray(rot["fb"])[:, None] * first_order,
    )
    torque = stack("torque") if roll else None
    gear = None
    total_roll = None
    if roll:
        assert torque is not None and per_axis.roll is not None
        gear = _clean_sum((table.rotation - table.output_sense)[:, None] * torque)
        total_roll = _clean_sum(
            np.concatenate([per_axis.roll, moment_z_rec[None], moment_z_rot[None], gear[None]])
        )

    def total(value: Any) -> Any:
        if value is None:
            return None
        v = np.asarray(value)
        return _clean_sum(v[:, None])[0] if v.ndim == 1 else _clean_sum(v)

    whole = Phasors(
        orders=orders,
        force_forward=total(per_axis.force_forward),
        force_backward=total(per_axis.force_backward),
        moment_forward=total(per_axis.moment_forward),
        moment_backward=total(per_axis.moment_backward),
        rotating_force=total(per_axis.rotating_force),
        rotating_moment=None if not moments else total(per_axis.rotating_moment),
        rotating_force_backward=total(per_axis.rotating_force_backward),
        rotating_moment_backward=None if not moments else total(per_axis.rotating_moment_backward),
        roll=total_roll,
    )
    parts = GearedParts(
        names=table.names,
        x=table.x,
        y=table.y,
        sense=table.rotation,
        phase=table.phase,
        output_sense=table.output_sense,
        members=tuple(members),
        force=per_axis,
        torque=torque,
        moment_z_reciprocating=moment_z_rec,
        moment_z_rotating=moment_z_rot,
        gear_couple=gear,
        roll_orders=orders.astype(np.float64),
    )
    return whole, parts, first


def with_gas(
    parts: GearedParts,
    cylinder_torque: FloatArray,
    cycle_deg: float,
    roll_orders: FloatArray,
    phasors_scale: float,
) -> tuple[GearedParts, ComplexArray, float]:
    r"""Each axis's torque, own roll and the engine's roll with gas forces.

    Gas pressure acts on the piston and the head alike (in an opposed-piston bore on its two
    pistons, pushing along one line): it adds no free force (and nothing to the moment
    about ``z``) and no angular momentum, only torque.  With :math:`M^g_s`
    the gas part of axis ``s``'s torque, its own roll gains :math:`-\sigma_s M^g_s` and the
    engine's roll :math:`-\sigma_o \sum_s M^g_s`: the gear couple carries the rest.

    Parameters
    ----------
    parts : GearedParts
        The inertia-only parts (integer orders).
    cylinder_torque : ndarray
        Each cylinder's torque on its crank over the cycle, in its crank's own sense, gas
        and inertia [N m], shape (cylinders, angles) (:class:`balance.core.torque.TorqueResult`).
    cycle_deg : float
        The cycle [deg] the angles cover evenly.
    roll_orders : ndarray
        The orders to report (halves for a four-stroke).
    phasors_scale : float
        The largest sum of magnitudes of the torques [N m], for the rounding of the spectra.

    Returns
    -------
    parts : GearedParts
        With each axis's torque (and its mean) and own roll with gas, the gear couple, on
        ``roll_orders``.
    roll : ndarray of complex
        The engine's roll with gas on ``roll_orders`` [N m].
    mean : float
        The mean torque of the output, :math:`\sum_s M_s` over the cycle [N m].
    """
    samples = cylinder_torque.shape[-1]
    bins = np.round(roll_orders * cycle_deg / 360.0).astype(np.intp)
    per_axis = np.stack([cylinder_torque[m].sum(axis=0) for m in parts.members])
    spectrum = np.fft.fft(per_axis, axis=-1) / samples
    total = phasors.cancel_to_zero(
        2.0 * spectrum[:, bins % samples], phasors_scale, 8 * int(math.log2(samples)) * parts.count
    )
    whole = np.isin(roll_orders, parts.force.orders)
    at = np.searchsorted(parts.force.orders, roll_orders[whole])

    def on_roll_orders(values: ComplexArray) -> ComplexArray:
        out = np.zeros(values.shape[:-1] + roll_orders.shape, dtype=np.complex128)
        out[..., whole] = values[..., at]
        return out

    assert parts.torque is not None and parts.force.roll is not None
    inertia = on_roll_orders(parts.torque)
    gas = total - inertia
    own = on_roll_orders(parts.force.roll) - parts.sense[:, None] * gas
    gear = _clean_sum((parts.sense - parts.output_sense)[:, None] * total)
    roll = _clean_sum(
        np.concatenate(
            [
                own,
                on_roll_orders(parts.moment_z_reciprocating + parts.moment_z_rotating)[None],
                gear[None],
            ]
        )
    )
    new = replace(
        parts,
        force=replace(parts.force, roll=own),
        torque=total,
        gear_couple=gear,
        roll_orders=np.asarray(roll_orders, dtype=np.float64),
        torque_mean=per_axis.mean(axis=-1),
    )
    return new, roll, float(per_axis.sum(axis=0).mean())


# --------------------------------------------------------------------------- the section


def geared_part(engine: Engine, request: Any, result: Any) -> Any:
    """The ``crankshafts`` section (:mod:`balance.core.sections`): each crank axis's force,
    own roll and torque, the moment about ``z`` and the gear couple of an engine with
    several (:attr:`Engine.geared`); the result as it is otherwise.

    Parameters
    ----------
    engine : Engine
        The analysed engine.
    request : Request
        The request (the section takes no options).
    result : Result
        The result so far (its :attr:`~balance.core.result.Result.shafts`).

    Returns
    -------
    Result
        ``result`` with the part (:class:`GearedParts`) added when the engine has several
        crank axes.
    """
    if result.shafts is None:
        return result
    return result.with_part("crankshafts", result.shafts)


def _part(result: Any) -> GearedParts:
    part: GearedParts = result.part("crankshafts")
    return part


def _has_roll(result: Any) -> bool:
    return _part(result).torque is not None


def _has_moments(result: Any) -> bool:
    return result.phasors.has("moment")


def _has_gas(result: Any) -> bool:
    return _part(result).torque_mean is not None


def _shaft_force(result: Any) -> Phasors:
    return _part(result).force.free()


def _roll_pair(
    name: str, what: str, get: Callable[[Any], Any], dims: tuple[str, ...]
) -> tuple[Output, Output]:
    return (
        Output(
            f"{name}_amplitude",
            dims,
            "N m",
            f"amplitude of {what} (sum of a_k cos(k theta + phase_k))",
            lambda r: np.abs(get(r)),
            when=_has_roll,
        ),
        Output(
            f"{name}_phase",
            dims,
            "deg",
            f"phase of {what}",
            lambda r: phasors.phase_deg(get(r)),
            when=_has_roll,
        ),
    )


def _rotating_backward(quantity: str) -> tuple[Output, Output]:
    unit = "N" if quantity == "force" else "N m"
    attribute = f"rotating_{quantity}_backward"
    when = None if quantity == "force" else _has_moments
    return (
        Output(
            f"rotating_{quantity}_backward_magnitude",
            (),
            unit,
            f"magnitude of the rotating {quantity} of masses turning backward "
            "(counter-rotating crankshafts), order 1 backward",
            lambda r: np.abs(getattr(r.phasors, attribute)),
            when=when,
        ),
        Output(
            f"rotating_{quantity}_backward_phase",
            (),
            "deg",
            f"phase of the backward rotating {quantity} at crank angle 0",
            lambda r: phasors.phase_deg(getattr(r.phasors, attribute)),
            when=when,
        ),
    )


#: The outputs of the ``crankshafts`` section.
OUTPUTS: tuple[Output, ...] = (
    Output(
        "crankshaft",
        ("crankshaft",),
        "",
        "crankshaft name",
        lambda r: list(_part(r).names),
        kind="coord",
    ),
    Output("crankshaft_x", ("crankshaft",), "m", "x of the crankshaft axis", lambda r: _part(r).x),
    Output("crankshaft_y", ("crankshaft",), "m", "y of the crankshaft axis", lambda r: _part(r).y),
    Output(
        "crankshaft_rotation",
        ("crankshaft",),
        "1",
        "sense of rotation relative to crankshaft 1 (+1 same, -1 opposite)",
        lambda r: _part(r).sense,
    ),
    Output(
        "crankshaft_phase",
        ("crankshaft",),
        "deg",
        "direction of the crankshaft's reference line at crank angle 0",
        lambda r: np.degrees(_part(r).phase),
    ),
    Output(
        "cylinder_crankshaft",
        ("cylinder",),
        "1",
        "number of the crankshaft the cylinder is on (1-based)",
        lambda r: np.concatenate([np.full(m.size, s + 1) for s, m in enumerate(_part(r).members)])[
            np.argsort(np.concatenate(_part(r).members))
        ],
    ),
    Output(
        "crankshaft_force_magnitude",
        ("crankshaft", "order", "rotation"),
        "N",
        "magnitude of the free force phasor of the crankshaft's pistons, rods and masses",
        lambda r: _shaft_force(r).magnitude("force"),
    ),
    Output(
        "crankshaft_force_phase",
        ("crankshaft", "order", "rotation"),
        "deg",
        "phase of the crankshaft's free force phasor at crank angle 0",
        lambda r: _shaft_force(r).phase("force"),
    ),
    Output(
        "crankshaft_force_peak",
        ("crankshaft", "order"),
        "N",
        "peak free force of the crankshaft over a revolution",
        lambda r: _shaft_force(r).peak("force"),
    ),
    *_roll_pair(
        "crankshaft_roll",
        "the torque about the crankshaft's own axis on the block with its drive outside the "
        "block, positive in crankshaft 1's sense",
        lambda r: _part(r).force.roll,
        ("crankshaft", "roll_order"),
    ),
    *_roll_pair(
        "crankshaft_torque",
        "the torque the crankshaft's rods put on it, positive in its own sense",
        lambda r: _part(r).torque,
        ("crankshaft", "roll_order"),
    ),
    Output(
        "crankshaft_torque_mean",
        ("crankshaft",),
        "N m",
        "mean torque on the crankshaft over the cycle, in its own sense",
        lambda r: _part(r).torque_mean,
        when=_has_gas,
    ),
    Output(
        "moment_z_amplitude",
        ("order",),
        "N m",
        "amplitude of the moment about the frame's z axis of the crankshafts' free forces "
        "on their axes (sum of a_k cos(k theta + phase_k))",
        lambda r: np.abs(_part(r).moment_z),
    ),
    Output(
        "moment_z_phase",
        ("order",),
        "deg",
        "phase of the moment about z, positive in crankshaft 1's sense",
        lambda r: phasors.phase_deg(_part(r).moment_z),
    ),
    Output(
        "moment_z_reciprocating_amplitude",
        ("order",),
        "N m",
        "amplitude of the moment about z of the reciprocating forces",
        lambda r: np.abs(_part(r).moment_z_reciprocating),
    ),
    Output(
        "moment_z_reciprocating_phase",
        ("order",),
        "deg",
        "phase of the moment about z of the reciprocating forces",
        lambda r: phasors.phase_deg(_part(r).moment_z_reciprocating),
    ),
    Output(
        "moment_z_rotating_amplitude",
        ("order",),
        "N m",
        "amplitude of the moment about z of the rotating forces",
        lambda r: np.abs(_part(r).moment_z_rotating),
    ),
    Output(
        "moment_z_rotating_phase",
        ("order",),
        "deg",
        "phase of the moment about z of the rotating forces",
        lambda r: phasors.phase_deg(_part(r).moment_z_rotating),
    ),
    *_roll_pair(
        "gear_couple",
        "the couple the gear meshes put on the block, sum of (sigma_s - sigma_o) M_s",
        lambda r: _part(r).gear_couple,
        ("roll_order",),
    ),
    *_rotating_backward("force"),
    *_rotating_backward("moment"),
    Output(
        "output_rotation",
        (),
        "",
        "output_rotation",
        lambda r: int(_part(r).output_sense),
        kind="attr",
    ),
)
