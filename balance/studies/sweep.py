r"""Design-space sweeps: one analysis over a whole grid of layout variants.

A sweep varies numeric layout fields over given values and computes the free forces,
moments, rotating forces and roll of every combination.  Nothing loops over grid points in
Python: each varied field becomes an array with one grid dimension of its own (size one on
the others), these arrays broadcast against the per-cylinder arrays of the engine, and
:func:`balance.core.kinematics.acceleration_coefficients` and the
:mod:`balance.core.phasors` sums are called once per chunk.  The acceleration coefficients
are therefore computed once per distinct rod ratio and offset ratio, not once per variant.

Fields
------
Engine-wide fields set the value for every cylinder (replacing per-cylinder overrides):

========================================  =======  =====================================
field                                     kind     meaning
========================================  =======  =====================================
``speed``                                 speed    crank speed
``stroke`` (``geometry.stroke``)          length   twice the crank radius
``crank_radius``                          length   crank radius
``conrod_length``                         length   conrod length
``offset``                                length   desaxé offset
``reciprocating`` (``masses.…``)          mass     reciprocating mass per cylinder
``rotating`` (``masses.…``)               mass     rotating mass per cylinder
``reference_z``                           length   where moments are taken
========================================  =======  =====================================

(``geometry.`` and ``masses.`` prefixes are optional.)  One cylinder's field is written
``cylinders[3].reciprocating`` or ``cylinders.3.reciprocating`` (cylinders numbered from 1,
as in the layout file's error messages); per-cylinder fields are ``throw`` and ``bank``
(angles), ``z``, ``stroke``, ``crank_radius``, ``conrod_length``, ``offset`` (lengths),
``reciprocating`` and ``rotating`` (masses).  When the layout file gives no
``reference_z``, it stays midway between the outermost cylinders as their ``z`` vary.

Values
------
``start:stop:count`` with units on the ends (``130mm:160mm:31``: 31 values, both ends
included) or a list ``a,b,c`` (``0.4kg,0.5kg,0.7kg``); plain numbers are SI (degrees for
angles), as in layout files.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import kinematics
from balance.core.analysis import FreePhasors, free_phasors_of, speed_squared
from balance.core.engine import CYLINDER_FIELDS, Engine
from balance.core.errors import AnalysisError, InputError
from balance.core.masses import PART_FIELDS
from balance.io.fields import parse_orders

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

__all__ = [
    "DEFAULT_CHUNK_SIZE",
    "Field",
    "Vary",
    "check_output",
    "chunk_slices",
    "lumped_again",
    "parse_field",
    "parse_values",
    "parse_vary",
    "sweep",
    "sweep_arrays",
    "sweep_to_file",
    "variant",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Grid points per chunk by default (about 100 MB of temporaries for a V12 at orders 1-8).
DEFAULT_CHUNK_SIZE = 50_000

# field name -> (Engine attribute, unit kind); "parts.X" is a MassParts array
_CYLINDER_FIELDS: dict[str, tuple[str, str]] = {
    "throw": ("throw", "angle"),
    "bank": ("bank", "angle"),
    "z": ("z", "length"),
    "stroke": ("crank_radius", "length"),
    "crank_radius": ("crank_radius", "length"),
    "conrod_length": ("conrod_length", "length"),
    "offset": ("offset", "length"),
    "reciprocating": ("reciprocating_mass", "mass"),
    "rotating": ("rotating_mass", "mass"),
    "piston_group": ("parts.piston_group", "mass"),
    "conrod": ("parts.conrod", "mass"),
    "conrod_cg_to_big_end": ("parts.conrod_cg_to_big_end", "length"),
    "conrod_inertia": ("parts.conrod_inertia", "inertia"),
    "crank_unbalance": ("parts.crank_unbalance", "mass"),
}
# engine-wide: the speed, every per-cylinder field but the crank's own angles and
# positions, and where moments are taken
_ENGINE_FIELDS: dict[str, tuple[str, str]] = {
    "speed": ("speed", "speed"),
    **{k: v for k, v in _CYLINDER_FIELDS.items() if k not in {"throw", "bank", "z"}},
    "reference_z": ("reference_z", "length"),
}
_SECTION = {
    "geometry": {"stroke", "crank_radius", "conrod_length", "offset"},
    "masses": {"reciprocating", "rotating", *PART_FIELDS},
}
_UNITS = {"speed": "rad/s", "length": "m", "mass": "kg", "angle": "deg", "inertia": "kg m^2"}
_LUMPED = {"reciprocating_mass", "rotating_mass"}
_CYLINDER = re.compile(r"^cylinders(?:\[(\d+)\]|\.(\d+))\.([a-z_]+)$")
_MAX_POINTS = 10**12


@dataclass(frozen=True)
class Field:
    """A numeric layout field that a sweep or a tolerance study may change.

    Attributes
    ----------
    text : str
        The field as the user wrote it.
    name : str
        A canonical name, usable as a dimension name (``conrod_length``,
        ``cylinder3_reciprocating``).
    attribute : str
        The :class:`~balance.io.layout_file.Layout` attribute it sets.
    kind : str
        Unit kind (:data:`balance.io.units.KINDS`): ``speed``, ``length``, ``mass``, ``angle``.
    key : str
        The field's own name (``stroke``, ``throw``...).
    cylinder : int or None
        0-based index of the cylinder, or None for every cylinder.
    """

    text: str
    name: str
    attribute: str
    kind: str
    key: str
    cylinder: int | None = None

    @property
    def unit(self) -> str:
        """SI unit of the values (degrees for angles)."""
        return _UNITS[self.kind]

    def to_layout_units(self, values: ArrayLike) -> FloatArray:
        """Values in the unit of the Engine attribute (radians for angles, radius for stroke)."""
        v = np.asarray(values, dtype=np.float64)
        if self.kind == "angle":
            return np.radians(v)
        if self.key == "stroke":
            return v / 2
        return v


def _valid_fields() -> str:
    return (
        f"valid: {', '.join(_ENGINE_FIELDS)}, or cylinders[N].FIELD with FIELD one of "
        f"{', '.join(_CYLINDER_FIELDS)}"
    )


def parse_field(text: str, layout: Engine, option: str = "--vary") -> Field:
    """Read a field name (see the module notes).

    Raises
    ------
    InputError
        If there is no such numeric field, or the cylinder does not exist.
    """
    import difflib

    name = text.strip()
    match = _CYLINDER.match(name)
    if match:
        number = int(match.group(1) or match.group(2))
        key = match.group(3)
        if key not in _CYLINDER_FIELDS:
            hint = difflib.get_close_matches(key, list(_CYLINDER_FIELDS), n=1)
            more = f"did you mean '{hint[0]}'? " if hint else ""
            raise InputError(
                f"{option}: '{name}' is not a numeric per-cylinder field; {more}"
                f"valid: {', '.join(_CYLINDER_FIELDS)}"
            )
        if not 1 <= number <= layout.n_cylinders:
            raise InputError(
                f"{option}: '{name}': the layout has cylinders 1 to {layout.n_cylinders}"
            )
        attribute, kind = _CYLINDER_FIELDS[key]
        _check_parts(layout, attribute, name, option)
        return Field(name, f"cylinder{number}_{key}", attribute, kind, key, number - 1)
    key = name
    for section, keys in _SECTION.items():
        if name.startswith(section + "."):
            key = name[len(section) + 1 :]
            if key not in keys:
                key = "?"
    if key not in _ENGINE_FIELDS:
        hint = difflib.get_close_matches(
            name, [*_ENGINE_FIELDS, "masses.reciprocating", "geometry.conrod_length"], n=1
        )
        more = f"did you mean '{hint[0]}'? " if hint else ""
        raise InputError(
            f"{option}: '{name}' is not a numeric layout field; {more}{_valid_fields()}"
        )
    attribute, kind = _ENGINE_FIELDS[key]
    _check_parts(layout, attribute, name, option)
    return Field(name, key, attribute, kind, key, None)


def _check_parts(layout: Engine, attribute: str, name: str, option: str) -> None:
    if attribute.startswith("parts.") and layout.mass_parts is None:
        raise InputError(
            f"{option}: '{name}' is a part of the moving masses, but this layout gives them "
            "lumped; vary masses.reciprocating or masses.rotating"
        )


def _quantity(text: str, field: Field, option: str) -> float:
    from balance.io.units import UnitProblem, parse_quantity

    try:
        return parse_quantity(text.strip(), field.kind)
    except UnitProblem as exc:
        raise InputError(f"{option}: {field.text}: {exc}; {exc.valid}") from None


def parse_values(text: str, field: Field, option: str = "--vary") -> FloatArray:
    """Values of a field from ``start:stop:count`` or ``a,b,c`` (SI, degrees for angles).

    Raises
    ------
    InputError
        If the range or list is malformed or a value has the wrong unit.
    """
    spec = text.strip()
    if not spec:
        raise InputError(f"{option}: {field.text}: no values; write start:stop:count or a,b,c")
    if ":" in spec:
        parts = spec.split(":")
        if len(parts) != 3 or not all(p.strip() for p in parts):
            raise InputError(
                f"{option}: {field.text}: cannot read range {spec!r}; write start:stop:count, "
                "e.g. 130mm:160mm:31"
            )
        start = _quantity(parts[0], field, option)
        stop = _quantity(parts[1], field, option)
        try:
            count = int(parts[2])
        except ValueError:
            count = 0
        if count < 1 or str(count) != parts[2].strip():
            raise InputError(
                f"{option}: {field.text}: count {parts[2].strip()!r} is not a whole number above 0"
            )
        if count == 1 and start != stop:
            raise InputError(f"{option}: {field.text}: one value from {start} to {stop}?")
        values = np.linspace(start, stop, count)
    else:
        values = np.array([_quantity(p, field, option) for p in spec.split(",")])
    return values


@dataclass(frozen=True)
class Vary:
    """One varied field and its values (SI, degrees for angles)."""

    field: Field
    values: FloatArray

    @property
    def dim(self) -> str:
        """The grid dimension's name."""
        return self.field.name


