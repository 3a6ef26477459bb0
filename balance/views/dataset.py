"""The result Dataset, a view of the :class:`~balance.core.result.Result`.

Every view reads the ``Result``; this one, :func:`build_dataset` (``build_dataset(result)``),
builds the ``xarray.Dataset`` for the Python API and the netCDF writer.  JSON, CSV and the
table read the ``Result`` directly and do not go through the Dataset.  With bearing loads
or mounts in the result, their variables are added (:mod:`balance.views.bearings`,
:mod:`balance.views.mounts`).

Variables (every one has ``units`` and ``long_name``):

================================================  ====================  ===========
variable                                          dims                  units
================================================  ====================  ===========
``reciprocating_force_magnitude`` / ``_phase``    order, rotation       N / deg
``reciprocating_force_peak``                      order                 N
``reciprocating_force_normalised``                order, rotation       1
``reciprocating_force_peak_normalised``           order                 1
``reciprocating_moment_*`` (same set)             ...                   N m
``rotating_force_magnitude`` / ``_phase``         ()                    N / deg
``rotating_moment_magnitude`` / ``_phase``        ()                    N m / deg
``rotating_*_normalised``                         ()                    1
``roll_amplitude`` / ``roll_phase``               roll_order            N m / deg
``roll_amplitude_normalised``                     roll_order            1
``piston_acceleration_cos`` / ``_sin``            cylinder, order       1
per-cylinder layout (``throw_angle``...)          cylinder              deg, m, kg
``cylinder_stroke`` / ``tdc_crank_angle``         cylinder              m / deg
``link_master``, ``link_pin_*`` (link rods only)  cylinder              1, m, deg
``speed``, ``reference_z``, ``pitch``,            ()                    rad/s, m,
``reference_force``, ``reference_moment``                               N, N m
================================================  ====================  ===========

Phases are in degrees in [0, 360), measured from +y in the direction of rotation at
crank angle 0; a phasor of zero magnitude has phase 0.  Normalised values are per
``reference_force`` :math:`F_1 = m_{rec} r \\omega^2` (engine means) and, for moments, per
``reference_moment`` :math:`F_1 a` with ``a`` the cylinder pitch.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from balance.views.polar import CONVENTIONS, SCHEMA, phase_deg, safe_ratio, speed_rpm

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.result import Balanced, Result
    from balance.core.torque import TorqueResult

__all__ = ["SCHEMA", "build_dataset", "phase_deg"]


def _var(dims: tuple[str, ...], data: Any, units: str, long_name: str, **attrs: Any) -> xr.Variable:
    """A variable with units and long_name.

    The data are always numpy arrays here, so xarray's fast path is safe; it also spares a
    probe for duck-array libraries that would import dask or pint on a cold start.
    """
    return xr.Variable(
        dims,
        np.asarray(data),
        attrs={"units": units, "long_name": long_name, **attrs},
        fastpath=True,
    )


def _coord(name: str, values: Any, long_name: str) -> xr.IndexVariable:
    """An index coordinate built from a pandas Index.

    (Handing xarray a pandas Index spares it a duck-array check that imports pint, which
    would cost a cold start about 0.1 s.)
    """
    import pandas as pd

    return xr.IndexVariable(
        (name,), pd.Index(values, name=name), attrs={"units": "1", "long_name": long_name}
    )


def build_dataset(result: Result) -> xr.Dataset:
    """The result Dataset of an analysis: a view of the :class:`~balance.core.result.Result`.

    Parameters
    ----------
    result : Result
        From :func:`balance.core.analysis.compute`; its stored references normalise, its
        roll (with gas forces and half orders where the engine has them) is reported as is,
        and what the request did not ask for is left out.

    Returns
    -------
    xarray.Dataset
    """
    from balance._version import __version__

    layout = result.engine
    phasors = result.phasors
    ks = phasors.orders
    f1 = result.reference_force
    pitch = result.pitch
    m1 = result.reference_moment
    with_gas = result.torque is not None

    def pair(fwd: NDArray[np.complex128], bwd: NDArray[np.complex128]) -> NDArray[np.complex128]:
        return np.stack([fwd, bwd], axis=-1)

    force = pair(phasors.force_forward, phasors.force_backward)
    moment = pair(phasors.moment_forward, phasors.moment_backward)
    force_mag = np.abs(force)
    moment_mag = np.abs(moment)
    # |P+| + |P-| (as the sweep forms it)
    force_peak = force_mag[..., 0] + force_mag[..., 1]
    moment_peak = moment_mag[..., 0] + moment_mag[..., 1]

    data: dict[str, xr.Variable] = {
        "reciprocating_force_magnitude": _var(
            ("order", "rotation"),
            force_mag,
            "N",
            "magnitude of the reciprocating inertia force phasor",
        ),
        "reciprocating_force_phase": _var(
            ("order", "rotation"),
            phase_deg(force),
            "deg",
            "phase of the reciprocating inertia force phasor at crank angle 0",
        ),
        "reciprocating_force_peak": _var(
            ("order",),
            force_peak,
            "N",
            "peak reciprocating inertia force over a revolution",
        ),
        "reciprocating_force_normalised": _var(
            ("order", "rotation"),
            safe_ratio(force_mag, f1),
            "1",
            "reciprocating force phasor magnitude per m_rec r omega^2",
        ),
        "reciprocating_force_peak_normalised": _var(
            ("order",),
            safe_ratio(force_peak, f1),
            "1",
            "peak reciprocating force per m_rec r omega^2",
        ),
        "reciprocating_moment_magnitude": _var(
            ("order", "rotation"),
            moment_mag,
            "N m",
            "magnitude of the reciprocating inertia moment phasor about reference_z",
        ),
        "reciprocating_moment_phase": _var(
            ("order", "rotation"),
            phase_deg(moment),
            "deg",
            "phase of the reciprocating inertia moment phasor at crank angle 0",
        ),
        "reciprocating_moment_peak": _var(
            ("order",),
            moment_peak,
            "N m",
            "peak reciprocating inertia moment over a revolution",
        ),
        "reciprocating_moment_normalised": _var(
            ("order", "rotation"),
            safe_ratio(moment_mag, m1),
            "1",
            "reciprocating moment phasor magnitude per m_rec r omega^2 times cylinder pitch",
        ),
        "reciprocating_moment_peak_normalised": _var(
            ("order",),
            safe_ratio(moment_peak, m1),
            "1",
            "peak reciprocating moment per m_rec r omega^2 times cylinder pitch",
        ),
        "rotating_force_magnitude": _var(
            (),
            np.abs(phasors.rotating_force),
            "N",
            "magnitude of the rotating (centrifugal) force, order 1 forward",
        ),
        "rotating_force_phase": _var(
            (),
            phase_deg(phasors.rotating_force),
            "deg",
            "phase of the rotating force at crank angle 0",
        ),
        "rotating_force_normalised": _var(
            (),
            safe_ratio(np.abs(phasors.rotating_force), f1),
            "1",
            "rotating force per m_rec r omega^2",
        ),
        "rotating_moment_magnitude": _var(
            (),
            np.abs(phasors.rotating_moment),
            "N m",
            "magnitude of the rotating (centrifugal) moment about reference_z, order 1 forward",
        ),
        "rotating_moment_phase": _var(
            (),
            phase_deg(phasors.rotating_moment),
            "deg",
            "phase of the rotating moment at crank angle 0",
        ),
        "rotating_moment_normalised": _var(
            (),
            safe_ratio(np.abs(phasors.rotating_moment), m1),
            "1",
            "rotating moment per m_rec r omega^2 times cylinder pitch",
        ),
        **_roll_variables(result.roll, result.reference_roll, with_gas),
        "piston_acceleration_cos": _var(
            ("cylinder", "order"),
            phasors.acceleration_coefficients.real,
            "1",
            "a_k: cosine coefficient of -s''/r (normalised reciprocating inertia)",
        ),
        "piston_acceleration_sin": _var(
            ("cylinder", "order"),
            -phasors.acceleration_coefficients.imag,
            "1",
            "b_k: sine coefficient of -s''/r (normalised reciprocating inertia)",
        ),
        "throw_angle": _var(
            ("cylinder",),
            np.degrees(layout.throw),
            "deg",
            "crank throw angle from +y in the direction of rotation",
        ),
        "bank_angle": _var(
            ("cylinder",),
            np.degrees(layout.bank),
            "deg",
            "bore axis direction from +y in the direction of rotation",
        ),
        "axial_position": _var(("cylinder",), layout.z, "m", "axial position of the throw plane"),
        "crank_radius": _var(("cylinder",), layout.crank_radius, "m", "crank radius"),
        "conrod_length": _var(("cylinder",), layout.conrod_length, "m", "conrod length"),
        "offset": _var(("cylinder",), layout.offset, "m", "bore axis offset (desaxe)"),
        "reciprocating_mass": _var(
            ("cylinder",), layout.reciprocating_mass, "kg", "reciprocating mass at the piston pin"
        ),
        "rotating_mass": _var(
            ("cylinder",), layout.rotating_mass, "kg", "rotating mass at the crank pin radius"
        ),
        "conrod_inertia_correction": _var(
            ("cylinder",),
            layout.conrod_inertia_correction,
            "kg m2",
            "conrod moment of inertia about its centre of gravity less its two-mass model's",
        ),
        "speed": _var((), layout.speed, "rad/s", "crank speed"),
        "reference_z": _var((), layout.reference_z, "m", "axial position moments are taken about"),
        "pitch": _var((), pitch, "m", "cylinder pitch used to normalise moments"),
        "reference_force": _var((), f1, "N", "m_rec r omega^2 (engine means)"),
        "reference_moment": _var((), m1, "N m", "m_rec r omega^2 times cylinder pitch"),
    }
    coords = {
        "order": _coord("order", ks, "harmonic order (multiple of crank speed)"),
        "rotation": _coord(
            "rotation",
            ["forward", "backward"],
            "sense of rotation of the phasor relative to the crank",
        ),
        "roll_order": _coord("roll_order", result.roll_orders, "harmonic order of the roll torque"),
        "cylinder": _coord("cylinder", np.arange(1, layout.n_cylinders + 1), "cylinder number"),
    }
    attrs = {
        "schema": SCHEMA,
        "layout": layout.name,
        "source_file": layout.path or "",
        "cycle": layout.cycle,
        "model": phasors.model,
        "series_terms": phasors.terms if phasors.model == "series" else 0,
        "time_samples": phasors.samples,
        "error_bound": float(phasors.error_bound),
        "error_bound_note": "bound on the normalised acceleration coefficients (force error per "
        "m_rec r omega^2) of the model used; see balance.core.accuracy",
        "speed_rpm": speed_rpm(layout.speed),
        "balance_version": __version__,
        "conventions": CONVENTIONS,
    }
    if layout.firing_order:  # numbers as numbers: an integer array, absent when not given
        attrs["firing_order"] = np.asarray(layout.firing_order, dtype=np.int64)
    data.update(_cylinder_variables(result))
    balanced = result.balanced
    if balanced is not None:
        assert result.residual_roll is not None  # a proposal needs the roll
        data.update(_proposal_variables(balanced, result.residual_roll, f1, m1, with_gas))
        attrs.update(_proposal_attrs(balanced))
    if not result.has_moments:
        data = {
            k: v
            for k, v in data.items()
            if not k.startswith(("reciprocating_moment", "rotating_moment"))
        }
    if result.torque is not None:
        torque = result.torque
        data.update(_torque_variables(torque))
        coords["crank_angle"] = xr.IndexVariable(
            ("crank_angle",),
            torque.crank_angle,
            attrs={"units": "deg", "long_name": "crank angle theta over the working cycle"},
        )
        attrs["gas_pressure_source"] = layout.gas.source if layout.gas is not None else ""
    if result.roll is None:  # roll not asked for
        coords = {k: v for k, v in coords.items() if k != "roll_order"}
    if result.mounts is not None:
        from balance.views.mounts import mounts_dataset_variables

        mount_data, mount_coords = mounts_dataset_variables(result.mounts)
        data.update(mount_data)
        coords.update(mount_coords)
    if result.bearings is not None:
        from balance.views.bearings import bearings_dataset_variables

        bearing_data, bearing_coords = bearings_dataset_variables(result.bearings)
        data.update(bearing_data)
        coords.update(bearing_coords)
    return xr.Dataset(data_vars=data, coords=coords, attrs=attrs)


def _cylinder_variables(result: Result) -> dict[str, xr.Variable]:
    """Each cylinder's actual stroke and TDC angle, and its link rod (CONTRACT §4–5)."""
    out: dict[str, xr.Variable] = {}
    if result.cylinder_stroke is not None and result.cylinder_tdc is not None:
        out["cylinder_stroke"] = _var(
            ("cylinder",),
            result.cylinder_stroke,
            "m",
            "piston travel between its dead centres",
        )
        out["tdc_crank_angle"] = _var(
            ("cylinder",),
            np.degrees(result.cylinder_tdc),
            "deg",
            "crank angle at which the piston is farthest from the crank axis",
        )
    links = result.engine.links
    if links is not None:
        linked = links.master >= 0
        out["link_master"] = _var(
            ("cylinder",),
            np.where(linked, links.master + 1, 0),
            "1",
            "number of the cylinder whose rod carries this cylinder's link rod (0: none)",
        )
        out["link_pin_radius"] = _var(
            ("cylinder",),
            np.where(linked, links.pin_radius, np.nan),
            "m",
            "distance of the link pin from the crank-pin centre on the master rod",
        )
        out["link_pin_angle"] = _var(
            ("cylinder",),
            np.where(linked, np.degrees(links.pin_angle), np.nan),
            "deg",
            "direction of the link pin from the master rod's centre line",
        )
    return out


