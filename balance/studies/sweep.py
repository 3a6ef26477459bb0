r"""Design-space sweeps: one analysis over a whole grid of layout variants.

A sweep varies numeric layout fields over given values and computes the free forces,
moments, rotating forces and roll of every combination.  Nothing loops over grid points in
Python: each varied field becomes an array with one grid dimension of its own (size one on
the others), these arrays broadcast against the per-cylinder arrays of the engine, and
:func:`balance.core.kinematics.acceleration_coefficients` and the
:mod:`balance.core.phasors` sums are called once per chunk.  The acceleration coefficients
are therefore computed once per distinct rod ratio and offset ratio, not once per variant.

The fields and their values are written as :mod:`balance.io.fields` describes
(``conrod_length=130mm:160mm:31``, ``cylinders[3].reciprocating=0.4kg,0.5kg``); each
variant is the engine :func:`balance.studies.changes.apply_changes` gives, the same rules
as for a single :func:`variant` and a tolerance study's samples.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray

from balance.core import kinematics
from balance.core.analysis import compute_phasors, engine_cylinders, free_phasors_of
from balance.core.catalogue import BASE, Output
from balance.core.engine import Engine
from balance.core.errors import AnalysisError, InputError
from balance.core.phasors import Phasors
from balance.core.result import FreeForces
from balance.core.speed import rad_per_s_to_rpm, speed_squared
from balance.io.fields import (
    Vary,
    check_varies,
    parse_field,
    parse_values,
    parse_vary,
)
from balance.io.orders import parse_orders
from balance.studies.changes import Change, apply_changes
from balance.studies.sweep_balance import balance_varied, residual_outputs, residual_point

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

__all__ = [
    "DEFAULT_CHUNK_SIZE",
    "check_output",
    "chunk_slices",
    "refuse_variable_speed",
    "sweep",
    "sweep_arrays",
    "sweep_to_file",
    "variant",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Grid points per chunk by default (about 100 MB of temporaries for a V12 at orders 1-8).
DEFAULT_CHUNK_SIZE = 50_000


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
    return check_varies(out)


def variant(layout: Engine, values: Mapping[str, float]) -> Engine:
    """The layout with some fields set (SI values, degrees for angles), as a sweep sees it.

    Parameters
    ----------
    layout : Engine
        The base layout.
    values : mapping of str to float
        Field name (see the module notes) to value: a Python number, SI (degrees for
        angles), not text, so no unit is written.

    Returns
    -------
    Engine
        As loading the layout file with those values written in would give it: for masses
        given by part, a changed part or conrod length is lumped again
        (:func:`balance.core.masses.two_mass_split`), and a lumped mass set here wins over the
        parts; ``reference_z`` is re-centred when the file gives none and a ``z`` changes.
    """
    changes: list[Change] = []
    for name, value in values.items():
        field = parse_field(name, layout)
        changes.append((field, float(field.to_layout_units(value))))
    return apply_changes(layout, changes, problem=_CG_BEYOND_ROD)


_CG_BEYOND_ROD = (
    "vary: the conrod's centre of gravity would lie beyond its small end "
    "(conrod_cg_to_big_end > conrod_length); keep it between the two ends"
)


# ---------------------------------------------------------------------------------------
# the grid and its chunks


def chunk_slices(shape: Sequence[int], chunk_size: int) -> list[tuple[slice, ...]]:
    """Split a grid into hyper-rectangular chunks of at most ``chunk_size`` points.

    The trailing dimensions are kept whole as far as they fit; the first dimension that
    does not fit is cut into slabs and the ones before it are taken one index at a time.
    Every chunk is therefore itself a grid, so the varied fields keep their broadcast
    (outer-product) structure inside it.

    Parameters
    ----------
    shape : sequence of int
        The grid's shape.
    chunk_size : int
        Most grid points per chunk, 1 or more.

    Returns
    -------
    list of tuple of slice
        One index per chunk, in grid order.
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

    @property
    def balance(self) -> bool:
        """Whether a field of the ``balance:`` section is varied (the residual with the
        proposal is then written too)."""
        return balance_varied(self.varies)


