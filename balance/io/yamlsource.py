"""Safe YAML reading that remembers where every value came from.

The layout file is parsed into plain Python values (``dict``, ``list``, ``str``, ``int``,
``float``, ``bool``, ``None``) together with a map from each value's path to its line and
column, so that validation errors can point back into the file.  Only the YAML core schema
is accepted: no object construction tags.  Alias expansion is counted, so a
"billion laughs" document is refused after a bounded amount of work, and so are documents
nested deeper than any layout needs.
"""

from __future__ import annotations

import pathlib
from collections.abc import Collection
from dataclasses import dataclass, field
from typing import Any

import yaml

from balance.core.errors import InputError, LayoutError, Location

__all__ = [
    "MAX_BYTES",
    "MAX_DEPTH",
    "MAX_NODES",
    "SourceDocument",
    "dotted_path",
    "parse_yaml",
    "read_yaml_file",
]

#: Largest layout file read [bytes].  Real layouts are a few kilobytes.
MAX_BYTES = 1_000_000
#: Largest number of values after alias expansion.
MAX_NODES = 200_000
#: Deepest nesting of mappings and lists.
MAX_DEPTH = 32

Path = tuple[str | int, ...]

_Loader: type[yaml.SafeLoader] = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


@dataclass(repr=False, eq=False)  # one per file read, never compared or shown
class SourceDocument:
    """Plain data of a YAML document and the location of each value and key."""

    data: Any
    file: str
    value_marks: dict[Path, tuple[int, int]] = field(default_factory=dict)
    key_marks: dict[Path, tuple[int, int]] = field(default_factory=dict)

    def location(self, path: Path, key: bool = False) -> Location:
        """Location of the value (or, with ``key=True``, of the key) at ``path``.

        Falls back to the nearest enclosing value when the path itself is absent
        (for example a missing field is reported at its parent mapping).
        """
        marks = self.key_marks if key else self.value_marks
        probe = tuple(path)
        while True:
            if probe in marks:
                line, col = marks[probe]
                return Location(self.file, line, col)
            if probe in self.value_marks:
                line, col = self.value_marks[probe]
                return Location(self.file, line, col)
            if not probe:
                return Location(self.file, 1, 1)
            probe = probe[:-1]


def _scalar(node: yaml.ScalarNode, constructor: yaml.SafeLoader, doc: SourceDocument) -> Any:
    try:
        return constructor.construct_object(node)
    except yaml.YAMLError as exc:
        line, col = node.start_mark.line + 1, node.start_mark.column + 1
        raise LayoutError(
            f"cannot read the value {node.value!r} ({_first_line(exc)})",
            Location(doc.file, line, col),
            valid="write a plain number or a quoted string such as '86 mm'",
        ) from None


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _check_tag(
    node: yaml.Node, allowed: Collection[str], what: str, doc: SourceDocument, line: int, col: int
) -> None:
    """Refuse a node whose tag is not one of ``allowed`` (plain YAML ``what`` only)."""
    if node.tag not in allowed:
        raise LayoutError(
            f"tag {node.tag!r} is not allowed",
            Location(doc.file, line, col),
            valid=f"plain YAML {what} only (no tags)",
        )