def parse_vary(text: str, layout: Engine) -> Vary:
    """Read ``FIELD=VALUES`` (see :func:`parse_field`, :func:`parse_values`)."""
    if "=" not in text:
        raise InputError(
            f"--vary: cannot read {text!r}; write FIELD=start:stop:count, e.g. "
            "conrod_length=130mm:160mm:31"
        )
    name, _, spec = text.partition("=")
    field = parse_field(name, layout)
    return Vary(field, parse_values(spec, field))


def _as_varies(layout: Engine, vary: Mapping[str, Any] | Sequence[Vary | str]) -> list[Vary]:
    out: list[Vary] = []
    if isinstance(vary, Mapping):
        for name, values in vary.items():
            field = parse_field(name, layout)
            if isinstance(values, str):
                out.append(Vary(field, parse_values(values, field)))
            else:
                out.append(Vary(field, np.atleast_1d(np.asarray(values, dtype=np.float64))))
    else:
        out = [v if isinstance(v, Vary) else parse_vary(v, layout) for v in vary]
    names = [v.dim for v in out]
    for name in names:
        if names.count(name) > 1:
            raise InputError(f"--vary: {name} is varied twice; give it once")
    if not out:
        raise InputError("--vary: give at least one field to vary")
    for v in out:
        if v.values.ndim != 1 or v.values.size == 0 or not np.all(np.isfinite(v.values)):
            raise InputError(f"--vary: {v.field.text}: values must be finite numbers")
        _check_values(v)
    total = math.prod(v.values.size for v in out)
    if total > _MAX_POINTS:
        raise InputError(f"--vary: {total:.3g} grid points; at most {_MAX_POINTS:.0e}")
    return out


