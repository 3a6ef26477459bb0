r"""The ``torsion:`` section of a layout: the mass-elastic table of the crank train, its
checks and its warnings.

A layout's ``torsion:`` section describes the crank train as a *mass-elastic table*
(docs/torsion.md): rigid masses on a chain of shaft sections written from the free end
(mass 1, usually the pulley or damper hub) to the driven end (the flywheel, or the load
beyond it), and dampers hung on its masses.  This module holds that table as frozen
dataclasses in SI (:class:`TorsionTrain`), the checks of its values
(:func:`train_problems`), its plausibility warnings (:func:`torsion_warnings`), the
inertias of its masses as used (:func:`mass_inertias`) and its matrices
(:func:`train_matrices`).  The analysis is in :mod:`balance.core.torsion`.

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
  reader passes the cylinders' ``tdc`` angles,
  :func:`balance.core.torsion_excitation.place_firing_tdc`, and stores the angles placed in
  :attr:`TorsionTrain.firing_tdc` when the engine has no ``gas:`` section).

The command line checks its options with
:func:`balance.core.torsion_excitation.order_problem` (half orders on a two-stroke, an
order not a multiple of 0.5) and :func:`balance.core.torsion_excitation.speed_problem` (a
speed that is not positive), and refuses ``--torsion`` on a layout without a ``torsion:``
section.  :func:`balance.core.torsion.torsion_part` repeats the value checks
(:func:`check_train`: an :class:`~balance.core.errors.InputError` naming the field), so that
a train built in Python is checked too.

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

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.plausibility import PlausibilityWarning
from balance.core.torsion_excitation import moving_parts_inertia, place_firing_tdc
from balance.core.torsion_response import TrainMatrices, assemble, normal_modes

__all__ = [
    "MAX_LOSS_FACTOR",
    "TUNING_BAND",
    "WARNING_RULES",
    "Shaft",
    "TorsionDamper",
    "TorsionMass",
    "TorsionTrain",
    "TrainProblem",
    "by_part_cylinders",
    "check_train",
    "mass_inertias",
    "resolve_mass",
    "torsion_warnings",
    "train_matrices",
    "train_problems",
]

FloatArray = NDArray[np.float64]

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
    mass's name; None when it names no mass.

    Parameters
    ----------
    train_masses : sequence of TorsionMass
        The masses of the table, free end first.
    at : int or str
        A mass's number (1-based) or its name, as the damper's ``at`` gives it (a bool
        names no mass).

    Returns
    -------
    int or None
        The mass's number (1-based; the first of that name), or None when ``at`` is out
        of range, names no mass or is a bool.
    """
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


def by_part_cylinders(engine: Engine) -> NDArray[np.bool_]:
    """Which cylinders have their masses by part, with no lumped override (their moving
    parts' inertia is defined: a lumped ``rotating`` mass holds the crank's own unbalance
    too).

    Parameters
    ----------
    engine : Engine
        The engine.

    Returns
    -------
    ndarray of bool, shape (cylinders,)
        True for a cylinder with masses by part and neither a lumped ``reciprocating`` nor
        a lumped ``rotating`` mass given over them; all False for an engine with lumped
        masses only.
    """
    parts = engine.mass_parts
    if parts is None:
        return np.zeros(engine.n_cylinders, dtype=bool)
    return np.asarray(np.isnan(parts.reciprocating_given) & np.isnan(parts.rotating_given))


def _by_part(engine: Engine, cylinders: Sequence[int]) -> bool:
    """Whether these cylinders' masses are all given by part."""
    idx = [c - 1 for c in cylinders if 1 <= c <= engine.n_cylinders]
    return bool(np.all(by_part_cylinders(engine)[idx]))


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


def check_train(train: TorsionTrain, engine: Engine) -> None:
    """Raise an :class:`~balance.core.errors.InputError` naming the first problem of
    :func:`train_problems` (and how many more there are); nothing for a good train.

    Parameters
    ----------
    train : TorsionTrain
        The table, in SI.
    engine : Engine
        The engine it belongs to (checked against it as :func:`train_problems` does; its
        name starts the message).

    Returns
    -------
    None

    Raises
    ------
    InputError
        When :func:`train_problems` finds a problem: the engine's name, then the first
        problem in one line (:meth:`TrainProblem.one_line`) and how many more there are.
    """
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
    :func:`balance.core.torsion_excitation.moving_parts_inertia` when not given).

    Parameters
    ----------
    engine : Engine
        The engine (read only to compute ``moving`` when a mass has ``crank_inertia`` and
        ``moving`` is not given).
    train : TorsionTrain
        The table (checked: :func:`train_problems` finds nothing).
    moving : ndarray, shape (cylinders,), optional
        Each cylinder's mean moving-parts inertia [kg m^2].

    Returns
    -------
    ndarray, shape (masses,)
        The inertia of each mass as used [kg m^2], free end first.
    """
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
    """The matrices of the train (:func:`balance.core.torsion_response.assemble`) with the
    masses' inertias as used, and the dampers ``dampers`` (0-based; default all).

    Parameters
    ----------
    train : TorsionTrain
        The table: its shaft sections, the masses' damping, its dampers and loss factor.
    inertias : array_like, shape (masses,)
        Each mass's inertia as used [kg m^2] (:func:`mass_inertias`).
    dampers : sequence of int, optional
        The dampers to include (0-based, in :attr:`TorsionTrain.dampers`); default all.
        The others are left out.

    Returns
    -------
    TrainMatrices
        Coordinates: the masses in order, then the ring of each included damper in the
        order given.
    """
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
