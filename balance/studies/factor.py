"""Studies built on the analysis: the balance-factor trade-off of singles and twins."""

from __future__ import annotations

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike, NDArray

from balance.core.analysis import first_order_parts, speed_squared
from balance.core.balancing import balance_factor_study, optimal_balance_factor
from balance.core.engine import Engine
from balance.core.phasors import rounding_threshold

__all__ = ["factor_study_dataset"]


def factor_study_dataset(
    layout: Engine,
    factors: ArrayLike | None = None,
    *,
    bearings: bool = False,
    strategy: str | None = None,
    counterweight_radius: float | None = None,
) -> xr.Dataset:
    """Residual first-order force against balance factor, as a Dataset.

    Parameters
    ----------
    layout : Engine
    factors : array_like, optional
        Balance factors [1]; default 0 to 1 in steps of 0.05.

    Returns
    -------
    xarray.Dataset
        ``study_vertical_peak`` and ``study_horizontal_peak`` [N], ``study_moment_peak``
        [N m] over ``study_factor``, and ``optimal_balance_factor``: the factor that makes
        the larger of the two force peaks smallest.  With ``bearings``, also
        ``study_largest_main_load`` [N] and ``study_largest_internal_moment`` [N m]: the
        largest main-bearing load and internal moment with each factor's proposed
        counterweights (``strategy``, ``counterweight_radius`` as for the proposal).
    """
    f = np.linspace(0.0, 1.0, 21) if factors is None else np.asarray(factors, dtype=np.float64)
    g1, pins = first_order_parts(layout)  # pins: the link rods' (None without link rods)
    study = _zero_below_rounding(balance_factor_study(layout, g1, f, pins), layout, g1, f)
    best = optimal_balance_factor(layout, g1, pins)

    def var(data: ArrayLike, units: str, long_name: str) -> xr.Variable:
        return xr.Variable(
            ("study_factor",), np.asarray(data), attrs={"units": units, "long_name": long_name}
        )

    extra = {}
    if bearings:
        from balance.studies.factor_bearings import factor_bearing_loads

        main_max, moment_max = factor_bearing_loads(layout, f, strategy, counterweight_radius)
        extra = {
            "study_largest_main_load": var(
                main_max, "N", "largest main-bearing load with the proposed counterweights"
            ),
            "study_largest_internal_moment": var(
                moment_max, "N m", "largest internal moment with the proposed counterweights"
            ),
        }
    return xr.Dataset(
        {
            **extra,
            "study_vertical_peak": var(
                study["vertical_peak"], "N", "peak residual first-order force along y"
            ),
            "study_horizontal_peak": var(
                study["horizontal_peak"], "N", "peak residual first-order force along x"
            ),
            "study_moment_peak": var(
                study["moment_peak"], "N m", "peak residual first-order moment"
            ),
            "optimal_balance_factor": xr.Variable(
                (),
                best,
                attrs={
                    "units": "1",
                    "long_name": "balance factor minimising the larger first-order force peak",
                },
            ),
        },
        coords={"study_factor": var(f, "1", "share of reciprocating mass on the crank")},
    )


def _zero_below_rounding(
    study: dict[str, NDArray[np.float64]],
    layout: Engine,
    first_order: NDArray[np.complex128],
    factors: NDArray[np.float64],
) -> dict[str, NDArray[np.float64]]:
    r"""The study with the peaks that rounding cannot tell from zero set to 0.

    The rule of :func:`balance.core.phasors.cancel_to_zero`, which every phasor sum of an
    analysis follows: a residual peak is a sum of the :math:`2n` forward and backward
    terms of the n cylinders, whose magnitudes add up to
    :math:`S = \sum_i m_{rec,i} r_i \omega^2 (|g_{1,i}| + f)` for the force (times
    :math:`|z_i - z_{ref}|` for the moment); a peak at most
    :func:`balance.core.phasors.rounding_threshold` of :math:`S` and :math:`2n` terms is 0
    (an inline-4 prints 0, not 3.96e-12 N, at every factor).
    """
    rec = np.asarray(layout.reciprocating_mass * layout.crank_radius) * float(
        speed_squared(layout.speed)
    )
    size = rec[None, :] * (np.abs(first_order)[None, :] + factors[:, None])
    lever = np.abs(np.asarray(layout.z) - layout.reference_z)
    n_terms = 2 * layout.n_cylinders
    force_limit = rounding_threshold(size.sum(axis=1), n_terms)
    moment_limit = rounding_threshold((size * lever[None, :]).sum(axis=1), n_terms)
    out = dict(study)
    for name, bound in (
        ("vertical_peak", force_limit),
        ("horizontal_peak", force_limit),
        ("moment_peak", moment_limit),
    ):
        out[name] = np.where(study[name] <= bound, 0.0, study[name])
    return out
