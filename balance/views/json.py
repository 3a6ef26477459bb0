"""The contract JSON (``schema: balance.analysis/1``) of a result Dataset."""

from __future__ import annotations

import json
import math
from typing import Any

import xarray as xr

__all__ = ["to_dict", "to_json"]


def _v(ds: xr.Dataset, name: str) -> Any:
    """A variable's values as numpy (through ``Dataset.variables``: no DataArray is built,
    which keeps a cold start's JSON view at about a millisecond)."""
    return ds.variables[name].values


def _num(value: Any) -> float | None:
    number = float(value)
    return number if math.isfinite(number) else None


def _phasor(ds: xr.Dataset, prefix: str) -> dict[str, Any]:
    """A scalar phasor (magnitude and phase variables without dimensions)."""
    return {
        "magnitude": _num(_v(ds, f"{prefix}_magnitude")),
        "phase_deg": _num(_v(ds, f"{prefix}_phase")),
    }


def _orders(ds: xr.Dataset, prefix: str) -> list[dict[str, Any]]:
    """Per-order entries; reads each variable once as a numpy array (``.sel`` per value
    would cost a cold start tens of milliseconds)."""
    variables = ds.variables
    magnitude = variables[f"{prefix}_magnitude"].transpose("order", "rotation").values
    phase = variables[f"{prefix}_phase"].transpose("order", "rotation").values
    peak = _v(ds, f"{prefix}_peak")
    normalised = _v(ds, f"{prefix}_peak_normalised")
    rotations = list(_v(ds, "rotation"))
    fwd, bwd = rotations.index("forward"), rotations.index("backward")
    return [
        {
            "order": int(k),
            "forward": {"magnitude": _num(magnitude[i, fwd]), "phase_deg": _num(phase[i, fwd])},
            "backward": {"magnitude": _num(magnitude[i, bwd]), "phase_deg": _num(phase[i, bwd])},
            "peak": _num(peak[i]),
            "peak_normalised": _num(normalised[i]),
        }
        for i, k in enumerate(_v(ds, "order"))
    ]


def _roll(ds: xr.Dataset, prefix: str) -> list[dict[str, Any]]:
    amplitude = _v(ds, f"{prefix}_amplitude")
    phase = _v(ds, f"{prefix}_phase")
    return [
        {"order": _order_value(k), "amplitude": _num(amplitude[i]), "phase_deg": _num(phase[i])}
        for i, k in enumerate(_v(ds, "roll_order"))
    ]


def _order_value(order: float) -> float | int:
    return int(order) if float(order).is_integer() else float(order)


