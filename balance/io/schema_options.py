"""The models of the layout file's optional settings sections ``balance:``, ``gas:`` and
``flywheel:`` (docs/layout-format.md), imported only for a layout that has one.

They are fields of :class:`balance.io.schema.LayoutSpec`, which names them and has them
imported into its module's namespace (:func:`balance.io.schema.settings_models`) before
pydantic builds a validator that needs them; a layout without them (most have none)
validates without defining them, nor importing the gas model of :mod:`balance.core.gas`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, model_validator

from balance.core.balance_factor import CONVENTIONS, BalanceFactor
from balance.core.engine import STRATEGIES, BalanceSettings, ShaftPosition
from balance.core.gas import GasModel
from balance.io.limits import MAX_ORDER
from balance.io.problems import FieldProblem
from balance.io.spec_blocks import (
    CoreSpec,
    OptLength,
    Strict,
    exactly_one,
    kg_m2,
    positive,
    quantity,
)
from balance.io.units import parse_quantity

__all__ = [
    "BalanceFactorSpec",
    "BalanceSpec",
    "FlywheelSpec",
    "GasModelSpec",
    "GasSpec",
    "ShaftSpec",
]

OptBodyInertia = Annotated[float | None, quantity("inertia", kg_m2)]
Pressure = Annotated[float, quantity("pressure")]
OptFraction = Annotated[float | None, quantity("fraction")]


def _speed_ratio(value: Any) -> int:
    """A balance shaft's speed ratio: a whole number other than 0, as written (no unit)."""
    valid = "a whole number from -64 to 64 other than 0, e.g. 2 or -2 (negative: against the crank)"
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise FieldProblem(f"speed_ratio is {value!r}", valid)
    if not math.isfinite(value):
        raise FieldProblem(f"speed_ratio is {value!r}", valid)
    if value != int(value):
        # docs/layout-format.md, "Balancing settings": why only whole numbers
        raise FieldProblem(
            f"speed_ratio is {value:g}: a shaft at a ratio that is not a whole number turns at "
            f"order {abs(value):g}, which the engine's inertia forces do not have (their orders "
            "are whole numbers), so it cancels nothing and adds a shaking force of its own",
            valid,
        )
    if value != int(value) or value == 0 or abs(value) > 64:
        raise FieldProblem(f"speed_ratio is {value:g}", valid)
    return int(value)


class ShaftSpec(
    CoreSpec,
    core=ShaftPosition,
    kinds={"x": "length", "y": "length"},
    types={"speed_ratio": Annotated[int, BeforeValidator(_speed_ratio)]},
):
    """One entry of ``balance: shafts:``: a balance shaft the design has room for
    (:class:`balance.core.engine.ShaftPosition`; SI).

    ``x`` and ``y`` locate its axis in the transverse plane; a coordinate left out is the
    proposal's to choose.
    """


class BalanceFactorSpec(
    CoreSpec,
    core=BalanceFactor,
    kinds={"value": "fraction"},
    types={"of": Literal[CONVENTIONS]},
):
    """``balance_factor: {of: one-cylinder, value: 100 %}``: a balance factor and what it
    is a share of (:class:`balance.core.balance_factor.BalanceFactor`); a bare
    ``balance_factor: 50 %`` is ``{of: each-cylinder, value: 50 %}``."""


def _balance_factor(value: Any) -> Any:
    """A bare balance factor is a share of each cylinder's reciprocating mass; a mapping
    says its convention (:class:`BalanceFactorSpec`)."""
    if value is None or isinstance(value, Mapping | BalanceFactorSpec):
        return value
    return {"value": parse_quantity(value, "fraction"), "of": CONVENTIONS[0]}


class BalanceSpec(
    CoreSpec,
    core=BalanceSettings,
    kinds={"counterweight_radius": "length"},
    types={
        "balance_factor": Annotated[BalanceFactorSpec | None, BeforeValidator(_balance_factor)],
        "orders": list[int] | None,
        # the allowed texts in the order the messages have always listed them
        "strategy": Literal[tuple(sorted(STRATEGIES))],
        "shafts": Annotated[list[ShaftSpec] | None, Field(min_length=1, max_length=64)],
    },
):
    """The ``balance:`` section: settings for the balancing proposal
    (:class:`balance.core.engine.BalanceSettings`)."""

    @model_validator(mode="after")
    def _check(self) -> BalanceSpec:
        positive(self.counterweight_radius, "counterweight_radius")
        shafts = self.shafts or ()
        for j, shaft in enumerate(shafts):
            if any(other.speed_ratio == shaft.speed_ratio for other in shafts[:j]):
                raise FieldProblem(
                    f"a second shaft at speed ratio {shaft.speed_ratio:+d}",
                    "give one shaft per speed ratio (a shaft's eccentrics may sit in two planes)",
                    ("shafts", j, "speed_ratio"),
                )
        factor = self.balance_factor
        if factor is not None and not 0.0 <= factor.value <= 2.0:
            whose = "each cylinder's" if factor.of == CONVENTIONS[0] else "one cylinder's"
            raise FieldProblem(
                f"balance_factor is {factor.value:.4g}",
                f"a share between 0 % and 200 % of {whose} reciprocating mass",
                ("balance_factor",),
                written="balance_factor is {}",
            )
        if self.orders is not None and any(not 1 <= k <= MAX_ORDER for k in self.orders):
            raise FieldProblem(
                f"orders must be 1 to {MAX_ORDER}", "for example [1, 2]", ("orders",)
            )
        return self

    def to_core(self) -> BalanceSettings:
        """The settings (:class:`balance.core.engine.BalanceSettings`); a balance factor of
        each cylinder's reciprocating mass as a float, as the core takes it."""
        settings: BalanceSettings = super().to_core()
        factor = settings.balance_factor
        if isinstance(factor, BalanceFactor) and factor.of == CONVENTIONS[0]:
            settings = dataclasses.replace(settings, balance_factor=factor.value)
        return settings