def _proposal_attrs(balanced: Balanced) -> dict[str, Any]:
    proposal = balanced.proposal
    factor = proposal.balance_factor
    attrs: dict[str, Any] = {
        "proposal_strategy": proposal.strategy,
        "proposal_orders": np.asarray(proposal.orders, dtype=np.int64),
        "proposal_cancel_roll": int(proposal.cancel_roll),
        "proposal_notes": "; ".join(proposal.notes),
    }
    if factor is not None:  # a number, present only when a balance factor was given
        attrs["proposal_balance_factor"] = float(factor)
    return attrs


def _roll_variables(
    roll: NDArray[np.complex128] | None, reference_roll: float, with_gas: bool
) -> dict[str, xr.Variable]:
    """The roll per roll order (nothing when the roll was not asked for)."""
    if roll is None:
        return {}
    gas = " with gas forces" if with_gas else ""
    return {
        "roll_amplitude": _var(
            ("roll_order",),
            np.abs(roll),
            "N m",
            f"amplitude of the roll torque on the block{gas} (sum of a_k cos(k theta + phase_k))",
        ),
        "roll_phase": _var(
            ("roll_order",),
            phase_deg(roll),
            "deg",
            "phase of the roll torque, positive in the direction of rotation",
        ),
        "roll_amplitude_normalised": _var(
            ("roll_order",),
            safe_ratio(np.abs(roll), reference_roll),
            "1",
            "roll torque amplitude per m_rec r^2 omega^2",
        ),
    }


