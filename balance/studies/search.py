r"""Crank-arrangement search: enumerate throw angles (and split pins), rank by balance.

An arrangement is ``T`` throws at equal axial spacing with ``B`` banks sharing each throw
(``T = N / B``), throw angles in multiples of ``step`` with the first throw at 0, and, for a
V (``B > 1``), a split-pin offset per bank, the first bank's 0.  Cylinder ``(t, j)`` has throw
``throw_t + split_j``, bank ``bank_j`` and ``z = t`` pitches.

Arrangements that are the same engine are counted once: a shift of the crank-angle origin
(fixed by the first throw at 0), the mirror image along the crank (throws in reverse
order), and the mirror image in the transverse plane (every angle negated, when the banks
are symmetric, which swaps the banks), with the cylinders renumbered to match.

Objectives, all normalised by :math:`m_{rec} r\omega^2` (and the pitch for moments), after
counterweights (which cancel the rotating masses and the forward first order, force and
couple):

``free``
    :math:`\sum_k (F_k + M_k)` over the orders, with ``F_k``, ``M_k`` the peaks of the
    free force and moment of order k that remain.
``moments``
    :math:`\sum_k M_k` (free moments only).
``shafts``
    the number of balance shafts needed to cancel the orders (a shaft per sense and order
    whose force or couple is not zero), ties broken by ``free``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from balance.core import kinematics, phasors
from balance.core.errors import InputError

__all__ = ["OBJECTIVES", "Arrangement", "SearchResult", "firing_order", "search"]

OBJECTIVES = ("free", "moments", "shafts")
IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]
_MAX_CANDIDATES = 5 * 10**7


@dataclass(frozen=True)
class Arrangement:
    """One crank arrangement and its score.

    Attributes
    ----------
    throws : tuple of float
        Throw angle of each throw [deg].
    splits : tuple of float
        Split-pin offset of each bank [deg] (all 0 for a common pin).
    banks : tuple of float
        Bank angles [deg].
    score : float
        Objective value (lower is better).
    force_peaks, moment_peaks : tuple of float
        Normalised free force and moment peak per order after counterweights [1].
    shafts : int
        Balance shafts needed for the orders.
    firing_order : tuple of int or None
        An even firing order (cylinders numbered throw by throw, banks in the given
        order), or None when the arrangement cannot fire evenly.
    """

    throws: tuple[float, ...]
    splits: tuple[float, ...]
    banks: tuple[float, ...]
    score: float
    force_peaks: tuple[float, ...]
    moment_peaks: tuple[float, ...]
    shafts: int
    firing_order: tuple[int, ...] | None

    @property
    def cylinder_throws(self) -> tuple[float, ...]:
        """Throw angle of each cylinder [deg], numbered throw by throw."""
        return tuple((t + s) % 360.0 for t in self.throws for s in self.splits)


@dataclass(frozen=True)
class SearchResult:
    """The ranked arrangements and what the search cost."""

    best: tuple[Arrangement, ...]
    enumerated: int
    evaluated: int
    seconds: float
    orders: tuple[int, ...]
    objective: str


def _canonical(throws: IntArray, splits: IntArray, bank_map: IntArray | None, m: int) -> IntArray:
    """Smallest code of each arrangement over its symmetry images (rows)."""
    images = []
    for mirror in (False, True):
        t = throws[:, ::-1] if mirror else throws
        s = splits
        for reflect in (False, True) if bank_map is not None else (False,):
            tt, ss = t, s
            if reflect:
                assert bank_map is not None
                tt = (-t) % m
                ss = ((-s) % m)[:, bank_map]
            # origin: the first cylinder's pin (throw 0 + first bank's split) at 0
            tt = (tt - tt[:, :1]) % m
            ss = (ss - ss[:, :1]) % m
            images.append(np.concatenate([tt, ss], axis=1))
    stacked = np.stack(images)  # (images, C, T + B)
    # lexicographic minimum over the images
    best = stacked[0]
    for other in stacked[1:]:
        diff = other != best
        first = np.argmax(diff, axis=1)
        rows = np.arange(best.shape[0])
        smaller = diff[rows, first] & (other[rows, first] < best[rows, first])
        best = np.where(smaller[:, None], other, best)
    return best


def _even_firing(tdc: FloatArray) -> NDArray[np.bool_]:
    """Whether cylinders reaching TDC at crank angles ``tdc`` [deg] (one row per
    arrangement) can fire evenly in a four-stroke cycle (every 720/N degrees)."""
    n = tdc.shape[1]
    slots = np.sort(np.round((np.arange(n) * 720.0 / n) % 360.0, 6))
    ok = np.zeros(tdc.shape[0], dtype=bool)
    for j in range(n):
        shifted = np.round((tdc - tdc[:, j : j + 1]) % 360.0, 6) % 360.0
        ok |= np.all(np.sort(shifted, axis=1) == slots, axis=1)
    return ok


def firing_order(
    cylinder_throws: Sequence[float], banks: Sequence[float]
) -> tuple[int, ...] | None:
    """An even four-stroke firing order, or None.

    Each cylinder reaches TDC at crank angle ``bank - throw`` (mod 360) and fires at that
    angle or 360° later; the order found is the lexicographically smallest starting at
    cylinder 1.

    Parameters
    ----------
    cylinder_throws, banks : sequence of float
        Each cylinder's throw and bank [deg].

    Returns
    -------
    tuple of int or None
        Cylinder numbers (1-based) in firing order; None when no order fires evenly.
    """
    n = len(cylinder_throws)
    interval = 720.0 / n
    tdc = [(b - t) % 360.0 for t, b in zip(cylinder_throws, banks, strict=True)]
    slots = [tdc[0] + i * interval for i in range(n)]

    def close(a: float, b: float) -> bool:
        return abs((a - b + 360.0) % 720.0 - 360.0) < 1e-6

    def place(assigned: list[int]) -> list[int] | None:
        # cylinders in increasing number first: the first complete order is the smallest
        if len(assigned) == n:
            return assigned
        slot = slots[len(assigned)]
        for c in range(n):
            if c not in assigned and (close(tdc[c], slot) or close(tdc[c] + 360.0, slot)):
                found = place([*assigned, c])
                if found is not None:
                    return found
        return None

    found = place([0])
    return None if found is None else tuple(c + 1 for c in found)


def search(
    cylinders: int,
    banks: Sequence[float] = (0.0,),
    *,
    step: float = 30.0,
    even_firing: bool = False,
    split: bool = True,
    objective: str = "free",
    orders: Sequence[int] = (1, 2),
    rod_ratio: float = 0.3,
    top: int = 5,
    chunk_size: int = 200_000,
) -> SearchResult:
    """Enumerate crank arrangements and rank them.

    Parameters
    ----------
    cylinders : int
        Number of cylinders N.
    banks : sequence of float
        Bank angles [deg]; one for an inline engine, two for a V (``-45, 45`` for a 90° V).
    step : float
        Angle step of throws and split-pin offsets [deg]; must divide 360.
    even_firing : bool
        Keep only arrangements that can fire evenly (four-stroke).
    split : bool
        Enumerate split-pin offsets as well (V engines).
    objective : {'free', 'moments', 'shafts'}
        What to minimise (see the module notes).
    orders : sequence of int
        Orders the objective counts.
    rod_ratio : float
        Crank radius over conrod length [1].
    top : int
        How many of the best to return.
    chunk_size : int
        Arrangements evaluated at a time (memory).

    Returns
    -------
    SearchResult
    """
    t0 = time.perf_counter()
    bank_list = [float(b) for b in banks]
    B = len(bank_list)
    if objective not in OBJECTIVES:
        raise InputError(f"objective: {objective!r}; valid: {', '.join(OBJECTIVES)}")
    if B < 1 or cylinders < 1 or cylinders % B:
        raise InputError(f"cylinders: {cylinders} cylinders cannot be shared out over {B} banks")
    if not (0 < step <= 360) or abs(360.0 / step - round(360.0 / step)) > 1e-9:
        raise InputError(f"step: {step:g} deg does not divide 360 deg; e.g. 30deg")
    if not (0 < rod_ratio < 1):
        raise InputError(f"rod_ratio: {rod_ratio:g} is not between 0 and 1")
    m = round(360.0 / step)
    T = cylinders // B
    n_split = m ** (B - 1) if (split and B > 1) else 1
    total = m ** (T - 1) * n_split
    if total > _MAX_CANDIDATES:
        raise InputError(
            f"step: {total:.3g} arrangements to enumerate; at most {_MAX_CANDIDATES:.0e}: use a "
            "larger step, or no split-pin offsets"
        )
    ks = np.asarray(sorted({int(k) for k in orders}), dtype=np.intp)
    if ks.size == 0 or ks.min() < 1:
        raise InputError("orders: give orders from 1, e.g. 1-2")
    # transverse reflection maps bank j to the bank at -angle (if every bank has one)
    neg = [
        next(
            (
                i
                for i, c in enumerate(bank_list)
                if math.isclose((b + c) % 360.0, 0.0, abs_tol=1e-9)
                or math.isclose((b + c) % 360.0, 360.0, abs_tol=1e-9)
            ),
            -1,
        )
        for b in bank_list
    ]
    bank_map = np.asarray(neg, dtype=np.intp) if all(i >= 0 for i in neg) else None
    # every arrangement's code: throws (T, first 0) and splits (B, first 0), in steps
    codes = (
        np.indices((m,) * (T - 1) + ((m,) * (B - 1) if n_split > 1 else ()))
        .reshape((T - 1) + ((B - 1) if n_split > 1 else 0), -1)
        .T.astype(np.int64)
    )
    throws = np.concatenate([np.zeros((codes.shape[0], 1), np.int64), codes[:, : T - 1]], axis=1)
    splits = np.zeros((codes.shape[0], B), np.int64)
    if n_split > 1:
        splits[:, 1:] = codes[:, T - 1 :]
    canon = _canonical(throws, splits, bank_map, m)
    is_self = np.all(canon == np.concatenate([throws, splits], axis=1), axis=1)
    throws, splits = throws[is_self], splits[is_self]
    # cylinder table, numbered throw by throw
    cyl_steps = (throws[:, :, None] + splits[:, None, :]).reshape(throws.shape[0], T * B) % m
    bank_rad = np.radians(np.tile(bank_list, T))
    if even_firing:
        tdc = (np.tile(bank_list, T)[None, :] - cyl_steps * step) % 360.0
        keep = _even_firing(tdc)
        cyl_steps, throws, splits = cyl_steps[keep], throws[keep], splits[keep]
    evaluated = cyl_steps.shape[0]
    coeffs = kinematics.acceleration_coefficients(rod_ratio, 0.0, ks)
    z = np.repeat(np.arange(T, dtype=np.float64), B)
    lever = z - z.mean()
    amp = np.ones(T * B)
    first = ks == 1
    scores = np.empty(evaluated)
    f_all = np.empty((evaluated, ks.size))
    m_all = np.empty((evaluated, ks.size))
    shafts = np.empty(evaluated, dtype=np.int64)
    for lo in range(0, evaluated, chunk_size):
        sl = slice(lo, min(lo + chunk_size, evaluated))
        throw = np.radians(cyl_steps[sl] * step)
        f_fwd, f_bwd = phasors.reciprocating_phasors(amp, coeffs, throw, bank_rad, ks)
        m_fwd, m_bwd = phasors.reciprocating_phasors(amp, coeffs, throw, bank_rad, ks, lever=lever)
        # counterweights take the forward first order (force and couple)
        f_fwd[:, first] = 0.0
        m_fwd[:, first] = 0.0
        fa, fb, ma, mb = (np.abs(a) for a in (f_fwd, f_bwd, m_fwd, m_bwd))
        fa, fb, ma, mb = (np.where(a < 1e-9, 0.0, a) for a in (fa, fb, ma, mb))
        f_all[sl] = fa + fb
        m_all[sl] = ma + mb
        shafts[sl] = ((fa + ma) > 0).sum(axis=1) + ((fb + mb) > 0).sum(axis=1)
        if objective == "moments":
            scores[sl] = m_all[sl].sum(axis=1)
        else:
            scores[sl] = f_all[sl].sum(axis=1) + m_all[sl].sum(axis=1)
    if objective == "shafts":
        rank = np.lexsort((np.round(scores, 9), shafts))
    else:
        n_split_used = (splits != 0).sum(axis=1)
        rank = np.lexsort((n_split_used, np.round(scores, 9)))
    best = []
    for i in rank[:top]:
        cyl_deg = tuple(float(v * step) for v in cyl_steps[i])
        best.append(
            Arrangement(
                throws=tuple(float(v * step) for v in throws[i]),
                splits=tuple(float(v * step) for v in splits[i]),
                banks=tuple(bank_list),
                score=float(shafts[i]) if objective == "shafts" else float(scores[i]),
                force_peaks=tuple(float(v) for v in f_all[i]),
                moment_peaks=tuple(float(v) for v in m_all[i]),
                shafts=int(shafts[i]),
                firing_order=firing_order(cyl_deg, list(np.tile(bank_list, T))),
            )
        )
    return SearchResult(
        best=tuple(best),
        enumerated=total,
        evaluated=evaluated,
        seconds=time.perf_counter() - t0,
        orders=tuple(int(k) for k in ks),
        objective=objective,
    )
