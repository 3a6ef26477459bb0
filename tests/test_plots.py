"""Figures: the synthesis behind them (numbers) and the figures themselves (pytest-mpl).

Image tests compare against ``tests/baseline/*.png`` when run with ``--mpl``; regenerate
the baselines (after checking the figures by eye) with::

    python -m pytest tests/test_plots.py --mpl-generate-path=tests/baseline
"""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np
import pytest
from helpers import engine, image_compare
from oracles import proposal_force_samples

import balance
from balance.core import sampled as timedomain
from balance.core.analysis import compute, compute_phasors
from balance.core.engine import Engine
from balance.core.errors import InputError
from balance.core.proposal import balance_engine
from balance.core.result import Result
from balance.io.request import build_request
from balance.views import plots
from balance.views import proposal as proposal_views
from balance.views import signals as synthesis
from balance.views.figures import significant_mask
from balance.views.torque import GAS_KINDS

#: The figure kinds of the bearing loads' section (balance.views.bearings).
BEARING_KINDS = ("pin_load", "main_loads", "internal_moment")
#: The figure kinds of the variable-speed analysis (balance.views.dynamics): drawn for a
#: result with the dynamic speed model's solution.
SPEED_MODEL_KINDS = ("crank_speed", "reduced_inertia", "speed_model_orders")
TORSION_KINDS = {"torsion_campbell", "torsion_modes", "torsion_response"}
#: The figure kinds of several crankshafts (balance.views.crankshafts).
CRANKSHAFT_KINDS = ("crankshaft_forces",)

ORDERS = 40
REL = 1e-9


def computed(layout: Engine, orders: int = 8, **settings: Any) -> Result:
    """The Result of orders 1 to ``orders`` (what the views read)."""
    return compute(layout, build_request(layout, range(1, orders + 1), **settings))


@cache
def analysed(name: str, orders: int = 8, proposal: bool = True):
    return computed(balance.load_layout(name), orders, proposal=proposal)


def offset_engine():
    """A V engine with offsets, uneven throws and a short rod: every order is present."""
    return engine(
        [0, 75, 200, 290],
        banks=[-30, 40],
        geometry={"stroke": 0.09, "conrod_length": 0.13, "offset": 0.006},
    )


LAYOUTS = {
    "inline-4": lambda: balance.load_layout("inline-4"),
    "inline-3": lambda: balance.load_layout("inline-3"),
    "v8-crossplane": lambda: balance.load_layout("v8-crossplane"),
    "v-twin-45": lambda: balance.load_layout("v-twin-45"),
    "offset-v8": offset_engine,
}


def _relative_error(got, expected):
    return float(np.max(np.abs(got - expected)) / np.max(np.abs(expected)))


# --------------------------------------------------------------------------- synthesis


@pytest.mark.parametrize("name", sorted(LAYOUTS))
@pytest.mark.parametrize("quantity", ["force", "moment"])
def test_sum_of_phasors_is_the_sampled_reciprocating_force(name, quantity, rng):
    """With 40 orders the phasors sum back to the brute-force force at any crank angle."""
    layout = LAYOUTS[name]()
    result = computed(layout, ORDERS, proposal=False)
    theta_deg = np.concatenate([[0.0, 90.0, 360.0], rng.uniform(-720.0, 720.0, 60)])
    orders, fwd, bwd = synthesis.phasors_of(result, quantity, "reciprocating")
    got = synthesis.phasor_signal(fwd, bwd, orders, theta_deg)
    expected = timedomain.reciprocating_force_samples(
        layout, np.radians(theta_deg), lever=quantity == "moment"
    )
    if np.max(np.abs(expected)) < 1e-9 * result.reference_force:
        assert np.max(np.abs(got)) < 1e-9 * result.reference_force
    else:
        assert _relative_error(got, expected) < REL


@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_free_and_residual_signals_match_the_sampled_forces(name, rng):
    """'free' adds the rotating masses, 'residual' every proposed mass as well."""
    layout = LAYOUTS[name]()
    result = computed(layout, ORDERS)
    proposal = balance_engine(layout, compute_phasors(layout, ORDERS)).proposal
    theta_deg = rng.uniform(0.0, 360.0, 50)
    theta = np.radians(theta_deg)
    for quantity, lever in (("force", False), ("moment", True)):
        free = timedomain.reciprocating_force_samples(layout, theta, lever)
        free = free + timedomain.rotating_force_samples(layout, theta, lever)
        residual = free + proposal_force_samples(proposal, layout, theta, lever)
        # relative to the force or moment, or to F1 (times the longest lever) where that is 0
        lever_arm = float(np.max(np.abs(layout.z - layout.reference_z))) if lever else 1.0
        scale = max(float(np.max(np.abs(free))), result.reference_force * lever_arm)
        got_free = synthesis.signal_of(result, theta_deg, quantity, "free")
        got_residual = synthesis.signal_of(result, theta_deg, quantity, "residual")
        assert np.max(np.abs(got_free - free)) <= REL * scale
        assert np.max(np.abs(got_residual - residual)) <= REL * scale


