"""The contract JSON (``schema: balance.analysis/1``) of a :class:`~balance.core.result.Result`.

Reads the Result's complex phasors and stored references directly (magnitudes with
``np.abs``, phases with :func:`balance.views.polar.phase_deg`); no xarray.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.views.polar import (
    SCHEMA,
    json_number,
    order_value,
    phase_deg,
    safe_ratio,
    speed_rpm,
)

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.balancing import Proposal
    from balance.core.result import Result
    from balance.core.torque import TorqueResult

__all__ = [
    "cylinder_entries",
    "json_number",
    "order_entries",
    "to_dict",
    "to_json",
    "warnings_json",
]

ComplexArray = NDArray[np.complex128]


_num = json_number  # the short name this module uses


def order_entries(
    orders: ArrayLike,
    magnitude: ArrayLike,
    phase: ArrayLike,
    peak: ArrayLike,
    normalised: ArrayLike,
) -> list[dict[str, Any]]:
    """Per-order entries from arrays: ``magnitude`` and ``phase`` (order, rotation) with the
    rotations forward and backward, ``peak`` and ``normalised`` per order."""
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


def _phasor_orders(
    orders: ArrayLike, forward: ComplexArray, backward: ComplexArray, reference: float
) -> list[dict[str, Any]]:
    """Per-order entries of forward and backward phasors; peak ``|P+| + |P-|``."""
    both = np.stack([forward, backward], axis=-1)
    magnitude = np.abs(both)
    peak = magnitude[..., 0] + magnitude[..., 1]
    return order_entries(orders, magnitude, phase_deg(both), peak, safe_ratio(peak, reference))


def _roll(orders: ArrayLike, roll: ComplexArray) -> list[dict[str, Any]]:
    amplitude = np.abs(roll)
    phase = phase_deg(roll)
    return [
        {"order": order_value(k), "amplitude": _num(amplitude[i]), "phase_deg": _num(phase[i])}
        for i, k in enumerate(np.asarray(orders))
    ]


def _rotating(phasor: complex, reference: float) -> dict[str, Any]:
    magnitude = np.abs(phasor)
    return {
        "forward": {"magnitude": _num(magnitude), "phase_deg": _num(phase_deg(phasor))},
        "peak": _num(magnitude),
        "peak_normalised": _num(safe_ratio(magnitude, reference)),
    }


def to_dict(result: Result, factor_study: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The result as plain data in the contract's JSON shape (SI units, degrees), with
    the plausibility warnings as ``warnings`` (:func:`warnings_json`).

    ``factor_study``: a balance-factor study (:func:`balance.studies.factor.factor_study_dataset`,
    or any mapping of its variable names to arrays), reported as ``balance_factor_study``.
    """
    p = result.phasors
    ks = p.orders
    rotating = {"force": _rotating(p.rotating_force, result.reference_force)}
    reciprocating = {
        "force": _phasor_orders(ks, p.force_forward, p.force_backward, result.reference_force)
    }
    if result.has_moments:
        rotating["moment"] = _rotating(p.rotating_moment, result.reference_moment)
        reciprocating["moment"] = _phasor_orders(
            ks, p.moment_forward, p.moment_backward, result.reference_moment
        )
    out: dict[str, Any] = {
        "schema": SCHEMA,
        "layout": result.engine.name,
        "speed_rpm": speed_rpm(result.engine.speed),
        "reference_z_m": float(result.engine.reference_z),
        "model": p.model,
        "accuracy": {
            "error_bound": _num(p.error_bound),
            "series_terms": int(p.terms if p.model == "series" else 0),
            "time_samples": int(p.samples),
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
        out["roll"] = _roll(result.roll_orders, result.roll)
    if result.cylinder_stroke is not None:
        out["cylinders"] = cylinder_entries(result)
    if result.torque is not None:
        out.update(_torque(result.torque))
    if result.balanced is not None:
        assert result.residual_roll is not None  # a proposal needs the roll
        b = result.balanced
        out["proposal"] = _proposal(b.proposal) | {
            "residual": {
                "force": _residual(ks, b.force_forward, b.force_backward, result.reference_force),
                "moment": _residual(
                    ks, b.moment_forward, b.moment_backward, result.reference_moment
                ),
                "roll": _roll(result.roll_orders, result.residual_roll),
            }
        }
    if factor_study is not None:
        out["balance_factor_study"] = _factor_study(factor_study)
    if result.mounts is not None:
        out["mounts"] = _mounts(result)
    if result.bearings is not None:
        from balance.views.bearings import bearings_json

        out["bearings"] = bearings_json(result.bearings)
    out["warnings"] = warnings_json(result)
    return out


def warnings_json(result: Result) -> list[dict[str, str]]:
    """The plausibility warnings: ``[{"rule": ..., "field": ..., "message": ...}]``
    (:mod:`balance.core.plausibility`), an empty list when there are none."""
    return [{"rule": w.rule, "field": w.field, "message": w.message} for w in result.warnings]


def cylinder_entries(result: Result) -> list[dict[str, Any]]:
    """The ``cylinders`` list (CONTRACT §5): number, actual stroke [m], TDC crank angle
    [deg] in [0, 360); a link cylinder also gets its ``link`` (master, pin and rod)."""
    assert result.cylinder_stroke is not None and result.cylinder_tdc is not None
    links = result.engine.links
    entries = []
    for i, (stroke, tdc) in enumerate(
        zip(result.cylinder_stroke, np.degrees(result.cylinder_tdc), strict=True)
    ):
        entry: dict[str, Any] = {
            "number": i + 1,
            "stroke_m": _num(stroke),
            "tdc_crank_deg": _num(tdc),
        }
        if links is not None and links.master[i] >= 0:
            entry["link"] = {
                "master": int(links.master[i]) + 1,
                "pin_radius_m": _num(links.pin_radius[i]),
                "pin_angle_deg": _num(math.degrees(float(links.pin_angle[i]))),
                "length_m": _num(result.engine.conrod_length[i]),
            }
        entries.append(entry)
    return entries


def _mounts(result: Result) -> dict[str, Any]:
    """The ``mounts`` block (CONTRACT §7), from :mod:`balance.views.mounts`."""
    from balance.views.mounts import mounts_json

    assert result.mounts is not None
    return mounts_json(result.mounts)


def _torque(t: TorqueResult) -> dict[str, Any]:
    return {
        "torque": {
            "mean_Nm": _num(t.mean),
            "max_Nm": _num(t.maximum),
            "min_Nm": _num(t.minimum),
            "speed_fluctuation": _num(t.speed_fluctuation),
            "flywheel_inertia_kgm2": _num(t.flywheel_inertia),
        },
        "gas": {
            "indicated_work_J": _num(t.mean * 2.0 * math.pi * t.cycle_deg / 360.0),
            "torque_nonuniformity": _num(t.nonuniformity),
            "excess_work_J": _num(t.excess_work),
            "firing_tdc_deg": [_num(v) for v in np.asarray(t.firing_tdc)],
        },
    }


def _residual(
    orders: ArrayLike, forward: ComplexArray, backward: ComplexArray, reference: float
) -> list[dict[str, Any]]:
    peak = np.abs(np.stack([forward, backward], axis=-1)).sum(axis=-1)
    normalised = safe_ratio(peak, reference)
    return [
        {"order": int(k), "peak": _num(peak[i]), "peak_normalised": _num(normalised[i])}
        for i, k in enumerate(np.asarray(orders))
    ]


def _proposal(proposal: Proposal) -> dict[str, Any]:
    counterweights = [
        {
            "z_m": _num(c.z),
            "mass_kg": _num(c.mass),
            "radius_m": _num(c.radius),
            "angle_deg": _num(c.angle_deg),
        }
        for c in proposal.counterweights
    ]
    shafts = []
    for s in proposal.shafts:
        unbalance = np.array([u for _, u in s.planes], dtype=np.complex128)
        angle = phase_deg(unbalance)
        planes = [
            {
                "z_m": float(z),
                "unbalance_kgm": _num(np.abs(unbalance[j])),
                "angle_deg": _num(angle[j]),
            }
            for j, (z, _) in enumerate(s.planes)
        ]
        shafts.append(
            {
                "speed_ratio": int(s.speed_ratio),
                "x_m": _num(s.x),
                "y_m": _num(s.y),
                "position_from": {"x": s.x_from, "y": s.y_from},
                "planes": planes,
            }
        )
    factor = proposal.balance_factor
    return {
        "strategy": proposal.strategy,
        "orders": [int(k) for k in proposal.orders],
        "balance_factor": None if factor is None else float(factor),
        "cancel_roll": bool(proposal.cancel_roll),
        "notes": [n for n in proposal.notes if n],
        "counterweights": counterweights,
        "balance_shafts": shafts,
    }


def _factor_study(study: Mapping[str, Any]) -> dict[str, Any]:
    factors = np.asarray(study["study_factor"])
    vertical = np.asarray(study["study_vertical_peak"])
    horizontal = np.asarray(study["study_horizontal_peak"])
    moment = np.asarray(study["study_moment_peak"])
    return {
        "optimal_factor": _num(np.asarray(study["optimal_balance_factor"])),
        "factors": [
            {
                "factor": float(f),
                "vertical_peak": _num(vertical[i]),
                "horizontal_peak": _num(horizontal[i]),
                "moment_peak": _num(moment[i]),
            }
            for i, f in enumerate(factors)
        ],
    }


def to_json(
    result: Result, indent: int | None = 2, factor_study: Mapping[str, Any] | None = None
) -> str:
    """The contract JSON text of a result."""
    return json.dumps(to_dict(result, factor_study), indent=indent, allow_nan=False) + "\n"
