"""Crank-slider kinematics and the Fourier coefficients of the piston acceleration."""

from __future__ import annotations

import csv
import itertools
import math
from pathlib import Path

import mpmath
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from balance.core import kinematics as kin
from balance.core.errors import AnalysisError

DATA = Path(__file__).parent / "data"


# --- worked example: the 6" rod, 2" crank (Wikipedia, "Piston motion equations") ------


def _velocity_extreme_deg(r: float, length: float) -> float:
    """Crank angle of the velocity maximum: the zero of the acceleration, by bisection."""

    def accel(beta_deg: float) -> float:
        return float(kin.piston_acceleration(math.radians(beta_deg), r, length))

    lo, hi = 10.0, 89.0  # the acceleration changes sign between these
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if accel(lo) * accel(mid) <= 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def test_seed000_velocity_extremes():
    """Worked example of the English Wikipedia article "Piston motion equations" (section
    on velocity maxima/minima; equations as Heywood 1988, eq. 2.4): rod 6", crank radius 2":
    velocity extremes at +-73.17615 deg.  A 30-digit mpmath root of s'' gives
    73.1752966362 deg: the article's root is 8.5e-4 deg off (its other figures are computed
    from its own root, below), so we agree with it to 1e-3 deg and with the high-precision
    root to 1e-9 deg."""
    beta = _velocity_extreme_deg(2.0, 6.0)
    with mpmath.workdps(30):
        lam = mpmath.mpf(1) / 3
        x = lambda b: mpmath.cos(b) + mpmath.sqrt(1 - (lam * mpmath.sin(b)) ** 2) / lam  # noqa: E731
        reference = float(mpmath.degrees(mpmath.findroot(lambda b: mpmath.diff(x, b, 2), 1.27)))
    assert beta == pytest.approx(reference, abs=1e-9)
    assert beta == pytest.approx(73.17615, abs=1e-3)
    assert float(kin.piston_acceleration(math.radians(-beta), 2.0, 6.0)) == pytest.approx(
        0, abs=1e-9
    )


def test_seed000_rod_and_crank_rod_angles():
    """Same worked example (Wikipedia, "Piston motion equations"): at its crank angle
    73.17615 deg, rod angle 18.60647 deg and crank-rod angle 88.21738 deg (the triangle's
    angles sum to 180 deg)."""
    rod = math.degrees(float(kin.conrod_angle(math.radians(73.17615), 2.0, 6.0)))
    assert rod == pytest.approx(18.60647, abs=5e-6)
    assert 180.0 - 73.17615 - rod == pytest.approx(88.21738, abs=5e-6)


# --- Makushev, Polyakova and Batrakov (2010), table 3 (VAZ-2108) -----------------------


def _table3() -> list[dict[str, str]]:
    with open(DATA / "seed003_table3.csv", encoding="utf-8") as fh:
        rows = [line for line in fh if not line.startswith("#")]
    return list(csv.DictReader(rows))


def _half_unit(text: str) -> float:
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0**-decimals


# The article's text (Makushev, Polyakova and Batrakov, "Determination of piston velocity and
# acceleration by means of derivatives", 2010, in Russian; full entry in docs/theory.md)
# states r = 0.035 m and omega = 513 1/s; the table fits r = 35.5 mm
# (stroke 71 mm, the VAZ-2108's real stroke), and omega from J(0) = r omega^2 (1 + lambda).
TABLE3_R = 0.0355
TABLE3_LAMBDA = 0.26
TABLE3_OMEGA = math.sqrt(11765.45 / (TABLE3_R * (1 + TABLE3_LAMBDA)))


def test_seed003_table3_fit_of_speed_is_consistent():
    # V(90 deg) = r omega holds for every rod ratio; it must agree with the omega fitted to J(0)
    assert pytest.approx(TABLE3_OMEGA, rel=3e-5) == 18.207 / TABLE3_R
    assert pytest.approx(512.9, abs=0.05) == TABLE3_OMEGA  # fitted to the printed table


