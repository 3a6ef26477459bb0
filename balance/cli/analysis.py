"""The commands that analyse one layout: ``analyse``, ``propose``, ``plot``, ``report`` and
``mounts``.

Each reads its options, loads the layout and builds the request through the one front door
(:func:`_prepare`, :func:`balance.io.request.build_request`), computes, and hands the result
to a view.  Every option of the engine on its mounts and of the bearing loads (``--mounts``,
``--on-mounts``, ``--with-proposal``, ``--bearings``) is declared here, and only here.
"""

# No ``from __future__ import annotations``: typer reads the annotations of every command's
# parameters when it builds the command line (see balance/cli/__init__.py).

import os
import sys
from collections.abc import Callable
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from balance.cli.common import (
    Model,
    OutputFile,
    Quiet,
    ReplaceOutput,
    Speed,
    check_output,
    console,
    emit_rich,
    emit_text,
    guarded,
    parse_speed,
    warn,
    write_netcdf,
)
from balance.core.errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.engine import Engine
    from balance.core.result import Request, Result

__all__ = ["COMMANDS"]


class SpeedModel(StrEnum):
    """Speed models (docs/dynamics.md)."""

    constant = "constant"
    dynamic = "dynamic"


class Format(StrEnum):
    """Output formats of ``balance analyse``."""

    table = "table"
    json = "json"
    csv = "csv"
    netcdf = "netcdf"


_Bearings = Annotated[
    bool,
    typer.Option(
        "--bearings",
        help="Crank-pin and main-bearing loads and internal moments "
        "(default mains unless the layout has a bearings: section).",
    ),
]


def _prepare(
    layout: str,
    orders: str,
    speed: str | None,
    *,
    output: Path | None = None,
    force: bool = False,
    binary: bool = False,
    mounts_file: Path | None = None,
    sweep_speeds: str | None = None,
    sweep_of: str = "mounts",
    **settings: Any,
) -> "tuple[Engine, Request]":
    """The preamble of a command that analyses one layout, written once.

    Reads ``--orders`` and ``--speed`` (each checked here, once), refuses an output that
    cannot be written (``output``/``force``; ``binary``: a format that needs ``-o``) before
    any work is done, loads the layout (with the mounts of ``--mounts FILE`` in place of its
    ``mounts:`` section), reads ``sweep_speeds`` (the ``--speed`` of ``balance mounts`` and
    ``balance torsion``: start:stop:count or a list, each above zero) into the ``speeds`` of
    the section ``sweep_of`` and builds the
    :class:`~balance.core.result.Request` with ``settings`` through the one front door
    (:func:`balance.io.request.build_request`, as :func:`balance.analyse` does).  A command
    with another kind of output (a directory of figures) checks it before calling this.
    """
    from balance.io.layout_reader import load_layout
    from balance.io.orders import parse_orders
    from balance.io.request import build_request

    order_list = parse_orders(orders, "--orders")
    speed_value = parse_speed(speed)
    check_output(output, force, binary)
    engine = load_layout(layout)
    if mounts_file is not None:
        from balance.io.mounts_section import load_mounts

        engine = engine.with_section("mounts", load_mounts(mounts_file))
    if "mounts" not in engine.sections:
        if settings.get("mounts"):
            raise InputError(
                f"layout '{engine.name}' has no mounts: section; add one, or give --mounts FILE"
            )
        if settings.get("with_proposal"):
            raise InputError(
                "--with-proposal puts the proposal on the mounts, and layout "
                f"'{engine.name}' has no mounts: section; give --mounts FILE (or add one)"
            )
    if sweep_speeds is not None:
        from balance.io.fields import parse_field, parse_values

        speeds = parse_values(sweep_speeds, parse_field("speed", engine), "--speed")
        if not (speeds.min() > 0):
            raise InputError(f"--speed: {sweep_speeds!r}: every speed must be above zero")
        given = settings.get(sweep_of)
        settings[sweep_of] = {**(given if isinstance(given, dict) else {}), "speeds": speeds}
    return engine, build_request(engine, order_list, speed=speed_value, **settings)


