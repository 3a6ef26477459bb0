"""Error types of balance.

Every problem the program can report is one of these.  The command line turns any of them
into a single line ``file:line:col: field: what is wrong; what is valid`` on stderr and an
exit code (2 for bad input, 1 for an analysis that could not be carried out).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["AnalysisError", "BalanceError", "InputError", "LayoutError", "Location"]


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


class InputError(BalanceError):
    """Bad input: a file, an option or an argument that cannot be used as given."""

    exit_code = 2


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


class AnalysisError(BalanceError):
    """An analysis that cannot be carried out for a valid input."""

    exit_code = 1