def _convert(
    node: yaml.Node,
    path: Path,
    depth: int,
    doc: SourceDocument,
    constructor: yaml.SafeLoader,
    budget: list[int],
) -> Any:
    budget[0] -= 1
    line, col = node.start_mark.line + 1, node.start_mark.column + 1
    if budget[0] < 0:
        raise LayoutError(
            f"the document expands to more than {MAX_NODES} values (alias expansion bomb?)",
            Location(doc.file, line, col),
            valid="a layout needs a few hundred values; write it without nested aliases",
        )
    if depth > MAX_DEPTH:
        raise LayoutError(
            f"nested deeper than {MAX_DEPTH} levels",
            Location(doc.file, line, col),
            valid="a layout is at most a few levels deep",
        )
    doc.value_marks.setdefault(path, (line, col))
    if isinstance(node, yaml.ScalarNode):
        _check_tag(node, _CORE_TAGS, "values", doc, line, col)
        return _scalar(node, constructor, doc)
    if isinstance(node, yaml.SequenceNode):
        _check_tag(node, _SEQ_TAGS, "lists", doc, line, col)
        return [
            _convert(item, (*path, i), depth + 1, doc, constructor, budget)
            for i, item in enumerate(node.value)
        ]
    if isinstance(node, yaml.MappingNode):
        _check_tag(node, _MAP_TAGS, "mappings", doc, line, col)
        out: dict[str, Any] = {}
        for key_node, value_node in node.value:
            kline, kcol = key_node.start_mark.line + 1, key_node.start_mark.column + 1
            if key_node.tag == "tag:yaml.org,2002:merge":
                raise LayoutError(
                    "merge keys ('<<') are not supported",
                    Location(doc.file, kline, kcol),
                    valid="write the keys out",
                )
            if not isinstance(key_node, yaml.ScalarNode) or key_node.tag != "tag:yaml.org,2002:str":
                shown = (
                    key_node.value if isinstance(key_node, yaml.ScalarNode) else "(a collection)"
                )
                raise LayoutError(
                    f"key {shown!r} is not a name",
                    Location(doc.file, kline, kcol),
                    valid="keys are lower-case names such as 'stroke'",
                )
            key = str(key_node.value)
            if key in out:
                first = doc.key_marks.get((*path, key), (kline, kcol))
                raise LayoutError(
                    f"duplicate key {key!r} (first given on line {first[0]})",
                    Location(doc.file, kline, kcol),
                    field=dotted_path((*path, key)),
                    valid="give each key once",
                )
            doc.key_marks[(*path, key)] = (kline, kcol)
            out[key] = _convert(value_node, (*path, key), depth + 1, doc, constructor, budget)
        return out
    raise LayoutError(  # pragma: no cover - PyYAML has only these three node kinds
        "unsupported YAML node", Location(doc.file, line, col)
    )


_SEQ_TAGS = frozenset({"tag:yaml.org,2002:seq"})
_MAP_TAGS = frozenset({"tag:yaml.org,2002:map"})
_CORE_TAGS = {
    "tag:yaml.org,2002:str",
    "tag:yaml.org,2002:int",
    "tag:yaml.org,2002:float",
    "tag:yaml.org,2002:bool",
    "tag:yaml.org,2002:null",
}


def _is_tab(text: str, line: int, column: int, problem: str) -> bool:
    """Whether a syntax error at 0-based ``line`` and ``column`` is a tab where YAML wants
    spaces (the parser says "cannot start any token" for a tab that indents a key)."""
    if "tab" in problem:
        return True
    lines = text.splitlines()
    return 0 <= line < len(lines) and lines[line][column : column + 1] == "\t"


def dotted_path(path: Path) -> str:
    """A path in the document as the messages write it.

    Parameters
    ----------
    path : tuple of (str or int)
        Keys and 0-based list indices from the document's root.

    Returns
    -------
    str
        The keys joined by dots, list entries numbered from 1 (``cylinders[2].link.master``).
    """
    text = ""
    for part in path:
        if isinstance(part, int):
            text += f"[{part + 1}]"
        else:
            text += ("." if text else "") + part
    return text


