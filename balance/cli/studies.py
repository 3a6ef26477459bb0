"""The commands that study many analyses: ``compare`` (layouts side by side), ``sweep`` (a
grid of variants of one layout), ``search`` (crank arrangements) and ``tolerance`` (Monte
Carlo over part scatter).  Each reads its options and hands them to :mod:`balance.studies`,
and the outcome to a view.
"""

# No ``from __future__ import annotations``: typer reads the annotations of every command's
# parameters when it builds the command line (see balance/cli/__init__.py).

import sys
from collections.abc import Callable
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any

import typer

from balance.cli.common import (
    Model,
    OutputFile,
    Quiet,
    ReplaceOutput,
    check_output,
    console,
    emit_rich,
    emit_text,
    guarded,
    options_named,
    parse_speed,
    warn,
    write_netcdf,
)
from balance.core.errors import InputError

__all__ = ["COMMANDS"]


class CompareFormat(StrEnum):
    """Output formats of ``balance compare``."""

    table = "table"
    markdown = "markdown"
    csv = "csv"
    json = "json"
    netcdf = "netcdf"


def _expand_layout_args(layouts: list[str], all_builtin: bool) -> list[str]:
    import glob

    from balance.io.layout_file import builtin_layout_names

    names: list[str] = list(builtin_layout_names()) if all_builtin else []
    for item in layouts:
        if any(ch in item for ch in "*?["):
            matches = sorted(glob.glob(item))
            if not matches:
                raise InputError(f"{item}: the pattern matches no file")
            names.extend(matches)
        else:
            names.append(item)
    if not names:
        raise InputError("compare: give layout files, built-in names, a glob, or --all")
    return names


@guarded
def compare_command(
    layouts: Annotated[
        list[str] | None, typer.Argument(help="Layout files, built-in names or globs.")
    ] = None,
    all_builtin: Annotated[bool, typer.Option("--all", help="Every built-in layout.")] = False,
    orders: Annotated[str, typer.Option("--orders", help="Orders, e.g. 1-4.")] = "1-4",
    absolute: Annotated[
        bool, typer.Option("--absolute", help="Absolute values (N, N m) instead of normalised.")
    ] = False,
    speed: Annotated[
        str | None, typer.Option("--speed", help="Common crank speed, e.g. 6000rpm.")
    ] = None,
    displacement: Annotated[
        str | None,
        typer.Option("--displacement", help="Scale every layout to this displacement, e.g. 2L."),
    ] = None,
    pitch: Annotated[
        str | None,
        typer.Option(
            "--pitch",
            help="One pitch a for the moments per F1 a of every layout, e.g. 90mm (default: "
            "each layout's pitch: key, else its bore pitch).",
        ),
    ] = None,
    model: Annotated[
        Model, typer.Option("--model", help="Piston acceleration model.")
    ] = Model.exact,
    format: Annotated[
        CompareFormat, typer.Option("--format", "-f", help="Output format.")
    ] = CompareFormat.table,
    output: OutputFile = None,
    force: ReplaceOutput = False,
    quiet: Quiet = False,
) -> None:
    """Compare layouts side by side: free forces, moments, roll and balancing needs."""
    import json

    from balance.io.fields import parse_option_quantity
    from balance.io.layout_file import load_layout
    from balance.io.orders import parse_orders
    from balance.studies.compare import compare_results
    from balance.views.compare import (
        compare_csv,
        compare_json,
        compare_table,
        comparison_dataset,
        markdown_table,
        render_comparison,
    )

    names = _expand_layout_args(layouts or [], all_builtin)
    order_list = parse_orders(orders, "--orders")
    speed_value = parse_speed(speed)
    volume = None
    if displacement is not None:
        volume = parse_option_quantity(displacement, "volume", "--displacement")
        if volume <= 0:
            raise InputError("--displacement: must be more than zero")
    pitch_value = None
    if pitch is not None:
        pitch_value = parse_option_quantity(pitch, "length", "--pitch")
        if not pitch_value > 0:
            raise InputError("--pitch: must be a length above zero, e.g. 90mm")
    check_output(output, force, binary=format is CompareFormat.netcdf)
    engines = [load_layout(name) for name in names]
    labels = [Path(n).stem if n.endswith((".yaml", ".yml")) else n for n in names]
    compared = compare_results(
        engines,
        labels,
        order_list,
        speed=speed_value,
        displacement=volume,
        model=model.value,
        pitch=pitch_value,
    )
    for c in compared:
        warn(c.result.warnings, quiet, c.label)
    ds = comparison_dataset(
        [c.result for c in compared],
        [c.label for c in compared],
        [c.scale_factor for c in compared],
        speed=speed_value,
        displacement=volume,
        pitch=pitch_value,
    )
    if format is CompareFormat.netcdf:
        assert output is not None
        write_netcdf(ds, output, force)
        return
    if format is CompareFormat.json:
        emit_text(json.dumps(compare_json(ds), indent=2, allow_nan=False) + "\n", output, force)
        return
    headers, rows = compare_table(ds, normalised=not absolute)
    if format is CompareFormat.markdown:
        emit_text(markdown_table(headers, rows), output, force)
    elif format is CompareFormat.csv:
        emit_text(compare_csv(headers, rows), output, force)
    else:
        from rich.console import Group

        emit_rich(Group(*render_comparison(ds, absolute=absolute)), output, force, width=240)


