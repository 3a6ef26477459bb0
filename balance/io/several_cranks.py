r"""Several crankshafts in a layout file: ``crankshafts:``, ``output:``, each cylinder's
``crankshaft`` and ``opposed``, and the compact form's blocks.

The layout reader (:mod:`balance.io.layout_reader`) calls this module at four points:

- :func:`expand_block` expands one block of ``crank:`` (a list of blocks, or one mapping)
  with its ``crankshaft``, ``opposed: [A, B]`` and ``z0``;
- :func:`resolve` checks the names, the crankshafts' own fields and each cylinder's shaft and
  opposed partner, and turns ``tdc`` into a throw in the shaft's own sense,
  :math:`\text{throw} = \sigma_s (\text{bank} - \varphi_s) - \text{tdc}`, before the crank
  throws are grouped (a throw is on one crankshaft: throws of two crankshafts are never one);
- :func:`check_bores` checks each opposed bore's geometry once the cylinders' crank radii
  and rods are known;
- :func:`attach` gives the engine its :class:`~balance.core.crankshafts.Crankshafts`.

Beside the reader: :func:`expand_part` is what ``layout expand`` writes of the crankshafts,
:func:`refuse_unsupported` refuses the analyses not made for several crankshafts (the
torsional analysis, the dynamic speed model), and :func:`shaft_field` and
:func:`shaft_changed` are the studies' fields ``crankshafts.NAME.phase``, ``.x``, ``.y``.

A file without ``crankshafts:`` gives no :class:`Plan` and an engine without crankshafts
(one crankshaft on the ``z`` axis), exactly as before.  The format, its angle rules and every
refusal are in docs/layout-format.md, "Several crankshafts"; the angles in
docs/conventions.md, "Several crankshafts".
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Annotated, Any, TypeAlias

import numpy as np
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from balance.core.errors import LayoutError
from balance.io.problems import FieldProblem
from balance.io.units import parse_quantity
from balance.io.yamlsource import SourceDocument, dotted_path

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.crankshafts import Crankshafts
    from balance.core.engine import Engine

# balance.io.schema's models (it imports this module's, so they are not imported here)
CrankSpec: TypeAlias = Any
CylinderSpec: TypeAlias = Any
LayoutSpec: TypeAlias = Any

__all__ = [
    "SHAFT_FIELDS",
    "CrankshaftSpec",
    "OutputSpec",
    "Plan",
    "attach",
    "blocks",
    "check_bores",
    "check_opposed_block",
    "expand_block",
    "expand_part",
    "refuse_unsupported",
    "resolve",
    "shaft_changed",
    "shaft_field",
]

Path = tuple[str | int, ...]
#: Keys that would give a crankshaft a speed of its own.
SPEED_KEYS = ("speed_ratio", "speed", "ratio", "gear_ratio")
#: How far apart two crankshafts' axes must be [m].
SAME_AXIS = 1e-9
_SENSE = {"same": 1.0, "opposite": -1.0}
# the blocks of balance.io.schema's models, which imports this module's
_Length = Annotated[float, BeforeValidator(lambda value: parse_quantity(value, "length"))]
_Angle = Annotated[float, BeforeValidator(lambda value: parse_quantity(value, "angle"))]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True, strict=True)


class CrankshaftSpec(_Strict):
    """One entry of ``crankshafts:``: its name, the position of its axis, its sense of
    rotation relative to crankshaft 1, and where its reference line points at crank angle 0
    (the checks that need the other crankshafts and the cylinders are :func:`resolve`'s)."""

    name: str = Field(min_length=1, max_length=100)
    x: _Length = 0.0
    y: _Length = 0.0
    rotation: str = "same"
    phase: _Angle = 0.0

    @model_validator(mode="before")
    @classmethod
    def _no_speed(cls, data: Any) -> Any:
        for key in SPEED_KEYS:
            if isinstance(data, dict) and key in data:
                raise FieldProblem(
                    f"'{key}' on a crankshaft",
                    "crankshafts turn at ±1 × crankshaft 1; a shaft at another speed is a "
                    "balance shaft (balance: shafts:); give rotation: same or opposite",
                    (key,),
                )
        return data

    @model_validator(mode="after")
    def _check(self) -> CrankshaftSpec:
        _rotation(self.rotation, "the crankshaft turns with crankshaft 1 or against it")
        return self


class OutputSpec(_Strict):
    """``output:``: the sense of the shaft the load is taken off, relative to crankshaft 1."""

    rotation: str = "same"

    @model_validator(mode="after")
    def _check(self) -> OutputSpec:
        _rotation(
            self.rotation, "the shaft the load is taken off turns with crankshaft 1 or against it"
        )
        return self


def _rotation(value: str, meaning: str) -> None:
    if value not in _SENSE:
        raise FieldProblem(
            f"rotation is '{value}'",
            f"rotation: same or rotation: opposite ({meaning})",
            ("rotation",),
        )


def check_opposed_block(crank: CrankSpec) -> None:
    """Refuse what an ``opposed: [A, B]`` block cannot hold.

    Parameters
    ----------
    crank : CrankSpec
        A block of the compact form with ``opposed``.

    Raises
    ------
    FieldProblem
        For ``crankshaft`` beside ``opposed``, one shaft named twice, or a key that places
        banks (``banks``, ``bank_count``, ``split``, ``bank_stagger``, ``row_rotation``,
        ``link``).
    """
    assert crank.opposed is not None
    if crank.crankshaft is not None:
        raise FieldProblem(
            "give crankshaft or opposed in a block, not both",
            "'crankshaft: NAME' puts the block's cylinders on one shaft; 'opposed: [A, B]' "
            "puts one piston on A and one on B per throw",
            ("opposed",),
        )
    if crank.opposed[0] == crank.opposed[1]:
        raise FieldProblem(
            f"opposed names crankshaft '{crank.opposed[0]}' twice",
            "the two crankshafts of the bores, e.g. 'opposed: [intake, exhaust]'",
            ("opposed",),
        )
    given = crank.model_fields_set & {"banks", "bank_count", "split", "bank_stagger"}
    given |= {k for k in ("row_rotation", "link") if getattr(crank, k) is not None}
    if given:
        key = sorted(given)[0]
        raise FieldProblem(
            f"'{key}' in an opposed block",
            "an opposed block's banks point from one shaft's axis to the other's: leave "
            "banks, bank_count, split, bank_stagger, row_rotation and link out",
            (key,),
        )


def blocks(spec: LayoutSpec) -> list[tuple[CrankSpec, Path]]:
    """The compact form's blocks, each with its path in the file.

    Parameters
    ----------
    spec : LayoutSpec
        A validated layout file.

    Returns
    -------
    list of (CrankSpec, tuple)
        ``[(crank, ("crank",))]`` for one mapping, ``(block, ("crank", b))`` for each block
        of a list; empty for the explicit form.
    """
    if spec.crank is None:
        return []
    if not isinstance(spec.crank, list):
        return [(spec.crank, ("crank",))]
    return [(block, ("crank", b)) for b, block in enumerate(spec.crank)]


def _direction(spec: LayoutSpec, a: str, b: str) -> float:
    """The engine-frame angle [deg] from shaft ``a``'s axis to shaft ``b``'s (0 where a
    name is unknown: :func:`resolve` refuses it)."""
    axes = {s.name: (s.x, s.y) for s in spec.crankshafts or ()}
    if a not in axes or b not in axes:
        return 0.0
    return math.degrees(math.atan2(axes[b][0] - axes[a][0], axes[b][1] - axes[a][1]))


def expand_block(
    spec: LayoutSpec,
    block: CrankSpec,
    path: Path,
    start: int,
    plain: Callable[[CrankSpec], list[CylinderSpec]],
    make: Any,
) -> list[CylinderSpec]:
    """The cylinders of one block of the compact form.

    A block without ``opposed`` is today's compact form (``plain``), its cylinders on the
    block's ``crankshaft`` and moved by ``z0``; an ``opposed: [A, B]`` block gives per
    throw one piston on A, its bank the direction from A's axis to B's, then one on B with
    the opposite bank, both with the throw, paired by ``opposed``.

    Parameters
    ----------
    spec : LayoutSpec
        The layout file (its ``crankshafts``).
    block : CrankSpec
        The block.
    path : tuple
        The block's path in the file.
    start : int
        The number of cylinders of the blocks before it.
    plain : callable
        The expansion of a block of one crankshaft (the reader's).
    make : type of pydantic model
        The model of a cylinder's entry (:class:`balance.io.schema.CylinderSpec`).

    Returns
    -------
    list of CylinderSpec
        Throw-major, each with its throw's ``throw_id`` (from 1 in the block).
    """
    if block.opposed is None:
        made = plain(block)
        if block.crankshaft is not None or block.z0 or start:
            # a link rod's master is numbered in the file: after the blocks before
            made = [
                c.model_copy(
                    update={
                        "crankshaft": block.crankshaft,
                        "z": c.z + block.z0 if block.z0 else c.z,
                        "link": c.link.model_copy(update={"master": c.link.master + start})
                        if c.link is not None and start
                        else c.link,
                    }
                )
                for c in made
            ]
    else:
        a, b = block.opposed
        bank = (_direction(spec, a, b), _direction(spec, b, a))
        spacing = block.spacing or 0.0
        made = []
        for t, throw in enumerate(block.throws):
            z = t * spacing + block.z0 if block.z0 else t * spacing
            for k, name in enumerate((a, b)):
                made.append(
                    make.model_construct(
                        throw=throw,
                        bank=bank[k],
                        z=z,
                        throw_id=t + 1,
                        crankshaft=name,
                        opposed=start + 2 * t + (2 - k),
                    )
                )
    for c in made:
        c._block = path
    return made


@dataclass(repr=False, eq=False)  # the reader's working state, never compared or shown
class Plan:
    """The crankshafts of a layout file, resolved (SI; radians).

    Attributes
    ----------
    names : list of str
        The crankshafts' names, the first crankshaft 1.
    x, y, rotation, phase : list of float
        Each crankshaft's axis [m], sense (+1.0 or -1.0) and phase [rad].
    of_cylinder : list of int
        Each cylinder's crankshaft (0-based).
    opposed : list of int
        Each cylinder's opposed partner (0-based), -1 where none.
    output_rotation : float
        The output's sense (+1.0 or -1.0).
    """

    names: list[str]
    x: list[float]
    y: list[float]
    rotation: list[float]
    phase: list[float]
    of_cylinder: list[int]
    opposed: list[int]
    output_rotation: float = 1.0


def _error(doc: SourceDocument, path: Path, message: str, valid: str) -> LayoutError:
    return LayoutError(message, doc.location(path), field=dotted_path(path), valid=valid)


def _where(cylinders: Sequence[CylinderSpec], prefix: Path | None, i: int, key: str) -> Path:
    """Where the file gives cylinder ``i``'s ``key``: its entry, or its compact block
    (``opposed`` of a block for an opposed piston's shaft)."""
    if prefix is not None:
        return (*prefix, i, key)
    return (*cylinders[i]._block, key)


def resolve(
    doc: SourceDocument,
    spec: LayoutSpec,
    cylinders: list[CylinderSpec],
    prefix: Path | None,
) -> tuple[Plan | None, list[LayoutError]]:
    """Check the crankshafts and each cylinder's shaft and partner, and give each cylinder
    with ``tdc`` its throw in its shaft's own sense.

    Parameters
    ----------
    doc : SourceDocument
        The layout file read (for the messages' lines).
    spec : LayoutSpec
        The validated file.
    cylinders : list of CylinderSpec
        Its cylinders in the explicit form (:func:`balance.io.layout_reader.cylinder_entries`);
        ``tdc`` throws and, for several compact blocks, ``throw_id`` are set here.
    prefix : tuple or None
        The path of the entries (``("cylinders",)``), None for the compact form.

    Returns
    -------
    Plan or None
        None for a file without ``crankshafts:``.
    list of LayoutError
        Every problem found (the plan is not to be used when there are some).
    """
    shafts = spec.crankshafts
    given_blocks = blocks(spec)
    if shafts is None:
        return None, _without(doc, spec, cylinders, prefix, given_blocks)
    errors: list[LayoutError] = []
    names = [s.name for s in shafts]
    for k, s in enumerate(shafts):
        if s.name in names[:k]:
            errors.append(
                _error(
                    doc,
                    ("crankshafts", k, "name"),
                    f"two crankshafts are named '{s.name}'",
                    "give each crankshaft its own name",
                )
            )
        for j in range(k):
            other = shafts[j]
            if math.hypot(s.x - other.x, s.y - other.y) <= SAME_AXIS:
                errors.append(
                    _error(
                        doc,
                        ("crankshafts", k),
                        f"crankshafts '{other.name}' and '{s.name}' are on one axis "
                        f"(x {s.x * 1e3:.6g} mm, y {s.y * 1e3:.6g} mm)",
                        "give each crankshaft its own axis position (x, y)",
                    )
                )
    first = shafts[0]
    if first.rotation != "same":
        errors.append(
            _error(
                doc,
                ("crankshafts", 0, "rotation"),
                f"crankshaft 1 ('{first.name}') has rotation: {first.rotation}",
                "crankshaft 1 defines the sense of rotation: rotation: same (or leave it out); "
                "give another crankshaft rotation: opposite",
            )
        )
    if first.phase != 0:
        errors.append(
            _error(
                doc,
                ("crankshafts", 0, "phase"),
                f"crankshaft 1 ('{first.name}') has phase {first.phase:.6g} deg",
                "crankshaft 1 defines the crank angle: phase 0 (or leave it out); give the "
                "other crankshafts their phase relative to it",
            )
        )
    index = {name: k for k, name in reversed(list(enumerate(names)))}

    def known(name: str, path: Path) -> int:
        if name in index:
            return index[name]
        hint = difflib.get_close_matches(name, names, n=1)
        errors.append(
            _error(
                doc,
                path,
                f"no crankshaft is named '{name}'",
                (f"did you mean '{hint[0]}'? " if hint else "")
                + f"crankshafts: {', '.join(names)}",
            )
        )
        return -1

    for block, path in given_blocks:
        for k, name in enumerate(block.opposed or ()):
            known(name, (*path, "opposed", k))
        if block.crankshaft is not None:
            known(block.crankshaft, (*path, "crankshaft"))
    of_cylinder = []
    for i, c in enumerate(cylinders):
        if c.crankshaft is None:
            of_cylinder.append(0)
        elif prefix is not None:
            of_cylinder.append(known(c.crankshaft, _where(cylinders, prefix, i, "crankshaft")))
        else:
            of_cylinder.append(index.get(c.crankshaft, -1))
    for k, s in enumerate(shafts):
        if k not in of_cylinder and not errors:
            errors.append(
                _error(
                    doc,
                    ("crankshafts", k, "name"),
                    f"crankshaft '{s.name}' carries no cylinder",
                    "name it in a cylinder's crankshaft (or a block's crankshaft or opposed), "
                    "or leave it out",
                )
            )
    if errors:
        return None, errors
    sense = [_SENSE[s.rotation] for s in shafts]
    for c, k in zip(cylinders, of_cylinder, strict=True):
        if c.throw is None and (sense[k] != 1.0 or shafts[k].phase != 0):
            c._shaft_throw = sense[k] * (c.bank - shafts[k].phase) - c.tdc
    opposed = _partners(doc, cylinders, prefix, of_cylinder, errors)
    _links(doc, cylinders, prefix, of_cylinder, opposed, errors)
    if len(given_blocks) > 1:
        _number_throws(cylinders, of_cylinder)
    plan = Plan(
        names=names,
        x=[s.x for s in shafts],
        y=[s.y for s in shafts],
        rotation=sense,
        phase=[math.radians(s.phase) for s in shafts],
        of_cylinder=of_cylinder,
        opposed=opposed,
        output_rotation=_SENSE[spec.output.rotation] if spec.output is not None else 1.0,
    )
    return plan, errors


def _without(
    doc: SourceDocument,
    spec: LayoutSpec,
    cylinders: list[CylinderSpec],
    prefix: Path | None,
    given_blocks: list[tuple[CrankSpec, Path]],
) -> list[LayoutError]:
    """``crankshaft``, ``opposed`` and ``output`` in a file without ``crankshafts:``."""
    found: list[Path] = []
    for block, path in given_blocks:
        found += [(*path, key) for key in ("crankshaft", "opposed") if getattr(block, key)]
    if prefix is not None:
        for i, c in enumerate(cylinders):
            found += [(*prefix, i, k) for k in ("crankshaft", "opposed") if getattr(c, k)]
    if spec.output is not None:
        found.append(("output",))
    return [
        _error(
            doc,
            path,
            f"'{path[-1]}' without a crankshafts: section",
            "name the crankshafts first, e.g. 'crankshafts: [{name: intake}, {name: exhaust, "
            "y: 945 mm, phase: 191 deg}]' (without it the engine has one crankshaft)",
        )
        for path in found[:1]
    ]


def _partners(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    prefix: Path | None,
    of_cylinder: list[int],
    errors: list[LayoutError],
) -> list[int]:
    """Each cylinder's opposed partner (0-based, -1 for none), every structural problem
    of a pairing added to ``errors``."""
    n = len(cylinders)
    partner = [-1] * n
    for i, c in enumerate(cylinders):
        if c.opposed is None:
            continue
        path = _where(cylinders, prefix, i, "opposed")
        j = c.opposed - 1
        problem = ""
        if j >= n:
            problem = f"opposed {c.opposed} is not a cylinder of this layout (cylinder {i + 1})"
            valid = f"the number (1-based, file order) of the other piston of the bore, 1 to {n}"
        elif j == i:
            problem = f"cylinder {i + 1} names itself as its opposed piston"
            valid = "name the other piston of the bore"
        elif of_cylinder[i] == of_cylinder[j]:
            problem = f"cylinders {i + 1} and {j + 1} are opposed but on one crankshaft"
            valid = "the two pistons of an opposed bore are on different crankshafts"
        elif (partner[i] not in (-1, j)) or (partner[j] not in (-1, i)):
            taken = partner[i] if partner[i] not in (-1, j) else partner[j]
            who = i if partner[i] not in (-1, j) else j
            problem = (
                f"cylinder {who + 1} is already opposed to cylinder {taken + 1} "
                f"(cylinder {i + 1} names {j + 1})"
            )
            valid = "a bore holds two pistons: pair each cylinder with one other"
        elif cylinders[j].opposed not in (None, i + 1):
            problem = (
                f"cylinder {i + 1} names {j + 1} as its opposed piston, but {j + 1} names "
                f"{cylinders[j].opposed}"
            )
            valid = "the two pistons of a bore name each other (or only one names the other)"
        if problem:
            errors.append(_error(doc, path, problem, valid))
            continue
        partner[i], partner[j] = j, i
    for i, j in enumerate(partner):
        if j < i:
            continue
        a, b = cylinders[i], cylinders[j]
        if abs(a.z - b.z) > 1e-12:
            errors.append(
                _error(
                    doc,
                    _where(cylinders, prefix, j, "z"),
                    f"opposed cylinders {i + 1} and {j + 1} are at z {a.z * 1e3:.6g} mm and "
                    f"{b.z * 1e3:.6g} mm",
                    "the two pistons of a bore are at one z",
                )
            )
        gap = abs((b.bank - a.bank) % 360.0 - 180.0)
        if gap > 1e-9:
            errors.append(
                _error(
                    doc,
                    _where(cylinders, prefix, j, "bank"),
                    f"opposed cylinders {i + 1} and {j + 1} have banks {a.bank:.6g} deg and "
                    f"{b.bank:.6g} deg, not 180 deg apart",
                    "each piston's bank points from its own crank towards the other: 180 deg apart",
                )
            )
    return partner


def _links(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    prefix: Path | None,
    of_cylinder: list[int],
    partner: list[int],
    errors: list[LayoutError],
) -> None:
    """A link rod hangs on a master of its own crankshaft and is in no opposed bore."""
    for i, c in enumerate(cylinders):
        if c.link is None:
            continue
        m = c.link.master - 1
        if 0 <= m < len(cylinders) and of_cylinder[m] != of_cylinder[i]:
            errors.append(
                _error(
                    doc,
                    _where(cylinders, prefix, i, "crankshaft"),
                    f"link cylinder {i + 1} hangs on cylinder {m + 1}'s rod, which is on "
                    "another crankshaft",
                    "a link rod hangs on a master rod of its own crankshaft",
                )
            )
        for k in (i, m if 0 <= m < len(cylinders) else i):
            if partner[k] >= 0:
                errors.append(
                    _error(
                        doc,
                        _where(cylinders, prefix, k, "opposed"),
                        f"cylinder {k + 1} is in an opposed bore and "
                        + ("has a link rod" if k == i else f"carries link cylinder {i + 1}"),
                        "an opposed bore's pistons have rods on the crank pin (no link rods)",
                    )
                )
                break


def _number_throws(cylinders: list[CylinderSpec], of_cylinder: list[int]) -> None:
    """``throw_id`` of the compact form's cylinders across several blocks: a throw of one
    block on one crankshaft, the rods of later blocks at one of its pins (one angle, one
    plane) on it."""
    ids: dict[tuple[Any, ...], int] = {}
    pins: dict[tuple[Any, ...], tuple[Path, int]] = {}
    for c, s in zip(cylinders, of_cylinder, strict=True):
        label = (c._block, s, c.throw_id)
        pin = (s, round(c.throw_angle % 360.0, 9) % 360.0, round(c.z, 12))
        if label not in ids:
            seen = pins.get(pin)
            ids[label] = seen[1] if seen is not None and seen[0] != c._block else len(ids) + 1
        pins.setdefault(pin, (c._block, ids[label]))
        object.__setattr__(c, "throw_id", ids[label])


def check_bores(
    doc: SourceDocument,
    plan: Plan,
    cylinders: list[CylinderSpec],
    prefix: Path | None,
    arrays: dict[str, Any],
) -> list[LayoutError]:
    """The geometry of each opposed bore: both bore lines one line, the pins apart.

    The bore line of a piston passes through its shaft's axis moved by its ``offset``
    towards the side its pin moves to after TDC (``bank + sigma 90 deg``); the two lines
    must agree to :data:`BORE_LINE` of the stroke, and the axes' distance along the bore
    must exceed ``(l + r)`` of both pistons (else the pins would meet).

    Parameters
    ----------
    doc : SourceDocument
        The layout file read.
    plan : Plan
        The resolved crankshafts (:func:`resolve`).
    cylinders : list of CylinderSpec
        The cylinders.
    prefix : tuple or None
        The path of the entries, None for the compact form.
    arrays : dict
        The engine's per-cylinder arrays (``bank`` [rad], ``crank_radius``,
        ``conrod_length``, ``offset`` [m]).

    Returns
    -------
    list of LayoutError
        One per bore that cannot be.
    """
    from balance.core.crankshafts import BORE_LINE, bore_lines

    errors = []
    shafts = _core(plan)
    for i, j in enumerate(plan.opposed):
        if j < i:
            continue
        miss, distance = bore_lines(shafts, i, j, arrays["bank"], arrays["offset"])
        r = arrays["crank_radius"]
        stroke = 2.0 * max(float(r[i]), float(r[j]))
        path = _where(cylinders, prefix, i if cylinders[i].opposed else j, "opposed")
        if miss > BORE_LINE * stroke:
            errors.append(
                _error(
                    doc,
                    path,
                    f"opposed cylinders {i + 1} and {j + 1}: their bore lines are "
                    f"{miss * 1e3:.6g} mm apart",
                    "the two crankshafts' axes (moved by each piston's offset) lie on one line "
                    "along the bank, to 1e-6 of the stroke: check x, y, bank and offset",
                )
            )
            continue
        reach = sum(float(arrays["conrod_length"][k] + r[k]) for k in (i, j))
        if distance <= reach:
            errors.append(
                _error(
                    doc,
                    path,
                    f"opposed cylinders {i + 1} and {j + 1}: the crankshafts are "
                    f"{distance * 1e3:.6g} mm apart along the bore, the pistons' pins reach "
                    f"{reach * 1e3:.6g} mm",
                    "the axes' distance along the bore exceeds (conrod_length + crank_radius) "
                    "of both pistons: move the crankshafts apart",
                )
            )
    return errors


def attach(engine: Engine, plan: Plan | None) -> Engine:
    """The engine with its crankshafts (unchanged without ``crankshafts:``).

    Parameters
    ----------
    engine : Engine
        The engine read.
    plan : Plan or None
        The resolved crankshafts (:func:`resolve`).

    Returns
    -------
    Engine
    """
    if plan is None:
        return engine
    return dataclasses.replace(engine, crankshafts=_core(plan))


def _core(plan: Plan) -> Crankshafts:
    # imported here: an engine with one crankshaft has none
    from balance.core.crankshafts import Crankshafts

    return Crankshafts(
        names=tuple(plan.names),
        x=np.asarray(plan.x, dtype=np.float64),
        y=np.asarray(plan.y, dtype=np.float64),
        rotation=np.asarray(plan.rotation, dtype=np.float64),
        phase=np.asarray(plan.phase, dtype=np.float64),
        of_cylinder=np.asarray(plan.of_cylinder, dtype=np.intp),
        opposed=np.asarray(plan.opposed, dtype=np.intp),
        output_rotation=plan.output_rotation,
    )


def refuse_unsupported(engine: Engine, sections: Any, speed_model: str | None) -> None:
    """Refuse what is not computed for several crankshafts in this version: the torsional
    analysis and the dynamic speed model (docs/layout-format.md, "Several crankshafts").

    Parameters
    ----------
    engine : Engine
        The engine analysed.
    sections : collection of str
        The sections asked for.
    speed_model : str or None
        The speed model asked for (``"dynamic"`` is refused).

    Raises
    ------
    InputError
        Naming the setting, for an engine with several crankshafts.
    """
    if engine.crankshafts is None:
        return
    from balance.core.errors import InputError

    count = engine.crankshafts.count
    if "torsion" in sections:
        raise InputError(
            f"torsion: the torsional analysis is for one crankshaft; this engine has {count} "
            "(several crankshafts are analysed without it: leave the torsion setting and the "
            "layout's torsion: section out)"
        )
    if speed_model == "dynamic":
        raise InputError(
            f"speed_model: 'dynamic' is for one crankshaft; this engine has {count}: use the "
            "constant speed model (and leave the layout's dynamics: section out)"
        )


def expand_part(
    spec: LayoutSpec, engine: Engine
) -> tuple[dict[str, Any], list[dict[str, Any]], list[str]]:
    """What ``layout expand`` writes of the crankshafts: the ``crankshafts`` and ``output``
    sections, each cylinder's ``crankshaft`` and ``opposed``, and per cylinder a comment
    with its drawn pin position at crank angle 0, :math:`\\alpha(0) = \\varphi_s +
    \\sigma_s \\text{throw}`, and its TDC crank angle :math:`\\sigma_s (\\text{bank} -
    \\varphi_s) - \\text{throw}` (engine frame, degrees, modulo 360).

    Parameters
    ----------
    spec : LayoutSpec
        The validated file.
    engine : Engine
        The engine it gives.

    Returns
    -------
    dict
        The top-level keys to write (empty without ``crankshafts:``).
    list of dict
        Per cylinder, the keys to add to its entry (empty dicts without).
    list of str
        Per cylinder, its comment (empty strings without).
    """
    from balance.io.layout_fields import written

    shafts = engine.crankshafts
    n = engine.n_cylinders
    if shafts is None or spec.crankshafts is None:
        return {}, [{} for _ in range(n)], ["" for _ in range(n)]
    top: dict[str, Any] = {
        "crankshafts": [
            {
                "name": s.name,
                "x": written(s.x, "length", exact=True),
                "y": written(s.y, "length", exact=True),
                "rotation": s.rotation,
                "phase": written(s.phase, "angle", exact=True),
            }
            for s in spec.crankshafts
        ],
        "output": {"rotation": "same" if shafts.output_rotation > 0 else "opposite"},
    }
    rows: list[dict[str, Any]] = []
    notes = []
    for i in range(n):
        k = int(shafts.of_cylinder[i])
        row: dict[str, Any] = {"crankshaft": shafts.names[k]}
        if shafts.opposed[i] >= 0:
            row["opposed"] = int(shafts.opposed[i]) + 1
        rows.append(row)
        sigma = float(shafts.rotation[k])
        phase, throw = spec.crankshafts[k].phase, math.degrees(float(engine.throw[i]))
        drawn = (phase + sigma * throw) % 360.0
        tdc = (sigma * (math.degrees(float(engine.bank[i])) - phase) - throw) % 360.0
        notes.append(f"alpha(0) {drawn:.6g} deg, TDC at crank angle {tdc:.6g} deg")
    return top, rows, notes


#: The crankshaft fields a sweep or a tolerance study may vary, and their unit kinds.
SHAFT_FIELDS = {"phase": "angle", "x": "length", "y": "length"}


def shaft_field(name: str, engine: Engine, option: str) -> tuple[str, str, str, str]:
    """Read a crankshaft field of a study, ``crankshafts.NAME.phase`` (or ``.x``, ``.y``).

    Parameters
    ----------
    name : str
        The field as written.
    engine : Engine
        The layout.
    option : str
        The option or parameter it was given to, for the message.

    Returns
    -------
    tuple of str
        The field's dimension name (``shaft2_phase``), the engine attribute it sets
        (``shaft.1.phase``: crankshaft 2's phase), its unit kind and its key.

    Raises
    ------
    InputError
        For a layout without crankshafts, an unknown crankshaft or key.
    """
    import difflib

    from balance.core.errors import InputError

    shafts = engine.crankshafts
    if shafts is None:
        raise InputError(
            f"{option}: '{name}': the layout has no crankshafts: section (one crankshaft)"
        )
    shaft, _, key = name.removeprefix("crankshafts.").rpartition(".")
    if shaft not in shafts.names:
        hint = difflib.get_close_matches(shaft, shafts.names, n=1)
        more = f"did you mean '{hint[0]}'? " if hint else ""
        raise InputError(
            f"{option}: '{name}': no crankshaft is named '{shaft}'; {more}crankshafts: "
            f"{', '.join(shafts.names)}"
        )
    if key not in SHAFT_FIELDS:
        raise InputError(
            f"{option}: '{name}' is not a field of a crankshaft a study varies; valid: "
            f"{', '.join(f'crankshafts.{shaft}.{k}' for k in SHAFT_FIELDS)}"
        )
    k = shafts.names.index(shaft)
    return f"shaft{k + 1}_{key}", f"shaft.{k}.{key}", SHAFT_FIELDS[key], key


def shaft_changed(shafts: Crankshafts, attribute: str, value: Any, add: bool) -> Crankshafts:
    """The crankshafts with one crankshaft's ``phase``, ``x`` or ``y`` set (or, with
    ``add``, changed by ``value``); the cylinders' throws and banks are the engine's.

    Parameters
    ----------
    shafts : Crankshafts
        The engine's crankshafts.
    attribute : str
        ``shaft.K.KEY`` (:func:`shaft_field`).
    value : array_like
        The value [rad or m]: a number, or an array over a grid with a trailing axis of
        size one; the crankshaft arrays then have the grid's axes and the crankshafts last.
    add : bool
        Add the value to the crankshaft's instead of setting it.

    Returns
    -------
    Crankshafts
    """
    _, index, key = attribute.split(".")
    k = int(index)
    base = np.asarray(getattr(shafts, key), dtype=np.float64)
    v = np.asarray(value, dtype=np.float64)
    v = v[..., 0] if v.ndim and v.shape[-1] == 1 else v
    new = np.array(np.broadcast_to(base, (*v.shape, base.shape[-1])), dtype=np.float64)
    new[..., k] = base[..., k] + v if add else v
    updates: dict[str, Any] = {key: new}
    return dataclasses.replace(shafts, **updates)
