r"""The balance factor and its two conventions (docs/theory.md, "The balance factor").

A balance factor says how much reciprocating mass the counterweights carry besides the
rotating masses, as a share of a reference mass.  Texts and workshops use two references:

* ``each-cylinder`` (a bare ``balance_factor:``, ``--balance-factor``): the share of *each*
  cylinder's reciprocating mass; a throw whose pin carries :math:`n` rods carries :math:`n`
  times that share of one rod's mass.  Workshop practice for V-twins with rods on one pin
  states the bob weight this way (rotating mass plus the factor times the *total*
  reciprocating mass).
* ``one-cylinder``: the share of *one* cylinder's reciprocating mass on each throw; a throw
  with :math:`n` rods carries the share of the rods' mean mass, i.e. share/:math:`n` of each
  rod's.  Motorcycle texts that call a 90° V-twin "100 % balanced" (the first order
  cancelled by a counterweight of one cylinder's reciprocating mass) mean this.

The two agree wherever every throw carries one rod (singles, inline engines, split pins); on
a 90° V-twin's common pin 100 % ``one-cylinder`` is 50 % ``each-cylinder``.  The rods of
a pin are those of one throw at one throw angle (:func:`balance.core.throws.rods_per_pin`):
rods staggered side by side on one pin count, split pins do not.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.errors import AnalysisError

__all__ = [
    "CONVENTIONS",
    "DEFINITIONS",
    "BalanceFactor",
    "FactorEquivalents",
    "cylinder_shares",
    "percent",
]

#: The conventions a balance factor may be given in; the first is the bare key's.
CONVENTIONS = ("each-cylinder", "one-cylinder")

#: What a factor of each convention is a share of, in words.
DEFINITIONS = {
    "each-cylinder": "of each cylinder's reciprocating mass",
    "one-cylinder": "of one cylinder's reciprocating mass on each throw",
}


@dataclass(frozen=True)
class BalanceFactor:
    """A balance factor and the convention it is given in.

    Attributes
    ----------
    value : float
        The share [1] (0.5 for 50 %).
    of : {'each-cylinder', 'one-cylinder'}
        What it is a share of (:data:`CONVENTIONS`).
    """

    value: float
    of: str = "each-cylinder"

    def __post_init__(self) -> None:
        if self.of not in CONVENTIONS:
            raise AnalysisError(
                f"balance factor of {self.of!r}; use one of {', '.join(CONVENTIONS)}"
            )


def percent(share: float) -> str:
    """A share as the proposal prints it: ``50 %``, ``33.33 %``.

    Parameters
    ----------
    share : float
        The share [1].

    Returns
    -------
    str
        Four significant digits and a percent sign.
    """
    return f"{100.0 * share:.4g} %"


def cylinder_shares(factor: BalanceFactor, rods: ArrayLike) -> NDArray[np.float64]:
    """Each cylinder's share of its own reciprocating mass that the crank carries.

    Parameters
    ----------
    factor : BalanceFactor
        The balance factor.
    rods : array_like of int
        Per cylinder, the number of rods on its throw.

    Returns
    -------
    ndarray
        The share [1] per cylinder: the factor (``each-cylinder``) or the factor over the
        number of rods on the throw (``one-cylinder``).
    """
    counts = np.asarray(rods, dtype=np.float64)
    if factor.of == "each-cylinder":
        return np.full(counts.shape, float(factor.value))
    return np.asarray(float(factor.value) / counts, dtype=np.float64)


@dataclass(frozen=True)
class FactorEquivalents:
    """A balance factor as given, and its value in each convention.

    Attributes
    ----------
    given : BalanceFactor
        The factor as the layout, the command line or the API gave it.
    rods : tuple of int
        The different numbers of rods per throw of the engine, ascending.
    """

    given: BalanceFactor
    rods: tuple[int, ...]

    @classmethod
    def of(cls, factor: BalanceFactor, rods: ArrayLike) -> FactorEquivalents:
        """The equivalents of ``factor`` on an engine with ``rods`` per throw.

        Parameters
        ----------
        factor : BalanceFactor
            The factor.
        rods : array_like of int
            Per cylinder (or per throw), the number of rods on its throw.

        Returns
        -------
        FactorEquivalents
        """
        return cls(factor, tuple(sorted({int(n) for n in np.asarray(rods).ravel()})))

    def value(self, convention: str) -> float | None:
        """The factor in ``convention`` [1]; None where it differs from throw to throw (throws
        with different numbers of rods).

        Parameters
        ----------
        convention : {'each-cylinder', 'one-cylinder'}
            The convention.

        Returns
        -------
        float or None
        """
        if convention == self.given.of:
            return float(self.given.value)
        if len(self.rods) != 1:
            return None
        n = self.rods[0]
        if convention == "each-cylinder":
            return float(self.given.value) / n
        return float(self.given.value) * n

    @property
    def each_cylinder(self) -> float | None:
        """The share of each cylinder's reciprocating mass [1] (None: not one number)."""
        return self.value("each-cylinder")

    @property
    def one_cylinder(self) -> float | None:
        """The share of one cylinder's reciprocating mass on each throw [1] (None: not one
        number)."""
        return self.value("one-cylinder")

    def stated(self) -> str:
        """The factor as given, with its convention: ``50 % of each cylinder's reciprocating
        mass``.

        Returns
        -------
        str
        """
        return f"{percent(self.given.value)} {DEFINITIONS[self.given.of]}"

    def other(self) -> str:
        """The factor in the other convention, in words.

        Returns
        -------
        str
            ``= 100 % of one cylinder's on each throw: 2 rods per throw``, or, where the
            throws carry different numbers of rods, the value on the throws of each number.
        """
        other = CONVENTIONS[1 - CONVENTIONS.index(self.given.of)]
        whose = "of each cylinder's" if other == "each-cylinder" else "of one cylinder's"
        if len(self.rods) == 1:
            n = self.rods[0]
            value = self.value(other)
            assert value is not None
            where = "" if other == "each-cylinder" else " on each throw"
            rods = "one rod per throw" if n == 1 else f"{n} rods per throw"
            return f"= {percent(value)} {whose}{where}: {rods}"
        parts = []
        for j, n in enumerate(self.rods):
            single = FactorEquivalents(self.given, (n,)).value(other)
            assert single is not None
            rods = "1 rod" if n == 1 else f"{n} rods"
            head = (
                f"{percent(single)} {whose} on the throws"
                if j == 0
                else f"{percent(single)} on those"
            )
            parts.append(f"{head} of {rods}")
        return f"= {', '.join(parts)}"

    def describe(self) -> str:
        """The factor as given and its equivalent in the other convention.

        Returns
        -------
        str
            For example ``100 % of one cylinder's reciprocating mass on each throw (= 50 % of
            each cylinder's: 2 rods per throw)``.
        """
        return f"{self.stated()} ({self.other()})"
