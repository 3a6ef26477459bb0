"""The layout reader: a layout file's YAML -> its validated models -> an :class:`Engine`.

:func:`load_layout` returns a :class:`~balance.core.engine.Engine`: one entry per cylinder
in numpy arrays, SI units (radians for angles).  Loading validates the file
(:mod:`balance.io.schema`, and each concern section's own model,
:mod:`balance.io.layout_sections`), expands the compact ``crank:`` form, applies
per-cylinder overrides, derives the lumped masses from parts where parts are given, checks
that the geometry can exist, and builds each concern section into
:attr:`~balance.core.engine.Engine.sections`, so that the physics never sees a unit string
or an impossible value.  Every problem of a file is reported at once, each as one
:class:`~balance.core.errors.LayoutError` naming file, line, column, field and what would
be valid (:mod:`balance.io.located`; docs/layout-format.md).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
from numpy.typing import NDArray
from pydantic import create_model

from balance.core.engine import CYLINDER_FIELDS, Engine, Links, PerCylinder, bore_pitch
from balance.core.errors import LayoutError, LayoutErrors, Location, raise_all
from balance.core.masses import MassParts, two_mass_split
from balance.core.throws import rods_per_throw
from balance.io.layout_fields import GEOMETRY_KEYS, LUMPED_KEYS, PART_KEYS, layout_field
from balance.io.layout_sections import section_keys, section_reader
from balance.io.layout_throws import throw_index
from balance.io.layouts import layout_path
from balance.io.located import problem_error, validate
from balance.io.problems import FieldProblem, FieldProblems
from balance.io.schema import (
    LAYOUT_HINTS,
    SETTINGS_FIELDS,
    CrankSpec,
    CylinderSpec,
    LayoutSpec,
    LinkSpec,
    settings_models,
)
from balance.io.several_cranks import attach, blocks, check_bores, expand_block, resolve
from balance.io.traces import read_pressure_trace
from balance.io.yamlsource import SourceDocument, dotted_path, parse_yaml, read_yaml_file

if TYPE_CHECKING:
    from balance.core.gas import GasInput

__all__ = [
    "build_layout",
    "cylinder_entries",
    "layout_from_dict",
    "layout_from_text",
    "load_layout",
    "read_document",
]

FloatArray = NDArray[np.float64]
#: The rod parts a compact ``link:`` gives every link rod.
ROD_KEYS = ("conrod", "conrod_cg_to_big_end", "conrod_inertia")


def load_layout(source: str | Path) -> Engine:
    """Load a layout from a file path or a built-in layout name.

    Parameters
    ----------
    source : str or path-like
        A YAML file, or the name of a built-in layout such as ``"inline-4"``
        (see :func:`balance.io.layouts.builtin_layout_names`).

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
    return build_layout(read_document(source))[1]


def read_document(source: str | Path) -> SourceDocument:
    """The parsed YAML of a layout file or built-in layout name
    (:func:`balance.io.layouts.layout_path`), with the line and column of every value.

    Parameters
    ----------
    source : str or path-like
        A YAML file, or the name of a built-in layout.

    Returns
    -------
    SourceDocument

    Raises
    ------
    InputError
        If the file cannot be found or read, or is no YAML.
    """
    return read_yaml_file(layout_path(source), source, "layout file")


def layout_from_text(text: str, file: str = "<input>") -> Engine:
    """Build a layout from YAML text (see :func:`load_layout`).

    Parameters
    ----------
    text : str
        The layout file's text.
    file : str
        The name the messages give the text.

    Returns
    -------
    Engine

    Raises
    ------
    LayoutError
        For every problem of the text (several at once as
        :class:`~balance.core.errors.LayoutErrors`).
    """
    return build_layout(parse_yaml(text, file))[1]


def layout_from_dict(data: dict[str, Any], file: str = "<dict>") -> Engine:
    """Build a layout from plain data shaped like a layout file, read by the file's rules:
    a dimensional quantity is text with its unit (``"86 mm"``); a bare number other than 0
    is refused, as in a file (see :func:`load_layout`).

    Parameters
    ----------
    data : dict
        The layout's keys and values, as YAML would give them.
    file : str
        The name the messages give the data.

    Returns
    -------
    Engine

    Raises
    ------
    LayoutError
        For every problem of the data.
    """
    return build_layout(SourceDocument(data=data, file=file))[1]


