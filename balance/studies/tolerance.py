r"""Tolerance studies: Monte Carlo over part-mass and geometry scatter, per cylinder.

Each sample draws every scattered field independently for every cylinder (or for the one
cylinder named, ``cylinders[3].reciprocating``) around the layout's value, and computes the
free forces and moments of order k (vectorised over the samples, in chunks).  The balancing
proposal is designed once, for the nominal layout (:func:`balance.core.analysis.balance_engine`),
and stays as built: the residual *with balancing* is each sample's reciprocating and rotating
phasors plus the nominal proposal's counterweights and shafts; *without* it, the engine's
own free force and moment (reciprocating + rotating).

Scatter is written ``FIELD=±TOL`` (``+-`` also accepted), with the fields of
:mod:`balance.studies.sweep` that belong to a cylinder: ``reciprocating``, ``rotating``,
``stroke``, ``crank_radius``, ``conrod_length``, ``offset``, ``z``, ``throw``, ``bank``.
By default a value is uniform in ``[nominal - TOL, nominal + TOL]``; with
``distribution="normal"`` it is normal with standard deviation ``TOL/3``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from balance.core.analysis import (
    balance_engine,
    compute_phasors,
    free_phasors_of,
    speed_squared,
)
from balance.core.balancing import proposal_phasors
from balance.core.engine import CYLINDER_FIELDS, Engine
from balance.core.errors import AnalysisError, InputError
from balance.io.fields import parse_orders
from balance.studies.sweep import Field, lumped_again, parse_field

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["PERCENTILES", "Scatter", "ToleranceResult", "histogram", "parse_scatter", "tolerance"]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
PERCENTILES = (50.0, 90.0, 99.0, 99.9, 100.0)


@dataclass(frozen=True)
class Scatter:
    """A scattered field and its tolerance (SI, degrees for angles)."""

    field: Field
    tolerance: float


def parse_scatter(text: str, layout: Engine) -> Scatter:
    """Read ``FIELD=±TOL`` (e.g. ``masses.reciprocating=±3g``).

    Raises
    ------
    InputError
        If the field is not a numeric per-cylinder field or the tolerance is malformed.
    """
    from balance.io.units import UnitProblem, parse_quantity

    if "=" not in text:
        raise InputError(
            f"--scatter: cannot read {text!r}; write FIELD=±TOL, e.g. reciprocating=±3g"
        )
    name, _, spec = text.partition("=")
    from balance.studies.sweep import _CYLINDER_FIELDS

    key = name.strip()
    if key in _CYLINDER_FIELDS and key in {"throw", "bank", "z"}:
        attribute, kind = _CYLINDER_FIELDS[key]
        field = Field(key, key, attribute, kind, key, None)
    else:
        field = parse_field(name, layout, option="--scatter")
    if field.attribute in {"speed", "reference_z"}:
        raise InputError(
            f"--scatter: '{name.strip()}' is not a part or geometry field of a cylinder; "
            "scatter masses, stroke, conrod_length, offset, z, throw or bank"
        )
    spec = spec.strip()
    for prefix in ("±", "+-", "+/-"):
        if spec.startswith(prefix):
            spec = spec[len(prefix) :]
            break
    else:
        raise InputError(f"--scatter: {field.text}: write the tolerance as ±TOL, e.g. ±3g")
    try:
        tol = parse_quantity(spec.strip(), field.kind)
    except UnitProblem as exc:
        raise InputError(f"--scatter: {field.text}: {exc}; {exc.valid}") from None
    if not tol >= 0:
        raise InputError(f"--scatter: {field.text}: the tolerance must not be negative")
    return Scatter(field, tol)


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
    """

    orders: NDArray[np.intp]
    samples: int
    force: dict[str, FloatArray]
    moment: dict[str, FloatArray]
    seconds: float

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
        Scattered fields (``"reciprocating=±3g"``...).
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
    items = [s if isinstance(s, Scatter) else parse_scatter(s, layout) for s in scatter]
    if not items:
        raise InputError("--scatter: give at least one field to scatter")
    if distribution not in {"uniform", "normal"}:
        raise InputError(f"--distribution: {distribution!r}; valid: uniform, normal")
    if samples < 1:
        raise InputError("--samples: must be at least 1")
    ks = parse_orders(orders)
    nominal = compute_phasors(layout, ks, model=model, roll=False)
    balanced = balance_engine(layout, nominal)
    added = proposal_phasors(balanced.proposal, layout, ks)
    rng = np.random.default_rng(seed)
    n = layout.n_cylinders
    first = ks == 1
    w2 = speed_squared(layout.speed)
    out = {
        f"{w}_{k}": np.empty((samples, ks.size))
        for w in ("force", "moment")
        for k in ("free", "balanced")
    }
    for lo in range(0, samples, chunk_size):
        m = min(chunk_size, samples - lo)
        p = {
            name: np.broadcast_to(getattr(layout, name), (m, n)).copy() for name in CYLINDER_FIELDS
        }
        parts: dict[str, FloatArray] = {}
        deltas = []
        for s in items:  # drawn in the order given, so a seed gives the same engines
            shape = (m, n) if s.field.cylinder is None else (m,)
            if distribution == "uniform":
                draw = rng.uniform(-1.0, 1.0, shape) * s.tolerance
            else:
                draw = rng.normal(0.0, s.tolerance / 3.0, shape)
            deltas.append((s.field, s.field.to_layout_units(draw)))
        relump = False
        for field, delta in deltas:  # geometry and parts first, as in a sweep
            if field.attribute in _LUMPED:
                continue
            if field.attribute.startswith("parts."):
                key = field.attribute.removeprefix("parts.")
                if key not in parts:
                    parts[key] = np.broadcast_to(getattr(layout.mass_parts, key), (m, n)).copy()
                _add(parts[key], field, delta)
                relump = True
            else:
                _add(p[field.attribute], field, delta)
                relump |= field.attribute == "conrod_length" and layout.mass_parts is not None
        if relump:
            rec, rot, _ = lumped_again(
                layout,
                p["conrod_length"],
                parts,
                "--scatter: the scatter puts a conrod's centre of gravity beyond its small "
                "end; reduce it",
            )
            p["reciprocating_mass"] = np.array(np.broadcast_to(rec, (m, n)))
            p["rotating_mass"] = np.array(np.broadcast_to(rot, (m, n)))
        for field, delta in deltas:
            if field.attribute in _LUMPED:
                _add(p[field.attribute], field, delta)
        if np.any(p["reciprocating_mass"] < 0) or np.any(p["rotating_mass"] < 0):
            raise InputError("--scatter: the scatter makes some masses negative; reduce it")
        try:
            unit = free_phasors_of(p, p["z"] - layout.reference_z, ks, model=model, roll=False)
        except AnalysisError as exc:
            raise InputError(
                f"--scatter: some samples have an impossible geometry: {exc}"
            ) from None
        v = unit.scaled(w2)
        f_fwd = _given(v["force_forward"]) + first * _given(v["rotating_force"])[:, None]
        m_fwd = _given(v["moment_forward"]) + first * _given(v["rotating_moment"])[:, None]
        f_bwd = _given(v["force_backward"])
        m_bwd = _given(v["moment_backward"])
        sl = slice(lo, lo + m)
        out["force_free"][sl] = np.abs(f_fwd) + np.abs(f_bwd)
        out["moment_free"][sl] = np.abs(m_fwd) + np.abs(m_bwd)
        out["force_balanced"][sl] = np.abs(f_fwd + added.force_forward) + np.abs(
            f_bwd + added.force_backward
        )
        out["moment_balanced"][sl] = np.abs(m_fwd + added.moment_forward) + np.abs(
            m_bwd + added.moment_backward
        )
    return ToleranceResult(
        orders=ks,
        samples=samples,
        force={"free": out["force_free"], "balanced": out["force_balanced"]},
        moment={"free": out["moment_free"], "balanced": out["moment_balanced"]},
        seconds=time.perf_counter() - t0,
    )


