"""The commands about layout files: ``layouts`` (the built-in ones) and ``layout expand``."""

# No ``from __future__ import annotations``: typer reads the annotations of every command's
# parameters when it builds the command line (see balance/cli/__init__.py).

import sys
from collections.abc import Callable
from typing import Annotated

import typer

from balance.cli.common import console, guarded

__all__ = ["COMMANDS", "layout_app"]

#: The group ``balance layout``.
layout_app = typer.Typer(help="Work with layout files.", no_args_is_help=True)


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
    console().print(Group(title, table))


@layout_app.command("expand")
@guarded
def expand_command(
    layout: Annotated[str, typer.Argument(help="Layout file or built-in name.")],
) -> None:
    """Print a layout in the explicit form, one entry per cylinder."""
    from balance.io.layout_file import expand_layout

    sys.stdout.write(expand_layout(layout))


#: The commands of this module, by name (:mod:`balance.cli` puts them in order).
COMMANDS: dict[str, Callable[..., None]] = {"layouts": layouts_command}
