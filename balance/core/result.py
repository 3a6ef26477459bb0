"""What a user asks for (:class:`Request`) and what the core answers (:class:`Result`).

A :class:`Result` holds the free forces, moments and roll as one
:class:`~balance.core.phasors.Phasors` bundle, the model rung that gave them, every
reference a view needs to normalise (so that no view recovers a reference by dividing two
numbers), and one *part* per section the request asked for (the proposal, the gas torque,
the bearing loads…: :mod:`balance.core.sections`).  It holds exactly what the request
asked for.  Every view (:mod:`balance.views`) reads it; polar form exists only where a
view prints.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from balance.core.phasors import Phasors
from balance.core.sections import default_sections

if TYPE_CHECKING:  # pragma: no cover (annotations only)
    from balance.core.engine import Engine
    from balance.core.plausibility import PlausibilityWarning

__all__ = ["FreeForces", "ModelRung", "Request", "Result"]

ComplexArray = NDArray[np.complex128]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ModelRung:
    """The rung of the speed/accuracy ladder that computed the phasors.

    Attributes
    ----------
    name : {'exact', 'series', 'textbook', 'time'}
        The piston acceleration model (docs/theory.md, "Fourier coefficients of the
        acceleration"; each model's error and cost: docs/benchmarks.md).
    terms : int
        Binomial terms of the ``series`` model (0 for ``time``).
    samples : int
        Crank angles per revolution of the ``time`` model (0 for the others).
    error_bound : float
        Bound on the error of the normalised acceleration coefficients (force error per
        :math:`m_{rec} r \\omega^2`) of this rung (:mod:`balance.core.accuracy`).
    """

    name: str
    terms: int
    samples: int
    error_bound: float


@dataclass(frozen=True)
class FreeForces:
    """The free forces, moments and roll of one engine at its speed (SI: N, N m).

    Attributes
    ----------
    phasors : Phasors
        Reciprocating force and moment per order, the rotating masses' order-1 phasors
        and the roll (inertia only, whole orders); the moments and the roll None when not
        asked.
    coefficients : ndarray of complex
        :math:`G_k` of each cylinder's :math:`-s''/r`, shape (cylinders, orders) (a link
        piston's in its own crank angle).
    model : ModelRung
        The model rung used, with its error bound.
    link_pins : Phasors or None
        Engines with link rods: each cylinder's link pin moving relative to its crank pin
        (included in :attr:`phasors`), force only, shape (cylinders, orders) [N]; None
        otherwise.
    shafts : GearedParts or None
        An engine with several crankshafts: each one's force, own roll and torque, the
        moment about ``z`` and the gear couple (:class:`balance.core.geared.GearedParts`);
        None otherwise.
    """

    phasors: Phasors
    coefficients: ComplexArray
    model: ModelRung
    link_pins: Phasors | None = None
    shafts: Any = None


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
    moments, roll : bool
        Whether to compute the free moments and the roll.
    sections : mapping of str to mapping
        The sections to compute (:mod:`balance.core.sections`), each with its options
        (``{"proposal": {"balance_factor": 0.6}, "bearings": {}}``); by default the
        sections that are computed unless turned off.  :func:`balance.io.request.build_request`
        builds it from what a user gives (and what the layout's sections turn on).
    """

    orders: tuple[int, ...] = (1, 2, 3, 4, 5, 6, 7, 8)
    model: str = "exact"
    terms: int = 3
    samples: int | None = None
    tolerance: float | None = None
    speed: float | None = None
    moments: bool = True
    roll: bool = True
    sections: Mapping[str, Mapping[str, Any]] = field(default_factory=default_sections)

    @classmethod
    def of(cls, orders: Iterable[int], **settings: Any) -> Request:
        """A request for these orders (sorted, each once) and settings."""
        return cls(orders=tuple(sorted({int(k) for k in orders})), **settings)

    def wants(self, name: str) -> bool:
        """Whether the request asks for the section ``name``."""
        return name in self.sections

    def options(self, name: str) -> Mapping[str, Any]:
        """The options the request gives the section ``name`` (empty if not asked)."""
        return self.sections.get(name, {})

    def only(self, *names: str) -> Request:
        """The same request with only the sections ``names`` of those it asks for."""
        return self.with_sections(**{name: None for name in self.sections if name not in names})

    def with_sections(self, **sections: Mapping[str, Any] | None) -> Request:
        """The same request with sections added (a mapping of options) or removed (None)."""
        new = dict(self.sections)
        for name, options in sections.items():
            if options is None:
                new.pop(name, None)
            else:
                new[name] = dict(options)
        return Request(
            orders=self.orders,
            model=self.model,
            terms=self.terms,
            samples=self.samples,
            tolerance=self.tolerance,
            speed=self.speed,
            moments=self.moments,
            roll=self.roll,
            sections=new,
        )


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
        Free force, moment, rotating and roll phasors per order (the roll: inertia only,
        whole orders); moments and roll None when not asked.
    coefficients : ndarray of complex
        Acceleration coefficients :math:`G_k` per cylinder and order
        (:attr:`FreeForces.coefficients`).
    model : ModelRung
        The model rung used and its error bound.
    roll_orders : ndarray
        Orders of :attr:`roll` (halves for a four-stroke with gas).
    roll : ndarray of complex or None
        Roll phasors on the block per roll order, with gas forces when the engine has them
        [N m]; None when not asked.
    reference_force : float
        :math:`F_1 = m_{rec} r \\omega^2` with engine means [N].
    pitch : float
        Cylinder pitch [m] (NaN when undefined).
    reference_moment : float
        :math:`F_1 a` [N m] (NaN without a pitch).
    reference_roll : float
        :math:`m_{rec} r^2 \\omega^2` with engine means [N m].
    link_pins : Phasors or None
        Each link pin's motion relative to its crank pin (:attr:`FreeForces.link_pins`).
    parts : mapping of str to object
        One part per section computed, in section order (:mod:`balance.core.sections`).
    warnings : tuple of PlausibilityWarning
        Inputs far outside piston-engine practice (:mod:`balance.core.plausibility`);
        they change no number.
    shafts : GearedParts or None
        An engine with several crankshafts: :attr:`FreeForces.shafts`.
    """

    engine: Engine
    request: Request
    phasors: Phasors
    coefficients: ComplexArray
    model: ModelRung
    roll_orders: FloatArray
    roll: ComplexArray | None
    reference_force: float
    pitch: float
    reference_moment: float
    reference_roll: float
    link_pins: Phasors | None = None
    parts: Mapping[str, Any] = field(default_factory=dict)
    warnings: tuple[PlausibilityWarning, ...] = ()
    shafts: Any = None

    @property
    def orders(self) -> NDArray[np.intp]:
        """The orders of the force and moment phasors."""
        return self.phasors.orders

    @property
    def speed(self) -> float:
        """Crank speed [rad/s]."""
        return self.engine.speed

    @property
    def has_moments(self) -> bool:
        """Whether the moments were computed."""
        return self.phasors.has("moment")

    @property
    def has_roll(self) -> bool:
        """Whether the roll was computed."""
        return self.roll is not None

    def part(self, name: str) -> Any:
        """The part of the section ``name``, or None when it was not computed."""
        return self.parts.get(name)

    def with_part(self, name: str, part: Any, **changes: Any) -> Result:
        """The result with the part of section ``name`` added (and fields changed: the
        gas torque's section changes the roll).

        A copy of the fields at a tenth of ``dataclasses.replace``'s cost (a result has
        no ``__post_init__`` and nothing derived to form again; each section adds one part).
        """
        unknown = changes.keys() - _RESULT_FIELDS
        if unknown:
            raise TypeError(f"Result has no field {', '.join(sorted(unknown))}")
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__, parts={**self.parts, name: part}, **changes)
        return new


#: The names of the fields of a :class:`Result` (what :meth:`Result.with_part` may change).
_RESULT_FIELDS = frozenset(f.name for f in fields(Result))
