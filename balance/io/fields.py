"""The grammar of field specifications on the command line: ``--orders``.

Every function here checks what it reads and raises :class:`~balance.core.errors.InputError`
with what would be valid.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from balance.core.errors import InputError

__all__ = ["DEFAULT_ORDERS", "MAX_ORDER", "parse_orders"]

#: Orders reported when none are asked for: 1 to this.
DEFAULT_ORDERS = 8
#: Highest order that can be asked for.
MAX_ORDER = 1000


def parse_orders(spec: int | str | Iterable[int] | NDArray[np.integer] | None) -> NDArray[np.intp]:
    """Orders from an int (1..N), a spec string (``"1-8"``, ``"2"``, ``"1,2,4-6"``) or a list.

    Raises
    ------
    InputError
        For an empty, malformed or out-of-range spec.
    """
    if spec is None:
        return np.arange(1, DEFAULT_ORDERS + 1)
    if isinstance(spec, bool):
        raise InputError("orders: expected a number, a range such as 1-8, or a list")
    if isinstance(spec, int | np.integer):
        values = list(range(1, int(spec) + 1))
    elif isinstance(spec, str):
        values = []
        for part in spec.replace(" ", "").split(","):
            match = re.fullmatch(r"(\d+)(?:-(\d+))?", part)
            if not match:
                raise InputError(
                    f"orders: cannot read {spec!r}; write a range or list such as 1-8, 2 or 1,2,4-6"
                )
            lo = int(match.group(1))
            hi = int(match.group(2)) if match.group(2) else lo
            if hi < lo or hi - lo > MAX_ORDER:
                raise InputError(f"orders: {part!r} is not an increasing range")
            values.extend(range(lo, hi + 1))
    else:
        values = [int(v) for v in spec]
    if not values:
        raise InputError("orders: no orders given; for example 1-8")
    if min(values) < 1 or max(values) > MAX_ORDER:
        raise InputError(f"orders: every order must be between 1 and {MAX_ORDER}")
    return np.asarray(sorted(set(values)), dtype=np.intp)
