r"""Torsional vibration of the crank train, as a section of an analysis.

A layout's ``torsion:`` section describes the crank train as a *mass-elastic table*
(docs/torsion.md): rigid masses on a chain of shaft sections written from the free end
(mass 1, usually the pulley or damper hub) to the driven end (the flywheel, or the load
beyond it), and dampers hung on its masses.  This module holds that table as frozen
dataclasses in SI (:class:`TorsionTrain`), the checks of its values
(:func:`train_problems`) and its plausibility warnings (:func:`torsion_warnings`), and the
analysis (:func:`torsion_analysis`, the section's part :func:`torsion_part`):

- the inertia of each mass as used: a ``crank_inertia`` plus the mean inertia of the moving
  parts of its cylinders (:func:`balance.core.torsion_excitation.moving_parts_inertia`);
- the undamped modes and the relative amplitude (vector) sums of every mode and order;
- the excitation of each cylinder per order
  (:func:`balance.core.torsion_excitation.excitation`);
- the exact steady state of :math:`M\ddot q + C\dot q + (K + i\eta K_s)q = T` for every
  speed and order, in one batched solve (:mod:`balance.core.torsion_dynamics`), and from it
  the free-end angle, each section's torque and nominal shear stress, each damper's power,
  per order and synthesised (half range over the cycle), and the resonances in the speed
  range.

Who checks what
---------------
The layout reader turns the ``torsion:`` section into a :class:`TorsionTrain` and refuses
(exit 2, one line naming file, line and field):

- what only the file shows, which the reader checks itself: a quantity without its unit
  (``inertia`` proposes ``kg m^2``, ``stiffness`` ``N m/rad``, ``damping`` ``N m s/rad``,
  lengths ``mm``), unknown keys, a damper ``at`` naming no mass (names are resolved to
  numbers by the reader, :func:`resolve_mass`);
- every value check of the table, by calling :func:`train_problems` (each problem carries
  the path in the file and the field), which refuses: fewer than two masses; two masses of
  one name; an inertia (mass, crank or ring) that is not positive; both or neither of
  ``inertia`` and ``crank_inertia``; ``crank_inertia`` without ``cylinders`` or with lumped
  masses; a mass other than the last without ``shaft``, or ``shaft`` on the last; a
  section stiffness that is not positive; negative damping (mass, section, damper); a
  negative ``loss_factor``; a diameter that is not positive, a negative bore, a ``bore``
  not below the ``diameter``; a cylinder on two masses, on none, or one that does not
  exist; a damper ``at`` no mass (a number out of range), with a negative stiffness, or
  with neither stiffness nor damping; a four-stroke whose firing TDCs cannot be placed (the
  reader passes the cylinders' ``tdc`` angles, :func:`place_firing_tdc`, and stores the
  angles placed in :attr:`TorsionTrain.firing_tdc` when the engine has no ``gas:``
  section).

The command line checks its options with :func:`order_problem` (half orders on a
two-stroke, an order not a multiple of 0.5) and :func:`speed_problem` (a speed that is not
positive), and refuses ``--torsion`` on a layout without a ``torsion:`` section.
:func:`torsion_part` repeats the value checks (an :class:`~balance.core.errors.InputError`
naming the field), so that a train built in Python is checked too.

The warnings are pure functions of the train (:func:`torsion_warnings`, each a
:class:`~balance.core.plausibility.PlausibilityWarning`), computed by the analysis and
added to the result's warnings: no damping at all (the response is then not computed),
the cylinders not in the order of their ``z`` along the table, mass 1 the heaviest, a
``loss_factor`` above 0.2, a tuned damper far from every natural frequency.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.catalogue import Output
from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.phasors import cancel_to_zero
from balance.core.plausibility import PlausibilityWarning
from balance.core.torsion_dynamics import (
    TrainMatrices,
    assemble,
    coupling_power,
    half_range,
    harmonic_response,
    normal_modes,
    vector_sums,
)
from balance.core.torsion_excitation import (
    Excitation,
    default_orders,
    default_speeds,
    excitation,
    harmonic_numbers,
    major_orders,
    moving_parts_inertia,
    order_problem,
    place_firing_tdc,
    speed_problem,
)

__all__ = [
    "MAX_LOSS_FACTOR",
    "OUTPUTS",
    "TUNING_BAND",
    "WARNING_RULES",
    "Resonance",
    "Shaft",
    "TorsionDamper",
    "TorsionMass",
    "TorsionResult",
    "TorsionTrain",
    "TrainProblem",
    "default_orders",
    "default_speeds",
    "mass_inertias",
    "order_problem",
    "place_firing_tdc",
    "resolve_mass",
    "speed_problem",
    "torsion_analysis",
    "torsion_part",
    "torsion_warnings",
    "train_matrices",
    "train_problems",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Loss factor above which a warning is given: rubber couplings reach about 0.1-0.2;
#: steel shafts lie far below 0.01 (Nestorides 1958).
MAX_LOSS_FACTOR = 0.2
#: A tuned damper whose own frequency lies more than this share away from every natural
#: frequency of the train without it is warned about.
TUNING_BAND = 0.5
#: The rules of the torsion warnings, in the order they are reported.
WARNING_RULES = (
    "torsion_damping",
    "torsion_order",
    "torsion_free_end",
    "torsion_loss_factor",
    "torsion_tuning",
)


# --------------------------------------------------------------------------- the train


@dataclass(frozen=True)
class Shaft:
    """A shaft section, from its mass to the next one (SI).

    Attributes
    ----------
    stiffness : float
        Torsional stiffness [N m/rad], above zero.
    damping : float
        Viscous damping in parallel [N m s/rad].
    diameter : float or None
        Outer diameter of the plain shaft [m], for the nominal shear stress; None: no stress.
    bore : float
        Inner diameter [m]; 0 for a solid shaft.
    """

    stiffness: float
    damping: float = 0.0
    diameter: float | None = None
    bore: float = 0.0

    @property
    def stress_factor(self) -> float:
        r"""Nominal shear stress per torque, :math:`16 d / (\pi (d^4 - d_i^4))` [Pa/(N m)];
        NaN without a diameter."""
        if self.diameter is None:
            return math.nan
        d, di = self.diameter, self.bore
        return 16.0 * d / (math.pi * (d**4 - di**4))


@dataclass(frozen=True)
class TorsionMass:
    """One station of the mass-elastic table (SI).

    Attributes
    ----------
    name : str
        Its name (unique in the table).
    inertia : float or None
        The whole station's inertia [kg m^2] (nothing is added).
    crank_inertia : float or None
        The crankshaft's own throw about its axis [kg m^2]; the mean inertia of the moving
        parts of its cylinders is added.  Exactly one of ``inertia`` and ``crank_inertia``.
    cylinders : tuple of int
        The cylinders (1-based) whose crank pin is on this mass.
    damping : float
        Absolute viscous damping to the block [N m s/rad].
    shaft : Shaft or None
        The section to the next mass; None on the last mass only.
    """

    name: str
    inertia: float | None = None
    crank_inertia: float | None = None
    cylinders: tuple[int, ...] = ()
    damping: float = 0.0
    shaft: Shaft | None = None


@dataclass(frozen=True)
class TorsionDamper:
    """A damper: a ring hung on a mass (its hub or housing is part of that mass) (SI).

    Attributes
    ----------
    at : int
        The mass (1-based) it is hung on.
    inertia : float
        The ring's inertia [kg m^2].
    stiffness : float
        The coupling's stiffness [N m/rad]: 0 for a viscous (untuned) damper, above 0 for
        a tuned (rubber) one.
    damping : float
        The coupling's viscous damping [N m s/rad].
    """

    at: int
    inertia: float
    stiffness: float = 0.0
    damping: float = 0.0

    @property
    def kind(self) -> str:
        """``"tuned"`` with a coupling stiffness, ``"viscous"`` without."""
        return "tuned" if self.stiffness > 0.0 else "viscous"

    @property
    def own_frequency(self) -> float:
        r"""The ring's frequency on its coupling, hub held, :math:`\sqrt{k/J}/2\pi` [Hz]
        (0 for a viscous damper)."""
        return math.sqrt(max(self.stiffness, 0.0) / self.inertia) / (2.0 * math.pi)


@dataclass(frozen=True)
class TorsionTrain:
    """The ``torsion:`` section: the mass-elastic table of the crank train (SI).

    Attributes
    ----------
    masses : tuple of TorsionMass
        From the free end (mass 1) to the driven end.
    dampers : tuple of TorsionDamper
        The dampers, in the order given.
    loss_factor : float
        Hysteretic loss factor :math:`\\eta` of every shaft section [1].
    firing_tdc : tuple of float or None
        Each cylinder's firing TDC [deg], placed by the reader for an engine without a
        ``gas:`` section from the cylinders' ``tdc`` angles (:func:`place_firing_tdc`);
        None: the gas section's, or placed from the firing order.
    """

    masses: tuple[TorsionMass, ...]
    dampers: tuple[TorsionDamper, ...] = ()
    loss_factor: float = 0.0
    firing_tdc: tuple[float, ...] | None = None

    @property
    def n_masses(self) -> int:
        """Number of masses."""
        return len(self.masses)

    @property
    def sections(self) -> tuple[Shaft, ...]:
        """The shaft sections, section j between masses j and j + 1 (1-based)."""
        return tuple(m.shaft for m in self.masses[:-1] if m.shaft is not None)

    @property
    def damped(self) -> bool:
        """Whether anything damps the train (mass, section or damper damping, or a loss
        factor)."""
        return (
            self.loss_factor > 0.0
            or any(m.damping > 0.0 for m in self.masses)
            or any(s.damping > 0.0 for s in self.sections)
            or any(d.damping > 0.0 for d in self.dampers)
        )

    def cylinder_masses(self, n_cylinders: int) -> NDArray[np.intp]:
        """The mass (0-based) each cylinder is on (-1 for a cylinder on none)."""
        out = np.full(n_cylinders, -1, dtype=np.intp)
        for i, mass in enumerate(self.masses):
            for c in mass.cylinders:
                if 1 <= c <= n_cylinders:
                    out[c - 1] = i
        return out


def resolve_mass(train_masses: Sequence[TorsionMass], at: int | str) -> int | None:
    """The number (1-based) of the mass a damper's ``at`` names: a number in range, or a
    mass's name; None when it names no mass."""
    if isinstance(at, bool):
        return None
    if isinstance(at, int):
        return at if 1 <= at <= len(train_masses) else None
    for i, mass in enumerate(train_masses):
        if mass.name == at:
            return i + 1
    return None


