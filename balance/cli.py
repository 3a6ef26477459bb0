"""The ``balance`` command line: parse, call the core, format.

Data goes to stdout (or ``-o PATH``), messages to stderr.  Exit codes: 0 success,
2 bad input, 1 an analysis that failed.  Errors are one line,
``file:line:col: field: what is wrong; what is valid``; ``--debug`` shows the traceback.
"""

# No ``from __future__ import annotations`` in this module: typer reads the annotations of
# every command's parameters whenever it builds the command line, and as strings each one
# would be compiled and evaluated at every start (about 20 ms of a 0.3 s start, the most
# that balance's own code costs there).  Names imported for type checking only are quoted.

import functools
import io
import os
import signal
import sys
from collections.abc import Callable
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

import typer

from balance.core.errors import BalanceError, InputError

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.engine import Engine
    from balance.core.result import Request, Result

__all__ = ["app", "main"]

# pydantic looks for plugins through package metadata on first use, which costs a command
# line start about 10 ms; the command line has none (set the variable to override)
os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")

_APP_SETTINGS: dict[str, Any] = {
    "name": "balance",
    "help": "Engine balancing analyser: free forces, moments and roll of any crank arrangement.",
    "add_completion": False,
    "no_args_is_help": True,
    "pretty_exceptions_enable": False,
    "rich_markup_mode": None,
}
app = typer.Typer(**_APP_SETTINGS)
layout_app = typer.Typer(help="Work with layout files.", no_args_is_help=True)
app.add_typer(layout_app, name="layout")

_STATE = {"debug": False}

F = TypeVar("F", bound=Callable[..., Any])


def _fail(message: str, code: int) -> None:
    sys.stderr.write(f"balance: {message}\n" if not message.startswith("balance") else message)
    raise typer.Exit(code)


