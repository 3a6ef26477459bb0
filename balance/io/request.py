"""The one front door: a :class:`~balance.core.result.Request` from what a user gives.

The command line (:mod:`balance.cli`) and the Python API (:func:`balance.analyse`) both
call :func:`build_request`, so that each can ask for everything the other can and a
layout's sections turn their concerns on the same way in both: a ``gas:`` section the
gas forces and torque, a ``bearings:`` section the bearing loads, a ``mounts:`` section
the engine on its mounts.  Keywords only add or override.  Every value is checked here,
once; the core assumes valid requests.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from balance.core import kinematics
from balance.core.balance_factor import CONVENTIONS
from balance.core.engine import STRATEGIES, Engine
from balance.core.errors import InputError
from balance.core.result import Request
from balance.core.sections import SECTIONS, Section
from balance.io.orders import check_speed, parse_orders

__all__ = ["MODELS", "SECTION_OPTIONS", "SPEED_MODELS", "build_request"]

#: The piston acceleration models, and ``time`` (sampled).
MODELS = (*kinematics.MODELS, "time")

#: The speed models: the crank speed constant, or the crank train's own motion solved
#: (docs/dynamics.md).
SPEED_MODELS = ("constant", "dynamic")

#: Each section option that names one section's, and the section it belongs to: an
#: option of several sections (``speeds``, ``orders``) is given in its section's mapping
#: (``mounts={"speeds": ...}``).
SECTION_OPTIONS: dict[str, str] = {
    option: section.name
    for section in SECTIONS
    for option in section.options
    if sum(option in other.options for other in SECTIONS) == 1
}


def _turned_on(section: Section, engine: Engine) -> bool:
    """Whether ``section`` is computed when a request says nothing of it.

    Parameters
    ----------
    section : Section
        The section (:data:`balance.core.sections.SECTIONS`).
    engine : Engine
        The engine (its ``gas:`` and concern sections).

    Returns
    -------
    bool
        True for a default section, or one whose layout section the engine has.
    """
    if section.default:
        return True
    if section.layout_key is None:
        return False
    if section.layout_key == "gas":
        return engine.gas is not None
    return section.layout_key in engine.sections


def build_request(
    engine: Engine,
    orders: int | str | Iterable[int] | None = None,
    *,
    speed: float | None = None,
    model: str | None = None,
    terms: int = 3,
    samples: int | None = None,
    tolerance: float | None = None,
    moments: bool = True,
    roll: bool = True,
    figures: bool = False,
    **sections: Any,
) -> Request:
    """What to compute for ``engine``.

    Parameters
    ----------
    engine : Engine
        The engine (its layout sections turn their concerns on).
    orders : int, str or iterable of int, optional
        Orders: 1 to N for an int, a spec such as ``"1-8"`` or ``"1,2,4-6"``, or a list;
        default 1 to 8.
    speed : float, optional
        Crank speed [rad/s] instead of the engine's.
    model : {'exact', 'series', 'textbook', 'time'}, optional
        Piston acceleration model (default ``exact``).
    terms : int
        Binomial terms of the ``series`` model.
    samples : int, optional
        Crank angles per revolution of the ``time`` model.
    tolerance : float, optional
        Instead of ``model``: the largest coefficient error allowed, between 0 and 1.
    moments, roll : bool
        Compute the free moments and the roll.
    figures : bool
        Compute what the figures of the sections need besides their tables (the mounts'
        speed sweep; :attr:`balance.core.sections.Section.figure_options`).
    **sections
        A section's name (``proposal``, ``torque``, ``cylinders``, ``factor_study``,
        ``mounts``, ``bearings``; :mod:`balance.core.sections`) with True (compute it), False
        (do not) or a mapping of its options; or one of its options by name
        (``balance_factor=0.6`` is the proposal's; :data:`SECTION_OPTIONS`).  A section not
        named is computed when it is a default one, the layout has its section, or one of
        its options is given.  The proposal needs the moments and the roll, and is left out
        without them.

    Returns
    -------
    Request

    Raises
    ------
    InputError
        For an unknown keyword, an option of a section that is not computed, or a value
        out of range; the message names the keyword.
    """
    ks = parse_orders(orders)
    if tolerance is not None and model is not None:
        raise InputError("give a model or a tolerance, not both")
    if tolerance is not None and not (0 < tolerance < 1):
        raise InputError(f"tolerance: {tolerance!r} is not between 0 and 1, e.g. 1e-6")
    if model is not None and model not in MODELS:
        raise InputError(f"model: {model!r}; use one of {', '.join(MODELS)}")
    wanted = _sections(engine, sections, figures)
    speed_model = wanted.get("dynamics", {}).get("speed_model")
    if speed_model is None and "dynamics" in engine.sections:
        speed_model = "dynamic"
    from balance.io.several_cranks import refuse_unsupported

    refuse_unsupported(engine, wanted, speed_model)  # several crankshafts
    if speed_model == "dynamic" and model in ("series", "textbook"):
        raise InputError(
            f"model: {model!r} with the dynamic speed model, which samples the exact "
            "kinematics; give the exact model (or none)"
        )
    if not (moments and roll):
        wanted.pop("proposal", None)
    return Request.of(
        ks.tolist(),
        model=model or "exact",
        terms=int(terms),
        samples=samples,
        tolerance=tolerance,
        speed=None if speed is None else check_speed(speed),
        moments=moments,
        roll=roll,
        sections=wanted,
    )


def _sections(
    engine: Engine, given: Mapping[str, Any], figures: bool = False
) -> dict[str, dict[str, Any]]:
    """The sections to compute, each with its checked options."""
    asked: dict[str, Any] = {}
    options: dict[str, dict[str, Any]] = {}
    for key, setting in given.items():
        if key in SECTION_OPTIONS:
            options.setdefault(SECTION_OPTIONS[key], {})[key] = setting
        elif key in {s.name for s in SECTIONS}:
            asked[key] = setting
        else:
            shared = [s.name for s in SECTIONS if key in s.options]
            if shared:
                raise InputError(
                    f"{key}: an option of {' and '.join(shared)}; give it in its section's "
                    f"mapping, e.g. {shared[0]}={{{key!r}: ...}}"
                )
            known = sorted({s.name for s in SECTIONS} | set(SECTION_OPTIONS))
            raise InputError(f"{key}: not a setting of an analysis; use one of {', '.join(known)}")
    out: dict[str, dict[str, Any]] = {}
    for section in SECTIONS:
        value = asked.get(section.name)
        own = dict(options.get(section.name, {}))
        if isinstance(value, Mapping):
            own = {**dict(value), **own}
            value = True
        with_options = False
        if own:  # each option known to the section; one that says more turns it on
            own = {k: v for k, v in own.items() if v is not None}
            unknown = set(own) - set(section.options)
            if unknown:
                raise InputError(
                    f"{section.name}: no option {', '.join(sorted(unknown))}; "
                    f"its options are {', '.join(section.options) or 'none'}"
                )
            with_options = any(_given(v) for v in own.values())
        # an option given turns its section on, unless the section is turned off
        on = (_turned_on(section, engine) or with_options) if value is None else bool(value)
        if not on:
            if with_options:
                raise InputError(
                    f"{', '.join(sorted(own))}: an option of the {section.title.lower()} "
                    f"({section.name}), which this analysis is asked not to compute"
                )
            continue
        if figures:
            own = {**dict(section.figure_options), **own}
        out[section.name] = _checked(section.name, own)
    return out


def _given(value: Any) -> bool:
    """Whether an option says more than its default (False and empty are defaults)."""
    return value is not False and value is not None


def _checked(name: str, options: dict[str, Any]) -> dict[str, Any]:
    """A section's options, each checked once."""
    if not options:  # nothing to check (most sections of most requests)
        return {}
    out = dict(options)
    if "balance_factor" in out:
        factor = float(out["balance_factor"])
        if not 0.0 <= factor <= 2.0:
            raise InputError(f"balance_factor: {factor!r} is outside 0 to 2 (0 % to 200 %)")
        out["balance_factor"] = factor
    if out.get("balance_factor_of") is not None:
        if out["balance_factor_of"] not in CONVENTIONS:
            raise InputError(
                f"balance_factor_of: {out['balance_factor_of']!r}; use one of "
                f"{', '.join(CONVENTIONS)}"
            )
        if out.get("balance_factor") is None:
            raise InputError(
                "balance_factor_of: the convention of a balance_factor; give the factor too"
            )
    if "counterweight_radius" in out:
        radius = float(out["counterweight_radius"])
        if not (math.isfinite(radius) and radius > 0):
            raise InputError(f"counterweight_radius: must be more than zero, got {radius!r} m")
        out["counterweight_radius"] = radius
    if "strategy" in out and out["strategy"] not in STRATEGIES:
        raise InputError(f"strategy: {out['strategy']!r}; use one of {', '.join(STRATEGIES)}")
    if "cancel" in out:
        out["cancel"] = tuple(int(k) for k in parse_orders(out["cancel"]))
    if "factors" in out:
        factors = np.asarray(out["factors"], dtype=np.float64).ravel()
        if factors.size == 0 or not np.all((factors >= 0) & (factors <= 2)):
            raise InputError("factors: balance factors between 0 and 2 (0 % to 200 %)")
        out["factors"] = factors
    if "speed_model" in out and out["speed_model"] not in SPEED_MODELS:
        raise InputError(
            f"speed_model: {out['speed_model']!r}; use one of {', '.join(SPEED_MODELS)}"
        )
    if isinstance(out.get("load"), str):
        from balance.io.fields import load_of

        out["load"] = load_of(out["load"])
    for flag in ("cancel_roll", "with_proposal", "strategies"):
        if flag in out:
            out[flag] = bool(out[flag])
    if "speeds" in out and not isinstance(out["speeds"], str):
        speeds = np.asarray(out["speeds"], dtype=np.float64).ravel()
        if speeds.size == 0 or not np.all(np.isfinite(speeds) & (speeds > 0)):
            raise InputError("speeds: every speed must be a finite number above zero [rad/s]")
        out["speeds"] = speeds
    return out