def _check_values(v: Vary) -> None:
    low = float(v.values.min())
    key = v.field.key
    positive = {"speed", "stroke", "crank_radius", "conrod_length"}
    if key in positive and low <= 0:
        raise InputError(f"--vary: {v.field.text}: values must be above zero, got {low:g}")
    if key in {"reciprocating", "rotating"} and low < 0:
        raise InputError(f"--vary: {v.field.text}: masses cannot be negative, got {low:g}")


def variant(layout: Engine, values: Mapping[str, float]) -> Engine:
    """The layout with some fields set (SI values, degrees for angles), as a sweep sees it.

    Parameters
    ----------
    layout : Engine
        The base layout.
    values : mapping of str to float
        Field name (see the module notes) to value.

    Returns
    -------
    Engine
        As loading the layout file with those values written in would give it: for masses
        given by part, a changed part or conrod length is lumped again
        (:func:`balance.core.masses.two_mass_split`), and a lumped mass set here wins over the
        parts; ``reference_z`` is re-centred when the file gives none and a ``z`` changes.
    """
    changes: dict[str, Any] = {}
    parts: dict[str, FloatArray] = {}
    lumped: list[tuple[Field, float]] = []
    relump = False
    for name, value in values.items():
        field = parse_field(name, layout)
        v = float(field.to_layout_units(value))
        attribute = field.attribute
        if attribute in {"speed", "reference_z"}:
            changes[attribute] = v
        elif attribute in _LUMPED:
            lumped.append((field, v))
        elif attribute.startswith("parts."):
            key = attribute.removeprefix("parts.")
            assert layout.mass_parts is not None
            parts[key] = _set_one(parts.get(key, getattr(layout.mass_parts, key)), field, v)
            relump = True
        else:
            changes[attribute] = _set_one(
                changes.get(attribute, getattr(layout, attribute)), field, v
            )
            relump |= attribute == "conrod_length" and layout.mass_parts is not None
    if relump:
        assert layout.mass_parts is not None
        mass_parts = replace(layout.mass_parts, **parts)
        length = changes.get("conrod_length", layout.conrod_length)
        rec, rot, correction = lumped_again(layout, length, parts, _CG_BEYOND_ROD)
        changes.update(
            reciprocating_mass=rec,
            rotating_mass=rot,
            conrod_inertia_correction=correction,
            mass_parts=mass_parts,
        )
    for field, v in lumped:
        changes[field.attribute] = _set_one(
            changes.get(field.attribute, getattr(layout, field.attribute)), field, v
        )
        if layout.mass_parts is not None:
            given = field.attribute.replace("_mass", "_given")
            parts_now = changes.get("mass_parts", layout.mass_parts)
            changes["mass_parts"] = replace(
                parts_now, **{given: _set_one(getattr(parts_now, given), field, v)}
            )
    if "reference_z" not in changes and "z" in changes and _auto_reference(layout):
        z = changes["z"]
        changes["reference_z"] = float(0.5 * (z.min() + z.max()))
    return replace(layout, **changes)