def _specs(doc: SourceDocument) -> tuple[LayoutSpec | None, dict[str, Any], list[LayoutError]]:
    """The file's model, the models of its concern sections by key, and every problem of
    their validation (the file's model None when it has problems)."""
    if not isinstance(doc.data, dict):
        kind = type(doc.data).__name__
        raise LayoutError(
            f"the document is a {'list' if kind == 'list' else 'single value'}, not a mapping",
            doc.location(()),
            valid="a layout is a mapping with name, speed, geometry, masses and cylinders",
        )
    keys = section_keys()
    rest = {k: v for k, v in doc.data.items() if k not in keys}
    spec: LayoutSpec | None = _valid_spec(rest)
    problems: list[LayoutError] = []
    if spec is None:  # report the problems as the whole layout's model finds them
        settings_models()
        spec, problems = validate(LayoutSpec, rest, doc, hints=LAYOUT_HINTS, also=keys)
    sections: dict[str, Any] = {}
    for key in keys:
        if key not in doc.data:
            continue
        reader = section_reader(key)
        given = doc.data[key] if doc.data[key] is not None else {}  # "key:" alone: defaults
        section, found = validate(reader.spec, given, doc, (key,), reader.hints)
        problems += found
        if section is not None:
            sections[key] = section
    return spec, sections, problems


def _valid_spec(rest: dict[str, Any]) -> LayoutSpec | None:
    """The layout's model, validated by the model of the optional sections it has
    (:func:`_spec_without`), or None when that finds a problem (which the caller reports
    as :class:`~balance.io.schema.LayoutSpec` finds it)."""
    absent = frozenset(
        name
        for name, info in LayoutSpec.model_fields.items()
        if name not in rest and info.default is None and not info.is_required()
    )
    if not absent >= SETTINGS_FIELDS:
        settings_models()
    try:
        return _spec_without(absent).model_validate(rest)
    except Exception:
        return None


@functools.cache
def _spec_without(absent: frozenset[str]) -> type[LayoutSpec]:
    """:class:`~balance.io.schema.LayoutSpec` with each optional field of ``absent`` (default
    None) of type None.

    pydantic builds a model's validator on first use, nested models and all, and a layout
    has few of the optional sections (``cylinders:`` or ``crank:``, ``balance:``, ``gas:``,
    ``flywheel:``, ``crankshafts:``, ``output:``).  For a layout without the fields of
    ``absent``, this subclass validates and gives what :class:`LayoutSpec` would (an absent
    field keeps its default and is not validated; the fields keep their order), with a
    smaller validator to build.
    """
    if not absent:
        return LayoutSpec
    fields: dict[str, Any] = {name: (None, None) for name in absent}
    return create_model(
        "LayoutSpec", __base__=LayoutSpec, __module__=LayoutSpec.__module__, **fields
    )


def cylinder_entries(
    spec: LayoutSpec,
) -> tuple[list[CylinderSpec], tuple[str | int, ...] | None]:
    """The file's cylinders in the explicit form (the compact form expanded).

    Parameters
    ----------
    spec : LayoutSpec
        A validated layout file.

    Returns
    -------
    list of CylinderSpec
        One entry per cylinder, in file order.
    tuple or None
        The path of the entries in the file (``("cylinders",)``), or None for the compact
        form (whose cylinders have no entries of their own).
    """
    if spec.cylinders is not None:
        return list(spec.cylinders), ("cylinders",)
    cylinders: list[CylinderSpec] = []
    for block, path in blocks(spec):  # several blocks: docs/layout-format.md, "Several ..."
        cylinders += expand_block(spec, block, path, len(cylinders), _expand_crank, CylinderSpec)
    return cylinders, None


def _expand_crank(crank: CrankSpec) -> list[CylinderSpec]:
    """The compact form's cylinders, throw-major, each with its throw's ``throw_id`` and
    with a compact ``link:``, every link bank's link entry and link-rod parts."""
    split = crank.split if crank.split is not None else [0.0] * len(crank.banks)
    rotation = crank.row_rotation or [0.0] * len(crank.throws)
    spacing = crank.spacing or 0.0
    link = crank.link
    n_banks = len(crank.banks)
    master = link.master - 1 if link is not None else -1
    rod = link.overrides(ROD_KEYS) if link is not None else {}
    cylinders = []
    for t, throw in enumerate(crank.throws):
        for j, bank in enumerate(crank.banks):
            # values already read and checked (SI): constructed, not read again
            values: dict[str, Any] = {
                "throw": throw + split[j],
                "bank": bank + rotation[t] if rotation[t] else bank,
                "z": t * spacing + j * crank.bank_stagger,
                "throw_id": t + 1,
            }
            if link is not None and j != master:
                k = j if j < master else j - 1
                angles = link.pin_angles
                values["link"] = LinkSpec.model_construct(
                    master=t * n_banks + master + 1,
                    pin_radius=link.pin_radius,
                    pin_angle=angles[k] if angles is not None else bank - crank.banks[master],
                    length=link.length,
                )
                values.update(rod)
            cylinders.append(CylinderSpec.model_construct(**values))
    return cylinders


