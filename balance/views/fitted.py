"""Tables of numbers that never cut a number: laid out when printed, for the width there is.

A :class:`NumberTable` holds a title, its columns (each a name and a unit) and rows of
formatted cells.  When rich prints it, it picks the first layout that shows every cell in
full at the console's width:

1. one table with one-line headers (``peak [N m]``);
2. one table with headers wrapped between words, the unit kept whole on its own
   (``peak`` over ``[N m]``), so that a column is as narrow as its widest number;
3. the same table split into parts side by side in the text, one after the other, each
   repeating the key columns (``order``, ``layout``) and each marked ``(part i of n)``;
4. when even one column beside the keys does not fit: one line per value,
   ``key: name [unit] = value``, after a line that says so.

A number is never wrapped, folded or cut with an ellipsis.  The title is a line of its
own (not wrapped to the table's width), and notes follow the table (for example the
remarks of a balancing proposal).  Headers and cells are plain text: square brackets are
never read as rich markup.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:  # pragma: no cover
    from rich.console import Console, ConsoleOptions, RenderableType
    from rich.measure import Measurement

__all__ = ["Column", "NumberTable"]


@dataclass(frozen=True)
class Column:
    """A column of a :class:`NumberTable`.

    Attributes
    ----------
    name : str
        What the column holds (``peak``, ``z``, ``order``).
    unit : str, optional
        Shown after the name in square brackets (``N m``, ``mm``, ``deg``, ``%``); None for
        labels, counts and ratios whose name says what they are relative to
        (``peak / F1``).
    key : bool
        Repeated in every part when the table is split (``order``, ``layout``).
    justify : {'right', 'left'}
        Numbers right, names left.
    """

    name: str
    unit: str | None = None
    key: bool = False
    justify: Literal["left", "right"] = "right"

    @property
    def header(self) -> str:
        """The one-line header: the name and the unit in brackets."""
        return self.name if self.unit is None else f"{self.name} [{self.unit}]"

    def tokens(self) -> list[str]:
        """The words a header may be wrapped between; the unit is one word."""
        words = self.name.split() or [""]
        return words if self.unit is None else [*words, f"[{self.unit}]"]


def _length(text: str) -> int:
    from rich.cells import cell_len

    return max((cell_len(line) for line in text.split("\n")), default=0)


def _wrap(tokens: Sequence[str], width: int) -> str:
    """Words into lines of at most ``width`` cells (a longer word on a line of its own)."""
    lines: list[str] = []
    for token in tokens:
        if lines and _length(lines[-1]) + 1 + _length(token) <= width:
            lines[-1] += " " + token
        else:
            lines.append(token)
    return "\n".join(lines)


def _narrowest(tokens: Sequence[str], low: int, lines: int) -> int:
    """The narrowest width from ``low`` on at which ``tokens`` wrap into ``lines`` lines."""
    width = low
    while len(_wrap(tokens, width).split("\n")) > lines:
        width += 1
    return width


def _balanced(sizes: Sequence[int], n: int) -> list[tuple[int, int]]:
    """Cut ``sizes`` into ``n`` contiguous groups, the largest group sum as small as it can
    be; the groups as (start, stop) index pairs."""
    total = len(sizes)
    prefix = [0]
    for size in sizes:
        prefix.append(prefix[-1] + size)
    inf = float("inf")
    best = [[inf] * (total + 1) for _ in range(n + 1)]
    cut = [[0] * (total + 1) for _ in range(n + 1)]
    best[0][0] = 0
    for parts in range(1, n + 1):
        for stop in range(1, total + 1):
            for start in range(parts - 1, stop):
                cost = max(best[parts - 1][start], prefix[stop] - prefix[start])
                if cost < best[parts][stop]:
                    best[parts][stop], cut[parts][stop] = cost, start
    groups = []
    stop = total
    for parts in range(n, 0, -1):
        start = cut[parts][stop]
        groups.append((start, stop))
        stop = start
    return groups[::-1]


def _greedy(
    others: Sequence[int], keys: Sequence[int], width: int, table: NumberTable
) -> list[tuple[int, int]]:
    """Contiguous groups of ``others`` filled one after the other up to ``width``."""
    groups = []
    start = 0
    while start < len(others):
        stop = start + 1
        while stop < len(others) and table._widths([*keys, *others[start : stop + 1]], width):
            stop += 1
        groups.append((start, stop))
        start = stop
    return groups


def _table_width(widths: Sequence[int]) -> int:
    """Width of a rich table (heavy head box, edges, one space of padding each side) whose
    columns have these content widths."""
    return sum(widths) + 2 * len(widths) + len(widths) + 1


@dataclass
class NumberTable:
    """A titled table of formatted numbers that lays itself out for the printing width
    (see the module notes).

    Attributes
    ----------
    title : str
        One line above the table.
    columns : sequence of Column
    rows : sequence of sequence of str
        Formatted cells, one per column; a cell may not contain a line break.  Not to be
        changed once the table is made (the widths of the cells are measured once).
    notes : sequence of str
        Lines printed after the table.
    """

    title: str
    columns: Sequence[Column]
    rows: Sequence[Sequence[str]]
    notes: Sequence[str] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        n = len(self.columns)
        for row in self.rows:
            if len(row) != n:
                raise ValueError(
                    f"table {self.title!r}: a row has {len(row)} cells for {n} columns"
                )

    # ------------------------------------------------------------------ widths

    @cached_property
    def _cell_widths(self) -> list[int]:
        """Width of each column's widest cell, measured once (the rows are not changed
        after the table is made)."""
        return [
            max((_length(str(row[i])) for row in self.rows), default=0)
            for i in range(len(self.columns))
        ]

    def _widths(self, indices: Sequence[int], width: int) -> list[int] | None:
        """Content widths of the columns ``indices`` in a table at most ``width`` wide, or
        None if they do not fit even with every header wrapped between its words.

        The headers are made as few lines high as the width allows: each column is the
        narrowest that holds its widest cell and its header in that many lines."""
        tokens = [self.columns[i].tokens() for i in indices]
        floor = [self._floor(i) for i in indices]
        if _table_width(floor) > width:
            return None
        tallest = max((len(_wrap(w, f).split("\n")) for w, f in zip(tokens, floor, strict=True)))
        for lines in range(1, tallest + 1):
            widths = [
                _narrowest(words, low, lines) for words, low in zip(tokens, floor, strict=True)
            ]
            if _table_width(widths) <= width:
                return widths
        return floor  # pragma: no cover - the loop ends at the floor widths

    def _parts(self, width: int) -> list[tuple[list[int], list[int]]] | None:
        """The table as parts that each fit: (column indices, content widths) per part; None
        when the keys and any one other column are wider than ``width``.

        As few parts as fit (each repeating the key columns), the columns kept in their
        order and shared out so that the widest part is as narrow as it can be."""
        everything = list(range(len(self.columns)))
        widths = self._widths(everything, width)
        if widths is not None:
            return [(everything, widths)]
        keys = [i for i, c in enumerate(self.columns) if c.key]
        others = [i for i, c in enumerate(self.columns) if not c.key]
        if any(self._widths([*keys, i], width) is None for i in others):
            return None
        # whether a part fits depends only on the sum of its columns' narrowest widths, so
        # the balanced cut into as many parts as a greedy filling needs fits as well
        n_parts = len(_greedy(others, keys, width, self))
        parts = []
        for lo, hi in _balanced([self._floor(i) + 3 for i in others], n_parts):
            indices = [*keys, *others[lo:hi]]
            fitted = self._widths(indices, width)
            assert fitted is not None
            parts.append((indices, fitted))
        return parts

    def _floor(self, i: int) -> int:
        """Narrowest content width of column ``i``: its widest cell or header word."""
        return max(self._cell_widths[i], *(_length(t) for t in self.columns[i].tokens()))

    # ------------------------------------------------------------------ rendering

    def _table(self, indices: Sequence[int], widths: Sequence[int]) -> RenderableType:
        from rich.table import Table
        from rich.text import Text

        table = Table(show_edge=True, pad_edge=True)
        for i, w in zip(indices, widths, strict=True):
            column = self.columns[i]
            table.add_column(
                Text(_wrap(column.tokens(), w), justify=column.justify),
                justify=column.justify,
                width=w,
                no_wrap=True,  # the widths fit every cell: nothing is ever cut
            )
        for row in self.rows:
            table.add_row(*(Text(str(row[i]), justify=self.columns[i].justify) for i in indices))
        return table

    def _as_list(self) -> list[RenderableType]:
        from rich.text import Text

        keys = [i for i, c in enumerate(self.columns) if c.key]
        others = [i for i, c in enumerate(self.columns) if not c.key]
        out: list[RenderableType] = [
            Text("(too narrow for this table: one line per value)", style="dim")
        ]
        for row in self.rows:
            label = ", ".join(f"{self.columns[i].header} {row[i]}" for i in keys)
            if label:
                out.append(Text(f"{label}:"))
            for i in others:
                out.append(Text(f"  {self.columns[i].header} = {row[i]}"))
        return out

    def renderables(self, width: int) -> list[RenderableType]:
        """What is printed at ``width`` columns: the title, the table (or its parts, or the
        list form) and the notes."""
        from rich.text import Text

        out: list[RenderableType] = [Text(self.title, style="table.title")]
        parts = self._parts(width)
        if parts is None:
            out += self._as_list()
        elif len(parts) == 1:
            out.append(self._table(*parts[0]))
        else:
            for n, (indices, widths) in enumerate(parts, start=1):
                if n > 1:
                    out.append(
                        Text(f"{self.title} (part {n} of {len(parts)})", style="table.title")
                    )
                else:
                    out[0] = Text(f"{self.title} (part 1 of {len(parts)})", style="table.title")
                out.append(self._table(indices, widths))
        out += [Text(note) for note in self.notes]
        return out

    def __rich_console__(
        self, console: Console, options: ConsoleOptions
    ) -> Iterator[RenderableType]:
        yield from self.renderables(options.max_width)

    def __rich_measure__(self, console: Console, options: ConsoleOptions) -> Measurement:
        from rich.measure import Measurement

        cells = self._cell_widths
        full = [max(c, _length(col.header)) for c, col in zip(cells, self.columns, strict=True)]
        widest = max(_table_width(full), _length(self.title))
        return Measurement(min(widest, options.max_width), min(widest, options.max_width))
