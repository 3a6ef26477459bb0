"""Comparing layouts side by side: one Dataset with a ``layout`` dimension.

Every layout is analysed with the same orders and model; its per-order results are
stacked along ``layout``.  Layouts of different size compare fairly when scaled to one
displacement (geometric similarity) and run at one speed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from balance.api import analyse
from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.io.fields import parse_orders

__all__ = ["compare", "compare_json", "compare_table", "markdown_table", "scale_layout"]

_PER_LAYOUT_DIMS = {"order", "rotation", "roll_order"}


def scale_layout(layout: Engine, factor: float) -> Engine:
    """A geometrically similar engine: lengths times ``factor``, masses times its cube.

    Moments of inertia scale with the fifth power.  Forces at the same speed then scale
    with ``factor**4`` and moments with ``factor**5``.
    """
    if not (math.isfinite(factor) and factor > 0):
        raise InputError(f"scale factor must be a positive number, got {factor!r}")
    balance = layout.balance
    if balance is not None and balance.counterweight_radius is not None:
        balance = replace(balance, counterweight_radius=balance.counterweight_radius * factor)
    return replace(
        layout,
        z=layout.z * factor,
        crank_radius=layout.crank_radius * factor,
        conrod_length=layout.conrod_length * factor,
        offset=layout.offset * factor,
        reciprocating_mass=layout.reciprocating_mass * factor**3,
        rotating_mass=layout.rotating_mass * factor**3,
        conrod_inertia_correction=layout.conrod_inertia_correction * factor**5,
        reference_z=layout.reference_z * factor,
        pitch=layout.pitch * factor,
        bore=layout.bore * factor,
        balance=balance,
        mass_parts=layout.mass_parts.scaled(factor) if layout.mass_parts is not None else None,
    )


def _label(layout: Engine, given: str, taken: set[str]) -> str:
    base = given
    label, i = base, 2
    while label in taken:
        label = f"{base} ({i})"
        i += 1
    taken.add(label)
    return label


def compare(
    layouts: Sequence[Engine],
    names: Sequence[str] | None = None,
    orders: int | str | Sequence[int] | NDArray[np.integer] | None = "1-4",
    *,
    speed: float | None = None,
    displacement: float | None = None,
    model: str = "exact",
    terms: int = 3,
) -> xr.Dataset:
    """Analyse several layouts the same way and stack the results along ``layout``.

    Parameters
    ----------
    layouts : sequence of Engine
    names : sequence of str, optional
        Labels for the ``layout`` coordinate (default the layout names), made unique.
    orders : int, str or sequence of int
        Orders of every analysis (default 1 to 4).
    speed : float, optional
        Common crank speed [rad/s]; default each layout's own.
    displacement : float, optional
        Scale every layout to this total displacement [m^3] (geometric similarity, see
        :func:`scale_layout`); needs each layout's ``bore``.
    model, terms
        Piston acceleration model (see :func:`balance.analyse`).

    Returns
    -------
    xarray.Dataset
        Per-order variables of :func:`balance.analyse` with a leading ``layout`` dimension,
        plus ``n_cylinders``, ``displacement``, ``scale_factor``,
        ``counterweight_total_mass``, ``counterweight_total_unbalance`` and ``n_shafts``.
    """
    if not layouts:
        raise InputError("compare: give at least one layout")
    ks = parse_orders(orders)
    labels = list(names) if names is not None else [lay.name for lay in layouts]
    taken: set[str] = set()
    pieces = []
    for layout, given in zip(layouts, labels, strict=True):
        factor = 1.0
        if displacement is not None:
            if not math.isfinite(layout.bore):
                raise InputError(
                    f"{given}: scaling to a displacement needs geometry.bore in the layout"
                )
            factor = (displacement / layout.displacement) ** (1.0 / 3.0)
            layout = scale_layout(layout, factor)
        ds = analyse(layout, ks, speed=speed, model=model, terms=terms)
        keep = [name for name, var in ds.data_vars.items() if set(var.dims) <= _PER_LAYOUT_DIMS]
        piece = ds[keep]
        piece = piece.drop_vars([c for c in piece.coords if c not in _PER_LAYOUT_DIMS])
        if "roll_order" in piece.dims:
            # with gas forces a four-stroke's roll has half orders too; compare the orders
            # every layout has
            piece = piece.sel(roll_order=ks.astype(np.float64))
        extra = {
            "n_cylinders": (layout.n_cylinders, "1", "number of cylinders"),
            "displacement": (layout.displacement, "m3", "swept volume (NaN without a bore)"),
            "scale_factor": (factor, "1", "length scale applied to reach the displacement"),
            "counterweight_total_mass": (
                float(ds["counterweight_mass"].sum()) if "counterweight_mass" in ds else 0.0,
                "kg",
                "sum of the proposed counterweight masses",
            ),
            "counterweight_total_unbalance": (
                float(ds["counterweight_unbalance"].sum())
                if "counterweight_unbalance" in ds
                else 0.0,
                "kg m",
                "sum of the proposed counterweight unbalances",
            ),
            "n_shafts": (int(ds.sizes.get("shaft", 0)), "1", "number of proposed balance shafts"),
        }
        for name, (value, units, long_name) in extra.items():
            piece[name] = xr.Variable((), value, attrs={"units": units, "long_name": long_name})
        piece = piece.expand_dims(layout=[_label(layout, given, taken)])
        pieces.append(piece)
    # variables that only some layouts have (the torque summary with gas forces) are left out
    common = set.intersection(*(set(p.data_vars) for p in pieces))
    pieces = [p[[name for name in p.data_vars if name in common]] for p in pieces]
    out = xr.concat(pieces, dim="layout", combine_attrs="drop_conflicts")
    for var_name in out.data_vars:
        # a long_name that differs between layouts (roll with or without gas) is dropped by
        # the concatenation; keep the units and a name that covers both
        if "long_name" not in out[var_name].attrs:
            names = sorted({str(p[var_name].attrs.get("long_name", var_name)) for p in pieces})
            out[var_name].attrs["long_name"] = " / ".join(names)
        if "units" not in out[var_name].attrs:
            out[var_name].attrs["units"] = str(pieces[0][var_name].attrs.get("units", "1"))
    out["layout"].attrs.update({"units": "1", "long_name": "layout"})
    out.attrs = {
        "schema": "balance.comparison/1",
        "model": model,
        "orders": ",".join(map(str, ks)),
        "common_speed_rpm": "" if speed is None else speed * 60 / (2 * math.pi),
        "displacement_m3": "" if displacement is None else displacement,
    }
    return out


def compare_table(ds: xr.Dataset, normalised: bool = True) -> tuple[list[str], list[list[str]]]:
    """Headers and formatted rows of a comparison (zeros print as 0).

    Normalised: peaks per :math:`F_1 = m_{rec} r\\omega^2` and per :math:`F_1 a`, roll per
    :math:`m_{rec} r^2\\omega^2`.  Absolute: N, N m.
    """
    from balance.views.table import format_number

    ks = [int(k) for k in ds["order"].values]
    suffix = "_normalised" if normalised else ""
    force_unit, moment_unit, roll_unit = (
        ("/F1", "/(F1 a)", "/(m r2 w2)") if normalised else (" [N]", " [N m]", " [N m]")
    )
    headers = ["layout", "cyl"]
    headers += [f"F{k}{force_unit}" for k in ks] + [f"M{k}{moment_unit}" for k in ks]
    headers += [f"rot F{force_unit}", f"rot M{moment_unit}"]
    headers += [f"roll {k}{roll_unit}" for k in ks]
    headers += ["cw mass [kg]", "shafts"]
    rows = []
    for label in ds["layout"].values:
        one = ds.sel(layout=label)
        row = [str(label), str(int(one["n_cylinders"]))]
        row += [
            format_number(float(one[f"reciprocating_force_peak{suffix}"].sel(order=k))) for k in ks
        ]
        row += [
            format_number(float(one[f"reciprocating_moment_peak{suffix}"].sel(order=k))) for k in ks
        ]
        rot = "_normalised" if normalised else "_magnitude"
        row += [
            format_number(float(one[f"rotating_force{rot}"])),
            format_number(float(one[f"rotating_moment{rot}"])),
        ]
        roll = "roll_amplitude_normalised" if normalised else "roll_amplitude"
        row += [format_number(float(one[roll].sel(roll_order=float(k)))) for k in ks]
        row += [format_number(float(one["counterweight_total_mass"])), str(int(one["n_shafts"]))]
        rows.append(row)
    return headers, rows


def markdown_table(headers: list[str], rows: list[list[str]]) -> str:
    """A GitHub-flavoured Markdown table."""

    def line(cells: list[str]) -> str:
        return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"

    out = [
        line(headers),
        "|" + "|".join("---" if i < 1 else "---:" for i in range(len(headers))) + "|",
    ]
    out += [line(r) for r in rows]
    return "\n".join(out) + "\n"


def compare_json(ds: xr.Dataset) -> dict[str, object]:
    """The comparison as plain data: one entry per layout, in the analysis JSON's shape."""
    from balance.views.json import _num, _orders

    entries = []
    for label in ds["layout"].values:
        one = ds.sel(layout=label)
        entries.append(
            {
                "layout": str(label),
                "n_cylinders": int(one["n_cylinders"]),
                "displacement_m3": _num(one["displacement"]),
                "scale_factor": _num(one["scale_factor"]),
                "speed_rpm": _num(one["speed"] * 60 / (2 * math.pi)),
                "reciprocating": {
                    "force": _orders(one, "reciprocating_force"),
                    "moment": _orders(one, "reciprocating_moment"),
                },
                "rotating": {
                    what: {
                        "peak": _num(one[f"rotating_{what}_magnitude"]),
                        "peak_normalised": _num(one[f"rotating_{what}_normalised"]),
                    }
                    for what in ("force", "moment")
                },
                "roll": [
                    {
                        "order": float(k),
                        "amplitude": _num(one["roll_amplitude"].sel(roll_order=k)),
                        "amplitude_normalised": _num(
                            one["roll_amplitude_normalised"].sel(roll_order=k)
                        ),
                    }
                    for k in one["roll_order"].values
                ],
                "balancing": {
                    "counterweight_total_mass_kg": _num(one["counterweight_total_mass"]),
                    "counterweight_total_unbalance_kgm": _num(one["counterweight_total_unbalance"]),
                    "n_shafts": int(one["n_shafts"]),
                },
            }
        )
    return {"schema": "balance.comparison/1", "model": ds.attrs["model"], "layouts": entries}