# --------------------------------------------------------------------------- checks


@dataclass(frozen=True)
class TrainProblem:
    """A value of the ``torsion:`` section that cannot be analysed.

    Attributes
    ----------
    path : tuple of str and int
        Where it is in the layout file (keys, and 0-based list indices), for the reader's
        line and column.
    field : str
        The field as messages name it (``torsion.masses[3].shaft.stiffness``, 1-based).
    message : str
        What is wrong.
    valid : str or None
        What would be valid instead.
    """

    path: tuple[str | int, ...]
    field: str
    message: str
    valid: str | None = None

    def one_line(self) -> str:
        """``field: message; valid`` in one line."""
        text = f"{self.field}: {self.message}"
        return f"{text}; {self.valid}" if self.valid else text


def _mass_field(i: int, *keys: str) -> tuple[tuple[str | int, ...], str]:
    path: tuple[str | int, ...] = ("torsion", "masses", i, *keys)
    return path, ".".join([f"torsion.masses[{i + 1}]", *keys])


def _damper_field(r: int, *keys: str) -> tuple[tuple[str | int, ...], str]:
    path: tuple[str | int, ...] = ("torsion", "dampers", r, *keys)
    return path, ".".join([f"torsion.dampers[{r + 1}]", *keys])


def _positive(value: float | None) -> bool:
    return value is not None and math.isfinite(value) and value > 0.0


def _not_negative(value: float) -> bool:
    return math.isfinite(value) and value >= 0.0


def _by_part_cylinders(engine: Engine) -> NDArray[np.bool_]:
    """Which cylinders have their masses by part, with no lumped override (their moving
    parts' inertia is defined: a lumped ``rotating`` mass holds the crank's own unbalance
    too)."""
    parts = engine.mass_parts
    if parts is None:
        return np.zeros(engine.n_cylinders, dtype=bool)
    return np.asarray(np.isnan(parts.reciprocating_given) & np.isnan(parts.rotating_given))


def _by_part(engine: Engine, cylinders: Sequence[int]) -> bool:
    """Whether these cylinders' masses are all given by part."""
    idx = [c - 1 for c in cylinders if 1 <= c <= engine.n_cylinders]
    return bool(np.all(_by_part_cylinders(engine)[idx]))