def _grid_parameters(plan: _Plan, where: tuple[slice, ...]) -> dict[str, Any]:
    """Engine arrays for one chunk: grid dims leading, cylinders last; broadcastable.

    The same rules as :func:`variant`, over a grid: parts and conrod lengths are lumped
    again for a by-part layout, then the varied lumped masses are set.
    """
    ndim = len(plan.varies)
    changes: list[Change] = []
    for axis, (v, sl) in enumerate(zip(plan.varies, where, strict=True)):
        values = v.field.to_layout_units(v.values[sl])
        shape = [1] * ndim
        shape[axis] = values.size
        changes.append((v.field, np.reshape(values, (*shape, 1))))
    engine = apply_changes(plan.layout, changes, problem=_CG_BEYOND_ROD)
    params: dict[str, Any] = engine_cylinders(engine)  # with the link-pin masses, if any
    params["speed"] = np.asarray(engine.speed, dtype=np.float64)
    params["reference_z"] = np.asarray(engine.reference_z, dtype=np.float64)
    return params


def _unit_phasors(plan: _Plan, p: dict[str, Any]) -> FreeForces:
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
            links=plan.layout.links if plan.layout.has_links else None,
        )
    except AnalysisError as exc:
        raise InputError(f"vary: some grid points have an impossible geometry: {exc}") from None


def _chunk(
    plan: _Plan, where: tuple[slice, ...], cache: dict[Any, FreeForces] | None = None
) -> dict[str, FloatArray]:
    r"""The sweep's variables over one chunk of the grid (full chunk shape leading).

    The phasor sums are formed by :func:`balance.core.analysis.free_phasors` at unit speed over
    the grid of the other fields and then multiplied by :math:`\omega^2`, exactly as
    :func:`balance.core.analysis.compute` does for one engine: a varied speed costs one
    multiplication per grid point and order, and every value is the one ``analyse`` gives.
    With a ``cache``, chunks that differ only in their speeds share those sums (the
    in-process run keeps the last ones).
    """
    if plan.layout.geared:
        return _geared_chunk(plan, where)
    p = _grid_parameters(plan, where)
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
    chunk = _Chunk(unit.phasors.scaled(speed_squared(p["speed"])))

    def full(a: FloatArray, tail: tuple[int, ...] = ()) -> FloatArray:
        lead = a.shape[: a.ndim - len(tail)]
        lead = (1,) * (len(chunk_shape) - len(lead)) + lead
        return np.ascontiguousarray(
            np.broadcast_to(a.reshape(lead + tail), chunk_shape + tail), dtype=np.float64
        )

    tails = _tails(plan)
    out = {
        output.name: full(
            np.asarray(output.get(chunk), dtype=np.float64),
            tuple(tails[d] for d in output.dims),
        )
        for output in _outputs(plan)
    }
    if plan.balance:  # the residual with the proposal, point by point (sweep_balance)
        residual = {
            o.name: np.empty(chunk_shape + tuple(tails[d] for d in o.dims))
            for o in residual_outputs()
        }
        starts = tuple(s.start for s in where)
        for index in np.ndindex(*chunk_shape):
            at = tuple(start + i for start, i in zip(starts, index, strict=True))
            point = residual_point(
                plan.layout, plan.varies, at, plan.orders, plan.model, plan.terms
            )
            for name, values in point.items():
                residual[name][index] = values
        out.update(residual)
    return out


