"""The concerns beyond the free forces, each one section: the registry.

The base analysis (:func:`balance.core.analysis.compute`) gives the free forces, moments
and roll of an engine.  Everything else a request may ask for is a *section*: the
proposal, the gas forces and torque, each cylinder's dead centres and link rods, the
balance-factor study, the engine on its mounts and the crank-pin and main-bearing loads.
A section says

- its name: the key of :attr:`balance.core.result.Request.sections` and of
  :attr:`balance.core.result.Result.parts`, the keyword of :func:`balance.analyse` and the
  flag of the command line;
- which section of the layout file turns it on (``gas:``, ``bearings:``, ``mounts:``; crosshead
  cylinders, ``crossheads``) and
  whether it is computed unless turned off;
- the options it takes (what a request may set besides turning it on);
- where its computation is: a function ``part(engine, request, result, **options)`` that
  returns the result with the section's part added (and, for the gas forces, the roll
  with them);
- where its outputs are declared (:class:`balance.core.catalogue.Output`).

:func:`balance.core.analysis.compute` runs the sections a request asks for in the order of
:data:`SECTIONS`; the writers (Dataset, JSON, CSV, table, report, plots) loop over the
parts a result holds and never name one.  Functions and outputs are named by their module
path, so that a section's module is imported only when it is used.  How to add a concern
is in docs/architecture.md, "Adding a physical concern".
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cache
from importlib import import_module
from typing import Any

__all__ = ["SECTIONS", "Section", "default_sections", "load", "names", "section"]


@dataclass(frozen=True)
class Section:
    """One concern of the analysis beyond the free forces.

    Attributes
    ----------
    name : str
        Key of the request's sections and of the result's parts.
    title : str
        What the section holds, as headings print it.
    part : str
        ``"module:function"`` computing the part: ``function(engine, request, result,
        **options) -> Result``.
    outputs : str
        ``"module:NAME"`` of the tuple of its :class:`balance.core.catalogue.Output`.
    layout_key : str or None
        The layout file's section whose presence turns this one on, if any.
    default : bool
        Computed unless the request turns it off (otherwise only when asked, or when the
        layout has its ``layout_key`` section).
    options : tuple of str
        Names of the options a request may give it.
    figure_options : tuple of (str, object)
        Options that its figures need beyond what it computes for a table (the mounts'
        speed sweep): a request for figures gives them (``build_request(figures=True)``).
    needed : callable, optional
        ``needed(engine, request, result, options)``: False where the part would return
        the result as it is, so that a default section's module is not even imported for
        an engine it has nothing to say about (the start of a command is part of its
        time).  None: the part is always run.
    """

    name: str
    title: str
    part: str
    outputs: str
    layout_key: str | None = None
    default: bool = False
    options: tuple[str, ...] = ()
    figure_options: tuple[tuple[str, Any], ...] = ()
    needed: Callable[[Any, Any, Any, Mapping[str, Any]], bool] | None = None


def _with_gas(engine: Any, request: Any, result: Any, options: Mapping[str, Any]) -> bool:
    """The ``torque`` part has something to add: the engine has a ``gas:`` section."""
    return engine.gas is not None


def _several_crank_axes(engine: Any, request: Any, result: Any, options: Mapping[str, Any]) -> bool:
    """The ``crankshafts`` part has something to add: the engine has several crank axes."""
    return result.shafts is not None


def _speed_model_applies(
    engine: Any, request: Any, result: Any, options: Mapping[str, Any]
) -> bool:
    """The ``dynamics`` part has something to add: gas forces (the constant rung's bound, or
    the dynamic rung), a ``dynamics:`` section, or a speed model asked for (the dynamic one
    without gas forces is refused there, with its reason)."""
    return (
        result.part("torque") is not None
        or engine.section("dynamics") is not None
        or options.get("speed_model") is not None
    )


#: Every section, in the order in which :func:`balance.core.analysis.compute` runs them (a
#: section may read the parts of those before it) and the writers show them.
SECTIONS: tuple[Section, ...] = (
    Section(
        "cylinders",
        "Cylinders: dead centres and link rods",
        part="balance.core.cylinders:cylinders_part",
        outputs="balance.core.cylinders:CYLINDER_OUTPUTS",
        default=True,
    ),
    Section(
        "torque",
        "Gas forces and torque",
        part="balance.core.torque:torque_part",
        outputs="balance.core.torque:OUTPUTS",
        layout_key="gas",
        default=True,
        needed=_with_gas,
    ),
    Section(
        "guide_forces",
        "Guide forces and guide-force moments (crosshead engines)",
        part="balance.core.crosshead:guide_force_part",
        outputs="balance.core.crosshead:OUTPUTS",
        layout_key="crossheads",
    ),
    Section(
        "crankshafts",
        "Several crankshafts",
        part="balance.core.geared:geared_part",
        outputs="balance.core.geared:OUTPUTS",
        default=True,
        needed=_several_crank_axes,
    ),
    Section(
        "dynamics",
        "Variable crank speed",
        part="balance.core.dynamics:dynamics_part",
        outputs="balance.core.dynamics:OUTPUTS",
        layout_key="dynamics",
        default=True,
        options=("speed_model", "load", "flywheel", "figures"),
        figure_options=(("figures", True),),
        needed=_speed_model_applies,
    ),
    Section(
        "proposal",
        "Balancing proposal",
        part="balance.core.proposal:proposal_part",
        outputs="balance.core.proposal:OUTPUTS",
        default=True,
        options=(
            "cancel",
            "strategy",
            "balance_factor",
            "counterweight_radius",
            "cancel_roll",
            "balance_factor_of",
        ),
    ),
    Section(
        "factor_study",
        "Balance-factor study",
        part="balance.core.factor_study:factor_study_part",
        outputs="balance.core.factor_study:STUDY_OUTPUTS",
        options=("factors",),
    ),
    Section(
        "mounts",
        "The engine on its mounts",
        part="balance.core.mount_loads:mounts_part",
        outputs="balance.core.mount_loads:OUTPUTS",
        layout_key="mounts",
        options=("with_proposal", "speeds"),
        figure_options=(("speeds", "figure"),),
    ),
    Section(
        "bearings",
        "Crank-pin and main-bearing loads",
        part="balance.core.bearing_loads:bearings_part",
        outputs="balance.core.bearing_loads:OUTPUTS",
        layout_key="bearings",
        options=("strategies",),
    ),
    Section(
        "torsion",
        "Torsional vibration of the crank train",
        part="balance.core.torsion:torsion_part",
        outputs="balance.core.torsion:OUTPUTS",
        layout_key="torsion",
        options=("speeds", "orders"),
        figure_options=(("speeds", "sweep"),),
    ),
)


@cache
def section(name: str) -> Section:
    """The section of this name.

    Parameters
    ----------
    name : str
        A section's name (``"proposal"``, ``"bearings"`` …).

    Returns
    -------
    Section

    Raises
    ------
    KeyError
        For a name that is no section, with the names that are.
    """
    for s in SECTIONS:
        if s.name == name:
            return s
    raise KeyError(f"{name!r} is no section; the sections are {', '.join(names())}")


def names() -> tuple[str, ...]:
    """The names of the sections, in order."""
    return tuple(s.name for s in SECTIONS)


def default_sections() -> dict[str, dict[str, Any]]:
    """What a request computes unless told otherwise: each default section, no options."""
    return {s.name: {} for s in SECTIONS if s.default}


@cache
def load(path: str) -> Any:
    """The object at ``"module:NAME"`` (imported on first use).

    Parameters
    ----------
    path : str
        ``"module:NAME"``, as :attr:`Section.part` and :attr:`Section.outputs` give it.

    Returns
    -------
    object
        The module's attribute ``NAME``.
    """
    module, _, name = path.partition(":")
    return getattr(import_module(module), name)
