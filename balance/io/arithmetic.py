"""Exact arithmetic in a quantity's number: ``360/7 deg``, ``2*360/5 deg``, ``-(90 - 360/7)``.

Designers write the angles of odd-numbered radials and evenly spaced cranks as fractions of a
turn.  A decimal (``51.42857143 deg``) is not the angle: the phasor sums that cancel by
symmetry then leave a residue far above rounding (docs/conventions.md, "Zero by symmetry").
So a number may be written as arithmetic:

- decimal numbers (``360``, ``2.5``, ``1e3``), ``+``, ``-``, ``*``, ``/`` (also ``−`` and
  ``×``), parentheses, and signs (``-360/7``);
- nothing else is evaluated: no names, no powers, no function calls.  The text is read by
  the small grammar below, never handed to Python's ``eval``;
- the value is exact: each number is the rational number its decimal digits say, the
  operations are done in rational arithmetic, and the result is rounded to the nearest
  float once.  ``360/7`` is therefore the float nearest to 360/7, the same number that
  ``bank_count: 7`` gives the second bank, and ``0.1 + 0.2`` is 0.3.

Grammar (``NUMBER`` a decimal number with an optional exponent)::

    sum     := product (("+" | "-") product)*
    product := signed (("*" | "/") signed)*
    signed  := ("+" | "-") signed | atom
    atom    := NUMBER | "(" sum ")"

The arithmetic is the longest start of the text that the grammar reads; the rest is the
unit.  An operator without a number after it is left to the unit, so ``6000/min`` stays the
number 6000 in ``/min``.  :mod:`balance.io.units` decides which kinds of quantity may be
written so (angles; docs/layout-format.md, "Quantities and units").
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from fractions import Fraction

__all__ = ["MAX_DEPTH", "MAX_EXPONENT", "Arithmetic", "ArithmeticProblem", "read_arithmetic"]

#: Deepest nesting of parentheses read.
MAX_DEPTH = 16
#: Largest decimal exponent of a number (``1e400`` is no float; 400 digits stay cheap).
MAX_EXPONENT = 400

_NUMBER = re.compile(r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eE]([+-]?\d+))?")
# each operator character -> the operator it is (the minus sign and the times sign too)
_OPERATORS = {c: c for c in "+-*/()"} | {"\u2212": "-", "\u00d7": "*"}
_PLAIN = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?")


class ArithmeticProblem(ValueError):
    """Arithmetic that cannot be read or computed (an unclosed parenthesis, a division by
    zero, a number out of range); ``args[0]`` says what."""


@dataclass(frozen=True)
class Arithmetic:
    """The arithmetic at the start of a quantity's text.

    Attributes
    ----------
    value : fractions.Fraction
        Its exact value.
    text : str
        The arithmetic as written (stripped).
    rest : str
        What follows it, stripped: the unit, or ``""``.
    plain : bool
        Whether it is one number, perhaps signed (``-45``): no arithmetic at all, which the
        caller reads as it reads any number (``value`` is then not computed when the
        number's exponent is beyond :data:`MAX_EXPONENT`).
    """

    value: Fraction
    text: str
    rest: str
    plain: bool


@dataclass(frozen=True)
class _Token:
    kind: str  # "n" for a number, else the operator
    start: int
    end: int
    number: Fraction | None = None


def _tokens(text: str) -> list[_Token]:
    """The tokens of the start of ``text`` that arithmetic may be made of, up to the first
    character that can be none (a letter of the unit)."""
    out: list[_Token] = []
    i = 0
    while i < len(text):
        char = text[i]
        if char.isspace():
            i += 1
            continue
        match = _NUMBER.match(text, i)
        if match:
            exponent = match.group(1)
            huge = exponent is not None and abs(int(exponent)) > MAX_EXPONENT
            number = None if huge else Fraction(match.group(0))
            out.append(_Token("n", i, match.end(), number))
            i = match.end()
            continue
        if char in _OPERATORS:
            out.append(_Token(_OPERATORS[char], i, i + 1))
            i += 1
            continue
        break
    return out


class _Parser:
    """Recursive descent over the tokens (the grammar of the module notes)."""

    def __init__(self, tokens: list[_Token]) -> None:
        self.tokens = tokens
        self.at = 0
        self.depth = 0
        self.operators = 0
        self.huge: _Token | None = None

    def peek(self) -> str | None:
        return self.tokens[self.at].kind if self.at < len(self.tokens) else None

    def sum(self) -> Fraction | None:
        value = self.product()
        if value is None:
            return None
        while self.peek() in ("+", "-"):
            mark = self.at
            sign = self.tokens[self.at].kind
            self.at += 1
            right = self.product()
            if right is None:  # no operand: the operator is the unit's
                self.at = mark
                break
            self.operators += 1
            value = value + right if sign == "+" else value - right
        return value

    def product(self) -> Fraction | None:
        value = self.signed()
        if value is None:
            return None
        while self.peek() in ("*", "/"):
            mark = self.at
            operator = self.tokens[self.at].kind
            self.at += 1
            right = self.signed()
            if right is None:
                self.at = mark
                break
            self.operators += 1
            if operator == "*":
                value = value * right
            elif right == 0:
                raise ArithmeticProblem("division by zero")
            else:
                value = value / right
        return value

    def signed(self) -> Fraction | None:
        if self.peek() in ("+", "-"):
            mark = self.at
            sign = self.tokens[self.at].kind
            self.at += 1
            value = self.signed()
            if value is None:
                self.at = mark
                return None
            return -value if sign == "-" else value
        return self.atom()

    def atom(self) -> Fraction | None:
        kind = self.peek()
        if kind == "n":
            token = self.tokens[self.at]
            self.at += 1
            if token.number is None:  # an exponent out of range: refused if it is computed
                self.huge = self.huge or token
                return Fraction(0)
            return token.number
        if kind != "(":
            return None
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise ArithmeticProblem(f"parentheses nested deeper than {MAX_DEPTH}")
        self.at += 1
        self.operators += 1
        value = self.sum()
        if value is None or self.peek() != ")":
            raise ArithmeticProblem("a '(' without its ')'")
        self.at += 1
        self.depth -= 1
        return value


def read_arithmetic(text: str) -> Arithmetic | None:
    """The arithmetic at the start of a quantity's text, and the rest (its unit).

    Parameters
    ----------
    text : str
        A quantity as written (``"360/7 deg"``, ``"2*360/5"``, ``"86 mm"``).

    Returns
    -------
    Arithmetic or None
        None when the text does not start with a number, a sign or a parenthesis (``nan``,
        ``inf`` and words are the caller's to read).

    Raises
    ------
    ArithmeticProblem
        For arithmetic that cannot be read (a ``(`` without its ``)``, a ``)`` without its
        ``(``, parentheses nested deeper than :data:`MAX_DEPTH`) or computed (a division
        by zero, a number with an exponent beyond :data:`MAX_EXPONENT`).

    Examples
    --------
    >>> float(read_arithmetic("360/7 deg").value) == 360 / 7
    True
    >>> read_arithmetic("6000/min").rest
    '/min'
    """
    tokens = _tokens(text)
    parser = _Parser(tokens)
    value = parser.sum()
    if value is None:
        return None
    end = tokens[parser.at - 1].end
    written = text[tokens[0].start : end].strip()
    rest = text[end:].strip()
    if rest.startswith(")"):
        raise ArithmeticProblem("a ')' without its '('")
    plain = parser.operators == 0 and _PLAIN.fullmatch(written) is not None
    if parser.huge is not None and not plain:
        number = text[parser.huge.start : parser.huge.end]
        raise ArithmeticProblem(f"the number {number!r} is out of range")
    return Arithmetic(value, written, rest, plain)
