"""The layout file's ``torsion:`` section: the crank train's mass-elastic table
(docs/torsion.md, "The layout file"; docs/layout-format.md, "Torsional vibration").

::

    torsion:
      masses:                      # from the free end to the driven end
        - {name: pulley, inertia: 0.0035 kg m^2,
           shaft: {stiffness: 1.5e6 N m/rad, damping: 1 N m s/rad, diameter: 40 mm}}
        - {name: throw 1, cylinders: [1], crank_inertia: 0.0030 kg m^2,
           shaft: {stiffness: 0.75e6 N m/rad, diameter: 50 mm, bore: 18 mm}}
        - ...
        - {name: flywheel, inertia: 0.10 kg m^2}
      dampers:
        - {at: pulley, inertia: 0.012 kg m^2, damping: 25 N m s/rad}
      loss_factor: 2 %

:class:`TorsionSpec` is the section's model (every quantity with its unit: inertias in
``kg m^2``, stiffnesses in ``N m/rad``, ``kN m/rad`` or ``N m/deg``, dampings in
``N m s/rad``, lengths); its builder makes a :class:`balance.core.torsion.TorsionTrain` and
reports every value that cannot be analysed at once, each at its line
(:func:`balance.core.torsion_train.train_problems`).  :data:`SECTION` is the section's
entry in the reader's registry (:mod:`balance.io.layout_sections`).
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import Field

from balance.core.engine import Engine
from balance.core.torsion_excitation import place_firing_tdc
from balance.core.torsion_train import (
    Shaft,
    TorsionDamper,
    TorsionMass,
    TorsionTrain,
    resolve_mass,
    train_problems,
)
from balance.io.layout_fields import exact_number, written
from balance.io.layout_sections import SectionReader
from balance.io.located import Hints
from balance.io.problems import FieldProblem, FieldProblems
from balance.io.spec_blocks import Strict, kg_m2, quantity

__all__ = ["SECTION", "DamperSpec", "MassSpec", "ShaftSpec", "TorsionSpec"]

#: The most masses (and dampers) a table may have.
MAX_MASSES = 256

Inertia = Annotated[float, quantity("inertia", kg_m2)]
OptInertia = Annotated[float | None, quantity("inertia", kg_m2)]
Stiffness = Annotated[float, quantity("rotational_stiffness")]
Damping = Annotated[float, quantity("rotational_damping")]
Length = Annotated[float, quantity("length")]
OptLength = Annotated[float | None, quantity("length")]
Fraction = Annotated[float, quantity("fraction")]


class ShaftSpec(Strict):
    """A shaft section to the next mass."""

    stiffness: Stiffness
    damping: Damping = 0.0
    diameter: OptLength = None
    bore: Length = 0.0


class MassSpec(Strict):
    """A mass of the table."""

    name: str = Field(min_length=1, max_length=100)
    inertia: OptInertia = None
    crank_inertia: OptInertia = None
    cylinders: list[int] = Field(default_factory=list, max_length=64)
    damping: Damping = 0.0
    shaft: ShaftSpec | None = None


class DamperSpec(Strict):
    """A damper hung on a mass: a number (1-based) or a mass's name."""

    at: int | str
    inertia: Inertia
    stiffness: Stiffness = 0.0
    damping: Damping = 0.0


class TorsionSpec(Strict):
    """The ``torsion:`` section."""

    masses: list[MassSpec] = Field(max_length=MAX_MASSES)
    dampers: list[DamperSpec] = Field(default_factory=list, max_length=MAX_MASSES)
    loss_factor: Fraction = 0.0


