"""balance: engine balancing analyser.

>>> import balance
>>> layout = balance.load_layout("inline-4")
>>> ds = balance.analyse(layout)

Importing the package is cheap: the modules load when first used.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

__all__ = [
    "AnalysisError",
    "BalanceError",
    "InputError",
    "Layout",
    "LayoutError",
    "__version__",
    "analyse",
    "builtin_layout_names",
    "load_layout",
]

_LAZY = {
    "analyse": "balance.analysis",
    "load_layout": "balance.layout",
    "builtin_layout_names": "balance.layout",
    "Layout": "balance.layout",
    "AnalysisError": "balance.errors",
    "BalanceError": "balance.errors",
    "InputError": "balance.errors",
    "LayoutError": "balance.errors",
}

if TYPE_CHECKING:  # pragma: no cover
    from .analysis import analyse
    from .errors import AnalysisError, BalanceError, InputError, LayoutError
    from .layout import Layout, builtin_layout_names, load_layout


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'balance' has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
