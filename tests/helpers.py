"""Helpers shared by the tests."""

from __future__ import annotations

import functools
import importlib.util
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import pytest

from balance.api import Engine
from balance.io.layout_file import layout_from_dict

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def needs(module: str, extra: str) -> pytest.MarkDecorator:
    """Skip a test, saying why, only when ``module`` is not installed: a package of the
    ``extra`` extra that the ``test`` extra does not install (README, "Development")."""
    return pytest.mark.skipif(
        importlib.util.find_spec(module) is None,
        reason=f"needs {module}, not installed (pip install '.[{extra}]')",
    )


def _with_unit(value: float | str, unit: str) -> str:
    """A number as layout text in ``unit`` (``repr`` round-trips it exactly); text as it is."""
    return value if isinstance(value, str) else f"{value!r} {unit}"


def engine(
    throws: list[float],
    banks: list[float] | None = None,
    *,
    spacing: float | str = 0.09,
    stroke: float | str = 0.086,
    conrod_length: float | str = 0.143,
    reciprocating: float | str = 0.6,
    rotating: float | str = 0.4,
    speed: str = "6000 rpm",
    **extra: Any,
) -> Engine:
    """A layout in the compact form, for tests (angles in degrees; a number for a length is
    metres and for a mass kilograms, written into the layout with its unit, since a layout
    file refuses bare dimensional numbers)."""
    spacing, stroke, conrod_length = (_with_unit(v, "m") for v in (spacing, stroke, conrod_length))
    reciprocating, rotating = (_with_unit(v, "kg") for v in (reciprocating, rotating))
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
    for section, unit in (("geometry", "m"), ("masses", "kg")):
        if section in extra:
            extra[section] = {k: _with_unit(v, unit) for k, v in extra[section].items()}
    data.update(extra)
    return layout_from_dict(data)


_compared = pytest.mark.mpl_image_compare(baseline_dir="baseline", tolerance=2, style="default")


def image_compare(test: Callable[..., Figure]) -> Callable[..., Figure]:
    """Image comparison against tests/baseline (pytest-mpl is a test dependency and ``--mpl``
    is in the pytest options, so a missing plugin is an error, not a silent skip).

    The figure is laid out before pytest-mpl saves it, as ``balance.views.plots.figure_bytes``
    does: savefig would lay out a figure with a layout engine in a draw of its own (without
    output) before the draw that writes it.  The pixels are the same, byte for byte.
    """

    @functools.wraps(test)
    def laid_out(*args: Any, **kwargs: Any) -> Figure:
        from matplotlib.backend_bases import FigureCanvasBase
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        fig = test(*args, **kwargs)
        engine = fig.get_layout_engine()
        if engine is not None:
            if type(fig.canvas) is FigureCanvasBase:
                FigureCanvasAgg(fig)  # the renderer the PNG is written with
            engine.execute(fig)
            fig.set_layout_engine(None)  # pytest-mpl's style sets no autolayout
        return fig

    return _compared(laid_out)


def draw_only(monkeypatch: pytest.MonkeyPatch, kinds: tuple[str, ...] = ()) -> list[str]:
    """Let ``balance plot`` (and :func:`balance.views.plots.save_plots`) build every figure
    it chooses but render only those of ``kinds`` to bytes; the others are written as a
    stub. For the tests of which kinds a command writes: the rendering of every kind is
    tested where the kind is (the image tests, the reports). Returns the kinds rendered, in
    order, filled as the command runs."""
    from balance.views import plots

    rendered: list[str] = []
    plot_kind, figure_bytes = plots.plot_kind, plots.figure_bytes

    def tagged(kind: str) -> Callable[..., Figure]:
        function = plot_kind(kind)

        @functools.wraps(function)
        def draw(*args: Any, **kwargs: Any) -> Figure:
            fig = function(*args, **kwargs)
            fig.balance_test_kind = kind  # type: ignore[attr-defined]
            return fig

        return draw

    def render(fig: Figure, fmt: str = "png") -> bytes:
        kind = getattr(fig, "balance_test_kind", None)
        if kind in kinds:
            rendered.append(kind)
            return figure_bytes(fig, fmt)
        return b"not drawn by this test"

    monkeypatch.setattr(plots, "plot_kind", tagged)
    monkeypatch.setattr(plots, "figure_bytes", render)
    return rendered
