"""CSV view: one row per order, the per-order variables of the result Dataset as columns."""

from __future__ import annotations

import csv
import io
import math

import xarray as xr

__all__ = ["to_csv"]


def _cell(value: float) -> str:
    return "" if not math.isfinite(value) else repr(float(value))


def to_csv(ds: xr.Dataset) -> str:
    """Per-order table: forward and backward magnitude and phase, peak, normalised peak.

    Columns carry their units in brackets, e.g. ``force_forward_magnitude [N]``.  Roll is
    joined on the same order where the roll orders match the orders.
    """
    columns: list[tuple[str, str, dict[str, str]]] = []
    for what in ("force", "moment"):
        prefix = f"reciprocating_{what}"
        if f"{prefix}_magnitude" not in ds:
            continue  # not asked for
        for rotation in ("forward", "backward"):
            for part in ("magnitude", "phase"):
                columns.append(
                    (f"{prefix}_{part}", f"{what}_{rotation}_{part}", {"rotation": rotation})
                )
        columns.append((f"{prefix}_peak", f"{what}_peak", {}))
        columns.append((f"{prefix}_peak_normalised", f"{what}_peak_normalised", {}))
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    header = ["order"] + [f"{name} [{ds[var].attrs['units']}]" for var, name, _ in columns]
    has_roll = "roll_amplitude" in ds
    if has_roll:
        header += [f"roll_amplitude [{ds['roll_amplitude'].attrs['units']}]", "roll_phase [deg]"]
    writer.writerow(header)
    roll_orders = {float(k) for k in ds["roll_order"].values} if has_roll else set()
    for k in ds["order"].values:
        row = [str(int(k))]
        for var, _, sel in columns:
            row.append(_cell(float(ds[var].sel({"order": k, **sel}))))
        if float(k) in roll_orders:
            row.append(_cell(float(ds["roll_amplitude"].sel(roll_order=float(k)))))
            row.append(_cell(float(ds["roll_phase"].sel(roll_order=float(k)))))
        elif has_roll:
            row += ["", ""]
        writer.writerow(row)
    return buffer.getvalue()
