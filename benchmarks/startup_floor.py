"""The start-up floor of the design's stack, for comparison with ``balance``'s own start.

A command line with nothing of ``balance`` in it: numpy imported, typer with a command of
the same eleven options as ``balance analyse`` (typer 0.29 builds a pydantic TypeAdapter
for each option it parses), a small pydantic model validated from a YAML file read with
PyYAML, and xarray imported.  ``benchmarks/model_ladder.py --cold-start`` times it beside
``python -c "import xarray"`` and ``balance analyse inline-4 --format json``.

With ``--without-xarray`` (given first) it leaves xarray out: then it is the floor of what
``balance analyse --format json`` needs (numpy for the physics, typer for the command line,
pydantic for the layout schema, PyYAML for the file), and what ``balance`` adds is the
difference between the two.

    python benchmarks/startup_floor.py analyse layouts/inline-4.yaml --format json
    python benchmarks/startup_floor.py --without-xarray analyse layouts/inline-4.yaml --format json
"""

import os
import sys

# as balance's command line does: no scan of package metadata for pydantic plugins
os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import numpy
import typer

WITH_XARRAY = sys.argv[1:2] != ["--without-xarray"]
if not WITH_XARRAY:
    del sys.argv[1]

app = typer.Typer(add_completion=False, pretty_exceptions_enable=False, rich_markup_mode=None)


class Fmt(StrEnum):
    table = "table"
    json = "json"


@app.callback()
def options(debug: Annotated[bool, typer.Option("--debug")] = False) -> None:
    """Global options, as balance has."""


@app.command("analyse")
def analyse(
    layout: Annotated[str, typer.Argument()],
    orders: Annotated[str, typer.Option("--orders")] = "1-8",
    speed: Annotated[str | None, typer.Option("--speed")] = None,
    fmt: Annotated[Fmt, typer.Option("--format")] = Fmt.table,
    output: Annotated[Path | None, typer.Option("-o")] = None,
    force: Annotated[bool, typer.Option("--force")] = False,
    model: Annotated[str, typer.Option("--model")] = "exact",
    terms: Annotated[int, typer.Option("--terms")] = 3,
    samples: Annotated[int | None, typer.Option("--samples")] = None,
    tolerance: Annotated[float | None, typer.Option("--tolerance")] = None,
    no_roll: Annotated[bool, typer.Option("--no-roll")] = False,
) -> None:
    """Read and validate a layout file, import xarray (unless left out), print one line."""
    import yaml
    from pydantic import BaseModel

    class Geometry(BaseModel):
        stroke: str
        conrod_length: str

    class Spec(BaseModel):
        name: str
        speed: str
        geometry: Geometry

    data = yaml.safe_load(Path(layout).read_text())
    spec = Spec(
        name=data["name"],
        speed=data["speed"],
        geometry={k: str(data["geometry"][k]) for k in ("stroke", "conrod_length")},
    )
    if WITH_XARRAY:
        import xarray

        print(spec.name, xarray.__name__, numpy.__name__)
    else:
        print(spec.name, numpy.__name__)


if __name__ == "__main__":
    app()
