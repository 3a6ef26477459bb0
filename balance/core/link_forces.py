r"""Forces of articulated (master-and-link) rods at the pistons, the link pins and the
crank pins.

Each link rod is its two-mass model (the piston-pin share with the link piston, the
link-pin share at the link pin :math:`L`) plus a massless rod of inertia
:math:`\Delta I_j`: a crank slider whose rod's lower end is :math:`L`
(:mod:`balance.core.crank_train`).  The master rod carries the link rods: it pushes each at
its link pin and takes the reaction there, which adds to the wall force on the master
piston and to the force on the crank pin (:func:`articulated_big_end_forces`).  The link
pin's motion is :mod:`balance.core.links`'s; the crank-train formulas are
:mod:`balance.core.crank_train`'s.

.. rubric:: References

Fearn, "The articulated connecting rod", Journal of the Royal Aeronautical Society, 1927
(the forces at the crank pin and on the master rod).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import crank_train
from balance.core.engine import Engine
from balance.core.links import LinkMotion, engine_geometry, link_motion, pin_masses
from balance.core.speed import speed_squared

__all__ = ["LinkRodForces", "articulated_big_end_forces", "link_rod_forces"]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass(frozen=True)
class LinkRodForces:
    r"""Forces of the link rods over crank angles (rows: the link cylinders in order), SI.

    Attributes
    ----------
    cylinder, master : ndarray of int
        Index of each link cylinder and of its master.
    motion : LinkMotion
        The link cylinders' motion at the crank angles.
    wall : ndarray
        Force of the wall on each link piston across its bore (+X of its frame) [N].
    on_link : ndarray of complex
        :math:`F_L`, the force the master rod puts on the link rod at the link pin [N]
        (engine frame, :math:`y + \mathrm{i}x`).
    master_wall : ndarray
        :math:`\Delta N`, what the link rod's push on the master rod adds to the wall force
        on the master piston (+X of the master's frame) [N].
    on_pin : ndarray of complex
        The link cylinder's share of the force on the crank pin,
        :math:`\mathrm{i}\,\Delta N e^{\mathrm{i}\psi_m} - F_L` [N] (engine frame): what the
        link rod passes through the master rod to the pin.
    """

    cylinder: NDArray[np.intp]
    master: NDArray[np.intp]
    motion: LinkMotion
    wall: FloatArray
    on_link: ComplexArray
    master_wall: FloatArray
    on_pin: ComplexArray


def link_rod_forces(
    engine: Engine, theta: ArrayLike, gas_force: ArrayLike | None = None
) -> LinkRodForces:
    r"""What each link rod does at its piston, at its link pin and, through the master rod,
    at the crank pin (the notes of :func:`articulated_big_end_forces`).

    Parameters
    ----------
    engine : Engine
        An engine with link rods.
    theta : array_like
        Crank angles [rad], shape (angles,).
    gas_force : array_like, optional
        Gas force on each piston towards the crank [N], shape (cylinders, angles).

    Returns
    -------
    LinkRodForces
    """
    th = np.asarray(theta, dtype=np.float64)[None, :]
    geometry = engine_geometry(engine)
    j = geometry.cylinder
    m_idx = geometry.master
    r = engine.crank_radius
    w2 = float(speed_squared(engine.speed))
    beta = th + (engine.throw[j] - engine.bank[j])[:, None]
    motion = link_motion(beta, *geometry.columns())
    psi_j = engine.bank[j][:, None]
    rj = r[j][:, None]
    gas = None if gas_force is None else np.asarray(gas_force, dtype=np.float64)[j]
    inertia = crank_train.reciprocating_force(
        engine.reciprocating_mass[j][:, None], w2, rj, motion.d2s
    )
    q = crank_train.piston_force(inertia, gas)
    length, delta_i = engine.conrod_length[j][:, None], engine.conrod_inertia_correction[j][:, None]
    wall = crank_train.side_thrust_moment_balance(
        q, motion.sin_rod, motion.cos_rod, length, delta_i, w2, motion.d2rod
    )
    pin_acc = w2 * rj * motion.d2pin * np.exp(1j * psi_j)  # engine frame
    link_force = pin_masses(engine)[j][:, None] * pin_acc + crank_train.rod_on_piston(
        q, wall, psi_j
    )
    # the master rod carries it: link pin and crank pin, engine frame
    pin_pos = rj * motion.pin * np.exp(1j * psi_j)
    crank = rj * np.exp(1j * (th + engine.throw[j][:, None]))
    length_m, psi_m = engine.conrod_length[m_idx][:, None], engine.bank[m_idx][:, None]
    delta_wall, on_pin = crank_train.hung_load(
        link_force, pin_pos, crank, length_m, motion.cos_master, psi_m
    )
    return LinkRodForces(j, m_idx, motion, wall, link_force, delta_wall, on_pin)


def articulated_big_end_forces(
    engine: Engine,
    theta: ArrayLike,
    forces: ComplexArray,
    gas_force: ArrayLike | None = None,
) -> ComplexArray:
    r"""Big-end forces on the crank pins with the link rods hung on their masters.

    Parameters
    ----------
    engine : Engine
        An engine with link rods.
    theta : array_like
        Crank angles [rad], shape (angles,).
    forces : ndarray of complex
        The big-end forces of every cylinder as a plain rod on its pin
        (:func:`balance.core.bearings.big_end_forces`), shape (cylinders, angles).
    gas_force : array_like, optional
        Gas force on each piston towards the crank [N], shape (cylinders, angles).

    Returns
    -------
    ndarray of complex
        ``forces`` with each link cylinder's row 0 and its master's row the force that the
        master rod, carrying its link rods, puts on the pin.

    Notes
    -----
    Each link rod is its two-mass model (piston-pin share with the piston, link-pin share
    at :math:`L`) plus a massless rod of inertia :math:`\Delta I_j`: a crank slider whose
    rod's lower end is :math:`L` (:mod:`balance.core.crank_train`), with :math:`Q =
    m\omega^2 s'' + G` along its bore, the wall force :math:`N` from the rod's moment
    balance about :math:`L` and the rod's force :math:`F_P` on its piston.  The master rod
    pushes the link rod at :math:`L` with :math:`F_L = m_L\omega^2\Lambda''r e^{i\psi_j} +
    F_P` (engine frame) and takes :math:`-F_L` there: its moment about the crank pin adds
    :math:`\Delta N` to the master piston's wall force, and the force on the pin becomes the
    plain master's plus :math:`i\,\Delta N e^{i\psi_m} - \sum_j F_{L,j}`
    (:func:`balance.core.crank_train.hung_load`, :func:`link_rod_forces`).
    """
    assert engine.links is not None
    out = np.array(forces, dtype=np.complex128, copy=True)
    if engine.links.link_indices.size == 0:
        return out
    links = link_rod_forces(engine, theta, gas_force)
    np.add.at(out, links.master, links.on_pin)
    out[links.cylinder] = 0.0
    return out
