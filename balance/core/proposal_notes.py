r"""What a balancing proposal leaves, in words computed from the residual.

The notes of :func:`balance.core.balancing.propose` say what the shafts do to the roll and
what shafts fixed by the layout leave.  The ones here are formed after the residual (the
free forces with every proposed mass, :func:`balance.core.proposal.residual`), from its
numbers, so that each says what the residual holds:

* :func:`factor_note`: what a balance factor leaves of the forward first order, force and
  moment, and whether that is short of the pistons' forward first order (under-balanced) or
  beyond it (overbalanced); with a counter-rotating crankshaft the same of the backward
  first order; with the factor in both conventions (:mod:`balance.core.balance_factor`);
* :func:`orders_left`: the orders asked to be cancelled whose residual force or moment is
  not zero;
* :func:`cancel_roll_notes`: what ``cancel_roll`` did where the notes of the placement say
  nothing (no shafts, or an order whose roll the shafts already cancel where they are).
"""

from __future__ import annotations

import numpy as np

from balance.core.balance_factor import percent
from balance.core.balancing import Proposal
from balance.core.phasors import Phasors

__all__ = ["cancel_roll_notes", "factor_note", "orders_left", "relation"]

#: Two phasors are along one line when the sine of the angle between them is below this.
_ALIGNED = 1e-9


def relation(left: complex, whole: complex) -> float | None:
    r"""What ``left`` is of ``whole`` when the two lie along one line: the signed share
    :math:`\mathrm{Re}(L\bar W)/|W|^2` (positive: the same direction), None otherwise.

    Parameters
    ----------
    left, whole : complex
        Two phasors in one unit.

    Returns
    -------
    float or None
        The share [1]; None when ``whole`` is 0 or the two are not along one line.
    """
    if whole == 0 or left == 0:
        return None
    cross = left * whole.conjugate()
    if abs(cross.imag) > _ALIGNED * abs(left) * abs(whole):
        return None
    return float(cross.real / abs(whole) ** 2)


def _part(value: complex, pistons: complex, unit: str, what: str, sense: str = "forward") -> str:
    """``12.3 N of forward first-order force (25 % of the pistons' 49.2 N: under-balanced)``."""
    if value == 0:
        return f"no {sense} first-order {what}"
    text = f"{abs(value):.4g} {unit} of {sense} first-order {what}"
    share = relation(value, pistons)
    if share is None:
        return text
    if share > 0:
        return (
            f"{text} ({percent(share)} of the pistons' {abs(pistons):.4g} {unit}: under-balanced)"
        )
    return (
        f"{text} (opposite to the pistons' {abs(pistons):.4g} {unit}, and {percent(-share)} of "
        "it: overbalanced)"
    )


def factor_note(
    proposal: Proposal, pistons: Phasors, residual: Phasors, backward: bool = False
) -> str | None:
    """The note of the balance factor: what it leaves of the forward first order (and of
    the backward one, with a counter-rotating crankshaft).

    Parameters
    ----------
    proposal : Proposal
        The proposal (its balance factor, and the orders it cancels).
    pistons : Phasors
        The engine's reciprocating phasors, with order 1 and moments [N, N m].
    residual : Phasors
        The residual at the same orders [N, N m].
    backward : bool
        Counterweights turn backwards too (a counter-rotating crankshaft,
        docs/several-crankshafts.md): say what is left in both senses, each against the
        pistons' first order of that sense.

    Returns
    -------
    str or None
        None without a balance factor.
    """
    if proposal.factor is None:
        return None
    head = f"balance factor {proposal.factor.describe()}"
    if 1 not in proposal.orders:
        listed = ", ".join(map(str, proposal.orders))
        return f"{head}: not used, since order 1 is not among the orders to cancel ({listed})"
    at = int(np.flatnonzero(np.asarray(residual.orders) == 1)[0])
    assert residual.moment_forward is not None and pistons.moment_forward is not None
    force = complex(residual.force_forward[at])
    moment = complex(residual.moment_forward[at])
    if not backward:
        if force == 0 and moment == 0:
            return f"{head}: the counterweights leave no forward first-order force or moment"
        return (
            f"{head}: the counterweights leave "
            f"{_part(force, complex(pistons.force_forward[at]), 'N', 'force')} and "
            f"{_part(moment, complex(pistons.moment_forward[at]), 'N m', 'moment')}"
        )
    assert residual.moment_backward is not None and pistons.moment_backward is not None
    left = (force, moment, complex(residual.force_backward[at]), residual.moment_backward[at])
    if all(value == 0 for value in left):
        return f"{head}: the counterweights leave no first-order force or moment in either sense"
    senses = [
        f"{_part(complex(left[0 + j]), complex(f[at]), 'N', 'force', sense)} and "
        f"{_part(complex(left[1 + j]), complex(m[at]), 'N m', 'moment', sense)}"
        for j, sense, f, m in (
            (0, "forward", pistons.force_forward, pistons.moment_forward),
            (2, "backward", pistons.force_backward, pistons.moment_backward),
        )
    ]
    return f"{head}: the counterweights leave {senses[0]}; and {senses[1]}"


def orders_left(proposal: Proposal, residual: Phasors) -> tuple[int, ...]:
    """The orders the proposal was asked to cancel whose residual force or moment is not 0.

    Parameters
    ----------
    proposal : Proposal
        The proposal.
    residual : Phasors
        The residual at (at least) the orders to cancel [N, N m].

    Returns
    -------
    tuple of int
        Ascending.
    """
    force = residual.peak("force")
    moment = residual.peak("moment")
    orders = np.asarray(residual.orders).tolist()
    out = []
    for k in proposal.orders:
        if k in orders and (force[i := orders.index(k)] != 0 or moment[i] != 0):
            out.append(int(k))
    return tuple(out)


def cancel_roll_notes(proposal: Proposal, residual: Phasors) -> list[str]:
    """What ``cancel_roll`` did where the proposal's notes say nothing of it.

    Parameters
    ----------
    proposal : Proposal
        The proposal, made with ``cancel_roll``.
    residual : Phasors
        The residual with its roll [N m], at (at least) the shafts' orders.

    Returns
    -------
    list of str
        A note when there are no shafts to place, and one for each order with shafts that
        no note of the proposal speaks of (their roll and the engine's already cancel where
        the shafts are, so they stay).
    """
    if not proposal.cancel_roll:
        return []
    if not proposal.shafts:
        return [
            "cancel_roll: no balance shafts are proposed, so there is nothing to place; the "
            "roll is the engine's"
        ]
    out = []
    for k in sorted({abs(s.speed_ratio) for s in proposal.shafts}):
        if any(note.startswith(f"order {k}:") for note in proposal.notes):
            continue
        at = np.flatnonzero(np.asarray(residual.orders) == k)
        if not at.size or residual.roll is None:
            continue
        amplitude = abs(complex(residual.roll[at[0]]))
        where = "; ".join(
            f"{s.speed_ratio:+d} at x = {s.x * 1e3:.4g} mm, y = {s.y * 1e3:.4g} mm"
            for s in proposal.shafts
            if abs(s.speed_ratio) == k
        )
        if amplitude == 0:
            out.append(
                f"order {k}: with the shafts where they are ({where}) the roll of this order is "
                "already 0 N m, so cancel_roll leaves them there"
            )
        else:
            out.append(
                f"order {k}: cancel_roll leaves the shafts where they are ({where}); the roll "
                f"of this order with them is {amplitude:.4g} N m"
            )
    return out
