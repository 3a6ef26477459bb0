"""Which crank throw each cylinder of a layout file is on: the ``throw_id`` labels, checked.

A cylinder's ``throw_id`` names the crank throw its rod runs on (docs/layout-format.md,
"Explicit form"); the compact form gives each entry of ``crank: throws`` its own
(:func:`balance.io.layout_reader.cylinder_entries`).  A file that labels no cylinder has
the rule that held before labels: rods at one throw angle and ``z`` share a throw
(:func:`balance.core.throws.default_throws`).  :func:`throw_index` turns either into the
engine's :attr:`~balance.core.engine.Engine.throw_index` and refuses what no crank can be:

- labels on some cylinders but not on others;
- two throws with rods at one pin (one throw angle in one plane): rods there share it;
- a rod of one throw between the rods of another along the crank (a throw's rods sit side
  by side on one stretch of the crank).

A link cylinder on another throw than its master is refused with the other link checks
(:mod:`balance.io.layout_reader`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from balance.core.errors import LayoutError
from balance.core.throws import default_throws, first_appearance, pin_keys
from balance.io.schema import CylinderSpec
from balance.io.yamlsource import SourceDocument, dotted_path

__all__ = ["throw_index"]

_NONE_OR_ALL = (
    "give every cylinder the number of the crank throw its rod runs on (throw_id), or none "
    "(then rods at one throw angle and z share a throw)"
)


def throw_index(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    prefix: tuple[str | int, ...] | None,
    shafts: Sequence[int] | None = None,
) -> NDArray[np.intp]:
    """The crank throw of each cylinder, numbered from 0 in the order of first appearance.

    With several crankshafts a throw is on one of them: labels and pins are those of each
    crankshaft (throws of two crankshafts are never one throw, even at one ``z``).

    Parameters
    ----------
    doc : SourceDocument
        The layout file read (for the messages' lines).
    cylinders : list of CylinderSpec
        The file's cylinders (:func:`balance.io.layout_reader.cylinder_entries`).
    prefix : tuple or None
        The path of the entries in the file (``("cylinders",)``), None for the compact form.
    shafts : sequence of int, optional
        Each cylinder's crankshaft (0-based) when the file has several; None for one.

    Returns
    -------
    ndarray of int
        Per cylinder, its throw.

    Raises
    ------
    LayoutError
        For labels on some cylinders only, two throws at one pin, or a throw's rods on both
        sides of another throw's rod; one line naming the file, line and field.
    """
    labels = [c.throw_id for c in cylinders]
    unlabelled = [i for i, label in enumerate(labels) if label is None]
    throw = np.asarray([math.radians(c.throw_angle) for c in cylinders], dtype=np.float64)
    z = np.asarray([c.z for c in cylinders], dtype=np.float64)
    shaft = list(shafts) if shafts is not None else [0] * len(cylinders)
    if len(unlabelled) == len(cylinders):
        if shafts is None:
            return default_throws(throw, z)
        keys = pin_keys(throw, z).tolist()
        return first_appearance([f"{s} {a!r} {p!r}" for s, (a, p) in zip(shaft, keys, strict=True)])
    if unlabelled:
        i = unlabelled[0]
        j = next(k for k, label in enumerate(labels) if label is not None)
        path = _path(prefix, i, "throw_id")
        raise LayoutError(
            f"cylinder {i + 1} has no throw_id, but cylinder {j + 1} has one",
            doc.location(path[:-1]),
            field=dotted_path(path),
            valid=_NONE_OR_ALL,
        )
    if shafts is None:
        index = first_appearance([int(label or 0) for label in labels])
    else:
        index = first_appearance([f"{s} {label}" for s, label in zip(shaft, labels, strict=True)])
    _check_pins(doc, cylinders, prefix, index, pin_keys(throw, z), shaft)
    _check_stretches(doc, cylinders, prefix, index, np.round(z, 12), shaft)
    return index


def _path(prefix: tuple[str | int, ...] | None, i: int, key: str) -> tuple[str | int, ...]:
    """A cylinder's key in the explicit form; in the compact form the crank's key that
    places the rods (the labels are the entries of ``throws``)."""
    return (*prefix, i, key) if prefix is not None else ("crank", key)


def _block(cylinders: list[CylinderSpec], i: int) -> tuple[str | int, ...]:
    """The compact block that gives cylinder ``i`` (``("crank",)`` or ``("crank", b)``)."""
    return cylinders[i]._block


def _members(index: NDArray[np.intp], t: int) -> str:
    numbers = [str(k + 1) for k in np.flatnonzero(index == t).tolist()]
    return f"cylinder {numbers[0]}" if len(numbers) == 1 else f"cylinders {', '.join(numbers)}"


def _check_pins(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    prefix: tuple[str | int, ...] | None,
    index: NDArray[np.intp],
    keys: NDArray[np.float64],
    shaft: list[int],
) -> None:
    """Two throws with rods at one pin (one angle, one plane, one crankshaft) are refused."""
    seen: dict[tuple[float, ...], int] = {}
    for i, key in enumerate(map(tuple, keys.tolist())):
        first = seen.setdefault((shaft[i], *key), i)
        if index[first] == index[i]:
            continue
        a, b = cylinders[first], cylinders[i]
        where = f"throw angle {key[0]:.6g} deg, z {key[1] * 1e3:.6g} mm"
        if prefix is not None:
            path = _path(prefix, i, "throw_id")
            message = (
                f"cylinders {first + 1} and {i + 1} are at one pin ({where}) but on "
                f"throws {a.throw_id} and {b.throw_id}"
            )
            valid = (
                "rods at one throw angle and z share the pin and its throw: give them one throw_id"
            )
        else:
            path = (*_block(cylinders, i), "throws", int(b.throw_id or 1) - 1)
            message = (
                f"throws {a.throw_id} and {b.throw_id} put rods at one pin ({where}): "
                f"cylinders {first + 1} and {i + 1}"
            )
            valid = (
                "throws lie one after another along the crank: give them different planes "
                "(spacing) or angles"
            )
        raise LayoutError(message, doc.location(path), field=dotted_path(path), valid=valid)


def _check_stretches(
    doc: SourceDocument,
    cylinders: list[CylinderSpec],
    prefix: tuple[str | int, ...] | None,
    index: NDArray[np.intp],
    z: NDArray[np.float64],
    shaft: list[int],
) -> None:
    """A rod of one throw strictly between the first and last rod of another throw of its
    crankshaft is refused."""
    on = np.asarray(shaft)
    for t in range(int(index.max()) + 1):
        own = index == t
        lo, hi = float(z[own].min()), float(z[own].max())
        same = on == on[own][0]
        inside = np.flatnonzero(~own & same & (z > lo) & (z < hi))
        if inside.size == 0:
            continue
        i = int(inside[0])
        label = cylinders[int(np.flatnonzero(own)[0])].throw_id
        span = f"z {lo * 1e3:.6g} to {hi * 1e3:.6g} mm"
        if prefix is not None:
            path = _path(prefix, i, "throw_id")
            message = (
                f"cylinder {i + 1} (throw {cylinders[i].throw_id}, z {z[i] * 1e3:.6g} mm) lies "
                f"between the rods of throw {label} ({_members(index, t)}, {span})"
            )
            valid = (
                "a throw's rods sit side by side on one stretch of the crank, no other "
                "throw's rod between them: check these cylinders' throw_id"
            )
        else:
            path = (*_block(cylinders, int(np.flatnonzero(own)[0])), "bank_stagger")
            message = (
                f"the rods of throw {label} ({span}) reach past throw "
                f"{cylinders[i].throw_id}'s (z {z[i] * 1e3:.6g} mm)"
            )
            valid = (
                "the rods of a throw stay on its stretch: |bank_stagger| x (banks - 1) below "
                "|spacing|"
            )
        raise LayoutError(message, doc.location(path), field=dotted_path(path), valid=valid)
