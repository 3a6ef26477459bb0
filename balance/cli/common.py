"""What every command of the command line shares: the error guard, the options several
commands declare alike, and the writing of an output (stdout, or ``-o PATH`` written
atomically; messages to stderr).

Errors are one line, ``file:line:col: field: what is wrong; what is valid`` (docs/cli.md);
``--debug`` (:func:`main_options`) shows the traceback instead.
"""

# No ``from __future__ import annotations``: typer reads the annotations of every command's
# parameters when it builds the command line (see balance/cli/__init__.py).

import contextlib
import functools
import io
import os
import sys
from collections.abc import Callable, Iterator
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any, TypeVar

import typer

from balance.core.errors import BalanceError, InputError, OutputExists

__all__ = [
    "Model",
    "OutputFile",
    "Quiet",
    "ReplaceOutput",
    "Speed",
    "check_output",
    "console",
    "emit_rich",
    "emit_text",
    "guarded",
    "main_options",
    "options_named",
    "package_version",
    "parse_speed",
    "warn",
    "write_netcdf",
]

_STATE = {"debug": False}

F = TypeVar("F", bound=Callable[..., Any])


def _fail(message: str, code: int) -> None:
    sys.stderr.write(f"balance: {message}\n" if not message.startswith("balance") else message)
    raise typer.Exit(code)


def guarded(func: F) -> F:
    """Turn every error of a command into one line on stderr and an exit code.

    Parameters
    ----------
    func : callable
        A command.

    Returns
    -------
    callable
        The command, which exits 2 on bad input, 1 on an analysis that failed, 130 on an
        interrupt and 0 on a closed pipe, each with one line on stderr (docs/cli.md).
    """

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except (typer.Exit, typer.Abort, SystemExit):
            raise
        except OutputExists as exc:  # the library names the setting, the command line --force
            if _STATE["debug"]:
                raise
            _fail(f"{exc.target}: {exc.what}; use --force to replace it", exc.exit_code)
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


def package_version() -> str:
    """The version of balance as installed (the package's metadata), or the source tree's
    (``balance/_version.py``) when it runs without being installed.

    Returns
    -------
    str
        For example ``"0.1.0"``.
    """
    from importlib import metadata

    try:
        return metadata.version("balance")
    except metadata.PackageNotFoundError:
        from balance._version import __version__

        return __version__


def _print_version(value: bool) -> None:
    if value:
        sys.stdout.write(f"balance {package_version()}\n")
        raise typer.Exit(0)


def main_options(
    debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks of errors.")] = False,
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            help="Print the version of balance and exit.",
            callback=_print_version,
            is_eager=True,
        ),
    ] = False,
) -> None:
    """The options of ``balance`` itself, before the command.

    Parameters
    ----------
    debug : bool
        Let an error's traceback through instead of one line.
    version : bool
        Print the installed version (:func:`package_version`) and exit (done by its
        callback, before any command).
    """
    _STATE["debug"] = debug


class Model(StrEnum):
    """Piston acceleration models."""

    exact = "exact"
    series = "series"
    textbook = "textbook"
    time = "time"


# options that several commands declare alike, written once
OutputFile = Annotated[Path | None, typer.Option("--output", "-o", help="Write to this file.")]
ReplaceOutput = Annotated[bool, typer.Option("--force", help="Replace an existing output file.")]
Speed = Annotated[str | None, typer.Option("--speed", help="Crank speed, e.g. 7000rpm.")]
Quiet = Annotated[
    bool,
    typer.Option(
        "--quiet", "-q", help="No plausibility warnings on stderr (JSON and tables keep them)."
    ),
]


def parse_speed(text: str | None) -> float | None:
    """The ``--speed`` option.

    Parameters
    ----------
    text : str or None
        The option as typed, e.g. ``7000rpm``.

    Returns
    -------
    float or None
        The speed [rad/s]; None when the option is not given.
    """
    if text is None:
        return None
    from balance.io import fields

    return fields.parse_speed(text, "--speed")


