"""The analysis JSON (``schema: balance.analysis/1``) of a :class:`~balance.core.result.Result`.

The free forces are read through the one phasor type
(:class:`~balance.core.phasors.Phasors`: magnitudes, phases and peaks each formed once);
each section the result holds adds its block (:mod:`balance.views.sections`).  No xarray.
The shape is that of docs/cli.md, "JSON output".
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from balance.core.catalogue import SCHEMA, speed_rpm
from balance.core.phasors import Phasors, Quantity, phase_deg, safe_ratio
from balance.views.polar import json_number, order_value
from balance.views.sections import views_of

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.result import Result

__all__ = [
    "merge",
    "order_entries",
    "roll_entries",
    "to_dict",
    "to_json",
]

_num = json_number  # the short name this module uses


def order_entries(
    orders: ArrayLike,
    magnitude: ArrayLike,
    phase: ArrayLike,
    peak: ArrayLike,
    normalised: ArrayLike,
) -> list[dict[str, Any]]:
    """Per-order entries from arrays, as the JSON writes a force or a moment.

    Parameters
    ----------
    orders : array_like of int
        The orders.
    magnitude, phase : array_like
        Shape (orders, 2): forward and backward magnitude [N or N m] and phase [deg].
    peak, normalised : array_like
        Per order: the peak [N or N m] and the peak per its reference [1].

    Returns
    -------
    list of dict
        ``{"order", "forward": {"magnitude", "phase_deg"}, "backward": {...}, "peak",
        "peak_normalised"}`` per order; a value that is not finite is None.
    """
    mag = np.asarray(magnitude)
    ph = np.asarray(phase)
    pk = np.asarray(peak)
    nm = np.asarray(normalised)
    return [
        {
            "order": int(k),
            "forward": {"magnitude": _num(mag[i, 0]), "phase_deg": _num(ph[i, 0])},
            "backward": {"magnitude": _num(mag[i, 1]), "phase_deg": _num(ph[i, 1])},
            "peak": _num(pk[i]),
            "peak_normalised": _num(nm[i]),
        }
        for i, k in enumerate(np.asarray(orders))
    ]


def _phasor_entries(phasors: Phasors, quantity: Quantity, reference: float) -> list[dict[str, Any]]:
    """Per-order entries of a force or moment: forward and backward magnitude and phase,
    peak ``|P+| + |P-|`` and peak per ``reference``."""
    peak = phasors.peak(quantity)
    return order_entries(
        phasors.orders,
        phasors.magnitude(quantity),
        phasors.phase(quantity),
        peak,
        safe_ratio(peak, reference),
    )


def roll_entries(orders: ArrayLike, roll: Any) -> list[dict[str, Any]]:
    """Per-order entries of a roll: amplitude and phase (half orders as floats).

    Parameters
    ----------
    orders : array_like
        The roll orders (halves with gas forces).
    roll : array_like of complex
        Roll phasors per order [N m].

    Returns
    -------
    list of dict
        ``{"order", "amplitude", "phase_deg"}`` per order [N m, deg].
    """
    amplitude = np.abs(roll)
    phase = phase_deg(roll)
    return [
        {"order": order_value(k), "amplitude": _num(amplitude[i]), "phase_deg": _num(phase[i])}
        for i, k in enumerate(np.asarray(orders))
    ]


def _rotating(phasors: Phasors, quantity: Quantity, reference: float) -> dict[str, Any]:
    phasor = phasors.rotating(quantity)
    magnitude = np.abs(phasor)
    return {
        "forward": {"magnitude": _num(magnitude), "phase_deg": _num(phase_deg(phasor))},
        "peak": _num(magnitude),
        "peak_normalised": _num(safe_ratio(magnitude, reference)),
    }


def to_dict(result: Result) -> dict[str, Any]:
    """The result as plain data in the JSON shape of docs/cli.md, "JSON output" (SI units,
    degrees): the free forces, moments and roll, a block per section the result holds, and
    the plausibility warnings as ``warnings`` (:func:`_warnings_json`).

    Parameters
    ----------
    result : Result
        The analysis.

    Returns
    -------
    dict
        Plain data (dicts, lists, numbers, strings) for ``json.dumps``.
    """
    p = result.phasors
    rotating = {"force": _rotating(p, "force", result.reference_force)}
    reciprocating = {"force": _phasor_entries(p, "force", result.reference_force)}
    if result.has_moments:
        rotating["moment"] = _rotating(p, "moment", result.reference_moment)
        reciprocating["moment"] = _phasor_entries(p, "moment", result.reference_moment)
    model = result.model
    out: dict[str, Any] = {
        "schema": SCHEMA,
        "layout": result.engine.name,
        "speed_rpm": speed_rpm(result.engine.speed),
        "reference_z_m": float(result.engine.reference_z),
        "model": model.name,
        "accuracy": {
            "error_bound": _num(model.error_bound),
            "series_terms": int(model.terms if model.name == "series" else 0),
            "time_samples": int(model.samples),
        },
        "normalisation": {
            "force_N": _num(result.reference_force),
            "pitch_m": _num(result.pitch),
            "moment_Nm": _num(result.reference_moment),
        },
        "reciprocating": reciprocating,
        "rotating": rotating,
    }
    if result.roll is not None:
        out["roll"] = roll_entries(result.roll_orders, result.roll)
    for _, views in views_of(result):
        block = getattr(views, "json_block", None)
        if block is not None:
            merge(out, block(result))
    out["warnings"] = _warnings_json(result)
    return out


def merge(out: dict[str, Any], block: dict[str, Any]) -> None:
    """Add a section's JSON block to ``out``: its new keys at the end, its objects under a
    key ``out`` has (``accuracy``) merged into that object, key by key, and its list of
    objects under a key whose list is as long (``cylinders``) merged entry by entry.

    Parameters
    ----------
    out : dict
        The JSON document so far (changed in place).
    block : dict
        What a section adds (its views module's ``json_block``).
    """
    for key, value in block.items():
        here = out.get(key)
        if isinstance(value, dict) and isinstance(here, dict):
            merge(here, value)
        elif (
            isinstance(here, list)
            and _entries(value)
            and _entries(here)
            and len(value) == len(here)
        ):
            for mine, theirs in zip(here, value, strict=True):  # one entry per cylinder
                merge(mine, theirs)
        else:
            out[key] = value


def _entries(value: Any) -> bool:
    return isinstance(value, list) and all(isinstance(v, dict) for v in value)


def _warnings_json(result: Result) -> list[dict[str, str]]:
    """The plausibility warnings: ``[{"rule": ..., "field": ..., "message": ...}]``
    (:mod:`balance.core.plausibility`), an empty list when there are none."""
    return [{"rule": w.rule, "field": w.field, "message": w.message} for w in result.warnings]


def to_json(result: Result, indent: int | None = 2) -> str:
    """The analysis JSON text of a result (:func:`to_dict`).

    Parameters
    ----------
    result : Result
        The analysis.
    indent : int or None
        Spaces per level; None for one line.

    Returns
    -------
    str
        The JSON text (docs/cli.md, "JSON output").
    """
    return json.dumps(to_dict(result), indent=indent, allow_nan=False) + "\n"
