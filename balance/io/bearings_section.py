"""The layout file's ``bearings:`` section and its conversion to main positions
(docs/layout-format.md, "Bearing loads").

::

    bearings:
      mains: [-45 mm, 45 mm, 136 mm, 227 mm, 318 mm]

The section is optional: ``--bearings`` without it (or a section without ``mains``) means
the default mains of :func:`balance.core.bearings.engine_default_mains` (one between
neighbouring throws, never between the rods of one throw, and one half a pitch beyond each
end throw).

What is valid
-------------
* at least two mains (one main cannot carry a crankshaft: the lever rule needs two);
* strictly increasing ``z`` (each main after the one before, none twice);
* no main in the plane of a crank pin (closer than 1 µm): a journal cannot sit where a
  pin is, and the lever rule would be ambiguous there;
* throws beyond the outermost main are allowed: they are carried as a cantilever by the
  two nearest mains.

Problems are raised as :class:`~balance.io.problems.FieldProblem` with the offending entry in
``at`` (``("mains", j)``), so that the reader can name its line (:mod:`balance.io.located`).
:data:`SECTION` is the section's entry in the reader's registry
(:mod:`balance.io.layout_sections`): its model, its builder (the mains, checked against the
engine's crank-pin planes) and its part of ``balance layout expand`` (the mains used).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, model_validator

from balance.core.engine import Engine
from balance.io.layout_fields import written
from balance.io.layout_sections import SectionReader
from balance.io.problems import FieldProblem
from balance.io.schema import Length, Strict

__all__ = ["PLANE_TOLERANCE", "SECTION", "BearingsSpec", "main_positions"]

#: A main closer than this to a crank pin's plane is in that plane [m].
PLANE_TOLERANCE = 1e-6


class BearingsSpec(Strict):
    """The ``bearings:`` section: positions of the main bearings along the crank (SI)."""

    mains: list[Length] | None = Field(default=None, max_length=1024)

    @model_validator(mode="after")
    def _check(self) -> BearingsSpec:
        if self.mains is None:
            return self
        if len(self.mains) < 2:
            raise FieldProblem(
                f"mains has {len(self.mains)} entr{'y' if len(self.mains) == 1 else 'ies'}",
                "give at least two main bearings, e.g. [-45 mm, 45 mm]",
                ("mains",),
            )
        for j in range(1, len(self.mains)):
            if not self.mains[j] > self.mains[j - 1]:
                raise FieldProblem(
                    f"main {j + 1} at {_mm(self.mains[j])} is not after main {j} at "
                    f"{_mm(self.mains[j - 1])}",
                    "list the mains in increasing z, each once",
                    ("mains", j),
                )
        return self


def main_positions(spec: BearingsSpec | None, engine: Engine) -> NDArray[np.float64]:
    """Main-bearing positions of an engine: the section's, or the defaults.

    Parameters
    ----------
    spec : BearingsSpec or None
        The validated ``bearings:`` section, if the layout has one.
    engine : Engine
        The engine (its cylinder planes ``z``; for the defaults its pitch and stroke,
        :func:`balance.core.bearings.engine_default_mains`).

    Returns
    -------
    ndarray
        Main positions [m], strictly increasing.

    Raises
    ------
    FieldProblem
        When a main lies in the plane of a crank pin (``at = ("mains", j)``).
    """
    if spec is None or spec.mains is None:
        from balance.core.bearings import engine_default_mains

        return engine_default_mains(engine)
    return _check_mains(spec.mains, engine.z)


def _check_mains(mains: Sequence[float], z: NDArray[np.float64]) -> NDArray[np.float64]:
    """The mains as an array, none in the plane of a crank pin.

    Parameters
    ----------
    mains : sequence of float
        Main positions [m].
    z : ndarray
        The cylinders' throw planes [m].

    Returns
    -------
    ndarray
        The mains [m].

    Raises
    ------
    FieldProblem
        When a main lies in the plane of a crank pin (``at = ("mains", j)``).
    """
    zm = np.asarray(mains, dtype=np.float64)
    for j, value in enumerate(zm):
        hit = np.flatnonzero(np.abs(np.asarray(z) - value) < PLANE_TOLERANCE)
        if hit.size:
            numbers = ", ".join(str(int(i) + 1) for i in hit)
            noun = "cylinder" if hit.size == 1 else "cylinders"
            raise FieldProblem(
                f"main {j + 1} at {_mm(float(value))} is in the plane of the crank pin of "
                f"{noun} {numbers}",
                "put main bearings between throw planes (or beyond the end throws)",
                ("mains", j),
            )
    return zm


def _mm(value: float) -> str:
    return f"{value * 1e3:.6g} mm"


def _build(spec: BearingsSpec, engine: Engine) -> tuple[float, ...]:
    """The main positions [m] the engine's sections hold: the section's, checked against
    the crank-pin planes, or the defaults for a section without ``mains``."""
    return tuple(float(v) for v in main_positions(spec, engine))


def _expand(section: Any, mains: tuple[float, ...]) -> dict[str, Any]:
    """The section as ``layout expand`` writes it: the mains used (the section's, or the
    defaults)."""
    return {"mains": [written(z, "length", exact=True) for z in mains]}


#: The ``bearings:`` section's entry in the reader's registry.
SECTION = SectionReader("bearings", BearingsSpec, _build, _expand)
