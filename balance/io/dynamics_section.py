"""The layout file's ``dynamics:`` section: the load on the crank of the variable-speed
analysis (docs/dynamics.md, "The layout file").

::

    dynamics:
      load: mean                                   # the default
      # load: propeller
      # load: {torque: 150 N m}                    # must equal the mean gas torque
      # load: {torque: 80 N m, at: 3000 rpm, exponent: 2}

A layout with a ``dynamics:`` section is analysed with the dynamic speed model
(:mod:`balance.core.dynamics`); ``dynamics: {}`` asks for it with the mean load.  The
section holds the :class:`balance.core.speed_model.Load` it names;
:func:`balance.io.fields.load_of` reads the same loads written as text (the command
line's ``--load``).  :data:`SECTION` is
the section's entry in the reader's registry (:mod:`balance.io.layout_sections`).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field

from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.speed_model import (
    ConstantLoad,
    Load,
    MeanLoad,
    PowerLawLoad,
    PropellerLoad,
)
from balance.io.layout_fields import written
from balance.io.layout_sections import SectionReader
from balance.io.located import Hints
from balance.io.problems import FieldProblem
from balance.io.spec_blocks import Speed, Strict, quantity

__all__ = ["SECTION", "DynamicsSpec", "LoadSpec"]

#: A torque, read with its unit into N m.
Torque = Annotated[float, quantity("torque")]


class LoadSpec(Strict):
    """A load given by its torque: constant (``torque`` alone, which must be the mean gas
    torque), or a power law ``torque (speed / at) ** exponent``."""

    torque: Torque
    at: Speed | None = None
    exponent: float | None = Field(default=None, gt=0.0)


class DynamicsSpec(Strict):
    """The ``dynamics:`` section."""

    load: Literal["mean", "propeller"] | LoadSpec = "mean"


def _load(spec: Literal["mean", "propeller"] | LoadSpec) -> Load:
    """The core load of a validated ``load:`` value."""
    if spec == "mean":
        return MeanLoad()
    if spec == "propeller":
        return PropellerLoad()
    assert isinstance(spec, LoadSpec)
    if spec.at is None and spec.exponent is None:
        return ConstantLoad(spec.torque)
    if spec.at is None or spec.exponent is None:
        missing = "at" if spec.at is None else "exponent"
        raise FieldProblem(
            f"a power-law load needs torque, at and exponent; {missing} is missing",
            "for example {torque: 80 N m, at: 3000 rpm, exponent: 2}, or {torque: 150 N m} "
            "for a constant torque",
            ("load", missing),
        )
    return PowerLawLoad(spec.torque, spec.at, spec.exponent)


def _build(spec: DynamicsSpec, engine: Engine) -> Load:
    """The load the engine's sections hold under ``dynamics``."""
    try:
        return _load(spec.load)
    except InputError as exc:  # a power law's value out of range
        raise FieldProblem(str(exc), "torque, at and exponent above zero", ("load",)) from None


def _expand(section: Any, load: Load) -> dict[str, Any]:
    """The section as ``layout expand`` writes it: the load read."""
    if isinstance(load, MeanLoad | PropellerLoad):
        return {"load": load.kind}
    if isinstance(load, ConstantLoad):
        return {"load": {"torque": written(load.torque, "torque", exact=True)}}
    assert isinstance(load, PowerLawLoad)
    return {
        "load": {
            "torque": written(load.torque, "torque", exact=True),
            "at": written(load.speed, "speed", exact=True),
            "exponent": load.exponent,
        }
    }


#: The ``dynamics:`` section's entry in the reader's registry.
SECTION = SectionReader(
    "dynamics",
    DynamicsSpec,
    _build,
    _expand,
    Hints(),
)
