"""Views of the result Dataset: JSON, CSV, netCDF and a rich table.

Each view only reads the Dataset built by :func:`balance.views.dataset.build_dataset`.
"""