def guarded(func: F) -> F:
    """Turn every error of a command into one line on stderr and an exit code."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except (typer.Exit, typer.Abort, SystemExit):
            raise
        except BalanceError as exc:
            if _STATE["debug"]:
                raise
            *first, last = exc.lines()  # every problem of a file, one line each
            sys.stderr.write("".join(f"balance: {line}\n" for line in first))
            _fail(last, exc.exit_code)
        except KeyboardInterrupt:
            _fail("interrupted", 130)
        except BrokenPipeError:
            raise typer.Exit(0) from None
        except Exception as exc:
            if _STATE["debug"]:
                raise
            text = " ".join(str(exc).split()) or type(exc).__name__
            _fail(f"internal error: {type(exc).__name__}: {text} (run with --debug for details)", 1)
        return None

    return wrapper  # type: ignore[return-value]


@app.callback()
def _main_options(
    debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks of errors.")] = False,
) -> None:
    _STATE["debug"] = debug


class Format(StrEnum):
    """Output formats of ``balance analyse``."""

    table = "table"
    json = "json"
    csv = "csv"
    netcdf = "netcdf"


class Model(StrEnum):
    """Piston acceleration models."""

    exact = "exact"
    series = "series"
    textbook = "textbook"
    time = "time"


# options that several commands declare alike, written once
_OutputFile = Annotated[Path | None, typer.Option("--output", "-o", help="Write to this file.")]
_ReplaceOutput = Annotated[bool, typer.Option("--force", help="Replace an existing output file.")]
_Speed = Annotated[str | None, typer.Option("--speed", help="Crank speed, e.g. 7000rpm.")]
_Quiet = Annotated[
    bool,
    typer.Option(
        "--quiet", "-q", help="No plausibility warnings on stderr (JSON and tables keep them)."
    ),
]
_Bearings = Annotated[
    bool,
    typer.Option(
        "--bearings",
        help="Crank-pin and main-bearing loads and internal moments "
        "(default mains unless the layout has a bearings: section).",
    ),
]


def _parse_speed(text: str | None) -> float | None:
    """The ``--speed`` option in rad/s (None when it is not given)."""
    from balance.io.fields import parse_speed

    return parse_speed(text)


def _warn(warnings: Any, quiet: bool, source: str) -> None:
    """The plausibility warnings on stderr, one line each (none with ``--quiet``)."""
    if not quiet:
        for w in warnings:
            sys.stderr.write(f"balance: warning: {source}: {w.field}: {w.message}\n")


def _console() -> Any:
    """A rich console on stdout, as wide as the terminal (or ``COLUMNS`` when it is set);
    240 columns when stdout is neither a terminal nor given a width.  Tables lay
    themselves out for that width and never cut a number (:mod:`balance.views.fitted`)."""
    from rich.console import Console

    if sys.stdout.isatty() or os.environ.get("COLUMNS", "").strip().isdigit():
        return Console()
    return Console(width=240)


def _check_output(output: Path | None, force: bool, binary: bool) -> None:
    """Refuse an output that cannot be written before any work is done."""
    if output is not None:
        from balance.io.atomic import check_target

        check_target(output, force)
    elif binary:
        raise InputError("--format netcdf writes a binary file; give -o PATH")


def _prepare(
    layout: str,
    orders: str,
    speed: str | None,
    *,
    output: Path | None = None,
    force: bool = False,
    binary: bool = False,
    mounts_file: Path | None = None,
    **settings: Any,
) -> "tuple[Engine, Request]":
    """The preamble of a command that analyses one layout, written once.

    Reads ``--orders`` and ``--speed`` (each checked here, once), refuses an output that
    cannot be written (``output``/``force``; ``binary``: a format that needs ``-o``) before
    any work is done, loads the layout (with the mounts of ``--mounts FILE`` in place of its
    ``mounts:`` section) and builds the :class:`~balance.core.result.Request` with
    ``settings`` through the one front door (:func:`balance.io.request.build_request`, as
    :func:`balance.analyse` does).  A command with another kind of output (a directory of
    figures) checks it before calling this.
    """
    from balance.io.fields import parse_orders
    from balance.io.layout_file import load_layout
    from balance.io.request import build_request

    order_list = parse_orders(orders)
    speed_value = _parse_speed(speed)
    _check_output(output, force, binary)
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
    return engine, build_request(engine, order_list, speed=speed_value, **settings)


def _write_netcdf(ds: Any, output: Path, force: bool) -> None:
    from balance.io.atomic import write_atomic

    write_atomic(output, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4"), force=force)
    sys.stderr.write(f"balance: wrote {output}\n")


def _emit_rich(renderable: Any, output: Path | None, force: bool, width: int) -> None:
    """Print a rich renderable, or write it as plain text ``width`` columns wide."""
    if output is None:
        _console().print(renderable)
        return
    from rich.console import Console

    console = Console(record=True, width=width, file=io.StringIO())
    console.print(renderable)
    _emit_text(console.export_text(), output, force)


def _emit_text(text: str, output: Path | None, force: bool) -> None:
    if output is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    from balance.io.atomic import write_atomic

    write_atomic(output, text.encode("utf-8"), force=force)
    sys.stderr.write(f"balance: wrote {output}\n")


@app.command("analyse")
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
    output: _OutputFile = None,
    force: _ReplaceOutput = False,
    quiet: _Quiet = False,
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
    )
    result = compute(engine, request)
    _warn(result.warnings, quiet, layout)
    _write(result, format, output, force)


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

        _emit_text(to_json(result), output, force)
    elif format is Format.csv:
        from balance.views.csv import to_csv

        _emit_text(to_csv(result), output, force)
    elif format is Format.netcdf:
        from balance.views.dataset import build_dataset

        assert output is not None
        _write_netcdf(build_dataset(result), output, force)
    else:
        from balance.views.table import render

        _emit_rich(render(result, only), output, force, width=140)


class Strategy(StrEnum):
    """Counterweight strategies."""

    two_plane = "two-plane"
    per_throw = "per-throw"


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


@app.command("propose")
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
            "--balance-factor", help="Share of reciprocating mass on the crank, e.g. 50%."
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
    speed: _Speed = None,
    bearings: _Bearings = False,
    format: Annotated[Format, typer.Option("--format", "-f", help="Output format.")] = Format.table,
    output: _OutputFile = None,
    force: _ReplaceOutput = False,
    quiet: _Quiet = False,
) -> None:
    """Propose counterweights and balance shafts, and show what remains."""
    from balance.core.analysis import compute
    from balance.io.fields import parse_orders

    cancel_orders = tuple(parse_orders(cancel).tolist()) if cancel is not None else None
    factor = _parse_fraction(balance_factor, "--balance-factor") if balance_factor else None
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
        counterweight_radius=radius,
        cancel_roll=cancel_roll,
        factor_study=factor_study,
        bearings=True if bearings else None,
    )
    if request.wants("bearings"):  # each strategy's bearing loads beside the proposal's
        request = request.with_sections(bearings={"strategies": True})
    result = compute(engine, request)
    _warn(result.warnings, quiet, layout)
    _write(result, format, output, force, only=("proposal", "factor_study", "bearings"))


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


@app.command("compare")
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
    model: Annotated[
        Model, typer.Option("--model", help="Piston acceleration model.")
    ] = Model.exact,
    format: Annotated[
        CompareFormat, typer.Option("--format", "-f", help="Output format.")
    ] = CompareFormat.table,
    output: _OutputFile = None,
    force: _ReplaceOutput = False,
    quiet: _Quiet = False,
) -> None:
    """Compare layouts side by side: free forces, moments, roll and balancing needs."""
    import json

    from balance.io.fields import parse_option_quantity, parse_orders
    from balance.io.layout_file import load_layout
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
    order_list = parse_orders(orders)
    speed_value = _parse_speed(speed)
    volume = None
    if displacement is not None:
        volume = parse_option_quantity(displacement, "volume", "--displacement")
        if volume <= 0:
            raise InputError("--displacement: must be more than zero")
    _check_output(output, force, binary=format is CompareFormat.netcdf)
    engines = [load_layout(name) for name in names]
    labels = [Path(n).stem if n.endswith((".yaml", ".yml")) else n for n in names]
    compared = compare_results(
        engines, labels, order_list, speed=speed_value, displacement=volume, model=model.value
    )
    for c in compared:
        _warn(c.result.warnings, quiet, c.label)
    ds = comparison_dataset(
        [c.result for c in compared],
        [c.label for c in compared],
        [c.scale_factor for c in compared],
        speed=speed_value,
        displacement=volume,
    )
    if format is CompareFormat.netcdf:
        assert output is not None
        _write_netcdf(ds, output, force)
        return
    if format is CompareFormat.json:
        _emit_text(json.dumps(compare_json(ds), indent=2, allow_nan=False) + "\n", output, force)
        return
    headers, rows = compare_table(ds, normalised=not absolute)
    if format is CompareFormat.markdown:
        _emit_text(markdown_table(headers, rows), output, force)
    elif format is CompareFormat.csv:
        _emit_text(compare_csv(headers, rows), output, force)
    else:
        from rich.console import Group

        _emit_rich(Group(*render_comparison(ds, absolute=absolute)), output, force, width=240)


class PlotFormat(StrEnum):
    """Figure file formats."""

    png = "png"
    svg = "svg"
    pdf = "pdf"


@app.command("plot")
@guarded
def plot_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
    kind: Annotated[
        list[str] | None,
        typer.Option(
            "--kind",
            "-k",
            help="crank_star, phasors, crank_angle, locus, spectrum, roll, balance, torque, "
            "forces, mounts, pin_load, main_loads or internal_moment, as in the file names "
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
    speed: _Speed = None,
    force: Annotated[bool, typer.Option("--force", help="Replace existing files.")] = False,
    bearings: _Bearings = False,
    quiet: _Quiet = False,
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
    _warn(result.warnings, quiet, layout)
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


@app.command("report")
@guarded
def report_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
    output: Annotated[Path, typer.Option("--output", "-o", help="The HTML file to write.")],
    orders: Annotated[str, typer.Option("--orders", help="Orders, e.g. 1-8.")] = "1-8",
    speed: _Speed = None,
    force: Annotated[bool, typer.Option("--force", help="Replace an existing file.")] = False,
    bearings: _Bearings = False,
    quiet: _Quiet = False,
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
    _warn(result.warnings, quiet, layout)
    from balance.views.report import write_report

    write_report(result, output, force=force)
    sys.stderr.write(f"balance: wrote {output}\n")


class MountsFormat(StrEnum):
    """Output formats of ``balance mounts``."""

    table = "table"
    json = "json"
    csv = "csv"


@app.command("mounts")
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
    format: Annotated[
        MountsFormat, typer.Option("--format", "-f", help="Output format.")
    ] = MountsFormat.table,
    plot: Annotated[
        Path | None,
        typer.Option("--plot", "-o", help="Also draw mount force against speed (png, svg, pdf)."),
    ] = None,
    force: Annotated[
        bool, typer.Option("--force", help="Replace an existing output file.")
    ] = False,
    quiet: _Quiet = False,
) -> None:
    """Mount forces per order against speed, the modes, and which order crosses which mode
    where (a mounts: section or --mounts FILE)."""
    from balance.core.analysis import compute
    from balance.io.fields import parse_field, parse_values

    if plot is not None and plot.suffix.lower().lstrip(".") not in ("png", "svg", "pdf"):
        raise InputError(f"-o {plot}: give a .png, .svg or .pdf file for the plot")
    engine, request = _prepare(
        layout,
        orders,
        None,
        output=plot,
        force=force,
        mounts_file=mounts,
        mounts=True,
        with_proposal=with_proposal,
        bearings=False,
    )
    speeds = parse_values(speed, parse_field("speed", engine), "--speed")
    if not (speeds.min() > 0):
        raise InputError(f"--speed: {speed!r}: every speed must be above zero")
    from balance.core.plausibility import check_engine

    _warn(check_engine(engine.with_speed(float(speeds.max()))), quiet, layout)  # the top speed
    options = {**request.options("mounts"), "speeds": speeds}
    sweep = compute(engine, request.with_sections(mounts=options)).part("mounts").sweep
    if format is MountsFormat.json:
        import json

        from balance.views.mounts import sweep_json

        sys.stdout.write(json.dumps(sweep_json(sweep, engine.name), indent=2) + "\n")
    elif format is MountsFormat.csv:
        from balance.views.mounts import sweep_csv

        sys.stdout.write(sweep_csv(sweep))
    else:
        from rich.console import Group

        from balance.views.mounts import sweep_tables

        _console().print(Group(*sweep_tables(sweep, engine.name)))
    if plot is not None:
        from balance.io.atomic import write_atomic
        from balance.views.mounts import plot_mount_sweep
        from balance.views.plots import figure_bytes

        fig = plot_mount_sweep(sweep, layout=engine.name)
        write_atomic(plot, figure_bytes(fig, plot.suffix.lower().lstrip(".")), force)
        sys.stderr.write(f"balance: wrote {plot}\n")


@app.command("sweep")
@guarded
def sweep_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
    vary: Annotated[
        list[str],
        typer.Option(
            "--vary",
            help="FIELD=start:stop:count or FIELD=a,b,c, e.g. conrod_length=130mm:160mm:31 "
            "or cylinders[3].reciprocating=0.4kg:0.7kg:13; repeat for more dimensions.",
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
    quiet: _Quiet = False,
) -> None:
    """Analyse a grid of layout variants and write one Dataset (netCDF or Zarr), chunk by chunk."""
    import time

    from balance.io.fields import check_varies, parse_vary
    from balance.io.layout_file import load_layout
    from balance.studies.sweep import check_output, sweep_to_file

    started = time.perf_counter()
    check_output(output, force)
    if scheduler is not None and workers is not None:
        raise InputError("give --scheduler or --workers, not both")
    base = load_layout(layout)
    grid = check_varies([parse_vary(text, base) for text in vary])
    if not quiet:
        from balance.studies.checks import sweep_warnings

        _warn(sweep_warnings(base, grid), quiet, layout)
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


@app.command("search")
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
    from balance.io.fields import parse_orders
    from balance.io.units import UnitProblem, parse_quantity
    from balance.studies.search import search

    try:
        step_deg = parse_quantity(step, "angle")
        bank_list = [parse_quantity(b, "angle") for b in banks.split(",")]
    except UnitProblem as exc:
        raise InputError(f"--step/--banks: {exc}; {exc.valid}") from None
    result = search(
        cylinders,
        bank_list,
        step=step_deg,
        even_firing=even_firing,
        split=not no_split,
        objective=objective,
        orders=[int(k) for k in parse_orders(orders)],
        rod_ratio=rod_ratio,
        top=top,
    )
    from rich.console import Group

    from balance.views.studies import search_tables

    _console().print(Group(*search_tables(result)))


@app.command("tolerance")
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
    quiet: _Quiet = False,
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
    items = [parse_scatter(text, engine) for text in scatter]
    if not quiet:
        from balance.studies.checks import tolerance_warnings

        _warn(tolerance_warnings(engine, items), quiet, layout)
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

    _console().print(Group(*tolerance_tables(result, PERCENTILES)))
    if plot is not None:
        from balance.io.atomic import write_atomic
        from balance.views.studies import figure_metadata

        fig = tolerance_histogram(result)
        fmt = plot.suffix.lower().lstrip(".")
        metadata = figure_metadata(result, fmt)
        write_atomic(plot, lambda tmp: fig.savefig(tmp, format=fmt, metadata=metadata), force=force)
        sys.stderr.write(f"balance: wrote {plot}\n")


@app.command("layouts")
@guarded
def layouts_command() -> None:
    """List the built-in layouts."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    from balance.io.layout_file import builtin_layout_names, load_layout

    table = Table()
    table.add_column("name", no_wrap=True)
    table.add_column("cylinders", justify="right", no_wrap=True)
    table.add_column("description", overflow="fold")  # words wrap; names and counts never
    for name in builtin_layout_names():
        layout = load_layout(name)
        table.add_row(Text(name), str(layout.n_cylinders), Text(layout.description or layout.name))
    title = Text("Built-in layouts (use the name in place of a file)", style="table.title")
    _console().print(Group(title, table))


