"""The ``mounts:`` section: the powertrain's mass, inertia and mounts
(docs/layout-format.md, "The engine on its mounts").

:class:`MountsSpec` is the section's pydantic model (quantities read with units, like the rest of
the layout file: lengths, a mass, inertias, stiffnesses in ``N/mm`` or ``N/m``, dampings in ``N
s/m``; a bare number other than 0 is refused, docs/layout-format.md, "Quantities and units").
:func:`mount_system` turns a validated section into a
:class:`balance.core.mounts.MountSystem`.  :func:`load_mounts` reads a standalone mounts file
(``--mounts FILE``): the section's keys at the top level, or the section under ``mounts:``.  Every
problem is a :class:`~balance.core.errors.LayoutError` naming file, line, field and what would be
valid (:mod:`balance.io.located`, as for every section).  :data:`SECTION` is the section's entry in
the layout reader's registry (:mod:`balance.io.layout_sections`).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Annotated, Any

import numpy as np
from numpy.typing import NDArray
from pydantic import BeforeValidator, Field, model_validator

from balance.core.engine import Engine
from balance.core.errors import LayoutError, raise_all
from balance.core.mounts import (
    COORDINATES,
    MountPoint,
    MountSystem,
    inertia_tensor,
    mass_matrix,
    normal_modes,
    stiffness_matrix,
)
from balance.io.layout_sections import SectionReader
from balance.io.located import Hints, validate
from balance.io.problems import FieldProblem
from balance.io.spec_blocks import Length, Strict, kg_m2, quantity
from balance.io.units import UnitProblem, check_thousands, registry
from balance.io.yamlsource import SourceDocument, parse_yaml, read_yaml_file

__all__ = [
    "SECTION",
    "InertiaSpec",
    "MountPointSpec",
    "MountsSpec",
    "load_mounts",
    "mount_system",
    "mounts_from_dict",
    "mounts_from_text",
]

#: Cosine of the angle between a mount's axes 1 and 2 above which they count as parallel.
PARALLEL_COSINE = 1.0 - 1e-6

_NUMBER = re.compile(r"^\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")

# unit text -> factor to SI, for the common units (pint reads the others)
_STIFFNESS_UNITS = {
    "N/m": 1.0,
    "N/mm": 1e3,
    "N/cm": 1e2,
    "kN/m": 1e3,
    "kN/mm": 1e6,
    "MN/m": 1e6,
}
_DAMPING_UNITS = {
    "N s/m": 1.0,
    "N*s/m": 1.0,
    "Ns/m": 1.0,
    "N·s/m": 1.0,
    "kg/s": 1.0,
    "N s/mm": 1e3,
    "N*s/mm": 1e3,
    "kN s/m": 1e3,
    "kN*s/m": 1e3,
}


def _per_unit(
    value: Any, what: str, si: str, units: dict[str, float], example: str, likely: str
) -> float:
    """A stiffness or damping [SI] from text with a unit; a bare number other than 0 is
    refused with the likely unit proposed (docs/layout-format.md, "Quantities and units")."""
    valid = f"give {what} with a unit, e.g. {example}"
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        shown = "a list" if isinstance(value, list) else repr(value)
        raise UnitProblem(f"expected {what}, got {shown}", valid)
    bare = value if not isinstance(value, str) else None
    if isinstance(value, str) and (match := _NUMBER.match(value)) and not match.group(2):
        bare = float(match.group(1))
    if bare is not None and bare != 0:
        raise UnitProblem(f"{value!r} has no unit", f"give a unit, e.g. '{bare:g} {likely}'")
    if isinstance(value, str):
        check_thousands(value)
        match = _NUMBER.match(value) if len(value) <= 80 else None
        if match is None:
            raise UnitProblem(f"cannot read {value!r} as {what}", valid)
        number = float(match.group(1))
        unit_text = " ".join(match.group(2).split())
        if not unit_text:
            result = number
        elif unit_text in units:
            result = number * units[unit_text]
        else:
            try:
                quantity = registry().Quantity(number, unit_text)
            except Exception:
                raise UnitProblem(f"unknown unit {unit_text!r}", valid) from None
            try:
                result = float(quantity.to(si).magnitude)
            except Exception:
                raise UnitProblem(f"{value!r} is not {what}", valid) from None
    else:
        result = float(value)
    if not math.isfinite(result) or abs(result) > 1e12:
        raise UnitProblem(f"{value!r} is not a finite {what} of sane size", valid)
    return result


def _stiffness(value: Any) -> float:
    return _per_unit(value, "a stiffness", "N/m", _STIFFNESS_UNITS, "'250 N/mm'", "N/mm")


def _damping(value: Any) -> float:
    return _per_unit(value, "a damping", "N s/m", _DAMPING_UNITS, "'300 N s/m'", "N s/m")


def _kg(number: float) -> str:
    """The unit proposed for a bare powertrain mass: kilograms at any size."""
    return "kg"


Mass = Annotated[float, quantity("mass", _kg)]
Inertia = Annotated[float, quantity("inertia", kg_m2)]
Stiffness = Annotated[float, BeforeValidator(_stiffness)]
Damping = Annotated[float, BeforeValidator(_damping)]
Point = Annotated[list[Length], Field(min_length=3, max_length=3)]
Direction = Annotated[list[float], Field(min_length=3, max_length=3)]

FloatArray = NDArray[np.float64]


class InertiaSpec(Strict):
    """Inertia tensor about the CG in engine axes [kg m^2]; ``xy`` is :math:`-\\int xy\\,dm`."""

    xx: Inertia
    yy: Inertia
    zz: Inertia
    xy: Inertia = 0.0
    xz: Inertia = 0.0
    yz: Inertia = 0.0

    @property
    def tensor(self) -> FloatArray:
        """The 3×3 tensor [kg m^2]."""
        return inertia_tensor(self.xx, self.yy, self.zz, self.xy, self.xz, self.yz)


class MountPointSpec(Strict):
    """One mount: position, stiffness (and damping) along its axes, and the axes."""

    position: Point
    stiffness: Annotated[list[Stiffness], Field(min_length=3, max_length=3)]
    damping: Annotated[list[Damping], Field(min_length=3, max_length=3)] | None = None
    axes: Annotated[list[Direction], Field(min_length=2, max_length=2)] | None = None

    @model_validator(mode="after")
    def _check(self) -> MountPointSpec:
        for key, unit in (("stiffness", "N/m"), ("damping", "N s/m")):
            values = getattr(self, key)
            for j, value in enumerate(values or ()):
                if value < 0:
                    raise FieldProblem(
                        f"{key} along axis {j + 1} is {value:g} {unit}",
                        f"each {key} must be zero or more",
                        (key, j),
                    )
        if self.axes is not None:
            first, second = (np.asarray(v, dtype=np.float64) for v in self.axes)
            for j, v in enumerate((first, second)):
                if not np.all(np.isfinite(v)) or not np.linalg.norm(v) > 0:
                    raise FieldProblem(
                        f"axis {j + 1} is {self.axes[j]}",
                        "each axis is a direction in engine axes, e.g. [0, 1, 0], not zero",
                        ("axes", j),
                    )
            cosine = abs(first @ second) / (np.linalg.norm(first) * np.linalg.norm(second))
            if cosine > PARALLEL_COSINE:
                raise FieldProblem(
                    "axes 1 and 2 are parallel",
                    "give two different directions: axis 2 is made perpendicular to axis 1, "
                    "and axis 3 = 1 × 2",
                    ("axes", 1),
                )
        return self

    @property
    def axes_matrix(self) -> FloatArray:
        """The mount's axes as the rows of a rotation matrix (engine frame).

        Axis 1 is ``axes[0]`` normalised; axis 2 is ``axes[1]`` less its component along
        axis 1 (Gram-Schmidt), normalised; axis 3 = 1 × 2.  Identity without ``axes``.
        """
        if self.axes is None:
            return np.eye(3)
        first, second = (np.asarray(v, dtype=np.float64) for v in self.axes)
        e1 = first / np.linalg.norm(first)
        e2 = second - (second @ e1) * e1
        e2 = e2 / np.linalg.norm(e2)
        return np.array([e1, e2, np.cross(e1, e2)])


class MountsSpec(Strict):
    """The ``mounts:`` section (docs/layout-format.md, "The engine on its mounts")."""

    mass: Mass
    cg: Point
    inertia: InertiaSpec
    points: list[MountPointSpec] = Field(min_length=1, max_length=64)

    @model_validator(mode="after")
    def _check(self) -> MountsSpec:
        if not self.mass > 0:
            raise FieldProblem(
                f"mass is {self.mass:g} kg", "mass must be more than zero", ("mass",)
            )
        principal = np.linalg.eigvalsh(self.inertia.tensor)
        shown = ", ".join(f"{p:.4g}" for p in principal)
        if not principal[0] > 0:
            raise FieldProblem(
                f"the inertia tensor is not positive definite (principal moments {shown} kg m^2)",
                "moments of inertia above zero, and products of inertia small enough that "
                "every principal moment is above zero",
                ("inertia",),
            )
        if principal[2] > (principal[0] + principal[1]) * (1 + 1e-9):
            raise FieldProblem(
                f"no body has these principal moments of inertia ({shown} kg m^2): the largest "
                "is more than the sum of the other two",
                "each principal moment at most the sum of the other two (triangle inequality)",
                ("inertia",),
            )
        system = mount_system(self)
        modes = normal_modes(mass_matrix(system.mass, system.inertia), stiffness_matrix(system))
        top = modes.frequency[-1]
        if not modes.frequency[0] > 1e-6 * top:
            free = COORDINATES[int(np.argmax(modes.energy_share[0]))]
            motion = {"x": "along x", "y": "along y", "z": "along z"}.get(free, f"about {free[1]}")
            raise FieldProblem(
                f"the mounts do not hold the engine: it moves freely, mostly {motion}",
                "place and orient the mounts so that they resist every translation and "
                "rotation (at least three mounts not in one line, or stiffness along each "
                "axis)",
                ("points",),
            )
        return self


def mount_system(spec: MountsSpec) -> MountSystem:
    """The mount system of a validated ``mounts:`` section (SI units).

    Parameters
    ----------
    spec : MountsSpec
        A validated section.

    Returns
    -------
    MountSystem
        Mass [kg], CG [m], inertia tensor [kg m^2], and each mount's position [m],
        stiffness [N/m], damping [N s/m] (zero when not given) and orthonormal axes.
    """
    return MountSystem(
        mass=spec.mass,
        cg=np.asarray(spec.cg, dtype=np.float64),
        inertia=spec.inertia.tensor,
        points=tuple(
            MountPoint(
                position=np.asarray(p.position, dtype=np.float64),
                stiffness=np.asarray(p.stiffness, dtype=np.float64),
                damping=np.asarray(p.damping if p.damping is not None else (0.0,) * 3),
                axes=p.axes_matrix,
            )
            for p in spec.points
        ),
    )


# ---------------------------------------------------------------------------------------
# a standalone mounts file


def load_mounts(source: str | Path) -> MountSystem:
    """Read a mounts file (``--mounts FILE``).

    Parameters
    ----------
    source : str or path-like
        A YAML file holding the ``mounts:`` section's keys (``mass``, ``cg``, ``inertia``,
        ``points``) at the top level, or a single ``mounts:`` mapping.

    Returns
    -------
    MountSystem

    Raises
    ------
    LayoutError
        If the file is not a valid mounts section (file, line, field and what is valid).
    InputError
        If the file cannot be found or read.
    """
    return _from_document(read_yaml_file(Path(source), source, "mounts file"))


def mounts_from_text(text: str, file: str = "<input>") -> MountSystem:
    """A mount system from YAML text (see :func:`load_mounts`).

    Parameters
    ----------
    text : str
        The mounts file's text: the section's keys at the top level, or a ``mounts:`` mapping.
    file : str
        The name the messages give the text.

    Returns
    -------
    MountSystem

    Raises
    ------
    LayoutError
        If the text is not a valid mounts section.
    """
    return _from_document(parse_yaml(text, file))


def mounts_from_dict(data: Any, file: str = "<dict>") -> MountSystem:
    """A mount system from plain data shaped like a mounts file (see :func:`load_mounts`).

    Parameters
    ----------
    data : dict
        The section's keys, or ``{"mounts": {...}}``.
    file : str
        Name used in error messages.

    Returns
    -------
    MountSystem
    """
    return _from_document(SourceDocument(data=data, file=file))


def _from_document(doc: SourceDocument) -> MountSystem:
    data = doc.data
    valid = "a mounts file holds mass, cg, inertia and points, at the top or under 'mounts:'"
    if not isinstance(data, dict):
        raise LayoutError("the document is not a mapping", doc.location(()), valid=valid)
    prefix: tuple[str | int, ...] = ()
    if "mounts" in data:
        extra = [k for k in data if k != "mounts"]
        if extra:
            raise LayoutError(
                f"unknown key '{extra[0]}' beside 'mounts'",
                doc.location((extra[0],), key=True),
                field=str(extra[0]),
                valid=valid,
            )
        data, prefix = data["mounts"], ("mounts",)
        if not isinstance(data, dict):
            raise LayoutError(
                "expected a mapping", doc.location(prefix), field="mounts", valid=valid
            )
    spec, problems = validate(MountsSpec, data, doc, prefix, SECTION.hints)
    raise_all(problems)
    assert spec is not None
    return mount_system(spec)


def _build(spec: MountsSpec, engine: Engine) -> MountSystem:
    """The mount system the engine's sections hold (it needs nothing of the engine)."""
    return mount_system(spec)


