"""The compact ``crank:`` form of a layout, kept for the studies that vary its fields.

A layout written in the compact form (docs/layout-format.md, "Compact form: crank") gives
throws, their axial ``spacing``, the ``banks`` and their ``bank_stagger``; the reader
expands them into one entry per cylinder, cylinder ``(t, j)`` of throw ``t`` and bank ``j``
at

    z = t * spacing + j * bank_stagger,   bank = banks[j] (+ row_rotation[t]),
    throw = throws[t] + split[j].

A sweep of ``crank.spacing``, ``crank.bank_stagger``, ``crank.banks[N]`` or ``crank.v_angle``
(:mod:`balance.io.fields`) needs those indices and values, which the :class:`Engine` does
not keep: :func:`crank_form` reads them again from the layout's file and checks that the
file still gives the engine's cylinders.  :func:`crank_geometry` forms ``z`` and the bank
angles by the same floating-point operations as the reader, so a varied layout is the one
the edited file gives, bit for bit.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.engine import Engine

__all__ = ["CrankForm", "crank_form", "crank_geometry"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class CrankForm:
    """The compact form of a layout (SI; angles in degrees, as the file gives them).

    Attributes
    ----------
    throw_index : ndarray of int
        The throw ``t`` (0-based, in the order of ``throws``) of each cylinder.
    bank_index : ndarray of int
        The bank ``j`` (0-based, in the order of ``banks``) of each cylinder.
    spacing : float
        Axial distance between neighbouring throws [m] (0 for one throw).
    bank_stagger : float
        Axial offset of bank ``j`` from bank 0, per bank [m].
    banks : tuple of float
        Bank angles [deg].
    row_rotation : tuple of float
        Per throw, the angle added to its rods' bank angles [deg] (``crank.row_rotation``;
        empty when the file gives none).
    """

    throw_index: NDArray[np.intp]
    bank_index: NDArray[np.intp]
    spacing: float
    bank_stagger: float
    banks: tuple[float, ...]
    row_rotation: tuple[float, ...] = ()


def crank_form(engine: Engine, field: str) -> CrankForm:
    """The compact form of ``engine``'s layout file.

    Parameters
    ----------
    engine : Engine
        A layout read from a file (:attr:`Engine.path`).
    field : str
        The field that needs it (``crank.spacing``), for the message.

    Returns
    -------
    CrankForm

    Raises
    ------
    InputError
        When the engine has no file, its file gives the cylinders one by one (no
        ``crank:``), or the file no longer gives the engine's throws, banks and positions
        (the engine was changed after it was read).
    """
    if engine.path is None:
        raise InputError(
            f"{field}: the layout was not read from a file, so its crank: section is not "
            "known; vary cylinders[N].z or cylinders[N].bank instead"
        )
    try:
        stat = os.stat(engine.path)
    except OSError:
        raise InputError(f"{field}: cannot read the layout file {engine.path}") from None
    form, throw, bank, z = _read(engine.path, stat.st_mtime_ns, stat.st_size)
    if isinstance(form, str):
        raise InputError(
            f"{field}: layout '{engine.name}' gives {form} in crank:; vary "
            "cylinders[N].z or cylinders[N].bank of its expansion (balance layout expand)"
        )
    if form is None:
        raise InputError(
            f"{field}: layout '{engine.name}' gives its cylinders one by one (no crank: "
            "section); vary cylinders[N].z or cylinders[N].bank instead"
        )
    same = (
        engine.throw.shape == throw.shape
        and np.array_equal(engine.throw, throw)
        and np.array_equal(engine.bank, bank)
        and np.array_equal(engine.z, z)
    )
    if not same:
        raise InputError(
            f"{field}: the engine's throws, banks or positions differ from its file's crank: "
            "section (changed after it was read); vary cylinders[N].z or cylinders[N].bank"
        )
    return form


@lru_cache(maxsize=16)
def _read(
    path: str, mtime: int, size: int
) -> tuple[CrankForm | str | None, FloatArray, FloatArray, FloatArray]:
    """The compact form of the file at ``path`` and the throws, banks and positions its
    engine has (cached by the file's modification time and size); what it gives instead
    where the compact form is several blocks, an opposed block or a block moved by ``z0``
    (docs/layout-format.md, "Several crankshafts")."""
    from balance.io.layout_reader import build_layout, read_document

    spec, engine = build_layout(read_document(path))
    crank = spec.crank
    if crank is None:
        return None, engine.throw, engine.bank, engine.z
    if isinstance(crank, list):
        return "several blocks", engine.throw, engine.bank, engine.z
    if crank.opposed is not None or crank.z0:
        return "an opposed block or z0", engine.throw, engine.bank, engine.z
    n_banks = len(crank.banks)
    count = len(crank.throws) * n_banks
    form = CrankForm(
        throw_index=np.arange(count, dtype=np.intp) // n_banks,
        bank_index=np.arange(count, dtype=np.intp) % n_banks,
        spacing=float(crank.spacing or 0.0),
        bank_stagger=float(crank.bank_stagger),
        banks=tuple(float(b) for b in crank.banks),
        row_rotation=tuple(float(r) for r in crank.row_rotation or ()),
    )
    return form, engine.throw, engine.bank, engine.z


def crank_geometry(
    form: CrankForm, spacing: ArrayLike, bank_stagger: ArrayLike, banks: list[Any]
) -> tuple[FloatArray, FloatArray]:
    """Each cylinder's axial position and bank angle for given crank values.

    The operations are the reader's (``t * spacing + j * bank_stagger``; the bank's angle
    in degrees, plus its throw's ``row_rotation`` where that is not 0, converted to
    radians), so the result is the one the file with these values
    gives, bit for bit.  The values may be arrays with grid axes and a trailing axis of size
    one (a sweep's grid); the result then has the grid's axes and the cylinders last.

    Parameters
    ----------
    form : CrankForm
        The layout's compact form.
    spacing : array_like
        Axial distance between throws [m].
    bank_stagger : array_like
        Axial offset per bank [m].
    banks : list of array_like
        Each bank's angle [deg].

    Returns
    -------
    z : ndarray
        Axial positions [m].
    bank : ndarray
        Bank angles [rad].
    """
    t = form.throw_index.astype(np.float64)
    j = form.bank_index.astype(np.float64)
    z = t * np.asarray(spacing, dtype=np.float64) + j * np.asarray(bank_stagger, dtype=np.float64)
    turn = form.row_rotation or (0.0,) * (int(form.throw_index.max()) + 1)
    columns = np.broadcast_arrays(
        *(
            np.atleast_1d(
                np.asarray(banks[k], dtype=np.float64) + turn[t]
                if turn[t]
                else np.asarray(banks[k], dtype=np.float64)
            )
            for t, k in zip(form.throw_index.tolist(), form.bank_index.tolist(), strict=True)
        )
    )
    return z, np.radians(np.concatenate(columns, axis=-1))
