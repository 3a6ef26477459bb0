"""The validation problem that the layout-file models raise (:class:`FieldProblem`).

It lives in its own module so that section modules (:mod:`balance.io.bearings_section`) can
raise it while :mod:`balance.io.schema` imports their models, without an import cycle.
"""

from __future__ import annotations

__all__ = ["FieldProblem", "FieldProblems"]


class FieldProblem(ValueError):
    """A validation problem tied to a field below the model that found it.

    Parameters
    ----------
    message : str
        What is wrong.
    valid : str
        What would be valid instead.
    at : tuple of str and int
        The field's path below the model (or section) that found it; with ``absolute``,
        its path from the top of the file (a section's builder that finds a problem of
        another key, the firing order of a torsion train).
    absolute : bool
        Whether ``at`` starts at the top of the file.
    written : str, optional
        The message with ``{}`` where the value goes as the file writes it (``"speed is
        {}"``: ``speed is -100 rpm``, not the SI number of ``message``); used where the file
        holds the value at the problem's field.
    """

    def __init__(
        self,
        message: str,
        valid: str = "",
        at: tuple[str | int, ...] = (),
        absolute: bool = False,
        written: str | None = None,
    ) -> None:
        super().__init__(message)
        self.valid = valid
        self.at = at
        self.absolute = absolute
        self.written = written


class FieldProblems(ValueError):
    """Several problems that a section's builder found at once, each reported.

    Parameters
    ----------
    problems : sequence of FieldProblem
        At least one.
    """

    def __init__(self, problems: list[FieldProblem]) -> None:
        super().__init__("; ".join(str(p) for p in problems))
        self.problems = problems