@guarded
def analyse_command(
    layout: Annotated[
        str, typer.Argument(help="Layout file or built-in name (see 'balance layouts').")
    ],
    format: Annotated[Format, typer.Option("--format", "-f", help="Output format.")] = Format.table,
    orders: Annotated[
        str,
        typer.Option("--orders", help="Orders to report: a range or list, e.g. 1-8, 2, 1,2,4-6."),
    ] = "1-8",
    speed: Annotated[
        str | None,
        typer.Option("--speed", help="Crank speed instead of the layout's, e.g. 7000rpm."),
    ] = None,
    model: Annotated[
        Model | None,
        typer.Option("--model", help="Piston acceleration model (default exact)."),
    ] = None,
    terms: Annotated[
        int, typer.Option("--terms", min=1, max=60, help="Series terms (--model series).")
    ] = 3,
    samples: Annotated[
        int | None,
        typer.Option("--samples", min=4, max=2**22, help="Crank angles (--model time)."),
    ] = None,
    tolerance: Annotated[
        float | None,
        typer.Option(
            "--tolerance",
            help="Largest coefficient error allowed; picks the cheapest model that meets it.",
        ),
    ] = None,
    speed_model: Annotated[
        SpeedModel | None,
        typer.Option(
            "--speed-model",
            help="constant (the default) or dynamic: the crank train's own motion over the "
            "cycle (needs a flywheel: section; default dynamic with a dynamics: section).",
        ),
    ] = None,
    load: Annotated[
        str | None,
        typer.Option(
            "--load",
            help="Load of the dynamic speed model: mean (default), propeller, a torque "
            "(150Nm) or a power law (80Nm@3000rpm^2).",
        ),
    ] = None,
    no_moments: Annotated[bool, typer.Option("--no-moments", help="Skip the moments.")] = False,
    no_roll: Annotated[bool, typer.Option("--no-roll", help="Skip the roll torque.")] = False,
    no_proposal: Annotated[
        bool, typer.Option("--no-proposal", help="Skip the balancing proposal.")
    ] = False,
    mounts: Annotated[
        Path | None,
        typer.Option(
            "--mounts",
            help="Engine on its mounts: a mounts file (mass, cg, inertia, points); "
            "replaces the layout's mounts: section.",
        ),
    ] = None,
    on_mounts: Annotated[
        bool,
        typer.Option(
            "--on-mounts",
            help="Engine on its mounts (the default for a layout with a mounts: section; "
            "kept for older scripts).",
        ),
    ] = False,
    with_proposal: Annotated[
        bool,
        typer.Option("--with-proposal", help="Load the mounts with the proposal added."),
    ] = False,
    bearings: _Bearings = False,
    torsion: Annotated[
        bool,
        typer.Option(
            "--torsion",
            help="Torsional vibration at the analysis speed (the default for a layout with "
            "a torsion: section; 'balance torsion' sweeps the speed).",
        ),
    ] = False,
    output: OutputFile = None,
    force: ReplaceOutput = False,
    quiet: Quiet = False,
) -> None:
    """Analyse a layout: free forces, moments and roll per order, and a balancing proposal."""
    from balance.core.analysis import compute

    engine, request = _prepare(
        layout,
        orders,
        speed,
        output=output,
        force=force,
        binary=format is Format.netcdf,
        mounts_file=mounts,
        model=None if model is None else model.value,
        terms=terms,
        samples=samples,
        tolerance=tolerance,
        moments=not no_moments,
        roll=not no_roll,
        proposal=False if no_proposal else None,
        mounts=True if (mounts is not None or on_mounts) else None,
        with_proposal=with_proposal,
        bearings=True if bearings else None,
        speed_model=None if speed_model is None else speed_model.value,
        load=None if load is None else _load_of(load),
        torsion=True if torsion else None,
    )
    result = compute(engine, request)
    warn(result.warnings, quiet, layout)
    _write(result, format, output, force)


def _load_of(text: str) -> Any:
    """The load of ``--load`` (:func:`balance.io.fields.load_of`; the grammar of the fields
    imported only when the option is given)."""
    from balance.io.fields import load_of

    return load_of(text, "--load")


def _write(
    result: "Result",
    format: Format,
    output: Path | None,
    force: bool,
    only: tuple[str, ...] | None = None,
) -> None:
    """Hand the result to the view of ``format`` (``only``: the sections the table shows,
    after a short heading, as ``balance propose`` prints)."""
    if format is Format.json:
        from balance.views.json import to_json

        emit_text(to_json(result), output, force)
    elif format is Format.csv:
        from balance.views.csv import to_csv

        emit_text(to_csv(result), output, force)
    elif format is Format.netcdf:
        from balance.views.dataset import build_dataset

        assert output is not None
        write_netcdf(build_dataset(result), output, force)
    else:
        from balance.views.table import render

        emit_rich(render(result, only), output, force, width=140)


class Strategy(StrEnum):
    """Counterweight strategies."""

    two_plane = "two-plane"
    per_throw = "per-throw"


class FactorOf(StrEnum):
    """What a balance factor is a share of (docs/theory.md, "The balance factor")."""

    each_cylinder = "each-cylinder"
    one_cylinder = "one-cylinder"


