"""A readable rich table of a result Dataset, for the terminal."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import xarray as xr

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import RenderableType

__all__ = ["format_number", "render", "render_factor_study", "render_proposal", "render_torque"]


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

    bound = float(ds.attrs.get("error_bound", float("nan")))
    title = (
        f"{ds.attrs['layout']}: {len(ds['cylinder'])} cylinders at "
        f"{ds.attrs['speed_rpm']:.0f} rpm, model {ds.attrs['model']}"
        + (f" (coefficient error below {bound:.1g})" if math.isfinite(bound) else "")
    )
    norm = Text(
        f"F1 = m_rec r w^2 = {format_number(float(ds['reference_force']))} N;  "
        f"pitch a = {format_number(float(ds['pitch']) * 1e3)} mm;  "
        f"moments about z = {format_number(float(ds['reference_z']) * 1e3)} mm"
    )
    tables = []
    has_moments = "reciprocating_moment_magnitude" in ds
    kinds = [("force", "N", "F1")] + ([("moment", "N m", "F1 a")] if has_moments else [])
    for what, unit, per in kinds:
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
    rotating_text = (
        "Rotating (order 1, forward): force "
        f"{format_number(float(ds['rotating_force_magnitude']))} N at "
        f"{format_number(float(ds['rotating_force_phase']))} deg"
    )
    if has_moments:
        rotating_text += (
            f";  moment {format_number(float(ds['rotating_moment_magnitude']))} N m at "
            f"{format_number(float(ds['rotating_moment_phase']))} deg"
        )
    parts: list[RenderableType] = [Text(title, style="bold"), norm, *tables, Text(rotating_text)]
    if "roll_amplitude" in ds:
        parts.append(_roll_table(ds))
    if "torque_mean" in ds:
        parts.append(render_torque(ds))
    if "counterweight_mass" in ds:
        parts.extend(render_proposal(ds))
    return Group(*parts)


def _roll_table(ds: xr.Dataset) -> RenderableType:
    from rich.table import Table

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
    return roll


def render_torque(ds: xr.Dataset) -> RenderableType:
    """Rich renderable of the torque summary of an analysis with gas forces."""
    from rich.table import Table

    table = Table(title="Engine torque with gas forces (over the cycle)", title_justify="left")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    rows = [
        ("mean torque [N m]", float(ds["torque_mean"])),
        ("largest torque [N m]", float(ds["torque_max"])),
        ("smallest torque [N m]", float(ds["torque_min"])),
        ("non-uniformity (M_max - M_min)/M_mean", float(ds["torque_nonuniformity"])),
        ("indicated work per cycle [J]", float(ds["indicated_work"])),
        ("largest excess work [J]", float(ds["excess_work"])),
        ("speed fluctuation (w_max - w_min)/w_mean", float(ds["speed_fluctuation"])),
        ("flywheel inertia [kg m^2]", float(ds["flywheel_inertia"])),
    ]
    from rich.markup import escape

    for label, value in rows:
        table.add_row(escape(label), format_number(value))
    return table


def render_proposal(ds: xr.Dataset) -> list[RenderableType]:
    """Rich renderables of the balancing proposal and its residual."""
    from rich.table import Table
    from rich.text import Text

    factor = ds.attrs.get("proposal_balance_factor", "")
    choice = (
        f"Proposal: strategy {ds.attrs['proposal_strategy']}, cancelling orders "
        f"{ds.attrs['proposal_orders']}"
        + ("" if factor == "" else f", balance factor {float(factor):.0%}")
    )
    out: list[RenderableType] = [Text(choice, style="bold")]
    notes = str(ds.attrs.get("proposal_notes", ""))
    if notes:
        out.append(Text(notes))
    n_cw = ds.sizes.get("counterweight", 0)
    n_shaft = ds.sizes.get("shaft", 0)
    if n_cw == 0 and n_shaft == 0:
        out.append(Text("Nothing to cancel: no counterweights or balance shafts are needed."))
    if n_cw:
        table = Table(title="Counterweights (turn with the crank)", title_justify="left")
        for label in ("z [mm]", "mass [kg]", "radius [mm]", "angle [deg]"):
            table.add_column(label, justify="right")
        for i in range(n_cw):
            table.add_row(
                format_number(float(ds["counterweight_z"][i]) * 1e3),
                format_number(float(ds["counterweight_mass"][i])),
                format_number(float(ds["counterweight_radius"][i]) * 1e3),
                format_number(float(ds["counterweight_angle"][i])),
            )
        out.append(table)
    if n_shaft:
        table = Table(title="Balance shafts", title_justify="left")
        for label in (
            "shaft",
            "speed ratio",
            "x [mm]",
            "y [mm]",
            "plane z [mm]",
            "unbalance [kg mm]",
            "angle [deg]",
        ):
            table.add_column(label, justify="right")
        for i in range(n_shaft):
            for j in range(ds.sizes.get("shaft_plane", 0)):
                z = float(ds["shaft_plane_z"][i, j])
                if not math.isfinite(z):
                    continue
                first = j == 0
                table.add_row(
                    str(i + 1) if first else "",
                    f"{int(ds['shaft_speed_ratio'][i]):+d}" if first else "",
                    format_number(float(ds["shaft_x"][i]) * 1e3) if first else "",
                    format_number(float(ds["shaft_y"][i]) * 1e3) if first else "",
                    format_number(z * 1e3),
                    format_number(float(ds["shaft_plane_unbalance"][i, j]) * 1e3),
                    format_number(float(ds["shaft_plane_angle"][i, j])),
                )
        out.append(table)
    table = Table(
        title="Residual with the proposal (all free forces and moments)", title_justify="left"
    )
    for label in (
        "order",
        "force peak [N]",
        "peak / F1",
        "moment peak [N m]",
        "peak / (F1 a)",
        "roll [N m]",
    ):
        table.add_column(label, justify="right")
    roll_orders = {float(k) for k in ds["roll_order"].values}
    for k in ds["order"].values:
        roll = (
            format_number(float(ds["residual_roll_amplitude"].sel(roll_order=float(k))))
            if float(k) in roll_orders
            else "-"
        )
        table.add_row(
            str(int(k)),
            format_number(float(ds["residual_force_peak"].sel(order=k))),
            format_number(float(ds["residual_force_peak_normalised"].sel(order=k))),
            format_number(float(ds["residual_moment_peak"].sel(order=k))),
            format_number(float(ds["residual_moment_peak_normalised"].sel(order=k))),
            roll,
        )
    out.append(table)
    return out


def render_factor_study(ds: xr.Dataset) -> list[RenderableType]:
    """Rich renderables of a balance-factor study (:mod:`balance.studies.factor`)."""
    from rich.table import Table
    from rich.text import Text

    table = Table(
        title="Balance factor study: residual first order (rotating masses balanced in full)",
        title_justify="left",
    )
    for label in ("factor", "vertical peak [N]", "horizontal peak [N]", "moment peak [N m]"):
        table.add_column(label, justify="right")
    for i, f in enumerate(ds["study_factor"].values):
        table.add_row(
            f"{f:.0%}",
            format_number(float(ds["study_vertical_peak"][i])),
            format_number(float(ds["study_horizontal_peak"][i])),
            format_number(float(ds["study_moment_peak"][i])),
        )
    best = float(ds["optimal_balance_factor"])
    return [table, Text(f"Factor minimising the larger force peak: {best:.1%}")]