_LUMPED = {"reciprocating_mass", "rotating_mass"}


def _add(array: FloatArray, field: Field, delta: FloatArray) -> None:
    """Add a drawn scatter to every cylinder's value, or to one cylinder's."""
    if field.cylinder is None:
        array += delta
    else:
        array[:, field.cylinder] += delta


def _given(value: ComplexArray | None) -> ComplexArray:
    assert value is not None
    return value


def histogram(result: ToleranceResult, *, bins: int = 60) -> Figure:
    """Histograms of the residual peaks with balancing, one panel per quantity and order.

    Returns
    -------
    matplotlib.figure.Figure
        Built with the object-oriented API (no pyplot).
    """
    from matplotlib.figure import Figure

    K = result.orders.size
    fig = Figure(figsize=(4.0 * K, 6.0), layout="constrained")
    axes = fig.subplots(2, K, squeeze=False)
    for row, (what, table, unit) in enumerate(
        (("force", result.force, "N"), ("moment", result.moment, "N m"))
    ):
        for col, k in enumerate(result.orders):
            ax = axes[row][col]
            values = table["balanced"][:, col]
            ax.hist(values, bins=bins, color="tab:blue")
            ax.set_title(f"order {int(k)}: residual {what} with balancing")
            ax.set_xlabel(f"peak {what} [{unit}]")
            ax.set_ylabel("samples")
    fig.suptitle(f"tolerance study, {result.samples} samples")
    return fig
