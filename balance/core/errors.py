"""Error types of balance.

Every problem the program can report is one of these.  The command line turns any of them
into a single line ``file:line:col: field: what is wrong; what is valid`` on stderr and an
exit code (2 for bad input, 1 for an analysis that could not be carried out); a file with
several problems (:class:`LayoutErrors`) gives one such line per problem.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

__all__ = [
    "AnalysisError",
    "BalanceError",
    "InputError",
    "LayoutError",
    "LayoutErrors",
    "Location",
    "OutputExists",
    "raise_all",
]


@dataclass(frozen=True)
class Location:
    """Where in an input file a problem was found (1-based line and column)."""

    file: str = "<input>"
    line: int | None = None
    column: int | None = None

    def __str__(self) -> str:
        parts = [self.file]
        if self.line is not None:
            parts.append(str(self.line))
            if self.column is not None:
                parts.append(str(self.column))
        return ":".join(parts)


class BalanceError(Exception):
    """Base class of every error balance reports to a user."""

    exit_code = 1

    def one_line(self) -> str:
        """The message as one line, without a traceback."""
        return " ".join(str(self).split())

    def lines(self) -> list[str]:
        """The problems, one line each (one line for every error but :class:`LayoutErrors`)."""
        return [self.one_line()]


class InputError(BalanceError):
    """Bad input: a file, an option or an argument that cannot be used as given."""

    exit_code = 2


class OutputExists(InputError):
    """An output that exists, where replacing it was not asked for (``force``).

    The message names the setting; the command line names its option instead.

    Parameters
    ----------
    target : str or path-like
        The output.
    what : str
        ``"file exists"``, or ``"exists"`` for an output that may be a directory.
    """

    def __init__(self, target: object, what: str = "file exists") -> None:
        self.target = target
        self.what = what
        super().__init__(f"{target}: {what} and replacing it was not asked for (force)")


class LayoutError(InputError):
    """A layout file that cannot be read, with where and what would be valid.

    Parameters
    ----------
    message : str
        What is wrong.
    location : Location, optional
        File, line and column of the offending value.
    field : str, optional
        Dotted path of the field, for example ``geometry.conrod_length``
        or ``cylinders[3].throw``.
    valid : str, optional
        What would be valid instead.
    """

    def __init__(
        self,
        message: str,
        location: Location | None = None,
        field: str | None = None,
        valid: str | None = None,
    ) -> None:
        self.message = message
        self.location = location or Location()
        self.field = field
        self.valid = valid
        super().__init__(self._format())

    def _format(self) -> str:
        text = f"{self.location}: "
        if self.field:
            text += f"{self.field}: "
        text += self.message
        if self.valid:
            text += f"; {self.valid}"
        return text


class LayoutErrors(LayoutError):
    """Every problem found in one input file, each a :class:`LayoutError`.

    It is itself the first problem (its ``message``, ``location``, ``field`` and ``valid``),
    so that code that handles one :class:`LayoutError` still works; ``str()`` is every
    problem, one per line, and :meth:`lines` lists them.

    Parameters
    ----------
    errors : sequence of LayoutError
        At least two problems, in the order to report them.
    """

    def __init__(self, errors: Sequence[LayoutError]) -> None:
        self.errors = tuple(errors)
        first = self.errors[0]
        self.message = first.message
        self.location = first.location
        self.field = first.field
        self.valid = first.valid
        Exception.__init__(self, "\n".join(e.one_line() for e in self.errors))

    def one_line(self) -> str:
        """The first problem, with the number of the others."""
        more = len(self.errors) - 1
        return f"{self.errors[0].one_line()} (and {more} more problem{'s' if more > 1 else ''})"

    def lines(self) -> list[str]:
        """Every problem, one line each."""
        return [e.one_line() for e in self.errors]


def raise_all(errors: Sequence[LayoutError]) -> None:
    """Raise the problems found (nothing when there are none): one as itself, several as
    :class:`LayoutErrors` in file order (line, then column), each reported once.

    Parameters
    ----------
    errors : sequence of LayoutError
        The problems found, in any order, duplicates allowed.

    Raises
    ------
    LayoutError
        The one problem, or :class:`LayoutErrors` holding several.
    """
    unique: dict[str, LayoutError] = {}
    for error in errors:
        unique.setdefault(error.one_line(), error)
    found = sorted(unique.values(), key=lambda e: (e.location.line or 0, e.location.column or 0))
    if len(found) == 1:
        raise found[0]
    if found:
        raise LayoutErrors(found)


class AnalysisError(BalanceError):
    """An analysis that cannot be carried out for a valid input."""

    exit_code = 1
