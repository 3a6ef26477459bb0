r"""Balance shafts: where their axes go and the roll their forces make.

A balance shaft turning at :math:`s\omega` with its eccentric force :math:`P e^{is\theta}`
acting at :math:`p = y + ix` in the transverse plane turns the block by
:math:`\mathrm{Im}(\bar p P e^{is\theta})` (:func:`shaft_roll_phasors`).  Its axis does
not change its force, so it is free to be placed for the roll: :func:`default_axes` gives
the axes neither the layout nor the roll places, :func:`place_shafts` places the shafts of
each order so that the engine's roll and theirs cancel (where asked) and says, order by
order, where the shafts raise the roll or sit beyond the crank train's reach.

The shafts' unbalances are sized by :func:`balance.core.balancing.balance_shafts`; this
module only moves their axes.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from balance.core.engine import Engine
from balance.core.errors import AnalysisError
from balance.core.speed import speed_squared

__all__ = [
    "SHAFT_CLEARANCE",
    "BalanceShaft",
    "default_axes",
    "place_shafts",
    "shaft_roll_phasors",
]

ComplexArray = NDArray[np.complex128]

#: Shaft axes that the proposal places keep this many mean crank radii from the crank axis
#: and from each other; the default axes sit this far from the crank axis, below it
#: (:func:`default_axes`).
SHAFT_CLEARANCE = 2.0
#: A roll is cancelled (or unchanged) when it differs from zero (or from the engine's own)
#: by less than this share of the magnitudes that meet in it.
_ROLL_TOL = 1e-9


@dataclass(frozen=True)
class BalanceShaft:
    r"""A shaft turning at ``speed_ratio`` times crank speed with eccentric masses.

    Attributes
    ----------
    speed_ratio : int
        Shaft speed over crank speed; negative turns against the crank.
    x, y : float
        Position of the shaft axis in the transverse plane [m] (for roll).
    planes : tuple of (float, complex)
        ``(z, unbalance)`` of each eccentric: plane [m] and :math:`m e\, e^{i\alpha}` [kg m];
        the mass sits at :math:`\alpha + s\theta`.
    x_from, y_from : {'default', 'layout', 'cancel-roll'}
        Where each coordinate of the axis comes from: the default placement, the layout's
        ``balance: shafts:`` section, or the placement that cancels the roll.
    """

    speed_ratio: int
    x: float
    y: float
    planes: tuple[tuple[float, complex], ...]
    x_from: str = "default"
    y_from: str = "default"

    @property
    def total_unbalance(self) -> complex:
        """Sum of the planes' unbalances [kg m] (what the shaft's force depends on)."""
        return complex(sum(u for _, u in self.planes))


def default_axes(r: float, side: int = 0) -> tuple[float, float]:
    r"""Where a balance shaft's axis goes when neither the layout nor the roll places it.

    On the circle of radius :math:`c = 2r` (:data:`SHAFT_CLEARANCE` mean crank radii) around
    the crank axis, below the crank: a single shaft straight below, :math:`(0, -c)`; the
    two shafts of a pair of one order 30° either side of straight down,
    :math:`(\mp c/2, -c\sqrt3/2) = (\mp r, -\sqrt3 r)`, forward on the :math:`-x` side, so
    that they are :math:`c` apart.  Every default axis is therefore :math:`2r` from the
    crank axis, within the crank train's reach :math:`r + l` for any rod longer than the
    crank radius, and within the crank's lateral sweep :math:`|x| \le r` (the theory docs,
    "Balance shafts").

    Parameters
    ----------
    r : float
        Mean crank radius [m].
    side : {0, 1, -1}
        0 for a single shaft; for a pair, the sense of the shaft (+1 forward, -1 backward).

    Returns
    -------
    tuple of float
        ``(x, y)`` of the axis [m].
    """
    c = SHAFT_CLEARANCE * r
    if side == 0:
        return 0.0, -c
    return (-0.5 * c if side > 0 else 0.5 * c), -0.5 * math.sqrt(3.0) * c


def shaft_roll_phasors(
    shafts: Sequence[BalanceShaft], speed: float, orders: Sequence[int] | NDArray[np.integer]
) -> ComplexArray:
    r"""Roll torque phasors that the shafts' eccentric forces put on the block.

    A shaft at :math:`p = y + ix` with force :math:`F(\theta) = P e^{is\theta}` gives the
    torque :math:`\mathrm{Im}(\bar p F)` about the crank axis (positive in the direction of
    rotation): :math:`R = -i\bar p P` for s > 0, :math:`R = i p \bar P` for s < 0.  At
    constant speed the shaft's drive carries no torque.

    Parameters
    ----------
    shafts : sequence of BalanceShaft
        The balance shafts (speed ratio, axis position [m], unbalance [kg m]).
    speed : float
        Crank speed [rad/s].
    orders : sequence of int
        The orders.

    Returns
    -------
    ndarray of complex
        Roll phasor per order [N m]; 0 at orders no shaft turns at.
    """
    ks = np.asarray(orders, dtype=np.intp).ravel()
    out = np.zeros(ks.size, dtype=np.complex128)
    for shaft in shafts:
        s = shaft.speed_ratio
        p = complex(shaft.y, shaft.x)
        P = shaft.total_unbalance * s * s * float(speed_squared(speed))
        R = -1j * p.conjugate() * P if s > 0 else 1j * p * P.conjugate()
        out[ks == abs(s)] += R
    return out


def place_shafts(
    layout: Engine,
    shafts: list[BalanceShaft],
    roll: ComplexArray | None,
    orders: Sequence[int],
    *,
    cancel_roll: bool,
    mean_radius: float,
) -> tuple[list[BalanceShaft], list[str]]:
    """The shafts placed to cancel the engine's roll (where asked), and the notes on what
    they do to the roll, order by order.

    Parameters
    ----------
    layout : Engine
        The engine (its speed, crank radii, conrod lengths and gas forces).
    shafts : list of BalanceShaft
        The shafts, sized, at their default or given axes.
    roll : ndarray of complex or None
        The engine's roll per order of ``orders`` [N m] (None, or NaN, when not computed).
    orders : sequence of int
        The orders of ``roll``.
    cancel_roll : bool
        Whether to place the shafts so that each order's roll cancels.
    mean_radius : float
        The mean crank radius [m]: the axes keep :data:`SHAFT_CLEARANCE` of them from the
        crank axis and from each other.

    Returns
    -------
    shafts : list of BalanceShaft
        The shafts, placed.
    notes : list of str
        Where they were placed, where they sit beyond the crank train's reach and where
        they raise an order's roll, by order.

    Raises
    ------
    AnalysisError
        When the roll is to be cancelled and the engine's roll is not given.
    """
    w2 = float(speed_squared(layout.speed))
    engine_roll = _roll_by_order(roll, orders)
    clearance = SHAFT_CLEARANCE * mean_radius
    placed: dict[int, str] = {}
    if cancel_roll:
        if engine_roll is None:
            raise AnalysisError("cancelling roll needs the engine's roll phasors")
        shafts, placed = place_for_roll(shafts, engine_roll, w2, clearance)
        reach = float(np.max(layout.crank_radius + layout.conrod_length))
        for k, text in _beyond_reach_notes(shafts, reach).items():
            placed[k] = f"{placed[k]}; {text}" if k in placed else f"order {k}: {text}"
    raised = (
        _roll_increase_notes(
            shafts, engine_roll, w2, clearance, cancel_roll, with_gas=layout.gas is not None
        )
        if engine_roll is not None
        else {}
    )
    notes: list[str] = []
    for k in sorted(placed.keys() | raised.keys()):
        notes.extend(note[k] for note in (placed, raised) if k in note)
    return shafts, notes


def _roll_by_order(roll: ComplexArray | None, orders: Sequence[int]) -> dict[int, complex] | None:
    """The engine's roll per order, or None when not given (or not computed: NaN)."""
    if roll is None:
        return None
    values = np.asarray(roll, dtype=np.complex128).ravel()
    if values.size != len(orders) or np.isnan(values).any():
        return None
    return {int(k): complex(values[i]) for i, k in enumerate(orders)}


