"""Changing fields of an engine: one set of rules for variants, sweep grids and samples.

A study changes some fields (:class:`balance.io.fields.Field`, rows of the table of layout
fields :data:`balance.io.layout_fields.FIELDS`) of an :class:`Engine` and
expects the engine that loading the layout file with those values written in would give:

0. a field of the compact ``crank:`` form (``crank.spacing``, ``crank.bank_stagger``,
   ``crank.banks[N]``, ``crank.v_angle``) sets every cylinder's axial position and bank
   angle as the file's expansion gives them (:mod:`balance.io.crank_form`); a field of the
   ``balance:`` section (``balance.balance_factor``) sets the proposal's setting;
1. the speed and ``reference_z`` are set as they are;
2. geometry (throw, bank, z, crank radius, conrod length, offset) and, for masses given
   by part, the parts are set; a changed part or conrod length lumps the parts again
   (:meth:`balance.core.masses.MassParts.lumped`, the two-mass split);
3. lumped masses set by the study are set last, so that they win over the parts;
4. when the layout gives no ``reference_z`` and a ``z`` changes, the reference is
   re-centred midway between the outermost cylinders.

The values may be arrays with leading dimensions (a sweep's grid, a tolerance study's
samples); they broadcast against the per-cylinder arrays, cylinders on the last axis.  The
engine returned then holds arrays of that broadcast shape.  Setting a value copies it
bit for bit and every derived number is formed by the same operations for one variant as
for a grid, so a sweep equals the analyses of its variants bit for bit.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.balance_factor import BalanceFactor
from balance.core.engine import BalanceSettings, Engine
from balance.core.errors import InputError
from balance.io.crank_form import crank_geometry
from balance.io.fields import Field
from balance.io.layout_fields import CYLINDER, FIELDS, GEOMETRY

__all__ = [
    "LINK_GEOMETRY",
    "LUMPED",
    "Change",
    "apply_changes",
]

FloatArray = NDArray[np.float64]

#: The lumped-mass attributes of an :class:`Engine`: set after any re-lumping.
LUMPED = frozenset(f.attribute for f in FIELDS if f.group == "lumped")

#: A change: the field and its value in the unit of the Engine attribute (radians for
#: angles, the crank radius for a stroke; :meth:`Field.to_layout_units`).  The value of a
#: per-cylinder field broadcasts against the cylinders (a trailing axis of size one, or
#: of the number of cylinders for a field of every cylinder).
Change = tuple[Field, ArrayLike]


def apply_changes(
    engine: Engine,
    changes: Sequence[Change],
    *,
    add: bool = False,
    problem: str = "the conrod's centre of gravity would lie beyond its small end",
) -> Engine:
    """The engine with some fields changed, by the rules of the module notes.

    Parameters
    ----------
    engine : Engine
        The base engine.
    changes : sequence of (Field, array_like)
        The fields and their values, applied in this order (later changes of the same
        attribute overwrite, or with ``add`` add to, the earlier ones).
    add : bool
        Add the values to the engine's (a tolerance study's scatter) instead of setting
        them.
    problem : str
        The message of the :class:`InputError` raised where a re-lumped conrod's centre
        of gravity would lie beyond its small end.

    Returns
    -------
    Engine
        With arrays of the broadcast shape of the values (cylinders last), and the speed
        and ``reference_z`` as given (arrays for a grid).
    """
    if engine.has_links:
        _check_link_fields(engine, [field for field, _ in changes])
    new: dict[str, Any] = _crank_changes(engine, changes, add)
    parts: dict[str, Any] = {}
    lumped: list[Change] = []
    relump = False
    n = engine.n_cylinders

    def current(name: str) -> Any:
        return new.get(name, getattr(engine, name))

    for field, value in changes:
        attribute = field.attribute
        if attribute.startswith("crank."):
            continue  # set above
        if attribute.startswith("shaft."):  # a crankshaft's phase, x or y
            from balance.io.several_cranks import shaft_changed

            new[_SHAFTS] = shaft_changed(current(_SHAFTS), attribute, value, add)
            continue
        if attribute.startswith("balance."):
            settings = engine.balance if engine.balance is not None else BalanceSettings()
            key = attribute.removeprefix("balance.")
            base = getattr(settings, key)
            setting: Any
            if isinstance(base, BalanceFactor):  # keeps the convention the file gave
                given: Any = value  # an array over a grid
                share = base.value + given if add else given
                setting = BalanceFactor(share, base.of)
            else:
                setting = base + value if add and base is not None else value
            new["balance"] = replace(current("balance") or settings, **{key: setting})
        elif attribute in {"speed", "reference_z"}:
            new[attribute] = current(attribute) + value if add else value
        elif attribute in LUMPED:
            lumped.append((field, value))
        elif attribute.startswith("parts."):
            key = attribute.removeprefix("parts.")
            assert engine.mass_parts is not None
            base = parts.get(key, getattr(engine.mass_parts, key))
            parts[key] = _put(base, field, value, n, add)
            relump = True
        else:
            new[attribute] = _put(current(attribute), field, value, n, add)
            relump |= attribute == "conrod_length" and engine.mass_parts is not None
    if relump:
        assert engine.mass_parts is not None
        rec, rot, correction = _lumped_again(engine, current("conrod_length"), parts, problem)
        new.update(
            reciprocating_mass=rec,
            rotating_mass=rot,
            conrod_inertia_correction=correction,
            mass_parts=replace(engine.mass_parts, **parts),
        )
    for field, value in lumped:
        new[field.attribute] = _put(current(field.attribute), field, value, n, add)
        if engine.mass_parts is not None:
            # a lumped mass given wins over the parts, also when they are lumped again
            given = field.attribute.replace("_mass", "_given")
            parts_now = current("mass_parts")
            value_given = _put(getattr(parts_now, given), field, value, n, add)
            new["mass_parts"] = replace(parts_now, **{given: value_given})
    if "reference_z" not in new and "z" in new and not engine.reference_z_given:
        z = new["z"]
        centre = 0.5 * (z.min(axis=-1) + z.max(axis=-1))
        new["reference_z"] = float(centre) if np.ndim(centre) == 0 else centre[..., None]
    return replace(engine, **new)


def _crank_changes(engine: Engine, changes: Sequence[Change], add: bool) -> dict[str, Any]:
    """The axial positions and bank angles that changes of the compact ``crank:`` form's
    fields give (:func:`balance.io.crank_form.crank_geometry`, the reader's operations), or
    nothing when no such field changes.

    ``crank.v_angle`` sets the two banks half of it either side of the middle of the
    layout's two bank angles, each bank keeping its side (``banks: [-45, 45]`` at 72° gives
    ``[-36, 36]``, ``banks: [45, -45]`` gives ``[36, -36]``).
    """
    crank = [(field, value) for field, value in changes if field.attribute.startswith("crank.")]
    if not crank:
        return {}
    form = crank[0][0].crank
    assert form is not None
    spacing: Any = form.spacing
    stagger: Any = form.bank_stagger
    banks: list[Any] = list(form.banks)
    for field, value in crank:
        key = field.key
        if key == "spacing":
            spacing = spacing + value if add else value
        elif key == "bank_stagger":
            stagger = stagger + value if add else value
        elif key == "banks":
            assert field.bank is not None
            banks[field.bank] = banks[field.bank] + value if add else value
        else:  # v_angle: about the middle of the two banks, each keeping its side
            first, second = form.banks[0], form.banks[1]
            middle = (first + second) / 2
            half = np.asarray(value, dtype=np.float64) / 2
            if second < first:
                half = -half
            banks[0], banks[1] = middle - half, middle + half
    z, bank = crank_geometry(form, spacing, stagger, banks)
    return {"z": z, "bank": bank}


#: Fields that move the kinematics of an engine with link rods (its geometry: the
#: attributes of each cylinder's own fields and of ``geometry:``).
LINK_GEOMETRY = frozenset(
    f.attribute for f in FIELDS if f.place in (CYLINDER, GEOMETRY) and f.attribute is not None
)
#: Rod parts whose engine-wide value the layout file gives the master rods only.
_ROD_PARTS = frozenset(f.attribute for f in FIELDS if f.group == "rod")
#: The :class:`Engine` attribute that holds several crankshafts.
_SHAFTS = "crankshafts"


def _check_link_fields(engine: Engine, fields: Sequence[Field]) -> None:
    """Refuse the fields that a study cannot change exactly on an engine with link rods.

    A study of an engine with link rods keeps its geometry: the link rods' Fourier
    coefficients are computed once for it (:mod:`balance.core.links`), so that each grid
    point is the single analysis of its variant bit for bit.  Allowed: the speed,
    ``reference_z``, the masses by part (engine-wide ``piston_group`` and
    ``crank_unbalance``; any part of one cylinder) and lumped masses of cylinders that are
    not link cylinders.

    Parameters
    ----------
    engine : Engine
        The engine studied.
    fields : sequence of Field
        The fields the study changes.

    Raises
    ------
    InputError
        Naming the first field refused and what may be changed instead.
    """
    assert engine.links is not None
    linked = engine.links.master >= 0
    numbers = ", ".join(str(int(i) + 1) for i in np.flatnonzero(linked))
    for field in fields:
        attribute = field.attribute
        if attribute in LINK_GEOMETRY or attribute.startswith("crank."):
            why = "it moves the link kinematics, which are computed once per engine"
        elif attribute in _ROD_PARTS and field.cylinder is None:
            why = (
                "the engine-wide rod is the master rods' (each link rod has its own); vary "
                "cylinders[N]." + field.key + " instead"
            )
        elif attribute in LUMPED and (field.cylinder is None or linked[field.cylinder]):
            why = (
                "a link cylinder's masses are given by part (its rod's lower end is not on "
                "the crank pin)"
            )
        else:
            continue
        raise InputError(
            f"{field.text}: cannot be varied on an engine with link rods (cylinders {numbers}): "
            f"{why}; vary the speed, reference_z or the masses by part"
        )


def _put(base: ArrayLike, field: Field, value: ArrayLike, n: int, add: bool) -> Any:
    """A per-cylinder array with one cylinder's (or every cylinder's) value set or added."""
    old = np.asarray(base, dtype=np.float64)
    new = np.asarray(value, dtype=np.float64)
    if add:
        new = old + new
    if field.cylinder is None:
        return np.broadcast_to(new, np.broadcast_shapes(new.shape, old.shape))
    return np.where(np.arange(n) == field.cylinder, new, old)


def _lumped_again(
    layout: Engine, conrod_length: ArrayLike, parts: Mapping[str, ArrayLike], problem: str
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Lumped masses of a by-part layout with some parts or the conrod length changed, as
    loading the file would give them.

    Parameters
    ----------
    layout : Engine
        A layout with masses by part.
    conrod_length : array_like
        Conrod length per cylinder [m], possibly with grid axes.
    parts : mapping of str to array_like
        The changed parts by name (:data:`balance.core.masses.PART_FIELDS`), arrays that
        broadcast against the cylinders.
    problem : str
        The message when a conrod's centre of gravity would lie beyond its small end.

    Returns
    -------
    reciprocating, rotating, correction : ndarray
        Reciprocating and rotating mass [kg] and the conrod inertia correction [kg m^2] per
        cylinder (:meth:`balance.core.masses.MassParts.lumped`).

    Raises
    ------
    InputError
        With the message ``problem`` where a conrod's centre of gravity would lie beyond
        its small end.
    """
    assert layout.mass_parts is not None
    cg = parts.get("conrod_cg_to_big_end", layout.mass_parts.conrod_cg_to_big_end)
    if np.any(np.asarray(cg) > np.asarray(conrod_length)):
        raise InputError(problem)
    return layout.mass_parts.lumped(conrod_length, parts)
