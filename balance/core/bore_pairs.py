r"""Bore pairs: the gas cycle of an opposed-piston bore (two pistons, one bore, no head).

Two pistons on two crank axes that share one bore (``opposed``,
docs/several-crankshafts.md, "Opposed pistons") work on one charge.  With :math:`s_1`,
:math:`s_2` each piston pin's distance from its own crank axis (offsets included) and
:math:`D` the distance between the axes along the bore, the distance between the crowns is
:math:`d = D - s_1 - s_2 - c` (:math:`c` the pins' heights under the crowns), so the bore's
volume is

.. math::

    V(\theta) = V_c + A\,(d(\theta) - d_{min}) = V_c + A\,(S_{max} - S(\theta)),
    \qquad S = s_1 + s_2,

with :math:`V_s = A(S_{max} - S_{min})` and :math:`V_c = V_s/(\varepsilon - 1)`: what
:func:`balance.core.gas.cylinder_volume` forms from a :class:`~balance.core.gas.PistonTravel`
whose position is :math:`S`.  The bore's cycle (a two-stroke) is counted from its smallest
volume, the crank angle :math:`\theta_0` at which :math:`S` is largest: each of the two
pistons has it as its "firing TDC", and the pressure trace or the parametric model is read
at :math:`\theta - \theta_0` for both.  The pressure pushes each piston towards its own
crank, :math:`(p - p_0)A`, and drives its own shaft; there is no head, so the gas puts no
force on the block (the two pistons' pushes, passed to the two axes, cancel along the bore
line) and the mean of the two shafts' torques over the cycle is :math:`\oint p\,dV / 2\pi`.

This module is the one place the pairing enters the gas forces; every pressure, force and
torque is then :mod:`balance.core.gas`'s and :mod:`balance.core.torque`'s.
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.gas import GasInput, PistonTravel
from balance.core.kinematics import normalised_slider, offset_ratio, rod_ratio

__all__ = ["bore_pair_gas", "bore_pairs", "bore_travel"]

FloatArray = NDArray[np.float64]

#: Samples per revolution of the search for the bore's dead centres (then refined by Newton).
SEARCH_SAMPLES = 3600


def bore_pairs(engine: Engine) -> list[tuple[int, int]]:
    """The opposed-piston bores of an engine: pairs of cylinders (0-based, first < second).

    Parameters
    ----------
    engine : Engine
        The engine.

    Returns
    -------
    list of (int, int)
        One pair per bore, in the order of its first cylinder; empty without crank axes.
    """
    if engine.crankshafts is None:
        return []
    partner = engine.axis_table().opposed
    return [(i, int(j)) for i, j in enumerate(partner.tolist()) if j > i]


def _sum_of_pins(
    theta: FloatArray, lead: FloatArray, radius: FloatArray, lam: FloatArray, eps: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """:math:`S(\\theta) = \\sum_k r_k s_k(\\theta + c_k)` and its first two derivatives."""
    total = np.zeros((3, *np.shape(theta)))
    for c, r, la, ep in zip(lead, radius, lam, eps, strict=True):
        total += r * np.asarray(normalised_slider(np.asarray(theta) + c, la, ep))
    return total[0], total[1], total[2]


def _extreme(
    lead: FloatArray, radius: FloatArray, lam: FloatArray, eps: FloatArray, sign: float
) -> float:
    """The crank angle [rad, in [0, 2 pi)] where ``sign`` * S is largest: the largest sample
    of a fine grid, refined by Newton's method on S' = 0."""
    grid = 2.0 * math.pi * np.arange(SEARCH_SAMPLES) / SEARCH_SAMPLES
    values, _, _ = _sum_of_pins(grid, lead, radius, lam, eps)
    theta = float(grid[int(np.argmax(sign * values))])
    for _ in range(30):
        _, d1, d2 = _sum_of_pins(np.array([theta]), lead, radius, lam, eps)
        if d2[0] == 0.0:
            break
        step = float(d1[0] / d2[0])
        theta -= step
        if abs(step) < 1e-15:
            break
    return theta % (2.0 * math.pi)


def bore_travel(engine: Engine, pair: tuple[int, int]) -> tuple[PistonTravel, float]:
    r"""The travel :math:`S = s_1 + s_2` of an opposed-piston bore against its cycle angle, and
    the crank angle of its smallest volume.

    Parameters
    ----------
    engine : Engine
        An engine with crank axes (:attr:`Engine.crankshafts`).
    pair : (int, int)
        The bore's two cylinders (0-based, :func:`bore_pairs`).

    Returns
    -------
    travel : PistonTravel
        ``position(alpha)``: :math:`S(\theta_0 + \alpha)` [m] at cycle angles ``alpha``
        [deg] from the smallest volume; ``top`` = :math:`S_{max}`, ``bottom`` =
        :math:`S_{min}` [m].
    theta0 : float
        :math:`\theta_0`, the crank angle of the smallest volume [deg], in [0, 360).
    """
    idx = np.asarray(pair, dtype=np.intp)
    lead = (engine.forward_throw() - engine.bank)[idx]
    radius = engine.crank_radius[idx]
    lam = np.asarray(rod_ratio(radius, engine.conrod_length[idx]))
    eps = np.asarray(offset_ratio(engine.offset[idx], radius))
    # the travel depends on the two pistons' geometry and on the second crank's lead over
    # the first only (rounded to 1e-12 rad, so that bores alike share one travel and one
    # pressure table): found with the first piston's crank angle as theta, then shifted
    two_pi = 2.0 * math.pi
    delta = round(float((lead[1] - lead[0]) % two_pi), 12)
    travel, top = _travel((*map(float, radius), *map(float, lam), *map(float, eps), delta))
    return travel, math.degrees((top - float(lead[0])) % two_pi) % 360.0


@functools.lru_cache(maxsize=64)
def _travel(key: tuple[float, ...]) -> tuple[PistonTravel, float]:
    """The travel of a bore of radii, rod ratios and offset ratios ``key[0:6]`` (two each)
    whose second crank leads the first by ``key[6]`` [rad], against the first crank's angle,
    and the first crank's angle at the smallest volume [rad]."""
    radius, lam, eps = (np.array(key[k : k + 2]) for k in (0, 2, 4))
    canonical = np.array([0.0, key[6]])
    top = _extreme(canonical, radius, lam, eps, 1.0)
    bottom = _extreme(canonical, radius, lam, eps, -1.0)
    s_top = float(_sum_of_pins(np.array([top]), canonical, radius, lam, eps)[0][0])
    s_bottom = float(_sum_of_pins(np.array([bottom]), canonical, radius, lam, eps)[0][0])
    at_top = np.mod(top + canonical, 2.0 * math.pi)

    def position(
        alpha_deg: FloatArray,
        lead: FloatArray = at_top,
        radius: FloatArray = radius,
        lam: FloatArray = lam,
        eps: FloatArray = eps,
    ) -> FloatArray:
        return _sum_of_pins(np.radians(np.asarray(alpha_deg)), lead, radius, lam, eps)[0]

    # the -1 keeps the key apart from a link piston's (lengths, > 0)
    return PistonTravel(position, s_top, s_bottom, key=(-1.0, *key)), top


