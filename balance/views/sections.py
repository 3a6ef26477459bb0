"""How each section shows itself: the registry of the section views.

Every section of an analysis (:mod:`balance.core.sections`) has one module of views here,
named in :data:`VIEWS`.  Such a module may define

- ``json_block(result) -> dict``: the keys it adds to the analysis JSON;
- ``tables(result) -> list``: its rich renderables in the table view;
- ``csv_columns(result) -> list``: the ``(header, values)`` columns it adds to the
  per-order CSV, one value per order;
- ``REPORT_TITLE`` and ``report_section(result, figures) -> str``: its section of the HTML
  design review (with ``REPORT_ABSENT``, what the review says where the result lacks it);
- ``report_columns(result) -> list``: the ``(header, cells)`` columns it adds to the
  review's table of cylinders, one cell per cylinder;
- ``PLOTS``: a mapping of the figure kinds it draws to their functions
  (``function(result, **options) -> Figure``), and ``drawn(result) -> bool``: whether they
  have something to draw;
- ``phasor_layers(result, source)``: the parts whose phasors add up to the engine's (the
  legend's heading and each part's name and ``Phasors``, or None), which the ``phasors``
  figure draws head to tail in each order's panel
  (:func:`balance.views.phasor_plots.plot_phasors`).

The writers (:mod:`balance.views.json`, :mod:`balance.views.table`,
:mod:`balance.views.report`, :mod:`balance.views.plots`, :mod:`balance.views.phasor_plots`)
loop over :func:`views_of` and
never name a section.  A module is imported only when a result holds its section.
"""

from __future__ import annotations

from collections.abc import Iterator
from importlib import import_module
from types import ModuleType
from typing import Any

from balance.core.sections import names

__all__ = ["VIEWS", "view", "views_of"]

#: The views module of each section, by the section's name.
VIEWS: dict[str, str] = {
    "cylinders": "balance.views.cylinders",
    "torque": "balance.views.torque",
    "guide_forces": "balance.views.crosshead",
    "crankshafts": "balance.views.crankshafts",
    "dynamics": "balance.views.dynamics",
    "proposal": "balance.views.proposal",
    "factor_study": "balance.views.factor_study",
    "mounts": "balance.views.mounts",
    "bearings": "balance.views.bearings",
    "torsion": "balance.views.torsion",
}


def view(name: str) -> ModuleType:
    """The views module of a section.

    Parameters
    ----------
    name : str
        The section's name (a key of :data:`VIEWS`).

    Returns
    -------
    module
        Its views module, imported on first use.
    """
    return import_module(VIEWS[name])


def views_of(result: Any, only: tuple[str, ...] | None = None) -> Iterator[tuple[str, Any]]:
    """The views of each section a result holds, in section order
    (:func:`balance.core.sections.names`).

    Parameters
    ----------
    result : Result
        The analysis.
    only : tuple of str, optional
        Only these sections.

    Yields
    ------
    name : str
        The section's name.
    module : module
        Its views module.
    """
    for name in names():
        if name in result.parts and (only is None or name in only):
            yield name, view(name)
