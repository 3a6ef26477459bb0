"""Validation problems located in the file: the one translator of pydantic's errors.

Every model of an input file (the layout file's, each of its sections', a mounts file's)
is validated through :func:`validate`, which turns each problem pydantic finds into one
:class:`~balance.core.errors.LayoutError` naming file, line, column, the field's dotted path
(``cylinders[3].stroke``) and what would be valid; a :class:`~balance.io.problems.FieldProblem`
that a section's builder raises after validation is located by :func:`problem_error`.  The
wording of each kind of problem is therefore the same in every section
(docs/layout-format.md, "Errors"):

- an unknown key: ``unknown key 'strok'; did you mean 'stroke'? valid keys: ...`` (a key
  reported missing beside a misspelling of it is reported once, as the misspelling);
- a missing key: ``missing 'z'`` and the section's hint of what to add;
- a value of the wrong type: ``expected a list, got a mapping``;
- a value out of its allowed set: ``'x' is not allowed; expected ...``;
- a list of the wrong length: ``2 entries`` and what the list holds;
- a quantity without its unit, and every check of a model, in their own words.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError

from balance.core.errors import LayoutError
from balance.io.problems import FieldProblem
from balance.io.units import UnitProblem
from balance.io.yamlsource import SourceDocument, dotted_path

__all__ = ["Hints", "Path", "problem_error", "validate"]

Path = tuple[str | int, ...]
M = TypeVar("M", bound=BaseModel)


@dataclass(frozen=True)
class Hints:
    """What a file's section proposes where a key is missing or a value has the wrong
    type or length, by the key's name.

    Attributes
    ----------
    missing : mapping of str to str
        What to add for a missing key (default ``add 'KEY'``).
    types : mapping of str to str
        What to write for a value of the wrong type (default ``write a mapping here`` with
        the type expected).
    sizes : mapping of str to str
        What a list of the wrong length should hold (default: its bounds).
    size : str
        What a list of the wrong length should hold where ``sizes`` has no entry for it
        (empty: its bounds).
    nouns : mapping of str to (str, str)
        What the entries of a list are called, one and many (``cylinders``: ``("cylinder",
        "cylinders")``), for a list of the wrong length: ``5000 cylinders; at most 256
        cylinders`` (default: entries).
    """

    missing: Mapping[str, str] = field(default_factory=dict)
    types: Mapping[str | int, str] = field(default_factory=dict)
    sizes: Mapping[str | int, str] = field(default_factory=dict)
    size: str = ""
    nouns: Mapping[str | int, tuple[str, str]] = field(default_factory=dict)


_NO_HINTS = Hints()


def validate(
    model: type[M],
    data: Any,
    doc: SourceDocument,
    prefix: Path = (),
    hints: Hints = _NO_HINTS,
    also: Sequence[str] = (),
) -> tuple[M | None, list[LayoutError]]:
    """The validated model of ``data``, or None and every problem found, located.

    Parameters
    ----------
    model : type of pydantic.BaseModel
        The model of the section.
    data : object
        The section's plain data, as read from the file.
    doc : SourceDocument
        The document read (for lines and columns).
    prefix : tuple
        Path of the section in the document (``("mounts",)`` under a ``mounts:`` key).
    hints : Hints
        The section's proposals (:class:`Hints`).
    also : sequence of str
        Keys valid at the top of the section besides the model's own (the sections that
        other models read), for an unknown key's list of valid keys.

    Returns
    -------
    model or None
        None when there are problems.
    list of LayoutError
        Every problem, empty for a valid section.
    """
    try:
        return model.model_validate(data), []
    except ValidationError as exc:
        errors = _located_errors(exc, doc, model, prefix, hints, also)
    return None, errors  # outside the handler: the ValidationError is no part of the report


def _located_errors(
    exc: ValidationError,
    doc: SourceDocument,
    model: type[BaseModel],
    prefix: Path = (),
    hints: Hints = _NO_HINTS,
    also: Sequence[str] = (),
) -> list[LayoutError]:
    """Every problem of a failed validation of ``model``, located in the file.

    Parameters
    ----------
    exc : pydantic.ValidationError
        The failed validation.
    doc, model, prefix, hints, also
        As for :func:`validate`.

    Returns
    -------
    list of LayoutError
        One per problem; a key reported missing where an unknown key beside it is a
        misspelling of it is reported once, as the unknown key.
    """
    errors = exc.errors(include_url=False)
    misspelt = set()
    for err in errors:
        if err["type"] == "extra_forbidden":
            loc = _error_loc(err)
            names = _keys(model, loc[:-1], also)
            for hint in difflib.get_close_matches(str(loc[-1]), names, n=1):
                misspelt.add((*loc[:-1], hint))
    return [
        _one_error(err, doc, model, prefix, hints, also)
        for err in errors
        if not (err["type"] == "missing" and _error_loc(err) in misspelt)
    ]


def problem_error(problem: FieldProblem, doc: SourceDocument, prefix: Path = ()) -> LayoutError:
    """A :class:`~balance.io.problems.FieldProblem` of the section at ``prefix``, located at
    its field (``prefix + problem.at``).

    Parameters
    ----------
    problem : FieldProblem
        Raised by a model's check or by a section's builder.
    doc : SourceDocument
        The document read.
    prefix : tuple
        Path of the model (or section) that raised it.

    Returns
    -------
    LayoutError
    """
    full = problem.at if problem.absolute else prefix + problem.at
    message = str(problem)
    if problem.written is not None:
        value = _value_at(doc.data, full)
        if isinstance(value, str | int | float) and not isinstance(value, bool):
            message = problem.written.format(str(value).strip())
    return LayoutError(
        message,
        doc.location(full),
        field=dotted_path(full) or None,
        valid=problem.valid or None,
    )


def _value_at(data: Any, path: Path) -> Any:
    """The plain value at ``path`` in the file's data (None where there is none)."""
    for part in path:
        listed = isinstance(part, int) and isinstance(data, list) and 0 <= part < len(data)
        if not (listed or (isinstance(part, str) and isinstance(data, dict) and part in data)):
            return None
        data = data[part]
    return data