def _shaft_force(shaft: BalanceShaft, w2: float) -> complex:
    """:math:`P`, the phasor of the shaft's whole eccentric force [N]."""
    return shaft.total_unbalance * shaft.speed_ratio**2 * w2


def _shaft_roll(shaft: BalanceShaft, w2: float) -> complex:
    """Roll phasor of one shaft [N m] (:func:`shaft_roll_phasors`)."""
    p = complex(shaft.y, shaft.x)
    force = _shaft_force(shaft, w2)
    return -1j * p.conjugate() * force if shaft.speed_ratio > 0 else 1j * p * force.conjugate()


def _roll_gradient(shaft: BalanceShaft, w2: float, coordinate: str) -> complex:
    """Change of the shaft's roll phasor per metre of ``x`` or ``y`` (it is linear in both)."""
    force = _shaft_force(shaft, w2)
    if shaft.speed_ratio > 0:  # -i conj(y + i x) P
        return -force if coordinate == "x" else -1j * force
    return -force.conjugate() if coordinate == "x" else 1j * force.conjugate()


def _mm(shaft: BalanceShaft) -> str:
    return f"x = {shaft.x * 1e3:.4g} mm, y = {shaft.y * 1e3:.4g} mm"


def _clean(value: float, clearance: float) -> float:
    """A placed coordinate, with rounding noise next to an exact 0 set to 0 [m]."""
    return 0.0 if abs(value) < 1e-9 * clearance else value + 0.0