@layout_app.command("expand")
@guarded
def expand_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
) -> None:
    """Print a layout in the explicit form, one entry per cylinder."""
    from balance.io.layout_file import expand_layout

    sys.stdout.write(expand_layout(layout))


def _terminate(signum: int, frame: Any) -> None:
    """SIGTERM, and SIGINT during a write: remove the run's temporary files and end at once
    (:func:`balance.io.atomic.exit_now`), or, while a Zarr store is written, at its next
    checkpoint (a second signal: at once).  An exception raised here would unwind through
    the interrupted library code, which can hang on a lock it held (xarray's netCDF writer)."""
    atomic = sys.modules.get("balance.io.atomic")
    writing = atomic is not None and atomic.writing()
    if signum == signal.SIGINT:
        if not writing:
            raise KeyboardInterrupt
        os.write(2, b"balance: interrupted\n")
    if atomic is not None:
        if atomic.stop_at_checkpoint(128 + signum):  # a Zarr store: stop between chunks
            return
        atomic.exit_now(128 + signum)
    os._exit(128 + signum)


def main() -> None:
    """Entry point of the ``balance`` command.

    SIGTERM, or an interrupt while a file is being written, ends the run at once: the file
    being written is removed and the previous output stays in place.
    """
    usage_errors, aborts = _click_exceptions()
    signal.signal(signal.SIGTERM, _terminate)
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _terminate)
    try:
        code = _app_for(sys.argv[1:])(standalone_mode=False)
    except usage_errors as exc:
        ctx = getattr(exc, "ctx", None)
        where = ctx.command_path if ctx is not None else "balance"
        if type(exc).__name__ == "NoArgsIsHelpError" and ctx is not None:
            sys.stderr.write(ctx.get_help() + "\n")
            sys.exit(2)
        message = " ".join(str(getattr(exc, "format_message", exc.__str__)()).split()).rstrip(".")
        sys.stderr.write(f"balance: {message}; see '{where} --help'\n")
        sys.exit(2)
    except aborts:
        sys.stderr.write("balance: interrupted\n")
        sys.exit(130)
    sys.exit(code if isinstance(code, int) else 0)