@pytest.mark.parametrize("name", ["inline-4", "v8-crossplane", "offset-v8"])
def test_roll_signal_is_the_newton_euler_roll(name, rng):
    layout = LAYOUTS[name]()
    result = computed(layout, ORDERS, proposal=False)
    theta_deg = rng.uniform(0.0, 360.0, 40)
    orders, roll = synthesis.roll_of(result)
    got = synthesis.roll_signal(roll, orders, theta_deg)
    expected = timedomain.roll_newton_euler(layout, np.radians(theta_deg))
    assert _relative_error(got, expected) < REL


def test_inline4_second_order_is_a_vertical_line():
    result = analysed("inline-4")
    theta = synthesis.crank_angle_grid(361)
    per_order = synthesis.signal_of(result, theta, "force", per_order=True)
    x, y = synthesis.transverse_components(per_order[1])
    assert np.max(np.abs(x)) < 1e-9 * np.max(np.abs(y))
    assert np.max(y) == pytest.approx(synthesis.peak_of(result, "force", "reciprocating")[1])


def test_crossplane_v8_first_order_moment_is_a_circle_turning_with_the_crank():
    result = analysed("v8-crossplane")
    theta = synthesis.crank_angle_grid(73)
    first = synthesis.signal_of(result, theta, "moment", per_order=True)[0]
    radius = np.abs(first)
    assert np.ptp(radius) < 1e-9 * radius.max()
    # forward: the angle grows with the crank angle, one turn per revolution
    turned = np.unwrap(np.angle(first))
    assert turned[-1] - turned[0] == pytest.approx(2 * np.pi)


