"""The ``balance`` command line: parse, call the core, format.

Data goes to stdout (or ``-o PATH``), messages to stderr.  Exit codes: 0 success,
2 bad input, 1 an analysis that failed.  Errors are one line,
``file:line:col: field: what is wrong; what is valid``; ``--debug`` shows the traceback.

The commands live by job: :mod:`balance.cli.analysis` (one layout: ``analyse``,
``propose``, ``plot``, ``report``, ``mounts``), :mod:`balance.cli.studies` (``compare``,
``sweep``, ``search``, ``tolerance``) and :mod:`balance.cli.layouts` (``layouts``,
``layout expand``); :mod:`balance.cli.common` holds the error guard, the options several
commands share and the writing of outputs.  This module puts them together in the order
``balance --help`` lists them (:data:`app`, made when first asked for) and runs the command
line (:func:`main`), which imports only the module of the command it runs.
"""

# No ``from __future__ import annotations`` in the modules of the command line: typer reads
# the annotations of every command's parameters whenever it builds the command line, and as
# strings each one would be compiled and evaluated at every start (about 20 ms of a 0.3 s
# start, the most that balance's own code costs there).  Names imported for type checking
# only are quoted.

import functools
import os
import re
import signal
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import typer

from balance.cli.common import main_options

if TYPE_CHECKING:  # pragma: no cover
    app: typer.Typer

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
#: Each command, in the order ``balance --help`` lists them, and the module of
#: :mod:`balance.cli` that holds it (in its ``COMMANDS``); the group ``layout`` is
#: :mod:`balance.cli.layouts`'s.
_COMMANDS = {
    "analyse": "analysis",
    "propose": "analysis",
    "compare": "studies",
    "plot": "analysis",
    "report": "analysis",
    "mounts": "analysis",
    "torsion": "analysis",
    "sweep": "studies",
    "search": "studies",
    "tolerance": "studies",
    "layouts": "layouts",
}


def _commands_of(module: str) -> dict[str, Callable[..., None]]:
    """The commands of one module of the command line, by name (importing only it)."""
    if module == "analysis":
        from balance.cli.analysis import COMMANDS
    elif module == "studies":
        from balance.cli.studies import COMMANDS
    else:
        from balance.cli.layouts import COMMANDS
    return COMMANDS


def _with_command(application: typer.Typer, name: str) -> typer.Typer:
    application.command(name)(_commands_of(_COMMANDS[name])[name])
    return application


@functools.cache
def _application() -> typer.Typer:
    """The application: its options, every command in the order of :data:`_COMMANDS`, and
    the group ``layout``."""
    from balance.cli.layouts import layout_app

    full = typer.Typer(**_APP_SETTINGS)
    full.add_typer(layout_app, name="layout")
    full.callback()(main_options)
    for name in _COMMANDS:
        _with_command(full, name)
    return full


def __getattr__(name: str) -> Any:
    """``app``, the whole application, made when first asked for (PEP 562)."""
    if name == "app":
        return _application()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


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
        message = _plain_usage_error(message, sys.argv[1:])
        sys.stderr.write(f"balance: {message}; see '{where} --help'\n")
        sys.exit(2)
    except aborts:
        sys.stderr.write("balance: interrupted\n")
        sys.exit(130)
    sys.exit(code if isinstance(code, int) else 0)


# typer's words for a value its type or bounds refuse -> ours, given the option and the value
# (patterns, each ``re`` string compiled on the first usage error: a run without one does
# not compile them)
_USAGE_WORDS: tuple[tuple[str, str], ...] = (
    (
        r"Input should be greater than or equal to (\S+)",
        "{value} is below {0}; give {0} or more",
    ),
    (
        r"Input should be greater than (\S+)",
        "{value} is not above {0}; give more than {0}",
    ),
    (
        r"Input should be less than or equal to (\S+)",
        "{value} is above {0}; give at most {0}",
    ),
    (
        r"Input should be less than (\S+)",
        "{value} is not below {0}; give less than {0}",
    ),
    (r"Input should be a valid integer.*", "{value} is not a whole number"),
    (r"Input should be a valid number.*", "{value} is not a number"),
    (r"Value error, (.*)", "{0}"),
)
_INVALID = r"^Invalid value for '(-[^']+)'(?: / '(-[^']+)')?: (.*)$"


def _plain_usage_error(message: str, args: list[str]) -> str:
    """A usage error of an option's value in the command line's words.

    typer words a value its type or bounds refuse as the validation library does
    ("Invalid value for '--samples': Input should be greater than or equal to 1"); this
    gives the option, the value as typed and the bound ("--samples: 0 is below 1; give 1
    or more").  Any other message is returned as it is.

    Parameters
    ----------
    message : str
        The usage error, on one line.
    args : list of str
        The command line's arguments (where the value is found).

    Returns
    -------
    str
    """
    match = re.match(_INVALID, message)
    if match is None:
        return message
    names = [n for n in match.group(1, 2) if n]
    value = _typed_value(args, names)
    detail = match.group(3)
    for pattern, words in _USAGE_WORDS:
        found = re.fullmatch(pattern, detail)
        if found:
            detail = words.format(
                *found.groups(), value=value if value is not None else "the value"
            )
            break
    return f"{names[0]}: {detail}"


def _typed_value(args: list[str], names: list[str]) -> str | None:
    """The value typed after the last of the option's names (``--samples 0``,
    ``--samples=0``), or None."""
    value = None
    for i, arg in enumerate(args):
        for name in names:
            if arg == name and i + 1 < len(args):
                value = args[i + 1]
            elif arg.startswith(name + "=") and name.startswith("--"):
                value = arg[len(name) + 1 :]
    return value


def _app_for(args: list[str]) -> typer.Typer:
    """The application to run for these arguments.

    Typer builds the click objects of every command it knows, with their type adapters,
    before it parses anything, which costs a start-up a few tens of milliseconds.  When
    the arguments name one of the plain commands, an application with the same settings,
    the same global options and that one command is run instead (and only the module of
    that command is imported); the command line, its help and its errors are the same.
    Anything else (no command, ``--help``, a group such as ``layout``, a misspelt name) runs
    the full application.
    """
    words = [a for a in args if not a.startswith("-")]
    if (
        not words
        or words[0] not in _COMMANDS
        or any(a in ("--help", "-h") for a in args[: args.index(words[0])])
    ):
        return _application()
    single = typer.Typer(**_APP_SETTINGS)
    single.callback()(main_options)
    return _with_command(single, words[0])


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
