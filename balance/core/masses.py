r"""Masses: from the parts of a cylinder's moving group to the lumped two-mass model.

A layout may give its masses lumped (``reciprocating``, ``rotating``) or by part (piston
group, conrod with its centre of gravity and inertia, crank unbalance).  The parts are
kept per cylinder in :class:`MassParts` so that a sweep or a tolerance study that changes
a part, or the conrod length, lumps them again exactly as loading the layout file would
(:func:`two_mass_split`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["PART_FIELDS", "MassParts", "two_mass_split"]

FloatArray = NDArray[np.float64]

#: The per-cylinder part arrays of :class:`MassParts` that a sweep may set.
PART_FIELDS = (
    "piston_group",
    "conrod",
    "conrod_cg_to_big_end",
    "conrod_inertia",
    "crank_unbalance",
    "piston_rod",
    "crosshead",
)


def two_mass_split(
    piston_group: ArrayLike,
    conrod: ArrayLike,
    conrod_cg_to_big_end: ArrayLike,
    conrod_inertia: ArrayLike,
    crank_unbalance: ArrayLike,
    rods_per_throw: ArrayLike,
    conrod_length: ArrayLike,
    piston_rod: ArrayLike = 0.0,
    crosshead: ArrayLike = 0.0,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    r"""Lumped reciprocating and rotating masses and the conrod inertia correction.

    Parameters
    ----------
    piston_group : array_like
        Piston, rings, pin and clips [kg].
    conrod : array_like
        Conrod mass [kg].
    conrod_cg_to_big_end : array_like
        Distance of the conrod's centre of gravity from the big-end centre, :math:`a` [m].
    conrod_inertia : array_like
        Conrod moment of inertia about its centre of gravity [kg m²]; NaN where not given.
    crank_unbalance : array_like
        Unbalance of the bare crank throw reduced to the pin radius [kg], per throw.
    rods_per_throw : array_like
        How many conrods share the throw (the unbalance is shared among them) [1].
    conrod_length : array_like
        Centre-to-centre length :math:`l` [m].
    piston_rod, crosshead : array_like
        A crosshead engine's piston rod and crosshead [kg] (0 for a trunk piston): they
        reciprocate with the piston group.

    Returns
    -------
    reciprocating, rotating : ndarray
        :math:`m_{rec} = m_p + m_{pr} + m_{xh} + m_c a/l` and
        :math:`m_{rot} = m_c (1 - a/l) + u/n_{throw}` [kg].
    inertia_correction : ndarray
        :math:`\Delta I = I_c - m_c\, a (l - a)` [kg m²]; 0 where no inertia is given.

    Notes
    -----
    The two masses at big end and small end keep the conrod's mass and centre of gravity;
    their moment of inertia about the centre of gravity is :math:`m_c a (l - a)`, and the
    difference from the real one enters the roll torque.  All arguments broadcast.

    References
    ----------
    Kolchin and Demidov, *Design of Automotive Engines*, Mir 1984 (the two-mass conrod);
    Taylor, *The Internal Combustion Engine in Theory and Practice*, vol. 2, 2nd ed., MIT
    Press 1985, ch. 8.  Derivation on the theory page.
    """
    m_c = np.asarray(conrod, dtype=np.float64)
    a = np.asarray(conrod_cg_to_big_end, dtype=np.float64)
    length = np.asarray(conrod_length, dtype=np.float64)
    inertia = np.asarray(conrod_inertia, dtype=np.float64)
    small_end = m_c * a / length
    big_end = m_c - small_end
    slider = (
        np.asarray(piston_group, dtype=np.float64)
        + np.asarray(piston_rod, dtype=np.float64)
        + np.asarray(crosshead, dtype=np.float64)
    )
    reciprocating = slider + small_end
    rotating = big_end + np.asarray(crank_unbalance, dtype=np.float64) / np.asarray(
        rods_per_throw, dtype=np.float64
    )
    correction = np.where(np.isnan(inertia), 0.0, inertia - m_c * a * (length - a))
    return reciprocating, rotating, np.asarray(correction, dtype=np.float64)


@dataclass(frozen=True, eq=False)
class MassParts:
    """The parts behind a by-part layout's lumped masses, one entry per cylinder.

    ``reciprocating_given`` and ``rotating_given`` hold a cylinder's lumped override
    (which wins over its parts) and NaN elsewhere; ``piston_rod`` and ``crosshead`` a
    crosshead engine's (0 for a trunk piston).
    """

    piston_group: FloatArray
    conrod: FloatArray
    conrod_cg_to_big_end: FloatArray
    conrod_inertia: FloatArray
    crank_unbalance: FloatArray
    rods_per_throw: FloatArray
    reciprocating_given: FloatArray
    rotating_given: FloatArray
    piston_rod: FloatArray
    crosshead: FloatArray

    def lumped(
        self, conrod_length: ArrayLike, parts: Mapping[str, ArrayLike] | None = None
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Reciprocating, rotating mass and inertia correction for these parts (some
        replaced by ``parts``, arrays that broadcast) at ``conrod_length``."""
        values = {name: getattr(self, name) for name in PART_FIELDS}
        values.update(parts or {})
        rec, rot, correction = two_mass_split(
            rods_per_throw=self.rods_per_throw, conrod_length=conrod_length, **values
        )
        rec = np.where(np.isnan(self.reciprocating_given), rec, self.reciprocating_given)
        rot = np.where(np.isnan(self.rotating_given), rot, self.rotating_given)
        return rec, rot, correction

    def reordered(self, idx: NDArray[np.intp]) -> MassParts:
        """The parts of renumbered cylinders."""
        return MassParts(**{name: getattr(self, name)[idx] for name in _ARRAYS})

    def scaled(self, factor: float) -> MassParts:
        """Geometrically similar parts: lengths times ``factor``, masses times its cube,
        inertias times its fifth power."""
        f3 = factor**3
        return replace(
            self,
            piston_group=self.piston_group * f3,
            piston_rod=self.piston_rod * f3,
            crosshead=self.crosshead * f3,
            conrod=self.conrod * f3,
            conrod_cg_to_big_end=self.conrod_cg_to_big_end * factor,
            conrod_inertia=self.conrod_inertia * factor**5,
            crank_unbalance=self.crank_unbalance * f3,
            reciprocating_given=self.reciprocating_given * f3,
            rotating_given=self.rotating_given * f3,
        )


_ARRAYS = (*PART_FIELDS, "rods_per_throw", "reciprocating_given", "rotating_given")
