"""The concern sections of a layout file: the registry the reader and the writer loop over.

A concern section (:mod:`balance.core.sections`) may have a section of the layout file
that turns it on and says what it needs (docs/layout-format.md).  Each such section has a
module of :mod:`balance.io` that defines a :class:`SectionReader` named ``SECTION``: its
key in the file, its pydantic model, the builder of what
:attr:`balance.core.engine.Engine.sections` holds under that key, and its part of
``balance layout expand``.  The reader (:mod:`balance.io.layout_reader`) validates each
section present with its model (every problem of the file at once, located by
:mod:`balance.io.located`), builds it on the engine and stores it; the writer
(:mod:`balance.io.layout_expand`) writes it back.  Neither names a section.

Adding a section of the layout file is: a module with its model, builder and ``SECTION``,
and its line in :data:`LAYOUT_SECTIONS`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache
from importlib import import_module
from typing import Any

from pydantic import BaseModel

from balance.core.engine import Engine
from balance.io.located import Hints

__all__ = ["LAYOUT_SECTIONS", "SectionReader", "section_keys", "section_reader"]


@dataclass(frozen=True)
class SectionReader:
    """How a layout file's concern section is read, built and written back.

    Attributes
    ----------
    key : str
        The section's key in the layout file, and the name under which
        :attr:`balance.core.engine.Engine.sections` holds what it says (the concern
        section's name, :mod:`balance.core.sections`).
    spec : type of pydantic.BaseModel
        The section's model (values read with their units, SI after validation).
    build : callable
        ``build(spec, engine)``: what the engine's sections hold under ``key``, from the
        validated section and the engine read from the rest of the file.  It raises a
        :class:`~balance.io.problems.FieldProblem` (located below the section's key) for a
        problem that needs the engine.
    expand : callable
        ``expand(written, value)``: the section as ``balance layout expand`` writes it,
        from the section as the file wrote it and the value built.
    hints : Hints
        What the section proposes for a missing key, a value of the wrong type or a list
        of the wrong length (:class:`balance.io.located.Hints`).
    """

    key: str
    spec: type[BaseModel]
    build: Callable[[Any, Engine], Any]
    expand: Callable[[Any, Any], Any]
    hints: Hints = field(default_factory=Hints)


#: Each section's key in the layout file -> ``"module:NAME"`` of its :class:`SectionReader`,
#: in the order the file's keys are listed and the engine holds the sections.  A module is
#: imported only for a file that has its section.
LAYOUT_SECTIONS: dict[str, str] = {
    "mounts": "balance.io.mounts_section:SECTION",
    "bearings": "balance.io.bearings_section:SECTION",
    "dynamics": "balance.io.dynamics_section:SECTION",
    "torsion": "balance.io.torsion_section:SECTION",
}


def section_keys() -> tuple[str, ...]:
    """The keys of the layout file's concern sections, in order.

    Returns
    -------
    tuple of str
    """
    return tuple(LAYOUT_SECTIONS)


@cache
def section_reader(key: str) -> SectionReader:
    """The reader of the section ``key`` (its module imported on first use).

    Parameters
    ----------
    key : str
        A key of :data:`LAYOUT_SECTIONS`.

    Returns
    -------
    SectionReader

    Raises
    ------
    KeyError
        If no concern section has that key.
    """
    module, _, name = LAYOUT_SECTIONS[key].partition(":")
    reader = getattr(import_module(module), name)
    assert isinstance(reader, SectionReader) and reader.key == key, LAYOUT_SECTIONS[key]
    return reader