def _proposal_variables(
    balanced: Balanced,
    residual_roll: NDArray[np.complex128],
    f1: float,
    m1: float,
    with_gas: bool,
) -> dict[str, xr.Variable]:
    proposal = balanced.proposal
    cws = proposal.counterweights
    shafts = proposal.shafts
    n_planes = max((len(s.planes) for s in shafts), default=0)
    plane_z = np.full((len(shafts), n_planes), np.nan)
    plane_u = np.full((len(shafts), n_planes), np.nan + 0j)
    for i, shaft in enumerate(shafts):
        for j, (z, u) in enumerate(shaft.planes):
            plane_z[i, j] = z
            plane_u[i, j] = u
    force = np.stack([balanced.force_forward, balanced.force_backward], axis=-1)
    moment = np.stack([balanced.moment_forward, balanced.moment_backward], axis=-1)
    force_peak = np.abs(force).sum(axis=-1)
    moment_peak = np.abs(moment).sum(axis=-1)
    cw_u = np.array([c.unbalance for c in cws], dtype=np.complex128)
    gas = "gas forces and " if with_gas else ""
    return {
        "counterweight_z": _var(
            ("counterweight",), [c.z for c in cws], "m", "axial plane of the proposed counterweight"
        ),
        "counterweight_mass": _var(
            ("counterweight",),
            [c.mass for c in cws],
            "kg",
            "counterweight mass at counterweight_radius",
        ),
        "counterweight_radius": _var(
            ("counterweight",),
            [c.radius for c in cws],
            "m",
            "radius of the counterweight's centre of gravity",
        ),
        "counterweight_angle": _var(
            ("counterweight",),
            [c.angle_deg for c in cws],
            "deg",
            "counterweight angle at crank angle 0, turning with the crank",
        ),
        "counterweight_unbalance": _var(
            ("counterweight",), np.abs(cw_u), "kg m", "counterweight mass times radius"
        ),
        "shaft_speed_ratio": _var(
            ("shaft",),
            [s.speed_ratio for s in shafts],
            "1",
            "balance shaft speed over crank speed (negative: against it)",
        ),
        "shaft_x": _var(("shaft",), [s.x for s in shafts], "m", "balance shaft axis, x"),
        "shaft_y": _var(("shaft",), [s.y for s in shafts], "m", "balance shaft axis, y"),
        "shaft_plane_z": _var(
            ("shaft", "shaft_plane"), plane_z, "m", "axial plane of the shaft's eccentric mass"
        ),
        "shaft_plane_unbalance": _var(
            ("shaft", "shaft_plane"), np.abs(plane_u), "kg m", "eccentric mass times eccentricity"
        ),
        "shaft_plane_angle": _var(
            ("shaft", "shaft_plane"),
            phase_deg(plane_u),
            "deg",
            "eccentric angle at crank angle 0 (it sits at angle + speed_ratio * theta)",
        ),
        "residual_force_magnitude": _var(
            ("order", "rotation"),
            np.abs(force),
            "N",
            "residual force phasor magnitude with the proposal",
        ),
        "residual_force_phase": _var(
            ("order", "rotation"),
            phase_deg(force),
            "deg",
            "residual force phasor phase at crank angle 0",
        ),
        "residual_force_peak": _var(
            ("order",), force_peak, "N", "peak residual force (reciprocating + rotating + proposal)"
        ),
        "residual_force_peak_normalised": _var(
            ("order",), safe_ratio(force_peak, f1), "1", "peak residual force per m_rec r omega^2"
        ),
        "residual_moment_magnitude": _var(
            ("order", "rotation"),
            np.abs(moment),
            "N m",
            "residual moment phasor magnitude with the proposal",
        ),
        "residual_moment_phase": _var(
            ("order", "rotation"),
            phase_deg(moment),
            "deg",
            "residual moment phasor phase at crank angle 0",
        ),
        "residual_moment_peak": _var(
            ("order",),
            moment_peak,
            "N m",
            "peak residual moment (reciprocating + rotating + proposal)",
        ),
        "residual_moment_peak_normalised": _var(
            ("order",),
            safe_ratio(moment_peak, m1),
            "1",
            "peak residual moment per m_rec r omega^2 a",
        ),
        "residual_roll_amplitude": _var(
            ("roll_order",),
            np.abs(residual_roll),
            "N m",
            f"roll torque amplitude with {gas}the proposed shafts",
        ),
        "residual_roll_phase": _var(
            ("roll_order",),
            phase_deg(residual_roll),
            "deg",
            f"roll torque phase with {gas}the proposed shafts",
        ),
    }