def lumped_again(
    layout: Engine, conrod_length: ArrayLike, parts: Mapping[str, ArrayLike], problem: str
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Lumped masses of a by-part layout with some parts (arrays that broadcast) or the
    conrod length changed, as loading the file would give them.

    Raises
    ------
    InputError
        With the message ``problem`` where a conrod's centre of gravity would lie beyond
        its small end.
    """
    assert layout.mass_parts is not None
    cg = parts.get("conrod_cg_to_big_end", layout.mass_parts.conrod_cg_to_big_end)
    if np.any(np.asarray(cg) > np.asarray(conrod_length)):
        raise InputError(problem)
    return layout.mass_parts.lumped(conrod_length, parts)


_CG_BEYOND_ROD = (
    "--vary: the conrod's centre of gravity would lie beyond its small end "
    "(conrod_cg_to_big_end > conrod_length); keep it between the two ends"
)


def _set_one(array: FloatArray, field: Field, value: float) -> FloatArray:
    """A copy of a per-cylinder array with one cylinder's (or every cylinder's) value set."""
    out = np.array(array, dtype=np.float64)
    if field.cylinder is None:
        out[:] = value
    else:
        out[field.cylinder] = value
    return out


def _auto_reference(layout: Engine) -> bool:
    return not layout.reference_z_given


# ---------------------------------------------------------------------------------------
# the grid and its chunks


def chunk_slices(shape: Sequence[int], chunk_size: int) -> list[tuple[slice, ...]]:
    """Split a grid into hyper-rectangular chunks of at most ``chunk_size`` points.

    The trailing dimensions are kept whole as far as they fit; the first dimension that
    does not fit is cut into slabs and the ones before it are taken one index at a time.
    Every chunk is therefore itself a grid, so the varied fields keep their broadcast
    (outer-product) structure inside it.
    """
    shape = tuple(int(s) for s in shape)
    size = max(int(chunk_size), 1)
    j = 0
    while j < len(shape) and math.prod(shape[j + 1 :]) > size:
        j += 1
    if j == len(shape):  # pragma: no cover - only for an empty shape
        return [tuple(slice(0, s) for s in shape)]
    inner = math.prod(shape[j + 1 :])
    step = max(size // inner, 1)
    chunks = []
    for outer in np.ndindex(*shape[:j]):
        for start in range(0, shape[j], step):
            chunks.append(
                (
                    *tuple(slice(i, i + 1) for i in outer),
                    slice(start, min(start + step, shape[j])),
                    *tuple(slice(0, s) for s in shape[j + 1 :]),
                )
            )
    return chunks


@dataclass(frozen=True)
class _Plan:
    """Everything a chunk needs (picklable, for Dask workers)."""

    layout: Engine
    varies: tuple[Vary, ...]
    orders: NDArray[np.intp]
    model: str
    terms: int
    moments: bool
    roll: bool

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(v.values.size for v in self.varies)

    @property
    def dims(self) -> tuple[str, ...]:
        return tuple(v.dim for v in self.varies)


def _grid_parameters(plan: _Plan, where: tuple[slice, ...]) -> dict[str, Any]:
    """Engine arrays for one chunk: grid dims leading, cylinders last; broadcastable.

    The same rules as :func:`variant`, over a grid: parts and conrod lengths are lumped
    again for a by-part layout, then the varied lumped masses are set.
    """
    layout = plan.layout
    ndim = len(plan.varies)
    params: dict[str, Any] = {name: getattr(layout, name) for name in CYLINDER_FIELDS}
    params["speed"] = np.float64(layout.speed)
    params["reference_z"] = np.float64(layout.reference_z)
    n = layout.n_cylinders
    parts: dict[str, Any] = {}
    lumped: list[tuple[Field, FloatArray]] = []
    relump = False

    def put(base: Any, field: Field, column: FloatArray) -> Any:
        if field.cylinder is None:
            return np.broadcast_to(column, np.broadcast_shapes(column.shape, np.shape(base)))
        return np.where(np.arange(n) == field.cylinder, column, base)

    for axis, (v, sl) in enumerate(zip(plan.varies, where, strict=True)):
        values = v.field.to_layout_units(v.values[sl])
        shape = [1] * ndim
        shape[axis] = values.size
        column = np.reshape(values, (*shape, 1))
        f = v.field
        if f.attribute in {"speed", "reference_z"}:
            params[f.attribute] = column
        elif f.attribute in _LUMPED:
            lumped.append((f, column))
        elif f.attribute.startswith("parts."):
            key = f.attribute.removeprefix("parts.")
            parts[key] = put(parts.get(key, getattr(layout.mass_parts, key)), f, column)
            relump = True
        else:
            params[f.attribute] = put(params[f.attribute], f, column)
            relump |= f.attribute == "conrod_length" and layout.mass_parts is not None
    if relump:
        rec, rot, correction = lumped_again(layout, params["conrod_length"], parts, _CG_BEYOND_ROD)
        params["reciprocating_mass"] = rec
        params["rotating_mass"] = rot
        params["conrod_inertia_correction"] = correction
    for f, column in lumped:
        params[f.attribute] = put(params[f.attribute], f, column)
    if _auto_reference(layout) and any(v.field.attribute == "z" for v in plan.varies):
        z = params["z"]
        params["reference_z"] = 0.5 * (z.min(axis=-1) + z.max(axis=-1))[..., None]
    return params


def _unit_phasors(plan: _Plan, p: dict[str, Any]) -> FreePhasors:
    """The unit-speed phasor sums over a chunk's grid of the fields other than speed."""
    try:
        return free_phasors_of(
            p,
            p["z"] - p["reference_z"],
            plan.orders,
            model=plan.model,
            terms=plan.terms,
            moments=plan.moments,
            roll=plan.roll,
        )
    except AnalysisError as exc:
        raise InputError(f"--vary: some grid points have an impossible geometry: {exc}") from None


