"""Bearing loads across a balance-factor study: one proposal per factor, loads in one pass."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.analysis import compute
from balance.core.bearings import counterweights_of, largest_loads
from balance.core.engine import Engine
from balance.core.result import Request

__all__ = ["factor_bearing_loads"]


def factor_bearing_loads(
    engine: Engine,
    factors: ArrayLike,
    strategy: str | None = None,
    counterweight_radius: float | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Largest main-bearing load [N] and internal moment [N m] with the counterweights that
    the proposal makes at each balance factor (the other settings as the engine's
    ``balance:`` section, else the defaults)."""
    sets = []
    for factor in np.asarray(factors, dtype=np.float64):
        request = Request(
            orders=(1, 2),
            balance_factor=float(factor),
            strategy=strategy,
            counterweight_radius=counterweight_radius,
            torque=False,
            cylinders=False,
        )
        balanced = compute(engine, request).balanced
        sets.append(counterweights_of(balanced.proposal if balanced is not None else None))
    return largest_loads(engine, sets)