def _app_for(args: list[str]) -> typer.Typer:
    """The application to run for these arguments.

    Typer builds the click objects of every command it knows, with their type adapters,
    before it parses anything, which costs a start-up a few tens of milliseconds.  When
    the arguments name one of the plain commands, an application with the same settings,
    the same global options and that one command is run instead; the command line, its
    help and its errors are the same.  Anything else (no command, ``--help``, a group
    such as ``layout``, a misspelt name) runs the full application.
    """
    words = [a for a in args if not a.startswith("-")]
    if not words or any(a in ("--help", "-h") for a in args[: args.index(words[0])]):
        return app
    chosen = [c for c in app.registered_commands if c.name == words[0]]
    if not chosen:
        return app
    single = typer.Typer(**_APP_SETTINGS)
    single.registered_callback = app.registered_callback
    single.registered_commands = chosen
    return single


def _click_exceptions() -> tuple[tuple[type[BaseException], ...], tuple[type[BaseException], ...]]:
    """Usage-error and abort classes of whichever click typer runs on (its own copy in
    recent typer, the click package in older ones; the click package is not imported when
    typer has its own)."""
    import importlib

    for name in ("typer._click.exceptions", "click.exceptions"):
        try:
            module = importlib.import_module(name)
        except ImportError:
            continue
        aborts: list[type[BaseException]] = [typer.Abort]
        if hasattr(module, "Abort"):
            aborts.append(module.Abort)
        return (module.UsageError,), tuple(aborts)
    return (), (typer.Abort,)  # pragma: no cover - typer always brings one of them


if __name__ == "__main__":  # pragma: no cover
    main()