@dataclass(frozen=True)
class _Placement:
    shafts: tuple[BalanceShaft, ...]
    note: str | None
    cancelled: bool


def place_for_roll(
    shafts: Sequence[BalanceShaft],
    roll: dict[int, complex],
    w2: float,
    clearance: float,
) -> tuple[list[BalanceShaft], dict[int, str]]:
    r"""Place the shafts of each order so that the roll of that order is zero.

    For every order :math:`k` that has shafts, the coordinates not given by the layout
    (``x_from``/``y_from`` other than ``'layout'``) are chosen so that the engine's roll
    phasor :math:`R_e` and the shafts' together vanish:

    .. math:: R_e + \sum_j R_j(x_j, y_j) = 0, \qquad
              R_j = -\mathrm{i}\,\bar p_j P_j \;(s_j > 0), \quad
              R_j = \mathrm{i}\,p_j \bar P_j \;(s_j < 0), \quad p_j = y_j + \mathrm{i}x_j.

    :math:`R_j` is linear in the coordinates, so this is two real equations; of their
    solutions the one nearest to the starting positions (least squares) is taken.  Axes the
    proposal places keep ``clearance`` from the crank axis and from each other; when the
    nearest solution does not, a pair with all four coordinates free is placed instead on
    either side of the crank axis, across the line of its force (the theory docs, "Balance
    shafts and the roll").
    Where no placement is possible the shafts stay, and the note of that order says why.

    Parameters
    ----------
    shafts : sequence of BalanceShaft
        The proposed shafts, at their starting positions.
    roll : dict of int to complex
        The engine's roll phasor per order [N m].
    w2 : float
        Crank speed squared [rad²/s²].
    clearance : float
        Smallest distance of a placed axis from the crank axis and from the other shaft [m].

    Returns
    -------
    list of BalanceShaft
        The shafts, placed.
    dict of int to str
        A note per order that has something to say (where the shafts went, or why not).

    References
    ----------
    K. Nakamura, "Silent Shaft Design for Engines", SAE Technical Paper
    760111, 1976: a Lanchester pair at two heights cancels the inline-4's second-order
    roll as well as its force.
    """
    result = list(shafts)
    notes: dict[int, str] = {}
    for k in sorted({abs(s.speed_ratio) for s in result}):
        if k not in roll:
            continue
        members = [i for i, shaft in enumerate(result) if abs(shaft.speed_ratio) == k]
        placement = _placement(tuple(result[i] for i in members), roll[k], w2, clearance)
        for i, shaft in zip(members, placement.shafts, strict=True):
            result[i] = shaft
        if placement.note:
            notes[k] = f"order {k}: {placement.note}"
    return result, notes


def _roll_scale(
    group: Sequence[BalanceShaft], engine: complex, w2: float, clearance: float
) -> float:
    """Size of the terms that meet in an order's roll with shafts [N m]."""
    return abs(engine) + sum(
        abs(_shaft_force(s, w2)) * max(abs(complex(s.y, s.x)), clearance) for s in group
    )