def _expand(section: Any, system: MountSystem) -> Any:
    """The section as ``layout expand`` writes it: as the file wrote it (validated)."""
    return section


_MISSING_HINTS = {
    "mass": "add the mass the mounts carry, e.g. 'mass: 160 kg'",
    "cg": "add the centre of gravity, e.g. 'cg: [0 mm, 60 mm, 140 mm]'",
    "inertia": "add the inertia about the CG, e.g. '{xx: 7.5 kg m^2, yy: 9 kg m^2, zz: 4 kg m^2}'",
    "points": "add the mounts, each {position: [...], stiffness: [...]}",
    "position": "add the mount's position, e.g. '[-220 mm, -120 mm, 0 mm]'",
    "stiffness": "add the stiffness along the mount's axes, e.g. '[250 N/mm, 400 N/mm, 150 N/mm]'",
    "xx": "add xx, e.g. '7.5 kg m^2'",
    "yy": "add yy, e.g. '9 kg m^2'",
    "zz": "add zz, e.g. '4 kg m^2'",
}


#: The ``mounts:`` section's entry in the layout reader's registry (and the hints of a
#: mounts file's problems).
SECTION = SectionReader(
    "mounts",
    MountsSpec,
    _build,
    _expand,
    Hints(
        missing=_MISSING_HINTS,
        sizes={"points": "1 to 64 mounts", "axes": "two directions: [[axis 1], [axis 2]]"},
        size="three values [x, y, z]",
    ),
)
