"""The contract JSON (``schema: balance.analysis/1``) of a result Dataset."""

from __future__ import annotations

import json
import math
from typing import Any

import xarray as xr

__all__ = ["to_dict", "to_json"]


def _num(value: Any) -> float | None:
    number = float(value)
    return number if math.isfinite(number) else None


def _phasor(ds: xr.Dataset, prefix: str, **sel: Any) -> dict[str, Any]:
    return {
        "magnitude": _num(ds[f"{prefix}_magnitude"].sel(**sel)),
        "phase_deg": _num(ds[f"{prefix}_phase"].sel(**sel)),
    }


def _orders(ds: xr.Dataset, prefix: str) -> list[dict[str, Any]]:
    out = []
    for k in ds["order"].values:
        out.append(
            {
                "order": int(k),
                "forward": _phasor(ds, prefix, order=k, rotation="forward"),
                "backward": _phasor(ds, prefix, order=k, rotation="backward"),
                "peak": _num(ds[f"{prefix}_peak"].sel(order=k)),
                "peak_normalised": _num(ds[f"{prefix}_peak_normalised"].sel(order=k)),
            }
        )
    return out


def _order_value(order: float) -> float | int:
    return int(order) if float(order).is_integer() else float(order)


def to_dict(ds: xr.Dataset) -> dict[str, Any]:
    """The result as plain data in the contract's JSON shape (SI units, degrees)."""
    rotating = {}
    for what in ("force", "moment"):
        prefix = f"rotating_{what}"
        rotating[what] = {
            "forward": _phasor(ds, prefix),
            "peak": _num(ds[f"{prefix}_magnitude"]),
            "peak_normalised": _num(ds[f"{prefix}_normalised"]),
        }
    return {
        "schema": ds.attrs["schema"],
        "layout": ds.attrs["layout"],
        "speed_rpm": float(ds.attrs["speed_rpm"]),
        "reference_z_m": float(ds["reference_z"]),
        "model": ds.attrs["model"],
        "normalisation": {
            "force_N": _num(ds["reference_force"]),
            "pitch_m": _num(ds["pitch"]),
            "moment_Nm": _num(ds["reference_moment"]),
        },
        "reciprocating": {
            "force": _orders(ds, "reciprocating_force"),
            "moment": _orders(ds, "reciprocating_moment"),
        },
        "rotating": rotating,
        "roll": [
            {
                "order": _order_value(k),
                "amplitude": _num(ds["roll_amplitude"].sel(roll_order=k)),
                "phase_deg": _num(ds["roll_phase"].sel(roll_order=k)),
            }
            for k in ds["roll_order"].values
        ],
    }


def to_json(ds: xr.Dataset, indent: int | None = 2) -> str:
    """The contract JSON text of a result Dataset."""
    return json.dumps(to_dict(ds), indent=indent, allow_nan=False) + "\n"