def _train(spec: TorsionSpec) -> tuple[TorsionTrain, list[FieldProblem]]:
    """The core train of a validated section, and the dampers hung on no mass."""
    masses = tuple(
        TorsionMass(
            name=m.name,
            inertia=m.inertia,
            crank_inertia=m.crank_inertia,
            cylinders=tuple(m.cylinders),
            damping=m.damping,
            shaft=None
            if m.shaft is None
            else Shaft(m.shaft.stiffness, m.shaft.damping, m.shaft.diameter, m.shaft.bore),
        )
        for m in spec.masses
    )
    problems = []
    dampers = []
    for r, d in enumerate(spec.dampers):
        at = resolve_mass(masses, d.at)
        if at is None:
            names = ", ".join(m.name for m in masses)
            problems.append(
                FieldProblem(
                    f"at {d.at!r} names no mass",
                    f"a mass's number (1 to {len(masses)}) or name ({names})",
                    ("dampers", r, "at"),
                )
            )
            continue
        dampers.append(TorsionDamper(at, d.inertia, d.stiffness, d.damping))
    return TorsionTrain(masses, tuple(dampers), spec.loss_factor), problems


def _build(spec: TorsionSpec, engine: Engine) -> TorsionTrain:
    """The train the engine's sections hold under ``torsion``: checked against the engine,
    with each cylinder's firing TDC placed (from the gas section, the firing order or the
    cylinders' ``tdc``)."""
    train, problems = _train(spec)
    for found in train_problems(train, engine):
        absolute = found.path[:1] != ("torsion",)
        at = found.path if absolute else found.path[1:]
        problems.append(FieldProblem(found.message, found.valid or "", at, absolute))
    if problems:
        raise FieldProblems(problems)
    if engine.gas is None:
        placed = place_firing_tdc(engine)
        assert not isinstance(placed, str)  # train_problems has checked it
        train = TorsionTrain(train.masses, train.dampers, train.loss_factor, tuple(placed))
    return train


def _expand(section: Any, train: TorsionTrain) -> dict[str, Any]:
    """The section as ``layout expand`` writes it: the table read (SI written back in the
    file's units)."""
    masses = []
    for m in train.masses:
        entry: dict[str, Any] = {"name": m.name}
        if m.inertia is not None:
            entry["inertia"] = written(m.inertia, "inertia", exact=True)
        else:
            assert m.crank_inertia is not None
            entry["crank_inertia"] = written(m.crank_inertia, "inertia", exact=True)
        if m.cylinders:
            entry["cylinders"] = list(m.cylinders)
        if m.damping:
            entry["damping"] = f"{exact_number(m.damping)} N m s/rad"
        if m.shaft is not None:
            shaft: dict[str, Any] = {"stiffness": f"{exact_number(m.shaft.stiffness)} N m/rad"}
            if m.shaft.damping:
                shaft["damping"] = f"{exact_number(m.shaft.damping)} N m s/rad"
            if m.shaft.diameter is not None:
                shaft["diameter"] = written(m.shaft.diameter, "length", exact=True)
            if m.shaft.bore:
                shaft["bore"] = written(m.shaft.bore, "length", exact=True)
            entry["shaft"] = shaft
        masses.append(entry)
    out: dict[str, Any] = {"masses": masses}
    if train.dampers:
        out["dampers"] = [
            {
                "at": d.at,
                "inertia": written(d.inertia, "inertia", exact=True),
                **({"stiffness": f"{exact_number(d.stiffness)} N m/rad"} if d.stiffness else {}),
                **({"damping": f"{exact_number(d.damping)} N m s/rad"} if d.damping else {}),
            }
            for d in train.dampers
        ]
    if train.loss_factor:
        out["loss_factor"] = written(train.loss_factor, "fraction", exact=True)
    return out


#: The ``torsion:`` section's entry in the reader's registry.
SECTION = SectionReader(
    "torsion",
    TorsionSpec,
    _build,
    _expand,
    Hints(
        missing={
            "masses": "add 'masses', the table from the free end: [{name: pulley, inertia: "
            "0.0035 kg m^2, shaft: {stiffness: 1.5e6 N m/rad}}, ...]",
            "stiffness": "add 'stiffness', e.g. '1.5e6 N m/rad'",
            "inertia": "add 'inertia', e.g. '0.012 kg m^2'",
            "at": "add 'at': the mass the damper hangs on, its number or name",
        }
    ),
)
