"""The built-in layouts: their names, their files, and which file a layout argument means.

The built-in layouts are the YAML files of ``balance/layouts`` (installed) or of the source
tree's ``layouts/`` (docs/layouts.md lists them).  A layout argument (``balance analyse
inline-4``, :func:`balance.load_layout`) is a file when it names one, else the name of a
built-in layout (:func:`layout_path`).
"""

from __future__ import annotations

import difflib
from importlib import resources
from pathlib import Path

from balance.core.errors import InputError

__all__ = ["builtin_layout_names", "builtin_layout_path", "layout_path"]


def _layout_dirs() -> list[Path]:
    dirs = []
    packaged = resources.files("balance") / "layouts"
    if packaged.is_dir():
        dirs.append(Path(str(packaged)))
    source_tree = Path(__file__).resolve().parents[2] / "layouts"
    if source_tree.is_dir():
        dirs.append(source_tree)
    return dirs


def builtin_layout_names() -> list[str]:
    """Names of the built-in layouts (``inline-4``, ``v8-crossplane``...).

    Returns
    -------
    list of str
        Sorted.
    """
    names: set[str] = set()
    for d in _layout_dirs():
        names.update(p.stem for p in d.glob("*.yaml"))
    return sorted(names)


def builtin_layout_path(name: str) -> Path:
    """Path of a built-in layout file.

    Parameters
    ----------
    name : str
        A built-in layout's name (:func:`builtin_layout_names`).

    Returns
    -------
    Path

    Raises
    ------
    InputError
        If there is no built-in layout of that name (with the closest names).
    """
    for d in _layout_dirs():
        candidate = d / f"{name}.yaml"
        if candidate.is_file():
            return candidate
    names = builtin_layout_names()
    hint = difflib.get_close_matches(name, names, n=3)
    valid = f"did you mean {' or '.join(hint)}?" if hint else "run 'balance layouts' for the list"
    raise InputError(f"{name}: no such file or built-in layout; {valid}")


def layout_path(source: str | Path) -> Path:
    """The file a layout argument means: the file it names, or else (a bare name without
    ``/`` and without a ``.yaml``/``.yml`` ending) the built-in layout of that name.

    Parameters
    ----------
    source : str or path-like
        A file path or a built-in layout's name.

    Returns
    -------
    Path
        The file (not checked to exist when ``source`` is a path).

    Raises
    ------
    InputError
        For a bare name that is neither a file nor a built-in layout.
    """
    path = Path(source)
    if (
        not path.exists()
        and isinstance(source, str)
        and "/" not in source
        and not source.endswith((".yaml", ".yml"))
    ):
        path = builtin_layout_path(source)
    return path
