"""What ``import balance`` offers: load a layout, analyse it into an xarray Dataset.

The command line (:mod:`balance.cli`) and the Python API both go through
:func:`balance.core.analysis.compute`; :func:`analyse` hands its result to the Dataset view
(:mod:`balance.views.dataset`).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from balance.core.analysis import compute
from balance.core.engine import Engine
from balance.core.result import Request
from balance.io.fields import check_speed, parse_orders
from balance.io.layout_file import builtin_layout_names, load_layout

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

__all__ = ["Engine", "Layout", "analyse", "builtin_layout_names", "load_layout"]

#: The engine as loaded from a layout file (the name used before the package had layers).
Layout = Engine


def analyse(
    layout: Engine,
    orders: int | str | Iterable[int] | None = None,
    *,
    speed: float | None = None,
    model: str = "exact",
    terms: int = 3,
    samples: int | None = None,
    tolerance: float | None = None,
    moments: bool = True,
    roll: bool = True,
    proposal: bool = True,
    cancel: Iterable[int] | None = None,
    strategy: str | None = None,
    balance_factor: float | None = None,
    counterweight_radius: float | None = None,
    cancel_roll: bool = False,
) -> xr.Dataset:
    r"""Analyse a layout: free forces, moments, rotating forces and roll per order.

    Parameters
    ----------
    layout : Engine
        The engine (:func:`balance.load_layout`).
    orders : int, str or sequence of int, optional
        Orders to report; default 1 to 8.
    speed : float, optional
        Crank speed [rad/s] instead of the layout's.  A Python number here is SI (rad/s);
        only text (layout files, the command line) must carry its unit.
    model : {'exact', 'series', 'textbook', 'time'}
        Piston acceleration model; ``exact`` is accurate to machine precision; ``time``
        synthesises the forces over crank angle (see :func:`compute`).
    terms : int
        Binomial terms for the ``series`` model.
    samples : int, optional
        Crank angles per revolution of the ``time`` model.
    tolerance : float, optional
        Instead of a model: the largest error allowed in the normalised coefficients (force
        error per :math:`m_{rec} r\omega^2`); the cheapest model that meets it is used
        (:func:`balance.core.accuracy.choose_model`) and recorded with its error bound.
    moments, roll : bool
        Whether to compute the moments and the roll torque.
    proposal : bool
        Propose counterweights and balance shafts and report the residual (needs moments
        and roll).
    cancel, strategy, balance_factor, counterweight_radius, cancel_roll
        Proposal settings (see :func:`balance_engine`); by default from the layout's
        ``balance:`` section.  Numbers are SI: ``balance_factor`` a fraction [1],
        ``counterweight_radius`` [m].

    Returns
    -------
    xarray.Dataset
        Every variable carries ``units`` and ``long_name``; see :mod:`balance.views.dataset`.
        With a ``gas:`` section the Dataset also holds the forces and torque over the cycle
        (dimension ``crank_angle``), the torque summary, and the roll with gas forces, in
        half orders for a four-stroke (:mod:`balance.core.torque`).

    Examples
    --------
    >>> import balance
    >>> ds = balance.analyse(balance.load_layout("inline-4"), orders=2)
    >>> float(ds.reciprocating_force_peak_normalised.sel(order=2)) > 1.0
    True
    """
    from balance.views.dataset import build_dataset

    if speed is not None:
        speed = check_speed(speed)
    request = Request.of(
        parse_orders(orders),
        model=model,
        terms=terms,
        samples=samples,
        tolerance=tolerance,
        speed=speed,
        moments=moments,
        roll=roll,
        proposal=proposal,
        cancel=None if cancel is None else tuple(int(k) for k in cancel),
        strategy=strategy,
        balance_factor=balance_factor,
        counterweight_radius=counterweight_radius,
        cancel_roll=cancel_roll,
    )
    result = compute(layout, request)
    return build_dataset(result)