def to_dict(ds: xr.Dataset) -> dict[str, Any]:
    """The result as plain data in the contract's JSON shape (SI units, degrees)."""
    has_moments = "reciprocating_moment_magnitude" in ds
    whats = ("force", "moment") if has_moments else ("force",)
    rotating = {}
    for what in whats:
        prefix = f"rotating_{what}"
        rotating[what] = {
            "forward": _phasor(ds, prefix),
            "peak": _num(_v(ds, f"{prefix}_magnitude")),
            "peak_normalised": _num(_v(ds, f"{prefix}_normalised")),
        }
    out: dict[str, Any] = {
        "schema": ds.attrs["schema"],
        "layout": ds.attrs["layout"],
        "speed_rpm": float(ds.attrs["speed_rpm"]),
        "reference_z_m": float(_v(ds, "reference_z")),
        "model": ds.attrs["model"],
        "accuracy": {
            "error_bound": _num(ds.attrs.get("error_bound", float("nan"))),
            "series_terms": int(ds.attrs.get("series_terms", 0)),
            "time_samples": int(ds.attrs.get("time_samples", 0)),
        },
        "normalisation": {
            "force_N": _num(_v(ds, "reference_force")),
            "pitch_m": _num(_v(ds, "pitch")),
            "moment_Nm": _num(_v(ds, "reference_moment")),
        },
        "reciprocating": {what: _orders(ds, f"reciprocating_{what}") for what in whats},
        "rotating": rotating,
    }
    if "roll_amplitude" in ds:
        out["roll"] = _roll(ds, "roll")
    if "torque_mean" in ds:
        out["torque"] = {
            "mean_Nm": _num(_v(ds, "torque_mean")),
            "max_Nm": _num(_v(ds, "torque_max")),
            "min_Nm": _num(_v(ds, "torque_min")),
            "speed_fluctuation": _num(_v(ds, "speed_fluctuation")),
            "flywheel_inertia_kgm2": _num(_v(ds, "flywheel_inertia")),
        }
        out["gas"] = {
            "indicated_work_J": _num(_v(ds, "indicated_work")),
            "torque_nonuniformity": _num(_v(ds, "torque_nonuniformity")),
            "excess_work_J": _num(_v(ds, "excess_work")),
            "firing_tdc_deg": [_num(v) for v in _v(ds, "firing_tdc")],
        }
    if "counterweight_mass" in ds:
        out["proposal"] = _proposal(ds)
    if "study_factor" in ds:
        out["balance_factor_study"] = {
            "optimal_factor": _num(_v(ds, "optimal_balance_factor")),
            "factors": [
                {
                    "factor": float(f),
                    "vertical_peak": _num(_v(ds, "study_vertical_peak")[i]),
                    "horizontal_peak": _num(_v(ds, "study_horizontal_peak")[i]),
                    "moment_peak": _num(_v(ds, "study_moment_peak")[i]),
                }
                for i, f in enumerate(_v(ds, "study_factor"))
            ],
        }
    return out


def _proposal(ds: xr.Dataset) -> dict[str, Any]:
    counterweights = [
        {
            "z_m": _num(_v(ds, "counterweight_z")[i]),
            "mass_kg": _num(_v(ds, "counterweight_mass")[i]),
            "radius_m": _num(_v(ds, "counterweight_radius")[i]),
            "angle_deg": _num(_v(ds, "counterweight_angle")[i]),
        }
        for i in range(ds.sizes.get("counterweight", 0))
    ]
    shafts = []
    for i in range(ds.sizes.get("shaft", 0)):
        planes = []
        for j in range(ds.sizes.get("shaft_plane", 0)):
            z = float(_v(ds, "shaft_plane_z")[i, j])
            if math.isfinite(z):
                planes.append(
                    {
                        "z_m": z,
                        "unbalance_kgm": _num(_v(ds, "shaft_plane_unbalance")[i, j]),
                        "angle_deg": _num(_v(ds, "shaft_plane_angle")[i, j]),
                    }
                )
        shafts.append(
            {
                "speed_ratio": int(_v(ds, "shaft_speed_ratio")[i]),
                "x_m": _num(_v(ds, "shaft_x")[i]),
                "y_m": _num(_v(ds, "shaft_y")[i]),
                "planes": planes,
            }
        )
    factor = ds.attrs.get("proposal_balance_factor", "")
    return {
        "strategy": ds.attrs["proposal_strategy"],
        "orders": [int(k) for k in str(ds.attrs["proposal_orders"]).split(",") if k],
        "balance_factor": None if factor == "" else float(factor),
        "notes": [n for n in str(ds.attrs.get("proposal_notes", "")).split("; ") if n],
        "counterweights": counterweights,
        "balance_shafts": shafts,
        "residual": {
            what: [
                {"order": int(k), "peak": _num(peak[i]), "peak_normalised": _num(norm[i])}
                for i, k in enumerate(_v(ds, "order"))
            ]
            for what, peak, norm in (
                (w, _v(ds, f"residual_{w}_peak"), _v(ds, f"residual_{w}_peak_normalised"))
                for w in ("force", "moment")
            )
        }
        | {"roll": _roll(ds, "residual_roll")},
    }


def to_json(ds: xr.Dataset, indent: int | None = 2) -> str:
    """The contract JSON text of a result Dataset."""
    return json.dumps(to_dict(ds), indent=indent, allow_nan=False) + "\n"
