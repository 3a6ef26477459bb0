"""Each cylinder's dead centres and link rod, as a section of an analysis.

Offsets and link rods move a piston's dead centres away from its throw and bank, and
change its travel: the ``cylinders`` section (:mod:`balance.core.sections`) reports each
cylinder's actual stroke and top-dead-centre crank angle
(:func:`balance.core.links.dead_centres`), and for an engine with master and link rods
which rod carries each link rod and where its link pin is.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from balance.core.catalogue import Output
from balance.core.engine import Engine

__all__ = ["CYLINDER_OUTPUTS", "DeadCentres", "cylinders_part"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
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


def cylinders_part(engine: Engine, request: Any, result: Any) -> Any:
    """The ``cylinders`` section: :class:`DeadCentres` of every cylinder."""
    from balance.core.links import engine_dead_centres

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
