"""Layout files: what the rest of balance reads and writes them with.

The front of the layout-file modules, each of which does one job:

- :mod:`balance.io.layouts`: the built-in layouts (:func:`builtin_layout_names`,
  :func:`builtin_layout_path`) and which file a layout argument means;
- :mod:`balance.io.layout_reader`: YAML -> validated models -> an
  :class:`~balance.core.engine.Engine` (:func:`load_layout`, :func:`layout_from_text`,
  :func:`layout_from_dict`), every problem of a file reported at once;
- :mod:`balance.io.schema` and :mod:`balance.io.layout_fields`: the file's models and the
  one table of its numeric fields;
- :mod:`balance.io.layout_sections`: the registry of the concern sections, each read and
  built by its own module;
- :mod:`balance.io.located`: the one translator of validation problems into located
  :class:`~balance.core.errors.LayoutError` s;
- :mod:`balance.io.layout_expand`: ``balance layout expand`` (:func:`expand_layout`).

The format is in docs/layout-format.md.
"""

from __future__ import annotations

from balance.io.layout_expand import expand_layout
from balance.io.layout_reader import layout_from_dict, layout_from_text, load_layout
from balance.io.layouts import builtin_layout_names, builtin_layout_path

__all__ = [
    "builtin_layout_names",
    "builtin_layout_path",
    "expand_layout",
    "layout_from_dict",
    "layout_from_text",
    "load_layout",
]
