"""The result Dataset, a view of the :class:`~balance.core.result.Result`.

:func:`build_dataset` builds the ``xarray.Dataset`` of the Python API and the netCDF writer
from the output catalogue (:mod:`balance.core.catalogue`): every output a result has, the
free forces' and those of every section it holds, with ``units`` and ``long_name``.  JSON,
CSV and the table read the ``Result`` through the same catalogue and do not go through the
Dataset.

The variables of an analysis (every one has ``units`` and ``long_name``):

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

and those of the sections (the proposal's ``counterweight_*``, ``shaft_*`` and
``residual_*``, the gas torque's, the bearing loads', the mounts'; docs/api.md lists them).
Phases are in degrees in [0, 360), measured from +y in the direction of rotation at
crank angle 0; a phasor of zero magnitude has phase 0.  Normalised values are per
``reference_force`` :math:`F_1 = m_{rec} r \\omega^2` (engine means) and, for moments, per
``reference_moment`` :math:`F_1 a` with ``a`` the cylinder pitch.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from balance.core.catalogue import Output, outputs_of

if TYPE_CHECKING:  # pragma: no cover
    from balance.core.result import Result

__all__ = ["build_dataset", "variable"]


def variable(output: Output, data: Any, result: Any, dims: tuple[str, ...] = ()) -> xr.Variable:
    """A variable with the output's ``units`` and ``long_name``.

    The data are always numpy arrays here, so xarray's fast path is safe; it also spares a
    probe for duck-array libraries that would import dask or pint on a cold start.

    Parameters
    ----------
    output : Output
        The output (:class:`balance.core.catalogue.Output`): its dimensions, units and
        ``long_name``.
    data : array_like
        The values, shaped ``dims`` then the output's own dimensions.
    result : Result
        The analysis, for a ``long_name`` that depends on it.
    dims : tuple of str
        Dimensions in front of the output's own (a sweep's grid).

    Returns
    -------
    xarray.Variable
    """
    return xr.Variable(
        (*dims, *output.dims),
        np.asarray(data),
        attrs={"units": output.units, "long_name": output.describe(result)},
        fastpath=True,
    )


def _coordinate(output: Output, data: Any, result: Any) -> xr.IndexVariable:
    """An index _coordinate built from a pandas Index.

    (Handing xarray a pandas Index spares it a duck-array check that imports pint, which
    would cost a cold start about 0.1 s.)
    """
    import pandas as pd

    (name,) = output.dims
    return xr.IndexVariable(
        (name,),
        pd.Index(np.asarray(data), name=name),
        attrs={"units": output.units, "long_name": output.describe(result)},
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
        Every output of the result (:func:`balance.core.catalogue.outputs_of`): data
        variables and coordinates with ``units`` and ``long_name``, and the attributes
        (with ``balance_version``, the version that wrote it).
    """
    from balance._version import __version__

    data: dict[str, xr.Variable] = {}
    coords: dict[str, xr.IndexVariable] = {}
    attrs: dict[str, Any] = {"balance_version": __version__}
    for output in outputs_of(result):
        value = output.get(result)
        if output.kind == "attr":
            attrs[output.name] = value
        elif output.kind == "coord":
            coords[output.name] = _coordinate(output, value, result)
        else:
            data[output.name] = variable(output, value, result)
    return xr.Dataset(data_vars=data, coords=coords, attrs=attrs)
