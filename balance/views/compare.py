"""The views of a comparison of layouts (:mod:`balance.studies.compare`).

:func:`comparison_dataset` stacks the analyses along a ``layout`` dimension (the Dataset of
``balance compare --format netcdf`` and of :func:`balance.compare`); :func:`compare_table`,
:func:`markdown_table`, :func:`compare_csv`, :func:`compare_json` and
:func:`render_comparison` print it.  Besides the free forces and the balancing needs, every
output of a section that declares itself a comparison column (:attr:`Output.compare
<balance.core.catalogue.Output.compare>`, :func:`balance.core.catalogue.compared`) is a
column of its own, NaN (``-``) for a layout whose analysis lacks it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from balance.core.catalogue import Compared, Output, compared, speed_rpm
from balance.core.speed import rad_per_s_to_rpm
from balance.views.json import order_entries
from balance.views.polar import json_number
from balance.views.table import format_number

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr
    from rich.console import RenderableType

    from balance.core.result import Result

__all__ = [
    "compare_csv",
    "compare_json",
    "compare_table",
    "comparison_dataset",
    "markdown_table",
    "pitch_heading",
    "render_comparison",
]

_PER_LAYOUT_DIMS = {"order", "rotation", "roll_order"}


def comparison_dataset(
    results: Sequence[Result],
    labels: Sequence[str],
    scale_factors: Sequence[float],
    *,
    speed: float | None = None,
    displacement: float | None = None,
    pitch: float | None = None,
) -> xr.Dataset:
    """The analyses of a comparison (:func:`balance.studies.compare.compare_results`)
    stacked along ``layout``, one label and length scale factor each.

    Parameters
    ----------
    results : sequence of Result
        One analysis per layout, with the same orders.
    labels : sequence of str
        Each layout's label (its name, or the file when names repeat).
    scale_factors : sequence of float
        The length scale applied to each layout [1] (1 without ``displacement``).
    speed : float, optional
        The common crank speed asked for [rad/s].
    displacement : float, optional
        The common displacement asked for [m^3].
    pitch : float, optional
        The common pitch asked for [m] (every result's ``pitch`` already is this one).

    Returns
    -------
    xarray.Dataset
        Per-order variables of :func:`balance.analyse` with a leading ``layout`` dimension,
        plus ``n_cylinders``, ``displacement``, ``scale_factor``,
        ``counterweight_total_mass``, ``counterweight_total_unbalance``, ``n_shafts`` and
        every compared output (:func:`balance.core.catalogue.compared`; NaN for a layout
        without it).
        ``speed``, ``displacement`` and ``pitch`` are recorded in the attributes
        ``common_speed_rpm``, ``displacement_m3`` and ``common_pitch_m`` when asked for;
        ``orders`` is an integer array.
    """
    import xarray as xr

    from balance.views.dataset import build_dataset

    first = results[0].request
    ks = np.asarray(first.orders, dtype=np.intp)
    pieces = []
    for result, label, factor in zip(results, labels, scale_factors, strict=True):
        layout = result.engine
        ds = build_dataset(result)
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
            "scale_factor": (
                factor,
                "1",
                "length scale applied to reach the displacement",
            ),
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
        for output in compared():
            extra[output.name] = (_scalar(ds, output.name), output.units, _spec(output).long_name)
        for name, (value, units, long_name) in extra.items():
            piece[name] = xr.Variable((), value, attrs={"units": units, "long_name": long_name})
        piece = piece.expand_dims(layout=[label])
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
        "model": first.model,
        "orders": np.asarray(ks, dtype=np.int64),
    }
    # numbers as numbers, present only when asked for
    if speed is not None:
        out.attrs["common_speed_rpm"] = speed_rpm(speed)
    if displacement is not None:
        out.attrs["displacement_m3"] = float(displacement)
    if pitch is not None:
        out.attrs["common_pitch_m"] = float(pitch)
    return out


def _columns(ds: xr.Dataset) -> list[Output]:
    """The compared outputs (:func:`balance.core.catalogue.compared`) that some layout of
    the comparison has (a finite value), in section order: a column each."""
    return [
        output
        for output in compared()
        if output.name in ds and bool(np.isfinite(ds[output.name].values).any())
    ]


def _spec(output: Output) -> Compared:
    """How the comparison shows a compared output."""
    assert output.compare is not None
    return output.compare


def _scalar(ds: xr.Dataset, name: str) -> float:
    """A scalar output of an analysis, NaN where the analysis has none (a section it did
    not compute)."""
    return float(ds[name]) if name in ds else float("nan")


def compare_table(ds: xr.Dataset, normalised: bool = True) -> tuple[list[str], list[list[str]]]:
    r"""Headers and formatted rows of a comparison (zeros print as 0).

    Parameters
    ----------
    ds : xarray.Dataset
        The comparison (:func:`comparison_dataset`).
    normalised : bool
        Peaks per :math:`F_1 = m_{rec} r\omega^2` and per :math:`F_1 a`, roll per
        :math:`m_{rec} r^2\omega^2`; otherwise absolute, in N and N m.

    Returns
    -------
    headers : list of str
    rows : list of list of str
        One row per layout.
    """
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
    columns = _columns(ds)
    headers += [_spec(output).header for output in columns]
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
        row += [format_number(float(one[output.name])) for output in columns]
        rows.append(row)
    return headers, rows


def markdown_table(headers: list[str], rows: list[list[str]]) -> str:
    """A GitHub-flavoured Markdown table.

    Parameters
    ----------
    headers : list of str
        The column headers.
    rows : list of list of str
        The cells, row by row.

    Returns
    -------
    str
    """

    def line(cells: list[str]) -> str:
        return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"

    out = [
        line(headers),
        "|" + "|".join("---" if i < 1 else "---:" for i in range(len(headers))) + "|",
    ]
    out += [line(r) for r in rows]
    return "\n".join(out) + "\n"


def compare_json(ds: xr.Dataset) -> dict[str, object]:
    """The comparison as plain data: one entry per layout, in the analysis JSON's shape.

    Parameters
    ----------
    ds : xarray.Dataset
        The comparison (:func:`comparison_dataset`).

    Returns
    -------
    dict
        Plain data for ``json.dumps``.
    """
    entries = []
    for label in ds["layout"].values:
        one = ds.sel(layout=label)
        entries.append(
            {
                "layout": str(label),
                "n_cylinders": int(one["n_cylinders"]),
                "displacement_m3": json_number(one["displacement"]),
                "scale_factor": json_number(one["scale_factor"]),
                "speed_rpm": json_number(rad_per_s_to_rpm(float(one["speed"]))),
                "pitch_m": json_number(one["pitch"]),
                "reciprocating": {
                    "force": _orders(one, "reciprocating_force"),
                    "moment": _orders(one, "reciprocating_moment"),
                },
                "rotating": {
                    what: {
                        "peak": json_number(one[f"rotating_{what}_magnitude"]),
                        "peak_normalised": json_number(one[f"rotating_{what}_normalised"]),
                    }
                    for what in ("force", "moment")
                },
                "roll": [
                    {
                        "order": float(k),
                        "amplitude": json_number(one["roll_amplitude"].sel(roll_order=k)),
                        "amplitude_normalised": json_number(
                            one["roll_amplitude_normalised"].sel(roll_order=k)
                        ),
                    }
                    for k in one["roll_order"].values
                ],
                "balancing": {
                    "counterweight_total_mass_kg": json_number(one["counterweight_total_mass"]),
                    "counterweight_total_unbalance_kgm": json_number(
                        one["counterweight_total_unbalance"]
                    ),
                    "n_shafts": int(one["n_shafts"]),
                },
            }
        )
    return {"schema": "balance.comparison/1", "model": ds.attrs["model"], "layouts": entries}


def _orders(ds: xr.Dataset, prefix: str) -> list[dict[str, Any]]:
    """Per-order entries of ``{prefix}_*`` variables of one layout of the comparison."""
    variables = ds.variables
    rotations = list(variables["rotation"].values)
    pick = [rotations.index("forward"), rotations.index("backward")]
    return order_entries(
        variables["order"].values,
        variables[f"{prefix}_magnitude"].transpose("order", "rotation").values[:, pick],
        variables[f"{prefix}_phase"].transpose("order", "rotation").values[:, pick],
        variables[f"{prefix}_peak"].values,
        variables[f"{prefix}_peak_normalised"].values,
    )


def compare_csv(headers: list[str], rows: list[list[str]]) -> str:
    """The table of :func:`compare_table` as CSV.

    Parameters
    ----------
    headers : list of str
        The column headers.
    rows : list of list of str
        The cells, row by row.

    Returns
    -------
    str
    """
    import csv
    import io

    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(headers)
    writer.writerows(rows)
    return buffer.getvalue()


def render_comparison(ds: xr.Dataset, *, absolute: bool) -> list[RenderableType]:
    r"""The comparison for the terminal: one table per quantity, a row per layout.

    Free force peaks per order (and the rotating force), free moment peaks, roll
    amplitudes, and the balancing needs (cylinders, counterweight mass, shafts, and each
    compared output some layout has, :func:`balance.core.catalogue.compared`).  Normalised
    values are per each layout's own :math:`F_1 = m_{rec} r\omega^2`, :math:`F_1 a` and
    :math:`m_{rec} r^2\omega^2`, with :math:`a` its pitch (the layout's ``pitch``, else its
    bore pitch, :func:`balance.core.engine.bore_pitch`), which the heading says; where a
    layout has no pitch (every cylinder in one plane, or one cylinder per bank) its
    moments per :math:`F_1 a` print as ``n/a``, and a note under the table says why.

    Parameters
    ----------
    ds : xarray.Dataset
        The comparison (:func:`comparison_dataset`).
    absolute : bool
        Print forces in N and moments in N m instead of normalised values.

    Returns
    -------
    list of rich.console.RenderableType
    """
    from rich.text import Text

    from balance.views.fitted import Column, NumberTable

    ks = [int(k) for k in ds["order"].values]
    labels = [str(label) for label in ds["layout"].values]
    layout = Column("layout", key=True, justify="left")
    suffix = "" if absolute else "_normalised"
    kind = "absolute" if absolute else "normalised"
    out: list[RenderableType] = [
        Text(f"Comparison of {len(labels)} layouts ({kind}; model {ds.attrs['model']})", "bold")
    ]
    if not absolute:
        out.append(Text(pitch_heading(ds)))

    no_pitch = (
        [label for label in labels if not np.isfinite(float(ds["pitch"].sel(layout=label)))]
        if "pitch" in ds
        else []
    )
    note = (
        (
            "n/a: no pitch a (all cylinders in one plane, or one cylinder per bank) for "
            + ", ".join(no_pitch),
        )
        if no_pitch and not absolute
        else ()
    )
    for what, unit, per in (("force", "N", "F1"), ("moment", "N m", "F1 a")):
        name = f"reciprocating_{what}_peak{suffix}"
        if name not in ds:
            continue
        rotating = f"rotating_{what}_{'magnitude' if absolute else 'normalised'}"
        with_pitch = what == "moment" and not absolute and "pitch" in ds
        rows = []
        for label in labels:
            one = ds.sel(layout=label)
            rows.append(
                [
                    label,
                    *([_pitch_cell(float(one["pitch"]))] if with_pitch else []),
                    *(_cell(float(one[name].sel(order=k)), name) for k in ks),
                    _cell(float(one[rotating]), rotating),
                ]
            )
        column_unit = unit if absolute else per
        out.append(
            NumberTable(
                f"Free {what} peaks: reciprocating per order, rotating (order 1)",
                [
                    layout,
                    *([Column("pitch a", "mm")] if with_pitch else []),
                    *(Column(f"order {k}", column_unit) for k in ks),
                    Column("rotating", column_unit),
                ],
                rows,
                notes=note if what == "moment" else (),
            )
        )
    roll = "roll_amplitude" if absolute else "roll_amplitude_normalised"
    if roll in ds:
        out.append(
            NumberTable(
                "Roll torque amplitude per order"
                + ("" if absolute else " (m r^2 w^2: m_rec r^2 w^2 of each layout)"),
                [
                    layout,
                    *(Column(f"order {k}", "N m" if absolute else "m r^2 w^2") for k in ks),
                ],
                [
                    [
                        label,
                        *(
                            _cell(float(ds[roll].sel(layout=label, roll_order=float(k))), roll)
                            for k in ks
                        ),
                    ]
                    for label in labels
                ],
            )
        )
    extra = _columns(ds)
    columns = [
        layout,
        Column("cylinders"),
        Column("counterweight mass", "kg"),
        Column("balance shafts"),
        *(Column(_spec(output).title, output.units) for output in extra),
    ]
    rows = []
    for label in labels:
        one = ds.sel(layout=label)
        row = [
            label,
            str(int(one["n_cylinders"])),
            format_number(float(one["counterweight_total_mass"])),
            str(int(one["n_shafts"])),
        ]
        row += [format_number(float(one[output.name])) for output in extra]
        rows.append(row)
    out.append(NumberTable("Balancing needs: what each layout's proposal uses", columns, rows))
    return out


def pitch_heading(ds: xr.Dataset) -> str:
    """What the normalised values of a comparison are per: each layout's :math:`F_1` and
    its own pitch (the layout's ``pitch``, else its bore pitch), or one pitch for all.

    Parameters
    ----------
    ds : xarray.Dataset
        The comparison (:func:`comparison_dataset`).

    Returns
    -------
    str
    """
    common = ds.attrs.get("common_pitch_m")
    if common is not None:
        return (
            "Per each layout's F1 = m_rec r w^2; moments per F1 a with one pitch "
            f"a = {format_number(float(common) * 1e3)} mm for every layout"
        )
    return (
        "Per each layout's F1 = m_rec r w^2; moments per F1 a with a the layout's pitch: "
        "its pitch: key, else its bore pitch (between neighbouring cylinders of one bank)"
    )


def _pitch_cell(pitch: float) -> str:
    """A layout's pitch [m] as the moment table prints it, in mm (``n/a`` without one)."""
    return format_number(pitch * 1e3) if np.isfinite(pitch) else "n/a"


def _cell(value: float, name: str) -> str:
    """A compared value: ``n/a`` for a normalised moment without a pitch."""
    if not np.isfinite(value) and name.endswith("_normalised") and "moment" in name:
        return "n/a"
    return format_number(value)