def _placement(
    group: tuple[BalanceShaft, ...], engine: complex, w2: float, clearance: float
) -> _Placement:
    """The shafts of one order placed to cancel its roll (see :func:`place_for_roll`)."""
    active = [j for j, shaft in enumerate(group) if _shaft_force(shaft, w2) != 0]
    scale = _roll_scale(group, engine, w2, clearance)
    total = engine + sum((_shaft_roll(shaft, w2) for shaft in group), 0j)
    if scale == 0 or abs(total) <= _ROLL_TOL * scale:
        return _Placement(group, None, True)
    if not active:
        return _Placement(
            group,
            "the shafts carry pure couples (no net force), which put no torque about the crank "
            f"axis: where they sit cannot cancel the roll ({abs(engine):.4g} N m)",
            False,
        )
    free = [
        (j, c) for j in active for c in ("x", "y") if getattr(group[j], f"{c}_from") != "layout"
    ]
    if not free:
        return _Placement(
            group,
            "the shaft axes are all given in balance.shafts, so the roll is not cancelled: "
            f"{abs(total):.4g} N m with them ({abs(engine):.4g} N m from the engine alone)",
            False,
        )
    nearest = _nearest_roll_free(group, free, engine, w2, scale, clearance)
    if nearest is None:
        names = ", ".join(f"{c} of the shaft at {group[j].speed_ratio:+d}" for j, c in free)
        return _Placement(
            group,
            f"the coordinates not given in balance.shafts ({names}) cannot cancel the roll "
            f"({abs(total):.4g} N m with the shafts where they are)",
            False,
        )
    crowded = _crowding(nearest, active, clearance)
    if crowded is None:
        placed = "shaft placed" if len(active) == 1 else "shafts placed"
        return _Placement(nearest, f"{placed} {_placed(nearest, engine, total)})", True)
    if len(active) == 2 and len(free) == 4:
        across = _nearest_roll_free(
            _across_force(group, w2, clearance), free, engine, w2, scale, clearance
        )
        if across is not None and _crowding(across, active, clearance) is None:
            return _Placement(
                across,
                "shafts placed on either side of the crank axis, across their force, "
                f"{_placed(across, engine, total)}; the placement nearest to their starting "
                f"positions would put {crowded})",
                True,
            )
    if len(active) == 1:
        alone = group[active[0]]
        return _Placement(
            group,
            f"one shaft (at {alone.speed_ratio:+d}) would cancel the roll only with its axis at "
            f"{_mm(nearest[active[0]])}, which puts {crowded}; it stays at {_mm(alone)}",
            False,
        )
    return _Placement(
        group, f"cancelling the roll would put {crowded}; the shafts stay where they were", False
    )


def _nearest_roll_free(
    group: tuple[BalanceShaft, ...],
    free: Sequence[tuple[int, str]],
    engine: complex,
    w2: float,
    scale: float,
    clearance: float,
) -> tuple[BalanceShaft, ...] | None:
    """The group with its ``free`` coordinates moved the least (least squares) so that the
    roll vanishes; None when they cannot make it vanish."""
    need = -(engine + sum((_shaft_roll(shaft, w2) for shaft in group), 0j))
    columns = [_roll_gradient(group[j], w2, c) for j, c in free]
    a = np.array([[c.real for c in columns], [c.imag for c in columns]])
    rhs = np.array([need.real, need.imag])
    step, *_ = np.linalg.lstsq(a, rhs, rcond=None)
    if np.linalg.norm(a @ step - rhs) > _ROLL_TOL * scale:
        return None
    moved = list(group)
    for (j, c), delta in zip(free, step, strict=True):
        shaft = moved[j]
        changes: dict[str, float | str] = {c: _clean(getattr(shaft, c) + float(delta), clearance)}
        if abs(delta) > 1e-9 * clearance or getattr(shaft, f"{c}_from") == "cancel-roll":
            changes[f"{c}_from"] = "cancel-roll"
        moved[j] = replace(shaft, **changes)  # type: ignore[arg-type]
    return tuple(moved)


def _crowding(
    group: tuple[BalanceShaft, ...], active: Sequence[int], clearance: float
) -> str | None:
    """What is too close among the axes the proposal places (None: nothing), in words."""
    limit = clearance * (1.0 - 1e-9)
    placed = [j for j in active if (group[j].x_from, group[j].y_from) != ("layout", "layout")]
    for j in placed:
        distance = abs(complex(group[j].y, group[j].x))
        if distance < limit:
            where = (
                "on the crank axis"
                if distance < 1e-6 * clearance
                else f"{distance * 1e3:.3g} mm from the crank axis"
            )
            return (
                f"the shaft at {group[j].speed_ratio:+d} {where}, within the "
                f"{clearance * 1e3:.3g} mm kept free for the crank"
            )
    if len(active) == 2 and placed:
        a, b = (group[j] for j in active)
        gap = abs(complex(a.y - b.y, a.x - b.x))
        if gap < limit:
            return f"the two shafts {gap * 1e3:.3g} mm apart, closer than {clearance * 1e3:.3g} mm"
    return None


