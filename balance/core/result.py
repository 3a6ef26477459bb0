"""What a user asks for (:class:`Request`) and what the core answers (:class:`Result`).

A :class:`Result` holds complex phasors (forward and backward per order), the proposal
with its residual, the gas torque when the engine has a ``gas:`` section, and every
reference a view needs to normalise (so that no view recovers a reference by dividing two
numbers).  It holds exactly what the request asked for: a quantity not asked for is None.
Every view (:mod:`balance.views`) reads it; polar form exists only where a view prints.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:  # pragma: no cover (annotations only: each part loads when computed)
    from balance.core.balancing import Proposal
    from balance.core.bearings import Bearings
    from balance.core.engine import Engine
    from balance.core.mounts import MountsResult
    from balance.core.plausibility import PlausibilityWarning
    from balance.core.torque import TorqueResult

__all__ = ["Balanced", "Phasors", "Request", "Result"]

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Phasors:
    """Complex phasors of one analysis (SI: N, N m).

    ``*_forward`` and ``*_backward`` have one entry per order; the rotating phasors are
    scalars (order 1, forward only); ``roll`` has one entry per order.  An engine with link
    rods also has ``link_pin_forward`` and ``link_pin_backward``, shape (cylinders, orders):
    each link rod's link-pin mass moving relative to its crank pin (included in the force
    and moment phasors; zero rows for the other cylinders) [N]; None otherwise.
    """

    orders: NDArray[np.intp]
    force_forward: ComplexArray
    force_backward: ComplexArray
    moment_forward: ComplexArray
    moment_backward: ComplexArray
    rotating_force: complex
    rotating_moment: complex
    roll: ComplexArray
    acceleration_coefficients: ComplexArray
    model: str
    terms: int
    reference_force: float
    reference_z: float
    samples: int = 0
    error_bound: float = float("nan")
    link_pin_forward: ComplexArray | None = None
    link_pin_backward: ComplexArray | None = None


@dataclass(frozen=True)
class Balanced:
    """A balancing proposal and the residual with every proposed mass added.

    The residual phasors are per order of the analysis: reciprocating + rotating +
    counterweights + shafts (N, N m); ``roll`` is the engine's roll plus the shafts'.
    """

    proposal: Proposal
    force_forward: ComplexArray
    force_backward: ComplexArray
    moment_forward: ComplexArray
    moment_backward: ComplexArray
    roll: ComplexArray


@dataclass(frozen=True)
class Request:
    """What to compute.

    Attributes
    ----------
    orders : tuple of int
        The orders, ascending.
    model : {'exact', 'series', 'textbook', 'time'}
        Piston acceleration model.
    terms : int
        Binomial terms of the ``series`` model.
    samples : int or None
        Crank angles per revolution of the ``time`` model (None: the default).
    tolerance : float or None
        Instead of ``model``: the largest coefficient error allowed; the cheapest model
        that meets it is used.
    speed : float or None
        Crank speed [rad/s] instead of the engine's.
    moments, roll, proposal, torque : bool
        Whether to compute the free moments, the roll, a balancing proposal with its
        residual (needs moments and roll), and the gas torque (engines with gas only).
    cancel : tuple of int or None
        Orders the proposal cancels (None: the engine's ``balance:`` section, else 1, 2).
    strategy, balance_factor, counterweight_radius
        Proposal settings (None: the engine's ``balance:`` section, else the defaults).
    cancel_roll : bool
        Place same-order shaft pairs so that they also cancel that order's roll.
    mounts : bool
        Compute the response of the engine on its mounts (needs :attr:`Engine.mounts`).
    mounts_with_proposal : bool
        Load the mounts with the residual (the proposal added) instead of the bare engine.
    bearings : bool
        Compute the crank-pin and main-bearing loads and the internal moments
        (:mod:`balance.core.bearings`), without and with the proposed counterweights.
    cylinders : bool
        Compute each cylinder's actual stroke and top-dead-centre crank angle
        (:func:`balance.core.links.dead_centres`).
    """

    orders: tuple[int, ...] = (1, 2, 3, 4, 5, 6, 7, 8)
    model: str = "exact"
    terms: int = 3
    samples: int | None = None
    tolerance: float | None = None
    speed: float | None = None
    moments: bool = True
    roll: bool = True
    proposal: bool = True
    torque: bool = True
    cancel: tuple[int, ...] | None = None
    strategy: str | None = None
    balance_factor: float | None = None
    counterweight_radius: float | None = None
    cancel_roll: bool = False
    mounts: bool = False
    mounts_with_proposal: bool = False
    bearings: bool = False
    cylinders: bool = True

    @classmethod
    def of(cls, orders: Iterable[int], **settings: object) -> Request:
        """A request for these orders (sorted, each once) and settings."""
        return cls(orders=tuple(sorted({int(k) for k in orders})), **settings)  # type: ignore[arg-type]


@dataclass(frozen=True)
class Result:
    """The answer to a :class:`Request` (SI units: N, N m, rad/s, m).

    Attributes
    ----------
    engine : Engine
        The engine analysed (at the request's speed).
    request : Request
        What was asked, with ``model``/``terms``/``samples`` as actually used.
    phasors : Phasors
        Free force, moment, rotating and roll phasors per order
        (:class:`Phasors`); moments and roll NaN when not asked.
    balanced : Balanced or None
        The proposal and the residual phasors (:class:`Balanced`).
    torque : TorqueResult or None
        Forces and torque over the cycle with gas forces (:mod:`balance.core.torque`).
    roll_orders : ndarray
        Orders of :attr:`roll` (halves for a four-stroke with gas).
    roll : ndarray of complex or None
        Roll phasors on the block per roll order, with gas forces when given [N m].
    residual_roll : ndarray of complex or None
        :attr:`roll` with the proposed shafts' roll added [N m].
    reference_force : float
        :math:`F_1 = m_{rec} r \\omega^2` with engine means [N].
    pitch : float
        Cylinder pitch [m] (NaN when undefined).
    reference_moment : float
        :math:`F_1 a` [N m] (NaN without a pitch).
    reference_roll : float
        :math:`m_{rec} r^2 \\omega^2` with engine means [N m].
    mounts : MountsResult or None
        Modes and response of the engine on its mounts (:mod:`balance.core.mounts`), when
        asked.
    bearings : Bearings or None
        Crank-pin and main-bearing loads and internal moments, without and with the
        proposed counterweights (:class:`balance.core.bearings.Bearings`), when asked.
    warnings : tuple of PlausibilityWarning
        Inputs far outside piston-engine practice (:mod:`balance.core.plausibility`);
        they change no number.
    cylinder_stroke : ndarray or None
        Each cylinder's piston travel between its dead centres [m], when asked.
    cylinder_tdc : ndarray or None
        Crank angle :math:`\\theta` in :math:`[0, 2\\pi)` at which each piston is farthest
        from the crank axis [rad], when asked.
    """

    engine: Engine
    request: Request
    phasors: Phasors
    balanced: Balanced | None
    torque: TorqueResult | None
    roll_orders: FloatArray
    roll: ComplexArray | None
    residual_roll: ComplexArray | None
    reference_force: float
    pitch: float
    reference_moment: float
    reference_roll: float
    mounts: MountsResult | None = None
    bearings: Bearings | None = None
    warnings: tuple[PlausibilityWarning, ...] = ()
    cylinder_stroke: FloatArray | None = None
    cylinder_tdc: FloatArray | None = None

    @property
    def orders(self) -> NDArray[np.intp]:
        """The orders of the force and moment phasors."""
        return np.asarray(self.request.orders, dtype=np.intp)

    @property
    def speed(self) -> float:
        """Crank speed [rad/s]."""
        return self.engine.speed

    @property
    def has_moments(self) -> bool:
        """Whether the moments were computed."""
        return self.request.moments

    @property
    def has_roll(self) -> bool:
        """Whether the roll was computed."""
        return self.roll is not None