def _mass_problems(engine: Engine | None, train: TorsionTrain) -> list[TrainProblem]:
    out: list[TrainProblem] = []
    n = train.n_masses
    seen: dict[str, int] = {}
    for i, mass in enumerate(train.masses):
        if mass.name in seen:
            path, field = _mass_field(i, "name")
            out.append(
                TrainProblem(
                    path,
                    field,
                    f"two masses are named {mass.name!r} (masses {seen[mass.name] + 1} "
                    f"and {i + 1})",
                    "give every mass its own name",
                )
            )
        seen.setdefault(mass.name, i)
        given = [k for k in ("inertia", "crank_inertia") if getattr(mass, k) is not None]
        if len(given) != 1:
            path, field = _mass_field(i)
            out.append(
                TrainProblem(
                    path,
                    field,
                    "both inertia and crank_inertia given"
                    if given
                    else "neither inertia nor crank_inertia given",
                    "give exactly one: 'inertia' (the whole station) or 'crank_inertia' "
                    "(the throw; the moving parts of its cylinders are added)",
                )
            )
        for key in given:
            if not _positive(getattr(mass, key)):
                path, field = _mass_field(i, key)
                out.append(TrainProblem(path, field, "an inertia must be above zero"))
        if mass.crank_inertia is not None:
            path, field = _mass_field(i, "crank_inertia")
            if not mass.cylinders:
                out.append(
                    TrainProblem(
                        path,
                        field,
                        "crank_inertia needs the cylinders on this throw",
                        "add 'cylinders: [...]', or give the whole station as 'inertia'",
                    )
                )
            elif engine is not None and not _by_part(engine, mass.cylinders):
                out.append(
                    TrainProblem(
                        path,
                        field,
                        "crank_inertia adds the moving parts of its cylinders, which needs "
                        "masses by part: lumped rotating masses include the crank's own "
                        "unbalance, which belongs to crank_inertia",
                        "give masses by part (piston_group, conrod, conrod_cg_to_big_end), "
                        "or the station's whole inertia as 'inertia'",
                    )
                )
        if not _not_negative(mass.damping):
            path, field = _mass_field(i, "damping")
            out.append(TrainProblem(path, field, "damping must not be negative"))
        out += _shaft_problems(i, n, mass.shaft)
    return out


def _shaft_problems(i: int, n: int, shaft: Shaft | None) -> list[TrainProblem]:
    out: list[TrainProblem] = []
    if shaft is None:
        if i < n - 1:
            path, field = _mass_field(i)
            out.append(
                TrainProblem(
                    path,
                    field,
                    "a mass other than the last needs a shaft: without it the train falls apart",
                    "add 'shaft: {stiffness: ... N m/rad}' to the next mass",
                )
            )
        return out
    if i == n - 1:
        path, field = _mass_field(i, "shaft")
        return [
            TrainProblem(
                path,
                field,
                "the last mass has no shaft: nothing follows it",
                "remove it, or add the mass it leads to",
            )
        ]
    if not _positive(shaft.stiffness):
        path, field = _mass_field(i, "shaft", "stiffness")
        out.append(
            TrainProblem(
                path,
                field,
                "a shaft section needs a positive stiffness: zero would split the train in two",
            )
        )
    if not _not_negative(shaft.damping):
        path, field = _mass_field(i, "shaft", "damping")
        out.append(TrainProblem(path, field, "damping must not be negative"))
    if shaft.diameter is not None and not _positive(shaft.diameter):
        path, field = _mass_field(i, "shaft", "diameter")
        out.append(TrainProblem(path, field, "a diameter must be above zero"))
    if not _not_negative(shaft.bore):
        path, field = _mass_field(i, "shaft", "bore")
        out.append(TrainProblem(path, field, "a bore must not be negative"))
    elif shaft.diameter is not None and shaft.bore >= shaft.diameter > 0:
        path, field = _mass_field(i, "shaft", "bore")
        out.append(
            TrainProblem(
                path,
                field,
                f"bore {shaft.bore * 1e3:g} mm is not below the diameter "
                f"{shaft.diameter * 1e3:g} mm",
                "the bore is the inner diameter of a hollow shaft",
            )
        )
    return out


def _cylinder_problems(engine: Engine, train: TorsionTrain) -> list[TrainProblem]:
    out: list[TrainProblem] = []
    n_cyl = engine.n_cylinders
    on: dict[int, int] = {}
    for i, mass in enumerate(train.masses):
        for c in mass.cylinders:
            path, field = _mass_field(i, "cylinders")
            if not 1 <= c <= n_cyl:
                out.append(
                    TrainProblem(
                        path,
                        field,
                        f"there is no cylinder {c}",
                        f"the cylinders are numbered 1 to {n_cyl} in file order",
                    )
                )
            elif c in on:
                out.append(
                    TrainProblem(
                        path,
                        field,
                        f"cylinder {c} is on two masses ({on[c] + 1} and {i + 1})",
                        "every cylinder's crank pin is on exactly one mass",
                    )
                )
            else:
                on[c] = i
    missing = [c for c in range(1, n_cyl + 1) if c not in on]
    if missing and train.n_masses:
        out.append(
            TrainProblem(
                ("torsion", "masses"),
                "torsion.masses",
                f"cylinder{'s' if len(missing) > 1 else ''} "
                f"{', '.join(map(str, missing))} on no mass",
                "list every cylinder in the 'cylinders' of the mass its crank pin is on",
            )
        )
    return out


def _damper_problems(train: TorsionTrain) -> list[TrainProblem]:
    out: list[TrainProblem] = []
    for r, damper in enumerate(train.dampers):
        if not 1 <= damper.at <= train.n_masses:
            path, field = _damper_field(r, "at")
            out.append(
                TrainProblem(
                    path,
                    field,
                    f"mass {damper.at} does not exist",
                    f"give a mass number (1 to {train.n_masses}) or name",
                )
            )
        if not _positive(damper.inertia):
            path, field = _damper_field(r, "inertia")
            out.append(TrainProblem(path, field, "an inertia must be above zero"))
        for key in ("stiffness", "damping"):
            if not _not_negative(getattr(damper, key)):
                path, field = _damper_field(r, key)
                out.append(TrainProblem(path, field, f"{key} must not be negative"))
        if damper.stiffness == 0.0 and damper.damping == 0.0:
            path, field = _damper_field(r)
            out.append(
                TrainProblem(
                    path,
                    field,
                    "a damper with neither stiffness nor damping: its ring is not connected",
                    "give 'damping' (a viscous damper) and, for a tuned one, 'stiffness'",
                )
            )
    return out