def _entry_path(
    prefix: tuple[str | int, ...] | None,
    cylinders: list[CylinderSpec],
    i: int,
    *keys: str,
) -> tuple[str | int, ...]:
    """Where the file gives cylinder ``i``'s ``keys``: its entry of the explicit form; in
    the compact form, a link cylinder's link fields and rod parts in ``crank: link:``
    (``pin_angle`` in ``pin_angles``), anything else at ``crank``."""
    if prefix is not None:
        return (*prefix, i, *keys)
    block = cylinders[i]._block  # ("crank",), or ("crank", b) for several blocks
    if cylinders[i].link is None:
        return block
    rest = keys[1:] if keys[:1] == ("link",) else keys
    if rest[:1] == ("pin_angle",):
        return (*block, "link", "pin_angles")
    if rest and (rest[0] in ROD_KEYS or keys[:1] == ("link",)):
        return (*block, "link", *rest)
    return (*block, "link")


def build_layout(doc: SourceDocument) -> tuple[LayoutSpec, Engine]:
    """The validated file and the engine it describes, its concern sections built.

    Parameters
    ----------
    doc : SourceDocument
        The layout file read (:func:`read_document`).

    Returns
    -------
    LayoutSpec
        The file's model (its concern sections are in the engine's ``sections``).
    Engine

    Raises
    ------
    LayoutError
        With every problem of the file (:class:`~balance.core.errors.LayoutErrors` for
        more than one).
    """
    spec, sections, problems = _specs(doc)
    if spec is None:
        raise_all(problems)
    assert spec is not None
    # every problem of the file, reported together: the sections' models', and below the
    # rest's and the sections' builders'
    section_problems, problems = problems, []
    cylinders, prefix = cylinder_entries(spec)
    n = len(cylinders)
    entry = functools.partial(_entry_path, prefix, cylinders)
    shafts, found = resolve(doc, spec, cylinders, prefix)  # None: one crankshaft
    raise_all(found + section_problems if found else [])
    throws = throw_index(doc, cylinders, prefix, shafts.of_cylinder if shafts else None)
    sharing = rods_per_throw(throws).tolist()
    if n > 256:
        too_many = LayoutError(
            f"{n} cylinders",
            doc.location(("crank",)),
            field="crank",
            valid="at most 256 cylinders",
        )
        raise_all([too_many, *section_problems])

    def where(i: int, key: str) -> tuple[Location, str]:
        if getattr(cylinders[i], key, None) is not None and (
            prefix is not None or cylinders[i].link is not None
        ):
            path = entry(i, key)
            return doc.location(path), dotted_path(path)
        section = layout_field(key).place  # geometry or masses
        return doc.location((section, key)), f"{section}.{key}"

    geometry = spec.geometry
    impossible: dict[tuple[Location, str, str], list[int]] = {}
    masters = _link_masters(doc, cylinders, entry)
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
                spec, doc, cyl, length, i, where, sharing[i], entry
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
    arrays: dict[str, Any] = {k: np.asarray(v, dtype=np.float64) for k, v in values.items()}
    # the link rods' reach needs sound master geometry and masses: checked once they are
    links = None
    if shafts is not None and not problems:
        problems += check_bores(doc, shafts, cylinders, prefix, arrays)
    links_checked = not problems
    if links_checked:
        links = _collect(problems, lambda: _links(doc, cylinders, masters, arrays, entry))
        links_checked = not problems
    z = arrays["z"]
    reference_z = spec.reference_z if spec.reference_z is not None else 0.5 * (z.min() + z.max())
    pitch = _pitch(spec, z, arrays["bank"])
    firing = _collect(problems, lambda: _firing_order(spec, n, doc))
    engine = Engine(
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
        pitch_given=spec.pitch is not None,
        balance=spec.balance.to_core() if spec.balance is not None else None,
        gas=None,
        mass_parts=_mass_parts(part_rows) if part_rows else None,
        sections={},
        links=links,
        throw_index=throws,
        **arrays,
    )
    engine = attach(engine, shafts)  # before the sections, which read it
    gas = None
    if spec.gas is not None and links_checked:
        # each cylinder fires at its own top dead centre: on a crankshaft of its own, at
        # the crank angle of a one-crank cylinder's (Engine.forward_equivalent; the engine
        # itself on one crankshaft)
        forward = engine.forward_equivalent()
        at_tdc = {**arrays, "throw": forward.throw, "bank": forward.bank}
        gas = _collect(
            problems, lambda: _gas(spec, doc, cylinders, prefix, at_tdc, firing, forward.links)
        )
        engine = dataclasses.replace(engine, gas=gas)
    built: dict[str, Any] = {}
    if spec.flywheel is not None and gas is None:  # a crank that coasts (docs/dynamics.md)
        from balance.core.speed_model import Flywheel

        built["flywheel"] = Flywheel(spec.flywheel.inertia, spec.flywheel.speed_fluctuation)
    # crosshead cylinders turn the guide-force section on (docs/crossheads.md)
    crossheads = [
        spec.crossheads or cyl.crosshead is not None or spec.masses.crosshead is not None
        for cyl in cylinders
    ]
    if any(crossheads):
        built["crossheads"] = PerCylinder(np.asarray(crossheads))
    for key, section in sections.items():  # each on the engine read from the rest
        value = _collect(problems, functools.partial(_section, doc, key, section, engine))
        if value is not None:
            built[key] = value
    raise_all(problems + section_problems)
    return spec, dataclasses.replace(engine, sections=built)