@guarded
def sweep_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
    vary: Annotated[
        list[str],
        typer.Option(
            "--vary",
            help="FIELD=start:stop:count or FIELD=a,b,c, e.g. conrod_length=130mm:160mm:31, "
            "cylinders[3].reciprocating=0.4kg:0.7kg:13, crank.v_angle=60:90:7 or "
            "balance.balance_factor=30%:100%:15; repeat for more dimensions.",
        ),
    ],
    output: Annotated[
        Path,
        typer.Option("--output", "-o", help="File to write: NAME.nc (netCDF) or NAME.zarr (Zarr)."),
    ],
    orders: Annotated[str, typer.Option("--orders", help="Orders, e.g. 1-8 or 1,2.")] = "1-8",
    model: Annotated[
        str, typer.Option("--model", help="Piston acceleration model: exact, series, textbook.")
    ] = "exact",
    no_moments: Annotated[bool, typer.Option("--no-moments", help="Skip the moments.")] = False,
    no_roll: Annotated[bool, typer.Option("--no-roll", help="Skip the roll torque.")] = False,
    chunk_size: Annotated[
        int, typer.Option("--chunk-size", min=1, help="Grid points per chunk (bounds memory).")
    ] = 50_000,
    scheduler: Annotated[
        str | None, typer.Option("--scheduler", help="Dask scheduler address to run chunks on.")
    ] = None,
    workers: Annotated[
        int | None, typer.Option("--workers", min=1, help="Run on a local Dask cluster.")
    ] = None,
    progress: Annotated[
        bool | None,
        typer.Option("--progress/--no-progress", help="Progress bar (default: on a terminal)."),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Replace an existing file.")] = False,
    quiet: Quiet = False,
) -> None:
    """Analyse a grid of layout variants and write one Dataset (netCDF or Zarr), chunk by chunk."""
    import time

    from balance.io.fields import check_varies, parse_vary
    from balance.io.layout_file import load_layout
    from balance.studies import sweep
    from balance.studies.sweep import sweep_to_file

    started = time.perf_counter()
    sweep.check_output(output, force)
    if scheduler is not None and workers is not None:
        raise InputError("give --scheduler or --workers, not both")
    base = load_layout(layout)
    grid = check_varies([parse_vary(text, base, "--vary") for text in vary], "--vary")
    balanced = [v.field.text for v in grid if v.field.attribute.startswith("balance.")]
    if balanced and (no_moments or no_roll):
        raise InputError(
            f"--vary {balanced[0]}: the residual with the proposal needs the moments and the "
            "roll; drop --no-moments and --no-roll"
        )
    if not quiet:
        from balance.studies.checks import sweep_warnings

        warn(sweep_warnings(base, grid), quiet, layout)
    show = sys.stderr.isatty() if progress is None else progress
    if show:
        from balance.views.progress import ProgressBar
    kwargs: dict[str, Any] = {
        "model": model,
        "moments": not no_moments,
        "roll": not no_roll,
        "chunk_size": chunk_size,
        "progress": ProgressBar() if show else None,
        "force": force,
    }
    with options_named(vary="--vary", model="--model", orders="--orders"):
        if scheduler is None and workers is None:
            sweep_to_file(base, grid, output, orders, **kwargs)
        else:
            from distributed import Client, LocalCluster

            if scheduler is not None:
                with Client(scheduler) as client:
                    sweep_to_file(base, grid, output, orders, client=client, **kwargs)
            else:
                with (
                    LocalCluster(
                        n_workers=workers, threads_per_worker=1, dashboard_address=None
                    ) as cluster,
                    Client(cluster) as client,
                ):
                    sweep_to_file(base, grid, output, orders, client=client, **kwargs)
    from balance.views.progress import sweep_summary

    sys.stderr.write(
        sweep_summary(
            output,
            [(v.dim, v.values.size) for v in grid],
            time.perf_counter() - started,
        )
        + "\n"
    )