def train_problems(
    train: TorsionTrain,
    engine: Engine | None = None,
    tdc_given: list[float | None] | None = None,
) -> tuple[TrainProblem, ...]:
    """Every value of a torsion train that cannot be analysed (see the module notes).

    Parameters
    ----------
    train : TorsionTrain
        The table, in SI.
    engine : Engine, optional
        The engine it belongs to: the cylinders, their masses by part and the firing TDCs
        are checked against it (only the table's own values without it).
    tdc_given : list of float or None, optional
        Each cylinder's ``tdc`` as written in the layout [deg] (for the firing TDCs of a
        four-stroke without a firing order).

    Returns
    -------
    tuple of TrainProblem
        In the order of the table; empty when the train can be analysed.
    """
    out: list[TrainProblem] = []
    if train.n_masses < 2:
        out.append(
            TrainProblem(
                ("torsion", "masses"),
                "torsion.masses",
                f"{train.n_masses} mass{'es' if train.n_masses != 1 else ''}: a torsion "
                "train needs at least two masses on a shaft",
            )
        )
    out += _mass_problems(engine, train)
    if not _not_negative(train.loss_factor):
        out.append(
            TrainProblem(
                ("torsion", "loss_factor"),
                "torsion.loss_factor",
                "a loss factor must not be negative",
            )
        )
    out += _damper_problems(train)
    if engine is not None:
        out += _cylinder_problems(engine, train)
        if train.firing_tdc is None:
            placed = place_firing_tdc(engine, tdc_given)
            if isinstance(placed, str):
                out.append(
                    TrainProblem(
                        ("firing_order",),
                        "firing_order",
                        placed,
                        "add e.g. 'firing_order: [1, 3, 4, 2]' (or give every cylinder 'tdc')",
                    )
                )
        elif len(train.firing_tdc) != engine.n_cylinders:
            out.append(
                TrainProblem(
                    ("torsion",),
                    "torsion",
                    f"{len(train.firing_tdc)} firing TDCs for {engine.n_cylinders} cylinders",
                )
            )
    return tuple(out)


def _check(train: TorsionTrain, engine: Engine) -> None:
    problems = train_problems(train, engine)
    if problems:
        more = len(problems) - 1
        tail = f" (and {more} more problem{'s' if more > 1 else ''})" if more else ""
        raise InputError(f"{engine.name}: {problems[0].one_line()}{tail}")


# --------------------------------------------------------------------------- the model


def mass_inertias(
    engine: Engine, train: TorsionTrain, moving: FloatArray | None = None
) -> FloatArray:
    """Each mass's inertia as used [kg m^2]: ``inertia``, or ``crank_inertia`` plus the mean
    inertia of the moving parts of its cylinders (``moving``, per cylinder; computed by
    :func:`balance.core.torsion_excitation.moving_parts_inertia` when not given)."""
    out = np.zeros(train.n_masses)
    for i, mass in enumerate(train.masses):
        if mass.inertia is not None:
            out[i] = mass.inertia
            continue
        if moving is None:
            moving = moving_parts_inertia(engine)
        assert mass.crank_inertia is not None
        out[i] = mass.crank_inertia + float(sum(moving[c - 1] for c in mass.cylinders))
    return out


def train_matrices(
    train: TorsionTrain, inertias: ArrayLike, dampers: Sequence[int] | None = None
) -> TrainMatrices:
    """The matrices of the train (:func:`balance.core.torsion_dynamics.assemble`) with the
    masses' inertias as used, and the dampers ``dampers`` (0-based; default all)."""
    chosen = [train.dampers[r] for r in (range(len(train.dampers)) if dampers is None else dampers)]
    sections = train.sections
    return assemble(
        inertias,
        [s.stiffness for s in sections],
        [s.damping for s in sections],
        [m.damping for m in train.masses],
        [d.at - 1 for d in chosen],
        [d.inertia for d in chosen],
        [d.stiffness for d in chosen],
        [d.damping for d in chosen],
        train.loss_factor,
    )


@dataclass(frozen=True)
class Resonance:
    """An order meeting a natural frequency inside the speed range.

    Attributes
    ----------
    mode : int
        The mode (1-based).
    order : float
        The order.
    speed : float
        The crank speed at which order times speed is the natural frequency [rad/s].
    vector_sum : float
        The relative amplitude sum of that mode and order.
    free_end : float or None
        Amplitude of that order's free-end angle at that speed [rad]; None undamped.
    section : int or None
        The section (1-based) with the largest torque of that order there.
    section_torque : float or None
        Its torque amplitude [N m].
    """

    mode: int
    order: float
    speed: float
    vector_sum: float
    free_end: float | None = None
    section: int | None = None
    section_torque: float | None = None


@dataclass(frozen=True, eq=False)
class TorsionResult:
    """The ``torsion`` section's part: modes, excitation and response (SI, radians).

    Response arrays are None for an undamped train (unbounded at every resonance).

    Attributes
    ----------
    train : TorsionTrain
        The table analysed.
    cycle : str
        ``"four-stroke"`` or ``"two-stroke"``.
    speeds : ndarray, shape (S,)
        Crank speeds [rad/s].
    orders : ndarray, shape (K,)
        Orders.
    inertias : ndarray, shape (n,)
        Each mass's inertia as used [kg m^2].
    moving_inertia : ndarray, shape (c,)
        Mean inertia of each cylinder's moving parts [kg m^2] (added to a
        ``crank_inertia`` mass); NaN for a cylinder with lumped masses.
    cylinder_mass : ndarray of int, shape (c,)
        The mass (0-based) each cylinder is on.
    excitation : Excitation
        Each cylinder's torque per order.
    frequencies : ndarray, shape (m,)
        Undamped natural frequencies [Hz], ascending.
    shapes : ndarray, shape (m, n + t)
        Mode shapes at the masses and the tuned rings, +1 at mass 1.
    stations : tuple of str
        Names of the shape's entries (the masses, then ``"damper r ring"``).
    vector_sums : ndarray, shape (m, K)
        Relative amplitude sums.
    major : ndarray of bool, shape (K,)
        Major orders (every cylinder in phase).
    resonances : tuple of Resonance
        Every mode and order meeting in the speed range, by speed.
    free_end : ndarray of complex, shape (K, S), or None
        Angle of mass 1 per order [rad]: :math:`\\operatorname{Re}(Q e^{ik\\theta})`.
    free_end_synthesis : ndarray, shape (S,), or None
        Half range of the free-end angle over the cycle [rad].
    section_torque : ndarray of complex, shape (J, K, S), or None
        Elastic torque :math:`k_j(q_j - q_{j+1})` per order [N m].
    section_torque_synthesis : ndarray, shape (J, S), or None
        Its half range over the cycle [N m].
    stress_factor : ndarray, shape (J,)
        Nominal shear stress per torque [Pa/(N m)]; NaN without a diameter.
    damper_power : ndarray, shape (D, K, S), or None
        Mean power dissipated in each damper's coupling per order [W].
    warnings : tuple of PlausibilityWarning
        The torsion warnings (:func:`torsion_warnings`).
    reference_speed : float
        The layout's speed [rad/s], the reference of the inertia excitation.
    """

    train: TorsionTrain
    cycle: str
    speeds: FloatArray
    orders: FloatArray
    inertias: FloatArray
    moving_inertia: FloatArray
    cylinder_mass: NDArray[np.intp]
    excitation: Excitation
    frequencies: FloatArray
    shapes: FloatArray
    stations: tuple[str, ...]
    vector_sums: FloatArray
    major: NDArray[np.bool_]
    resonances: tuple[Resonance, ...]
    free_end: ComplexArray | None
    free_end_synthesis: FloatArray | None
    section_torque: ComplexArray | None
    section_torque_synthesis: FloatArray | None
    stress_factor: FloatArray
    damper_power: FloatArray | None
    warnings: tuple[PlausibilityWarning, ...]
    reference_speed: float

    @property
    def damped(self) -> bool:
        """Whether the response was computed (the train has damping)."""
        return self.free_end is not None

    @property
    def section_stress(self) -> FloatArray | None:
        """Nominal shear stress amplitude per section, order and speed [Pa] (NaN without a
        diameter); None undamped."""
        if self.section_torque is None:
            return None
        return np.asarray(np.abs(self.section_torque) * self.stress_factor[:, None, None])

    @property
    def section_stress_synthesis(self) -> FloatArray | None:
        """Half range of the nominal shear stress per section and speed [Pa]; None
        undamped."""
        if self.section_torque_synthesis is None:
            return None
        return np.asarray(self.section_torque_synthesis * self.stress_factor[:, None])

    @property
    def damper_power_total(self) -> FloatArray | None:
        """Each damper's power summed over the orders, per speed [W]; None undamped."""
        if self.damper_power is None:
            return None
        return np.asarray(np.sum(self.damper_power, axis=1))


