r"""Several crankshafts geared together: where each sits, which way it turns, its cylinders.

An engine with one crankshaft at the frame's origin has :attr:`Engine.crankshafts` None and
every computation of the core is the one-crankshaft computation.  With a ``crankshafts:``
section (docs/layout-format.md, "Several crankshafts") each cylinder names its crankshaft:
the shaft's axis sits at ``(x, y)``, turns with sense :math:`\sigma = \pm 1` relative to
crankshaft 1, and its reference line points at ``phase`` when :math:`\theta = 0`.  A
cylinder's crank pin is then at the engine-frame angle

.. math:: \alpha = \varphi_s + \sigma_s (\theta + \text{throw})

and its own crank angle from top dead centre is
:math:`\beta = \theta + \text{throw} + \sigma_s (\varphi_s - \text{bank})`
(docs/conventions.md, "Several crankshafts").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["AxisTable", "Crankshafts", "axis_table", "forward_throw", "is_plain"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class Crankshafts:
    """The crankshafts of an engine and the crankshaft of each cylinder (SI, radians).

    Attributes
    ----------
    names : tuple of str
        Name of each crankshaft; the first is crankshaft 1.
    x, y : ndarray
        Position of each crankshaft's axis in the engine frame [m].
    rotation : ndarray
        Sense of rotation of each crankshaft relative to crankshaft 1, +1.0 or -1.0 [1].
    phase : ndarray
        Engine-frame angle of each crankshaft's reference line at crank angle 0 [rad].
    of_cylinder : ndarray of int
        The crankshaft (0-based index into ``names``) of each cylinder.
    opposed : ndarray of int
        The cylinder (0-based) that shares each cylinder's bore, -1 where none.
    output_rotation : float
        Sense of the shaft the load is taken off, relative to crankshaft 1, +1.0 or -1.0 [1].
    """

    names: tuple[str, ...]
    x: FloatArray
    y: FloatArray
    rotation: FloatArray
    phase: FloatArray
    of_cylinder: NDArray[np.intp]
    opposed: NDArray[np.intp]
    output_rotation: float = 1.0

    @property
    def count(self) -> int:
        """Number of crankshafts."""
        return len(self.names)

    def reordered(self, idx: NDArray[np.intp]) -> Crankshafts:
        """The same crankshafts with the cylinders renumbered (``idx``: the old index of
        each new cylinder), opposed partners renumbered with them."""
        idx = np.asarray(idx, dtype=np.intp)
        new_of_old = np.empty_like(idx)
        new_of_old[idx] = np.arange(idx.size, dtype=np.intp)
        partner = self.opposed[idx]
        opposed = np.where(partner >= 0, new_of_old[np.maximum(partner, 0)], -1)
        return Crankshafts(
            names=self.names,
            x=self.x,
            y=self.y,
            rotation=self.rotation,
            phase=self.phase,
            of_cylinder=self.of_cylinder[idx],
            opposed=opposed.astype(np.intp),
            output_rotation=self.output_rotation,
        )


@dataclass(frozen=True, eq=False)
class AxisTable:
    """Each cylinder's crank axis under generic names, for the physics modules.

    Attributes
    ----------
    axis : ndarray of int
        The axis (0-based crankshaft) of each cylinder.
    sense : ndarray
        :math:`\\sigma` of each cylinder's axis, +1.0 or -1.0 [1].
    axis_phase : ndarray
        Phase of each cylinder's axis [rad].
    axis_x, axis_y : ndarray
        Position of each cylinder's axis [m].
    names : tuple of str
        Name of each axis.
    x, y, rotation, phase : ndarray
        Per axis: position [m], sense [1] and phase [rad].
    output_sense : float
        :math:`\\sigma_o`, the sense of the shaft the load is taken off [1].
    opposed : ndarray of int
        The cylinder (0-based) sharing each cylinder's bore, -1 where none.
    """

    axis: NDArray[np.intp]
    sense: FloatArray
    axis_phase: FloatArray
    axis_x: FloatArray
    axis_y: FloatArray
    names: tuple[str, ...]
    x: FloatArray
    y: FloatArray
    rotation: FloatArray
    phase: FloatArray
    output_sense: float
    opposed: NDArray[np.intp]


def axis_table(crankshafts: Crankshafts) -> AxisTable:
    """The per-cylinder arrays of the crankshafts, the one place they are formed.

    Parameters
    ----------
    crankshafts : Crankshafts
        The crankshafts and the crankshaft of each cylinder.

    Returns
    -------
    AxisTable
        Each cylinder's axis index, sense, phase [rad] and position [m], and the
        per-axis values.
    """
    of = np.asarray(crankshafts.of_cylinder, dtype=np.intp)
    return AxisTable(
        axis=of,
        sense=np.asarray(crankshafts.rotation, dtype=np.float64)[of],
        axis_phase=np.asarray(crankshafts.phase, dtype=np.float64)[of],
        axis_x=np.asarray(crankshafts.x, dtype=np.float64)[of],
        axis_y=np.asarray(crankshafts.y, dtype=np.float64)[of],
        names=crankshafts.names,
        x=np.asarray(crankshafts.x, dtype=np.float64),
        y=np.asarray(crankshafts.y, dtype=np.float64),
        rotation=np.asarray(crankshafts.rotation, dtype=np.float64),
        phase=np.asarray(crankshafts.phase, dtype=np.float64),
        output_sense=float(crankshafts.output_rotation),
        opposed=np.asarray(crankshafts.opposed, dtype=np.intp),
    )


def is_plain(crankshafts: Crankshafts | None) -> bool:
    """Whether the crankshafts are the one-crankshaft engine of every other page: none
    given, or one on the frame's ``z`` axis turning forward with phase 0 and the output
    turning with it.

    Parameters
    ----------
    crankshafts : Crankshafts or None
        The engine's crankshafts.

    Returns
    -------
    bool
        True when the engine computes as one crankshaft, bit for bit.
    """
    if crankshafts is None:
        return True
    return (
        crankshafts.count == 1
        and float(crankshafts.x[0]) == 0.0
        and float(crankshafts.y[0]) == 0.0
        and float(crankshafts.rotation[0]) == 1.0
        and float(crankshafts.phase[0]) == 0.0
        and float(crankshafts.output_rotation) == 1.0
    )


def forward_throw(throw: FloatArray, bank: FloatArray, table: AxisTable) -> FloatArray:
    r"""The throw of the forward one-crank cylinder with the same crank angle from TDC.

    A cylinder on an axis of sense :math:`\sigma` and phase :math:`\varphi_s` is at
    :math:`\beta = \theta + \text{throw} + \sigma(\varphi_s - \text{bank})` from its TDC;
    the one-crank cylinder with throw :math:`\text{throw} + \sigma(\varphi_s - \text{bank})
    + \text{bank}` and the same bank is at the same :math:`\beta`.  For
    :math:`\sigma = -1` it is the cylinder's mirror image across its bore line
    (:math:`\text{throw} - \varphi_s + 2\,\text{bank}`); for :math:`\sigma = +1` the
    cylinder turned by :math:`\varphi_s` (:math:`\text{throw} + \varphi_s`).

    Parameters
    ----------
    throw, bank : ndarray
        Per cylinder [rad].
    table : AxisTable
        The cylinders' axes (:func:`axis_table`).

    Returns
    -------
    ndarray
        The equivalent throw per cylinder [rad].
    """
    forward = throw + table.axis_phase
    return np.asarray(np.where(table.sense > 0, forward, throw - table.axis_phase + 2.0 * bank))