@guarded
def search_command(
    cylinders: Annotated[int, typer.Option("--cylinders", min=1, max=16, help="Cylinders.")],
    banks: Annotated[
        str, typer.Option("--banks", help="Bank angles, e.g. 0 (inline) or -45,45 (90 deg V).")
    ] = "0",
    step: Annotated[str, typer.Option("--step", help="Angle step of throws.")] = "30deg",
    even_firing: Annotated[
        bool, typer.Option("--even-firing", help="Only evenly firing arrangements.")
    ] = False,
    no_split: Annotated[
        bool, typer.Option("--no-split", help="Common crank pins only (no split-pin offsets).")
    ] = False,
    objective: Annotated[
        str, typer.Option("--objective", help="free, moments or shafts (after counterweights).")
    ] = "free",
    orders: Annotated[str, typer.Option("--orders", help="Orders the objective counts.")] = "1-2",
    rod_ratio: Annotated[
        float, typer.Option("--rod-ratio", help="Crank radius / conrod length.")
    ] = 0.3,
    top: Annotated[int, typer.Option("--top", min=1, help="How many to print.")] = 5,
) -> None:
    """Enumerate crank arrangements, drop symmetric duplicates, print the best."""
    from balance.io.fields import parse_option_quantity
    from balance.io.orders import parse_orders
    from balance.studies.search import search

    step_deg = parse_option_quantity(step, "angle", "--step")
    bank_list = [parse_option_quantity(b, "angle", "--banks") for b in banks.split(",")]
    with options_named(
        objective="--objective",
        cylinders="--cylinders",
        step="--step",
        rod_ratio="--rod-ratio",
        orders="--orders",
    ):
        result = search(
            cylinders,
            bank_list,
            step=step_deg,
            even_firing=even_firing,
            split=not no_split,
            objective=objective,
            orders=[int(k) for k in parse_orders(orders, "--orders")],
            rod_ratio=rod_ratio,
            top=top,
        )
    from rich.console import Group

    from balance.views.studies import search_tables

    console().print(Group(*search_tables(result)))


@guarded
def tolerance_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
    scatter: Annotated[
        list[str],
        typer.Option("--scatter", help="FIELD=±TOL, e.g. reciprocating=±3g; repeatable."),
    ],
    samples: Annotated[int, typer.Option("--samples", min=1, help="Engines drawn.")] = 100_000,
    orders: Annotated[str, typer.Option("--orders", help="Orders, e.g. 1-2.")] = "1-2",
    distribution: Annotated[
        str, typer.Option("--distribution", help="uniform (±TOL) or normal (sigma TOL/3).")
    ] = "uniform",
    seed: Annotated[int, typer.Option("--seed", help="Random seed.")] = 0,
    plot: Annotated[
        Path | None,
        typer.Option("--plot", help="Write histograms of the balanced residuals (png, svg, pdf)."),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Replace an existing plot.")] = False,
    quiet: Quiet = False,
) -> None:
    """Monte Carlo over part-mass and geometry scatter: percentiles of the residuals."""
    from balance.io.fields import parse_scatter
    from balance.io.layout_file import load_layout
    from balance.studies.tolerance import PERCENTILES, tolerance

    if plot is not None:
        from balance.io.atomic import check_target

        if plot.suffix.lower().lstrip(".") not in ("png", "svg", "pdf"):
            raise InputError(f"--plot {plot}: give a .png, .svg or .pdf file for the histograms")
        check_target(plot, force)
    engine = load_layout(layout)
    items = [parse_scatter(text, engine, "--scatter") for text in scatter]
    if not quiet:
        from balance.studies.checks import tolerance_warnings

        warn(tolerance_warnings(engine, items), quiet, layout)
    with options_named(
        scatter="--scatter", distribution="--distribution", samples="--samples", orders="--orders"
    ):
        result = tolerance(
            engine,
            items,
            samples=samples,
            orders=orders,
            distribution=distribution,
            seed=seed,
        )
    from rich.console import Group

    from balance.views.studies import tolerance_histogram, tolerance_tables

    console().print(Group(*tolerance_tables(result, PERCENTILES)))
    if plot is not None:
        from balance.io.atomic import write_atomic
        from balance.views.studies import figure_metadata

        fig = tolerance_histogram(result)
        fmt = plot.suffix.lower().lstrip(".")
        metadata = figure_metadata(result, fmt)
        write_atomic(plot, lambda tmp: fig.savefig(tmp, format=fmt, metadata=metadata), force=force)
        sys.stderr.write(f"balance: wrote {plot}\n")


#: The commands of this module, by name (:mod:`balance.cli` puts them in order).
COMMANDS: dict[str, Callable[..., None]] = {
    "compare": compare_command,
    "sweep": sweep_command,
    "search": search_command,
    "tolerance": tolerance_command,
}
