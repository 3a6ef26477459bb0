r"""The balance-factor study: the residual first order against the balance factor.

With one crankshaft the study is a closed form (:func:`balance_factor_study`): the rotating
masses balanced in full, each factor's share of every cylinder's reciprocating mass added
opposite its pin, the residual first-order force traces an ellipse whose vertical and
horizontal peaks are given per factor.  With several crankshafts
(docs/several-crankshafts.md, "Balancing proposals") each point is the proposal with that
``balance_factor`` (:func:`balance.core.proposal.balance_engine`, the factor per cylinder on
its own crankshaft), its residual without the balance shafts at ±1 that it adds: what the
counterweights leave, forward and backward (:func:`geared_factor_study`).  The section is
``factor_study`` (:mod:`balance.core.sections`), its outputs :data:`STUDY_OUTPUTS`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import kinematics
from balance.core.analysis import compute_phasors
from balance.core.balance_factor import BalanceFactor, FactorEquivalents
from balance.core.catalogue import Output
from balance.core.counterweights import axis_rods_per_pin
from balance.core.engine import Engine
from balance.core.phasors import rounding_threshold
from balance.core.proposal import balance_engine, residual
from balance.core.result import FreeForces, Result
from balance.core.speed import speed_squared
from balance.core.throws import rods_per_pin

__all__ = [
    "STUDY_OUTPUTS",
    "FactorStudy",
    "balance_factor_study",
    "factor_study",
    "factor_study_part",
    "geared_factor_study",
    "optimal_balance_factor",
]

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class FactorStudy:
    """Residual first-order force and moment against the balance factor.

    Attributes
    ----------
    factor : ndarray
        Balance factors [1].
    vertical_peak, horizontal_peak : ndarray
        Peak residual first-order force along y and x per factor [N].
    moment_peak : ndarray
        Peak residual first-order moment per factor [N m].
    optimal : float
        The factor that makes the larger of the two force peaks smallest.
    largest_main_load, largest_internal_moment : ndarray or None
        With the crank-pin and main-bearing loads asked for: the largest main-bearing
        load [N] and internal moment [N m] with each factor's proposed counterweights.
    rods : tuple of int
        The different numbers of rods per throw of the engine (the factors are shares of
        each cylinder's reciprocating mass; one cylinder's on each throw is this many times
        them, :mod:`balance.core.balance_factor`).
    force_forward, force_backward, moment_forward, moment_backward : ndarray or None
        Several crankshafts: the magnitudes of the residual first-order force [N] and
        moment [N m] turning with crankshaft 1 (forward) and against it (backward) per
        factor, each the proposal's with that factor; None for one crankshaft.
    """

    factor: FloatArray
    vertical_peak: FloatArray
    horizontal_peak: FloatArray
    moment_peak: FloatArray
    optimal: float
    largest_main_load: FloatArray | None = None
    largest_internal_moment: FloatArray | None = None
    rods: tuple[int, ...] = ()
    force_forward: FloatArray | None = None
    force_backward: FloatArray | None = None
    moment_forward: FloatArray | None = None
    moment_backward: FloatArray | None = None

    def equivalents(self, factor: float) -> FactorEquivalents:
        """A factor of the study (a share of each cylinder's reciprocating mass) in both
        conventions.

        Parameters
        ----------
        factor : float
            The share [1].

        Returns
        -------
        FactorEquivalents
        """
        return FactorEquivalents(BalanceFactor(float(factor)), self.rods or (1,))


def _first_order_parts(
    layout: Engine,
) -> tuple[ComplexArray, tuple[ComplexArray, ComplexArray] | None]:
    r"""What the balance-factor study needs of each cylinder's first order, from one
    analysis.

    Parameters
    ----------
    layout : Engine
        The engine.

    Returns
    -------
    g1 : ndarray of complex
        :math:`G_1` of each cylinder's :math:`-s''/r` (exact; a link piston's in
        :math:`\beta_j`).
    pins : tuple of ndarray of complex, or None
        Forward and backward first-order phasors of each cylinder's link pin moving relative
        to its crank pin, at the engine's speed [N] (None without link rods).
    """
    if not layout.has_links:
        r = layout.crank_radius
        ratio = kinematics.rod_ratio(r, layout.conrod_length)
        eps = kinematics.offset_ratio(layout.offset, r)
        return np.asarray(kinematics.acceleration_coefficients(ratio, eps, [1])[..., 0]), None
    free = compute_phasors(layout, [1], moments=False, roll=False)
    assert free.link_pins is not None
    g1 = np.asarray(free.coefficients[:, 0])
    return g1, (free.link_pins.force_forward[:, 0], free.link_pins.force_backward[:, 0])


def _residual_first_order(
    layout: Engine,
    first_order: ComplexArray,
    factor: float,
    pin_first_order: tuple[ComplexArray, ComplexArray] | None = None,
) -> tuple[complex, complex, complex]:
    """Free first-order force phasors (forward, backward) and moment peak after counterweights
    carrying rotating mass plus ``factor`` of the reciprocating mass, per-throw; link pins'
    relative motion (``pin_first_order``: forward and backward per cylinder [N]) added."""
    w2 = float(speed_squared(layout.speed))
    r = layout.crank_radius
    c1 = 0.5 * np.asarray(first_order, dtype=np.complex128)
    rec = layout.reciprocating_mass * r * w2
    along = np.exp(1j * layout.bank)
    turn = np.exp(1j * (layout.throw - layout.bank))
    fwd_terms = rec * c1 * turn * along - factor * rec * np.exp(1j * layout.throw)
    bwd_terms = rec * np.conj(c1) * np.conj(turn) * along
    if pin_first_order is not None:
        fwd_terms = fwd_terms + pin_first_order[0]
        bwd_terms = bwd_terms + pin_first_order[1]
    lever = layout.z - layout.reference_z
    moment_peak = abs(complex((fwd_terms * lever).sum())) + abs(complex((bwd_terms * lever).sum()))
    return complex(fwd_terms.sum()), complex(bwd_terms.sum()), complex(moment_peak)


def balance_factor_study(
    layout: Engine,
    first_order: ComplexArray,
    factors: Sequence[float] | FloatArray,
    pin_first_order: tuple[ComplexArray, ComplexArray] | None = None,
) -> dict[str, FloatArray]:
    r"""Residual first-order force against balance factor.

    The rotating masses are balanced in full; ``factor`` of each cylinder's reciprocating
    mass is added to the crank.  The residual first-order force traces an ellipse; its
    vertical (y) and horizontal (x) peaks are

    .. math:: |P^{+} + \bar P^{-}| \quad\text{and}\quad |P^{+} - \bar P^{-}|

    Parameters
    ----------
    layout : Engine
        The engine (masses, crank radii, throws, banks, ``z`` and speed).
    first_order : ndarray of complex
        :math:`G_1` of each cylinder's :math:`-s''/r` [1] (1 without offset).
    factors : sequence of float
        The balance factors to evaluate [1].
    pin_first_order : tuple of ndarray of complex, optional
        The link pins' first-order forward and backward phasors per cylinder [N], for an
        engine with link rods.

    Returns
    -------
    dict of ndarray
        ``factor`` [1], ``vertical_peak`` [N], ``horizontal_peak`` [N], ``moment_peak``
        [N m] (first order).
    """
    f = np.asarray(factors, dtype=np.float64).ravel()
    vertical = np.empty(f.size)
    horizontal = np.empty(f.size)
    moment = np.empty(f.size)
    for i, factor in enumerate(f):
        fwd, bwd, mpk = _residual_first_order(layout, first_order, float(factor), pin_first_order)
        vertical[i] = abs(fwd + bwd.conjugate())
        horizontal[i] = abs(fwd - bwd.conjugate())
        moment[i] = mpk.real
    return {
        "factor": f,
        "vertical_peak": vertical,
        "horizontal_peak": horizontal,
        "moment_peak": moment,
    }


def optimal_balance_factor(
    layout: Engine,
    first_order: ComplexArray,
    pin_first_order: tuple[ComplexArray, ComplexArray] | None = None,
) -> float:
    """Balance factor that minimises the larger of the vertical and horizontal first-order
    residual peaks (ternary search: the larger of two convex functions is convex).

    Parameters
    ----------
    layout : Engine
        The engine.
    first_order : ndarray of complex
        :math:`G_1` of each cylinder's :math:`-s''/r` [1].
    pin_first_order : tuple of ndarray of complex, optional
        The link pins' first-order forward and backward phasors per cylinder [N].

    Returns
    -------
    float
        The balance factor in [0, 1].
    """

    def worst(factor: float) -> float:
        study = balance_factor_study(layout, first_order, [factor], pin_first_order)
        return float(max(study["vertical_peak"][0], study["horizontal_peak"][0]))

    return _least_on_unit_interval(worst)


def factor_study(layout: Engine, factors: ArrayLike | None = None) -> FactorStudy:
    """Residual first-order force against balance factor.

    Parameters
    ----------
    layout : Engine
        The engine.
    factors : array_like, optional
        Balance factors [1]; default 0 to 1 in steps of 0.05.

    Returns
    -------
    FactorStudy
        The peaks per factor, those that rounding cannot tell from zero set to 0, and the
        factor that makes the larger of the two force peaks smallest.
    """
    f = np.linspace(0.0, 1.0, 21) if factors is None else np.asarray(factors, dtype=np.float64)
    g1, pins = _first_order_parts(layout)  # pins: the link rods' (None without link rods)
    study = _zero_below_rounding(balance_factor_study(layout, g1, f, pins), layout, g1, f)
    return FactorStudy(
        factor=f,
        vertical_peak=study["vertical_peak"],
        horizontal_peak=study["horizontal_peak"],
        moment_peak=study["moment_peak"],
        optimal=optimal_balance_factor(layout, g1, pins),
        rods=FactorEquivalents.of(BalanceFactor(0.0), rods_per_pin(layout)).rods,
    )


def _zero_below_rounding(
    study: dict[str, FloatArray],
    layout: Engine,
    first_order: ComplexArray,
    factors: FloatArray,
) -> dict[str, FloatArray]:
    r"""The study with the peaks that rounding cannot tell from zero set to 0.

    The rule of :func:`balance.core.phasors.cancel_to_zero`, which every phasor sum of an
    analysis follows: a residual peak is a sum of the :math:`2n` forward and backward
    terms of the n cylinders, whose magnitudes add up to
    :math:`S = \sum_i m_{rec,i} r_i \omega^2 (|g_{1,i}| + f)` for the force (times
    :math:`|z_i - z_{ref}|` for the moment); a peak at most
    :func:`balance.core.phasors.rounding_threshold` of :math:`S` and :math:`2n` terms is 0
    (an inline-4 prints 0, not 3.96e-12 N, at every factor).
    """
    rec = np.asarray(layout.reciprocating_mass * layout.crank_radius) * float(
        speed_squared(layout.speed)
    )
    size = rec[None, :] * (np.abs(first_order)[None, :] + factors[:, None])
    lever = np.abs(np.asarray(layout.z) - layout.reference_z)
    n_terms = 2 * layout.n_cylinders
    force_limit = rounding_threshold(size.sum(axis=1), n_terms)
    moment_limit = rounding_threshold((size * lever[None, :]).sum(axis=1), n_terms)
    out = dict(study)
    for name, bound in (
        ("vertical_peak", force_limit),
        ("horizontal_peak", force_limit),
        ("moment_peak", moment_limit),
    ):
        out[name] = np.where(study[name] <= bound, 0.0, study[name])
    return out


def factor_study_part(
    engine: Engine, request: Any, result: Result, *, factors: ArrayLike | None = None
) -> Result:
    """The ``factor_study`` section: :func:`factor_study` of the analysed engine.

    Parameters
    ----------
    engine : Engine
        The analysed engine.
    request : Request
        The request.
    result : Result
        The result so far.
    factors : array_like, optional
        Balance factors [1]; default 0 to 1 in steps of 0.05.

    Returns
    -------
    Result
        ``result`` with the ``factor_study`` part (:class:`FactorStudy`) added.
    """
    if engine.geared:
        study = geared_factor_study(engine, result, request.options("proposal"), factors)
        return result.with_part("factor_study", study)
    return result.with_part("factor_study", factor_study(engine, factors))


def geared_factor_study(
    layout: Engine,
    result: Result,
    settings: Mapping[str, Any],
    factors: ArrayLike | None = None,
) -> FactorStudy:
    r"""The balance-factor study of an engine with several crankshafts: at each factor, the
    first order that the proposal with that ``balance_factor`` leaves with its
    counterweights.

    Each point is :func:`balance.core.proposal.balance_engine` with ``balance_factor`` set
    to the factor (a share of each cylinder's reciprocating mass, on its own crankshaft) and
    the other settings as the proposal's, and its residual
    (:func:`balance.core.proposal.residual`) without the balance shafts at ±1 it adds (on
    co-rotating crankshafts the backward first order goes to a shaft at −1): with a
    counter-rotating crankshaft there is none, and the point is the proposal's residual bit
    for bit.  The peaks are those of one crankshaft's study, from the residual's forward
    and backward first order :math:`R^{+}`, :math:`R^{-}`: :math:`|R^{+} + \bar R^{-}|`
    along y, :math:`|R^{+} - \bar R^{-}|` along x and the moment's
    :math:`|M^{+}| + |M^{-}|`, with the zero rule of :func:`factor_study`.  The residual
    is affine in the factor, so the optimum is searched on the line through the points at 0
    and 1.

    Parameters
    ----------
    layout : Engine
        The engine (:attr:`Engine.geared`).
    result : Result
        Its analysis (free forces, coefficients, model).
    settings : mapping
        The proposal's settings (``cancel``, ``strategy``, ``counterweight_radius``,
        ``cancel_roll``; a ``balance_factor`` given is replaced by each factor); order 1 is
        added to the orders to cancel.
    factors : array_like, optional
        Balance factors [1]; default 0 to 1 in steps of 0.05.

    Returns
    -------
    FactorStudy
        With the forward and backward magnitudes per factor.
    """
    f = np.linspace(0.0, 1.0, 21) if factors is None else np.asarray(factors, dtype=np.float64)
    f = f.ravel()
    free = FreeForces(result.phasors, result.coefficients, result.model, result.link_pins)
    p = result.phasors
    if 1 not in p.orders or not p.has("moment"):
        model = result.model
        p = compute_phasors(
            layout, [1], model=model.name, terms=model.terms, samples=model.samples or None
        ).phasors
    at = int(np.flatnonzero(np.asarray(p.orders) == 1)[0])
    cancel = settings.get("cancel")
    if cancel is None and layout.balance is not None:
        cancel = layout.balance.orders
    if cancel is not None and 1 not in cancel:
        cancel = (1, *cancel)

    def point(factor: float) -> tuple[complex, complex, float, float, float, float, float]:
        made = balance_engine(
            layout,
            free,
            cancel=cancel,
            strategy=settings.get("strategy"),
            balance_factor=factor,
            counterweight_radius=settings.get("counterweight_radius"),
            cancel_roll=bool(settings.get("cancel_roll", False)),
        )
        shafts = tuple(s for s in made.proposal.shafts if abs(s.speed_ratio) != 1)
        left = residual(layout, replace(made.proposal, shafts=shafts), p)
        forward, backward = left.force_forward[at], left.force_backward[at]
        assert left.moment_forward is not None and left.moment_backward is not None
        return (
            complex(forward),
            complex(backward),
            float(np.abs(left.force_forward)[at]),
            float(np.abs(left.force_backward)[at]),
            float(np.abs(left.moment_forward)[at]),
            float(np.abs(left.moment_backward)[at]),
            float(left.peak("moment")[at]),
        )

    points = [point(float(x)) for x in f]
    vertical = np.array([abs(q[0] + q[1].conjugate()) for q in points])
    horizontal = np.array([abs(q[0] - q[1].conjugate()) for q in points])
    g1, _ = _first_order_parts(layout)
    peaks = {
        "vertical_peak": vertical,
        "horizontal_peak": horizontal,
        "moment_peak": np.array([q[6] for q in points]),
    }
    study = _zero_below_rounding(peaks, layout, g1, f)
    ends = [points[i] if f.size and f[i] == x else point(x) for i, x in ((0, 0.0), (-1, 1.0))]
    return FactorStudy(
        factor=f,
        vertical_peak=study["vertical_peak"],
        horizontal_peak=study["horizontal_peak"],
        moment_peak=study["moment_peak"],
        optimal=_optimal_on_line(ends[0][:2], ends[1][:2]),
        rods=FactorEquivalents.of(BalanceFactor(0.0), axis_rods_per_pin(layout)).rods,
        force_forward=np.array([q[2] for q in points]),
        force_backward=np.array([q[3] for q in points]),
        moment_forward=np.array([q[4] for q in points]),
        moment_backward=np.array([q[5] for q in points]),
    )


def _optimal_on_line(at_0: tuple[complex, complex], at_1: tuple[complex, complex]) -> float:
    """The factor in [0, 1] that makes the larger force peak smallest, the forward and
    backward residual affine in the factor through ``at_0`` and ``at_1`` (ternary search, as
    :func:`optimal_balance_factor`)."""
    (f0, b0), (f1, b1) = at_0, at_1

    def worst(x: float) -> float:
        fwd, bwd = f0 + x * (f1 - f0), (b0 + x * (b1 - b0)).conjugate()
        return max(abs(fwd + bwd), abs(fwd - bwd))

    return round(_least_on_unit_interval(worst), 12)  # 0, not 3e-36, where every factor leaves 0


def _study(result: Any) -> FactorStudy:
    part: FactorStudy = result.part("factor_study")
    return part


def _study_output(name: str, units: str, long_name: str, attribute: str) -> Output:
    return Output(
        name,
        ("study_factor",),
        units,
        long_name,
        lambda r: getattr(_study(r), attribute),
        when=lambda r: getattr(_study(r), attribute) is not None,
    )


#: The outputs of the ``factor_study`` section.
STUDY_OUTPUTS: tuple[Output, ...] = (
    _study_output(
        "study_largest_main_load",
        "N",
        "largest main-bearing load with the proposed counterweights",
        "largest_main_load",
    ),
    _study_output(
        "study_largest_internal_moment",
        "N m",
        "largest internal moment with the proposed counterweights",
        "largest_internal_moment",
    ),
    _study_output(
        "study_vertical_peak", "N", "peak residual first-order force along y", "vertical_peak"
    ),
    _study_output(
        "study_horizontal_peak", "N", "peak residual first-order force along x", "horizontal_peak"
    ),
    _study_output("study_moment_peak", "N m", "peak residual first-order moment", "moment_peak"),
    _study_output(
        "study_force_forward",
        "N",
        "residual first-order force turning with crankshaft 1 (forward), magnitude",
        "force_forward",
    ),
    _study_output(
        "study_force_backward",
        "N",
        "residual first-order force turning against crankshaft 1 (backward), magnitude",
        "force_backward",
    ),
    _study_output(
        "study_moment_forward",
        "N m",
        "residual first-order moment turning with crankshaft 1 (forward), magnitude",
        "moment_forward",
    ),
    _study_output(
        "study_moment_backward",
        "N m",
        "residual first-order moment turning against crankshaft 1 (backward), magnitude",
        "moment_backward",
    ),
    Output(
        "optimal_balance_factor",
        (),
        "1",
        "balance factor minimising the larger first-order force peak, as a share of each "
        "cylinder's reciprocating mass",
        lambda r: _study(r).optimal,
    ),
    Output(
        "study_factor",
        ("study_factor",),
        "1",
        "balance factor: share of each cylinder's reciprocating mass on the crank "
        "(balance_factor of: each-cylinder)",
        lambda r: _study(r).factor,
        kind="coord",
    ),
)


def _least_on_unit_interval(worst: Callable[[float], float]) -> float:
    """Where a unimodal function of the balance factor is least in [0, 1]: ternary search
    to the rounding of the factor (200 steps of two thirds)."""
    lo, hi = 0.0, 1.0
    for _ in range(200):
        m1, m2 = lo + (hi - lo) / 3, hi - (hi - lo) / 3
        if worst(m1) <= worst(m2):
            hi = m2
        else:
            lo = m1
    return 0.5 * (lo + hi)
