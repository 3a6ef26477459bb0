"""The output catalogue: every quantity balance reports, declared once.

An :class:`Output` names a quantity, its dimensions, its unit, its ``long_name`` and how to
get its values from a result.  The Dataset view (:mod:`balance.views.dataset`), the sweep's
Dataset (:mod:`balance.studies.sweep`), and the JSON, CSV and table views read their
values through it, so that a single analysis and a sweep cannot drift apart.

:data:`BASE` holds the free forces, moments and roll of every analysis; each section
(:mod:`balance.core.sections`) declares its own outputs beside its physics.
:func:`outputs_of` gives the outputs of a result: the base ones and those of every part it
holds.  The values are numpy arrays (numbers in the unit declared, phases in degrees);
building xarray variables from them is the Dataset view's job.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from balance.core.phasors import phase_deg, safe_ratio
from balance.core.sections import SECTIONS, load, section
from balance.core.speed import rad_per_s_to_rpm

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.result import Result

__all__ = [
    "BASE",
    "CONVENTIONS",
    "SCHEMA",
    "Compared",
    "Output",
    "compared",
    "compared_sections",
    "outputs_of",
    "speed_rpm",
    "value",
]

#: Schema name of the analysis JSON and the result Dataset.
SCHEMA = "balance.analysis/1"

#: The frame and sign conventions, as the result Dataset's ``conventions`` attribute and
#: the report state them.
CONVENTIONS = (
    "balance conventions (docs/conventions.md): frame z crank axis, y up, angles from +y in the "
    "direction of rotation; (x, y) as y + i x"
)


@dataclass(frozen=True)
class Compared:
    """How a comparison of layouts (``balance compare``, docs/cli.md) shows a scalar output:
    one column, NaN (``-`` where printed) for a layout without it.

    Attributes
    ----------
    header : str
        Its column header, with its unit, in the comparison's CSV and Markdown tables.
    title : str
        Its column title in the comparison's terminal table (the unit is the output's
        ``units``).
    long_name : str
        Its ``long_name`` in the comparison's Dataset.
    """

    header: str
    title: str
    long_name: str


@dataclass(frozen=True)
class Output:
    """One reported quantity.

    Attributes
    ----------
    name : str
        Its name in the Dataset (and the root of its names in CSV and JSON).
    dims : tuple of str
        Its dimensions (a sweep puts its grid's in front).
    units : str
        Unit of the values (``"1"`` for ratios and numbers, ``"deg"`` for angles).
    long_name : str or callable
        What it is, or a function of the result that says so (a roll "with gas forces").
    get : callable
        ``get(result) -> array_like``: the values.
    kind : {'data', 'coord', 'attr'}
        A data variable, a coordinate, or an attribute of the Dataset (dims ``()``).
    per_variant : bool
        A sweep writes it too: ``get`` reads only the result's ``phasors`` and ``roll``,
        which a sweep's chunk holds with its grid's axes in front.
    when : callable or None
        ``when(result) -> bool``: whether the result has it (the moments when computed,
        the firing order when given); None: always.
    compare : Compared or None
        A scalar output that a comparison of layouts shows as a column of its own
        (:func:`compared`); None: not compared.
    """

    name: str
    dims: tuple[str, ...]
    units: str
    long_name: str | Callable[[Any], str]
    get: Callable[[Any], Any]
    kind: Literal["data", "coord", "attr"] = "data"
    per_variant: bool = False
    when: Callable[[Any], bool] | None = None
    compare: Compared | None = None

    def describe(self, result: Any) -> str:
        """The ``long_name`` for this result."""
        return self.long_name if isinstance(self.long_name, str) else self.long_name(result)

    def present(self, result: Any) -> bool:
        """Whether the result has this output."""
        return self.when is None or bool(self.when(result))


def speed_rpm(speed: float) -> float:
    """Crank speed in rpm as reported, to 12 significant digits (8000 rpm read from a file
    stays 8000, not 7999.999999999999).

    Parameters
    ----------
    speed : float
        Crank speed [rad/s].

    Returns
    -------
    float
        The speed [rpm].
    """
    return float(f"{rad_per_s_to_rpm(speed):.12g}")


def _moments(result: Any) -> bool:
    return result.phasors.has("moment")


def _roll(result: Any) -> bool:
    return result.roll is not None


def _gas(result: Any) -> str:
    return " with gas forces" if "torque" in result.parts else ""


def _phasor_outputs(quantity: Literal["force", "moment"]) -> tuple[Output, ...]:
    """Magnitude, phase, peak and their normalised values of a force or moment."""
    unit = "N" if quantity == "force" else "N m"
    about = "" if quantity == "force" else " about reference_z"
    per = "m_rec r omega^2" if quantity == "force" else "m_rec r omega^2 times cylinder pitch"
    when = None if quantity == "force" else _moments

    def reference(result: Any) -> float:
        return float(result.reference_force if quantity == "force" else result.reference_moment)

    name = f"reciprocating_{quantity}"
    rotating = f"rotating_{quantity}"
    return (
        Output(
            f"{name}_magnitude",
            ("order", "rotation"),
            unit,
            f"magnitude of the reciprocating inertia {quantity} phasor{about}",
            lambda r: r.phasors.magnitude(quantity),
            per_variant=True,
            when=when,
        ),
        Output(
            f"{name}_phase",
            ("order", "rotation"),
            "deg",
            f"phase of the reciprocating inertia {quantity} phasor at crank angle 0",
            lambda r: r.phasors.phase(quantity),
            when=when,
        ),
        Output(
            f"{name}_peak",
            ("order",),
            unit,
            f"peak reciprocating inertia {quantity} over a revolution",
            lambda r: r.phasors.peak(quantity),
            per_variant=True,
            when=when,
        ),
        Output(
            f"{name}_normalised",
            ("order", "rotation"),
            "1",
            f"reciprocating {quantity} phasor magnitude per {per}",
            lambda r: safe_ratio(r.phasors.magnitude(quantity), reference(r)),
            when=when,
        ),
        Output(
            f"{name}_peak_normalised",
            ("order",),
            "1",
            f"peak reciprocating {quantity} per {per}",
            lambda r: safe_ratio(r.phasors.peak(quantity), reference(r)),
            when=when,
        ),
        Output(
            f"{rotating}_magnitude",
            (),
            unit,
            f"magnitude of the rotating (centrifugal) {quantity}{about}, order 1 forward",
            lambda r: np.abs(r.phasors.rotating(quantity)),
            per_variant=True,
            when=when,
        ),
        Output(
            f"{rotating}_phase",
            (),
            "deg",
            f"phase of the rotating {quantity} at crank angle 0",
            lambda r: phase_deg(r.phasors.rotating(quantity)),
            when=when,
        ),
        Output(
            f"{rotating}_normalised",
            (),
            "1",
            f"rotating {quantity} per {per}",
            lambda r: safe_ratio(np.abs(r.phasors.rotating(quantity)), reference(r)),
            when=when,
        ),
    )


def _per_cylinder(name: str, attribute: str, units: str, long_name: str) -> Output:
    return Output(name, ("cylinder",), units, long_name, lambda r: getattr(r.engine, attribute))


def _attrs() -> tuple[Output, ...]:
    def attr(name: str, get: Callable[[Any], Any], **options: Any) -> Output:
        return Output(name, (), "", name, get, kind="attr", **options)

    return (
        attr("schema", lambda r: SCHEMA),
        attr("layout", lambda r: r.engine.name),
        attr("source_file", lambda r: r.engine.path or ""),
        attr("cycle", lambda r: r.engine.cycle),
        attr("model", lambda r: r.model.name),
        attr("series_terms", lambda r: r.model.terms if r.model.name == "series" else 0),
        attr("time_samples", lambda r: r.model.samples),
        attr("error_bound", lambda r: float(r.model.error_bound)),
        attr(
            "error_bound_note",
            lambda r: (
                "bound on the normalised acceleration coefficients (force error per "
                "m_rec r omega^2) of the model used; see balance.core.accuracy"
            ),
        ),
        attr("speed_rpm", lambda r: speed_rpm(r.engine.speed)),
        attr("conventions", lambda r: CONVENTIONS),
        attr(
            "firing_order",  # numbers as numbers: an integer array, absent when not given
            lambda r: np.asarray(r.engine.firing_order, dtype=np.int64),
            when=lambda r: bool(r.engine.firing_order),
        ),
    )


#: The outputs of every analysis: free forces, moments, rotating forces, roll, the
#: acceleration coefficients, the layout's cylinders and the references.
BASE: tuple[Output, ...] = (
    *_phasor_outputs("force"),
    *_phasor_outputs("moment"),
    Output(
        "roll_amplitude",
        ("roll_order",),
        "N m",
        lambda r: (
            f"amplitude of the roll torque on the block{_gas(r)} "
            "(sum of a_k cos(k theta + phase_k))"
        ),
        lambda r: np.abs(r.roll),
        per_variant=True,
        when=_roll,
    ),
    Output(
        "roll_phase",
        ("roll_order",),
        "deg",
        "phase of the roll torque, positive in the direction of rotation",
        lambda r: phase_deg(r.roll),
        when=_roll,
    ),
    Output(
        "roll_amplitude_normalised",
        ("roll_order",),
        "1",
        "roll torque amplitude per m_rec r^2 omega^2",
        lambda r: safe_ratio(np.abs(r.roll), r.reference_roll),
        when=_roll,
    ),
    Output(
        "piston_acceleration_cos",
        ("cylinder", "order"),
        "1",
        "a_k: cosine coefficient of -s''/r (normalised reciprocating inertia)",
        lambda r: r.coefficients.real,
    ),
    Output(
        "piston_acceleration_sin",
        ("cylinder", "order"),
        "1",
        "b_k: sine coefficient of -s''/r (normalised reciprocating inertia)",
        lambda r: -r.coefficients.imag,
    ),
    Output(
        "throw_angle",
        ("cylinder",),
        "deg",
        "crank throw angle from +y in the direction of rotation",
        lambda r: np.degrees(r.engine.throw),
    ),
    Output(
        "bank_angle",
        ("cylinder",),
        "deg",
        "bore axis direction from +y in the direction of rotation",
        lambda r: np.degrees(r.engine.bank),
    ),
    _per_cylinder("axial_position", "z", "m", "axial position of the throw plane"),
    _per_cylinder("crank_radius", "crank_radius", "m", "crank radius"),
    _per_cylinder("conrod_length", "conrod_length", "m", "conrod length"),
    _per_cylinder("offset", "offset", "m", "bore axis offset (desaxe)"),
    _per_cylinder(
        "reciprocating_mass", "reciprocating_mass", "kg", "reciprocating mass at the piston pin"
    ),
    _per_cylinder("rotating_mass", "rotating_mass", "kg", "rotating mass at the crank pin radius"),
    _per_cylinder(
        "conrod_inertia_correction",
        "conrod_inertia_correction",
        "kg m2",
        "conrod moment of inertia about its centre of gravity less its two-mass model's",
    ),
    Output("speed", (), "rad/s", "crank speed", lambda r: r.engine.speed),
    Output(
        "reference_z",
        (),
        "m",
        "axial position moments are taken about",
        lambda r: r.engine.reference_z,
    ),
    Output("pitch", (), "m", "cylinder pitch used to normalise moments", lambda r: r.pitch),
    Output(
        "reference_force", (), "N", "m_rec r omega^2 (engine means)", lambda r: r.reference_force
    ),
    Output(
        "reference_moment",
        (),
        "N m",
        "m_rec r omega^2 times cylinder pitch",
        lambda r: r.reference_moment,
    ),
    Output(
        "order",
        ("order",),
        "1",
        "harmonic order (multiple of crank speed)",
        lambda r: r.phasors.orders,
        kind="coord",
    ),
    Output(
        "rotation",
        ("rotation",),
        "1",
        "sense of rotation of the phasor relative to the crank",
        lambda r: ["forward", "backward"],
        kind="coord",
    ),
    Output(
        "roll_order",
        ("roll_order",),
        "1",
        "harmonic order of the roll torque",
        lambda r: r.roll_orders,
        kind="coord",
        when=_roll,
    ),
    Output(
        "cylinder",
        ("cylinder",),
        "1",
        "cylinder number",
        lambda r: np.arange(1, r.engine.n_cylinders + 1),
        kind="coord",
    ),
    *_attrs(),
)


def outputs_of(result: Result) -> Iterator[Output]:
    """The outputs a result has: :data:`BASE`, then each part's, in section order.

    Parameters
    ----------
    result : Result
        The result.

    Returns
    -------
    iterator of Output
        Each output present in the result (:meth:`Output.present`).
    """
    for output in BASE:
        if output.present(result):
            yield output
    for name in result.parts:
        for output in load(section(name).outputs):
            if output.present(result):
                yield output


def value(result: Result, name: str) -> Any:
    """The values of the output ``name`` of a result, as :attr:`Output.get` gives them.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`.
    name : str
        An output of the result (:func:`outputs_of`).

    Returns
    -------
    array_like
        Its values, in its ``units``.

    Raises
    ------
    KeyError
        For a name that is no output of the result.
    """
    for output in outputs_of(result):
        if output.name == name:
            return output.get(result)
    raise KeyError(f"{name!r} is no output of this result")


def compared_sections() -> tuple[str, ...]:
    """The sections with an output that a comparison of layouts shows (:func:`compared`).

    Returns
    -------
    tuple of str
        Section names, in section order.
    """
    return tuple(s.name for s in SECTIONS if any(o.compare is not None for o in load(s.outputs)))


def compared() -> tuple[Output, ...]:
    """The outputs a comparison of layouts shows as columns of their own (those with a
    :attr:`Output.compare`), of every section, in section order.

    Returns
    -------
    tuple of Output
        Scalar outputs (dims ``()``); a layout whose analysis has none of one shows NaN.
    """
    return tuple(
        output for s in SECTIONS for output in load(s.outputs) if output.compare is not None
    )