def _geared_chunk(plan: _Plan, where: tuple[slice, ...]) -> dict[str, FloatArray]:
    """A chunk of an engine with several crankshafts, point by point: each point is the
    engine of the hand-edited file (:func:`variant`) analysed as ``analyse`` analyses it
    (:func:`balance.core.analysis.compute_phasors`); there is no grid sum over several
    crank axes (docs/several-crankshafts.md, "Sweeps and tolerance studies")."""
    chunk_shape = tuple(s.stop - s.start for s in where)
    tails = _tails(plan)
    outputs = _outputs(plan)
    out = {o.name: np.empty(chunk_shape + tuple(tails[d] for d in o.dims)) for o in outputs}
    if plan.balance:
        out.update(
            {
                o.name: np.empty(chunk_shape + tuple(tails[d] for d in o.dims))
                for o in residual_outputs()
            }
        )
    starts = tuple(s.start for s in where)
    for index in np.ndindex(*chunk_shape):
        at = tuple(start + i for start, i in zip(starts, index, strict=True))
        changes: list[Change] = [
            (v.field, float(v.field.to_layout_units(v.values[i])))
            for v, i in zip(plan.varies, at, strict=True)
        ]
        engine = apply_changes(plan.layout, changes, problem=_CG_BEYOND_ROD)
        try:
            free = compute_phasors(
                engine,
                plan.orders,
                model=plan.model,
                terms=plan.terms,
                moments=plan.moments,
                roll=plan.roll,
            )
        except AnalysisError as exc:
            raise InputError(f"vary: some grid points have an impossible geometry: {exc}") from None
        point = _Chunk(free.phasors)
        for output in outputs:
            out[output.name][index] = np.asarray(output.get(point), dtype=np.float64)
        if plan.balance:
            residual = residual_point(
                plan.layout, plan.varies, at, plan.orders, plan.model, plan.terms
            )
            for name, values in residual.items():
                out[name][index] = values
    return out


@dataclass(frozen=True)
class _Chunk:
    """What the catalogue's per-variant outputs read of one chunk of a sweep: its phasors
    (the grid's axes in front) and its roll; a sweep has no sections."""

    phasors: Phasors | None
    parts: dict[str, Any] = field(default_factory=dict)

    @property
    def roll(self) -> ComplexArray | None:
        return None if self.phasors is None else self.phasors.roll

    def part(self, name: str) -> Any:
        """A section's part: a sweep computes none (its values are the inertia forces')."""
        return self.parts.get(name)


def _outputs(plan: _Plan) -> list[Output]:
    """The outputs a sweep writes: the catalogue's per-variant ones
    (:attr:`balance.core.catalogue.Output.per_variant`) of what the plan computes."""
    return [
        output
        for output in BASE
        if output.per_variant
        and (plan.moments or "moment" not in output.name)
        and (plan.roll or "roll_order" not in output.dims)
    ]


def _tails(plan: _Plan) -> dict[str, int]:
    """The size of each dimension an output has after the grid's."""
    K = plan.orders.size
    return {"order": K, "rotation": 2, "roll_order": K}


def _variables(plan: _Plan) -> dict[str, tuple[tuple[str, ...], str, str]]:
    """Each variable of a sweep with its dimensions after the grid's, unit and
    ``long_name`` (a sweep's, which has no gas forces)."""
    out = {
        output.name: (output.dims, output.units, output.describe(_Chunk(None)))
        for output in _outputs(plan)
    }
    if plan.balance:
        for output in residual_outputs():
            out[output.name] = (output.dims, output.units, output.describe(_Chunk(None)))
    return out


def refuse_variable_speed(layout: Engine, study: str) -> None:
    """Refuse a study of a layout that asks for the variable-speed analysis (its
    ``dynamics:`` section): studies run at constant speed in this version.

    Parameters
    ----------
    layout : Engine
        The layout studied.
    study : str
        The study, as messages name it (``sweep``, ``tolerance``).

    Raises
    ------
    InputError
        When the layout has a ``dynamics:`` section.
    """
    if "dynamics" in layout.sections:
        raise InputError(
            f"{study}: layout '{layout.name}' asks for the variable-speed analysis (its "
            f"dynamics: section), which a {study} does not run in this version; remove the "
            "section to study the engine at constant speed"
        )


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
        raise InputError(f"model: {model!r}; a sweep uses one of {', '.join(kinematics.MODELS)}")
    refuse_variable_speed(layout, "sweep")
    ks = parse_orders(orders)
    varies = tuple(_as_varies(layout, vary))
    if balance_varied(varies) and not (moments and roll):
        names = ", ".join(v.field.text for v in varies if v.field.attribute.startswith("balance."))
        raise InputError(
            f"vary: {names}: the residual with the proposal needs the moments and the roll; "
            "compute both (moments, roll)"
        )
    return _Plan(layout, varies, ks, model, terms, moments, roll)


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
    coords.update(_speed_coords(plan))
    return coords