def _resonances(
    frequencies: FloatArray, orders: FloatArray, speeds: FloatArray
) -> list[tuple[int, int, float]]:
    """(mode, order index, speed [rad/s]) of every mode and order meeting inside the speed
    range, by speed."""
    low, high = float(np.min(speeds)), float(np.max(speeds))
    meet = 2.0 * math.pi * np.asarray(frequencies)[:, None] / np.asarray(orders)[None, :]
    j, i = np.nonzero((meet >= low) & (meet <= high) & (np.asarray(frequencies) > 0)[:, None])
    found = [(int(a), int(b), float(meet[a, b])) for a, b in zip(j, i, strict=True)]
    found.sort(key=lambda item: (item[2], item[0], item[1]))
    return found


def torsion_analysis(
    engine: Engine,
    train: TorsionTrain,
    speeds: ArrayLike | None = None,
    orders: ArrayLike | None = None,
    *,
    torque: Any = None,
) -> TorsionResult:
    """The torsional vibration of an engine's crank train (docs/torsion.md).

    Parameters
    ----------
    engine : Engine
        The engine, at the reference speed of the inertia excitation.
    train : TorsionTrain
        Its mass-elastic table.
    speeds : array_like, optional
        Crank speeds [rad/s]; default :func:`default_speeds` of the engine's speed.
    orders : array_like, optional
        Orders; default :func:`default_orders` of its cycle.
    torque : TorqueResult, optional
        The engine's gas torque over the cycle, when already computed.

    Returns
    -------
    TorsionResult

    Raises
    ------
    InputError
        For a train that cannot be analysed (:func:`train_problems`), or bad orders or
        speeds.
    """
    _check(train, engine)
    w = default_speeds(engine.speed) if speeds is None else np.asarray(speeds, dtype=np.float64)
    w = np.asarray(w, dtype=np.float64).reshape(-1)
    k = default_orders(engine.cycle) if orders is None else np.asarray(orders, dtype=np.float64)
    k = np.asarray(k, dtype=np.float64).reshape(-1)
    for problem in (speed_problem(w), order_problem(k, engine.cycle)):
        if problem is not None:
            raise InputError(f"{engine.name}: torsion: {problem}")
    k = np.sort(k)
    firing = (
        np.asarray(train.firing_tdc, dtype=np.float64)
        if train.firing_tdc is not None
        else np.asarray(place_firing_tdc(engine), dtype=np.float64)
    )
    moving = np.where(_by_part_cylinders(engine), moving_parts_inertia(engine), np.nan)
    inertias = mass_inertias(engine, train, moving)
    matrices = train_matrices(train, inertias)
    frequencies, shapes = normal_modes(matrices)
    cyl_mass = train.cylinder_masses(engine.n_cylinders)
    sums = vector_sums(shapes, cyl_mass, firing, k)
    exc = excitation(engine, k, firing, torque=torque)
    meets = _resonances(frequencies, k, w)
    stress = np.array([s.stress_factor for s in train.sections], dtype=np.float64)
    stations = tuple(m.name for m in train.masses) + tuple(
        f"damper {r + 1} ring" for r, d in enumerate(train.dampers) if d.kind == "tuned"
    )
    response = _response(engine, train, matrices, exc, w, k, meets) if matrices.damped else None
    resonances = tuple(
        Resonance(j + 1, float(k[i]), wr, float(sums[j, i]))
        if response is None
        else Resonance(
            j + 1,
            float(k[i]),
            wr,
            float(sums[j, i]),
            float(np.abs(response["resonance_free_end"][n])),
            int(response["resonance_section"][n]) + 1,
            float(response["resonance_torque"][n]),
        )
        for n, (j, i, wr) in enumerate(meets)
    )
    warnings = torsion_warnings(engine, train, inertias)
    return TorsionResult(
        train=train,
        cycle=engine.cycle,
        speeds=w,
        orders=k,
        inertias=inertias,
        moving_inertia=moving,
        cylinder_mass=cyl_mass,
        excitation=exc,
        frequencies=frequencies,
        shapes=shapes,
        stations=stations,
        vector_sums=sums,
        major=major_orders(firing, k),
        resonances=resonances,
        free_end=None if response is None else response["free_end"],
        free_end_synthesis=None if response is None else response["free_end_synthesis"],
        section_torque=None if response is None else response["torque"],
        section_torque_synthesis=None if response is None else response["torque_synthesis"],
        stress_factor=stress,
        damper_power=None if response is None else response["power"],
        warnings=warnings,
        reference_speed=float(engine.speed),
    )


