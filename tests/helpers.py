"""Helpers shared by the tests."""

from __future__ import annotations

from typing import Any

import pytest

from balance.api import Layout
from balance.io.layout_file import layout_from_dict


def engine(
    throws: list[float],
    banks: list[float] | None = None,
    *,
    spacing: float = 0.09,
    stroke: float = 0.086,
    conrod_length: float = 0.143,
    reciprocating: float = 0.6,
    rotating: float = 0.4,
    speed: str = "6000 rpm",
    **extra: Any,
) -> Layout:
    """A layout in the compact form, for tests (angles in degrees, lengths in metres)."""
    crank: dict[str, Any] = {"throws": throws, "spacing": spacing}
    if banks is not None:
        crank["banks"] = banks
    crank.update(extra.pop("crank", {}))
    data: dict[str, Any] = {
        "name": "test engine",
        "speed": speed,
        "geometry": {"stroke": stroke, "conrod_length": conrod_length},
        "masses": {"reciprocating": reciprocating, "rotating": rotating},
        "crank": crank,
    }
    data.update(extra)
    return layout_from_dict(data)


#: Image comparison against tests/baseline (pytest-mpl is a test dependency and ``--mpl`` is in
#: the pytest options, so a missing plugin is an error, not a silent skip).
image_compare = pytest.mark.mpl_image_compare(baseline_dir="baseline", tolerance=2, style="default")