def test_seed003_table3_reproduced_by_textbook_kinematics():
    """Every S, V, J of table 3 to half a unit of its last printed digit."""
    r, lam, w = TABLE3_R, TABLE3_LAMBDA, TABLE3_OMEGA
    for row in _table3():
        beta = math.radians(float(row["phi_deg"]))
        s, ds, d2s = kin.textbook_slider(beta, lam)
        displacement = r * (1 + 1 / lam) - r * float(s)
        velocity = -w * r * float(ds)
        accel = -(w**2) * r * float(d2s)
        assert displacement == pytest.approx(float(row["S_m"]), abs=_half_unit(row["S_m"]) + 1e-12)
        assert velocity == pytest.approx(float(row["V_m_s"]), abs=_half_unit(row["V_m_s"]) + 1e-9)
        # omega^2 is fitted to the printed J(0) = 11765.45, which carries +-0.005 of rounding:
        # that relative uncertainty (4.2e-7) propagates to every J
        omega_sq_rounding = 0.005 / 11765.45
        tolerance = _half_unit(row["J_m_s2"]) + omega_sq_rounding * abs(accel)
        assert accel == pytest.approx(float(row["J_m_s2"]), abs=tolerance)


def test_seed003_table3_is_the_two_term_approximation_not_the_exact_motion():
    """The exact acceleration differs from the printed J by 3.6 % at 90 deg: the table was
    computed with cos(beta) + lambda cos(2 beta), whose error is of order lambda^3."""
    r, lam, w = TABLE3_R, TABLE3_LAMBDA, TABLE3_OMEGA
    _, _, d2s = kin.normalised_slider(math.radians(90.0), lam, 0.0)
    exact = -(w**2) * r * float(d2s)
    # exact value at 90 deg: -r omega^2 lambda / sqrt(1 - lambda^2)
    assert exact == pytest.approx(-(w**2) * r * lam / math.sqrt(1 - lam**2), rel=1e-13)
    assert abs(exact / -2427.79 - 1) > 0.03


# --- exact derivatives against high-precision differentiation --------------------------


def _mp_position(beta: mpmath.mpf, lam: float, eps: float) -> mpmath.mpf:
    u = mpmath.sin(beta) - eps
    return mpmath.cos(beta) + mpmath.sqrt(1 - (lam * u) ** 2) / lam


def _mp_gamma(beta: mpmath.mpf, lam: float, eps: float) -> mpmath.mpf:
    return mpmath.asin(lam * (mpmath.sin(beta) - eps))


@given(
    beta=st.floats(-math.pi, math.pi),
    lam=st.floats(1e-3, 0.9),
    eps_share=st.floats(-0.9, 0.9),
)
def test_slider_derivatives_match_mpmath(beta, lam, eps_share):
    eps = eps_share * (1 / lam - 1)  # keeps l > r + |e|
    with mpmath.workdps(40):
        b = mpmath.mpf(beta)
        d1 = mpmath.diff(lambda x: _mp_position(x, lam, eps), b, 1)
        d2 = mpmath.diff(lambda x: _mp_position(x, lam, eps), b, 2)
        g1 = mpmath.diff(lambda x: _mp_gamma(x, lam, eps), b, 1)
        g2 = mpmath.diff(lambda x: _mp_gamma(x, lam, eps), b, 2)
        s0 = _mp_position(b, lam, eps)
    s, ds, d2s = kin.normalised_slider(beta, lam, eps)
    dg, d2g = kin.conrod_angle_derivatives(beta, lam, eps)
    scale = 1 + 1 / lam
    assert float(s) == pytest.approx(float(s0), rel=1e-14, abs=1e-14 * scale)
    assert float(ds) == pytest.approx(float(d1), abs=1e-12 * scale)
    assert float(d2s) == pytest.approx(float(d2), abs=1e-11 * scale / (1 - lam * (1 + abs(eps))))
    assert float(dg) == pytest.approx(float(g1), abs=1e-12)
    assert float(d2g) == pytest.approx(float(g2), abs=1e-11 / (1 - lam * (1 + abs(eps))) ** 3)


def test_dimensional_functions_scale_with_radius_and_speed():
    beta = np.linspace(0, 2 * np.pi, 7)
    a1 = kin.piston_acceleration(beta, 0.04, 0.14, 0.002, speed=100.0)
    a2 = kin.piston_acceleration(beta, 0.08, 0.28, 0.004, speed=200.0)
    np.testing.assert_allclose(a2, 8 * a1, rtol=1e-13)
    v = kin.piston_velocity(beta, 0.04, 0.14, 0.0, speed=100.0)
    s = kin.piston_position(beta, 0.04, 0.14)
    # velocity is the derivative of position: check by central differences
    h = 1e-6
    fd = (kin.piston_position(beta + h, 0.04, 0.14) - kin.piston_position(beta - h, 0.04, 0.14)) / (
        2 * h
    )
    np.testing.assert_allclose(v, 100.0 * fd, atol=1e-6)
    assert s[0] == pytest.approx(0.04 + 0.14)