def _section(doc: SourceDocument, key: str, section: Any, engine: Engine) -> Any:
    """What the engine's sections hold under ``key``, built from the validated section; a
    problem its builder finds is located below the section's key."""
    try:
        return section_reader(key).build(section, engine)
    except FieldProblem as problem:
        errors = [problem_error(problem, doc, (key,))]
    except FieldProblems as found:
        errors = [problem_error(problem, doc, (key,)) for problem in found.problems]
    raise_all(errors)  # outside the handler: the problem is no part of the report
    raise AssertionError("a builder's problem is reported")  # pragma: no cover


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
    from balance.core.cylinders import dead_centre_lag
    from balance.core.gas import GasInput, cycle_degrees, firing_tdc

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
        model=section.model.to_core() if section.model is not None else None,
        crankcase_pressure=section.crankcase_pressure,
        bore=float(bore),
        firing_tdc=tdc,
        cycle_deg=cycle_deg,
        flywheel_inertia=flywheel.inertia if flywheel is not None else None,
        speed_fluctuation=flywheel.speed_fluctuation if flywheel is not None else None,
        source=source,
    )


def _cylinder_masses(
    spec: LayoutSpec,
    doc: SourceDocument,
    cyl: CylinderSpec,
    length: float,
    i: int,
    where: Any,
    sharing: float,
    entry: Callable[..., tuple[str | int, ...]],
) -> tuple[float, float, float, tuple[float, ...] | None]:
    """Reciprocating mass, rotating mass, conrod inertia correction of one cylinder, and
    its parts (the fields of :class:`~balance.core.masses.MassParts`; None for lumped masses).

    ``crank_unbalance`` is per throw: each of the ``sharing`` rods on a throw
    (:func:`balance.core.throws.rods_per_throw`) carries its share.
    """
    masses = spec.masses
    part_over = cyl.overrides(PART_KEYS)
    lumped_over = cyl.overrides(LUMPED_KEYS)
    if cyl.link is not None:
        _check_link_masses(spec, doc, cyl, i, where, entry)
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
        return float(rec), float(rot), 0.0, None
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
        sharing,
        float(lumped_over.get("reciprocating", math.nan)),
        float(lumped_over.get("rotating", math.nan)),
        float(parts["piston_rod"] or 0.0),
        float(parts["crosshead"] or 0.0),
    )
    rec_split, rot_split, dinertia = two_mass_split(*record[:6], length, *record[8:])
    rec = record[6] if not math.isnan(record[6]) else float(rec_split)
    rot = record[7] if not math.isnan(record[7]) else float(rot_split)
    return rec, rot, float(dinertia), record


def _link_error(
    doc: SourceDocument, path: tuple[str | int, ...], message: str, valid: str
) -> LayoutError:
    return LayoutError(message, doc.location(path), field=dotted_path(path), valid=valid)


_SHARED = (
    "a link cylinder shares its master's throw and z (docs/layout-format.md, 'Articulated rods')"
)


