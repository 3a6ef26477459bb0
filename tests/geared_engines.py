"""Engines with several crankshafts for the tests, built in Python: a layout read as today
and its crankshafts set with :func:`with_crankshafts` (the one place to switch to layout
files with a ``crankshafts:`` section once they are read)."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from balance.api import Engine
from balance.core.crankshafts import Crankshafts
from tests.helpers import engine as helper_engine


def with_crankshafts(
    base: Engine,
    of_cylinder: list[int],
    *,
    x: list[float],
    y: list[float],
    rotation: list[float] | None = None,
    phase_deg: list[float] | None = None,
    output: float = 1.0,
    names: tuple[str, ...] | None = None,
) -> Engine:
    """``base`` with its cylinders on crankshafts (0-based ``of_cylinder``) at ``x``, ``y``
    [m], turning with ``rotation`` (±1) and with ``phase_deg`` [deg]."""
    n = len(x)
    return replace(
        base,
        crankshafts=Crankshafts(
            names=names or tuple(f"shaft{i + 1}" for i in range(n)),
            x=np.asarray(x, dtype=np.float64),
            y=np.asarray(y, dtype=np.float64),
            rotation=np.asarray(rotation or [1.0] * n, dtype=np.float64),
            phase=np.radians(np.asarray(phase_deg or [0.0] * n, dtype=np.float64)),
            of_cylinder=np.asarray(of_cylinder, dtype=np.intp),
            opposed=np.full(base.n_cylinders, -1, dtype=np.intp),
            output_rotation=float(output),
        ),
    )


def cylinders(throws: list[float], banks: list[float], z: list[float], **options: Any) -> Engine:
    """An engine of explicit cylinders (degrees, metres) with the helper's masses."""
    e = helper_engine([0.0] * len(throws), None, **options)
    return replace(
        e,
        throw=np.radians(np.asarray(throws, dtype=np.float64)),
        bank=np.radians(np.asarray(banks, dtype=np.float64)),
        z=np.asarray(z, dtype=np.float64),
        reference_z=0.5 * (min(z) + max(z)),
    )


def twin_crank(sense: float, *, counterweighted: bool = True, gap: float = 0.09) -> Engine:
    """Two one-cylinder cranks side by side at ``x = -gap/2, +gap/2``, one ``z``, parallel
    vertical bores; the second turns with ``sense``.  Counterweighted: each crank's rotating
    mass is its big end less a counterweight for its big end and 100 % of its reciprocating
    mass (a net ``-m_rec`` at the pin)."""
    base = cylinders([0.0, 0.0], [0.0, 0.0], [0.0, 0.0])
    if counterweighted:
        base = replace(base, rotating_mass=-base.reciprocating_mass)
    return with_crankshafts(
        base, [0, 1], x=[-gap / 2, gap / 2], y=[0.0, 0.0], rotation=[1.0, sense]
    )


DEG = math.pi / 180.0
