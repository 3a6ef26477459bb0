"""Sphinx extension: the figure gallery of a few built-in layouts, drawn at build time.

When the builder starts (``builder-inited``) every figure kind of :mod:`balance.views.plots`
that applies (:func:`balance.views.plots.applicable_kinds`) is drawn for each layout of
:data:`LAYOUTS` (the :class:`~balance.core.result.Result` of
:func:`balance.core.analysis.compute` with the request given there: balancing proposals,
bearing loads, gas forces, mounts) into ``_generated/gallery/<layout>-<kind>.png`` under
the documentation source, and the MyST page ``_generated/gallery.md`` that shows them is
written; ``gallery.md`` includes it.  Between them the layouts show every kind.

The output is deterministic: the same package gives the same bytes, and a file is only
rewritten when its content changes, so that Sphinx does not rebuild pages for nothing.
``_generated`` is added to ``exclude_patterns`` (it is included, not a page of its own).

Enable it in ``conf.py`` with::

    sys.path.insert(0, os.path.abspath("_ext"))
    extensions = [..., "gallery"]
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any

#: Built-in layouts shown in the gallery, in order, each with the settings of its
#: :class:`~balance.core.result.Request` (orders 1 to 8) and, optionally, the kinds shown
#: (default: every kind that applies).  A kind is drawn only where it has something to show.
LAYOUTS: tuple[tuple[str, dict[str, bool], tuple[str, ...] | None], ...] = (
    ("inline-4", {"bearings": True}, None),
    ("inline-3", {"bearings": True}, None),
    ("v8-crossplane", {"bearings": True}, None),
    ("inline-4-gas", {}, ("torque", "forces")),
    ("inline-4-mounts", {"mounts": True}, ("mounts",)),
    ("single-idle", {}, ("crank_speed", "reduced_inertia", "speed_model_orders")),
    ("inline-6-diesel-torsion", {}, ("torsion_campbell", "torsion_modes", "torsion_response")),
    # several crankshafts (docs/several-crankshafts.md); the crank star draws every shaft's
    # throws about one centre
    ("jumo-205", {}, None),
    # (its torque plot's legend of 36 pistons leaves the axes no room: not shown)
    ("deltic-18", {}, ("crank_star", "phasors", "crank_angle", "spectrum", "roll", "forces")),
    ("twin-crank-2", {}, None),
    ("h16-brm", {}, None),
)

#: Where the gallery goes, relative to the documentation source directory.
GENERATED = "_generated"

#: What each figure shows, for its caption.
CAPTIONS = {
    "crank_star": "Crank star: throws and banks seen from the front (+y up, +x right, the "
    "crank turning clockwise).",
    "phasors": "Force and moment phasors at crank angle 0, one panel per order, each on its "
    "own scale: forward (wide) turns with the crank, backward (dashed) against it.",
    "crank_angle": "Vertical and horizontal force and the pitch and yaw couples over one "
    "revolution, per order and in total.",
    "locus": "Path of the force and moment vectors in the transverse plane over a revolution: "
    "an ellipse per order, and their sum.",
    "spectrum": "Peak force and peak moment of each order.",
    "roll": "Roll torque on the block over a revolution, and its amplitude per order.",
    "balance": "Force, moment and roll before and after the proposed counterweights and "
    "balance shafts.",
    "torque": "With gas forces: the torque of each cylinder and the engine torque over the "
    "working cycle, with the mean.",
    "forces": "With gas forces: the forces on cylinder 1's crank train over the cycle "
    "(piston force P split into gas and inertia, side force N, rod force S, tangential T, "
    "radial K).",
    "mounts": "On its mounts: the largest mount force of each order against speed, with the "
    "speeds where an order meets a rigid-body mode.",
    "pin_load": "Crank-pin load in the crank-fixed frame (up: outwards along the throw), "
    "one diagram per different pin.",
    "main_loads": "Main-bearing loads in the engine frame, without and with the proposed "
    "counterweights.",
    "internal_moment": "The crankshaft's largest internal bending moment at each main, "
    "without and with the proposed counterweights.",
    "crank_speed": "Variable speed: the crank speed over the cycle under the layout's load, "
    "with the constant-speed line.",
    "reduced_inertia": "Variable speed: the reduced inertia J(theta) of the crank train and "
    "its slope.",
    "speed_model_orders": "Variable speed: per order, the free force and roll under the "
    "constant and the dynamic speed model.",
    "torsion_campbell": "Torsion: natural frequencies against speed with the order lines "
    "(major orders heavier) and the resonances with their vector sums.",
    "torsion_modes": "Torsion: the shapes of the lowest modes, +1 at the free end.",
    "torsion_response": "Torsion: free-end angle and the most loaded section against speed, "
    "per order and synthesised (half range over the cycle).",
}


def _write_if_changed(path: Path, data: bytes) -> bool:
    """Write ``data`` to ``path`` atomically unless the file already holds it."""
    if path.exists() and path.read_bytes() == data:
        return False
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    try:
        with os.fdopen(handle, "wb") as tmp:
            tmp.write(data)
        os.chmod(tmp_name, 0o644)
        os.replace(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return True


def _page(sections: list[tuple[str, str, str, list[str]]]) -> str:
    """The MyST text of the gallery: per layout a heading, a line, and its figures."""
    lines = [
        "<!-- generated by docs/_ext/gallery.py at build time; do not edit -->",
        "",
    ]
    for name, title, summary, kinds in sections:
        lines += [
            f"## {title}",
            "",
            f"Built-in layout `{name}`; {summary}.",
            "",
        ]
        for kind in kinds:
            lines += [
                f"```{{figure}} /{GENERATED}/gallery/{name}-{kind}.png",
                f":alt: {kind.replace('_', ' ')} of {title}",
                ":width: 100%",
                "",
                f"`{kind}`: {CAPTIONS.get(kind, '')}",
                "```",
                "",
            ]
    return "\n".join(lines)


def generate(srcdir: str | os.PathLike[str]) -> list[Path]:
    """Draw the gallery's figures and write its page under ``srcdir``.

    Parameters
    ----------
    srcdir : path
        The documentation source directory.

    Returns
    -------
    list of Path
        The files that were (re)written; empty when everything was up to date.
    """
    import balance
    from balance.core.analysis import compute
    from balance.io.request import build_request
    from balance.views.plots import applicable_kinds, figure_bytes, plot_kind
    from balance.views.proposal import proposal_summary

    root = Path(srcdir) / GENERATED
    written = []
    sections = []
    for name, settings, shown in LAYOUTS:
        layout = balance.load_layout(name)
        result = compute(layout, build_request(layout, range(1, 9), figures=True, **settings))
        kinds = [k for k in applicable_kinds(result) if shown is None or k in shown]
        for kind in kinds:
            path = root / "gallery" / f"{name}-{kind}.png"
            if _write_if_changed(path, figure_bytes(plot_kind(kind)(result), "png")):
                written.append(path)
        sections.append((name, result.engine.name, proposal_summary(result), kinds))
    page = root / "gallery.md"
    if _write_if_changed(page, _page(sections).encode("utf-8")):
        written.append(page)
    return written


def _builder_inited(app: Any) -> None:
    from sphinx.util import logging

    written = generate(app.srcdir)
    logging.getLogger(__name__).info(
        f"gallery: {len(written)} file(s) written under {GENERATED}/"
        if written
        else "gallery: up to date"
    )


def _config_inited(app: Any, config: Any) -> None:
    pattern = f"{GENERATED}/**"
    if pattern not in config.exclude_patterns:
        config.exclude_patterns = [*config.exclude_patterns, pattern]


def setup(app: Any) -> dict[str, Any]:
    """Register the extension with Sphinx."""
    app.connect("config-inited", _config_inited)
    app.connect("builder-inited", _builder_inited)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