def test_complex_plane_convention():
    """(x, y) is y + i x: a forward phasor at phase 90 deg (i) points along +x at theta 0."""
    q = synthesis.phasor_signal([1j], [0.0], [1], [0.0, 90.0])
    x, y = synthesis.transverse_components(q)
    np.testing.assert_allclose(x, [1.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(y, [0.0, -1.0], atol=1e-15)
    pitch, yaw = synthesis.couple_components(np.array([1.0 + 2.0j]))
    assert (pitch[0], yaw[0]) == (-1.0, 2.0)


def test_synthesis_checks_its_input():
    with pytest.raises(ValueError, match="one entry per order"):
        synthesis.phasor_signal([1.0, 2.0], [1.0], [1, 2], [0.0])
    with pytest.raises(ValueError, match="one entry per order"):
        synthesis.roll_signal([1.0, 2.0], [1.0], [0.0])
    with pytest.raises(ValueError, match="proposal"):
        synthesis.phasors_of(analysed("inline-4", proposal=False), "force", "residual")
    with pytest.raises(ValueError, match="proposal"):
        synthesis.roll_of(analysed("inline-4", proposal=False), residual=True)
    with pytest.raises(ValueError, match="quantity"):
        synthesis.phasors_of(analysed("inline-4"), "torque", "free")  # type: ignore[arg-type]
    assert synthesis.roll_span_deg([1.0, 2.0]) == 360.0
    assert synthesis.roll_span_deg([0.5, 1.0]) == 720.0


# --------------------------------------------------------------------------- figures


@image_compare
def test_crank_star_inline4():
    return plots.plot_crank_star(analysed("inline-4"))


@image_compare
def test_crank_star_v8_crossplane():
    return plots.plot_crank_star(analysed("v8-crossplane"))


@image_compare
def test_phasors_inline3():
    return plots.plot_phasors(analysed("inline-3"))


@image_compare
def test_phasors_v8_crossplane():
    return plots.plot_phasors(analysed("v8-crossplane"))


@image_compare
def test_crank_angle_inline3():
    return plots.plot_crank_angle(analysed("inline-3"))


@image_compare
def test_locus_inline4():
    return plots.plot_locus(analysed("inline-4"))


@image_compare
def test_locus_v8_crossplane():
    return plots.plot_locus(analysed("v8-crossplane"))


@image_compare
def test_spectrum_inline4_normalised():
    return plots.plot_spectrum(analysed("inline-4"), normalised=True)


@image_compare
def test_roll_inline4():
    return plots.plot_roll(analysed("inline-4"))


@image_compare
def test_balance_inline3():
    return proposal_views.plot_balance(analysed("inline-3"))


@image_compare
def test_balance_v8_crossplane():
    return proposal_views.plot_balance(analysed("v8-crossplane"))


@image_compare
def test_crank_star_deltic_like():
    """Several crankshafts: each shaft where it sits, its pins at theta = 0, its sense."""
    from tests.test_geared_brute_force import deltic_like

    return plots.plot_crank_star(computed(deltic_like()))


@image_compare
def test_crankshaft_forces_counter_rotating_pair():
    from tests.test_geared_brute_force import counter_rotating_pair

    return plots.plot_kind("crankshaft_forces")(computed(counter_rotating_pair(1.0)))


def test_crankshaft_forces_draw_each_shafts_force_at_its_axis():
    """The locus of each shaft, less its axis and over the drawing's scale, is the shaft's
    free force synthesised from its phasors; the crank star puts each pin at its alpha(0)."""
    from tests.test_geared_brute_force import counter_rotating_pair

    result = computed(counter_rotating_pair(1.0))
    part = result.part("crankshafts")
    fig = plots.plot_kind("crankshaft_forces")(result)
    axes = fig.axes[0]
    loci = {line.get_label(): line for line in axes.lines if line.get_label() in part.names}
    free = part.force.free()
    theta = np.radians(np.linspace(0.0, 360.0, 361))
    turn = np.exp(1j * free.orders[:, None] * theta)
    peaks = []
    drawn = []
    for s, name in enumerate(part.names):
        force = free.force_forward[s] @ turn + free.force_backward[s] @ np.conj(turn)
        x, y = loci[name].get_data()
        drawn.append((np.asarray(x) - part.x[s] * 1e3) + 1j * (np.asarray(y) - part.y[s] * 1e3))
        peaks.append(force)
    # one scale for every shaft: drawn = scale * (F_x + i F_y)
    scale = abs(drawn[0][0]) / abs(peaks[0][0])
    for force, line in zip(peaks, drawn, strict=True):
        np.testing.assert_allclose(line, scale * (force.imag + 1j * force.real), atol=1e-9)
    star = plots.plot_crank_star(result).axes[0]
    table = result.engine.axis_table()
    alpha = table.axis_phase + table.sense * result.engine.throw
    tips = {
        (round(float(line.get_xdata()[0]), 9), round(float(line.get_ydata()[0]), 9))
        for line in star.lines
        if line.get_marker() == "o" and line.get_color() == "C0"
    }
    for i in range(result.engine.n_cylinders):
        s = table.axis[i]
        r = result.engine.crank_radius[i] * 1e3
        tip = (table.x[s] * 1e3 + r * np.sin(alpha[i]), table.y[s] * 1e3 + r * np.cos(alpha[i]))
        assert (round(float(tip[0]), 9), round(float(tip[1]), 9)) in tips


@image_compare
def test_phasors_deltic_like():
    """Several crankshafts: each shaft's phasors head to tail, ending at the engine's."""
    from tests.test_geared_brute_force import deltic_like

    return plots.plot_phasors(computed(deltic_like()))


def _arrow_phasor(axes: Any, point: Any) -> complex:
    """The phasor ``y + i x`` of an arrow's end: ``(x, y)`` on plain axes, ``(angle,
    radius)`` on polar ones."""
    a, b = (float(v) for v in point)
    if axes.name == "polar":
        return complex(b * np.exp(1j * a))
    return complex(b + 1j * a)


def _drawn_arrows(axes: Any) -> list[tuple[str, complex, complex]]:
    """Each phasor arrow of a panel as drawn: its label, tail and head."""
    return [
        (t.get_label(), _arrow_phasor(axes, t.xyann), _arrow_phasor(axes, t.xy))
        for t in axes.texts
        if getattr(t, "arrow_patch", None) is not None
    ]


def _phasor_panel_axes(result: Result, fig: Any, **options: Any) -> list[tuple[str, int, Any]]:
    """The panels of the per-order phasor figure: quantity, order and axes."""
    out, axes = [], iter(fig.axes)
    for quantity, ks in plots.phasor_panels(result, **options):
        if not ks:
            next(axes)  # the note
        out += [(quantity, k, next(axes)) for k in ks]
    return out


def _assert_shaft_chains(result: Result, fig: Any, source: str = "free") -> set[int]:
    """Every panel of the phasor figure: each shaft's forward (backward) phasor of the
    order is an arrow from the head of the shaft's before it, the first from the centre,
    the last ending at the engine's phasor (1e-9 of the panel's sum of magnitudes); a shaft
    without an arrow has a phasor of zero.  Returns the orders of the force panels."""
    part = result.part("crankshafts")
    bundle = part.force.free() if source == "free" else part.force
    at = {int(k): j for j, k in enumerate(result.orders)}
    forces = set()
    for quantity, k, axes in _phasor_panel_axes(result, fig, source=source):
        forces |= {k} if quantity == "force" else set()
        drawn = _drawn_arrows(axes)
        _, engine_fwd, engine_bwd = synthesis.phasors_of(result, quantity, source)
        shafts = bundle.pair(quantity)
        for d, direction in enumerate(("forward", "backward")):
            phasors = shafts[d][:, at[k]]
            engine = (engine_fwd, engine_bwd)[d][at[k]]
            tol = REL * (float(np.abs(phasors).sum()) + abs(engine))
            arrows = {
                label.rsplit(" ", 1)[0]: (tail, head)
                for label, tail, head in drawn
                if label.endswith(" " + direction)
            }
            assert set(arrows) <= set(part.names)
            end = 0j
            for name, phasor in zip(part.names, phasors, strict=True):
                if name not in arrows:
                    assert abs(phasor) <= tol, (quantity, k, name, direction)
                    continue
                tail, head = arrows[name]
                assert abs(tail - end) <= tol, (quantity, k, name, direction)
                assert abs((head - tail) - phasor) <= tol, (quantity, k, name, direction)
                end = head
            assert abs(end - engine) <= tol, (quantity, k, direction)
        # the engine's own arrows stay, from the centre
        for label, tail, head in drawn:
            if not label.endswith(("forward", "backward")):
                assert tail == 0
                assert min(abs(head - engine_fwd[at[k]]), abs(head - engine_bwd[at[k]])) <= tol
    return forces


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_phasors_draw_each_shafts_phasors_head_to_tail(sense):
    """Two one-cylinder cranks side by side, co- or counter-rotating (the phasors figure
    through ``plot_kind``): each order's force panel chains the two shafts' phasors to the
    engine's, and names both shafts in the legend.  Counter-rotating, their first orders
    cancel (the engine's is zero) and its panel is drawn all the same."""
    from tests.geared_engines import twin_crank

    result = computed(twin_crank(sense))
    fig = plots.plot_kind("phasors")(result)
    forces = _assert_shaft_chains(result, fig)
    assert forces == {1, 2, 4, 6, 8}
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert {"shaft1", "shaft2"} <= set(legend)
    labels = {
        label for _, _, ax in _phasor_panel_axes(result, fig) for label, *_ in _drawn_arrows(ax)
    }
    assert {"shaft1 forward", "shaft2 forward", "shaft1 backward", "shaft2 backward"} <= labels
    _, forward, backward = synthesis.phasors_of(result, "force")
    if sense < 0:
        assert forward[0] == backward[0] == 0.0  # cancelled, and the shafts drawn
    # on polar axes given, alike
    from matplotlib.figure import Figure

    n = sum(max(len(ks), 1) for _, ks in plots.phasor_panels(result))
    polar = Figure().subplots(1, n, subplot_kw={"projection": "polar"})
    _assert_shaft_chains(result, plots.plot_phasors(result, ax=polar))


def test_phasors_deltic_18_shafts_add_up_to_the_engines():
    """The deltic-18 built-in: three shafts, one counter-rotating; the forces of order 6 and
    the moments of orders 2, 4 and 8 chain to the engine's, free and reciprocating; the
    residual (not split by shaft) draws the engine's alone."""
    result = balance.compute_result("deltic-18")
    for source in ("free", "reciprocating"):
        fig = plots.plot_phasors(result, source=source)
        _assert_shaft_chains(result, fig, source)
        legend = [t.get_text() for t in fig.legends[0].get_texts()]
        assert set(result.part("crankshafts").names) <= set(legend)
    assert plots.phasor_panels(result) == [("force", [6]), ("moment", [2, 4, 8])]
    residual = plots.plot_phasors(result, source="residual")
    assert len(residual.legends[0].get_texts()) == 2
    for axes in residual.axes:
        assert all(label == "" for label, *_ in _drawn_arrows(axes))


@pytest.mark.parametrize("name", ["inline-4", "v8-crossplane", "inline-3"])
def test_phasors_one_crankshaft_draws_nothing_new(name):
    """One crankshaft: the engine's arrows only, from the centre (one per phasor not zero
    of each panel), and the legend's two entries."""
    result = analysed(name)
    fig = plots.plot_phasors(result)
    assert [t.get_text().split(":")[0] for t in fig.legends[0].get_texts()] == [
        "forward (wide)",
        "backward (dashed)",
    ]
    at = {int(k): j for j, k in enumerate(result.orders)}
    for quantity, k, axes in _phasor_panel_axes(result, fig):
        _, forward, backward = synthesis.phasors_of(result, quantity)
        pair = np.array([abs(forward[at[k]]), abs(backward[at[k]])])
        drawn = _drawn_arrows(axes)
        assert len(drawn) == int(np.count_nonzero(significant_mask(pair)))
        assert all(label == "" and tail == 0 for label, tail, _ in drawn)


#: One layout of each family for the smoke test of every kind: inline with gas forces (half
#: orders, torque and forces), a V-twin on one pin, a boxer, a radial, the staggered VR6
#: with offset bores, a W12, and the inline-6, whose free forces and moments are all zero.
DRAWN = ["inline-4-gas", "v-twin-45", "boxer-4", "radial-5", "vr6", "w12", "inline-6"]
NOTES = ("zero", "all zero", "not computed", "no gas forces")


def _bars(axes) -> np.ndarray:
    """Heights of each bar series of an axes, one row per series."""
    return np.array([[bar.get_height() for bar in series] for series in axes.containers])


def _order_lines(axes) -> dict[int, Any]:
    return {
        int(line.get_label().split()[1]): line
        for line in axes.lines
        if line.get_label().startswith("order ")
    }


def _assert_drawn_peaks(heights: np.ndarray, peaks: np.ndarray, first: int = 0) -> None:
    """Bars equal the Dataset's peaks from order ``first + 1`` on (zero where the figure's
    rule calls a peak round-off: within the rounding of the sum of the bars,
    docs/conventions.md "Zero by symmetry")."""
    largest = float(heights.max())
    threshold = 64 * heights.size * np.finfo(float).eps * float(np.nansum(np.abs(heights)))
    expected = np.where(np.nan_to_num(peaks) > threshold, peaks, 0.0)
    np.testing.assert_allclose(heights[first:], expected[first:], rtol=1e-12, atol=1e-12 * largest)


@pytest.mark.parametrize("name", DRAWN)
def test_every_kind_draws_the_numbers_of_the_result(name):
    """Every kind the result supports draws: a title naming the engine, labelled axes with
    something on them (or a note saying why not: zero, not computed), and the numbers of
    the Dataset: the bars of the spectrum, roll and balance figures are its peaks, and each
    order's curve in the crank-angle and locus figures reaches that order's peak."""
    layout = balance.load_layout(name)
    result = analysed(name)
    ds = balance.analyse(layout)
    kinds = [
        k
        for k in plots.all_kinds()
        if (k != "balance" or synthesis.has_proposal(result))
        and (k != "mounts" or result.part("mounts") is not None)
        and (k not in BEARING_KINDS or result.part("bearings") is not None)
        and k not in SPEED_MODEL_KINDS  # not asked for: drawn in tests/test_dynamics.py
    ]
    figures = {kind: plots.plot_kind(kind)(result) for kind in kinds}
    for kind, fig in figures.items():
        assert " ".join(result.engine.name.split()) in " ".join(fig.get_suptitle().split()), kind
        for axes in fig.axes:
            notes = [t.get_text() for t in axes.texts if t.get_text().startswith(NOTES)]
            drawn = (
                any(len(line.get_xdata()) > 1 for line in axes.lines)
                or any(len(series) for series in axes.containers)
                or any(getattr(t, "arrow_patch", None) is not None for t in axes.texts)
                or bool(axes.collections)
            )
            assert drawn or notes, (kind, axes.get_title())
            if drawn and axes.name == "rectilinear" and axes.lines + axes.containers:
                if axes.axison:
                    assert axes.get_xlabel() and axes.get_ylabel(), (kind, axes.get_title())
                else:  # a phasor panel: a polar frame drawn on plain axes, its angles labelled
                    angles = {t.get_text() for t in axes.texts}
                    assert {"0°", "90°", "180°", "270°"} <= angles, (kind, axes.get_title())
    peaks = {
        "force": ds["reciprocating_force_peak"].values,
        "moment": ds["reciprocating_moment_peak"].values,
    }
    # the spectrum: free = reciprocating + rotating, which is order 1 only
    spectrum = figures["spectrum"].axes
    for axes, quantity in zip(spectrum, ("force", "moment"), strict=True):
        heights = _bars(axes)[0]
        if heights.max() == 0:  # said, and true
            assert "all zero" in [t.get_text() for t in axes.texts]
            assert np.nan_to_num(peaks[quantity]).max() == 0.0
        else:
            _assert_drawn_peaks(heights, peaks[quantity], first=1)
    reciprocating = plots.plot_spectrum(result, source="reciprocating").axes
    for axes, quantity in zip(reciprocating, ("force", "moment"), strict=True):
        if _bars(axes)[0].max() > 0:
            _assert_drawn_peaks(_bars(axes)[0], peaks[quantity])
    if "balance" in figures:  # after (residual) bars: the residual peaks
        bottom = figures["balance"].axes[3:]
        for axes, quantity in zip(bottom[:2], ("force", "moment"), strict=True):
            after = _bars(axes)[1]
            if after.max() > 0:
                _assert_drawn_peaks(after, ds[f"residual_{quantity}_peak"].values)
        roll_after = _bars(bottom[2])[1]
        if roll_after.max() > 0:
            _assert_drawn_peaks(roll_after, ds["residual_roll_amplitude"].values)
    roll_bars = _bars(figures["roll"].axes[1])[0]
    if roll_bars.max() > 0:
        _assert_drawn_peaks(roll_bars, ds["roll_amplitude"].values)
    # each order's curve over a revolution reaches |P+| + |P-| (721 angles: to 1e-3)
    f_y, f_x = figures["crank_angle"].axes[:2]
    lines_y, lines_x = _order_lines(f_y), _order_lines(f_x)
    locus = _order_lines(figures["locus"].axes[0])
    assert lines_y.keys() == lines_x.keys() == locus.keys()
    for k in lines_y:
        size = np.hypot(lines_y[k].get_ydata(), lines_x[k].get_ydata())
        x, y = locus[k].get_data()
        if k >= 2:
            assert size.max() == pytest.approx(peaks["force"][k - 1], rel=1e-3)
        assert np.hypot(x, y).max() == pytest.approx(size.max(), rel=1e-12)
    # the orders without a curve are zero, or within the rounding of the peaks drawn
    bars = _bars(spectrum[0])[0]
    threshold = 64 * bars.size * np.finfo(float).eps * float(bars.sum())
    for k in range(2, len(peaks["force"]) + 1):
        if k not in lines_y:
            assert peaks["force"][k - 1] <= threshold


#: The kinds that read the moments and the roll; the others read neither (crank_star the
#: engine, torque and forces the gas torque, mounts and the bearing kinds their own results),
#: which test_every_kind_draws_what_was_computed checks.
READS = {
    "moments": {"phasors", "crank_angle", "locus", "spectrum", "balance"},
    "roll": {"roll", "balance"},
}


def _content(fig) -> list[Any]:
    """What a figure shows: its title, and each axes' title, texts (with where an arrow
    points), lines (bit for bit) and bars."""
    out: list[Any] = [fig.get_suptitle()]
    for axes in fig.axes:
        out.append(axes.get_title())
        out += [(t.get_text(), getattr(t, "xy", None)) for t in axes.texts]
        out += [line.get_xydata().tobytes() for line in axes.lines]
        out += [[bar.get_height() for bar in series] for series in axes.containers]
    return out


def _assert_same_figure(got, expected, rel: float) -> None:
    """Two figures that show the same: titles and texts alike, arrows, lines and bars equal
    to ``rel`` of the largest value of each (NaN where the other has NaN)."""
    a, b = _content(got), _content(expected)
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        if isinstance(x, bytes):  # a line's data
            x, y = np.frombuffer(x), np.frombuffer(y)
        elif isinstance(x, tuple) and x[1] is not None:  # a text with where it points
            assert x[0] == y[0]
            x, y = np.asarray(x[1], dtype=float), np.asarray(y[1], dtype=float)
        if isinstance(x, np.ndarray | list) and not isinstance(x, str):
            x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
            scale = float(np.nanmax(np.abs(y), initial=0.0))
            np.testing.assert_allclose(x, y, rtol=0, atol=rel * scale)
        else:
            assert x == y


@pytest.mark.parametrize("options", [{"moments": False}, {"roll": False}, {"model": "time"}])
def test_every_kind_draws_what_was_computed(options):
    """Without moments or roll the figures say so instead of failing; balance needs both.
    Drawing leaves matplotlib's global settings as they were.

    Without the moments (the roll), the kinds that read them (READS) are drawn, and the
    others are built and shown to be the figures of the result with them: drawing them
    again would draw the same figures.  With the time model every kind is built and shown
    to be the exact model's figure to rounding (the views read the phasors, never the
    model), and the kinds that only say what the result lacks (gas, mounts, bearing
    loads) are drawn; every kind with something to draw is drawn as PNG by the image tests
    (test_torque.py for torque and forces), mounts by test_mounts_analysis.py and the
    bearing kinds as SVG by test_bearings_cli.py."""
    import matplotlib as mpl

    before = dict(mpl.rcParams)
    full = analysed("v8-crossplane")
    result = computed(balance.load_layout("v8-crossplane"), **options)
    missing = set().union(*(READS[k] for k in READS if options.get(k) is False))
    for kind in plots.all_kinds():
        function = plots.plot_kind(kind)
        if kind == "balance" and not synthesis.has_proposal(result):
            continue
        if "model" in options:
            fig = function(result)
            _assert_same_figure(fig, function(full), rel=1e-9)
            if kind in GAS_KINDS + BEARING_KINDS + ("mounts",):
                assert plots.figure_bytes(fig, "png").startswith(b"\x89PNG")
            continue
        if missing and kind not in missing:
            assert _content(function(result)) == _content(function(full))
            continue
        assert plots.figure_bytes(function(result), "png").startswith(b"\x89PNG")
    assert dict(mpl.rcParams) == before
    if "moments" in options:
        _, forward, backward = synthesis.phasors_of(result, "moment")
        assert np.isnan(forward).all() and np.isnan(backward).all()
    if "roll" in options:
        assert synthesis.roll_of(result)[0].size == 0


@pytest.mark.xdist_group("fresh_process")  # one worker builds the session fixture once
def test_no_pyplot_and_lazy_matplotlib(fresh_process):
    """Importing balance.views.plots loads no matplotlib; drawing never loads pyplot, and
    the figures, ``balance report`` and ``balance plot`` read the Result: no xarray
    Dataset is built.  One fresh process for all of it (conftest.fresh_process: one start
    of Python and matplotlib), checked after each step: every kind built, the report's
    figures written as SVG and the plot's as PNG (the Agg backend)."""
    assert fresh_process.done.returncode == 0, fresh_process.done.stderr
    assert fresh_process.report.read_text(encoding="utf-8").startswith("<!DOCTYPE html>")
    for kind in ("locus", "roll"):
        assert (fresh_process.directory / f"inline-3-{kind}.png").exists()


def test_balance_without_a_proposal_is_a_clear_error():
    with pytest.raises(InputError, match="no balancing proposal"):
        proposal_views.plot_balance(analysed("inline-4", proposal=False))


def test_drawing_into_given_axes():
    from matplotlib.figure import Figure

    fig = Figure()
    axes = fig.subplots(1, 2)
    assert plots.plot_locus(analysed("inline-4"), ax=axes) is fig
    assert fig.get_suptitle() == ""  # the caller's figure keeps its own title
    with pytest.raises(ValueError, match="2 axes"):
        plots.plot_locus(analysed("inline-4"), ax=axes[0])
    with pytest.raises(ValueError, match="polar"):
        plots.plot_phasors(analysed("inline-4"), ax=axes, scale="common")
    # one panel per order: the inline-4's forces of orders 2, 4, 6, 8 and a note that its
    # moments are zero
    assert [(q, ks) for q, ks in plots.phasor_panels(analysed("inline-4"))] == [
        ("force", [2, 4, 6, 8]),
        ("moment", []),
    ]
    with pytest.raises(ValueError, match="5 axes"):
        plots.plot_phasors(analysed("inline-4"), ax=axes)
    polar = Figure().subplots(1, 5, subplot_kw={"projection": "polar"})
    drawn = plots.plot_phasors(analysed("inline-4"), ax=polar)
    assert [a.get_title().split("\n")[0] for a in polar[:4]] == [
        "order 2",
        "order 4",
        "order 6",
        "order 8",
    ]
    assert drawn.get_suptitle() == ""
    single = Figure().subplots()
    assert plots.plot_crank_star(analysed("inline-4"), ax=single) is single.figure


def test_orders_must_exist():
    with pytest.raises(ValueError, match="not in the result"):
        plots.plot_locus(analysed("inline-4"), orders=[9])


@pytest.mark.parametrize("fmt", plots.FORMATS)
def test_save_plots_writes_whole_files(tmp_path, fmt):
    """Whole files in each format of a polar and a cartesian kind (their labels hold the
    non-ASCII text of the figures: θ, Σ, Δ), and matplotlib's global settings left as they
    were.  Every kind is drawn as PNG by test_every_kind_draws_what_was_computed and as
    SVG in every report; which kinds are written by default, test_save_plots_choices."""
    import matplotlib as mpl

    before = dict(mpl.rcParams)
    result = analysed("inline-3")
    kinds = ["phasors", "locus"]
    written = plots.save_plots(result, tmp_path / "figures", kinds, fmt=fmt, prefix="i3-")
    assert [p.name for p in written] == [f"i3-{kind}.{fmt}" for kind in kinds]
    assert sorted(p.name for p in (tmp_path / "figures").iterdir()) == sorted(
        p.name for p in written
    )  # no temporary files left
    magic = {"png": b"\x89PNG", "svg": b"<?xml", "pdf": b"%PDF"}[fmt]
    for path in written:
        assert path.read_bytes().startswith(magic)
    with pytest.raises(InputError, match="exists"):
        plots.save_plots(result, tmp_path / "figures", kinds=["locus"], fmt=fmt, prefix="i3-")
    again = plots.save_plots(result, tmp_path / "figures", kinds[:1], fmt, prefix="i3-", force=True)
    assert again[0].read_bytes() == written[0].read_bytes()  # deterministic
    assert dict(mpl.rcParams) == before


def test_save_plots_choices(tmp_path, monkeypatch):
    # which kinds are written, not how (test_save_plots_writes_whole_files draws them): no
    # figure is built or drawn, but plot_balance runs (it refuses a result without a proposal)
    monkeypatch.setattr(plots, "figure_bytes", lambda fig, fmt="png": b"")
    for kind in plots.PLOT_KINDS:
        if kind != "balance":
            monkeypatch.setitem(plots.PLOT_KINDS, kind, lambda result, **options: None)
    written = plots.save_plots(analysed("inline-3"), tmp_path / "all", prefix="i3-")
    # by default, the kinds of what was computed (no mounts, bearing loads or gas here)
    default = [
        k
        for k in plots.all_kinds()
        if k != "mounts"
        and k not in BEARING_KINDS
        and k not in GAS_KINDS
        and k not in SPEED_MODEL_KINDS
        and k not in TORSION_KINDS
        and k not in CRANKSHAFT_KINDS
    ]
    assert [p.name for p in written] == [f"i3-{kind}.png" for kind in default]
    gas = plots.save_plots(
        computed(balance.load_layout("inline-4-gas"), 2), tmp_path / "gas", prefix="g-"
    )
    assert {"g-torque.png", "g-forces.png"} <= {p.name for p in gas}
    no_proposal = analysed("inline-4", proposal=False)
    written = plots.save_plots(no_proposal, tmp_path)
    assert "balance.png" not in {p.name for p in written}
    with pytest.raises(InputError, match="no balancing proposal"):
        plots.save_plots(no_proposal, tmp_path / "b", kinds=["balance"])
    with pytest.raises(InputError, match="plot kind"):
        plots.save_plots(no_proposal, tmp_path, kinds=["pie"])
    with pytest.raises(InputError, match="format"):
        plots.save_plots(no_proposal, tmp_path, fmt="jpg")


def test_peaks_are_the_phasor_bundles():
    """The views form no peak or magnitude of their own: signals.peak_of and magnitude_of
    are Phasors.peak and Phasors.magnitude of the source's bundle (bundle_of: the result's
    phasors, their free() or the proposal's residual), NaN for what was not computed."""
    result = analysed("v8-crossplane")
    free = result.phasors.free()
    assert synthesis.bundle_of(result, "reciprocating") is result.phasors
    assert synthesis.bundle_of(result, "residual") is result.part("proposal").residual
    for quantity in synthesis.QUANTITIES:
        np.testing.assert_array_equal(synthesis.peak_of(result, quantity), free.peak(quantity))
        np.testing.assert_array_equal(
            synthesis.magnitude_of(result, quantity, "residual"),
            result.part("proposal").residual.magnitude(quantity),
        )
    without = computed(balance.load_layout("v8-crossplane"), moments=False)
    assert np.isnan(synthesis.peak_of(without, "moment")).all()
    assert synthesis.magnitude_of(without, "moment").shape == (8, 2)
    with pytest.raises(ValueError, match="no balancing proposal"):
        synthesis.bundle_of(analysed("inline-4", proposal=False), "residual")