def _decode_text(raw: bytes, file: str) -> str:
    """Decode a layout file's bytes as UTF-8, refusing binary and oversized input.

    Parameters
    ----------
    raw : bytes
        The file's contents.
    file : str
        The name the messages give the file.

    Returns
    -------
    str
        The text (a UTF-8 byte order mark dropped).

    Raises
    ------
    LayoutError
        For more than :data:`MAX_BYTES` bytes, a NUL byte, or bytes that are no UTF-8 (with
        their line and column).
    """
    if len(raw) > MAX_BYTES:
        raise LayoutError(
            f"file is {len(raw)} bytes, more than the {MAX_BYTES} bytes a layout may have",
            Location(file),
            valid="a layout file is a few kilobytes of YAML",
        )
    if b"\x00" in raw:
        raise LayoutError(
            "file is binary (it contains NUL bytes)", Location(file), valid="a YAML text file"
        )
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        before = raw[: exc.start]
        line = before.count(b"\n") + 1
        col = exc.start - (before.rfind(b"\n") + 1) + 1
        raise LayoutError(
            f"byte 0x{raw[exc.start]:02x} is not UTF-8",
            Location(file, line, col),
            valid="save the file as UTF-8 text",
        ) from None
    return text


def read_yaml_file(path: pathlib.Path, source: str | pathlib.Path, what: str) -> SourceDocument:
    """Read, decode and parse a YAML file (a layout, a mounts file).

    The text is decoded by :func:`_decode_text` and parsed by :func:`parse_yaml`.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    source : str or pathlib.Path
        The name the user gave (used in the messages).
    what : str
        The kind of file, for the message when ``path`` is a directory (``"layout file"``).

    Returns
    -------
    SourceDocument

    Raises
    ------
    InputError
        If the path is missing, unreadable or a directory.
    LayoutError
        If the text cannot be decoded or is no YAML.
    """
    if not path.exists():
        raise InputError(f"{source}: no such file")
    if path.is_dir():
        raise InputError(f"{source}: is a directory, not a {what}")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{source}: cannot read ({exc.strerror})") from None
    return parse_yaml(_decode_text(raw, str(source)), str(path))


def parse_yaml(text: str, file: str = "<input>") -> SourceDocument:
    """Parse YAML text into plain data with locations.

    Parameters
    ----------
    text : str
        The YAML document.
    file : str
        Name used in error messages.

    Returns
    -------
    SourceDocument
        Plain data and the locations of its values and keys.

    Raises
    ------
    LayoutError
        For syntax errors, multiple documents, tags, duplicate keys, alias bombs and
        documents nested deeper than :data:`MAX_DEPTH`.
    """
    doc = SourceDocument(data=None, file=file)
    if len(text.encode("utf-8", "surrogatepass")) > MAX_BYTES:
        raise LayoutError(
            f"text is more than the {MAX_BYTES} bytes a layout may have",
            Location(file),
            valid="a layout file is a few kilobytes of YAML",
        )
    loader = _Loader(text)
    try:
        try:
            node = loader.get_single_node()
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            problem = exc.problem or exc.context or "syntax error"
            location = Location(file, mark.line + 1, mark.column + 1) if mark else Location(file)
            if "expected a single document" in (exc.context or ""):
                raise LayoutError(
                    "more than one YAML document", location, valid="one layout per file"
                ) from None
            if mark is not None and _is_tab(text, mark.line, mark.column, problem):
                raise LayoutError(
                    "a tab character: YAML does not allow tabs for indentation",
                    location,
                    valid="indent with spaces",
                ) from None
            raise LayoutError(
                f"YAML syntax error: {problem}", location, valid="check indentation and quoting"
            ) from None
        except yaml.YAMLError as exc:
            raise LayoutError(f"YAML error: {_first_line(exc)}", Location(file)) from None
        if node is None:
            raise LayoutError(
                "the file is empty",
                Location(file, 1, 1),
                valid="a layout is a mapping with name, speed, geometry, masses and cylinders",
            )
        budget = [MAX_NODES]
        doc.data = _convert(node, (), 0, doc, loader, budget)
    except RecursionError:  # in the parser or in the conversion
        raise LayoutError(
            "nested too deeply to read",
            Location(file),
            valid=f"a layout is at most {MAX_DEPTH} levels deep",
        ) from None
    finally:
        loader.dispose()
    return doc