def _chunk(
    plan: _Plan, where: tuple[slice, ...], cache: dict[Any, FreePhasors] | None = None
) -> dict[str, FloatArray]:
    r"""The sweep's variables over one chunk of the grid (full chunk shape leading).

    The phasor sums are formed by :func:`balance.core.analysis.free_phasors` at unit speed over
    the grid of the other fields and then multiplied by :math:`\omega^2`, exactly as
    :func:`balance.core.analysis.compute` does for one engine: a varied speed costs one
    multiplication per grid point and order, and every value is the one ``analyse`` gives.
    With a ``cache``, chunks that differ only in their speeds share those sums (the
    in-process run keeps the last ones).
    """
    p = _grid_parameters(plan, where)
    ks = plan.orders
    chunk_shape = tuple(s.stop - s.start for s in where)
    key = tuple(
        (s.start, s.stop)
        for v, s in zip(plan.varies, where, strict=True)
        if v.field.attribute != "speed"
    )
    unit = cache.get(key) if cache is not None else None
    if unit is None:
        unit = _unit_phasors(plan, p)
        if cache is not None:
            cache.clear()
            cache[key] = unit
    values = unit.scaled(speed_squared(p["speed"]))

    def magnitude(name: str) -> FloatArray:
        value = values[name]
        assert value is not None
        return np.abs(value)

    def full(a: FloatArray, tail: tuple[int, ...] = ()) -> FloatArray:
        lead = a.shape[: a.ndim - len(tail)]
        lead = (1,) * (len(chunk_shape) - len(lead)) + lead
        return np.ascontiguousarray(
            np.broadcast_to(a.reshape(lead + tail), chunk_shape + tail), dtype=np.float64
        )

    K = ks.size
    out: dict[str, FloatArray] = {}
    pairs = [("force", "reciprocating_force")]
    if plan.moments:
        pairs.append(("moment", "reciprocating_moment"))
    for what, name in pairs:
        forward = magnitude(f"{what}_forward")
        backward = magnitude(f"{what}_backward")
        out[f"{name}_magnitude"] = full(np.stack([forward, backward], axis=-1), (K, 2))
        out[f"{name}_peak"] = full(forward + backward, (K,))
        out[f"rotating_{what}_magnitude"] = full(magnitude(f"rotating_{what}"))
    if plan.roll:
        out["roll_amplitude"] = full(magnitude("roll"), (K,))
    return out


# variable -> (trailing dims, units, long_name)
_VARIABLES: dict[str, tuple[tuple[str, ...], str, str]] = {
    "reciprocating_force_magnitude": (
        ("order", "rotation"),
        "N",
        "magnitude of the reciprocating inertia force phasor",
    ),
    "reciprocating_force_peak": (
        ("order",),
        "N",
        "peak reciprocating inertia force over a revolution",
    ),
    "rotating_force_magnitude": (
        (),
        "N",
        "magnitude of the rotating (centrifugal) force, order 1 forward",
    ),
    "reciprocating_moment_magnitude": (
        ("order", "rotation"),
        "N m",
        "magnitude of the reciprocating inertia moment phasor about reference_z",
    ),
    "reciprocating_moment_peak": (
        ("order",),
        "N m",
        "peak reciprocating inertia moment over a revolution",
    ),
    "rotating_moment_magnitude": (
        (),
        "N m",
        "magnitude of the rotating (centrifugal) moment about reference_z, order 1 forward",
    ),
    "roll_amplitude": (
        ("roll_order",),
        "N m",
        "amplitude of the roll torque on the block",
    ),
}


