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

__all__ = [
    "BORE_LINE",
    "MAX_AXIS_STROKES",
    "MAX_OPPOSED_LAG",
    "AxisTable",
    "Crankshafts",
    "axis_table",
    "bore_lines",
    "forward_throw",
    "is_plain",
    "layout_warnings",
    "tdc_angles",
]

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


#: Largest distance of a crankshaft's axis from the frame's origin, in strokes, before the
#: ``crankshaft_position`` warning (a unit slip: 945 m for 945 mm).
MAX_AXIS_STROKES = 50.0
#: Largest lag between the inner dead centres of an opposed bore's pistons [deg] before the
#: ``opposed_phase`` warning.
MAX_OPPOSED_LAG = 40.0
#: How far two bore lines may lie apart and still be one bore, per stroke [1].
BORE_LINE = 1e-6


def bore_lines(
    shafts: Crankshafts, i: int, j: int, bank: FloatArray, offset: FloatArray
) -> tuple[float, float]:
    """How far apart the bore lines of cylinders ``i`` and ``j`` lie, and how far apart
    their crankshafts' axes are along cylinder ``i``'s bore.

    A cylinder's bore line passes through its crankshaft's axis moved by its ``offset``
    towards the side its pin moves to after top dead centre (the engine-frame direction
    ``bank + sigma 90 deg``) and runs along its ``bank``.

    Parameters
    ----------
    shafts : Crankshafts
        The crankshafts and each cylinder's.
    i, j : int
        The two cylinders (0-based).
    bank : ndarray
        Bank angle of each cylinder [rad].
    offset : ndarray
        Offset of each cylinder [m].

    Returns
    -------
    miss : float
        Distance of ``j``'s bore line from ``i``'s [m] (0 for one line).
    along : float
        Distance from ``i``'s crankshaft axis to ``j``'s along ``i``'s bank [m].
    """
    a, b = int(shafts.of_cylinder[i]), int(shafts.of_cylinder[j])

    def point(k: int, s: int) -> complex:
        side = float(bank[k]) + float(shafts.rotation[s]) * np.pi / 2
        axis = complex(float(shafts.y[s]), float(shafts.x[s]))
        return axis + float(offset[k]) * complex(np.cos(side), np.sin(side))

    u = complex(np.cos(float(bank[i])), np.sin(float(bank[i])))  # y + i x, as in the frame
    d = (point(j, b) - point(i, a)) / u
    axes = complex(float(shafts.y[b] - shafts.y[a]), float(shafts.x[b] - shafts.x[a])) / u
    return abs(d.imag), axes.real


def tdc_angles(shafts: Crankshafts, throw: FloatArray, bank: FloatArray) -> FloatArray:
    """The crank angle at which each cylinder reaches its (inner) top dead centre,
    :math:`\\sigma_s (\\text{bank} - \\varphi_s) - \\text{throw}`, in [0, 2 pi) (rod
    geometry aside: an offset or a link rod moves it slightly).

    Parameters
    ----------
    shafts : Crankshafts
        The crankshafts and each cylinder's.
    throw, bank : ndarray
        Throw and bank angle of each cylinder [rad].

    Returns
    -------
    ndarray
        Per cylinder [rad].
    """
    s = shafts.of_cylinder
    angle = shafts.rotation[s] * (bank - shafts.phase[s]) - throw
    return np.asarray(np.mod(angle, 2 * np.pi), dtype=np.float64)


def layout_warnings(
    shafts: Crankshafts,
    throw: FloatArray,
    bank: FloatArray,
    z: FloatArray,
    crank_radius: FloatArray,
    offset: FloatArray,
) -> list[tuple[str, str, str, float]]:
    """What looks wrong in an engine's crankshafts, at most one per rule: a shared bore
    not declared ``opposed`` (``shared_bore``), an opposed bore whose pistons reach their
    inner dead centres more than :data:`MAX_OPPOSED_LAG` apart (``opposed_phase``), a
    crankshaft axis farther than :data:`MAX_AXIS_STROKES` strokes from the origin
    (``crankshaft_position``).

    Parameters
    ----------
    shafts : Crankshafts
        The crankshafts and each cylinder's.
    throw, bank : ndarray
        Throw and bank angle of each cylinder [rad].
    z : ndarray
        Axial position of each cylinder [m].
    crank_radius, offset : ndarray
        Crank radius and offset of each cylinder [m].

    Returns
    -------
    list of (str, str, str, float)
        Per warning its rule, the layout field, the message and how far beyond its
        threshold the value is (a factor of at least 1).
    """
    found: list[tuple[str, str, str, float]] = []
    n = throw.size
    stroke = 2.0 * crank_radius
    shared = None
    # the pairs (i < j, in order) on two shafts, not paired, at one z and 180 deg apart:
    # screened at once, each then checked for a common bore line; the first one warns
    of = np.asarray(shafts.of_cylinder)
    index = np.arange(n)
    apart = np.abs(np.mod(bank[None, :] - bank[:, None], 2 * np.pi) - np.pi)
    candidate = (
        (index[None, :] > index[:, None])
        & (of[None, :] != of[:, None])
        & (np.asarray(shafts.opposed)[:, None] != index[None, :])
        & ~(np.abs(z[:, None] - z[None, :]) > 1e-12)
        & ~(apart > 1e-9)
    )
    for i, j in np.argwhere(candidate).tolist():
        miss, _ = bore_lines(shafts, i, j, bank, offset)
        if miss <= BORE_LINE * max(stroke[i], stroke[j]):
            shared = (
                "shared_bore",
                f"cylinders[{j + 1}].opposed",
                f"cylinders {i + 1} and {j + 1} share a bore: declare `opposed`?",
                1.0,
            )
            break
    if shared is not None:
        found.append(shared)
    tdc = np.degrees(tdc_angles(shafts, throw, bank))
    worst = None
    for i in range(n):
        j = int(shafts.opposed[i])
        if j <= i:
            continue
        lag = float(np.mod(tdc[j] - tdc[i], 360.0))
        gap = min(lag, 360.0 - lag)
        if gap > MAX_OPPOSED_LAG and (worst is None or gap > worst[0] + 1e-9):
            worst = (gap, i, j, lag)
    if worst is not None:
        gap, i, j, lag = worst
        when = f"{lag:.0f}° after" if lag <= 180.0 else f"{360.0 - lag:.0f}° before"
        found.append(
            (
                "opposed_phase",
                f"crankshafts[{int(shafts.of_cylinder[j]) + 1}].phase",
                f"cylinder {j + 1} reaches its inner dead centre {when} cylinder {i + 1}: "
                "the 180° of a piston facing the other way missing from `phase`?",
                gap / MAX_OPPOSED_LAG,
            )
        )
    reach = MAX_AXIS_STROKES * float(np.max(stroke))
    distance = np.hypot(shafts.x, shafts.y)
    k = int(np.argmax(distance))
    if distance[k] > reach:
        found.append(
            (
                "crankshaft_position",
                f"crankshafts[{k + 1}].y",
                f"crankshaft '{shafts.names[k]}' is {distance[k]:.6g} m from the origin, "
                f"more than {MAX_AXIS_STROKES:g} strokes; check x, y and their unit",
                float(distance[k] / reach),
            )
        )
    return found


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