def _speed_coords(plan: _Plan) -> dict[str, tuple[tuple[str, ...], Any, dict[str, str]]]:
    """The crank speed in rpm beside rad/s: along the speed dimension when speed is varied,
    else the layout's speed as scalar coordinates (so no attribute goes stale)."""
    varied = [v for v in plan.varies if v.field.attribute == "speed"]
    rpm = {"units": "rpm", "long_name": "crank speed in revolutions per minute"}
    if varied:
        v = varied[0]
        return {"speed_rpm": ((v.dim,), _rpm(v.values), rpm)}
    speed = float(plan.layout.speed)
    return {
        "speed": ((), np.float64(speed), {"units": "rad/s", "long_name": "crank speed"}),
        "speed_rpm": ((), _rpm(np.asarray(speed))[()], rpm),
    }


def _rpm(speed: NDArray[np.float64]) -> NDArray[np.float64]:
    """rad/s to rpm to 12 significant digits (1000 rpm stays 1000, not 1000.0000000000001)."""
    values = np.atleast_1d(np.asarray(speed, dtype=np.float64))
    out = np.array([float(f"{rad_per_s_to_rpm(float(v)):.12g}") for v in values])
    return out.reshape(np.shape(speed))


def _auxiliary(plan: _Plan) -> str:
    """The coordinates that are not dimensions, as a data variable's CF ``coordinates``
    attribute, so that netCDF and Zarr readers restore them as coordinates."""
    return " ".join(name for name, (dims, _, _) in _coords(plan).items() if dims != (name,))


def _attrs(plan: _Plan) -> dict[str, Any]:
    from balance._version import __version__

    return {
        "schema": "balance.sweep/1",
        "layout": plan.layout.name,
        "source_file": plan.layout.path or "",
        "model": plan.model,
        "varied_fields": ";".join(v.field.text for v in plan.varies),
        "balance_version": __version__,
        "conventions": "balance conventions (docs/conventions.md); values of every analysis as "
        "'balance analyse' gives them for the layout with the varied fields set",
    }


def _run_chunks(
    plan: _Plan,
    chunks: list[tuple[slice, ...]],
    client: Any,
    progress: Progress | None,
) -> Iterator[tuple[tuple[slice, ...], dict[str, FloatArray]]]:
    """Results chunk by chunk, in-process or on a Dask client (in order of completion)."""

    def results() -> Iterator[tuple[tuple[slice, ...], dict[str, FloatArray]]]:
        if client is None:
            cache: dict[Any, FreeForces] = {}
            for where in chunks:
                yield where, _chunk(plan, where, cache)
            return
        from distributed import as_completed

        # hash=False: a fresh key for every run.  With the default the key is the plan's
        # hash, so a second run of the same plan on the same client scatters a key whose
        # release by the first run may still be on its way to the scheduler; the scheduler
        # then forgets the new copy, and the chunks fail with "lost dependencies"
        # (dask/distributed issue 3703).
        plan_future = client.scatter(plan, broadcast=True, hash=False)
        futures = {client.submit(_chunk, plan_future, where, pure=False): where for where in chunks}
        try:
            for future in as_completed(list(futures)):
                where = futures.pop(future)
                result = future.result()
                future.release()
                yield where, result
        finally:  # stopped early (an error, an interrupted write): nothing left on the cluster
            client.cancel([*futures, plan_future])

    if progress is not None:
        progress.start(math.prod(plan.shape))
    try:
        for where, result in results():
            if progress is not None:
                progress.advance(math.prod(s.stop - s.start for s in where))
            yield where, result
    finally:
        if progress is not None:
            progress.stop()


