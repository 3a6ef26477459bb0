"""Limits of the input that several readers share (docs/layout-format.md, "Limits").

A module of its own, importing nothing, so that the layout file's schema
(:mod:`balance.io.schema`) and the command line's fields (:mod:`balance.io.fields`) read
the same number without importing each other.
"""

from __future__ import annotations

__all__ = ["MAX_ORDER"]

#: Highest harmonic order that can be asked for (``--orders``, ``balance: orders:``).  The
#: inertia forces' coefficients of orders above about 30 are below double-precision rounding
#: at every rod ratio an engine has (they fall off geometrically with the order), so the
#: bound only keeps a mistyped range from making every output that many rows long.
MAX_ORDER = 1000
