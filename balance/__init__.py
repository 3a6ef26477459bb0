"""balance: engine balancing analyser.

>>> import balance
>>> layout = balance.load_layout("inline-4")
>>> ds = balance.analyse(layout)

Importing the package is cheap: the modules load when first used.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

from balance._version import __version__

__all__ = [
    "AnalysisError",
    "BalanceError",
    "Engine",
    "InputError",
    "LayoutError",
    "__version__",
    "analyse",
    "builtin_layout_names",
    "compute_result",
    "load_layout",
]

_LAZY = {
    "analyse": "balance.api",
    "load_layout": "balance.api",
    "builtin_layout_names": "balance.api",
    "Engine": "balance.api",
    "compute_result": "balance.api",
    "AnalysisError": "balance.core.errors",
    "BalanceError": "balance.core.errors",
    "InputError": "balance.core.errors",
    "LayoutError": "balance.core.errors",
}

if TYPE_CHECKING:  # pragma: no cover
    from balance.api import Engine, analyse, builtin_layout_names, compute_result, load_layout
    from balance.core.errors import AnalysisError, BalanceError, InputError, LayoutError


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'balance' has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
