"""Layouts: reading a layout file into a table of cylinders.

:func:`load_layout` returns a :class:`~balance.core.engine.Engine`: one entry per cylinder
in numpy arrays, SI units (radians for angles).  Loading validates the file
(:mod:`balance.io.schema`), expands the compact ``crank:`` form, applies per-cylinder
overrides, derives the lumped masses from parts where parts are given, and checks that the
geometry can exist, so that the physics never sees a unit string or an impossible value.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
from numpy.typing import NDArray
from pydantic import BaseModel, ValidationError

from balance.core.engine import CYLINDER_FIELDS, BalanceSettings, Engine, Links, ShaftPosition
from balance.core.errors import InputError, LayoutError, LayoutErrors, Location, raise_all
from balance.core.gas import GasInput, GasModel, cycle_degrees, firing_tdc
from balance.core.masses import MassParts, two_mass_split
from balance.core.speed import rad_per_s_to_rpm
from balance.io.bearings_section import check_mains
from balance.io.schema import (
    GEOMETRY_KEYS,
    LUMPED_KEYS,
    PART_KEYS,
    CrankSpec,
    CylinderSpec,
    FieldProblem,
    LayoutSpec,
)
from balance.io.schema import (
    BalanceSettings as BalanceSpec,
)
from balance.io.traces import read_pressure_trace
from balance.io.units import UnitProblem

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.mounts import MountSystem
from balance.io.yamlsource import SourceDocument, dotted_path, parse_yaml, read_yaml_file

__all__ = [
    "builtin_layout_names",
    "builtin_layout_path",
    "expand_layout",
    "layout_from_dict",
    "layout_from_text",
    "load_layout",
]

FloatArray = NDArray[np.float64]

# ---------------------------------------------------------------------------------------
# built-in layouts


def _layout_dirs() -> list[Path]:
    dirs = []
    packaged = resources.files("balance") / "layouts"
    if packaged.is_dir():
        dirs.append(Path(str(packaged)))
    source_tree = Path(__file__).resolve().parents[2] / "layouts"
    if source_tree.is_dir():
        dirs.append(source_tree)
    return dirs


def builtin_layout_names() -> list[str]:
    """Names of the built-in layouts (``inline-4``, ``v8-crossplane``...)."""
    names: set[str] = set()
    for d in _layout_dirs():
        names.update(p.stem for p in d.glob("*.yaml"))
    return sorted(names)


def builtin_layout_path(name: str) -> Path:
    """Path of a built-in layout file.

    Raises
    ------
    InputError
        If there is no built-in layout of that name.
    """
    for d in _layout_dirs():
        candidate = d / f"{name}.yaml"
        if candidate.is_file():
            return candidate
    names = builtin_layout_names()
    hint = difflib.get_close_matches(name, names, n=3)
    valid = f"did you mean {' or '.join(hint)}?" if hint else "run 'balance layouts' for the list"
    raise InputError(f"{name}: no such file or built-in layout; {valid}")


# ---------------------------------------------------------------------------------------
# loading


def load_layout(source: str | Path) -> Engine:
    """Load a layout from a file path or a built-in layout name.

    Parameters
    ----------
    source : str or path-like
        A YAML file, or the name of a built-in layout such as ``"inline-4"``
        (see :func:`builtin_layout_names`).

    Returns
    -------
    Engine

    Raises
    ------
    LayoutError
        If the file is not a valid layout; the message names file, line, column and field.
    InputError
        If the file cannot be found or read.
    """
    return _build(_read_document(source))[1]


def _read_document(source: str | Path) -> SourceDocument:
    """The parsed YAML of a layout file or built-in layout name."""
    path = Path(source)
    if (
        not path.exists()
        and isinstance(source, str)
        and "/" not in source
        and not source.endswith((".yaml", ".yml"))
    ):
        path = builtin_layout_path(source)
    return read_yaml_file(path, source, "layout file")


def layout_from_text(text: str, file: str = "<input>") -> Engine:
    """Build a layout from YAML text (see :func:`load_layout`)."""
    return _build(parse_yaml(text, file))[1]


def layout_from_dict(data: dict[str, Any], file: str = "<dict>") -> Engine:
    """Build a layout from plain data shaped like a layout file, read by the file's rules:
    a dimensional quantity is text with its unit (``"86 mm"``); a bare number other than 0
    is refused, as in a file (see :func:`load_layout`)."""
    return _build(SourceDocument(data=data, file=file))[1]


def _spec(doc: SourceDocument) -> LayoutSpec:
    if not isinstance(doc.data, dict):
        kind = type(doc.data).__name__
        raise LayoutError(
            f"the document is a {'list' if kind == 'list' else 'single value'}, not a mapping",
            doc.location(()),
            valid="a layout is a mapping with name, speed, geometry, masses and cylinders",
        )
    problems: list[LayoutError] = []
    spec = None
    try:
        spec = LayoutSpec.model_validate(doc.data)
    except ValidationError as exc:
        problems += _layout_errors(exc, doc)
    mounts = doc.data.get("mounts")
    if spec is None and isinstance(mounts, dict):  # its problems too, at once
        from balance.io.mounts_section import MountsSpec, section_errors

        try:
            MountsSpec.model_validate(mounts)
        except ValidationError as exc:
            problems += section_errors(exc, doc, ("mounts",))
    raise_all(problems)
    assert spec is not None
    return spec


def _model_at(path: tuple[str | int, ...]) -> type[BaseModel] | None:
    model: type[BaseModel] | None = LayoutSpec
    for part in path:
        if model is None:
            return None
        if isinstance(part, int):
            continue
        info = model.model_fields.get(part)
        if info is None:
            return None
        model = _model_of(info.annotation)
    return model


def _model_of(annotation: Any) -> type[BaseModel] | None:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in getattr(annotation, "__args__", ()) or ():
        found = _model_of(arg)
        if found is not None:
            return found
    return None


_TYPE_NAMES = {
    "dict": "a mapping",
    "list": "a list",
    "str": "text",
    "int": "a whole number",
    "float": "a number",
    "bool": "true or false",
    "NoneType": "nothing",
}


def _layout_errors(exc: ValidationError, doc: SourceDocument) -> list[LayoutError]:
    """Every problem of a failed validation, located in the file.

    A key reported missing where an unknown key beside it is a misspelling of it (the
    unknown key's "did you mean") is reported once, as the unknown key.
    """
    errors = exc.errors(include_url=False)
    misspelt = set()
    for err in errors:
        if err["type"] == "extra_forbidden":
            loc = _clean_loc(err["loc"])
            model = _model_at(loc[:-1])
            names = list(model.model_fields) if model else []
            for hint in difflib.get_close_matches(str(loc[-1]), names, n=1):
                misspelt.add((*loc[:-1], hint))
    return [
        _one_error(err, doc)
        for err in errors
        if not (err["type"] == "missing" and _clean_loc(err["loc"]) in misspelt)
    ]


def _clean_loc(raw: Any) -> tuple[str | int, ...]:
    loc = tuple(p for p in raw if isinstance(p, str | int))
    return tuple(p for p in loc if not (isinstance(p, str) and p.startswith("function-")))


def _one_error(err: Any, doc: SourceDocument) -> LayoutError:
    """One pydantic error as a located :class:`LayoutError`."""
    loc = _clean_loc(err["loc"])
    kind = err["type"]
    ctx = err.get("ctx") or {}
    problem = ctx.get("error")
    if kind == "extra_forbidden":
        key = str(loc[-1])
        model = _model_at(loc[:-1])
        names = list(model.model_fields) if model else []
        hint = difflib.get_close_matches(key, names, n=1)
        valid = f"did you mean '{hint[0]}'?" if hint else ""
        valid = (valid + " " if valid else "") + (
            f"valid keys: {', '.join(names)}" if names else ""
        )
        return LayoutError(
            f"unknown key '{key}'",
            doc.location(loc, key=True),
            field=dotted_path(loc),
            valid=valid.strip(),
        )
    if kind == "missing":
        key = str(loc[-1])
        return LayoutError(
            f"missing '{key}'",
            doc.location(loc[:-1]),
            field=dotted_path(loc),
            valid=_MISSING_HINTS.get(key, f"add '{key}'"),
        )
    if isinstance(problem, FieldProblem):
        full = loc + problem.at
        return LayoutError(
            str(problem),
            doc.location(full),
            field=dotted_path(full) or None,
            valid=problem.valid or None,
        )
    if isinstance(problem, UnitProblem):
        return LayoutError(
            str(problem), doc.location(loc), field=dotted_path(loc), valid=problem.valid
        )
    if kind == "literal_error":
        return LayoutError(
            f"{err['input']!r} is not allowed",
            doc.location(loc),
            field=dotted_path(loc),
            valid=f"expected {ctx.get('expected', 'one of the documented values')}",
        )
    if kind.endswith("_type") or kind in {"model_attributes_type", "int_parsing"}:
        got = _TYPE_NAMES.get(type(err["input"]).__name__, type(err["input"]).__name__)
        want = {
            "dict_type": "a mapping",
            "model_type": "a mapping",
            "list_type": "a list",
            "string_type": "text",
            "int_type": "a whole number",
            "int_from_float": "a whole number",
            "int_parsing": "a whole number",
        }.get(kind, err["msg"].lower())
        return LayoutError(
            f"expected {want}, got {got}",
            doc.location(loc),
            field=dotted_path(loc),
            valid=_TYPE_HINTS.get(loc[-1] if loc else "", f"write {want} here"),
        )
    if kind in {"too_short", "too_long", "string_too_short", "string_too_long"}:
        return LayoutError(
            err["msg"],
            doc.location(loc),
            field=dotted_path(loc) or None,
            valid="see the layout format in the docs",
        )
    return LayoutError(err["msg"], doc.location(loc), field=dotted_path(loc) or None)


_MISSING_HINTS = {
    "name": "add a name, e.g. 'name: Inline-4, flat crank'",
    "speed": "add the crank speed, e.g. 'speed: 6000 rpm'",
    "geometry": "add geometry with stroke (or crank_radius) and conrod_length",
    "masses": "add masses: reciprocating and rotating (or the parts)",
    "conrod_length": "add conrod_length, e.g. '143 mm'",
    "z": "add the axial position of the throw plane, e.g. 'z: 91 mm'",
    "throws": "add the throw angles, e.g. 'throws: [0, 180, 180, 0]'",
    "speed_ratio": "add the shaft's speed over crank speed, e.g. 'speed_ratio: 2'",
    "master": "add the master cylinder's number, e.g. 'master: 1'",
    "pin_radius": "add the link pin's distance from the crank-pin centre, e.g. '46 mm'",
    "pin_angle": "add the link pin's direction from the master rod's centre line, e.g. "
    "'72 deg' (usually this cylinder's bank minus the master's)",
    "length": "add the link rod's length, link pin to piston pin, e.g. '230 mm'",
}
_TYPE_HINTS: dict[str | int, str] = {
    "cylinders": "a list of cylinders, each {throw: ..., bank: ..., z: ...}",
    "geometry": "a mapping with stroke (or crank_radius), conrod_length and offset",
    "masses": "a mapping with reciprocating and rotating (or the parts)",
    "throws": "a list of angles, e.g. [0, 180, 180, 0]",
    "banks": "a list of angles, e.g. [-45 deg, 45 deg]",
    "firing_order": "a list of cylinder numbers, e.g. [1, 3, 4, 2]",
    "master": "the number (1-based, in file order) of the cylinder whose rod carries this "
    "link rod, e.g. 'master: 1'",
    "link": "a mapping {master: 1, pin_radius: 46 mm, pin_angle: 72 deg, length: 230 mm}",
}


def _cylinders(spec: LayoutSpec) -> tuple[list[CylinderSpec], tuple[str | int, ...] | None]:
    """Explicit cylinders (expanding the compact form); with the path prefix of entries."""
    if spec.cylinders is not None:
        return list(spec.cylinders), ("cylinders",)
    crank = spec.crank
    assert crank is not None
    return _expand_crank(crank), None


def _expand_crank(crank: CrankSpec) -> list[CylinderSpec]:
    split = crank.split if crank.split is not None else [0.0] * len(crank.banks)
    spacing = crank.spacing or 0.0
    cylinders = []
    for t, throw in enumerate(crank.throws):
        for j, bank in enumerate(crank.banks):
            # values already read and checked (SI): constructed, not read again
            cylinders.append(
                CylinderSpec.model_construct(
                    throw=throw + split[j], bank=bank, z=t * spacing + j * crank.bank_stagger
                )
            )
    return cylinders


def _build(doc: SourceDocument) -> tuple[LayoutSpec, Engine]:
    """The validated file and the engine it describes."""
    spec = _spec(doc)
    cylinders, prefix = _cylinders(spec)
    n = len(cylinders)
    sharing = _rods_per_throw(spec, cylinders)
    if n > 256:
        raise LayoutError(
            f"{n} cylinders",
            doc.location(("crank",)),
            field="crank",
            valid="at most 256 cylinders",
        )

    def where(i: int, key: str) -> tuple[Location, str]:
        if prefix is not None and getattr(cylinders[i], key, None) is not None:
            path = (*prefix, i, key)
            return doc.location(path), dotted_path(path)
        section = "geometry" if key in GEOMETRY_KEYS else "masses"
        return doc.location((section, key)), f"{section}.{key}"

    geometry = spec.geometry
    problems: list[LayoutError] = []  # every problem of the file, reported together
    impossible: dict[tuple[Location, str, str], list[int]] = {}
    masters = _link_masters(spec, doc, cylinders)
    values: dict[str, list[float]] = {k: [] for k in CYLINDER_FIELDS}
    part_rows: list[tuple[float, ...]] = []
    for i, cyl in enumerate(cylinders):
        own = cylinders[masters[i]] if masters[i] >= 0 else cyl
        g = cyl.overrides(GEOMETRY_KEYS)
        g_own = own.overrides(GEOMETRY_KEYS)
        if "stroke" in g_own:
            radius = g_own["stroke"] / 2
        elif "crank_radius" in g_own:
            radius = g_own["crank_radius"]
        else:
            radius = geometry.radius
        length = g.get("conrod_length", geometry.conrod_length)
        offset = g.get("offset", geometry.offset)
        if cyl.link is not None:
            length = cyl.link.length  # the link rod; its reach is checked with the links
        elif not length > radius + abs(offset):
            impossible.setdefault(_geometry_problem(doc, cylinders, prefix, i), []).append(i + 1)
        try:
            rec, rot, dinertia, record = _cylinder_masses(
                spec, doc, cyl, length, i, where, sharing[i]
            )
        except LayoutError as exc:  # reported with every other problem below
            problems.append(exc)
            rec = rot = dinertia = math.nan
            record = None
        if record is not None:
            part_rows.append(record)
        values["throw"].append(math.radians(cyl.throw_angle))
        values["bank"].append(math.radians(cyl.bank))
        values["z"].append(cyl.z)
        values["crank_radius"].append(radius)
        values["conrod_length"].append(length)
        values["offset"].append(offset)
        values["reciprocating_mass"].append(rec)
        values["rotating_mass"].append(rot)
        values["conrod_inertia_correction"].append(dinertia)

    for (loc, name, message), numbers in impossible.items():
        problems.append(
            LayoutError(
                f"{message} ({_cylinder_list(numbers, n)})",
                loc,
                field=name,
                valid="the crank slider exists only while conrod_length > crank_radius + |offset|",
            )
        )
    arrays = {k: np.asarray(v, dtype=np.float64) for k, v in values.items()}
    # the link rods' reach needs sound master geometry and masses: checked once they are
    links = None
    links_checked = not problems
    if links_checked:
        links = _collect(problems, lambda: _links(doc, cylinders, masters, arrays))
        links_checked = not problems
    z = arrays["z"]
    reference_z = spec.reference_z if spec.reference_z is not None else 0.5 * (z.min() + z.max())
    pitch = _pitch(spec, z)
    firing = _collect(problems, lambda: _firing_order(spec, n, doc))
    gas = (
        _collect(problems, lambda: _gas(spec, doc, cylinders, prefix, arrays, firing, links))
        if spec.gas is not None and links_checked
        else None
    )
    mounts = _collect(problems, lambda: _mounts(spec, doc))
    stroke = 2.0 * float(np.max(arrays["crank_radius"]))
    mains = _collect(problems, lambda: _mains(spec, doc, arrays["z"], pitch, stroke))
    raise_all(problems)
    return spec, Engine(
        name=spec.name,
        speed=spec.speed,
        cycle=spec.cycle,
        reference_z=float(reference_z),
        pitch=pitch,
        bore=float(spec.geometry.bore) if spec.geometry.bore is not None else math.nan,
        firing_order=firing,
        description=spec.description,
        source=spec.source,
        path=None if doc.file.startswith("<") else doc.file,
        reference_z_given=spec.reference_z is not None,
        balance=_balance_settings(spec.balance),
        gas=gas,
        mass_parts=_mass_parts(part_rows) if part_rows else None,
        sections={
            key: value
            for key, value in (("mounts", mounts), ("bearings", mains))
            if value is not None
        },
        links=links,
        **arrays,
    )


T = TypeVar("T")


def _collect(problems: list[LayoutError], check: Callable[[], T]) -> T | None:
    """The value of ``check()``; a :class:`LayoutError` it raises is added to ``problems``
    (every problem of a file is reported at once) and None returned instead."""
    try:
        return check()
    except LayoutErrors as exc:
        problems.extend(exc.errors)
    except LayoutError as exc:
        problems.append(exc)
    return None


def _cylinder_list(numbers: list[int], n: int) -> str:
    if len(numbers) == n > 1:
        return "every cylinder"
    if len(numbers) == 1:
        return f"cylinder {numbers[0]}"
    return f"cylinders {', '.join(str(k) for k in numbers)}"


def _written(doc: SourceDocument, path: tuple[str | int, ...]) -> str | None:
    """A value as the file wrote it (``'120 mm'``; a YAML number as a number), or None
    where the file gives nothing at ``path``."""
    value: Any = doc.data
    for part in path:
        try:
            value = value[part]
        except (KeyError, IndexError, TypeError):
            return None
    if value is None or isinstance(value, dict | list):
        return None
    return f"'{value}'" if isinstance(value, str) else str(value)


def _geometry_problem(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    prefix: tuple[str | int, ...] | None,
    i: int,
) -> tuple[Location, str, str]:
    """Where and what an impossible crank slider of cylinder ``i`` is: the fields on both
    sides of ``conrod_length > crank_radius + |offset|`` with their values as written.

    Located at the cylinder's own entry when it overrides one of them (the conrod length
    first, then the stroke or crank radius, then the offset), else at
    ``geometry.conrod_length``.
    """
    cyl = cylinders[i]

    def source(key: str) -> tuple[str | int, ...]:
        if prefix is not None and getattr(cyl, key, None) is not None:
            return (*prefix, i, key)
        return ("geometry", key)

    def given(key: str) -> bool:
        path = source(key)
        return path[0] != "geometry" or _written(doc, path) is not None

    def name(path: tuple[str | int, ...]) -> str:  # the key; the full path of an override
        return str(path[-1]) if path[0] == "geometry" else dotted_path(path)

    rod = source("conrod_length")
    radius_key = next(
        (k for k in ("stroke", "crank_radius") if source(k)[0] != "geometry"),
        "stroke" if given("stroke") else "crank_radius",
    )
    radius = source(radius_key)
    offset = source("offset")
    radius_text = f"{name(radius)} {_written(doc, radius)}"
    if radius_key == "stroke":
        radius_text = f"crank_radius ({radius_text} / 2)"
    offset_text = (
        f"|{name(offset)}| {_written(doc, offset)}" if given("offset") else "|offset| 0 (not given)"
    )
    message = f"{name(rod)} {_written(doc, rod)} is not more than {radius_text} + {offset_text}"
    at = next((p for p in (rod, radius, offset) if p[0] != "geometry"), rod)
    return doc.location(at), dotted_path(at), message


def _mains(
    spec: LayoutSpec, doc: SourceDocument, z: NDArray[np.float64], pitch: float, stroke: float
) -> tuple[float, ...] | None:
    """The ``bearings:`` section's main positions [m], checked against the pin planes (the
    default mains for a section without ``mains``; None without a section)."""
    if spec.bearings is None:
        return None
    if spec.bearings.mains is None:
        from balance.core.bearings import default_mains

        return tuple(float(v) for v in default_mains(z, pitch, stroke))
    try:
        mains = check_mains(spec.bearings.mains, z)
    except FieldProblem as problem:
        path = ("bearings", *problem.at)
        raise LayoutError(
            str(problem), doc.location(path), field=dotted_path(path), valid=problem.valid
        ) from None
    return tuple(float(v) for v in mains)


def _mounts(spec: LayoutSpec, doc: SourceDocument) -> MountSystem | None:
    """The ``mounts:`` section as a mount system, its errors located in the file."""
    if spec.mounts is None:
        return None
    from balance.io.mounts_section import MountsSpec, mount_system, section_errors

    try:
        return mount_system(MountsSpec.model_validate(spec.mounts))
    except ValidationError as exc:
        errors = section_errors(exc, doc, ("mounts",))
    raise_all(errors)  # outside the handler: the ValidationError is no part of the report
    raise AssertionError("a failed validation has at least one problem")  # pragma: no cover


def _balance_settings(section: BalanceSpec | None) -> BalanceSettings | None:
    if section is None:
        return None
    return BalanceSettings(
        counterweight_radius=section.counterweight_radius,
        balance_factor=section.balance_factor,
        orders=tuple(section.orders) if section.orders is not None else None,
        strategy=section.strategy,
        shafts=_shaft_positions(section),
    )


def _shaft_positions(section: BalanceSpec) -> tuple[ShaftPosition, ...] | None:
    """The ``balance: shafts:`` entries (SI), or None when the section has none."""
    if section.shafts is None:
        return None
    return tuple(ShaftPosition(s.speed_ratio, s.x, s.y) for s in section.shafts)


def _mass_parts(rows: list[tuple[float, ...]]) -> MassParts:
    columns = np.asarray(rows, dtype=np.float64).T
    names = [f.name for f in dataclasses.fields(MassParts)]
    return MassParts(**dict(zip(names, columns, strict=True)))


def _gas(
    spec: LayoutSpec,
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    prefix: tuple[str | int, ...] | None,
    arrays: dict[str, Any],
    firing: tuple[int, ...] | None,
    links: Links | None = None,
) -> GasInput:
    """Resolve the ``gas:`` and ``flywheel:`` sections: read the trace, place firing TDCs."""
    from balance.core.links import dead_centre_lag

    section = spec.gas
    assert section is not None
    cycle_deg = cycle_degrees(spec.cycle)
    angle = pressure = None
    source = "model"
    if section.pressure_trace is not None:
        base = Path(doc.file).parent if not doc.file.startswith("<") else Path.cwd()
        trace = base / section.pressure_trace
        if not trace.is_file():
            raise LayoutError(
                f"no such file {str(trace)!r}",
                doc.location(("gas", "pressure_trace")),
                field="gas.pressure_trace",
                valid="a CSV file of crank angle [deg from firing TDC] and absolute pressure, "
                "relative to the layout file",
            )
        angle, pressure = read_pressure_trace(trace, cycle_deg)
        source = str(trace)
    tdc_given = [c.tdc for c in cylinders] if prefix is not None else None
    # every cylinder's cycle starts at its actual top dead centre (offset, link rod)
    lag = dead_centre_lag(
        arrays["crank_radius"], arrays["conrod_length"], arrays["offset"], arrays["bank"], links
    )
    tdc = firing_tdc(
        np.degrees(arrays["throw"]),
        np.degrees(arrays["bank"]),
        spec.cycle,
        firing,
        tdc_given,
        tdc_lag=np.degrees(lag),
    )
    if isinstance(tdc, str):
        path: tuple[str | int, ...] = ("firing_order",) if firing else ("gas",)
        raise LayoutError(
            tdc,
            doc.location(path),
            field="firing_order",
            valid="add e.g. 'firing_order: [1, 3, 4, 2]' (or give every cylinder 'tdc')"
            if not firing
            else "list the cylinders in the order they fire",
        )
    bore = section.bore if section.bore is not None else spec.geometry.bore
    flywheel = spec.flywheel
    return GasInput(
        angle=angle,
        pressure=pressure,
        model=GasModel(**section.model.model_dump()) if section.model is not None else None,
        crankcase_pressure=section.crankcase_pressure,
        bore=float(bore),  # type: ignore[arg-type]
        firing_tdc=tdc,
        cycle_deg=cycle_deg,
        flywheel_inertia=flywheel.inertia if flywheel is not None else None,
        speed_fluctuation=flywheel.speed_fluctuation if flywheel is not None else None,
        source=source,
    )


def _rods_per_throw(spec: LayoutSpec, cylinders: list[CylinderSpec]) -> list[int]:
    """How many rods share each cylinder's crank throw.

    In the compact form the rods of one entry of ``throws`` share it (split pins included);
    in the explicit form cylinders with the same throw angle and the same ``z`` do.
    """
    if spec.crank is not None:
        per_throw = len(spec.crank.banks)
        return [per_throw] * len(cylinders)
    keys = [(round(cyl.throw_angle % 360.0, 9) % 360.0, round(cyl.z, 12)) for cyl in cylinders]
    return [keys.count(key) for key in keys]


def _cylinder_masses(
    spec: LayoutSpec,
    doc: SourceDocument,
    cyl: CylinderSpec,
    length: float,
    i: int,
    where: Any,
    sharing: int,
) -> tuple[float, float, float, tuple[float, ...] | None]:
    """Reciprocating mass, rotating mass, conrod inertia correction of one cylinder, and
    its parts (the fields of :class:`~balance.core.masses.MassParts`; None for lumped masses).

    ``crank_unbalance`` is per throw: each of the ``sharing`` rods on a throw carries its
    share.
    """
    masses = spec.masses
    part_over = cyl.overrides(PART_KEYS)
    lumped_over = cyl.overrides(LUMPED_KEYS)
    if cyl.link is not None:
        _check_link_masses(spec, doc, cyl, i, where)
    if not masses.by_part:
        if part_over:
            key = next(iter(part_over))
            loc, name = where(i, key)
            raise LayoutError(
                f"'{key}' overrides a part, but the engine's masses are lumped",
                loc,
                field=name,
                valid="override reciprocating or rotating, or give the engine's masses by part",
            )
        rec = lumped_over.get("reciprocating", masses.reciprocating)
        rot = lumped_over.get("rotating", masses.rotating)
        return float(rec), float(rot), 0.0, None  # type: ignore[arg-type]
    parts = {k: getattr(masses, k) for k in PART_KEYS}
    if cyl.link is not None:  # the engine-wide rod is the master rod, not this link rod
        parts["conrod_inertia"] = None
    parts.update(part_over)
    cg = parts["conrod_cg_to_big_end"]
    if cg > length:
        loc, name = where(i, "conrod_cg_to_big_end")
        raise LayoutError(
            f"conrod_cg_to_big_end {cg * 1e3:.6g} mm is longer than the "
            f"{'link rod' if cyl.link is not None else 'conrod'} "
            f"({length * 1e3:.6g} mm, cylinder {i + 1})",
            loc,
            field=name,
            valid="the centre of gravity lies between big end and small end",
        )
    inertia = parts["conrod_inertia"]
    record = (
        float(parts["piston_group"]),
        float(parts["conrod"]),
        float(cg),
        math.nan if inertia is None else float(inertia),
        float(parts["crank_unbalance"] or 0.0),
        float(sharing),
        float(lumped_over.get("reciprocating", math.nan)),
        float(lumped_over.get("rotating", math.nan)),
    )
    rec_split, rot_split, dinertia = two_mass_split(*record[:6], length)
    rec = record[6] if not math.isnan(record[6]) else float(rec_split)
    rot = record[7] if not math.isnan(record[7]) else float(rot_split)
    return rec, rot, float(dinertia), record


def _link_error(
    doc: SourceDocument, path: tuple[str | int, ...], message: str, valid: str
) -> LayoutError:
    return LayoutError(message, doc.location(path), field=dotted_path(path), valid=valid)


_SHARED = "a link cylinder shares its master's throw and z (CONTRACT §5)"


def _link_masters(
    spec: LayoutSpec, doc: SourceDocument, cylinders: list[CylinderSpec]
) -> list[int]:
    """Index of each cylinder's master (-1 for none), with every check that needs the
    other cylinders: the master exists, is not itself a link cylinder, and shares throw and
    z; a link cylinder gives no crank radius or conrod length of its own."""
    n = len(cylinders)
    out = [-1] * n
    for i, cyl in enumerate(cylinders):
        if cyl.link is None:
            continue
        at = ("cylinders", i, "link")
        k = cyl.link.master
        if k > n:
            raise _link_error(
                doc,
                (*at, "master"),
                f"master {k} is not a cylinder of this layout (cylinder {i + 1})",
                f"the number of the cylinder whose rod carries this link rod, 1 to {n}",
            )
        if k == i + 1:
            raise _link_error(
                doc,
                (*at, "master"),
                f"cylinder {i + 1} names itself as its master",
                "name the cylinder whose rod carries this link rod",
            )
        master = cylinders[k - 1]
        if master.link is not None:
            raise _link_error(
                doc,
                (*at, "master"),
                f"cylinder {k} is itself a link cylinder (its rod hangs on cylinder "
                f"{master.link.master}'s); cylinder {i + 1} cannot hang on it",
                "a master's rod runs on the crank pin: name a cylinder without a link entry",
            )
        throw_here = cyl.throw_angle % 360.0
        throw_master = master.throw_angle % 360.0
        gap = abs((throw_here - throw_master + 180.0) % 360.0 - 180.0)
        if gap > 1e-9:
            key = "throw" if cyl.throw is not None else "tdc"
            raise _link_error(
                doc,
                ("cylinders", i, key),
                f"cylinder {i + 1} hangs on cylinder {k}'s rod but its throw is "
                f"{throw_here:.6g} deg, the master's {throw_master:.6g} deg",
                _SHARED,
            )
        if abs(cyl.z - master.z) > 1e-12:
            raise _link_error(
                doc,
                ("cylinders", i, "z"),
                f"cylinder {i + 1} hangs on cylinder {k}'s rod but its z is "
                f"{cyl.z * 1e3:.6g} mm, the master's {master.z * 1e3:.6g} mm",
                _SHARED,
            )
        for key in ("stroke", "crank_radius"):
            if getattr(cyl, key) is not None:
                raise _link_error(
                    doc,
                    ("cylinders", i, key),
                    f"'{key}' on link cylinder {i + 1}: its crank radius is its master's "
                    f"(cylinder {k})",
                    "leave it out; a link piston's actual stroke is in the analysis' "
                    "'cylinders' list",
                )
        if cyl.conrod_length is not None:
            raise _link_error(
                doc,
                ("cylinders", i, "conrod_length"),
                f"'conrod_length' on link cylinder {i + 1}",
                "give the link rod's length as link.length (geometry.conrod_length and "
                "conrod_length are master rods' lengths)",
            )
        out[i] = k - 1
    return out


def _check_link_masses(
    spec: LayoutSpec, doc: SourceDocument, cyl: CylinderSpec, i: int, where: Any
) -> None:
    """A link cylinder's masses are given by part, its link rod's in its own entry."""
    at = ("cylinders", i)
    for key in LUMPED_KEYS:
        if getattr(cyl, key) is not None:
            loc, name = where(i, key)
            raise LayoutError(
                f"lumped '{key}' on link cylinder {i + 1}: its rod's lower end moves with the "
                "master rod, not on the crank circle",
                loc,
                field=name,
                valid="give its piston_group, conrod (the link rod), conrod_cg_to_big_end "
                "(from the link pin) and optional conrod_inertia",
            )
    if not spec.masses.by_part:
        raise LayoutError(
            f"cylinder {i + 1} has a link rod, but the engine's masses are lumped",
            doc.location((*at, "link")),
            field=dotted_path((*at, "link")),
            valid="give masses by part (piston_group, conrod, conrod_cg_to_big_end) and each "
            "link rod's conrod and conrod_cg_to_big_end in its cylinder's entry",
        )
    for key in ("conrod", "conrod_cg_to_big_end"):
        if getattr(cyl, key) is None:
            raise LayoutError(
                f"link cylinder {i + 1} gives no '{key}' of its link rod",
                doc.location(at),
                field=dotted_path((*at, key)),
                valid="give the link rod's conrod (mass) and conrod_cg_to_big_end (its centre "
                "of gravity from the link pin) in this cylinder's entry",
            )
    if spec.masses.conrod_inertia is not None and cyl.conrod_inertia is None:
        raise LayoutError(
            f"link cylinder {i + 1} gives no conrod_inertia of its link rod",
            doc.location(at),
            field=dotted_path((*at, "conrod_inertia")),
            valid="the engine-wide conrod_inertia is the master rods'; give the link rod's in "
            "this cylinder's entry (or leave conrod_inertia out everywhere)",
        )


def _links(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    masters: list[int],
    arrays: dict[str, FloatArray],
) -> Links | None:
    """The :class:`~balance.core.engine.Links` of the file (None without link entries),
    with the link rods' reach checked: a link rod must be longer than its link pin's
    largest distance across its bore, or the mechanism cannot move."""
    if all(m < 0 for m in masters):
        return None
    from balance.core.links import link_geometry, link_reach

    n = len(cylinders)
    links = Links(
        master=np.asarray(masters, dtype=np.intp),
        pin_radius=np.asarray(
            [c.link.pin_radius if c.link is not None else 0.0 for c in cylinders], dtype=np.float64
        ),
        pin_angle=np.asarray(
            [math.radians(c.link.pin_angle) if c.link is not None else 0.0 for c in cylinders],
            dtype=np.float64,
        ),
    )
    # the masters are plain cylinders: their crank sliders were checked with the others
    geometry = link_geometry(
        arrays["crank_radius"], arrays["conrod_length"], arrays["offset"], arrays["bank"], links
    )
    reach = link_reach(geometry)
    for row, j in enumerate(geometry.cylinder.tolist()):
        if not reach[row] < 1.0:
            link = cylinders[j].link
            assert link is not None
            across = reach[row] * link.length if math.isfinite(reach[row]) else math.inf
            raise _link_error(
                doc,
                ("cylinders", j, "link", "length"),
                f"link rod of cylinder {j + 1} ({link.length * 1e3:.6g} mm) cannot reach its "
                f"piston: its link pin swings {across * 1e3:.6g} mm across the bore axis",
                "length must exceed the link pin's largest distance from the bore axis "
                "(about crank radius + pin_radius + |offset|); lengthen the link rod or "
                "shorten pin_radius",
            )
    assert n == links.master.size
    return links


def _pitch(spec: LayoutSpec, z: FloatArray) -> float:
    if spec.pitch is not None:
        return float(spec.pitch)
    if spec.crank is not None and len(spec.crank.throws) > 1 and spec.crank.spacing:
        return float(spec.crank.spacing)
    distinct = np.unique(np.round(z, 12))
    if distinct.size < 2:
        return math.nan
    return float((distinct[-1] - distinct[0]) / (distinct.size - 1))


def _firing_order(spec: LayoutSpec, n: int, doc: SourceDocument) -> tuple[int, ...] | None:
    if spec.firing_order is None:
        return None
    order = tuple(spec.firing_order)
    if sorted(order) != list(range(1, n + 1)):
        raise LayoutError(
            f"firing_order {list(order)} is not an ordering of cylinders 1 to {n}",
            doc.location(("firing_order",)),
            field="firing_order",
            valid=f"list each cylinder number 1..{n} once",
        )
    return order


# ---------------------------------------------------------------------------------------
# expansion to the explicit form


def _fmt(value: float, unit: str, scale: float = 1.0) -> str:
    number = value * scale
    text = f"{number:.10g}"
    if text in {"-0", "-0.0"}:
        text = "0"
    return f"{text} {unit}"


def expand_layout(source: str | Path) -> str:
    """The layout written in the explicit form (one entry per cylinder), as YAML text.

    Compact forms are expanded; throws are given (``tdc`` is converted); every other
    section is kept as validated, in SI values with units.
    """
    import yaml

    spec, layout = _build(_read_document(source))
    cylinders, _ = _cylinders(spec)
    out: dict[str, Any] = {"name": spec.name}
    if spec.description:
        out["description"] = spec.description
    if spec.source:
        out["source"] = spec.source
    out["speed"] = _fmt(rad_per_s_to_rpm(spec.speed), "rpm")
    out["cycle"] = spec.cycle
    geometry: dict[str, str] = {}
    g = spec.geometry
    if g.stroke is not None:
        geometry["stroke"] = _fmt(g.stroke, "mm", 1e3)
    else:
        geometry["crank_radius"] = _fmt(g.radius, "mm", 1e3)
    if g.bore is not None:
        geometry["bore"] = _fmt(g.bore, "mm", 1e3)
    geometry["conrod_length"] = _fmt(g.conrod_length, "mm", 1e3)
    geometry["offset"] = _fmt(g.offset, "mm", 1e3)
    out["geometry"] = geometry
    out["masses"] = _masses_dict(spec.masses.model_dump(exclude_none=True))
    entries = []
    for cyl in cylinders:
        entry: dict[str, Any] = {
            "throw": _fmt(_wrap_deg(cyl.throw_angle), "deg"),
            "bank": _fmt(cyl.bank, "deg"),
            "z": _fmt(cyl.z, "mm", 1e3),
        }
        over = cyl.model_dump(exclude_none=True, exclude={"throw", "tdc", "bank", "z", "link"})
        entry.update(_masses_dict(over))
        if cyl.link is not None:
            entry["link"] = {
                "master": int(cyl.link.master),
                "pin_radius": _fmt(cyl.link.pin_radius, "mm", 1e3),
                "pin_angle": _fmt(cyl.link.pin_angle, "deg"),
                "length": _fmt(cyl.link.length, "mm", 1e3),
            }
        entries.append(entry)
    out["cylinders"] = entries
    out["reference_z"] = _fmt(layout.reference_z, "mm", 1e3)
    if math.isfinite(layout.pitch):
        out["pitch"] = _fmt(layout.pitch, "mm", 1e3)
    if layout.firing_order:
        out["firing_order"] = list(layout.firing_order)
    if spec.balance is not None:
        out["balance"] = _balance_dict(spec.balance)
    if spec.gas is not None:
        out["gas"] = _gas_dict(spec.gas, layout.path)
    if spec.flywheel is not None:
        fly: dict[str, str] = {}
        if spec.flywheel.inertia is not None:
            fly["inertia"] = _fmt(spec.flywheel.inertia, "kg m^2")
        if spec.flywheel.speed_fluctuation is not None:
            fly["speed_fluctuation"] = _fmt(spec.flywheel.speed_fluctuation, "%", 100)
        out["flywheel"] = fly
    if spec.mounts is not None:
        out["mounts"] = spec.mounts  # as written (validated in _build)
    if spec.bearings is not None:  # the mains used: the section's, or the defaults
        mains = layout.section("bearings")
        assert mains is not None
        out["bearings"] = {"mains": [_fmt(z, "mm", 1e3) for z in mains]}

    class _Dumper(yaml.SafeDumper):
        pass

    def _flow_dict(dumper: yaml.SafeDumper, data: dict[str, Any]) -> Any:
        flow = ("throw" in data or "master" in data or "speed_ratio" in data) and all(
            not isinstance(v, list) and (not isinstance(v, dict) or "master" in v)
            for v in data.values()
        )
        return dumper.represent_mapping("tag:yaml.org,2002:map", data, flow_style=flow)

    _Dumper.add_representer(dict, _flow_dict)
    header = f"# {spec.name}: explicit form"
    if layout.path:
        header += f" of {layout.path}"
    return (
        header
        + "\n"
        + yaml.dump(out, Dumper=_Dumper, sort_keys=False, width=100, allow_unicode=True)
        + _link_comments(layout)
    )


def _link_comments(layout: Engine) -> str:
    """YAML comments with each cylinder's actual stroke and TDC for an engine with link
    rods (computed, so not part of the layout)."""
    if not layout.has_links:
        return ""
    assert layout.links is not None
    from balance.core.links import dead_centres

    stroke, tdc = dead_centres(
        layout.throw,
        layout.bank,
        layout.crank_radius,
        layout.conrod_length,
        layout.offset,
        layout.links,
    )
    lines = ["# articulated rods: each cylinder's actual stroke and top dead centre (computed)"]
    for i in range(layout.n_cylinders):
        m = int(layout.links.master[i])
        rod = f"link rod on cylinder {m + 1}'s rod" if m >= 0 else "rod on the crank pin"
        lines.append(
            f"#   cylinder {i + 1}: {rod}; stroke {stroke[i] * 1e3:.6g} mm, "
            f"TDC at {math.degrees(tdc[i]):.6g} deg"
        )
    return "\n".join(lines) + "\n"


def _wrap_deg(angle: float) -> float:
    wrapped = math.fmod(angle, 360.0)
    if wrapped < 0:
        wrapped += 360.0
    return 0.0 if wrapped == 360.0 else wrapped


_MASS_UNITS = {
    "reciprocating": ("kg", 1.0),
    "rotating": ("kg", 1.0),
    "piston_group": ("kg", 1.0),
    "conrod": ("kg", 1.0),
    "crank_unbalance": ("kg", 1.0),
    "conrod_cg_to_big_end": ("mm", 1e3),
    "conrod_inertia": ("kg m^2", 1.0),
    "stroke": ("mm", 1e3),
    "crank_radius": ("mm", 1e3),
    "conrod_length": ("mm", 1e3),
    "offset": ("mm", 1e3),
}


def _masses_dict(values: dict[str, float]) -> dict[str, str]:
    return {k: _fmt(v, *_MASS_UNITS[k]) for k, v in values.items() if k in _MASS_UNITS}


def _gas_dict(gas: Any, path: str | None) -> dict[str, Any]:
    """The gas section with units; a trace path made absolute, so that the expanded text
    stands on its own wherever it is saved."""
    out: dict[str, Any] = {}
    if gas.pressure_trace is not None:
        trace = Path(gas.pressure_trace)
        if not trace.is_absolute() and path is not None:
            trace = (Path(path).resolve().parent / trace).resolve()
        out["pressure_trace"] = str(trace)
    if gas.model is not None:
        units = {
            "intake_pressure": ("bar", 1e-5),
            "exhaust_pressure": ("bar", 1e-5),
            "peak_pressure": ("bar", 1e-5),
            "combustion_start": ("deg", 1.0),
            "combustion_duration": ("deg", 1.0),
            "heat_released": ("J", 1.0),
        }
        model: dict[str, Any] = {}
        for key, value in gas.model.model_dump(exclude_none=True).items():
            if key in units:
                model[key] = _fmt(value, units[key][0], units[key][1])
            else:
                model[key] = float(value)
        out["model"] = model
    out["crankcase_pressure"] = _fmt(gas.crankcase_pressure, "bar", 1e-5)
    if gas.bore is not None:
        out["bore"] = _fmt(gas.bore, "mm", 1e3)
    return out


def _balance_dict(settings: BalanceSpec) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if settings.counterweight_radius is not None:
        out["counterweight_radius"] = _fmt(settings.counterweight_radius, "mm", 1e3)
    if settings.balance_factor is not None:
        out["balance_factor"] = _fmt(settings.balance_factor, "%", 100)
    if settings.orders is not None:
        out["orders"] = list(settings.orders)
    out["strategy"] = settings.strategy
    if settings.shafts is not None:
        out["shafts"] = [
            {"speed_ratio": s.speed_ratio}
            | ({} if s.x is None else {"x": _fmt(s.x, "mm", 1e3)})
            | ({} if s.y is None else {"y": _fmt(s.y, "mm", 1e3)})
            for s in settings.shafts
        ]
    return out