def _clean_loc(raw: Any) -> Path:
    loc = tuple(p for p in raw if isinstance(p, str | int))
    # a validator's name, and the tag of a union's member (``crank:``'s ``<block>``)
    return tuple(p for p in loc if not (isinstance(p, str) and (p.startswith(("function-", "<")))))


def _error_loc(err: Any) -> Path:
    """Where a pydantic error is, in the file's keys: an unknown key's location ends with
    the key itself, whatever it is (a fuzzed layout had one named '<', which a union
    member's tag also begins with)."""
    if err["type"] == "extra_forbidden" and err["loc"]:
        return (*_clean_loc(err["loc"][:-1]), err["loc"][-1])
    return _clean_loc(err["loc"])


def _model_at(model: type[BaseModel], path: Path) -> type[BaseModel] | None:
    """The model of the mapping at ``path`` below ``model`` (list indices skipped)."""
    found: type[BaseModel] | None = model
    for part in path:
        if found is None:
            return None
        if isinstance(part, int):
            continue
        info = found.model_fields.get(part)
        if info is None:
            return None
        found = _model_of(info.annotation)
    return found


def _model_of(annotation: Any) -> type[BaseModel] | None:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in getattr(annotation, "__args__", ()) or ():
        found = _model_of(arg)
        if found is not None:
            return found
    return None


def _keys(model: type[BaseModel], path: Path, also: Sequence[str]) -> list[str]:
    """The keys valid in the mapping at ``path`` below ``model``."""
    found = _model_at(model, path)
    names = list(found.model_fields) if found is not None else []
    return names + list(also) if not path else names


_TYPE_NAMES = {
    "dict": "a mapping",
    "list": "a list",
    "str": "text",
    "int": "a whole number",
    "float": "a number",
    "bool": "true or false",
    "NoneType": "nothing",
}
_WANTED = {
    "dict_type": "a mapping",
    "model_type": "a mapping",
    "model_attributes_type": "a mapping",
    "list_type": "a list",
    "string_type": "text",
    "int_type": "a whole number",
    "int_from_float": "a whole number",
    "int_parsing": "a whole number",
    "float_type": "a number",
    "float_parsing": "a number",
}


