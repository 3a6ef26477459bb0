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

__all__ = ["Crankshafts"]

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