# --- Fourier coefficients ---------------------------------------------------------------


def _mp_coefficients(lam: float, eps: float, orders: list[int]) -> list[complex]:
    """a_k - i b_k of -s''/r at 30 digits, by the trapezoidal rule on n equally spaced
    angles, done with n = 256 and n = 512 and checked to agree to 1e-25.

    For a periodic analytic integrand the rule converges geometrically, its error falling
    like exp(-(n - k) d), d the distance of the nearest singularity of the integrand from
    the real axis (where lam |sin x - eps| = 1; d = 0.32 at lam 0.95), so both are exact
    to the working precision (they agree with mpmath.quad to 1e-31)."""

    def f(x):
        u = mpmath.sin(x) - eps
        D = mpmath.sqrt(1 - (lam * u) ** 2)
        c = mpmath.cos(x)
        return c + lam * ((c**2 - u * mpmath.sin(x)) / D + (lam * u * c) ** 2 / D**3)

    def trapezoid(n: int) -> list:
        x = [2 * mpmath.pi * j / n for j in range(n)]
        values = [f(xj) for xj in x]
        turns = [mpmath.expj(-xj) for xj in x]
        pairs = list(zip(values, turns, strict=True))
        return [mpmath.fsum(v * w**k for v, w in pairs) * 2 / n for k in orders]

    with mpmath.workdps(30):
        coarse, fine = trapezoid(256), trapezoid(512)
        assert max(abs(a - b) for a, b in zip(coarse, fine, strict=True)) < 1e-25  # converged
    return [complex(c) for c in fine]


def _mp_coefficient(lam: float, eps: float, k: int) -> complex:
    """a_k - i b_k of -s''/r by adaptive quadrature (mpmath.quad) at 30 digits, for rod
    ratios so close to 1 that the trapezoidal rule needs thousands of angles."""

    def f(x):
        u = mpmath.sin(x) - eps
        D = mpmath.sqrt(1 - (lam * u) ** 2)
        c = mpmath.cos(x)
        return c + lam * ((c**2 - u * mpmath.sin(x)) / D + (lam * u * c) ** 2 / D**3)

    with mpmath.workdps(30):
        pts = mpmath.linspace(0, 2 * mpmath.pi, 17)
        a = mpmath.quad(lambda x: f(x) * mpmath.cos(k * x), pts) / mpmath.pi
        b = mpmath.quad(lambda x: f(x) * mpmath.sin(k * x), pts) / mpmath.pi
    return complex(float(a), -float(b))


@pytest.mark.parametrize(
    ("lam", "eps"), [(0.1, 0.0), (0.25, 0.0), (0.31, 0.15), (0.5, -0.3), (0.8, 0.1), (0.95, 0.0)]
)
def test_exact_coefficients_match_quadrature(lam, eps):
    orders = [1, 2, 3, 4, 5, 6, 8]
    got = kin.acceleration_coefficients(lam, eps, orders)
    want = np.array(_mp_coefficients(lam, eps, orders))
    # the rounding floor grows with the peak of the acceleration near lambda -> 1
    floor = 1e-14 / (1 - lam * (1 + abs(eps))) ** 1.5
    np.testing.assert_allclose(got, want, rtol=0, atol=floor)


def test_series_closed_form_matches_domain_terms():
    """Binomial series of the acceleration (Taylor 1985, vol. 2, ch. 8; derivation in
    docs/theory.md): A2 = l + l^3/4 + 15 l^5/128, A4 = -(l^3/4 + 3 l^5/16),
    A6 = 9 l^5/128 (l = lambda)."""
    lam = np.array([0.05, 0.2, 0.26, 0.31, 0.5])
    np.testing.assert_allclose(
        kin.series_coefficients_centred(lam, 3, 2), lam + lam**3 / 4 + 15 * lam**5 / 128, rtol=1e-15
    )
    np.testing.assert_allclose(
        kin.series_coefficients_centred(lam, 3, 4), -(lam**3 / 4 + 3 * lam**5 / 16), rtol=1e-15
    )
    np.testing.assert_allclose(
        kin.series_coefficients_centred(lam, 3, 6), 9 * lam**5 / 128, rtol=1e-15
    )
    assert np.all(kin.series_coefficients_centred(lam, 3, 3) == 0)
    assert np.all(kin.series_coefficients_centred(lam, 3, 1) == 1)


