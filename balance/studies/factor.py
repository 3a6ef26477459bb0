"""Studies built on the analysis: the balance-factor trade-off of singles and twins."""

from __future__ import annotations

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from balance.core.balancing import balance_factor_study, optimal_balance_factor
from balance.core.engine import Engine
from balance.core.kinematics import acceleration_coefficients

__all__ = ["factor_study_dataset"]


def factor_study_dataset(layout: Engine, factors: ArrayLike | None = None) -> xr.Dataset:
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
        the larger of the two force peaks smallest.
    """
    f = np.linspace(0.0, 1.0, 21) if factors is None else np.asarray(factors, dtype=np.float64)
    r = layout.crank_radius
    g1 = acceleration_coefficients(r / layout.conrod_length, layout.offset / r, [1])[..., 0]
    study = balance_factor_study(layout, g1, f)
    best = optimal_balance_factor(layout, g1)

    def var(data: ArrayLike, units: str, long_name: str) -> xr.Variable:
        return xr.Variable(
            ("study_factor",), np.asarray(data), attrs={"units": units, "long_name": long_name}
        )

    return xr.Dataset(
        {
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
