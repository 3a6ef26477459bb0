"""Views of the ``torque`` section: the engine torque with gas forces
(:mod:`balance.core.torque`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.catalogue import value
from balance.views.fitted import Column, NumberTable
from balance.views.polar import format_number, json_number

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

    from balance.core.result import Result
    from balance.core.torque import TorqueResult

__all__ = ["json_block", "render_torque", "tables"]


def _part(result: Result) -> TorqueResult:
    part: TorqueResult = result.part("torque")
    return part


def json_block(result: Result) -> dict[str, Any]:
    """The section's part of the analysis JSON: ``torque`` and ``gas``."""
    t = _part(result)
    return {
        "torque": {
            "mean_Nm": json_number(t.mean),
            "max_Nm": json_number(t.maximum),
            "min_Nm": json_number(t.minimum),
            "speed_fluctuation": json_number(t.speed_fluctuation),
            "flywheel_inertia_kgm2": json_number(t.flywheel_inertia),
        },
        "gas": {
            "indicated_work_J": json_number(value(result, "indicated_work")),
            "torque_nonuniformity": json_number(t.nonuniformity),
            "excess_work_J": json_number(t.excess_work),
            "firing_tdc_deg": [json_number(v) for v in np.asarray(t.firing_tdc)],
        },
    }


def render_torque(result: Result) -> RenderableType:
    """Rich renderable of the torque summary of an analysis with gas forces.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`, with the ``torque`` section.

    Returns
    -------
    rich.console.RenderableType
        The table of the mean, largest and smallest torque, the non-uniformity, the
        indicated and excess work, the speed fluctuation and the flywheel inertia.
    """
    t = _part(result)
    rows = [
        ("mean torque", "N m", float(t.mean)),
        ("largest torque", "N m", float(t.maximum)),
        ("smallest torque", "N m", float(t.minimum)),
        ("non-uniformity (M_max - M_min)/M_mean", "1", float(t.nonuniformity)),
        ("indicated work per cycle", "J", float(value(result, "indicated_work"))),
        ("largest excess work", "J", float(t.excess_work)),
        ("speed fluctuation (w_max - w_min)/w_mean", "1", float(t.speed_fluctuation)),
        ("flywheel inertia", "kg m^2", float(t.flywheel_inertia)),
    ]
    return NumberTable(
        "Engine torque with gas forces, over the cycle",
        [
            Column("quantity", key=True, justify="left"),
            Column("value"),
            Column("unit", justify="left"),
        ],
        [[label, format_number(value), unit] for label, unit, value in rows],
    )


def tables(result: Result) -> list[RenderableType]:
    """The section's table: :func:`render_torque`."""
    return [render_torque(result)]