def _link_masters(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    entry: Callable[..., tuple[str | int, ...]],
) -> list[int]:
    """Index of each cylinder's master (-1 for none), with every check that needs the
    other cylinders: the master exists, is not itself a link cylinder, and shares throw
    and z (and so its crank throw, :mod:`balance.io.layout_throws`); a link cylinder gives
    no crank radius or conrod length of its own."""
    n = len(cylinders)
    out = [-1] * n
    for i, cyl in enumerate(cylinders):
        if cyl.link is None:
            continue
        k = cyl.link.master
        if k > n:
            raise _link_error(
                doc,
                entry(i, "link", "master"),
                f"master {k} is not a cylinder of this layout (cylinder {i + 1})",
                f"the number of the cylinder whose rod carries this link rod, 1 to {n}",
            )
        if k == i + 1:
            raise _link_error(
                doc,
                entry(i, "link", "master"),
                f"cylinder {i + 1} names itself as its master",
                "name the cylinder whose rod carries this link rod",
            )
        master = cylinders[k - 1]
        if master.link is not None:
            raise _link_error(
                doc,
                entry(i, "link", "master"),
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
                entry(i, key),
                f"cylinder {i + 1} hangs on cylinder {k}'s rod but its throw is "
                f"{throw_here:.6g} deg, the master's {throw_master:.6g} deg",
                _SHARED,
            )
        if abs(cyl.z - master.z) > 1e-12:
            raise _link_error(
                doc,
                entry(i, "z"),
                f"cylinder {i + 1} hangs on cylinder {k}'s rod but its z is "
                f"{cyl.z * 1e3:.6g} mm, the master's {master.z * 1e3:.6g} mm",
                _SHARED,
            )
        for key in ("stroke", "crank_radius"):
            if getattr(cyl, key) is not None:
                raise _link_error(
                    doc,
                    entry(i, key),
                    f"'{key}' on link cylinder {i + 1}: its crank radius is its master's "
                    f"(cylinder {k})",
                    "leave it out; a link piston's actual stroke is in the analysis' "
                    "'cylinders' list",
                )
        if cyl.conrod_length is not None:
            raise _link_error(
                doc,
                entry(i, "conrod_length"),
                f"'conrod_length' on link cylinder {i + 1}",
                "give the link rod's length as link.length (geometry.conrod_length and "
                "conrod_length are master rods' lengths)",
            )
        out[i] = k - 1
    return out


def _check_link_masses(
    spec: LayoutSpec,
    doc: SourceDocument,
    cyl: CylinderSpec,
    i: int,
    where: Any,
    entry: Callable[..., tuple[str | int, ...]],
) -> None:
    """A link cylinder's masses are given by part, its link rod's in its own entry."""
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
            doc.location(entry(i, "link")),
            field=dotted_path(entry(i, "link")),
            valid="give masses by part (piston_group, conrod, conrod_cg_to_big_end) and each "
            "link rod's conrod and conrod_cg_to_big_end in its cylinder's entry",
        )
    for key in ("conrod", "conrod_cg_to_big_end"):
        if getattr(cyl, key) is None:
            raise LayoutError(
                f"link cylinder {i + 1} gives no '{key}' of its link rod",
                doc.location(entry(i)),
                field=dotted_path(entry(i, key)),
                valid="give the link rod's conrod (mass) and conrod_cg_to_big_end (its centre "
                "of gravity from the link pin) in this cylinder's entry",
            )
    if spec.masses.conrod_inertia is not None and cyl.conrod_inertia is None:
        raise LayoutError(
            f"link cylinder {i + 1} gives no conrod_inertia of its link rod",
            doc.location(entry(i)),
            field=dotted_path(entry(i, "conrod_inertia")),
            valid="the engine-wide conrod_inertia is the master rods'; give the link rod's in "
            "this cylinder's entry (or leave conrod_inertia out everywhere)",
        )


def _links(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    masters: list[int],
    arrays: dict[str, FloatArray],
    entry: Callable[..., tuple[str | int, ...]],
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
                entry(j, "link", "length"),
                f"link rod of cylinder {j + 1} ({link.length * 1e3:.6g} mm) cannot reach its "
                f"piston: its link pin swings {across * 1e3:.6g} mm across the bore axis",
                "length must exceed the link pin's largest distance from the bore axis "
                "(about crank radius + pin_radius + |offset|); lengthen the link rod or "
                "shorten pin_radius",
            )
    assert n == links.master.size
    return links


def _pitch(spec: LayoutSpec, z: FloatArray, bank: FloatArray) -> float:
    """The layout's ``pitch``, else the bore pitch (docs/conventions.md, "Normalisation and
    ``pitch``"): the compact form's ``spacing`` is the bore pitch of each of its banks
    (unless ``row_rotation`` turns the rows: then its rows' banks are banks of their own,
    as in the expansion)."""
    if spec.pitch is not None:
        return float(spec.pitch)
    given = blocks(spec)
    crank = given[0][0] if len(given) == 1 else None
    turned = crank is not None and any(crank.row_rotation or ())
    if crank is not None and len(crank.throws) > 1 and crank.spacing and not turned:
        return float(crank.spacing)
    return bore_pitch(z, bank)


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