def _response(
    engine: Engine,
    train: TorsionTrain,
    matrices: TrainMatrices,
    exc: Excitation,
    speeds: FloatArray,
    orders: FloatArray,
    meets: list[tuple[int, int, float]],
) -> dict[str, Any]:
    """The steady state at every speed and order and at every resonance, in one solve."""
    n, size = train.n_masses, matrices.size
    cyl_mass = train.cylinder_masses(engine.n_cylinders)
    to_mass = np.zeros((engine.n_cylinders, size))
    to_mass[np.arange(engine.n_cylinders), cyl_mass] = 1.0
    res_speed = np.array([wr for _, _, wr in meets], dtype=np.float64)
    res_order = np.array([i for _, i, _ in meets], dtype=np.intp)
    all_speeds = np.concatenate([speeds, res_speed])
    per_cylinder = exc.at_crank(all_speeds)  # (S + R, K, c)
    forces = cancel_to_zero(
        per_cylinder @ to_mass, np.abs(per_cylinder) @ to_mass, engine.n_cylinders
    )  # (S + R, K, size): what cancels on a mass by symmetry is exactly zero
    grid_forces = forces[: speeds.size]
    res_forces = forces[speeds.size + np.arange(res_speed.size), res_order]
    grid_freq = np.outer(speeds, orders)  # (S, K)
    res_freq = res_speed * orders[res_order]
    stacked_freq = np.concatenate([grid_freq.reshape(-1), res_freq])
    stacked = np.concatenate([grid_forces.reshape(-1, size), res_forces])
    q = harmonic_response(matrices, stacked_freq, stacked)
    grid = q[: grid_freq.size].reshape(speeds.size, orders.size, size)
    at_res = q[grid_freq.size :]
    k_sec = np.array([s.stiffness for s in train.sections], dtype=np.float64)
    twist = grid[..., : n - 1] - grid[..., 1:n]  # (S, K, J)
    torque = np.transpose(k_sec * twist, (2, 1, 0))  # (J, K, S)
    free_end = grid[..., 0].T  # (K, S)
    harmonics = harmonic_numbers(orders, engine.cycle)
    series = np.concatenate([free_end.T[None], np.transpose(torque, (0, 2, 1))])  # (1+J, S, K)
    synthesis = half_range(series, harmonics)
    free_syn, torque_syn = synthesis[0], synthesis[1:]
    power = np.zeros((len(train.dampers), orders.size, speeds.size))
    for r, damper in enumerate(train.dampers):
        hub, ring = grid[..., damper.at - 1], grid[..., n + r]
        power[r] = coupling_power(grid_freq, damper.damping, hub, ring).T
    res_torque = np.abs(k_sec * (at_res[:, : n - 1] - at_res[:, 1:n]))
    return {
        "free_end": free_end,
        "free_end_synthesis": free_syn,
        "torque": torque,
        "torque_synthesis": torque_syn,
        "power": power,
        "resonance_free_end": at_res[:, 0],
        "resonance_section": np.argmax(res_torque, axis=1) if res_torque.size else [],
        "resonance_torque": np.max(res_torque, axis=1) if res_torque.size else [],
    }


# --------------------------------------------------------------------------- warnings


def _no_damping(train: TorsionTrain) -> PlausibilityWarning | None:
    if train.damped:
        return None
    return PlausibilityWarning(
        "torsion_damping",
        "torsion",
        "the torsion train has no damping at all (no mass, section or damper damping, no "
        "loss_factor): modes and vector sums are given, the response is not, since it is "
        "unbounded at every resonance",
    )


def _z_order(engine: Engine, train: TorsionTrain) -> PlausibilityWarning | None:
    means = [
        float(np.mean([engine.z[c - 1] for c in m.cylinders]))
        for m in train.masses
        if m.cylinders and all(1 <= c <= engine.n_cylinders for c in m.cylinders)
    ]
    steps = np.diff(means)
    if steps.size == 0 or np.all(steps >= 0) or np.all(steps <= 0):
        return None
    return PlausibilityWarning(
        "torsion_order",
        "torsion.masses",
        "the cylinders are not in the order of their z along the torsion table (the mean z "
        f"of the masses' cylinders goes {', '.join(f'{1e3 * z:.4g}' for z in means)} mm): "
        "is a cylinder on the wrong mass?",
    )


def _heaviest_first(train: TorsionTrain, inertias: FloatArray) -> PlausibilityWarning | None:
    if inertias.size < 2 or not inertias[0] > np.max(inertias[1:]):
        return None
    return PlausibilityWarning(
        "torsion_free_end",
        "torsion.masses[1]",
        f"mass 1 ({train.masses[0].name}, {inertias[0]:.4g} kg m^2) is the heaviest of the "
        "torsion table, which is written from the free end (pulley or damper) to the driven "
        "end (flywheel): is it written from the driven end?",
        float(inertias[0] / np.max(inertias[1:])),
    )


def _loss_factor(train: TorsionTrain) -> PlausibilityWarning | None:
    if not train.loss_factor > MAX_LOSS_FACTOR:
        return None
    return PlausibilityWarning(
        "torsion_loss_factor",
        "torsion.loss_factor",
        f"loss_factor {train.loss_factor:.4g} is above {MAX_LOSS_FACTOR:g}: steel shafts lie "
        "far below 0.01 and rubber couplings near 0.1-0.2; was a percentage meant?",
        train.loss_factor / MAX_LOSS_FACTOR,
    )


def _tuning(train: TorsionTrain, inertias: FloatArray) -> list[PlausibilityWarning]:
    out = []
    for r, damper in enumerate(train.dampers):
        if damper.kind != "tuned":
            continue
        others = [s for s in range(len(train.dampers)) if s != r]
        frequencies, _ = normal_modes(train_matrices(train, inertias, others))
        own = damper.own_frequency
        if frequencies.size and np.any(np.abs(own / frequencies - 1.0) <= TUNING_BAND):
            continue
        nearest = (
            float(frequencies[np.argmin(np.abs(frequencies - own))]) if frequencies.size else 0.0
        )
        out.append(
            PlausibilityWarning(
                "torsion_tuning",
                f"torsion.dampers[{r + 1}]",
                f"tuned damper {r + 1}'s own frequency sqrt(k/J)/2pi = {own:.4g} Hz is more "
                f"than {100 * TUNING_BAND:g} % away from every natural frequency of the train "
                f"without it (nearest {nearest:.4g} Hz): check its stiffness and inertia",
                own / nearest if nearest > 0 else math.inf,
            )
        )
    return out


def torsion_warnings(
    engine: Engine,
    train: TorsionTrain,
    inertias: FloatArray | None = None,
) -> tuple[PlausibilityWarning, ...]:
    """The plausibility warnings of a torsion train, in the order of :data:`WARNING_RULES`.

    Parameters
    ----------
    engine : Engine
        The engine (the cylinders' ``z``).
    train : TorsionTrain
        The table (checked: :func:`train_problems` finds nothing).
    inertias : ndarray, optional
        The masses' inertias as used [kg m^2] (:func:`mass_inertias` when not given).

    Returns
    -------
    tuple of PlausibilityWarning
        No damping at all; the cylinders not in the order of their ``z`` along the table;
        mass 1 the heaviest; a loss factor above :data:`MAX_LOSS_FACTOR`; each tuned
        damper whose own frequency is more than :data:`TUNING_BAND` away from every
        natural frequency of the train without it.
    """
    j = mass_inertias(engine, train) if inertias is None else np.asarray(inertias)
    found = [
        _no_damping(train),
        _z_order(engine, train),
        _heaviest_first(train, j),
        _loss_factor(train),
    ]
    return tuple(w for w in found if w is not None) + tuple(_tuning(train, j))


