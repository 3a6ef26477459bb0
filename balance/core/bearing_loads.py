"""The crank-pin and main-bearing loads as a section of an analysis.

:func:`bearings_part` computes the loads of an analysed engine with the proposal's
counterweights (:func:`balance.core.bearings.analysis_bearings`), and on request with each
counterweight strategy's and each balance factor's; :data:`OUTPUTS` declares what it adds
to the output catalogue (:mod:`balance.core.catalogue`).  The physics is in
:mod:`balance.core.bearings`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.bearings import Bearings, analysis_bearings, counterweights_of, largest_loads
from balance.core.catalogue import Output
from balance.core.engine import STRATEGIES, Engine

__all__ = ["OUTPUTS", "BearingsPart", "bearings_part", "factor_loads"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class BearingsPart:
    """The ``bearings`` section's part of a result.

    Attributes
    ----------
    loads : Bearings
        Crank-pin and main-bearing loads and internal moments, without and with the
        proposed counterweights.
    strategies : tuple of (str, Bearings)
        With the option ``strategies``: the loads with each counterweight strategy's
        proposal (the other settings as the request's), in :data:`STRATEGIES` order.
    """

    loads: Bearings
    strategies: tuple[tuple[str, Bearings], ...] = ()


def bearings_part(engine: Engine, request: Any, result: Any, *, strategies: bool = False) -> Any:
    """The ``bearings`` section (:mod:`balance.core.sections`): the loads with the result's
    proposal (:func:`analysis_bearings`); with ``strategies``, also with the proposal of
    each counterweight strategy; and, when the result holds a balance-factor study, the
    largest main-bearing load and internal moment with each factor's proposal."""
    from balance.core.analysis import compute

    proposal = result.part("proposal")
    loads = analysis_bearings(engine, counterweights_of(proposal.proposal if proposal else None))
    by_strategy: list[tuple[str, Bearings]] = []
    if strategies:
        asked = request.only("proposal")
        for strategy in STRATEGIES:
            options = {**asked.options("proposal"), "strategy": strategy}
            other = replace(asked.with_sections(proposal=options), roll=True)
            theirs = compute(engine, other).part("proposal")
            cws = counterweights_of(theirs.proposal if theirs is not None else None)
            by_strategy.append((strategy, analysis_bearings(engine, cws)))
    study = result.part("factor_study")
    if study is not None:
        main_max, moment_max = factor_loads(engine, study.factor, request.options("proposal"))
        result = result.with_part(
            "factor_study",
            replace(study, largest_main_load=main_max, largest_internal_moment=moment_max),
        )
    return result.with_part("bearings", BearingsPart(loads, tuple(by_strategy)))


def factor_loads(
    engine: Engine, factors: ArrayLike, settings: Mapping[str, Any]
) -> tuple[FloatArray, FloatArray]:
    """Largest main-bearing load [N] and internal moment [N m] with the counterweights that
    the proposal makes at each balance factor (its ``strategy`` and
    ``counterweight_radius`` from ``settings``, the rest as the engine's ``balance:``
    section, else the defaults)."""
    from balance.core.analysis import compute
    from balance.core.result import Request

    sets = []
    for factor in np.asarray(factors, dtype=np.float64):
        proposal = {
            "balance_factor": float(factor),
            "strategy": settings.get("strategy"),
            "counterweight_radius": settings.get("counterweight_radius"),
        }
        part = compute(engine, Request(orders=(1, 2), sections={"proposal": proposal})).part(
            "proposal"
        )
        sets.append(counterweights_of(part.proposal if part is not None else None))
    return largest_loads(engine, sets)


def _loads(result: Any) -> Bearings:
    part: BearingsPart = result.part("bearings")
    return part.loads


def _with_gas(result: Any) -> str:
    return " (with gas forces)" if _loads(result).gas else ""


def _output(name: str, dims: tuple[str, ...], units: str, long_name: Any, get: Any) -> Output:
    if isinstance(long_name, str) and "{gas}" in long_name:
        text = long_name
        long_name = lambda r: text.format(gas=_with_gas(r))  # noqa: E731
    return Output(name, dims, units, long_name, lambda r: get(_loads(r)))


def _curves(
    name: str, attribute: str, dims: tuple[str, ...], units: str, what: str
) -> tuple[Output, ...]:
    """A complex curve (the loads' ``attribute``) as its y and x components, ``name_y``
    and ``name_x`` (netCDF has no complex numbers)."""
    return (
        _output(
            f"{name}_y",
            dims,
            units,
            f"{what}, y component (engine frame)",
            lambda b: getattr(b, attribute).real,
        ),
        _output(
            f"{name}_x",
            dims,
            units,
            f"{what}, x component (engine frame)",
            lambda b: getattr(b, attribute).imag,
        ),
    )


_PIN, _MAIN = ("crank_pin",), ("main_bearing",)
_PIN_CURVE = ("crank_pin", "bearing_crank_angle")
_MAIN_CURVE = ("main_bearing", "bearing_crank_angle")
_MOMENT_CURVE = ("main_bearing", "moment_crank_angle")

#: The outputs of the ``bearings`` section.
OUTPUTS: tuple[Output, ...] = (
    _output("crank_pin_z", _PIN, "m", "axial position of the crank pin", lambda b: b.pin_z),
    _output(
        "crank_pin_cylinders",
        _PIN,
        "1",
        "cylinders whose rods act on the crank pin",
        lambda b: [" ".join(map(str, c)) for c in b.pin_cylinders],
    ),
    _output("crank_pin_max_load", _PIN, "N", "largest crank-pin load{gas}", lambda b: b.pin_max),
    _output(
        "crank_pin_mean_load",
        _PIN,
        "N",
        "mean magnitude of the crank-pin load{gas}",
        lambda b: b.pin_mean,
    ),
    _output(
        "crank_pin_max_angle",
        _PIN,
        "deg",
        "crank angle of the largest crank-pin load",
        lambda b: np.degrees(b.pin_max_angle),
    ),
    _output("main_bearing_z", _MAIN, "m", "axial position of the main bearing", lambda b: b.main_z),
    _output(
        "main_bearing_max_load", _MAIN, "N", "largest main-bearing load{gas}", lambda b: b.main_max
    ),
    _output(
        "main_bearing_mean_load",
        _MAIN,
        "N",
        "mean magnitude of the main-bearing load{gas}",
        lambda b: b.main_mean,
    ),
    _output(
        "main_bearing_max_load_with_proposal",
        _MAIN,
        "N",
        "largest main-bearing load with the proposed counterweights{gas}",
        lambda b: b.main_max_with_proposal,
    ),
    _output(
        "main_bearing_mean_load_with_proposal",
        _MAIN,
        "N",
        "mean magnitude of the main-bearing load with the proposed counterweights{gas}",
        lambda b: b.main_mean_with_proposal,
    ),
    _output(
        "internal_moment_max",
        _MAIN,
        "N m",
        "largest internal bending moment of the crankshaft at the main",
        lambda b: b.moment_max,
    ),
    _output(
        "internal_moment_max_with_proposal",
        _MAIN,
        "N m",
        "largest internal bending moment at the main with the proposed counterweights",
        lambda b: b.moment_max_with_proposal,
    ),
    *_curves("crank_pin_load", "pin_load", _PIN_CURVE, "N", "crank-pin load"),
    *_curves("main_bearing_load", "main_load", _MAIN_CURVE, "N", "main-bearing load"),
    *_curves(
        "main_bearing_load_with_proposal",
        "main_load_with_proposal",
        _MAIN_CURVE,
        "N",
        "main-bearing load with the proposed counterweights",
    ),
    *_curves("internal_moment", "internal_moment", _MOMENT_CURVE, "N m", "internal moment"),
    *_curves(
        "internal_moment_with_proposal",
        "internal_moment_with_proposal",
        _MOMENT_CURVE,
        "N m",
        "internal moment with the proposed counterweights",
    ),
    Output(
        "crank_pin",
        _PIN,
        "1",
        "crank pin number",
        lambda r: np.arange(1, _loads(r).pin_z.size + 1),
        kind="coord",
    ),
    Output(
        "main_bearing",
        _MAIN,
        "1",
        "main bearing number",
        lambda r: np.arange(1, _loads(r).main_z.size + 1),
        kind="coord",
    ),
    Output(
        "bearing_crank_angle",
        ("bearing_crank_angle",),
        "deg",
        "crank angle theta of the bearing-load curves",
        lambda r: np.degrees(_loads(r).theta),
        kind="coord",
    ),
    Output(
        "moment_crank_angle",
        ("moment_crank_angle",),
        "deg",
        "crank angle theta of the internal-moment curves",
        lambda r: np.degrees(_loads(r).moment_theta),
        kind="coord",
    ),
)
