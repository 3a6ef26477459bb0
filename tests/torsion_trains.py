"""Torsion trains for the tests: built-in layouts with a mass-elastic table added in Python
(the layout reader's ``torsion:`` section is wired separately)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from balance.core.analysis import compute
from balance.core.engine import Engine
from balance.core.result import Request, Result
from balance.core.torsion import Shaft, TorsionDamper, TorsionMass, TorsionTrain, torsion_part
from balance.io.layout_file import load_layout


def inline4_train(**changes: Any) -> TorsionTrain:
    """A car inline-4 with a pulley, a timing sprocket, four throws, a flywheel and a
    vehicle beyond a clutch, and a tuned rubber damper at the pulley (illustrative values:
    the order of a 2-litre engine's, not a published table)."""
    throws = tuple(
        TorsionMass(
            f"throw {c}",
            crank_inertia=0.0030,
            cylinders=(c,),
            damping=0.3,
            shaft=Shaft(0.75e6, 1.0, 0.050, 0.018),
        )
        for c in (1, 2, 3, 4)
    )
    masses = (
        TorsionMass("pulley", inertia=0.0035, shaft=Shaft(1.5e6, 1.0, 0.040)),
        TorsionMass("sprocket", inertia=0.0006, shaft=Shaft(0.9e6, 1.0, 0.045)),
        *throws[:3],
        replace(throws[3], shaft=Shaft(1.2e6, 1.0, 0.060)),
        TorsionMass("flywheel", inertia=0.10, shaft=Shaft(8000.0, 4.0)),
        TorsionMass("vehicle", inertia=0.5, damping=2.0),
    )
    train = TorsionTrain(
        masses,
        (TorsionDamper(1, inertia=0.010, stiffness=7.0e4, damping=8.0),),
        loss_factor=0.02,
    )
    return replace(train, **changes)


def v8_train() -> TorsionTrain:
    """A 12-mass V8 train (pulley, gear, four throws of two cylinders, flywheel, gearbox,
    propshaft, differential, wheels, vehicle) with a tuned damper: the benchmark's."""
    masses = [
        TorsionMass("pulley", inertia=0.006, shaft=Shaft(1.2e6, 1.0, 0.045)),
        TorsionMass("gear", inertia=0.002, shaft=Shaft(1.5e6, 1.0, 0.055)),
    ]
    for t in range(4):
        masses.append(
            TorsionMass(
                f"throw {t + 1}",
                crank_inertia=0.004,
                cylinders=(2 * t + 1, 2 * t + 2),
                damping=0.5,
                shaft=Shaft(1.1e6, 1.0, 0.060, 0.02),
            )
        )
    masses += [
        TorsionMass("flywheel", inertia=0.15, shaft=Shaft(2.0e4, 5.0)),
        TorsionMass("gearbox", inertia=0.02, shaft=Shaft(1.5e4, 2.0)),
        TorsionMass("propshaft", inertia=0.01, shaft=Shaft(2.0e4, 2.0)),
        TorsionMass("differential", inertia=0.02, shaft=Shaft(8e3, 2.0)),
        TorsionMass("wheels", inertia=1.0, shaft=Shaft(3e4, 5.0)),
        TorsionMass("vehicle", inertia=30.0, damping=5.0),
    ]
    return TorsionTrain(tuple(masses), (TorsionDamper(1, 0.012, 9e4, 8.0),), loss_factor=0.02)


def with_train(layout: str | Engine, train: TorsionTrain) -> Engine:
    """A built-in layout (or an engine) with the torsion train as its ``torsion`` section."""
    engine = load_layout(layout) if isinstance(layout, str) else layout
    return engine.with_section("torsion", train)


def analysed(engine: Engine, **options: Any) -> Result:
    """The analysis of the engine (its default sections) and then its ``torsion`` part, over
    the default sweep of speeds unless ``speeds`` says otherwise."""
    options.setdefault("speeds", "sweep")
    result = compute(engine, Request())
    if engine.gas is not None:
        from balance.core.torque import torque_part

        result = torque_part(engine, Request(), result)
    return torsion_part(engine, Request(), result, **options)


def chain(inertias: Any, stiffnesses: Any) -> TorsionTrain:
    """A plain chain of ``inertia`` masses (no cylinders) on sections of ``stiffnesses``."""
    j = np.asarray(inertias, dtype=float)
    k = np.asarray(stiffnesses, dtype=float)
    masses = tuple(
        TorsionMass(
            f"m{i + 1}", inertia=float(j[i]), shaft=Shaft(float(k[i])) if i < k.size else None
        )
        for i in range(j.size)
    )
    return TorsionTrain(masses)