class Progress(Protocol):
    """What a sweep tells about its progress: the number of grid points, then each chunk's
    points as it is done (a view draws it: :class:`balance.views.progress.ProgressBar`)."""

    def start(self, total: int) -> None: ...

    def advance(self, points: int) -> None: ...

    def stop(self) -> None: ...


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
    progress: Progress | None = None,
    sink: Callable[[tuple[slice, ...], dict[str, FloatArray]], None] | None = None,
) -> tuple[_Plan, dict[str, FloatArray] | None]:
    """Run a sweep chunk by chunk; hand each chunk to ``sink`` or gather it in memory.

    Parameters
    ----------
    layout, vary, orders, model, terms, moments, roll, chunk_size, client, progress
        As for :func:`sweep`.
    sink : callable, optional
        ``sink(where, arrays)``: takes each chunk's arrays by variable name, ``where`` its
        index in the grid (:func:`chunk_slices`); without it the chunks are gathered.

    Returns
    -------
    plan : object
        The sweep's plan: the layout, the checked varied fields, the orders, the model.
    arrays : dict of ndarray or None
        Every variable over the whole grid (SI), without a sink; None with one.
    """
    plan = _plan(layout, vary, orders, model, terms, moments, roll)
    chunks = chunk_slices(plan.shape, chunk_size)
    tails = _tails(plan)
    arrays: dict[str, FloatArray] | None = None
    if sink is None:
        arrays = {
            name: np.empty(plan.shape + tuple(tails[d] for d in dims))
            for name, (dims, _, _) in _variables(plan).items()
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
    progress: Progress | None,
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
    progress: Progress | None = None,
) -> xr.Dataset:
    """Analyse every combination of the varied fields' values.

    Parameters
    ----------
    layout : Engine
        The base layout.
    vary : mapping or sequence
        ``{field: values}`` with values an array (SI, degrees for angles) or text such as
        ``"130mm:160mm:31"``; or a sequence of ``"field=values"`` strings or :class:`Vary`.
        Each becomes a dimension of the result, in the order given.  Numbers from Python
        are SI floats; text is read as on the command line, where a dimensional value
        needs its unit (a bare number other than 0 is refused).
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
    progress : Progress, optional
        Told of the progress chunk by chunk (the command line draws a bar with it).

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
    meta = _variables(plan)
    data = {
        name: (
            plan.dims + meta[name][0],
            values,
            {"units": meta[name][1], "long_name": meta[name][2]},
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
    progress: Progress | None = None,
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

    Parameters
    ----------
    path : str or Path
        The file (``.nc``) or store (``.zarr``) to write.
    force : bool
        Replace an existing output.
    file_format : {'netcdf', 'zarr'}, optional
        The format, instead of the one the suffix names.

    Returns
    -------
    str
        ``'netcdf'`` or ``'zarr'``.

    Raises
    ------
    InputError
        For an unknown suffix, a missing ``zarr`` package, or a target that cannot be
        written (:mod:`balance.io.atomic`; an existing one without ``force`` is
        :class:`~balance.core.errors.OutputExists`).
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
                if dims == (name,):
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
            auxiliary = _auxiliary(plan)
            for name, (tail, units, long_name) in _variables(plan).items():
                var = nc.createVariable(name, "f8", plan.dims + tail)
                var.setncatts({"units": units, "long_name": long_name, "coordinates": auxiliary})
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

    from balance.io.atomic import checkpoint, write_atomic_directory

    tails = _tails(plan)
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
            array[...] = data
        arrays = {}
        auxiliary = _auxiliary(plan)
        for name, (tail, units, long_name) in _variables(plan).items():
            tail_shape = tuple(tails[d] for d in tail)
            arrays[name] = group.create_array(
                name,
                shape=plan.shape + tail_shape,
                chunks=grid_chunk + tail_shape,
                dtype="f8",
                fill_value=np.nan,
                dimension_names=plan.dims + tail,
                attributes={
                    "units": units,
                    "long_name": long_name,
                    "coordinates": auxiliary,
                },
            )

        def sink(where: tuple[slice, ...], result: dict[str, FloatArray]) -> None:
            checkpoint()  # no chunk in flight: where a signal may stop the write
            for key, values in result.items():
                arrays[key][where] = values

        run(sink)
        with warnings.catch_warnings():
            # consolidated metadata is what xarray.open_zarr looks for first; zarr warns
            # that it is not yet part of the Zarr 3 specification
            warnings.filterwarnings("ignore", message="Consolidated metadata")
            zarr.consolidate_metadata(tmp)

    return write_atomic_directory(target, write, force=force, is_replaceable=_is_zarr_store)