@pytest.mark.parametrize("terms", [1, 2, 3, 6, 10])
def test_series_model_equals_closed_form_without_offset(terms):
    lam = np.array([0.1, 0.26, 0.4])
    orders = [1, 2, 3, 4, 6, 8]
    got = kin.acceleration_coefficients(lam, 0.0, orders, model="series", terms=terms)
    want = np.stack([kin.series_coefficients_centred(lam, terms, k) for k in orders], axis=-1)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-15)


@pytest.mark.parametrize(("lam", "eps"), [(0.25, 0.0), (0.3, 0.2), (0.45, -0.4)])
def test_series_converges_to_exact(lam, eps):
    orders = list(range(1, 9))
    exact = kin.acceleration_coefficients(lam, eps, orders)
    errors = [
        np.abs(kin.acceleration_coefficients(lam, eps, orders, "series", n) - exact).max()
        for n in (1, 2, 4, 8, 16)
    ]
    assert all(b < a for a, b in itertools.pairwise(errors) if a > 1e-14)
    # truncation after n terms leaves an error of order x^(2n+1), x = lambda (1 + |e|/r)
    x = lam * (1 + abs(eps))
    for n, err in zip((1, 2, 4, 8, 16), errors, strict=True):
        assert err < 4 * x ** (2 * n + 1) + 1e-15


def test_textbook_model_is_two_terms():
    got = kin.acceleration_coefficients([0.2, 0.3], [0.0, 0.5], [1, 2, 3], model="textbook")
    np.testing.assert_array_equal(got, [[1, 0.2, 0], [1, 0.3, 0]])


def test_unknown_model_and_bad_orders_are_errors():
    with pytest.raises(AnalysisError, match="unknown model"):
        kin.acceleration_coefficients(0.3, 0.0, [1], model="magic")
    with pytest.raises(AnalysisError, match="orders start at 1"):
        kin.acceleration_coefficients(0.3, 0.0, [0, 1])


def test_zero_offset_has_only_cosines_and_even_orders():
    got = kin.acceleration_coefficients(np.linspace(0.05, 0.6, 8), 0.0, range(1, 10))
    assert np.abs(got.imag).max() < 1e-15
    assert np.abs(got[:, 2::2].real).max() < 1e-15  # orders 3, 5, 7, 9
    np.testing.assert_allclose(got[:, 0].real, 1.0, atol=1e-15)


@given(lam=st.floats(0.01, 0.7), eps_share=st.floats(0.0, 0.9))
def test_offset_mirror_symmetry(lam, eps_share):
    """f(-beta; -e) = f(beta; e): a_k is even in the offset, b_k odd."""
    eps = eps_share * (1 / lam - 1)
    plus = kin.acceleration_coefficients(lam, eps, range(1, 7))
    minus = kin.acceleration_coefficients(lam, -eps, range(1, 7))
    np.testing.assert_allclose(plus, np.conj(minus), atol=1e-13)


@pytest.mark.parametrize("lam", [1e-9, 1e-6, 0.999])
def test_extreme_rod_ratios_are_finite_and_right(lam):
    got = kin.acceleration_coefficients(lam, 0.0, [1, 2, 4])
    assert np.all(np.isfinite(got))
    assert got[0].real == pytest.approx(1.0, abs=1e-13)
    if lam < 1e-3:
        assert got[1].real == pytest.approx(lam, rel=1e-9)
    else:
        assert got[1].real == pytest.approx(_mp_coefficient(lam, 0.0, 2).real, rel=1e-10)


def test_roll_coefficients_first_approximation():
    """Two-mass rod, no offset: roll ~ (1/2) m r^2 w^2 sin 2 beta + O(lambda)."""
    rec, rod = kin.roll_coefficients(1e-6, 0.0, [1, 2, 3])
    np.testing.assert_allclose(rec, [0, -0.5j, 0], atol=1e-5)
    assert np.abs(rod).max() < 1e-5
