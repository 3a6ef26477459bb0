"""What ``import balance`` offers: load a layout, analyse it into an xarray Dataset.

The command line (:mod:`balance.cli`) and the Python API go through the same front door,
:func:`balance.io.request.build_request`, and the same computation,
:func:`balance.core.analysis.compute`: :func:`analyse` can ask for everything the command
line can, and a layout's sections (``gas:``, ``bearings:``, ``mounts:``) turn their
concerns on in both.  :func:`analyse` hands the result to the Dataset view
(:mod:`balance.views.dataset`); :func:`compute_result` returns the
:class:`~balance.core.result.Result` itself, for the other views.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

from balance.core.analysis import compute
from balance.core.engine import Engine
from balance.io.layout_file import builtin_layout_names, load_layout
from balance.io.request import build_request

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

    from balance.core.result import Result

__all__ = ["Engine", "analyse", "builtin_layout_names", "compute_result", "load_layout"]


def compute_result(
    layout: Engine | str,
    orders: int | str | Iterable[int] | None = None,
    **settings: Any,
) -> Result:
    """Analyse a layout and return the :class:`~balance.core.result.Result` (complex
    phasors and one part per section), for the views that read it.

    Parameters
    ----------
    layout : Engine or str
        The engine (:func:`balance.load_layout`), or a layout file or built-in name.
    orders : int, str or sequence of int, optional
        Orders to report; default 1 to 8.
    **settings
        As :func:`analyse`.

    Returns
    -------
    Result
    """
    engine = load_layout(layout) if isinstance(layout, str) else layout
    return compute(engine, build_request(engine, orders, **settings))


def analyse(
    layout: Engine | str,
    orders: int | str | Iterable[int] | None = None,
    *,
    speed: float | None = None,
    model: str | None = None,
    terms: int = 3,
    samples: int | None = None,
    tolerance: float | None = None,
    moments: bool = True,
    roll: bool = True,
    **sections: Any,
) -> xr.Dataset:
    r"""Analyse a layout: free forces, moments, rotating forces and roll per order, and
    every section asked for or turned on by the layout.

    Parameters
    ----------
    layout : Engine or str
        The engine (:func:`balance.load_layout`), or a layout file or built-in name.
    orders : int, str or sequence of int, optional
        Orders to report: 1 to N for an int, ``"1-8"``, ``"1,2,4-6"`` or a list; default
        1 to 8.
    speed : float, optional
        Crank speed [rad/s] instead of the layout's.  A Python number here is SI (rad/s);
        only text (layout files, the command line) must carry its unit.
    model : {'exact', 'series', 'textbook', 'time'}, optional
        Piston acceleration model (default ``exact``, accurate to machine precision;
        ``time`` synthesises the forces over crank angle).
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
    **sections
        Each concern beyond the free forces, by name, with True, False or a mapping of its
        options, or its options by name (docs/api.md lists them):

        - ``proposal`` (on unless False; needs moments and roll): counterweights and
          balance shafts and the residual; options ``cancel`` (orders), ``strategy``
          (``'two-plane'``, ``'per-throw'``), ``balance_factor`` (a fraction of each
          cylinder's reciprocating mass, or with ``balance_factor_of='one-cylinder'`` of
          one cylinder's on each throw), ``counterweight_radius`` [m], ``cancel_roll``; by
          default from the layout's ``balance:`` section;
        - ``torque`` (on with a ``gas:`` section): forces and torque over the cycle, the
          roll with gas forces;
        - ``cylinders`` (on): each cylinder's stroke and TDC, its link rod;
        - ``factor_study``: the residual first order against the balance factor
          (option ``factors``);
        - ``bearings`` (on with a ``bearings:`` section): crank-pin and main-bearing loads
          (option ``strategies``: also with each counterweight strategy);
        - ``mounts`` (on with a ``mounts:`` section): the engine on its mounts (options
          ``with_proposal``, ``speeds`` [rad/s]);
        - ``dynamics`` (on with a ``dynamics:`` section, or ``speed_model='dynamic'``): the
          crank train's own periodic motion (options ``speed_model``, ``load``,
          ``flywheel``; docs/dynamics.md);
        - ``torsion`` (on with a ``torsion:`` section): torsional vibration of the crank
          train (options ``speeds`` [rad/s] or ``'sweep'`` for the default range, default
          the analysis speed alone; ``orders``; docs/torsion.md).

    Returns
    -------
    xarray.Dataset
        Every variable carries ``units`` and ``long_name``; see :mod:`balance.views.dataset`
        and the output catalogue (:mod:`balance.core.catalogue`).

    Raises
    ------
    InputError
        For an unknown keyword or a value out of range (one line naming it).

    Examples
    --------
    >>> import balance
    >>> ds = balance.analyse("inline-4", orders=2)
    >>> float(ds.reciprocating_force_peak_normalised.sel(order=2)) > 1.0
    True
    >>> "main_bearing_max_load" in balance.analyse("inline-4", bearings=True)
    True
    """
    from balance.views.dataset import build_dataset

    result = compute_result(
        layout,
        orders,
        speed=speed,
        model=model,
        terms=terms,
        samples=samples,
        tolerance=tolerance,
        moments=moments,
        roll=roll,
        **sections,
    )
    return build_dataset(result)