@contextlib.contextmanager
def options_named(**options: str) -> Iterator[None]:
    """Name the command line's options in the problems of the library it calls.

    The library names a problem by its parameter (``objective: 'best'; valid: ...``); in
    this block such a problem is raised again with the option instead (``--objective:
    'best'; valid: ...``).

    Parameters
    ----------
    **options : str
        The option of each parameter, e.g. ``rod_ratio="--rod-ratio"``.

    Yields
    ------
    None

    Raises
    ------
    InputError
        A problem of the block, its leading parameter name replaced by the option.
    """
    try:
        yield
    except InputError as exc:
        text = str(exc)
        for name, option in options.items():
            if text.startswith(f"{name}: "):
                raise InputError(option + text[len(name) :]) from None
        raise


def warn(warnings: Any, quiet: bool, source: str) -> None:
    """The plausibility warnings on stderr, one line each (none with ``--quiet``).

    Parameters
    ----------
    warnings : iterable of Warning
        Each with its ``field`` and ``message`` (:mod:`balance.core.plausibility`).
    quiet : bool
        Write nothing.
    source : str
        The layout as given, at the start of each line.
    """
    if not quiet:
        for w in warnings:
            sys.stderr.write(f"balance: warning: {source}: {w.field}: {w.message}\n")


def console() -> Any:
    """A rich console on stdout, as wide as the terminal (or ``COLUMNS`` when it is set).

    Returns
    -------
    rich.console.Console
        240 columns when stdout is neither a terminal nor given a width.  Tables lay
        themselves out for that width and never cut a number (:mod:`balance.views.fitted`).
    """
    from rich.console import Console

    if sys.stdout.isatty() or os.environ.get("COLUMNS", "").strip().isdigit():
        return Console()
    return Console(width=240)


def check_output(output: Path | None, force: bool, binary: bool) -> None:
    """Refuse an output that cannot be written before any work is done.

    Parameters
    ----------
    output : Path or None
        The ``-o`` file; None for stdout.
    force : bool
        ``--force``: an existing file may be replaced.
    binary : bool
        The format is binary (netCDF), which stdout does not take.

    Raises
    ------
    InputError
        If the file exists without ``--force``, cannot be written, or is missing for a
        binary format.
    """
    if output is not None:
        from balance.io.atomic import check_target

        check_target(output, force)
    elif binary:
        raise InputError("--format netcdf writes a binary file; give -o PATH")


def write_netcdf(ds: Any, output: Path, force: bool) -> None:
    """Write a Dataset to a netCDF file, atomically, and say so on stderr.

    Parameters
    ----------
    ds : xarray.Dataset
        What to write.
    output : Path
        The file.
    force : bool
        Replace an existing file.
    """
    from balance.io.atomic import write_atomic

    write_atomic(output, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4"), force=force)
    sys.stderr.write(f"balance: wrote {output}\n")


def emit_rich(renderable: Any, output: Path | None, force: bool, width: int) -> None:
    """Print a rich renderable, or write it as plain text.

    Parameters
    ----------
    renderable : rich renderable
        A table or a group of them.
    output : Path or None
        The file; None for the console on stdout (:func:`console`).
    force : bool
        Replace an existing file.
    width : int
        Columns of the text written to a file.
    """
    if output is None:
        console().print(renderable)
        return
    from rich.console import Console

    recorder = Console(record=True, width=width, file=io.StringIO())
    recorder.print(renderable)
    emit_text(recorder.export_text(), output, force)


def emit_text(text: str, output: Path | None, force: bool) -> None:
    """Write text to stdout, or to a file atomically (and say so on stderr).

    Parameters
    ----------
    text : str
        What to write.
    output : Path or None
        The file; None for stdout.
    force : bool
        Replace an existing file.
    """
    if output is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    from balance.io.atomic import write_atomic

    write_atomic(output, text.encode("utf-8"), force=force)
    sys.stderr.write(f"balance: wrote {output}\n")
