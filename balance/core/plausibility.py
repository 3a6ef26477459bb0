r"""Plausibility: inputs far outside piston-engine practice, reported as warnings.

A layout can be valid (every value readable, the crank slider possible) and still describe
no engine anyone built: a speed meant in rpm but written in rad/s, grams written as
kilograms, a stroke in metres meant as millimetres.  These rules catch such slips.  Each
is a pure function of an :class:`~balance.core.engine.Engine`'s SI numbers; each warning
says what was read and why it looks wrong.  A warning never changes a number: the analysis
runs on what was given.

Rules and thresholds (the sources are in the docs, ``docs/layout-format.md``):

===========================  ==============================================================
rule                         warns when
===========================  ==============================================================
``mean_piston_speed``        :math:`c_m = 2 s n` above :data:`MAX_MEAN_PISTON_SPEED`
``rod_ratio``                :math:`\lambda = r / l` outside :data:`ROD_RATIO_RANGE`
``stroke``                   the stroke outside :data:`STROKE_RANGE`
``reciprocating_mass``       :math:`m_{rec} / B^3` outside :data:`RECIPROCATING_DENSITY_RANGE`
                             (only when the bore is known)
``conrod_inertia``           the conrod's inertia about its CG above :math:`m l^2`
``counterweight_radius``     the counterweight radius larger than the stroke
``speed``                    the crank speed above :data:`MAX_SPEED_RPM`
``shared_bore``              two cylinders on different crankshafts in one bore, not
                             declared ``opposed``
``opposed_phase``            an opposed bore's inner dead centres more than 40 deg apart
``crankshaft_position``      a crankshaft's axis more than 50 strokes from the origin
===========================  ==============================================================

The last three are an engine's with several crankshafts (docs/layout-format.md, "Several
crankshafts"), from :meth:`Engine.arrangement_warnings`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from balance.core.engine import Engine
from balance.core.kinematics import rod_ratio
from balance.core.speed import rad_per_s_to_rpm

__all__ = [
    "MAX_MEAN_PISTON_SPEED",
    "MAX_SPEED_RPM",
    "RECIPROCATING_DENSITY_RANGE",
    "ROD_RATIO_RANGE",
    "RULES",
    "STROKE_RANGE",
    "PlausibilityWarning",
    "check_engine",
    "summarise",
]

FloatArray = NDArray[np.float64]

#: Highest mean piston speed [m/s] before a warning: twice the 15 m/s top of the range of
#: engines at rated power (Heywood 1988, §2.2) and the ~30 m/s of drag-racing engines.
MAX_MEAN_PISTON_SPEED = 30.0
#: Crank radius / conrod length [1] outside which a warning is given; engines built lie
#: within 0.11-0.33 (l/r = 3 to 9, Heywood 1988, §2.2).
ROD_RATIO_RANGE = (0.1, 0.5)
#: Stroke [m] outside which a warning is given: from model-aircraft engines (about 6 mm)
#: to two-stroke marine crosshead engines (up to about 3.7 m).
STROKE_RANGE = (5e-3, 4.0)
#: Reciprocating mass per bore cubed [kg/m^3] outside which a warning is given: pistons
#: alone weigh about 400-1300 kg/m^3 of bore cubed (MAHLE 2016); pin, rings and the
#: conrod's small-end share add to that; the bounds leave a factor of about 4 below and
#: 15 above, and a gram-kilogram slip (x or / 1000) falls outside them.
RECIPROCATING_DENSITY_RANGE = (100.0, 20_000.0)
#: The upper bound for a crosshead cylinder [kg/m^3], whose slider adds piston rod and
#: crosshead to the piston (together about two to four times its mass; docs/crossheads.md).
SLIDER_DENSITY_MAX = 60_000.0
#: Crank speed [rpm] above which a warning is given: Formula One engines, the fastest
#: car engines built, peaked near 20 000 rpm.
MAX_SPEED_RPM = 25_000.0

#: The rules, in the order they are checked and reported.
RULES = (
    "speed",
    "mean_piston_speed",
    "stroke",
    "rod_ratio",
    "reciprocating_mass",
    "conrod_inertia",
    "counterweight_radius",
    "shared_bore",
    "opposed_phase",
    "crankshaft_position",
)


@dataclass(frozen=True)
class PlausibilityWarning:
    """An input far outside piston-engine practice.

    Attributes
    ----------
    rule : str
        Which rule (one of :data:`RULES`).
    field : str
        The layout field read (``speed``, ``geometry.stroke``, ``cylinders[3].stroke``,
        ``masses.reciprocating``...).
    message : str
        What was read and why it looks wrong, one line.
    excess : float
        How far beyond its threshold the value is, as a factor of at least 1 (the value
        over an upper bound, a lower bound over the value); a study reports the worst.
    """

    rule: str
    field: str
    message: str
    excess: float = 1.0


def check_engine(
    engine: Engine, counterweight_radius: float | None = None
) -> tuple[PlausibilityWarning, ...]:
    """The plausibility warnings of an engine, at most one per rule.

    Parameters
    ----------
    engine : Engine
        The engine, at the speed analysed.
    counterweight_radius : float, optional
        The counterweight radius [m] of the proposal, when given on the command line
        (otherwise the ``balance:`` section's, if any).

    Returns
    -------
    tuple of PlausibilityWarning
        In the order of :data:`RULES`; empty for a plausible engine.
    """
    radius = np.asarray(engine.crank_radius, dtype=np.float64)
    stroke = 2.0 * radius
    rpm = rad_per_s_to_rpm(float(engine.speed))
    found = [
        _speed(rpm),
        _mean_piston_speed(stroke, rpm),
        _stroke(stroke),
        _rod_ratio(radius, np.asarray(engine.conrod_length, dtype=np.float64)),
        _reciprocating(engine),
        _conrod_inertia(engine),
        _counterweight(engine, stroke, counterweight_radius),
        *(PlausibilityWarning(*w) for w in engine.arrangement_warnings()),
    ]
    return tuple(w for w in found if w is not None)


def summarise(
    warnings: Sequence[Sequence[PlausibilityWarning]], where: str
) -> tuple[PlausibilityWarning, ...]:
    """One warning per rule and field for many engines checked (a study's variants).

    Parameters
    ----------
    warnings : sequence of sequences of PlausibilityWarning
        The warnings of each engine checked.
    where : str
        What the engines are, for the message (``"corners of the sweep grid"``).

    Returns
    -------
    tuple of PlausibilityWarning
        The worst warning of each rule and field (largest ``excess``), its message
        followed by how many of the engines it holds for (``(at 2 of 4 corners of the
        sweep grid)``).
    """
    worst: dict[tuple[str, str], PlausibilityWarning] = {}
    count: dict[tuple[str, str], int] = {}
    for found in warnings:
        for w in found:
            key = (w.rule, w.field)
            if key not in worst or w.excess > worst[key].excess:
                worst[key] = w
            count[key] = count.get(key, 0) + 1
    total = len(warnings)
    # the engine's rules in their order, then the sections' (torsion, speed model) by name
    ordered = sorted(
        worst, key=lambda key: (RULES.index(key[0]) if key[0] in RULES else len(RULES), key)
    )
    return tuple(
        PlausibilityWarning(
            key[0],
            key[1],
            f"{worst[key].message} (at {count[key]} of {total} {where})",
            worst[key].excess,
        )
        for key in ordered
    )


# ---------------------------------------------------------------------------------------
# the rules


def _length(value: float) -> str:
    """A length for a message: metres from 1 m on, millimetres below."""
    return f"{value:.4g} m" if abs(value) >= 1 else f"{value * 1e3:.4g} mm"


def _mass(value: float) -> str:
    """A mass for a message: kilograms from 0.1 kg on, grams below."""
    return f"{value:.4g} kg" if abs(value) >= 0.1 else f"{value * 1e3:.4g} g"


def _worst(excess: FloatArray) -> tuple[int, str]:
    """The cylinder farthest beyond the threshold (``excess`` above 1 where a rule is
    broken), and which cylinders break it (``"cylinders 2, 3"``; empty for one cylinder)."""
    hits = np.flatnonzero(excess > 1)
    numbers = ", ".join(str(int(i) + 1) for i in hits)
    if excess.size == 1:
        which = ""
    elif hits.size == excess.size:
        which = "every cylinder"
    else:
        which = f"cylinder{'s' if hits.size > 1 else ''} {numbers}"
    return int(np.argmax(excess)), which


def _also(which: str, before: str = ", ") -> str:
    """``which`` cylinders as an aside (nothing for a one-cylinder engine)."""
    return f"{before}{which}" if which else ""


def _within(values: FloatArray, low: float, high: float | FloatArray) -> bool:
    """Whether every value lies in ``[low, high]`` (NaN counts as within, as in
    :func:`_beyond`): the common case, decided without forming the excess factors."""
    return not bool(np.any((values < low) | (values > high)))


def _beyond(values: FloatArray, low: float, high: float | FloatArray) -> FloatArray:
    """How far each value is outside ``[low, high]``, as a factor (1 inside; NaN: 1)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = np.maximum(values / high, low / values)
    return np.where(np.isfinite(factor) & (factor > 1), factor, 1.0)


def _outside(
    values: FloatArray, low: float, high: float | FloatArray
) -> tuple[int, str, float] | None:
    """The cylinder whose value lies farthest outside ``[low, high]``, which cylinders lie
    outside (see :func:`_worst`) and by what factor; None when every value lies within."""
    if _within(values, low, high):
        return None
    excess = _beyond(values, low, high)
    if not np.any(excess > 1):
        return None
    i, which = _worst(excess)
    return i, which, float(excess[i])


def _field(values: FloatArray, i: int, engine_wide: str, key: str) -> str:
    """The engine-wide field when every cylinder has the same value, else the cylinder's."""
    if values.size <= 1 or np.all(values == values.flat[0]):
        return engine_wide
    return f"cylinders[{i + 1}].{key}"


def _speed(rpm: float) -> PlausibilityWarning | None:
    if not rpm > MAX_SPEED_RPM:
        return None
    return PlausibilityWarning(
        "speed",
        "speed",
        f"speed {rpm:.6g} rpm is above {MAX_SPEED_RPM:.6g} rpm, faster than any car or "
        "motorcycle engine (Formula One engines peaked near 20 000 rpm); check the speed "
        "and its unit",
        rpm / MAX_SPEED_RPM,
    )


def _mean_piston_speed(stroke: FloatArray, rpm: float) -> PlausibilityWarning | None:
    r"""Mean piston speed :math:`c_m = 2 s n` [m/s], ``n`` in revolutions per second."""
    mean_speed = 2.0 * stroke * rpm / 60.0
    found = _outside(mean_speed, 0.0, MAX_MEAN_PISTON_SPEED)
    if found is None:
        return None
    i, which, excess = found
    return PlausibilityWarning(
        "mean_piston_speed",
        "speed",
        f"mean piston speed {mean_speed[i]:.3g} m/s (stroke {_length(stroke[i])} at "
        f"{rpm:.6g} rpm{_also(which)}) is above {MAX_MEAN_PISTON_SPEED:g} m/s; engines run at "
        "8-15 m/s at rated power, racing engines near 25 m/s; check the speed, the stroke "
        "and their units",
        excess,
    )


def _stroke(stroke: FloatArray) -> PlausibilityWarning | None:
    low, high = STROKE_RANGE
    found = _outside(stroke, low, high)
    if found is None:
        return None
    i, which, excess = found
    return PlausibilityWarning(
        "stroke",
        _field(stroke, i, "geometry.stroke", "stroke"),
        f"stroke {_length(stroke[i])}{_also(which, ' (') + (')' if which else '')} "
        f"is outside {_length(low)} to {_length(high)}, the strokes of piston engines "
        "built; check its unit",
        excess,
    )


def _rod_ratio(radius: FloatArray, length: FloatArray) -> PlausibilityWarning | None:
    ratio = rod_ratio(radius, length)
    low, high = ROD_RATIO_RANGE
    found = _outside(ratio, low, high)
    if found is None:
        return None
    i, which, excess = found
    return PlausibilityWarning(
        "rod_ratio",
        _field(length, i, "geometry.conrod_length", "conrod_length"),
        f"rod ratio r/l = {ratio[i]:.3g} (crank radius {_length(radius[i])}, conrod_length "
        f"{_length(length[i])}{_also(which)}) is outside {low:g} to {high:g}; engines built lie "
        "within 0.11-0.33; check the stroke, the conrod length and their units",
        excess,
    )


def _bore(engine: Engine) -> float:
    """The bore [m]: ``geometry.bore``, else the ``gas:`` section's; NaN when unknown."""
    bore = float(engine.bore)
    if not math.isfinite(bore) and engine.gas is not None:
        bore = float(engine.gas.bore)
    return bore


def _reciprocating(engine: Engine) -> PlausibilityWarning | None:
    bore = _bore(engine)
    if not (math.isfinite(bore) and bore > 0):
        return None
    mass = np.asarray(engine.reciprocating_mass, dtype=np.float64)
    density = mass / bore**3
    low, high = RECIPROCATING_DENSITY_RANGE
    sliders = engine.section("crossheads")  # crosshead cylinders: a heavier slider
    top = high if sliders is None else np.where(sliders, SLIDER_DENSITY_MAX, high)
    found = _outside(density, low, top)
    if found is None:
        return None
    i, which, excess = found
    return PlausibilityWarning(
        "reciprocating_mass",
        _field(mass, i, "masses.reciprocating", "reciprocating"),
        f"reciprocating mass {_mass(mass[i])} on a bore of {_length(bore)}{_also(which)}: "
        f"{density[i] / 1e3:.3g} g per cm^3 of bore cubed, outside {low / 1e3:g} to "
        f"{float(np.broadcast_to(top, density.shape)[i]) / 1e3:g} g/cm^3 (pistons alone "
        "weigh about 0.4-1.3 g/cm^3); check the "
        "units of the masses and of the bore (g or kg? mm or m?)",
        excess,
    )


def _conrod_inertia(engine: Engine) -> PlausibilityWarning | None:
    parts = engine.mass_parts
    if parts is None:
        return None
    inertia = np.asarray(parts.conrod_inertia, dtype=np.float64)
    mass = np.asarray(parts.conrod, dtype=np.float64)
    length = np.asarray(engine.conrod_length, dtype=np.float64)
    bound = mass * length**2
    found = _outside(inertia, 0.0, bound)  # NaN (no inertia given): within
    if found is None:
        return None
    i, which, excess = found
    return PlausibilityWarning(
        "conrod_inertia",
        _field(inertia, i, "masses.conrod_inertia", "conrod_inertia"),
        f"conrod_inertia {inertia[i]:.4g} kg m^2{_also(which, ' (') + (')' if which else '')}"
        f" is more than conrod mass x length^2 = {_mass(mass[i])} x ({_length(length[i])})^2"
        f" = {bound[i]:.4g} kg m^2, more than any rod of that mass and length can have; "
        "check its unit (kg m^2 or kg cm^2?)",
        excess,
    )


def _counterweight(
    engine: Engine, stroke: FloatArray, given: float | None
) -> PlausibilityWarning | None:
    field = "counterweight_radius"
    radius = given
    if radius is None and engine.balance is not None:
        radius = engine.balance.counterweight_radius
        field = "balance.counterweight_radius"
    longest = float(np.max(stroke))
    if radius is None or not radius > longest:
        return None
    return PlausibilityWarning(
        "counterweight_radius",
        field,
        f"counterweight radius {_length(radius)} is larger than the stroke "
        f"{_length(longest)}; a counterweight's centre of gravity that far out would swing "
        "through the piston's path; check its unit",
        radius / longest,
    )
