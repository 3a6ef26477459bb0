"""The layout file's ``bearings:`` section and its conversion to main positions
(docs/layout-format.md, "Bearing loads").

::

    bearings:
      mains: [-45 mm, 45 mm, 136 mm, 227 mm, 318 mm]

With several crankshafts (docs/several-crankshafts.md, "Bearing loads") ``mains`` may be a
mapping from crankshaft name to that shaft's list::

    bearings:
      mains: {left: [-40 mm, 40 mm], right: [-40 mm, 40 mm]}

A plain list is crankshaft 1's; a shaft without a list gets the default mains of its own
throws.  A name that is no crankshaft is refused ("did you mean").

The section is optional: ``--bearings`` without it (or a section without ``mains``) means
the default mains of :func:`balance.core.bearings.engine_default_mains` (one between
neighbouring throws, never between the rods of one throw, and one half a pitch beyond each
end throw).

What is valid
-------------
* at least two mains in each list (one main cannot carry a crankshaft: the lever rule needs two);
* strictly increasing ``z`` (each main after the one before, none twice);
* no main in the plane of a crank pin (closer than 1 µm): a journal cannot sit where a
  pin is, and the lever rule would be ambiguous there;
* throws beyond the outermost main are allowed: they are carried as a cantilever by the
  two nearest mains.

Problems are raised as :class:`~balance.io.problems.FieldProblem` with the offending entry in
``at`` (``("mains", j)``, or ``("mains", name, j)`` in the mapping form), so that the
reader can name its line (:mod:`balance.io.located`).
:data:`SECTION` is the section's entry in the reader's registry
(:mod:`balance.io.layout_sections`): its model, its builder (the mains, checked against the
engine's crank-pin planes) and its part of ``balance layout expand`` (the mains used).
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping, Sequence
from typing import Annotated, Any

import numpy as np
from numpy.typing import NDArray
from pydantic import Discriminator, Field, Tag, model_validator

from balance.core.engine import Engine
from balance.io.layout_fields import written
from balance.io.layout_sections import SectionReader
from balance.io.problems import FieldProblem
from balance.io.spec_blocks import Length, Strict

__all__ = ["PLANE_TOLERANCE", "SECTION", "BearingsSpec", "main_positions", "shaft_mains"]

#: A main closer than this to a crank pin's plane is in that plane [m].
PLANE_TOLERANCE = 1e-6


def _form(value: Any) -> str:
    """Which form ``mains`` takes: a mapping by crankshaft name, else a list."""
    return "<mapping>" if isinstance(value, dict) else "<list>"


#: ``mains``: a list, or a mapping from crankshaft name to a list (several crankshafts).
MainsForm = Annotated[
    Annotated[list[Length], Tag("<list>"), Field(max_length=1024)]
    | Annotated[dict[str, Annotated[list[Length], Field(max_length=1024)]], Tag("<mapping>")],
    Discriminator(_form),
]


class BearingsSpec(Strict):
    """The ``bearings:`` section: positions of the main bearings along the crank (SI)."""

    mains: MainsForm | None = None

    @model_validator(mode="after")
    def _check(self) -> BearingsSpec:
        if isinstance(self.mains, dict):
            for name, mains in self.mains.items():
                _check_order(mains, ("mains", name))
        elif self.mains is not None:
            _check_order(self.mains, ("mains",))
        return self


def _check_order(mains: Sequence[float], at: tuple[str | int, ...]) -> None:
    """At least two mains, in strictly increasing ``z``; problems at ``at`` (+ entry)."""
    if len(mains) < 2:
        raise FieldProblem(
            f"{'.'.join(map(str, at))} has {len(mains)} entr{'y' if len(mains) == 1 else 'ies'}",
            "give at least two main bearings, e.g. [-45 mm, 45 mm]",
            at,
        )
    for j in range(1, len(mains)):
        if not mains[j] > mains[j - 1]:
            raise FieldProblem(
                f"main {j + 1} at {_mm(mains[j])} is not after main {j} at {_mm(mains[j - 1])}",
                "list the mains in increasing z, each once",
                (*at, j),
            )


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
    mains = spec.mains
    if isinstance(mains, dict):
        if not engine.axes_named:
            raise FieldProblem(
                "mains is a mapping from crankshaft name to mains, but the layout has no "
                "crankshafts: section",
                "give the mains as a list, e.g. [-45 mm, 45 mm]",
                ("mains",),
            )
        names = _names(engine)
        _known(mains, names)
        if names[0] not in mains:
            from balance.core.bearings import engine_default_mains

            return engine_default_mains(engine)
        return _check_mains(mains[names[0]], engine.z, ("mains", names[0]))
    return _check_mains(mains, engine.z)


def shaft_mains(spec: BearingsSpec | None, engine: Engine) -> dict[str, tuple[float, ...]]:
    """Main-bearing positions of each crankshaft of an engine with several
    (:attr:`~balance.core.engine.Engine.geared`): its list in the section, else the default
    mains of its own throws (:func:`balance.core.bearing_loads.axis_mains`).

    Parameters
    ----------
    spec : BearingsSpec or None
        The validated ``bearings:`` section; ``mains`` a list (crankshaft 1's) or a mapping
        from crankshaft name to its list.
    engine : Engine
        The engine.

    Returns
    -------
    dict of str to tuple of float
        Each crankshaft's mains [m], strictly increasing, in the crankshafts' order.

    Raises
    ------
    FieldProblem
        For a name that is no crankshaft (``at = ("mains", name)``), or a main in the plane
        of one of its shaft's crank pins (``at = ("mains", name, j)``, or ``("mains", j)``
        for a plain list).
    """
    from balance.core.bearing_loads import axis_engine, axis_mains

    names = _names(engine)
    given: Mapping[str, Sequence[float]] = {}
    mains = spec.mains if spec is not None else None
    if isinstance(mains, dict):
        given = mains
        _known(given, names)
    elif mains is not None:
        given = {names[0]: mains}
    table = engine.axis_table()
    out = {}
    plain = not isinstance(mains, dict)
    for s, name in enumerate(names):
        if name in given:
            at: tuple[str | int, ...] = ("mains",) if plain else ("mains", name)
            on = np.flatnonzero(table.axis == s)
            checked = _check_mains(given[name], engine.z[on], at, on + 1)
            out[name] = tuple(float(v) for v in checked)
        else:
            out[name] = tuple(float(v) for v in axis_mains(engine, s, axis_engine(engine, s)))
    return out


def _names(engine: Engine) -> tuple[str, ...]:
    """The engine's crankshaft names (one unnamed crankshaft: ``("crankshaft",)``)."""
    return tuple(engine.axis_table().names)


