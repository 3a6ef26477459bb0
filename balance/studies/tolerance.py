r"""Tolerance studies: Monte Carlo over part-mass and geometry scatter, per cylinder.

Each sample draws every scattered field independently for every cylinder (or for the one
cylinder named, ``cylinders[3].reciprocating``) around the layout's value, and computes the
free forces and moments of order k (vectorised over the samples, in chunks).  The balancing
proposal is designed once, for the nominal layout (:func:`balance.core.analysis.balance_engine`),
and stays as built: the residual *with balancing* is each sample's reciprocating and rotating
phasors plus the nominal proposal's counterweights and shafts; *without* it, the engine's
own free force and moment (reciprocating + rotating).

Scatter is written ``FIELD=±TOL`` (``+-`` also accepted; :mod:`balance.io.fields`), with
the fields that belong to a cylinder: ``reciprocating``, ``rotating``,
``stroke``, ``crank_radius``, ``conrod_length``, ``offset``, ``z``, ``throw``, ``bank``
and the parts of masses given by part.  A sample is the engine
:func:`balance.studies.changes.apply_changes` gives with the drawn scatter added, the rules
of a sweep's variants, except that moments stay about the nominal ``reference_z``: the
scatter is that of one engine's parts, not a new layout.  By default a value is uniform
in ``[nominal - TOL, nominal + TOL]``; with ``distribution="normal"`` it is normal with
standard deviation ``TOL/3``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from balance.core.analysis import compute_phasors, engine_cylinders, free_phasors_of
from balance.core.counterweights import proposal_phasors
from balance.core.engine import Engine
from balance.core.errors import AnalysisError, InputError
from balance.core.phasors import Phasors
from balance.core.proposal import balance_engine
from balance.core.speed import speed_squared
from balance.io.fields import Scatter, parse_scatter
from balance.io.orders import parse_orders
from balance.studies.changes import LINK_GEOMETRY, Change, apply_changes
from balance.studies.sweep import refuse_variable_speed

__all__ = ["PERCENTILES", "Scatter", "ToleranceResult", "parse_scatter", "tolerance"]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
PERCENTILES = (50.0, 90.0, 99.0, 99.9, 100.0)


@dataclass(frozen=True)
class ToleranceResult:
    """Distributions of the residual free forces and moments.

    Attributes
    ----------
    orders : ndarray of int
    samples : int
    force, moment : dict of str to ndarray
        ``"free"`` and ``"balanced"``: peaks per sample and order, shape
        ``(samples, orders)`` [N] and [N m].
    seconds : float
        Time of the computation [s].
    scatter : tuple of Scatter
        The scattered fields and their tolerances (SI, degrees for angles).
    distribution : {'uniform', 'normal'}
        Uniform over ±TOL, or normal with standard deviation TOL/3.
    seed : int or None
        The random seed.
    """

    orders: NDArray[np.intp]
    samples: int
    force: dict[str, FloatArray]
    moment: dict[str, FloatArray]
    seconds: float
    scatter: tuple[Scatter, ...] = ()
    distribution: str = "uniform"
    seed: int | None = None

    def percentiles(self, q: Sequence[float] = PERCENTILES) -> dict[str, FloatArray]:
        """Percentiles [N, N m], keyed ``force_free``, ``force_balanced``, ``moment_free``,
        ``moment_balanced``, each of shape ``(len(q), orders)``."""
        out = {}
        for what, table in (("force", self.force), ("moment", self.moment)):
            for key, values in table.items():
                out[f"{what}_{key}"] = np.percentile(values, q, axis=0)
        return out


def tolerance(
    layout: Engine,
    scatter: Sequence[Scatter | str],
    *,
    samples: int = 100_000,
    orders: int | str | Sequence[int] | None = "1-2",
    distribution: str = "uniform",
    seed: int | None = 0,
    model: str = "exact",
    chunk_size: int = 100_000,
) -> ToleranceResult:
    """Monte Carlo tolerance study (see the module notes).

    Parameters
    ----------
    layout : Engine
        The nominal engine.
    scatter : sequence of Scatter or str
        Scattered fields (``"reciprocating=±3g"``...): text as on the command line, where
        a tolerance needs its unit; a :class:`Scatter` holds it in SI.
    samples : int
        Number of engines drawn.
    orders : int, str or sequence of int
        Orders reported (default 1 and 2).
    distribution : {'uniform', 'normal'}
        Uniform over ±TOL, or normal with sigma TOL/3.
    seed : int, optional
        Random seed (the same seed gives the same samples).
    model : {'exact', 'series', 'textbook'}
        Piston acceleration model.
    chunk_size : int
        Samples per chunk (memory).

    Returns
    -------
    ToleranceResult
    """
    import time

    t0 = time.perf_counter()
    refuse_variable_speed(layout, "tolerance")
    items = [s if isinstance(s, Scatter) else parse_scatter(s, layout) for s in scatter]
    if not items:
        raise InputError("scatter: give at least one field to scatter")
    if distribution not in {"uniform", "normal"}:
        raise InputError(f"distribution: {distribution!r}; valid: uniform, normal")
    if samples < 1:
        raise InputError("samples: must be at least 1")
    ks = parse_orders(orders)
    nominal = compute_phasors(layout, ks, model=model, roll=False)
    added = proposal_phasors(balance_engine(layout, nominal).proposal, layout, ks)
    rng = np.random.default_rng(seed)
    n = layout.n_cylinders
    # moments about the nominal reference: the scatter does not move the block's
    fixed = replace(layout, reference_z_given=True)
    w2 = speed_squared(layout.speed)
    out = {
        f"{w}_{k}": np.empty((samples, ks.size))
        for w in ("force", "moment")
        for k in ("free", "balanced")
    }
    for lo in range(0, samples, chunk_size):
        m = min(chunk_size, samples - lo)
        changes: list[Change] = []
        for s in items:  # drawn in the order given, so a seed gives the same engines
            shape = (m, n) if s.field.cylinder is None else (m,)
            if distribution == "uniform":
                draw = rng.uniform(-1.0, 1.0, shape) * s.tolerance
            else:
                draw = rng.normal(0.0, s.tolerance / 3.0, shape)
            delta = s.field.to_layout_units(draw)
            changes.append((s.field, delta if s.field.cylinder is None else delta[:, None]))
        if layout.geared:  # sample by sample (docs/several-crankshafts.md)
            sl = slice(lo, lo + m)
            for key, values in _geared_samples(fixed, changes, ks, model, m, added).items():
                out[key][sl] = values
            continue
        drawn = apply_changes(fixed, changes, add=True, problem=_CG_BEYOND_ROD)
        # with link rods, one geometry (changes._check_link_fields): the link path wants it 1-D
        links = layout.links if layout.has_links else None
        p = {
            name: value
            if links is not None and name in LINK_GEOMETRY
            else np.broadcast_to(value, (m, n)).copy()
            for name, value in engine_cylinders(drawn).items()
        }
        if np.any(p["reciprocating_mass"] < 0) or np.any(p["rotating_mass"] < 0):
            raise InputError("scatter: the scatter makes some masses negative; reduce it")
        try:
            unit = free_phasors_of(
                p, p["z"] - layout.reference_z, ks, model=model, roll=False, links=links
            )
        except AnalysisError as exc:
            raise InputError(f"scatter: some samples have an impossible geometry: {exc}") from None
        free = unit.phasors.scaled(w2).free()
        balanced = free + added
        sl = slice(lo, lo + m)
        out["force_free"][sl] = free.peak("force")
        out["moment_free"][sl] = free.peak("moment")
        out["force_balanced"][sl] = balanced.peak("force")
        out["moment_balanced"][sl] = balanced.peak("moment")
    return ToleranceResult(
        orders=ks,
        samples=samples,
        force={"free": out["force_free"], "balanced": out["force_balanced"]},
        moment={"free": out["moment_free"], "balanced": out["moment_balanced"]},
        seconds=time.perf_counter() - t0,
        scatter=tuple(items),
        distribution=distribution,
        seed=seed,
    )


def _geared_samples(
    fixed: Engine,
    changes: list[Change],
    ks: NDArray[np.intp],
    model: str,
    m: int,
    added: Phasors,
) -> dict[str, FloatArray]:
    """The peaks of ``m`` drawn engines with several crankshafts, each analysed on its own
    (:func:`balance.core.analysis.compute_phasors`: there is no grid sum over several crank
    axes), free and with the nominal proposal's masses ``added``."""
    out = {
        f"{w}_{k}": np.empty((m, ks.size))
        for w in ("force", "moment")
        for k in ("free", "balanced")
    }
    for j in range(m):
        one = [(f, np.asarray(d)[j]) for f, d in changes]
        engine = apply_changes(fixed, one, add=True, problem=_CG_BEYOND_ROD)
        if np.any(engine.reciprocating_mass < 0) or np.any(engine.rotating_mass < 0):
            raise InputError("scatter: the scatter makes some masses negative; reduce it")
        try:
            free = compute_phasors(engine, ks, model=model, roll=False).phasors.free()
        except AnalysisError as exc:
            raise InputError(f"scatter: some samples have an impossible geometry: {exc}") from None
        balanced = free + added
        out["force_free"][j] = free.peak("force")
        out["moment_free"][j] = free.peak("moment")
        out["force_balanced"][j] = balanced.peak("force")
        out["moment_balanced"][j] = balanced.peak("moment")
    return out


_CG_BEYOND_ROD = (
    "scatter: the scatter puts a conrod's centre of gravity beyond its small end; reduce it"
)
