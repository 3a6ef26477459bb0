"""The orders and the crank speed that every analysis is asked for: ``--orders`` (and a
section's ``cancel:`` orders) and a speed given in place of the layout's.

A module of its own, apart from the other fields of the command line
(:mod:`balance.io.fields`, which gives these too), so that building a request
(:mod:`balance.io.request`) imports neither the table of fields nor the grammar of
``--vary`` and ``--scatter``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from balance.core.errors import InputError
from balance.io.limits import MAX_ORDER

__all__ = ["DEFAULT_ORDERS", "check_speed", "parse_orders"]

#: Orders reported when none are asked for: 1 to this.
DEFAULT_ORDERS = 8


def parse_orders(
    spec: int | str | Iterable[int] | NDArray[np.integer] | None, option: str = "orders"
) -> NDArray[np.intp]:
    """Orders from an int (1..N), a spec string (``"1-8"``, ``"2"``, ``"1,2,4-6"``) or a list.

    Parameters
    ----------
    spec : int, str, sequence of int or None
        The orders as given; None is 1 to :data:`DEFAULT_ORDERS`.
    option : str
        The parameter (``orders``, ``cancel``) or option (``--orders``) they were given to,
        for the message.

    Returns
    -------
    ndarray of int
        The distinct orders, sorted.

    Raises
    ------
    InputError
        For an empty, malformed or out-of-range spec (orders 1 to :data:`MAX_ORDER`; a
        range written high to low).
    """
    out_of_range = f"every order must be between 1 and {MAX_ORDER}"
    if spec is None:
        return np.arange(1, DEFAULT_ORDERS + 1)
    if isinstance(spec, bool):
        raise InputError(f"{option}: expected a number, a range such as 1-8, or a list")
    if isinstance(spec, int | np.integer):
        if not 1 <= spec <= MAX_ORDER:
            raise InputError(f"{option}: {int(spec)}: {out_of_range}")
        values = list(range(1, int(spec) + 1))
    elif isinstance(spec, str):
        values = []
        for part in spec.replace(" ", "").split(","):
            match = re.fullmatch(r"(\d+)(?:-(\d+))?", part)
            if not match:
                raise InputError(
                    f"{option}: cannot read {spec!r}; write a range or list such as 1-8, 2 or "
                    "1,2,4-6"
                )
            lo = int(match.group(1))
            hi = int(match.group(2)) if match.group(2) else lo
            if hi < lo:
                raise InputError(
                    f"{option}: {part!r} is not an increasing range; write the lower order "
                    f"first, e.g. {hi}-{lo}"
                )
            if lo < 1 or hi > MAX_ORDER:
                raise InputError(f"{option}: {part!r}: {out_of_range}")
            values.extend(range(lo, hi + 1))
    else:
        values = [int(v) for v in spec]
    if not values:
        raise InputError(f"{option}: no orders given; for example 1-8")
    if min(values) < 1 or max(values) > MAX_ORDER:
        raise InputError(f"{option}: {out_of_range}")
    return np.asarray(sorted(set(values)), dtype=np.intp)


def check_speed(speed: float) -> float:
    """A crank speed that every analysis can use: finite and above zero.

    Parameters
    ----------
    speed : float
        Crank speed [rad/s].

    Returns
    -------
    float
        The speed [rad/s].

    Raises
    ------
    InputError
        Otherwise.
    """
    if not (math.isfinite(speed) and speed > 0):
        raise InputError(f"speed must be a finite number above zero, got {speed!r} rad/s")
    return float(speed)