def _plan(
    layout: Engine,
    vary: Mapping[str, Any] | Sequence[Vary | str],
    orders: int | str | Sequence[int] | None,
    model: str,
    terms: int,
    moments: bool,
    roll: bool,
) -> _Plan:
    if model not in kinematics.MODELS:
        raise InputError(f"--model: {model!r}; a sweep uses one of {', '.join(kinematics.MODELS)}")
    ks = parse_orders(orders)
    return _Plan(layout, tuple(_as_varies(layout, vary)), ks, model, terms, moments, roll)


def _variables(plan: _Plan) -> list[str]:
    names = [
        "reciprocating_force_magnitude",
        "reciprocating_force_peak",
        "rotating_force_magnitude",
    ]
    if plan.moments:
        names += [
            "reciprocating_moment_magnitude",
            "reciprocating_moment_peak",
            "rotating_moment_magnitude",
        ]
    if plan.roll:
        names.append("roll_amplitude")
    return names


def _coords(plan: _Plan) -> dict[str, tuple[tuple[str, ...], Any, dict[str, str]]]:
    coords: dict[str, tuple[tuple[str, ...], Any, dict[str, str]]] = {}
    for v in plan.varies:
        coords[v.dim] = (
            (v.dim,),
            v.values,
            {"units": v.field.unit, "long_name": f"varied field {v.field.text}"},
        )
    coords["order"] = (("order",), plan.orders, {"long_name": "harmonic order", "units": "1"})
    coords["rotation"] = (
        ("rotation",),
        np.array(["forward", "backward"]),
        {"long_name": "sense of rotation of the phasor relative to the crank", "units": "1"},
    )
    if plan.roll:
        coords["roll_order"] = (
            ("roll_order",),
            plan.orders.astype(np.float64),
            {"long_name": "harmonic order of the roll torque", "units": "1"},
        )
    return coords


def _attrs(plan: _Plan) -> dict[str, Any]:
    from balance._version import __version__

    return {
        "schema": "balance.sweep/1",
        "layout": plan.layout.name,
        "source_file": plan.layout.path or "",
        "model": plan.model,
        "varied_fields": ";".join(v.field.text for v in plan.varies),
        "speed_rpm": float(f"{plan.layout.speed * 60.0 / (2.0 * math.pi):.12g}"),
        "balance_version": __version__,
        "conventions": "balance CONTRACT; values of every analysis as 'balance analyse' gives "
        "them for the layout with the varied fields set",
    }


def _run_chunks(
    plan: _Plan,
    chunks: list[tuple[slice, ...]],
    client: Any,
    progress: bool,
) -> Iterator[tuple[tuple[slice, ...], dict[str, FloatArray]]]:
    """Results chunk by chunk, in-process or on a Dask client (in order of completion)."""
    bar = _Progress(progress, math.prod(plan.shape))
    with bar:
        if client is None:
            cache: dict[Any, FreePhasors] = {}
            for where in chunks:
                result = _chunk(plan, where, cache)
                bar.advance(where)
                yield where, result
            return
        from distributed import as_completed

        plan_future = client.scatter(plan, broadcast=True)
        futures = {client.submit(_chunk, plan_future, where, pure=False): where for where in chunks}
        for future in as_completed(list(futures)):
            where = futures.pop(future)
            result = future.result()
            future.release()
            bar.advance(where)
            yield where, result


class _Progress:
    """A rich progress bar on stderr (or nothing)."""

    def __init__(self, show: bool, total: int) -> None:
        self.show = show
        self.total = total
        self._bar: Any = None
        self._task: Any = None

    def __enter__(self) -> _Progress:
        if self.show:
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeRemainingColumn,
            )

            self._bar = Progress(
                TextColumn("sweep"),
                BarColumn(),
                MofNCompleteColumn(),
                TimeRemainingColumn(),
                console=Console(stderr=True),
                transient=True,
            )
            self._bar.__enter__()
            self._task = self._bar.add_task("sweep", total=self.total)
        return self

    def advance(self, where: tuple[slice, ...]) -> None:
        if self._bar is not None:
            self._bar.advance(self._task, math.prod(s.stop - s.start for s in where))

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._bar.__exit__(*exc)


def sweep_arrays(
    layout: Engine,
    vary: Mapping[str, Any] | Sequence[Vary | str],
    orders: int | str | Sequence[int] | None = None,
    *,
    model: str = "exact",
    terms: int = 3,
    moments: bool = True,
    roll: bool = True,
    chunk_size: int = DEFAULT_CHUNK_SIZE,
    client: Any = None,
    progress: bool = False,
    sink: Callable[[tuple[slice, ...], dict[str, FloatArray]], None] | None = None,
) -> tuple[_Plan, dict[str, FloatArray] | None]:
    """Run a sweep chunk by chunk; hand each chunk to ``sink`` or gather it in memory.

    Returns the plan and, without a sink, the full arrays.  See :func:`sweep`.
    """
    plan = _plan(layout, vary, orders, model, terms, moments, roll)
    chunks = chunk_slices(plan.shape, chunk_size)
    K = plan.orders.size
    tails = {"order": K, "rotation": 2, "roll_order": K}
    arrays: dict[str, FloatArray] | None = None
    if sink is None:
        arrays = {
            name: np.empty(plan.shape + tuple(tails[d] for d in _VARIABLES[name][0]))
            for name in _variables(plan)
        }
    for where, result in _run_chunks(plan, chunks, client, progress):
        if sink is not None:
            sink(where, result)
        else:
            assert arrays is not None
            for name, values in result.items():
                arrays[name][where] = values
    return plan, arrays