def _one_error(
    err: Any,
    doc: SourceDocument,
    model: type[BaseModel],
    prefix: Path,
    hints: Hints,
    also: Sequence[str],
) -> LayoutError:
    """One pydantic error as a located :class:`LayoutError`."""
    own = _error_loc(err)
    loc = prefix + own
    kind = err["type"]
    ctx = err.get("ctx") or {}
    problem = ctx.get("error")
    name: str | int = loc[-1] if loc else ""
    if kind == "extra_forbidden":
        names = _keys(model, own[:-1], also)
        hint = difflib.get_close_matches(str(name), names, n=1)
        valid = f"did you mean '{hint[0]}'?" if hint else ""
        valid = (valid + " " if valid else "") + (
            f"valid keys: {', '.join(names)}" if names else ""
        )
        return LayoutError(
            f"unknown key '{name}'",
            doc.location(loc, key=True),
            field=dotted_path(loc),
            valid=valid.strip(),
        )
    if kind == "missing":
        return LayoutError(
            f"missing '{name}'",
            doc.location(loc[:-1]),
            field=dotted_path(loc),
            valid=hints.missing.get(str(name), f"add '{name}'"),
        )
    if isinstance(problem, FieldProblem):
        return problem_error(problem, doc, loc)
    if isinstance(problem, UnitProblem):
        return LayoutError(
            str(problem), doc.location(loc), field=dotted_path(loc), valid=problem.valid
        )
    if kind == "literal_error":
        return LayoutError(
            f"{err['input']!r} is not allowed",
            doc.location(loc),
            field=dotted_path(loc),
            valid=f"expected {ctx.get('expected', 'one of the documented values')}",
        )
    if kind in _WANTED or kind.endswith("_type"):
        got = _TYPE_NAMES.get(type(err["input"]).__name__, type(err["input"]).__name__)
        want = _WANTED.get(kind, err["msg"].lower())
        return LayoutError(
            f"expected {want}, got {got}",
            doc.location(loc),
            field=dotted_path(loc),
            valid=hints.types.get(name, f"write {want} here"),
        )
    if kind in {"too_short", "too_long", "string_too_short", "string_too_long"}:
        noun = hints.nouns.get(name)
        return LayoutError(
            _length(err["input"], kind, err["msg"], noun),
            doc.location(loc),
            field=dotted_path(loc) or None,
            valid=hints.sizes.get(name) or hints.size or _bounds(kind, ctx, noun),
        )
    if kind in _LIMITS:
        words, key = _LIMITS[kind]
        return LayoutError(
            f"{name} is {err['input']!r}",
            doc.location(loc),
            field=dotted_path(loc) or None,
            valid=f"{words} {ctx.get(key)}",
        )
    return LayoutError(err["msg"], doc.location(loc), field=dotted_path(loc) or None)


# pydantic's bounds of a number: what the bound is called, and its key in ``ctx``
_LIMITS = {
    "greater_than_equal": ("at least", "ge"),
    "greater_than": ("more than", "gt"),
    "less_than_equal": ("at most", "le"),
    "less_than": ("less than", "lt"),
}


def _count(n: int, one: str, many: str) -> str:
    return f"{n} {one if n == 1 else many}"


def _length(given: Any, kind: str, message: str, noun: tuple[str, str] | None = None) -> str:
    """What a list (or text) of the wrong length holds: ``2 entries``, ``5000 cylinders``."""
    if isinstance(given, list):
        return _count(len(given), *(noun or ("entry", "entries")))
    if isinstance(given, str):
        return _count(len(given), "character", "characters")
    return message


def _bounds(kind: str, ctx: Mapping[str, Any], noun: tuple[str, str] | None = None) -> str:
    """What a list (or text) should hold: ``at least 1 entry``, ``at most 256 cylinders``."""
    one, many = (
        ("character", "characters") if kind.startswith("string") else (noun or ("entry", "entries"))
    )
    if kind.endswith("short"):
        return f"at least {_count(int(ctx.get('min_length', 1)), one, many)}"
    return f"at most {_count(int(ctx.get('max_length', 0)), one, many)}"