def _parse_fraction(text: str, option: str) -> float:
    from balance.io.fields import parse_option_quantity

    value = parse_option_quantity(text, "fraction", option)
    if not 0.0 <= value <= 2.0:
        raise InputError(f"{option}: {text!r} is outside 0 % to 200 %")
    return value


def _parse_length(text: str, option: str) -> float:
    from balance.io.fields import parse_option_quantity

    value = parse_option_quantity(text, "length", option)
    if value <= 0:
        raise InputError(f"{option}: must be more than zero")
    return value


@guarded
def propose_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
    cancel: Annotated[
        str | None,
        typer.Option("--cancel", help="Orders to cancel, e.g. 1,2 (default: layout's, else 1,2)."),
    ] = None,
    strategy: Annotated[
        Strategy | None, typer.Option("--strategy", help="Counterweights: two-plane or per-throw.")
    ] = None,
    balance_factor: Annotated[
        str | None,
        typer.Option(
            "--balance-factor",
            help="Share of each cylinder's reciprocating mass on the crank, e.g. 50% "
            "(see --balance-factor-of).",
        ),
    ] = None,
    balance_factor_of: Annotated[
        FactorOf | None,
        typer.Option(
            "--balance-factor-of",
            help="What --balance-factor is a share of: each-cylinder (default) or "
            "one-cylinder (one cylinder's reciprocating mass on each throw).",
        ),
    ] = None,
    counterweight_radius: Annotated[
        str | None,
        typer.Option("--counterweight-radius", help="e.g. 55mm (default: crank radius)."),
    ] = None,
    cancel_roll: Annotated[
        bool,
        typer.Option("--cancel-roll", help="Place a shaft pair to cancel its order's roll too."),
    ] = False,
    factor_study: Annotated[
        bool,
        typer.Option("--factor-study", help="Residual first-order force for factors 0-100 %."),
    ] = False,
    orders: Annotated[str, typer.Option("--orders", help="Orders of the residual report.")] = "1-8",
    speed: Speed = None,
    bearings: _Bearings = False,
    format: Annotated[Format, typer.Option("--format", "-f", help="Output format.")] = Format.table,
    output: OutputFile = None,
    force: ReplaceOutput = False,
    quiet: Quiet = False,
) -> None:
    """Propose counterweights and balance shafts, and show what remains."""
    from balance.core.analysis import compute
    from balance.io.orders import parse_orders

    cancel_orders = tuple(parse_orders(cancel, "--cancel").tolist()) if cancel is not None else None
    factor = _parse_fraction(balance_factor, "--balance-factor") if balance_factor else None
    if balance_factor_of is not None and factor is None:
        raise InputError(
            "--balance-factor-of: says what --balance-factor is a share of; give the factor "
            "too, e.g. --balance-factor 100% --balance-factor-of one-cylinder"
        )
    radius = (
        _parse_length(counterweight_radius, "--counterweight-radius")
        if counterweight_radius
        else None
    )
    engine, request = _prepare(
        layout,
        orders,
        speed,
        output=output,
        force=force,
        binary=format is Format.netcdf,
        cancel=cancel_orders,
        strategy=strategy.value if strategy is not None else None,
        balance_factor=factor,
        balance_factor_of=balance_factor_of.value if balance_factor_of is not None else None,
        counterweight_radius=radius,
        cancel_roll=cancel_roll,
        factor_study=factor_study,
        bearings=True if bearings else None,
        speed_model="constant",  # proposals are made at constant speed
    )
    if request.wants("bearings"):  # each strategy's bearing loads beside the proposal's
        request = request.with_sections(bearings={"strategies": True})
    result = compute(engine, request)
    warn(result.warnings, quiet, layout)
    _write(result, format, output, force, only=("proposal", "factor_study", "bearings"))


class PlotFormat(StrEnum):
    """Figure file formats."""

    png = "png"
    svg = "svg"
    pdf = "pdf"