def _torque_variables(t: TorqueResult) -> dict[str, xr.Variable]:
    """Forces over the cycle and the torque summary of a layout with gas forces."""
    per = ("cylinder", "crank_angle")
    out = {
        "gas_pressure": _var(per, t.pressure, "Pa", "absolute cylinder pressure"),
        "gas_force": _var(
            per, t.gas_force, "N", "gas force (p - p0) A on the piston, to the crank"
        ),
        "inertia_force": _var(
            per, t.inertia_force, "N", "reciprocating inertia force on the piston pin, to the crank"
        ),
        "piston_force": _var(
            per, t.piston_force, "N", "total force P along the bore on the piston pin, to the crank"
        ),
        "side_thrust": _var(
            per,
            t.side_thrust,
            "N",
            "side thrust N of the piston on the wall (P tan psi and the rod's inertia couple)",
        ),
        "rod_force": _var(
            per, t.rod_force, "N", "rod force S along the rod at the piston pin (compression +)"
        ),
        "tangential_force": _var(
            per, t.tangential_force, "N", "tangential force T on the crank pin (with rotation +)"
        ),
        "radial_force": _var(
            per, t.radial_force, "N", "radial force K on the crank pin (to the axis +)"
        ),
        "cylinder_torque": _var(per, t.cylinder_torque, "N m", "torque T r of one cylinder"),
        "engine_torque": _var(
            ("crank_angle",), t.engine_torque, "N m", "engine torque on the crankshaft (sum)"
        ),
        "roll_torque": _var(
            ("crank_angle",),
            t.roll_torque,
            "N m",
            "roll torque on the block with gas forces, positive in the direction of rotation",
        ),
        "firing_tdc": _var(
            ("cylinder",), t.firing_tdc, "deg", "crank angle of the cylinder's firing TDC"
        ),
        "torque_mean": _var((), t.mean, "N m", "mean engine torque over the cycle"),
        "torque_max": _var((), t.maximum, "N m", "largest engine torque over the cycle"),
        "torque_min": _var((), t.minimum, "N m", "smallest engine torque over the cycle"),
        "torque_nonuniformity": _var(
            (), t.nonuniformity, "1", "torque non-uniformity (M_max - M_min) / M_mean"
        ),
        "excess_work": _var(
            (), t.excess_work, "J", "largest excess work: max - min of the integral of M - M_mean"
        ),
        "speed_fluctuation": _var(
            (), t.speed_fluctuation, "1", "speed fluctuation (w_max - w_min) / w_mean"
        ),
        "flywheel_inertia": _var(
            (), t.flywheel_inertia, "kg m2", "moment of inertia of the rotating assembly"
        ),
        "indicated_work": _var(
            (),
            t.mean * 2.0 * math.pi * t.cycle_deg / 360.0,
            "J",
            "indicated work of the engine per cycle (mean torque times cycle angle)",
        ),
    }
    return out