def _known(mains: Mapping[str, Any], names: Sequence[str]) -> None:
    """Refuse a name of the mapping form that is no crankshaft."""
    for key in mains:
        if key not in names:
            hint = difflib.get_close_matches(key, names, n=1)
            more = f"did you mean '{hint[0]}'? " if hint else ""
            raise FieldProblem(
                f"mains names '{key}', which is no crankshaft",
                f"{more}the crankshafts are {', '.join(names)}",
                ("mains", key),
            )


def _check_mains(
    mains: Sequence[float],
    z: NDArray[np.float64],
    at: tuple[str | int, ...] = ("mains",),
    numbers: NDArray[np.intp] | None = None,
) -> NDArray[np.float64]:
    """The mains as an array, none in the plane of a crank pin.

    Parameters
    ----------
    mains : sequence of float
        Main positions [m].
    z : ndarray
        The cylinders' throw planes [m].
    at : tuple of str and int
        The list's path in the section.
    numbers : ndarray of int, optional
        The cylinders' numbers (1-based; default their order in ``z``).

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
            named = ", ".join(str(int(i) + 1 if numbers is None else int(numbers[i])) for i in hit)
            noun = "cylinder" if hit.size == 1 else "cylinders"
            raise FieldProblem(
                f"main {j + 1} at {_mm(float(value))} is in the plane of the crank pin of "
                f"{noun} {named}",
                "put main bearings between throw planes (or beyond the end throws)",
                (*at, j),
            )
    return zm


def _mm(value: float) -> str:
    return f"{value * 1e3:.6g} mm"


def _build(spec: BearingsSpec, engine: Engine) -> Any:
    """The main positions [m] the engine's sections hold: the section's, checked against
    the crank-pin planes, or the defaults for a section without ``mains``; with several
    crankshafts each one's, by name (:func:`shaft_mains`)."""
    if engine.geared:
        return shaft_mains(spec, engine)
    return tuple(float(v) for v in main_positions(spec, engine))


def _expand(section: Any, mains: Any) -> dict[str, Any]:
    """The section as ``layout expand`` writes it: the mains used (the section's, or the
    defaults); with several crankshafts a mapping from name to list."""
    if isinstance(mains, Mapping):
        return {
            "mains": {
                name: [written(z, "length", exact=True) for z in zs] for name, zs in mains.items()
            }
        }
    return {"mains": [written(z, "length", exact=True) for z in mains]}


#: The ``bearings:`` section's entry in the reader's registry.
SECTION = SectionReader("bearings", BearingsSpec, _build, _expand)