@guarded
def plot_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
    kind: Annotated[
        list[str] | None,
        typer.Option(
            "--kind",
            "-k",
            help="crank_star, phasors, crank_angle, locus, spectrum, roll, balance, torque, "
            "forces, mounts, pin_load, main_loads, internal_moment, crank_speed, "
            "reduced_inertia, speed_model_orders, torsion_campbell, torsion_modes, "
            "torsion_response or crankshaft_forces, as in the file names "
            "(- may stand for _; repeat for several; default: all that apply).",
        ),
    ] = None,
    format: Annotated[PlotFormat, typer.Option("--format", "-f", help="File format.")] = (
        PlotFormat.png
    ),
    output_dir: Annotated[
        Path,
        typer.Option(
            "--output-dir",
            "-o",
            help="Directory for the figures; created, with its parents, if it does not exist.",
        ),
    ] = Path("."),
    orders: Annotated[str, typer.Option("--orders", help="Orders, e.g. 1-8.")] = "1-8",
    speed: Speed = None,
    force: Annotated[bool, typer.Option("--force", help="Replace existing files.")] = False,
    bearings: _Bearings = False,
    quiet: Quiet = False,
) -> None:
    """Draw the design-review figures of a layout into a directory."""
    from balance.core.analysis import compute
    from balance.views.plots import section_kinds

    _check_output_directory(output_dir)
    asked = {k.replace("-", "_") for k in kind or ()}
    # a figure kind of a section asked for by name turns its section on
    drawn = {name for k, (name, _) in section_kinds().items() if k in asked}
    wanted: dict[str, Any] = {name: True for name in drawn}
    if bearings:
        wanted["bearings"] = True
    result = compute(*_prepare(layout, orders, speed, figures=True, **wanted))
    warn(result.warnings, quiet, layout)
    from balance.views.plots import save_plots

    stem = Path(layout).stem if layout.endswith((".yaml", ".yml")) else layout
    kinds = [k.replace("-", "_") for k in kind] if kind else None
    written = save_plots(
        result, output_dir, kinds=kinds, fmt=format.value, prefix=f"{stem}-", force=force
    )
    for path in written:
        sys.stderr.write(f"balance: wrote {path}\n")


def _check_output_directory(directory: Path) -> None:
    """Refuse, before any work, a directory output that cannot be made or written: a file
    in its place or on its path, or a nearest existing ancestor that is not writable.  A
    missing directory is created (with its parents) when the first file is written."""
    if directory.exists() and not directory.is_dir():
        raise InputError(f"{directory}: is a file, not a directory; give a directory for -o")
    existing = directory
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise InputError(f"{directory}: {existing} is a file, so the directory cannot be made")
    if not os.access(existing, os.W_OK | os.X_OK):
        what = "directory" if existing == directory else "parent directory"
        raise InputError(f"{directory}: {what} {existing} is not writable")


@guarded
def report_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
    output: Annotated[Path, typer.Option("--output", "-o", help="The HTML file to write.")],
    orders: Annotated[str, typer.Option("--orders", help="Orders, e.g. 1-8.")] = "1-8",
    speed: Speed = None,
    force: Annotated[bool, typer.Option("--force", help="Replace an existing file.")] = False,
    bearings: _Bearings = False,
    quiet: Quiet = False,
) -> None:
    """Write a self-contained HTML design review (tables, figures, proposal, accuracy)."""
    from balance.core.analysis import compute

    result = compute(
        *_prepare(
            layout,
            orders,
            speed,
            output=output,
            force=force,
            figures=True,
            bearings=True if bearings else None,
        )
    )
    warn(result.warnings, quiet, layout)
    from balance.views.report import write_report

    write_report(result, output, force=force)
    sys.stderr.write(f"balance: wrote {output}\n")


class SweepFormat(StrEnum):
    """Output formats of the speed sweeps, ``balance mounts`` and ``balance torsion``."""

    table = "table"
    json = "json"
    csv = "csv"


SweepFormatOption = Annotated[SweepFormat, typer.Option("--format", "-f", help="Output format.")]


def _write_figure(fig: Any, path: Path, force: bool) -> None:
    """Write a figure whole to ``path`` (its suffix the format) and say so on stderr."""
    from balance.io.atomic import write_atomic
    from balance.views.plots import figure_bytes

    write_atomic(path, figure_bytes(fig, path.suffix.lower().lstrip(".")), force)
    sys.stderr.write(f"balance: wrote {path}\n")


