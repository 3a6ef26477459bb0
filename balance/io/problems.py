"""The validation problem that the layout-file models raise (:class:`FieldProblem`).

It lives in its own module so that section modules (:mod:`balance.io.bearings_section`) can
raise it while :mod:`balance.io.schema` imports their models, without an import cycle.
"""

from __future__ import annotations

__all__ = ["FieldProblem"]


class FieldProblem(ValueError):
    """A validation problem tied to a field below the model that found it."""

    def __init__(self, message: str, valid: str = "", at: tuple[str | int, ...] = ()) -> None:
        super().__init__(message)
        self.valid = valid
        self.at = at
