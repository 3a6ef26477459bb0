"""The ``balance`` command line: parse, call the core, format.

Data goes to stdout (or ``-o PATH``), messages to stderr.  Exit codes: 0 success,
2 bad input, 1 an analysis that failed.  Errors are one line,
``file:line:col: field: what is wrong; what is valid``; ``--debug`` shows the traceback.
"""

from __future__ import annotations

import functools
import io
import sys
from collections.abc import Callable
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any, TypeVar

import typer

from .errors import BalanceError, InputError

__all__ = ["app", "main"]

app = typer.Typer(
    name="balance",
    help="Engine balancing analyser: free forces, moments and roll of any crank arrangement.",
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)
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
            _fail(exc.one_line(), exc.exit_code)
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


def _parse_speed(text: str) -> float:
    from .units import UnitProblem, parse_quantity

    try:
        return parse_quantity(text, "speed")
    except UnitProblem as exc:
        raise InputError(f"--speed: {exc}; {exc.valid}") from None


def _emit_text(text: str, output: Path | None, force: bool) -> None:
    if output is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    from .output import write_atomic

    def write(tmp: Path) -> None:
        tmp.write_text(text, encoding="utf-8")

    write_atomic(output, write, force=force)
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
        Model, typer.Option("--model", help="Piston acceleration model.")
    ] = Model.exact,
    terms: Annotated[
        int, typer.Option("--terms", min=1, max=60, help="Series terms (--model series).")
    ] = 3,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write to this file.")
    ] = None,
    force: Annotated[
        bool, typer.Option("--force", help="Replace an existing output file.")
    ] = False,
) -> None:
    """Analyse a layout: free forces, moments and roll per order."""
    from .analysis import analyse, parse_orders
    from .layout import load_layout

    order_list = parse_orders(orders)
    speed_value = _parse_speed(speed) if speed is not None else None
    if output is not None:
        from .output import check_target

        check_target(output, force)
    elif format is Format.netcdf:
        raise InputError("--format netcdf writes a binary file; give -o PATH")
    ds = analyse(load_layout(layout), order_list, speed=speed_value, model=model.value, terms=terms)
    if format is Format.json:
        from .views.json import to_json

        _emit_text(to_json(ds), output, force)
    elif format is Format.csv:
        from .views.csv import to_csv

        _emit_text(to_csv(ds), output, force)
    elif format is Format.netcdf:
        from .output import write_atomic

        assert output is not None
        write_atomic(output, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4"), force=force)
        sys.stderr.write(f"balance: wrote {output}\n")
    else:
        from rich.console import Console

        from .views.table import render

        if output is not None:
            console = Console(record=True, width=140, file=io.StringIO())
            console.print(render(ds))
            _emit_text(console.export_text(), output, force)
        else:
            Console().print(render(ds))


@app.command("layouts")
@guarded
def layouts_command() -> None:
    """List the built-in layouts."""
    from rich.console import Console
    from rich.table import Table

    from .layout import builtin_layout_names, load_layout

    table = Table(title="Built-in layouts (use the name in place of a file)", title_justify="left")
    table.add_column("name")
    table.add_column("cylinders", justify="right")
    table.add_column("description")
    for name in builtin_layout_names():
        layout = load_layout(name)
        table.add_row(name, str(layout.n_cylinders), layout.description or layout.name)
    Console().print(table)


@layout_app.command("expand")
@guarded
def expand_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
) -> None:
    """Print a layout in the explicit form, one entry per cylinder."""
    from .layout import expand_layout

    sys.stdout.write(expand_layout(layout))


def main() -> None:
    """Entry point of the ``balance`` command."""
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