class GasModelSpec(
    CoreSpec,
    core=GasModel,
    kinds={
        "intake_pressure": "pressure",
        "exhaust_pressure": "pressure",
        "combustion_start": "angle",
        "combustion_duration": "angle",
        "heat_released": "energy",
        "peak_pressure": "pressure",
    },
):
    """``gas: model:``: a parametric cylinder pressure (polytropes and a Wiebe heat release;
    :class:`balance.core.gas.GasModel`).

    See :mod:`balance.core.gas` for the equations.  Angles are crank angles from firing TDC.
    """

    @model_validator(mode="after")
    def _check(self) -> GasModelSpec:
        exactly_one(
            self,
            "heat_released",
            "peak_pressure",
            "for example 'peak_pressure: 75 bar' or 'heat_released: 1.6 kJ' (per cylinder "
            "and cycle)",
        )
        if not 1.0 < self.compression_ratio <= 50.0:
            raise FieldProblem(
                f"compression_ratio is {self.compression_ratio:g}",
                "a compression ratio above 1 and at most 50, e.g. 10.5",
                ("compression_ratio",),
            )
        for key in ("polytropic_compression", "polytropic_expansion"):
            value = getattr(self, key)
            if not 1.0 < value < 2.0:
                raise FieldProblem(
                    f"{key} is {value:g}", "a polytropic exponent above 1 and below 2", (key,)
                )
        for key in ("intake_pressure", "exhaust_pressure"):
            positive(getattr(self, key), key)
        if not 0.0 < self.combustion_duration <= 180.0:
            raise FieldProblem(
                f"combustion_duration is {self.combustion_duration:g} deg",
                "more than 0 and at most 180 deg",
                ("combustion_duration",),
            )
        if not -180.0 < self.combustion_start < 90.0:
            raise FieldProblem(
                f"combustion_start is {self.combustion_start:g} deg",
                "a crank angle from firing TDC between -180 and 90 deg (negative: before TDC)",
                ("combustion_start",),
            )
        if self.combustion_start + self.combustion_duration >= 180.0:
            raise FieldProblem(
                "combustion ends at or after bottom dead centre",
                "combustion_start + combustion_duration must be below 180 deg",
                ("combustion_duration",),
            )
        if not self.wiebe_a > 0:
            raise FieldProblem(
                f"wiebe_a is {self.wiebe_a:g}", "more than zero, e.g. 5", ("wiebe_a",)
            )
        if not self.wiebe_m > -1:
            raise FieldProblem(f"wiebe_m is {self.wiebe_m:g}", "more than -1, e.g. 2", ("wiebe_m",))
        positive(self.heat_released, "heat_released")
        if self.peak_pressure is not None and not self.peak_pressure > self.intake_pressure:
            raise FieldProblem(
                f"peak_pressure {self.peak_pressure / 1e5:g} bar is not above the intake pressure",
                "a peak pressure above intake_pressure, e.g. '75 bar'",
                ("peak_pressure",),
            )
        return self


class GasSpec(Strict):
    """The ``gas:`` section: cylinder pressure for the gas forces and the torque."""

    pressure_trace: str | None = Field(default=None, min_length=1, max_length=1000)
    model: GasModelSpec | None = None
    crankcase_pressure: Pressure = 1.0e5
    bore: OptLength = None

    @model_validator(mode="after")
    def _check(self) -> GasSpec:
        exactly_one(
            self,
            "pressure_trace",
            "model",
            "pressure_trace: a CSV file of crank angle [deg from firing TDC] and absolute "
            "pressure; or model: {compression_ratio: ..., peak_pressure: ...}",
        )
        positive(self.crankcase_pressure, "crankcase_pressure", allow_zero=True)
        positive(self.bore, "bore")
        return self


class FlywheelSpec(Strict):
    """The ``flywheel:`` section: an inertia to check, or a speed fluctuation to size one."""

    inertia: OptBodyInertia = None
    speed_fluctuation: OptFraction = None

    @model_validator(mode="after")
    def _check(self) -> FlywheelSpec:
        exactly_one(
            self,
            "inertia",
            "speed_fluctuation",
            "for example '{inertia: 0.12 kg m^2}' or '{speed_fluctuation: 1 %}'",
        )
        positive(self.inertia, "inertia")
        if self.speed_fluctuation is not None and not 0.0 < self.speed_fluctuation < 1.0:
            raise FieldProblem(
                f"speed_fluctuation is {self.speed_fluctuation:.4g} "
                f"({self.speed_fluctuation * 100:.4g} %)",
                "a fraction above 0 and below 100 %, e.g. '1 %'",
                ("speed_fluctuation",),
            )
        return self