def _options(
    model: str,
    terms: int,
    moments: bool,
    roll: bool,
    chunk_size: int,
    client: Any,
    progress: bool,
) -> dict[str, Any]:
    """The keyword arguments that :func:`sweep` and :func:`sweep_to_file` pass on."""
    return {
        "model": model,
        "terms": terms,
        "moments": moments,
        "roll": roll,
        "chunk_size": chunk_size,
        "client": client,
        "progress": progress,
    }


def sweep(
    layout: Engine,
    vary: Mapping[str, Any] | Sequence[Vary | str],
    orders: int | str | Sequence[int] | None = None,
    *,
    model: str = "exact",
    terms: int = 3,
    moments: bool = True,
    roll: bool = True,
    chunk_size: int = DEFAULT_CHUNK_SIZE,
    client: Any = None,
    progress: bool = False,
) -> xr.Dataset:
    """Analyse every combination of the varied fields' values.

    Parameters
    ----------
    layout : Engine
        The base layout.
    vary : mapping or sequence
        ``{field: values}`` with values an array (SI, degrees for angles) or text such as
        ``"130mm:160mm:31"``; or a sequence of ``"field=values"`` strings or :class:`Vary`.
        Each becomes a dimension of the result, in the order given.
    orders : int, str or sequence of int, optional
        Orders (default 1 to 8).
    model : {'exact', 'series', 'textbook'}
        Piston acceleration model.
    terms : int
        Terms of the ``series`` model.
    moments, roll : bool
        Compute the moments and the roll torque.
    chunk_size : int
        Grid points per chunk; memory is proportional to it.
    client : distributed.Client, optional
        Run the chunks on this Dask client; the result is bit for bit the same.
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    xarray.Dataset
        One dimension per varied field, then ``order``, ``rotation`` and ``roll_order``;
        variables named as in :func:`balance.analyse` (forces [N], moments [N m]).
        Every value equals the one :func:`balance.analyse` gives for :func:`variant` of
        the layout at that grid point to 1e-12 relative (sums over cylinders may be
        reduced in another order, and speed and engine-wide masses are factored out);
        values that cancel by symmetry are exactly 0 in both.
    """
    import xarray as xr

    options = _options(model, terms, moments, roll, chunk_size, client, progress)
    plan, arrays = sweep_arrays(layout, vary, orders, **options)
    assert arrays is not None
    data = {
        name: (
            plan.dims + _VARIABLES[name][0],
            values,
            {"units": _VARIABLES[name][1], "long_name": _VARIABLES[name][2]},
        )
        for name, values in arrays.items()
    }
    return xr.Dataset(data_vars=data, coords=_coords(plan), attrs=_attrs(plan))


#: Output formats of :func:`sweep_to_file`, by file name suffix.
FORMATS = {".nc": "netcdf", ".nc4": "netcdf", ".zarr": "zarr"}


def sweep_to_file(
    layout: Engine,
    vary: Mapping[str, Any] | Sequence[Vary | str],
    path: str | Path,
    orders: int | str | Sequence[int] | None = None,
    *,
    model: str = "exact",
    terms: int = 3,
    moments: bool = True,
    roll: bool = True,
    chunk_size: int = DEFAULT_CHUNK_SIZE,
    client: Any = None,
    progress: bool = False,
    force: bool = False,
    file_format: str | None = None,
) -> Path:
    """Run a sweep and write it chunk by chunk to netCDF-4 or Zarr (see :func:`sweep`).

    Parameters
    ----------
    path : str or Path
        The output: a ``.nc`` file or a ``.zarr`` directory store (Zarr format 3,
        consolidated metadata, one Zarr chunk per sweep chunk).
    file_format : {'netcdf', 'zarr'}, optional
        Instead of the suffix.

    Notes
    -----
    Only one chunk's results are in memory at a time; the output appears complete or not
    at all (:mod:`balance.io.atomic`).  It opens with ``xarray.open_dataset`` (netCDF) or
    ``xarray.open_zarr`` as the same Dataset :func:`sweep` returns, bit for bit.
    """
    target = Path(path)
    fmt = check_output(target, force, file_format)
    plan = _plan(layout, vary, orders, model, terms, moments, roll)
    chunks = chunk_slices(plan.shape, chunk_size)

    options = _options(model, terms, moments, roll, chunk_size, client, progress)

    def run(sink: Callable[[tuple[slice, ...], dict[str, FloatArray]], None]) -> None:
        sweep_arrays(layout, plan.varies, [int(k) for k in plan.orders], sink=sink, **options)

    if fmt == "zarr":
        return _write_zarr(plan, chunks, target, run, force)
    return _write_netcdf(plan, target, run, force)