# --------------------------------------------------------------------------- the section


def _speeds_option(engine: Engine, speeds: ArrayLike | str | None) -> FloatArray:
    if speeds is None or (isinstance(speeds, str) and speeds in ("default", "sweep", "figure")):
        return default_speeds(engine.speed)
    if isinstance(speeds, str):
        if speeds == "analysis":
            return np.array([engine.speed])
        raise InputError(f"torsion speeds {speeds!r}: give speeds [rad/s], 'analysis' or 'sweep'")
    return np.asarray(speeds, dtype=np.float64).reshape(-1)


def torsion_part(
    engine: Engine,
    request: Any,
    result: Any,
    *,
    speeds: ArrayLike | str | None = None,
    orders: ArrayLike | None = None,
) -> Any:
    """The ``torsion`` section: the torsional vibration of the crank train
    (:func:`torsion_analysis`) of the layout's ``torsion:`` section.

    Parameters
    ----------
    engine : Engine
        The engine (at the analysis speed, the reference of the inertia excitation), with
        its ``torsion`` section (a :class:`TorsionTrain`).
    request : Request
        Not read (the section's options come as keywords).
    result : Result
        The analysis so far; its ``torque`` part, when there, gives the gas torque.
    speeds : array_like or str, optional
        Crank speeds [rad/s]; default (None, ``"sweep"``): 200 from 20 % to 120 % of the
        engine's speed (:func:`default_speeds`); ``"analysis"``: the engine's speed alone
        (``balance analyse --torsion``).
    orders : array_like, optional
        Orders; default every half order from 0.5 to 12 (four-stroke), 1 to 12
        (two-stroke).

    Returns
    -------
    Result
        With the part ``torsion`` (:class:`TorsionResult`) and its warnings added to the
        result's.

    Raises
    ------
    InputError
        Without a ``torsion`` section, or for one that cannot be analysed.
    """
    del request
    train = engine.section("torsion")
    if train is None:
        raise InputError(
            f"layout '{engine.name}' has no torsion: section, so its torsional vibration "
            "cannot be computed; add one (docs/torsion.md)"
        )
    part = torsion_analysis(
        engine, train, _speeds_option(engine, speeds), orders, torque=result.part("torque")
    )
    return result.with_part("torsion", part, warnings=tuple(result.warnings) + part.warnings)


# --------------------------------------------------------------------------- outputs


def _part(result: Any) -> TorsionResult:
    part: TorsionResult = result.part("torsion")
    return part


def _damped(result: Any) -> bool:
    return _part(result).damped


def _has_dampers(result: Any) -> bool:
    return bool(_part(result).train.dampers)


def _has_gas(result: Any) -> bool:
    return _part(result).excitation.gas is not None


def _rpm(speed: ArrayLike) -> FloatArray:
    from balance.core.catalogue import speed_rpm

    return np.array([speed_rpm(float(w)) for w in np.atleast_1d(speed)], dtype=np.float64)


def _out(
    name: str, dims: tuple[str, ...], units: str, long_name: str, get: Any, when: Any = None
) -> Output:
    return Output(name, dims, units, long_name, lambda r: get(_part(r)), when=when)


def _coord(name: str, units: str, long_name: str, get: Any, when: Any = None) -> Output:
    return Output(name, (name,), units, long_name, lambda r: get(_part(r)), kind="coord", when=when)


def _amplitude_deg(values: ComplexArray | None) -> FloatArray:
    assert values is not None
    return np.asarray(np.degrees(np.abs(values)))


def _phase_deg(values: ComplexArray | None) -> FloatArray:
    from balance.core.phasors import phase_deg

    assert values is not None
    return phase_deg(values)


def _resonance_field(name: str) -> Any:
    def get(t: TorsionResult) -> FloatArray:
        values = [getattr(r, name) for r in t.resonances]
        return np.array([math.nan if v is None else v for v in values], dtype=np.float64)

    return get


_SPEED = "torsion_speed"
_ORDER = "torsion_order"
_SECTION = "torsion_section"
_DAMPER = "torsion_damper"
_MODE = "torsion_mode"
_RES = "torsion_resonance"