@guarded
def mounts_command(
    layout: Annotated[
        str, typer.Argument(help="Layout file or built-in name (see 'balance layouts').")
    ],
    speed: Annotated[
        str,
        typer.Option(
            "--speed", help="Speeds: start:stop:count or a list, e.g. 800rpm:8000rpm:200."
        ),
    ] = "800rpm:8000rpm:200",
    orders: Annotated[
        str, typer.Option("--orders", help="Orders: a range or list, e.g. 1-8.")
    ] = "1-8",
    mounts: Annotated[
        Path | None,
        typer.Option("--mounts", help="A mounts file instead of the layout's mounts: section."),
    ] = None,
    with_proposal: Annotated[
        bool, typer.Option("--with-proposal", help="Load the mounts with the proposal added.")
    ] = False,
    format: SweepFormatOption = SweepFormat.table,
    plot: Annotated[
        Path | None,
        typer.Option("--plot", "-o", help="Also draw mount force against speed (png, svg, pdf)."),
    ] = None,
    force: ReplaceOutput = False,
    quiet: Quiet = False,
) -> None:
    """Mount forces per order against speed, the modes, and which order crosses which mode
    where (a mounts: section or --mounts FILE)."""
    from balance.core.analysis import compute

    if plot is not None and plot.suffix.lower().lstrip(".") not in ("png", "svg", "pdf"):
        raise InputError(f"-o {plot}: give a .png, .svg or .pdf file for the plot")
    engine, request = _prepare(
        layout,
        orders,
        None,
        output=plot,
        force=force,
        mounts_file=mounts,
        sweep_speeds=speed,
        mounts=True,
        with_proposal=with_proposal,
        bearings=False,
    )
    from balance.core.plausibility import check_engine

    top = float(request.options("mounts")["speeds"].max())
    warn(check_engine(engine.with_speed(top)), quiet, layout)  # at the top speed
    sweep = compute(engine, request).part("mounts").sweep
    if format is SweepFormat.json:
        import json

        from balance.views.mounts import sweep_json

        sys.stdout.write(json.dumps(sweep_json(sweep, engine.name), indent=2) + "\n")
    elif format is SweepFormat.csv:
        from balance.views.mounts import sweep_csv

        sys.stdout.write(sweep_csv(sweep))
    else:
        from rich.console import Group

        from balance.views.mounts import sweep_tables

        console().print(Group(*sweep_tables(sweep, engine.name)))
    if plot is not None:
        from balance.views.mounts import plot_mount_sweep

        _write_figure(plot_mount_sweep(sweep, layout=engine.name), plot, force)


@guarded
def torsion_command(
    layout: Annotated[
        str, typer.Argument(help="Layout file or built-in name (see 'balance layouts').")
    ],
    speed: Annotated[
        str | None,
        typer.Option(
            "--speed",
            help="Speeds: start:stop:count or a list, e.g. 800rpm:7200rpm:200 "
            "(default: 200 from 20 % to 120 % of the layout's speed).",
        ),
    ] = None,
    orders: Annotated[
        str | None,
        typer.Option(
            "--orders",
            help="Orders: a range or list, halves on a four-stroke, e.g. 0.5-12 or 4.5,6 "
            "(default 0.5-12, a two-stroke 1-12).",
        ),
    ] = None,
    format: SweepFormatOption = SweepFormat.table,
    plot: Annotated[
        Path | None,
        typer.Option("--plot", "-o", help="Also draw the Campbell diagram (png, svg, pdf)."),
    ] = None,
    force: ReplaceOutput = False,
    quiet: Quiet = False,
) -> None:
    """Torsional vibration of the crank train over a speed range: modes, vector sums,
    resonances, forced response, stresses and damper power (a torsion: section)."""
    from balance.core.analysis import compute
    from balance.io.fields import parse_half_orders
    from balance.io.layout_file import load_layout

    if plot is not None and plot.suffix.lower().lstrip(".") not in ("png", "svg", "pdf"):
        raise InputError(f"-o {plot}: give a .png, .svg or .pdf file for the plot")
    cycle = load_layout(layout).cycle if orders is not None else "four-stroke"
    section: dict[str, Any] = {"speeds": "sweep"}
    if orders is not None:
        section["orders"] = parse_half_orders(orders, cycle, "--orders")
    engine, request = _prepare(
        layout,
        "1-8",
        None,
        output=plot,
        force=force,
        sweep_speeds=speed,
        sweep_of="torsion",
        torsion=section,
        moments=False,
        roll=False,
    )
    result = compute(engine, request.only("torque", "torsion"))
    warn(result.warnings, quiet, layout)
    if format is SweepFormat.json:
        from balance.views.torsion import torsion_text

        sys.stdout.write(torsion_text(result))
    elif format is SweepFormat.csv:
        from balance.views.torsion import torsion_csv

        sys.stdout.write(torsion_csv(result))
    else:
        from rich.console import Group

        from balance.views.torsion import tables

        console().print(Group(*tables(result)))
    if plot is not None:
        from balance.views.plots import plot_kind

        _write_figure(plot_kind("torsion_campbell")(result), plot, force)


#: The commands of this module, by name (:mod:`balance.cli` puts them in order).
COMMANDS: dict[str, Callable[..., None]] = {
    "analyse": analyse_command,
    "propose": propose_command,
    "plot": plot_command,
    "report": report_command,
    "mounts": mounts_command,
    "torsion": torsion_command,
}