def bore_pair_gas(
    engine: Engine, travels: list[PistonTravel | None]
) -> tuple[GasInput, list[PistonTravel | None]]:
    """The gas input and piston travels with every opposed-piston bore's cycle: both pistons
    of a bore at the bore's travel (:func:`bore_travel`) and "firing" at its smallest volume.

    Parameters
    ----------
    engine : Engine
        An engine with a ``gas:`` section.
    travels : list of (PistonTravel or None)
        Each cylinder's travel without the pairing
        (:func:`balance.core.torque.piston_travels`).

    Returns
    -------
    gas : GasInput
        The engine's, with the paired cylinders' firing TDCs at their bore's smallest volume.
    travels : list of (PistonTravel or None)
        ``travels`` with each paired cylinder's entry its bore's travel.

    Raises
    ------
    InputError
        If the engine works a four-stroke cycle (an opposed-piston bore is a two-stroke).
    """
    gas = engine.gas
    assert gas is not None
    pairs = bore_pairs(engine)
    if not pairs:
        return gas, travels
    if engine.cycle != "two-stroke":
        raise InputError(
            "cycle: an opposed-piston bore with gas forces works a two-stroke cycle counted "
            "from its smallest volume; write cycle: two-stroke"
        )
    tdc = np.array(gas.firing_tdc, dtype=np.float64, copy=True)
    out = list(travels)
    for pair in pairs:
        travel, theta0 = bore_travel(engine, pair)
        for k in pair:
            tdc[k] = theta0
            out[k] = travel
    return replace(gas, firing_tdc=tdc), out