#: The outputs of the ``torsion`` section (docs/torsion.md).
OUTPUTS: tuple[Output, ...] = (
    _out(
        "torsion_mass_inertia",
        ("torsion_mass",),
        "kg m2",
        "inertia of each mass as used (crank_inertia plus the mean of the moving parts)",
        lambda t: t.inertias,
    ),
    _out(
        "torsion_mass_name",
        ("torsion_mass",),
        "",
        "name of each mass of the torsion table, free end first",
        lambda t: np.array([m.name for m in t.train.masses]),
    ),
    _out(
        "torsion_moving_inertia",
        ("cylinder",),
        "kg m2",
        "mean inertia of each cylinder's piston group and rod about the crank axis "
        "(NaN with lumped masses)",
        lambda t: t.moving_inertia,
    ),
    _out(
        "torsion_section_stiffness",
        (_SECTION,),
        "N m/rad",
        "torsional stiffness of the shaft section from mass j to mass j + 1",
        lambda t: np.array([s.stiffness for s in t.train.sections]),
    ),
    _out(
        "torsion_section_diameter",
        (_SECTION,),
        "m",
        "outer diameter of the shaft section for the nominal stress (NaN: none given)",
        lambda t: np.array(
            [math.nan if s.diameter is None else s.diameter for s in t.train.sections]
        ),
    ),
    _out(
        "torsion_mode_frequency",
        (_MODE,),
        "Hz",
        "undamped natural frequency of the torsion train (rigid-body mode left out)",
        lambda t: t.frequencies,
    ),
    _out(
        "torsion_mode_shape",
        (_MODE, "torsion_station"),
        "1",
        "mode shape at the masses and the tuned damper rings, +1 at mass 1",
        lambda t: t.shapes,
    ),
    _out(
        "torsion_vector_sum",
        (_MODE, _ORDER),
        "1",
        "relative amplitude (vector) sum |sum_c phi(mass of c) exp(-i k theta_c)|",
        lambda t: t.vector_sums,
    ),
    _out(
        "torsion_major_order",
        (_ORDER,),
        "1",
        "1 where every cylinder's excitation of the order is in phase (a major order)",
        lambda t: t.major.astype(np.int64),
    ),
    _out(
        "torsion_firing_tdc",
        ("cylinder",),
        "deg",
        "crank angle of each cylinder's firing TDC",
        lambda t: t.excitation.firing_tdc,
    ),
    _out(
        "torsion_excitation_inertia_amplitude",
        ("cylinder", _ORDER),
        "N m",
        "amplitude of the moving parts' tangential torque per order at the reference speed",
        lambda t: np.abs(t.excitation.inertia),
    ),
    _out(
        "torsion_excitation_inertia_phase",
        ("cylinder", _ORDER),
        "deg",
        "phase of the moving parts' torque per order in the angle from the firing TDC",
        lambda t: _phase_deg(t.excitation.inertia),
    ),
    _out(
        "torsion_excitation_gas_amplitude",
        ("cylinder", _ORDER),
        "N m",
        "amplitude of the gas part of the tangential torque per order (every speed)",
        lambda t: np.abs(t.excitation.gas),
        when=_has_gas,
    ),
    _out(
        "torsion_excitation_gas_phase",
        ("cylinder", _ORDER),
        "deg",
        "phase of the gas torque per order in the angle from the firing TDC",
        lambda t: _phase_deg(t.excitation.gas),
        when=_has_gas,
    ),
    _out(
        "torsion_tangential_pressure",
        ("cylinder", _ORDER),
        "bar",
        "gas torque amplitude per piston area and crank radius",
        lambda t: t.excitation.tangential_pressure / 1e5,
        when=_has_gas,
    ),
    _out(
        "torsion_free_end_amplitude",
        (_ORDER, _SPEED),
        "deg",
        "amplitude a of the free end's angle a cos(k theta + phase) per order",
        lambda t: _amplitude_deg(t.free_end),
        when=_damped,
    ),
    _out(
        "torsion_free_end_phase",
        (_ORDER, _SPEED),
        "deg",
        "phase of the free end's angle per order (0 where the amplitude is 0)",
        lambda t: _phase_deg(t.free_end),
        when=_damped,
    ),
    _out(
        "torsion_free_end_synthesis",
        (_SPEED,),
        "deg",
        "half range (max - min)/2 over the cycle of the free end's angle, all orders",
        lambda t: np.degrees(t.free_end_synthesis),
        when=_damped,
    ),
    _out(
        "torsion_section_torque_amplitude",
        (_SECTION, _ORDER, _SPEED),
        "N m",
        "amplitude of the elastic torque in each shaft section per order",
        lambda t: np.abs(t.section_torque),
        when=_damped,
    ),
    _out(
        "torsion_section_torque_synthesis",
        (_SECTION, _SPEED),
        "N m",
        "half range over the cycle of the elastic torque in each section, all orders",
        lambda t: t.section_torque_synthesis,
        when=_damped,
    ),
    _out(
        "torsion_section_stress_amplitude",
        (_SECTION, _ORDER, _SPEED),
        "MPa",
        "amplitude of the nominal shear stress 16 T d / (pi (d^4 - d_i^4)) per order",
        lambda t: t.section_stress / 1e6,
        when=_damped,
    ),
    _out(
        "torsion_section_stress_synthesis",
        (_SECTION, _SPEED),
        "MPa",
        "half range over the cycle of the nominal shear stress, all orders",
        lambda t: t.section_stress_synthesis / 1e6,
        when=_damped,
    ),
    _out(
        "torsion_damper_power",
        (_DAMPER, _ORDER, _SPEED),
        "W",
        "mean power dissipated in each damper's coupling per order",
        lambda t: t.damper_power,
        when=lambda r: _damped(r) and _has_dampers(r),
    ),
    _out(
        "torsion_damper_power_total",
        (_DAMPER, _SPEED),
        "W",
        "mean power dissipated in each damper's coupling, all orders",
        lambda t: t.damper_power_total,
        when=lambda r: _damped(r) and _has_dampers(r),
    ),
    _out(
        "torsion_resonance_mode",
        (_RES,),
        "1",
        "mode of each resonance (order times speed equal to the natural frequency)",
        lambda t: np.array([r.mode for r in t.resonances], dtype=np.int64),
    ),
    _out(
        "torsion_resonance_order",
        (_RES,),
        "1",
        "order of each resonance",
        lambda t: np.array([r.order for r in t.resonances], dtype=np.float64),
    ),
    _out(
        "torsion_resonance_speed",
        (_RES,),
        "rpm",
        "crank speed of each resonance, 60 f / k",
        lambda t: _rpm([r.speed for r in t.resonances]) if t.resonances else np.zeros(0),
    ),
    _out(
        "torsion_resonance_vector_sum",
        (_RES,),
        "1",
        "relative amplitude sum of each resonance's mode and order",
        _resonance_field("vector_sum"),
    ),
    _out(
        "torsion_resonance_free_end",
        (_RES,),
        "deg",
        "free end's amplitude of the resonance's order at its speed (NaN undamped)",
        lambda t: np.degrees(_resonance_field("free_end")(t)),
    ),
    _out(
        "torsion_resonance_section",
        (_RES,),
        "1",
        "section with the largest torque of the order at the resonance (NaN undamped)",
        _resonance_field("section"),
    ),
    _out(
        "torsion_resonance_section_torque",
        (_RES,),
        "N m",
        "that section's torque amplitude at the resonance (NaN undamped)",
        _resonance_field("section_torque"),
    ),
    _out(
        "torsion_reference_speed",
        (),
        "rpm",
        "the layout's speed: the inertia excitation is given at it, scaling with speed^2",
        lambda t: float(_rpm(t.reference_speed)[0]),
    ),
    _coord(_SPEED, "rpm", "crank speed of the torsion response", lambda t: _rpm(t.speeds)),
    _coord(_ORDER, "1", "order of the torsional excitation", lambda t: t.orders),
    _coord(
        "torsion_mass",
        "1",
        "mass number, free end first",
        lambda t: np.arange(1, t.train.n_masses + 1),
    ),
    _coord(
        _SECTION,
        "1",
        "shaft section number (section j joins masses j and j + 1)",
        lambda t: np.arange(1, t.train.n_masses),
    ),
    _coord(_MODE, "1", "torsional mode number", lambda t: np.arange(1, t.frequencies.size + 1)),
    _coord(
        "torsion_station",
        "",
        "mass or tuned damper ring of a mode shape",
        lambda t: np.array(t.stations),
    ),
    _coord(
        _DAMPER,
        "1",
        "damper number",
        lambda t: np.arange(1, len(t.train.dampers) + 1),
        when=_has_dampers,
    ),
    _coord(_RES, "1", "resonance number, by speed", lambda t: np.arange(1, len(t.resonances) + 1)),
)
