"""The model ladder: each model within its documented bound, the tolerance mode, extremes."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
from functools import cache

import mpmath
import numpy as np
import pytest
from helpers import engine

from balance.api import Engine, analyse
from balance.core import accuracy
from balance.core import kinematics as kin
from balance.core import sampled as td
from balance.core.analysis import compute_phasors, reference_force
from balance.core.errors import AnalysisError

ORDERS = np.arange(1, 9)
LAMBDAS = [1e-9, 0.1, 0.25, 0.4, 0.6, 0.8, 0.95, 0.999]


@cache
def reference(lam: float, eps: float) -> np.ndarray:
    """G_k (orders 1-8) of -s''/r at 30 digits by the trapezoidal rule, which is spectrally
    accurate for this analytic periodic function; the number of points makes the aliasing
    below 1e-30 (it decays like exp(-a k), a = arccosh(1/lambda - |eps|))."""
    a = math.acosh(1 / lam - abs(eps)) if 1 / lam - abs(eps) < 1e6 else 20.0
    n = max(64, int(2 * (75 / a + 8)))
    with mpmath.workdps(30):
        lam_mp, eps_mp = mpmath.mpf(lam), mpmath.mpf(eps)
        # exp(-i b_m), b_m = 2 pi m / n: the cosine and sine of every angle, and the Fourier
        # factor exp(-i k b_j) = turn[k j mod n] (n complex exponentials in all, not n per order)
        turn = [mpmath.expjpi(-2 * mpmath.mpf(m) / n) for m in range(n)]
        values = []
        for j in range(n):
            c, s = turn[j].real, -turn[j].imag
            u = s - eps_mp
            D = mpmath.sqrt(1 - (lam_mp * u) ** 2)
            values.append(c + lam_mp * ((c**2 - u * s) / D + (lam_mp * u * c) ** 2 / D**3))
        out = []
        for k in ORDERS:
            total = mpmath.mpc(0)
            for j, v in enumerate(values):
                total += v * turn[(int(k) * j) % n]
            out.append(complex(2 * total / n))
    return np.array(out)


def _error(model: str, lam: float, eps: float, **kw: int) -> float:
    got = kin.acceleration_coefficients(lam, eps, ORDERS, model=model, **kw)
    return float(np.abs(got - reference(lam, eps)).max())


CASES = [(lam, 0.0) for lam in LAMBDAS] + [(0.25, 0.3), (0.4, -0.5), (0.6, 0.6)]


@pytest.mark.parametrize(("lam", "eps"), CASES)
def test_each_model_within_its_bound(lam, eps):
    assert _error("exact", lam, eps) <= accuracy.error_bound("exact", lam, eps)
    assert _error("textbook", lam, eps) <= accuracy.error_bound("textbook", lam, eps)
    for terms in (1, 3, 8):
        bound = accuracy.error_bound("series", lam, eps, terms=terms)
        assert _error("series", lam, eps, terms=terms) <= bound


@pytest.mark.parametrize(("lam", "eps"), [(0.1, 0.0), (0.4, 0.2), (0.8, 0.0), (0.95, 0.0)])
@pytest.mark.parametrize("samples", [32, 64, 256])
def test_time_model_within_its_bound(lam, eps, samples):
    layout = engine([0], spacing=0.0, stroke=0.08, conrod_length=0.04 / lam)
    layout = dataclasses.replace(layout, offset=np.full(1, eps * 0.04))
    result = compute_phasors(
        layout, ORDERS, model="time", samples=samples, moments=False, roll=False
    )
    got = result.coefficients[0]
    error = float(np.abs(got - reference(lam, eps)).max())
    assert error <= result.model.error_bound
    # and the forces the time model synthesises carry that accuracy
    f1 = reference_force(layout)
    exact = compute_phasors(layout, ORDERS, moments=False, roll=False)
    assert (
        np.abs(result.phasors.force_forward - exact.phasors.force_forward).max()
        <= (result.model.error_bound + 1e-13) * f1
    )


@pytest.mark.parametrize("tolerance", [1e-2, 1e-4, 1e-6, 1e-9, 1e-12])
@pytest.mark.parametrize(
    ("lam", "eps"), [(0.1, 0.0), (0.25, 0.0), (0.3, 0.2), (0.6, 0.0), (0.8, 0.0)]
)
def test_tolerance_mode_meets_the_tolerance(tolerance, lam, eps):
    model, terms, bound = accuracy.choose_model(tolerance, lam, eps)
    assert bound <= tolerance
    assert _error(model, lam, eps, terms=max(terms, 1)) <= tolerance


def test_tolerance_mode_prefers_cheap_models_and_records_them():
    layout = engine([0, 180, 180, 0], stroke=0.02, conrod_length=0.2)  # lambda = 0.05
    loose = analyse(layout, tolerance=1e-2)
    assert loose.attrs["model"] == "textbook"
    tight = analyse(layout, tolerance=1e-9)
    assert tight.attrs["model"] == "series" and tight.attrs["series_terms"] >= 3
    assert tight.attrs["error_bound"] <= 1e-9
    # lambda = 0.3: twelve series terms give 8e-13, so 1e-13 needs the exact model
    exact = analyse(engine([0, 180, 180, 0], stroke=0.06, conrod_length=0.1), tolerance=1e-13)
    assert exact.attrs["model"] == "exact"
    with pytest.raises(AnalysisError, match="below what double precision gives"):
        analyse(layout, tolerance=1e-18)


# --- extremes ------------------------------------------------------------------------------


@pytest.mark.parametrize("lam", [1e-9, 1e-6, 1e-3, 0.5, 0.9, 0.99, 0.999])
@pytest.mark.parametrize("offset_share", [0.0, 0.5, 0.999])
def test_rod_ratio_and_offset_extremes(lam, offset_share):
    """Finite, warning-free (warnings are errors in this suite) and right, up to 99.9 % of
    the geometric limit of the offset."""
    eps = offset_share * (1 / lam - 1)
    got = kin.acceleration_coefficients(lam, eps, ORDERS)
    assert np.all(np.isfinite(got))
    if lam * (1 + eps) < 0.9995 and eps < 1e3:
        np.testing.assert_allclose(
            got, reference(lam, eps), rtol=0, atol=accuracy.error_bound("exact", lam, eps)
        )
    rec, rod = kin.roll_coefficients(lam, eps, ORDERS)
    assert np.all(np.isfinite(rec)) and np.all(np.isfinite(rod))


def test_at_and_past_the_limit_is_a_clear_error():
    for lam, eps in [(1.0, 0.0), (0.5, 1.0), (0.5, 1.5), (2.0, 0.0)]:
        with pytest.raises(AnalysisError, match="must be below 1"):
            kin.acceleration_coefficients(lam, eps, [1])


def _random_layout(n: int, rng: np.random.Generator, **over: object) -> Engine:
    layout = Engine(
        name="extreme",
        speed=600.0,
        throw=rng.uniform(0, 2 * np.pi, n),
        bank=rng.uniform(-1, 1, n),
        z=rng.uniform(-0.5, 0.5, n),
        crank_radius=np.full(n, 0.04),
        conrod_length=np.full(n, 0.14),
        offset=rng.uniform(-0.01, 0.01, n),
        reciprocating_mass=np.full(n, 0.5),
        rotating_mass=np.full(n, 0.3),
        conrod_inertia_correction=np.zeros(n),
        reference_z=0.0,
        pitch=0.1,
    )
    return dataclasses.replace(layout, **over)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("name", "over", "orders"),
    [
        ("1 rpm", {"speed": 2 * math.pi / 60}, 8),
        ("1e6 rpm", {"speed": 2 * math.pi * 1e6 / 60}, 8),
        ("1 mg", {"reciprocating_mass": np.full(6, 1e-6), "rotating_mass": np.full(6, 1e-6)}, 8),
        ("10 t", {"reciprocating_mass": np.full(6, 1e4), "rotating_mass": np.full(6, 1e4)}, 8),
        ("order 50", {}, 50),
    ],
)
def test_speed_mass_and_order_extremes(name, over, orders, rng):
    layout = _random_layout(6, rng, **over)
    ks = np.arange(1, orders + 1)
    result = compute_phasors(layout, ks)
    theta = td.crank_angles(4 * 1024)
    fwd, bwd = td.phasors_from_samples(td.reciprocating_force_samples(layout, theta), ks)
    scale = float(np.max(layout.reciprocating_mass * layout.crank_radius) * layout.speed**2)
    np.testing.assert_allclose(result.phasors.force_forward, fwd, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(result.phasors.force_backward, bwd, rtol=0, atol=1e-9 * scale)
    assert np.all(np.isfinite(result.phasors.roll))


def test_sixty_four_cylinders(rng):
    layout = _random_layout(64, rng)
    result = compute_phasors(layout, ORDERS)
    theta = td.crank_angles(1024)
    fwd, _ = td.phasors_from_samples(td.reciprocating_force_samples(layout, theta, True), ORDERS)
    scale = float(np.max(layout.reciprocating_mass * layout.crank_radius) * layout.speed**2)
    np.testing.assert_allclose(result.phasors.moment_forward, fwd, rtol=0, atol=1e-9 * scale)
    sampled = td.roll_phasors_from_samples(td.roll_newton_euler(layout, theta), ORDERS)
    np.testing.assert_allclose(result.phasors.roll, sampled, rtol=0, atol=1e-9 * scale * 0.04)


# --- only what is asked ---------------------------------------------------------------------


def test_skipped_quantities_are_absent_not_nan():
    ds = analyse(engine([0, 180, 180, 0]), orders=[2], moments=False, roll=False, proposal=False)
    assert list(ds["order"].values) == [2]
    assert not any("moment" in name and name != "reference_moment" for name in ds.data_vars)
    assert not any(name.startswith("roll") for name in ds.data_vars)
    assert "counterweight_mass" not in ds


def test_a_json_request_imports_no_pint_matplotlib_or_dask():
    code = (
        "import sys, io, contextlib\n"
        "from balance.cli import main\n"
        "sys.argv = ['balance', 'analyse', 'inline-4', '--format', 'json']\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try:\n        main()\n    except SystemExit:\n        pass\n"
        "print(' '.join(m for m in ('pint', 'matplotlib', 'dask', 'rich') if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_a_vanishing_piston_mass_gives_infinite_ratios_not_a_warning(tmp_path):
    """Found by the fuzz test: with a 1e-308 kg piston the normalising force F1 is a few
    1e-303 N and the rotating force per F1 exceeds the float range.  The ratio is inf
    (null in JSON), the command succeeds, and numpy's overflow warning is not raised."""
    import json

    from typer.testing import CliRunner

    from balance.cli import app

    rows = "\n".join(f"- {{throw: 0, bank: 0, z: {90 * i} mm}}" for i in range(5))
    path = tmp_path / "tiny.yaml"
    path.write_text(
        "name: tiny\nspeed: 6000 rpm\ngeometry: {stroke: 86 mm, conrod_length: 143 mm}\n"
        f"masses: {{reciprocating: 1.0e-308 kg, rotating: 0.4 kg}}\ncylinders:\n{rows}\n"
    )
    result = CliRunner().invoke(app, ["analyse", str(path), "--format", "json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    rotating = doc["rotating"]["force"]
    assert rotating["peak"] > 0
    assert rotating["peak_normalised"] is None  # inf in the Dataset, null in JSON


def test_series_parameters_are_the_largest_rod_and_offset_ratios():
    """What the report's accuracy statement quotes: the largest lambda = r/l and the largest
    lambda (1 + |e|/r) over the cylinders (here the second cylinder has the longer stroke
    and an offset)."""
    layout = engine([0, 180])
    r = np.array([0.043, 0.05])
    layout = dataclasses.replace(
        layout, crank_radius=r, offset=np.array([0.0, -0.01]), conrod_length=np.array([0.143, 0.15])
    )
    ratio, x = accuracy.series_parameters(layout)
    lam = r / layout.conrod_length
    assert ratio == float(np.max(lam))
    assert x == float(np.max(lam * (1.0 + np.abs(layout.offset / r))))
    assert x == pytest.approx(0.05 / 0.15 * 1.2, rel=1e-15)
