r"""Which rods share a crank throw, and which a crank pin: the one rule of the core.

A *crank throw* is the part of the crankshaft between two webs that carries rods: one crank
pin, or on a split-pin crank two pins at different angles joined by a web, with rods side
by side along it (``bank_stagger``).  Its ``crank_unbalance`` is shared by the rods on it
(docs/layout-format.md, "Masses").  A *crank pin* is where rods sit at one angle in one
plane, on one throw; its load is what :mod:`balance.core.bearings` calls a crank-pin load,
and the ``per-throw`` counterweights of :mod:`balance.core.balancing` sit one per pin.

Which throw each rod is on is :attr:`balance.core.engine.Engine.throw_index`: the layout
file's ``throw_id`` of each cylinder, or the entry of ``crank: throws`` it was expanded
from (docs/layout-format.md, "Explicit form").  A file that labels no throw, and an engine
built in code without ``throw_index``, have the rule that held before labels
(:func:`default_throws`): rods whose throw angles agree to 1e-9 deg (modulo 360 deg) and
whose ``z`` agree to 1e-12 m share a throw, and each such throw is one pin
(:func:`pin_keys`).  Every grouping of rods in the core goes through this module:
``crank_unbalance`` shared per throw (:func:`rods_per_throw`, which the reader lumps into
the rotating masses), the pins of the bearing loads and of the ``per-throw``
counterweights (:func:`crank_pins`), and the default main bearings, never between the rods
of one throw (:func:`throw_spans`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.engine import Engine

__all__ = [
    "crank_pins",
    "crank_throws",
    "default_throws",
    "first_appearance",
    "group_least",
    "pin_keys",
    "rods_per_pin",
    "rods_per_throw",
    "throw_spans",
]

FloatArray = NDArray[np.float64]
IndexArray = NDArray[np.intp]


def pin_keys(throw: ArrayLike, z: ArrayLike) -> FloatArray:
    """The place of each rod's pin: its throw angle and its plane, rounded so that rods at
    one place agree exactly.

    Parameters
    ----------
    throw : array_like
        Throw angle of each cylinder [rad].
    z : array_like
        Axial position of each cylinder's rod [m].

    Returns
    -------
    ndarray, shape (cylinders, 2)
        Per cylinder, the throw angle in [0, 360) rounded to 1e-9 [deg] and ``z`` rounded
        to 1e-12 [m].
    """
    angle = np.round(np.mod(np.degrees(np.asarray(throw, dtype=np.float64)), 360.0), 9) % 360.0
    plane = np.round(np.asarray(z, dtype=np.float64), 12)
    return np.stack([angle, plane], axis=-1)


def first_appearance(groups: ArrayLike) -> IndexArray:
    """Groups renumbered 0, 1, … in the order their first member appears.

    Parameters
    ----------
    groups : array_like of int or str
        A label per cylinder.

    Returns
    -------
    ndarray of int
        Per cylinder, the number of its group, from 0, the first cylinder's group 0.
    """
    seen: dict[object, int] = {}
    out = [seen.setdefault(g, len(seen)) for g in np.asarray(groups).tolist()]
    return np.asarray(out, dtype=np.intp)


def default_throws(throw: ArrayLike, z: ArrayLike) -> IndexArray:
    """The throws of rods that no label places: rods at one pin (:func:`pin_keys`) share a
    throw, and a throw is one pin.

    Parameters
    ----------
    throw : array_like
        Throw angle of each cylinder [rad].
    z : array_like
        Axial position of each cylinder's rod [m].

    Returns
    -------
    ndarray of int
        Per cylinder, the number of its throw, from 0, in the order of first appearance.
    """
    keys = pin_keys(throw, z)
    _, inverse = np.unique(keys, axis=0, return_inverse=True)
    return first_appearance(inverse.ravel())


def crank_throws(engine: Engine) -> IndexArray:
    """The crank throw each cylinder's rod is on.

    Parameters
    ----------
    engine : Engine
        The engine: its ``throw_index``, or without one its throws and ``z``
        (:func:`default_throws`).

    Returns
    -------
    ndarray of int
        Per cylinder, the number of its throw, from 0.
    """
    if engine.throw_index is not None:
        return np.asarray(engine.throw_index, dtype=np.intp)
    return default_throws(engine.throw, engine.z)


def rods_per_throw(throws: ArrayLike) -> FloatArray:
    """How many rods share each cylinder's throw (the share of ``crank_unbalance`` each
    carries is one over this).

    Parameters
    ----------
    throws : array_like of int
        The throw of each cylinder (:func:`crank_throws`).

    Returns
    -------
    ndarray
        Per cylinder, the number of rods on its throw [1].
    """
    index = np.asarray(throws, dtype=np.intp)
    counts = np.bincount(index)
    return np.asarray(counts[index], dtype=np.float64)


def rods_per_pin(engine: Engine) -> FloatArray:
    """How many rods share each cylinder's crank pin as the balance factor's one-cylinder
    convention counts them: the rods of one throw at one throw angle, so that rods
    staggered side by side on one pin are that pin's rods and split pins are pins of their
    own (docs/theory.md, "The balance factor").

    Parameters
    ----------
    engine : Engine
        The engine: its throws (:func:`crank_throws`) and throw angles.

    Returns
    -------
    ndarray
        Per cylinder, the number of rods on its pin [1].
    """
    keys = np.stack([crank_throws(engine), pin_keys(engine.throw, engine.z)[:, 0]], axis=-1)
    _, inverse = np.unique(keys, axis=0, return_inverse=True)
    return rods_per_throw(inverse.ravel())


def crank_pins(engine: Engine) -> IndexArray:
    """The crank pin each cylinder's rod is on: rods at one throw angle and in one plane
    (:func:`pin_keys`).

    A pin lies on one throw: the layout reader refuses two throws with rods at one pin
    (:mod:`balance.io.layout_throws`), so that the pins of an engine read from a file
    divide its throws (split pins and staggered rods are pins of their own).

    Parameters
    ----------
    engine : Engine
        The engine (its throws and ``z``).

    Returns
    -------
    ndarray of int
        Per cylinder, the number of its pin, from 0, pins ordered by angle, then plane.
    """
    _, inverse = np.unique(pin_keys(engine.throw, engine.z), axis=0, return_inverse=True)
    return np.asarray(inverse.ravel(), dtype=np.intp)


def throw_spans(z: ArrayLike, throws: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The stretches of the crank that the throws take, in ``z`` order: the planes of each
    throw's rods from the first to the last, throws that touch or share a plane taken as
    one stretch.

    Parameters
    ----------
    z : array_like
        Axial position of each cylinder's rod [m] (rounded to 1e-12 m here).
    throws : array_like of int
        The throw of each cylinder (:func:`crank_throws`).

    Returns
    -------
    lo, hi : ndarray
        The first and last plane of each stretch [m], increasing; ``lo == hi`` where a
        stretch is one plane (every throw without staggered rods).
    """
    planes = np.round(np.asarray(z, dtype=np.float64), 12)
    index = np.asarray(throws, dtype=np.intp)
    n = int(index.max()) + 1
    lo = np.full(n, np.inf)
    hi = np.full(n, -np.inf)
    np.minimum.at(lo, index, planes)
    np.maximum.at(hi, index, planes)
    order = np.lexsort((hi, lo))
    starts: list[float] = []
    ends: list[float] = []
    for a, b in zip(lo[order].tolist(), hi[order].tolist(), strict=True):
        if ends and a <= ends[-1]:
            ends[-1] = max(ends[-1], b)
        else:
            starts.append(a)
            ends.append(b)
    return np.asarray(starts, dtype=np.float64), np.asarray(ends, dtype=np.float64)


def group_least(values: ArrayLike, groups: NDArray[np.intp]) -> NDArray[np.float64]:
    """The least member value of each group of :func:`crank_pins`.

    The rods of a pin agree only to the rounding of
    :func:`crank_pins`; taking the least of them, rather than the first
    or last, keeps the pin where it is whatever the cylinders' numbering.

    Parameters
    ----------
    values : array_like
        One value per cylinder (a throw's plane [m] or angle [rad]).
    groups : ndarray of int
        The pin of each cylinder (:func:`crank_pins`).

    Returns
    -------
    ndarray
        One value per pin, in the unit of ``values``.
    """
    out = np.full(int(groups.max()) + 1, np.inf)
    np.minimum.at(out, groups, np.asarray(values, dtype=np.float64))
    return out
