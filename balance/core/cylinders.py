"""Each cylinder's dead centres and link rod, as a section of an analysis.

Offsets and link rods move a piston's dead centres away from its throw and bank, and change its
travel: the ``cylinders`` section (:mod:`balance.core.sections`) reports each cylinder's actual
stroke and top-dead-centre crank angle (:func:`dead_centres`; a link piston's by
:func:`balance.core.links.link_dead_centres`), and for an engine with master and link rods which
rod carries each link rod and where its link pin is.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.catalogue import Output
from balance.core.engine import Engine, Links

__all__ = [
    "CYLINDER_OUTPUTS",
    "DeadCentres",
    "cylinders_part",
    "dead_centre_lag",
    "dead_centres",
    "engine_dead_centres",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)  # arrays: compared as their arrays, not as a whole
class DeadCentres:
    """Each cylinder's piston travel and top dead centre.

    Attributes
    ----------
    stroke : ndarray
        The piston's travel between its dead centres [m].
    tdc : ndarray
        Crank angle :math:`\\theta` in :math:`[0, 2\\pi)` at which the piston is farthest
        from the crank axis [rad].
    """

    stroke: FloatArray
    tdc: FloatArray


def dead_centres(
    throw: ArrayLike,
    bank: ArrayLike,
    crank_radius: ArrayLike,
    conrod_length: ArrayLike,
    offset: ArrayLike,
    links: Links | None = None,
) -> tuple[FloatArray, FloatArray]:
    r"""Actual stroke and top-dead-centre crank angle of every cylinder.

    Parameters
    ----------
    throw, bank : array_like
        Per cylinder [rad].
    crank_radius, conrod_length, offset : array_like
        Per cylinder [m] (a link cylinder's ``conrod_length`` is its link rod's).
    links : Links, optional
        The articulated rods.

    Returns
    -------
    stroke : ndarray
        Travel of each piston pin between its dead centres [m].
    tdc : ndarray
        Crank angle :math:`\theta` in :math:`[0, 2\pi)` at which each piston pin is farthest
        from the crank axis [rad].

    Notes
    -----
    A plain crank slider is at its dead centres when rod and crank are in line:
    :math:`\sin\beta_{TDC} = e/(l + r)`, :math:`s_{TDC} = \sqrt{(l+r)^2 - e^2}`,
    :math:`\beta_{BDC} = \pi + \arcsin(e/(l - r))`, :math:`s_{BDC} = \sqrt{(l-r)^2 - e^2}`;
    a link piston's dead centres are found by :func:`~balance.core.links.link_dead_centres`.  Then
    :math:`\theta_{TDC} = \beta_{TDC} + \psi - \varphi`.
    """
    phi = np.asarray(throw, dtype=np.float64)
    psi = np.asarray(bank, dtype=np.float64)
    beta_top, stroke = _top_and_stroke(crank_radius, conrod_length, offset, bank, links)
    tdc = np.mod(beta_top + psi - phi, 2.0 * np.pi)
    tdc = np.where(tdc >= 2.0 * np.pi, 0.0, tdc)
    return np.asarray(stroke, dtype=np.float64), np.asarray(tdc, dtype=np.float64)


def _top_and_stroke(
    crank_radius: ArrayLike,
    conrod_length: ArrayLike,
    offset: ArrayLike,
    bank: ArrayLike,
    links: Links | None,
) -> tuple[FloatArray, FloatArray]:
    r""":math:`\beta_{TDC}` [rad] (a link cylinder's in :math:`[0, 2\pi)`) and the stroke [m]
    of every cylinder (:func:`dead_centres`)."""
    r = np.asarray(crank_radius, dtype=np.float64)
    length = np.asarray(conrod_length, dtype=np.float64)
    e = np.asarray(offset, dtype=np.float64)
    beta_top = np.arcsin(e / (length + r))
    with np.errstate(invalid="ignore"):  # a link cylinder's row is replaced below
        stroke = np.where(
            e == 0.0, 2.0 * r, np.sqrt((length + r) ** 2 - e**2) - np.sqrt((length - r) ** 2 - e**2)
        )
    if links is not None and np.any(links.master >= 0):
        from balance.core.links import link_dead_centres, link_geometry  # link rods only

        geometry = link_geometry(r, length, e, bank, links)
        top, s_top, s_bottom = link_dead_centres(geometry)
        j = geometry.cylinder
        beta_top = np.array(beta_top, dtype=np.float64)
        stroke = np.array(stroke, dtype=np.float64)
        beta_top[j] = top
        stroke[j] = r[j] * (s_top - s_bottom)
    return np.asarray(beta_top, dtype=np.float64), np.asarray(stroke, dtype=np.float64)


def dead_centre_lag(
    crank_radius: ArrayLike,
    conrod_length: ArrayLike,
    offset: ArrayLike,
    bank: ArrayLike,
    links: Links | None = None,
) -> FloatArray:
    r"""How far each piston's actual top dead centre lies after its nominal one [rad].

    The crank angle :math:`\beta_{TDC}` from the cylinder's nominal TDC direction (:math:`\theta +
    \varphi - \psi = 0`, docs/conventions.md, "Frame and angles") at which the piston pin is
    farthest from the crank axis, in :math:`(-\pi, \pi]`: :math:`\arcsin(e/(l + r))` for a plain
    crank slider (exactly 0 without offset), :func:`~balance.core.links.link_dead_centres` for a
    link piston.

    Parameters
    ----------
    crank_radius, conrod_length, offset : array_like
        Per cylinder [m] (a link cylinder's ``conrod_length`` is its link rod's).
    bank : array_like
        Per cylinder [rad].
    links : Links, optional
        The articulated rods.

    Returns
    -------
    ndarray
        :math:`\beta_{TDC}` per cylinder [rad].
    """
    top, _ = _top_and_stroke(crank_radius, conrod_length, offset, bank, links)
    return np.asarray(np.where(top > np.pi, top - 2.0 * np.pi, top), dtype=np.float64)


def engine_dead_centres(engine: Engine) -> tuple[FloatArray, FloatArray]:
    r""":func:`dead_centres` of an engine.

    Parameters
    ----------
    engine : Engine
        The engine (throws, banks, crank radii, rods, offsets, links).

    Returns
    -------
    stroke : ndarray
        Travel of each piston pin between its dead centres [m].
    tdc : ndarray
        Crank angle in :math:`[0, 2\pi)` of each cylinder's top dead centre [rad].
    """
    forward = engine.forward_equivalent()  # each cylinder at its crank angle from TDC
    return dead_centres(
        forward.throw,
        forward.bank,
        engine.crank_radius,
        engine.conrod_length,
        engine.offset,
        forward.links,
    )


def cylinders_part(engine: Engine, request: Any, result: Any) -> Any:
    """The ``cylinders`` section (:mod:`balance.core.sections`): :class:`DeadCentres` of every
    cylinder.

    Parameters
    ----------
    engine : Engine
        The analysed engine.
    request : Request
        The request (the section takes no options).
    result : Result
        The result so far.

    Returns
    -------
    Result
        ``result`` with the ``cylinders`` part added.
    """
    stroke, tdc = engine_dead_centres(engine)
    return result.with_part("cylinders", DeadCentres(stroke, tdc))


def _dead_centres(result: Any) -> DeadCentres:
    part: DeadCentres = result.part("cylinders")
    return part


def _has_links(result: Any) -> bool:
    return result.engine.links is not None


def _linked(result: Any) -> NDArray[np.bool_]:
    return np.asarray(result.engine.links.master >= 0)


#: The outputs of the ``cylinders`` section.
CYLINDER_OUTPUTS: tuple[Output, ...] = (
    Output(
        "cylinder_stroke",
        ("cylinder",),
        "m",
        "piston travel between its dead centres",
        lambda r: _dead_centres(r).stroke,
    ),
    Output(
        "tdc_crank_angle",
        ("cylinder",),
        "deg",
        "crank angle at which the piston is farthest from the crank axis",
        lambda r: np.degrees(_dead_centres(r).tdc),
    ),
    Output(
        "link_master",
        ("cylinder",),
        "1",
        "number of the cylinder whose rod carries this cylinder's link rod (0: none)",
        lambda r: np.where(_linked(r), r.engine.links.master + 1, 0),
        when=_has_links,
    ),
    Output(
        "link_pin_radius",
        ("cylinder",),
        "m",
        "distance of the link pin from the crank-pin centre on the master rod",
        lambda r: np.where(_linked(r), r.engine.links.pin_radius, np.nan),
        when=_has_links,
    ),
    Output(
        "link_pin_angle",
        ("cylinder",),
        "deg",
        "direction of the link pin from the master rod's centre line",
        lambda r: np.where(_linked(r), np.degrees(r.engine.links.pin_angle), np.nan),
        when=_has_links,
    ),
)
