"""Views of a :class:`~balance.core.result.Result`: Dataset (API, netCDF), JSON, CSV, table...

Each view reads the Result directly; only :mod:`balance.views.dataset` imports xarray.
"""
