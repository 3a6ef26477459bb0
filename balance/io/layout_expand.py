"""The layout writer: ``balance layout expand``, a layout in the explicit form.

:func:`expand_layout` reads a layout (:mod:`balance.io.layout_reader`) and writes it back
as YAML with one entry per cylinder: the compact ``crank:`` form expanded (a compact
``link:`` into each link cylinder's ``link`` entry and rod parts), every cylinder's throw
angle as the file gives it (``throw``, or its ``tdc``, which without a firing order places
its firing) and the crank throw it is on (``throw_id``: the file's, or numbered along the
file), and every other section as validated, in SI values written with the units of the
table of fields (:mod:`balance.io.layout_fields`), each number with the fewest digits that
read back to the same float.  The expansion is the same engine: analysed, it gives the
file's numbers bit for bit, and expanded again, the same text.  Each concern section writes
its own part (:mod:`balance.io.layout_sections`).  The format is in docs/layout-format.md,
"Seeing the expansion".
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from balance.core.engine import Engine
from balance.io.layout_fields import layout_field, written
from balance.io.layout_reader import build_layout, cylinder_entries, read_document
from balance.io.layout_sections import section_keys, section_reader
from balance.io.several_cranks import expand_part
from balance.io.spec_blocks import CoreSpec

if TYPE_CHECKING:
    from balance.io.schema_options import GasSpec

__all__ = ["expand_layout"]


def expand_layout(source: str | Path) -> str:
    """The layout written in the explicit form (one entry per cylinder), as YAML text.

    Compact forms are expanded; every cylinder gives its throw angle (``throw``, or the
    ``tdc`` the file gives) and its crank throw (``throw_id``); every other section is kept
    as validated, in SI values with units.  Read back, the text is the same engine.

    Parameters
    ----------
    source : str or path-like
        A layout file, or the name of a built-in layout.

    Returns
    -------
    str
        YAML, headed by a comment naming the layout (and, for an engine with link rods,
        followed by comments with each cylinder's actual stroke and TDC).

    Raises
    ------
    LayoutError
        If the layout is not valid (as :func:`balance.io.layout_reader.load_layout`).
    """
    import yaml

    doc = read_document(source)
    spec, layout = build_layout(doc)
    cylinders, _ = cylinder_entries(spec)
    out: dict[str, Any] = {"name": spec.name}
    if spec.description:
        out["description"] = spec.description
    if spec.source:
        out["source"] = spec.source
    out["speed"] = written(spec.speed, "speed", exact=True)
    out["cycle"] = spec.cycle
    if spec.crossheads:  # docs/crossheads.md
        out["crossheads"] = True
    geometry: dict[str, str] = {}
    g = spec.geometry
    if g.stroke is not None:
        geometry["stroke"] = _written("stroke", g.stroke)
    else:
        geometry["crank_radius"] = _written("crank_radius", g.radius)
    if g.bore is not None:
        geometry["bore"] = _written("bore", g.bore)
    geometry["conrod_length"] = _written("conrod_length", g.conrod_length)
    geometry["offset"] = _written("offset", g.offset)
    out["geometry"] = geometry
    out["masses"] = _fields_dict(spec.masses.model_dump(exclude_none=True))
    shafts, shaft_rows, notes = expand_part(spec, layout)  # several crankshafts
    out.update(shafts)
    entries = []
    assert layout.throw_index is not None
    for i, cyl in enumerate(cylinders):
        # a tdc stays a tdc: without a firing order it places the cylinder's firing (mod 720)
        angle = ("tdc", cyl.tdc) if cyl.tdc is not None else ("throw", cyl.throw_angle)
        entry: dict[str, Any] = {
            angle[0]: _written(angle[0], angle[1]),
            "bank": _written("bank", cyl.bank),
            "z": _written("z", cyl.z),
            "throw_id": cyl.throw_id
            if cyl.throw_id is not None and not shafts
            else int(layout.throw_index[i]) + 1,
            **shaft_rows[i],
        }
        over = cyl.model_dump(
            exclude_none=True,
            exclude={"throw", "tdc", "bank", "z", "throw_id", "link", "crankshaft", "opposed"},
        )
        entry.update(_fields_dict(over))
        if cyl.link is not None:
            entry["link"] = {
                "master": int(cyl.link.master),
                "pin_radius": written(cyl.link.pin_radius, "length", exact=True),
                "pin_angle": written(cyl.link.pin_angle, "angle", exact=True),
                "length": written(cyl.link.length, "length", exact=True),
            }
        entries.append(entry)
    out["cylinders"] = entries
    out["reference_z"] = _written("reference_z", layout.reference_z)
    # the pitch made explicit: with several crank axes only a pitch the file gives (the
    # engine-wide spacing of its cylinders is no shaft's throw pitch, and each shaft's
    # default mains take the layout's pitch only where it is given)
    if math.isfinite(layout.pitch) and (layout.pitch_given or not layout.geared):
        out["pitch"] = written(layout.pitch, "length", exact=True)
    if layout.firing_order:
        out["firing_order"] = list(layout.firing_order)
    if spec.balance is not None:
        out["balance"] = _core_dict(spec.balance)
    if spec.gas is not None:
        out["gas"] = _gas_dict(spec.gas, layout.path)
    if spec.flywheel is not None:
        fly: dict[str, str] = {}
        if spec.flywheel.inertia is not None:
            fly["inertia"] = written(spec.flywheel.inertia, "inertia", exact=True)
        if spec.flywheel.speed_fluctuation is not None:
            fly["speed_fluctuation"] = written(
                spec.flywheel.speed_fluctuation, "fraction", exact=True
            )
        out["flywheel"] = fly
    for key, value in layout.sections.items():  # each concern section writes its own
        if key in section_keys():  # not the flywheel of a crank that coasts: written above
            out[key] = section_reader(key).expand(doc.data[key], value)

    class _Dumper(yaml.SafeDumper):
        pass

    def _flow_dict(dumper: yaml.SafeDumper, data: dict[str, Any]) -> Any:
        keys = ("throw_id", "master", "speed_ratio", "rotation")
        flow = any(k in data for k in keys) and all(
            not isinstance(v, list) and (not isinstance(v, dict) or "master" in v)
            for v in data.values()
        )
        return dumper.represent_mapping("tag:yaml.org,2002:map", data, flow_style=flow)

    _Dumper.add_representer(dict, _flow_dict)
    header = f"# {spec.name}: explicit form"
    if layout.path:
        header += f" of {layout.path}"

    def dumped(keys: list[str]) -> str:
        part = {k: out[k] for k in keys}
        if not part:
            return ""
        return yaml.dump(part, Dumper=_Dumper, sort_keys=False, width=100, allow_unicode=True)

    keys = list(out)
    at = keys.index("cylinders")
    return (
        header
        + "\n"
        + dumped(keys[:at])
        + _cylinders_text(out["cylinders"], notes=notes)
        + dumped(keys[at + 1 :])
        + _link_comments(layout)
    )


def _flow(value: Any) -> str:
    """A value of a cylinder's entry in YAML's flow style, on one line."""
    import yaml

    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_flow(v)}" for k, v in value.items()) + "}"
    # the cylinders of a layout repeat the same texts: each is dumped once (the key tells
    # -0.0 from 0.0 and 1 from 1.0 and True, which are equal as keys of their own)
    key = (type(value), repr(value))
    text = _FLOWN.get(key)
    if text is None:
        dumped = yaml.safe_dump([value], default_flow_style=True, width=10**9, allow_unicode=True)
        text = _FLOWN[key] = dumped.strip()[1:-1]
        if len(_FLOWN) > 4096:
            _FLOWN.clear()
    return text


#: :func:`_flow`'s texts of the values it dumped, by type and ``repr``.
_FLOWN: dict[tuple[type, str], str] = {}


def _cylinders_text(
    entries: list[dict[str, Any]], width: int = 100, notes: list[str] | None = None
) -> str:
    """The ``cylinders:`` list, one flow mapping per cylinder, broken between its keys (a
    link entry kept whole) where a line would pass ``width`` columns; a cylinder's note
    (``notes``) as a comment on the line before it."""
    lines = ["cylinders:"]
    for k, entry in enumerate(entries):
        if notes and notes[k]:
            lines.append(f"# cylinder {k + 1}: {notes[k]}")
        items = [f"{k}: {_flow(v)}" for k, v in entry.items()]
        line = "- {"
        for j, item in enumerate(items):
            piece = item + ("}" if j == len(items) - 1 else ",")
            if j and len(line) + 1 + len(piece) > width:
                lines.append(line)
                line = "    " + piece
            else:
                line += (" " if j else "") + piece
        lines.append(line)
    return "\n".join(lines) + "\n"


def _written(name: str, value: float) -> str:
    """A value of the field ``name`` in its unit (:mod:`balance.io.layout_fields`)."""
    return written(value, layout_field(name).kind, exact=True)


def _fields_dict(values: dict[str, float]) -> dict[str, str]:
    """Fields of the table (``masses:``, a cylinder's overrides) with their units."""
    return {k: _written(k, v) for k, v in values.items()}


def _core_dict(spec: CoreSpec) -> dict[str, Any]:
    """A section that is a dataclass of :mod:`balance.core` (``balance:``, ``gas: model:``):
    its fields given, in order, each quantity in its kind's unit and each nested section
    likewise."""
    out: dict[str, Any] = {}
    assert spec.core_type is not None
    for f in dataclasses.fields(spec.core_type):
        value = getattr(spec, f.name)
        if value is None:
            continue
        kind = spec.core_kinds.get(f.name)
        if kind is not None:
            out[f.name] = written(value, kind, exact=True)
        elif isinstance(value, list):
            out[f.name] = [_core_dict(v) if isinstance(v, CoreSpec) else v for v in value]
        elif isinstance(value, CoreSpec):
            out[f.name] = _core_dict(value)
        else:
            out[f.name] = value
    return out


def _gas_dict(gas: GasSpec, path: str | None) -> dict[str, Any]:
    """The gas section with units; a trace path made absolute, so that the expanded text
    stands on its own wherever it is saved."""
    out: dict[str, Any] = {}
    if gas.pressure_trace is not None:
        trace = Path(gas.pressure_trace)
        if not trace.is_absolute() and path is not None:
            trace = (Path(path).resolve().parent / trace).resolve()
        out["pressure_trace"] = str(trace)
    if gas.model is not None:
        out["model"] = _core_dict(gas.model)
    out["crankcase_pressure"] = written(gas.crankcase_pressure, "pressure", exact=True)
    if gas.bore is not None:
        out["bore"] = written(gas.bore, "length", exact=True)
    return out


def _link_comments(layout: Engine) -> str:
    """YAML comments with each cylinder's actual stroke and TDC for an engine with link
    rods (computed, so not part of the layout)."""
    if not layout.has_links:
        return ""
    assert layout.links is not None
    from balance.core.cylinders import engine_dead_centres

    # each cylinder at its own crank angle from TDC (several crankshafts: its shaft's sense)
    stroke, tdc = engine_dead_centres(layout)
    lines = ["# articulated rods: each cylinder's actual stroke and top dead centre (computed)"]
    for i in range(layout.n_cylinders):
        m = int(layout.links.master[i])
        rod = f"link rod on cylinder {m + 1}'s rod" if m >= 0 else "rod on the crank pin"
        lines.append(
            f"#   cylinder {i + 1}: {rod}; stroke {stroke[i] * 1e3:.6g} mm, "
            f"TDC at {math.degrees(tdc[i]):.6g} deg"
        )
    return "\n".join(lines) + "\n"
