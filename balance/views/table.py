"""A readable rich table of a result Dataset, for the terminal."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import xarray as xr

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

__all__ = ["format_number", "render"]


def format_number(value: float, digits: int = 4) -> str:
    """Compact engineering formatting: 0 stays 0, NaN shows as a dash."""
    if not math.isfinite(value):
        return "-"
    if value == 0.0:
        return "0"
    return f"{value:.{digits}g}"


def render(ds: xr.Dataset) -> RenderableType:
    """Rich renderable: summary line, free forces and moments per order, rotating, roll."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    title = (
        f"{ds.attrs['layout']}: {len(ds['cylinder'])} cylinders at "
        f"{ds.attrs['speed_rpm']:.0f} rpm, model {ds.attrs['model']}"
    )
    norm = Text(
        f"F1 = m_rec r w^2 = {format_number(float(ds['reference_force']))} N;  "
        f"pitch a = {format_number(float(ds['pitch']) * 1e3)} mm;  "
        f"moments about z = {format_number(float(ds['reference_z']) * 1e3)} mm"
    )
    tables = []
    for what, unit, per in (("force", "N", "F1"), ("moment", "N m", "F1 a")):
        table = Table(
            title=f"Reciprocating inertia: free {what}s"
            + (" about reference_z" if what == "moment" else ""),
            title_justify="left",
        )
        table.add_column("order", justify="right")
        for label in (
            f"forward [{unit}]",
            "phase [deg]",
            f"backward [{unit}]",
            "phase [deg]",
            f"peak [{unit}]",
            f"peak / {per}",
        ):
            table.add_column(label, justify="right")
        prefix = f"reciprocating_{what}"
        for k in ds["order"].values:
            mag = ds[f"{prefix}_magnitude"].sel(order=k)
            phase = ds[f"{prefix}_phase"].sel(order=k)
            table.add_row(
                str(int(k)),
                format_number(float(mag.sel(rotation="forward"))),
                format_number(float(phase.sel(rotation="forward"))),
                format_number(float(mag.sel(rotation="backward"))),
                format_number(float(phase.sel(rotation="backward"))),
                format_number(float(ds[f"{prefix}_peak"].sel(order=k))),
                format_number(float(ds[f"{prefix}_peak_normalised"].sel(order=k))),
            )
        tables.append(table)
    rotating = Text(
        "Rotating (order 1, forward): force "
        f"{format_number(float(ds['rotating_force_magnitude']))} N at "
        f"{format_number(float(ds['rotating_force_phase']))} deg;  moment "
        f"{format_number(float(ds['rotating_moment_magnitude']))} N m at "
        f"{format_number(float(ds['rotating_moment_phase']))} deg"
    )
    roll = Table(title="Roll torque on the block (a_k cos(k theta + phase))", title_justify="left")
    roll.add_column("order", justify="right")
    roll.add_column("amplitude [N m]", justify="right")
    roll.add_column("phase [deg]", justify="right")
    roll.add_column("per m_rec r^2 w^2", justify="right")
    for k in ds["roll_order"].values:
        roll.add_row(
            f"{k:g}",
            format_number(float(ds["roll_amplitude"].sel(roll_order=k))),
            format_number(float(ds["roll_phase"].sel(roll_order=k))),
            format_number(float(ds["roll_amplitude_normalised"].sel(roll_order=k))),
        )
    return Group(Text(title, style="bold"), norm, *tables, rotating, roll)