def check_output(path: str | Path, force: bool = False, file_format: str | None = None) -> str:
    """Check a sweep's output before the work starts; return its format.

    Raises
    ------
    InputError
        For an unknown suffix, a missing ``zarr`` package, or a target that cannot be
        written (:mod:`balance.io.atomic`).
    """
    from balance.io.atomic import check_directory_target, check_target

    target = Path(path)
    fmt = file_format or FORMATS.get(target.suffix.lower())
    if fmt not in {"netcdf", "zarr"}:
        raise InputError(
            f"{target}: cannot tell the format from the suffix {target.suffix!r}; "
            "name it .nc (netCDF) or .zarr (Zarr)"
        )
    if fmt == "zarr":
        import importlib.util

        if importlib.util.find_spec("zarr") is None:
            raise InputError(
                f"{target}: writing Zarr needs the zarr package; install balance[zarr] "
                "(pip install 'balance[zarr]') or write netCDF (.nc)"
            )
        check_directory_target(target, force, _is_zarr_store)
    else:
        check_target(target, force)
    return fmt


_Runner = Callable[[Callable[[tuple[slice, ...], dict[str, FloatArray]], None]], None]


def _write_netcdf(plan: _Plan, target: Path, run: _Runner, force: bool) -> Path:
    import netCDF4

    from balance.io.atomic import write_atomic

    def write(tmp: Path) -> None:
        with netCDF4.Dataset(tmp, "w", format="NETCDF4") as nc:
            for key, value in _attrs(plan).items():
                nc.setncattr(key, value)
            for name, (dims, values, attrs) in _coords(plan).items():
                nc.createDimension(name, len(values))
                if values.dtype.kind in "US":
                    var = nc.createVariable(name, str, dims)
                    for i, text in enumerate(values):
                        var[i] = str(text)
                else:
                    var = nc.createVariable(name, values.dtype, dims)
                    var[:] = values
                var.setncatts(attrs)
            variables = {}
            for name in _variables(plan):
                tail, units, long_name = _VARIABLES[name]
                var = nc.createVariable(name, "f8", plan.dims + tail)
                var.setncatts({"units": units, "long_name": long_name})
                var.set_auto_mask(False)
                variables[name] = var

            def sink(where: tuple[slice, ...], result: dict[str, FloatArray]) -> None:
                for key, values in result.items():
                    variables[key][where] = values

            run(sink)

    return write_atomic(target, write, force=force)


def _is_zarr_store(path: Path) -> bool:
    return (path / "zarr.json").is_file() or (path / ".zgroup").is_file()


def _write_zarr(
    plan: _Plan, chunks: list[tuple[slice, ...]], target: Path, run: _Runner, force: bool
) -> Path:
    import warnings

    import zarr

    from balance.io.atomic import write_atomic_directory

    K = plan.orders.size
    tails = {"order": K, "rotation": 2, "roll_order": K}
    grid_chunk = tuple(s.stop - s.start for s in chunks[0])

    def write(tmp: Path) -> None:
        group = zarr.open_group(tmp, mode="w", zarr_format=3)
        group.attrs.update(_attrs(plan))
        for name, (dims, values, attrs) in _coords(plan).items():
            data = values.astype(object) if values.dtype.kind in "US" else values
            array = group.create_array(
                name,
                shape=data.shape,
                dtype=str if data.dtype == object else data.dtype,
                dimension_names=dims,
                attributes=dict[str, Any](attrs),
            )
            array[:] = data
        arrays = {}
        for name in _variables(plan):
            tail, units, long_name = _VARIABLES[name]
            tail_shape = tuple(tails[d] for d in tail)
            arrays[name] = group.create_array(
                name,
                shape=plan.shape + tail_shape,
                chunks=grid_chunk + tail_shape,
                dtype="f8",
                fill_value=np.nan,
                dimension_names=plan.dims + tail,
                attributes={"units": units, "long_name": long_name},
            )

        def sink(where: tuple[slice, ...], result: dict[str, FloatArray]) -> None:
            for key, values in result.items():
                arrays[key][where] = values

        run(sink)
        with warnings.catch_warnings():
            # consolidated metadata is what xarray.open_zarr looks for first; zarr warns
            # that it is not yet part of the Zarr 3 specification
            warnings.filterwarnings("ignore", message="Consolidated metadata")
            zarr.consolidate_metadata(tmp)

    return write_atomic_directory(target, write, force=force, is_replaceable=_is_zarr_store)