def _across_force(
    group: tuple[BalanceShaft, ...], w2: float, clearance: float
) -> tuple[BalanceShaft, ...]:
    r"""A pair placed on either side of the crank axis, across the line of its force.

    The pair's force :math:`P_+ e^{\mathrm{i}k\theta} + P_- e^{-\mathrm{i}k\theta}` is
    largest along :math:`u = e^{\mathrm{i}(\arg P_+ + \arg P_-)/2}`; the axes go to
    :math:`\pm\sqrt2\,c\,v` with :math:`v = \mathrm{i}u` (the forward shaft on the lower
    side, or on the :math:`-x` side when the force is vertical), :math:`\sqrt2\,c` from the
    crank axis.  For a force along a line this alone puts no roll on the block.
    """
    forward = 0 if group[0].speed_ratio > 0 else 1
    backward = 1 - forward
    gamma = 0.5 * (
        cmath.phase(_shaft_force(group[forward], w2))
        + cmath.phase(_shaft_force(group[backward], w2))
    )
    v = 1j * cmath.exp(1j * gamma)
    if v.real > 1e-9 or (abs(v.real) <= 1e-9 and v.imag > 0):
        v = -v
    distance = math.sqrt(2.0) * clearance
    out = list(group)
    for j, p in ((forward, distance * v), (backward, -distance * v)):
        out[j] = replace(
            group[j],
            x=_clean(p.imag, clearance),
            y=_clean(p.real, clearance),
            x_from="cancel-roll",
            y_from="cancel-roll",
        )
    return tuple(out)


def _placed(group: tuple[BalanceShaft, ...], engine: complex, before: complex) -> str:
    """The note of a placement: where the shafts went, and the rolls it cancels (with the
    closing parenthesis left to the caller)."""
    where = "; ".join(f"{s.speed_ratio:+d} at {_mm(s)}" for s in group)
    return (
        f"to cancel the roll: {where} (roll {abs(before):.4g} N m with the shafts at their "
        f"starting positions, {abs(engine):.4g} N m from the engine alone"
    )


def _beyond_reach_notes(shafts: Sequence[BalanceShaft], reach: float) -> dict[int, str]:
    """A note for every order whose roll placement puts a shaft farther from the crank axis
    than the crank train reaches (crank radius + conrod length [m]): the roll is cancelled on
    paper, but a crankcase seldom has room there."""
    out: dict[int, str] = {}
    for s in shafts:
        distance = abs(complex(s.y, s.x))
        if "cancel-roll" in (s.x_from, s.y_from) and distance > reach:
            k = abs(s.speed_ratio)
            text = (
                f"the shaft at {s.speed_ratio:+d} is {distance * 1e3:.4g} mm from the crank "
                f"axis, beyond the crank train's reach (crank radius + conrod length = "
                f"{reach * 1e3:.4g} mm): check that the crankcase has room for it, or give "
                "the shafts' positions in the layout (balance: shafts:)"
            )
            out[k] = f"{out[k]}; {text}" if k in out else text
    return out


def _roll_increase_notes(
    shafts: Sequence[BalanceShaft],
    roll: dict[int, complex],
    w2: float,
    clearance: float,
    cancel_roll: bool,
    *,
    with_gas: bool,
) -> dict[int, str]:
    """A note for every order whose roll the shafts make larger than the engine's own."""
    out = {}
    for k in sorted({abs(s.speed_ratio) for s in shafts}):
        if k not in roll:
            continue
        group = tuple(s for s in shafts if abs(s.speed_ratio) == k)
        engine = roll[k]
        total = engine + sum((_shaft_roll(s, w2) for s in group), 0j)
        if abs(total) <= abs(engine) + _ROLL_TOL * _roll_scale(group, engine, w2, clearance):
            continue
        text = (
            f"order {k}: the balance shafts raise the roll from {abs(engine):.4g} to "
            f"{abs(total):.4g} N m"
        )
        if with_gas:
            text += " (inertia forces; the gas torque is not in these two figures)"
        if not cancel_roll and _placement(group, engine, w2, clearance).cancelled:
            text += "; the setting cancel_roll places them so that it is cancelled"
        out[k] = text
    return out
