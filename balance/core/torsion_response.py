r"""The linear dynamics of a torsional mass-elastic system: matrices, modes, steady state.

A crank train's torsional model (docs/torsion.md) is a chain of rigid inertias
:math:`J_1 \dots J_n` on shaft sections of stiffness :math:`k_j` (between masses j and j+1),
with damper rings of inertia :math:`J_r` hung on some masses by a coupling of stiffness
:math:`k_r` (0 for a viscous damper) and damping :math:`c_r`.  Each mass and ring has one
angle :math:`q`, its small vibratory rotation on top of the steady rotation.  With the
inertia matrix :math:`M`, the stiffness :math:`K` (sections and couplings), the sections'
part :math:`K_s` of it, the viscous damping :math:`C` (in the sections, in the couplings and
from masses to the block) and the sections' loss factor :math:`\eta`:

.. math::

    M\ddot q + C\dot q + (K + i\eta K_s)\,q = T(t).

This module knows nothing of engines: it assembles the matrices (:func:`assemble`), finds
the undamped modes (:func:`normal_modes`), solves the steady state of harmonic excitation
exactly, every frequency in one batched solve (:func:`harmonic_response`), and forms what
is reported from it: the half range of a periodic sum of harmonics (:func:`half_range`),
relative amplitude sums (:func:`vector_sums`) and the power a damper dissipates
(:func:`coupling_power`).

.. rubric:: References

J. P. Den Hartog, *Mechanical Vibrations*, 4th ed., McGraw-Hill 1956, §3.3-3.4 (the damped
vibration absorber, the untuned damper) and chs. 4-5 (many-mass torsional systems);
W. K. Wilson, *Practical Solution of Torsional Vibration Problems*, vol. 1, 3rd ed.,
Chapman & Hall 1956 (the mass-elastic system, Holzer's tabulation); W. T. Thomson, *Theory
of Vibration with Applications*, Prentice Hall (the generalised eigenproblem and its
Cholesky reduction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core.phasors import cancel_to_zero

__all__ = [
    "TrainMatrices",
    "assemble",
    "coupling_power",
    "half_range",
    "harmonic_response",
    "normal_modes",
    "vector_sums",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.intp]

#: Samples of a period per harmonic of the highest order before the extremes are refined
#: by Newton's method (:func:`half_range`).
SAMPLES_PER_HARMONIC = 8
#: Newton steps that refine an extreme of a trigonometric sum at least (its value is then
#: taken to third order, :func:`_newton`).
NEWTON_STEPS = 2
#: Newton steps go on past :data:`NEWTON_STEPS` until every step is at most this [rad]: the
#: third-order value is then exact to about :math:`h^3|X|\,\Delta t^3`, below 1e-13 of the
#: sum for 24 harmonics.  Where the sum is far from a parabola over the sampling step (an
#: asymmetric extreme between two samples), two steps from the parabola's vertex can stop
#: 4e-6 short of the extreme's value (a sum of 22 harmonics hypothesis found).
NEWTON_STEP_TOLERANCE = 1e-6
#: Newton steps at most.
NEWTON_STEPS_MAX = 50
#: Points across a sample interval at which the bound of a sum above its Hermite cubic is
#: evaluated (:func:`_beside`).
_GRID = np.linspace(0.0, 1.0, 17)


@dataclass(frozen=True, eq=False)
class TrainMatrices:
    """The matrices of a torsional system (SI: kg m^2, N m/rad, N m s/rad).

    The coordinates are the masses 1..n in order, then one ring per damper in the order
    the dampers are given.

    Attributes
    ----------
    mass : ndarray, shape (N, N)
        :math:`M`, the inertias on the diagonal.
    stiffness : ndarray, shape (N, N)
        :math:`K`: the shaft sections and the tuned couplings.
    section_stiffness : ndarray, shape (N, N)
        :math:`K_s`: the shaft sections' part of :math:`K` (what the loss factor acts on).
    damping : ndarray, shape (N, N)
        :math:`C`: viscous damping in the sections, in the couplings and to the block.
    loss_factor : float
        :math:`\\eta` of every shaft section [1].
    n_masses : int
        Number of masses (the first coordinates).
    hubs : ndarray of int
        The coordinate (0-based) of the mass each damper is hung on.
    tuned : ndarray of bool
        Which dampers have a coupling stiffness (their rings take part in the modes).
    """

    mass: FloatArray
    stiffness: FloatArray
    section_stiffness: FloatArray
    damping: FloatArray
    loss_factor: float
    n_masses: int
    hubs: IntArray
    tuned: NDArray[np.bool_]

    @property
    def size(self) -> int:
        """Number of coordinates (masses and rings)."""
        return int(self.mass.shape[0])

    @property
    def rings(self) -> IntArray:
        """The coordinates of the damper rings."""
        return np.arange(self.n_masses, self.size, dtype=np.intp)

    @property
    def damped(self) -> bool:
        """Whether there is any damping (viscous or hysteretic)."""
        return bool(np.any(self.damping != 0.0)) or self.loss_factor > 0.0

    def modal_coordinates(self) -> IntArray:
        """The coordinates of the undamped modes: the masses and the tuned rings (a viscous
        damper's ring is held by nothing elastic)."""
        return np.concatenate(
            [np.arange(self.n_masses, dtype=np.intp), self.rings[self.tuned]]
        ).astype(np.intp)


def _couple(matrix: FloatArray, i: int, j: int, value: float) -> None:
    """Add a spring (or dashpot) of ``value`` between coordinates ``i`` and ``j``."""
    matrix[i, i] += value
    matrix[j, j] += value
    matrix[i, j] -= value
    matrix[j, i] -= value


def assemble(
    inertia: ArrayLike,
    section_stiffness: ArrayLike,
    section_damping: ArrayLike,
    mass_damping: ArrayLike,
    damper_at: ArrayLike = (),
    damper_inertia: ArrayLike = (),
    damper_stiffness: ArrayLike = (),
    damper_damping: ArrayLike = (),
    loss_factor: float = 0.0,
) -> TrainMatrices:
    """The matrices of a chain of masses on shaft sections with damper rings.

    Parameters
    ----------
    inertia : array_like, shape (n,)
        Inertia of each mass, free end first [kg m^2].
    section_stiffness, section_damping : array_like, shape (n - 1,)
        Stiffness [N m/rad] and viscous damping [N m s/rad] of the section from mass j to
        mass j + 1.
    mass_damping : array_like, shape (n,)
        Viscous damping of each mass to the block [N m s/rad].
    damper_at : array_like of int, shape (d,)
        The mass (0-based) each damper's ring is hung on.
    damper_inertia, damper_stiffness, damper_damping : array_like, shape (d,)
        Ring inertia [kg m^2], coupling stiffness [N m/rad] (0: a viscous damper) and
        coupling damping [N m s/rad].
    loss_factor : float
        Hysteretic loss factor of every shaft section [1].

    Returns
    -------
    TrainMatrices
    """
    j_masses = np.asarray(inertia, dtype=np.float64)
    k_sec = np.asarray(section_stiffness, dtype=np.float64)
    c_sec = np.asarray(section_damping, dtype=np.float64)
    at = np.asarray(damper_at, dtype=np.intp).reshape(-1)
    j_ring = np.asarray(damper_inertia, dtype=np.float64).reshape(-1)
    k_ring = np.asarray(damper_stiffness, dtype=np.float64).reshape(-1)
    c_ring = np.asarray(damper_damping, dtype=np.float64).reshape(-1)
    n = j_masses.size
    size = n + at.size
    mass = np.diag(np.concatenate([j_masses, j_ring]))
    ks = np.zeros((size, size))
    k = np.zeros((size, size))
    c = np.zeros((size, size))
    for j in range(n - 1):
        _couple(ks, j, j + 1, float(k_sec[j]))
        _couple(c, j, j + 1, float(c_sec[j]))
    k += ks
    c[np.arange(n), np.arange(n)] += np.asarray(mass_damping, dtype=np.float64)
    for r in range(at.size):
        _couple(k, int(at[r]), n + r, float(k_ring[r]))
        _couple(c, int(at[r]), n + r, float(c_ring[r]))
    return TrainMatrices(
        mass=mass,
        stiffness=k,
        section_stiffness=ks,
        damping=c,
        loss_factor=float(loss_factor),
        n_masses=n,
        hubs=at,
        tuned=np.asarray(k_ring > 0.0),
    )


def normal_modes(matrices: TrainMatrices) -> tuple[FloatArray, FloatArray]:
    r"""The undamped modes of the system, the rigid-body mode left out.

    Parameters
    ----------
    matrices : TrainMatrices
        The system; damping and the loss factor are ignored, and the rings of viscous
        dampers (held by nothing elastic) are left out.

    Returns
    -------
    frequency : ndarray, shape (m,)
        Natural frequencies [Hz], ascending.
    shape : ndarray, shape (m, n + t)
        Mode shapes at the masses, then at the tuned rings (in the order of the dampers),
        each normalised to +1 at mass 1 (to its largest amplitude, +1, in the rare mode
        in which mass 1 stands still).

    Notes
    -----
    :math:`K\varphi = \omega^2 M\varphi` is reduced to a symmetric standard problem with
    the Cholesky factor :math:`M = LL^T`: :math:`(L^{-1}KL^{-T})\,y = \omega^2 y`,
    :math:`\varphi = L^{-T}y`.  The train is free at both ends and held together by
    positive stiffnesses, so exactly one eigenvalue is zero, the rigid-body rotation; it is
    the smallest and is dropped.
    """
    keep = matrices.modal_coordinates()
    m = matrices.mass[np.ix_(keep, keep)]
    k = matrices.stiffness[np.ix_(keep, keep)]
    lower = np.linalg.cholesky(m)
    inv = np.linalg.inv(lower)
    reduced = inv @ k @ inv.T
    reduced = 0.5 * (reduced + reduced.T)
    eigenvalues, vectors = np.linalg.eigh(reduced)
    shapes = (inv.T @ vectors).T[1:]
    omega2 = np.maximum(eigenvalues[1:], 0.0)
    frequency = np.sqrt(omega2) / (2.0 * math.pi)
    return np.asarray(frequency, dtype=np.float64), _normalised(shapes)


def _normalised(shapes: FloatArray) -> FloatArray:
    """Each shape (a row) divided by its value at mass 1 (the first coordinate), or by its
    largest-magnitude value where mass 1 stands still."""
    out = np.array(shapes, dtype=np.float64, copy=True)
    for row in out:
        largest = float(np.max(np.abs(row)))
        pivot = float(row[0])
        if abs(pivot) <= 1e-9 * largest:
            pivot = float(row[int(np.argmax(np.abs(row)))])
        row /= pivot
    return out


def harmonic_response(
    matrices: TrainMatrices, frequency: ArrayLike, forces: ArrayLike
) -> ComplexArray:
    r"""The exact steady state of harmonic excitation, one batched solve.

    Parameters
    ----------
    matrices : TrainMatrices
        The system.
    frequency : array_like, shape (...)
        Angular frequency :math:`\omega` of each excitation [rad/s], above zero.
    forces : array_like of complex, shape (..., N)
        Complex torque amplitudes :math:`F` on each coordinate [N m]: the torque is
        :math:`\operatorname{Re}(F e^{i\omega t})`.

    Returns
    -------
    ndarray of complex, shape (..., N)
        :math:`Q` with :math:`(K + i\eta K_s - \omega^2 M + i\omega C)\,Q = F` [rad]: the
        angle is :math:`\operatorname{Re}(Q e^{i\omega t})`.

    Notes
    -----
    No modal truncation: every frequency's system is solved as it stands, all of them
    stacked into one call of :func:`numpy.linalg.solve`.  A damper ring with damping is held
    by its coupling alone, :math:`Z = k_r + i\omega c_r` to its hub; its equation,
    :math:`-Z Q_h + (Z - \omega^2 J_r) Q_r = F_r`, is solved for :math:`Q_r` and put into the
    hub's (exact elimination, never singular since :math:`\operatorname{Im} D = \omega c_r
    > 0`), so that the stacked systems are smaller by one row per such ring.
    """
    w = np.asarray(frequency, dtype=np.float64)
    f = np.asarray(forces, dtype=np.complex128)
    size = matrices.size
    rings = matrices.rings
    damped = rings[np.diag(matrices.damping)[rings] > 0.0]  # rings eliminated exactly
    keep = np.setdiff1d(np.arange(size), damped)
    static = matrices.stiffness + 1j * matrices.loss_factor * matrices.section_stiffness
    damping = matrices.damping[np.ix_(keep, keep)]
    system = np.empty((*w.shape, keep.size, keep.size), dtype=np.complex128)
    system[...] = static[np.ix_(keep, keep)]
    diagonal = np.arange(keep.size)  # M is diagonal
    system[..., diagonal, diagonal] -= (w * w)[..., None] * np.diag(matrices.mass)[keep]
    row, col = np.nonzero(damping)  # C is sparse: the chain and the couplings
    system[..., row, col] += (1j * w)[..., None] * damping[row, col]
    rhs = f[..., keep]
    eliminated = []
    for ring in damped:
        hub = int(np.searchsorted(keep, matrices.hubs[ring - matrices.n_masses]))
        coupling = matrices.stiffness[ring, ring] + 1j * w * matrices.damping[ring, ring]
        ring_stiffness = coupling - w * w * matrices.mass[ring, ring]
        system[..., hub, hub] -= coupling * coupling / ring_stiffness
        rhs[..., hub] += coupling * f[..., ring] / ring_stiffness
        eliminated.append((ring, hub, coupling, ring_stiffness))
    reduced = np.linalg.solve(system, rhs[..., None])[..., 0]
    q = np.empty(f.shape, dtype=np.complex128)
    q[..., keep] = reduced
    for ring, hub, coupling, ring_stiffness in eliminated:
        q[..., ring] = (f[..., ring] + coupling * reduced[..., hub]) / ring_stiffness
    return q


def coupling_power(
    frequency: ArrayLike, damping: float, hub: ComplexArray, ring: ComplexArray
) -> FloatArray:
    r"""Mean power dissipated in a viscous coupling [W]:
    :math:`\omega^2 c\,|Q_{hub} - Q_{ring}|^2 / 2`.

    Parameters
    ----------
    frequency : array_like
        Angular frequency :math:`\omega` [rad/s].
    damping : float
        The coupling's viscous damping :math:`c` [N m s/rad].
    hub, ring : ndarray of complex
        Complex amplitudes of the hub and of the ring [rad] (broadcast with ``frequency``).
    """
    w = np.asarray(frequency, dtype=np.float64)
    return np.asarray(0.5 * w * w * damping * np.abs(hub - ring) ** 2, dtype=np.float64)


def vector_sums(
    shapes: ArrayLike, cylinder_mass: ArrayLike, firing_tdc: ArrayLike, orders: ArrayLike
) -> FloatArray:
    r"""Relative amplitude (vector) sums :math:`|\sum_c \varphi_j(\text{mass of } c)\,
    e^{-ik\theta_c}|` of every mode and order.

    Parameters
    ----------
    shapes : array_like, shape (m, n...)
        Mode shapes at the masses (rings may follow; they are not read).
    cylinder_mass : array_like of int, shape (c,)
        The mass (0-based) each cylinder is on.
    firing_tdc : array_like, shape (c,)
        Crank angle :math:`\theta_c` of each cylinder's firing TDC [deg].
    orders : array_like, shape (K,)
        The orders :math:`k`.

    Returns
    -------
    ndarray, shape (m, K)

    Notes
    -----
    The classical :math:`\sum\beta` of Wilson (1956) and Nestorides (1958): the work of
    order k done on mode j per cycle is proportional to it.  For an engine firing evenly
    z times a cycle every cylinder has the same phase at the major orders (multiples of
    :math:`z \cdot 360/\text{cycle}`), and the sum is the plain sum of the amplitudes.
    A sum that cancels to rounding (:func:`balance.core.phasors.cancel_to_zero`) is 0.
    """
    phi = np.asarray(shapes, dtype=np.float64)[:, np.asarray(cylinder_mass, dtype=np.intp)]
    theta = np.radians(np.asarray(firing_tdc, dtype=np.float64))
    k = np.asarray(orders, dtype=np.float64)
    phase = np.exp(-1j * k[:, None] * theta[None, :])  # (K, c)
    total = cancel_to_zero(phi @ phase.T, np.sum(np.abs(phi), axis=1)[:, None], theta.size)
    return np.asarray(np.abs(total), dtype=np.float64)


def half_range(coefficients: ArrayLike, harmonics: ArrayLike) -> FloatArray:
    r"""Half the range, :math:`(\max - \min)/2`, over a period of sums of harmonics.

    Parameters
    ----------
    coefficients : array_like of complex, shape (..., K)
        :math:`X_h` of :math:`f(t) = \sum_h \operatorname{Re}(X_h e^{iht})`.
    harmonics : array_like of int, shape (K,)
        The harmonic numbers :math:`h \ge 1` (distinct), per period of :math:`2\pi`.

    Returns
    -------
    ndarray, shape (...)

    Notes
    -----
    :math:`f` is sampled at :data:`SAMPLES_PER_HARMONIC` points per period of its highest
    harmonic, :math:`n` points a period (an inverse real FFT).  The true extreme lies within
    half a step :math:`\delta = 2\pi/n` of a sample, so it is beyond the most extreme
    sample by at most :math:`B = \delta^2 \sum_h h^2|X_h| / 8`.  Every local extreme of the
    samples within :math:`B` of the most extreme one is refined by Newton's method on
    :math:`f' = 0` (:data:`NEWTON_STEPS` steps, more until they are below
    :data:`NEWTON_STEP_TOLERANCE`) (a refined point replaces its sample only where it is
    beyond it), and the most extreme is kept.  An extreme beside no local extreme of the
    samples, or in the sample interval of the extreme found, is sought where Hermite's
    cubic through :math:`f` and :math:`f'` at an interval's ends, with its error bound,
    could rise beyond it (:func:`_beside`): the extremes are those of the trigonometric
    sum, not of the grid (docs/torsion.md, "Synthesis").
    """
    x = np.asarray(coefficients, dtype=np.complex128)
    h = np.asarray(harmonics, dtype=np.intp)
    lead = x.shape[:-1]
    if h.size == 0:
        return np.zeros(lead)
    top = int(h.max())
    n = max(64, SAMPLES_PER_HARMONIC * top)
    flat = x.reshape(-1, h.size)
    m = flat.shape[0]
    spectrum = np.zeros((m, n // 2 + 1), dtype=np.complex128)
    spectrum[:, h] = flat * (n / 2.0)
    samples = np.fft.irfft(spectrum, n=n, axis=-1)
    step = 2.0 * math.pi / n
    bound = step * step / 8.0 * (np.abs(flat) @ (h * h).astype(np.float64))
    extreme = np.concatenate([np.max(samples, axis=1), -np.min(samples, axis=1)])
    rows, starts = [], []
    samples_at: list[tuple[FloatArray, FloatArray]] = []
    near_at: list[IntArray] = []
    for sign, best in ((1.0, extreme[:m]), (-1.0, extreme[m:])):
        g = sign * samples
        near = np.flatnonzero(g >= (best - bound)[:, None])  # flat: faster than 2-D nonzero
        near_at.append(near)
        row, col = near // n, near % n
        before, here, after = g[row, col - 1], g[row, col], g[row, (col + 1) % n]
        peak = (here > before) & (here >= after)
        # the vertex of the parabola through the three samples of each local extreme: a
        # start within a small fraction of a step of the extreme
        before, here, after, col = before[peak], here[peak], after[peak], col[peak]
        curve = before - 2.0 * here + after
        shift = np.where(curve < 0.0, 0.5 * (before - after) / np.where(curve < 0, curve, 1), 0.0)
        rows.append(row[peak] + (0 if sign > 0 else m))
        starts.append(step * (col + np.clip(shift, -0.5, 0.5)))
        samples_at.append((np.asarray(step * col, dtype=np.float64), here))
    row = np.concatenate(rows)
    sense = np.asarray(np.where(row < m, 1.0, -1.0), dtype=np.float64)
    start = np.asarray(np.concatenate(starts), dtype=np.float64)
    value, point, bend = _refine(flat[row % m], h, start, sense)
    refined = sense * value
    # where the parabola's vertex led Newton to another, lower extreme (several within one
    # step), start again from the sample itself
    sample_t = np.concatenate([t for t, _ in samples_at])
    sample_value = np.concatenate([v for _, v in samples_at])
    astray = np.flatnonzero(refined < sample_value)
    if astray.size:
        value, again_at, again_bend = _refine(
            flat[row[astray] % m], h, sample_t[astray], sense[astray]
        )
        again = sense[astray] * value
        better = again > refined[astray]
        point[astray] = np.where(better, again_at, point[astray])
        bend[astray] = np.where(better, again_bend, bend[astray])
        refined[astray] = np.maximum(refined[astray], again)
    np.maximum.at(extreme, row, refined)  # a refined extreme replaces its sample if beyond
    # where each extreme is if refined (f' = 0 there), and f'' there times the sense; NaN:
    # the extreme is a sample
    at, curve = np.full(2 * m, np.nan), np.zeros(2 * m)
    kept = refined >= extreme[row]
    at[row[kept]], curve[row[kept]] = point[kept], bend[kept]
    _beside(extreme, at, curve, flat, h, samples, near_at, step)
    return np.asarray(0.5 * (extreme[:m] + extreme[m:]), dtype=np.float64).reshape(lead)


def _beside(
    extreme: FloatArray,
    at: FloatArray,
    curve: FloatArray,
    x: ComplexArray,
    h: IntArray,
    samples: FloatArray,
    near_at: list[IntArray],
    step: float,
) -> None:
    r"""Raise ``extreme`` (the maxima of the rows of ``x``, then minus their minima) to the
    extremes that lie beside no local extreme of the samples.

    Only a sample interval with an end among the near samples (``near_at``, flat indices
    per sense) can hold an extreme beyond ``extreme``, and only if each end is within
    :math:`\max|f''|/2` times its distance squared of it.  The interval that holds a
    refined extreme (``at``, where :math:`f' = 0`; NaN where the extreme is a sample) is
    split there in two.  Within :math:`3|f''|/\max|f'''|` of a refined extreme
    (``curve``: :math:`f''` there, times the sense) :math:`f` stays below it (Taylor's
    series to third order): an interval or piece within that is left out.  On each piece
    :math:`[a, b]` the Hermite cubic :math:`p` through :math:`f` and :math:`f'` at its ends
    is within :math:`\max|f^{(4)}|\,(t - a)^2(t - b)^2/24` of :math:`f`,
    :math:`\max|f^{(4)}| \le \sum_h h^4|X_h|`.  Where that bound over
    :math:`p`, evaluated on :data:`_GRID` and padded by the grid's error, rises beyond the
    extreme by more than rounding, Newton's method starts from its highest point, and a
    value beyond the extreme by more than rounding replaces it (an extreme already found
    is kept as it was)."""
    m, n = samples.shape
    size = np.abs(x)
    power = h.astype(np.float64) ** 2
    curvature = size @ power  # at least |f''|
    third = size @ (power * h)  # at least |f'''|
    fourth = size @ (power * power)  # at least |f''''|
    rounding = 1e-13 * np.sum(size, axis=1)
    # the intervals (by their first sample, flat over both senses) with a near end: the
    # near samples and those before them (once: the near are sorted)
    ends = np.concatenate([near_at[0], near_at[1] + m * n])
    before = ends - 1 + n * (ends % n == 0)
    first = np.concatenate([ends, before[np.concatenate([[True], ends[:-1] != ends[1:] - 1])]])
    row, col = first // n, first % n  # row: 0..2m (minima after maxima)
    sign = np.where(row < m, 1.0, -1.0)
    fa = sign * samples.reshape(-1)[first % (m * n)]
    nxt = (col + 1) % n
    fb = sign * samples.reshape(-1)[(row % m) * n + nxt]
    into = np.mod(at[row], 2.0 * math.pi) - step * col  # the refined extreme, if in it
    split = (into >= 0.0) & (into < step)
    gap = np.sqrt(np.maximum(extreme[row] - fa, 0.0)) + np.sqrt(np.maximum(extreme[row] - fb, 0.0))
    # within the radius of a refined extreme about it, f stays below it
    radius = 3.0 * np.maximum(-curve[row], 0.0) / np.maximum(third[row % m], 1e-300)
    lead = np.mod(step * col - at[row] + math.pi, 2.0 * math.pi) - math.pi
    far = np.isnan(at[row]) | (np.maximum(np.abs(lead), np.abs(lead + step)) >= radius)
    keep = far & (split | (gap <= step * np.sqrt(0.5 * curvature[row % m])))
    row, col, nxt, sign = row[keep], col[keep], nxt[keep], sign[keep]
    fa, fb, split, into, radius = fa[keep], fb[keep], split[keep], into[keep], radius[keep]
    if not row.size:
        return
    # f' at the ends: the sums at the samples' turns e^{iht}, times ih
    turns = np.exp((2.0j * math.pi / n) * np.outer(np.arange(n), h)) * (1j * h)
    xs = x[row % m]
    sa = sign * np.einsum("kh,kh->k", xs, turns[col]).real
    sb = sign * np.einsum("kh,kh->k", xs, turns[nxt]).real
    # the pieces: the whole intervals, then each side of each refined extreme, taken from
    # the extreme outwards (u = 0 there, where f = extreme and f' = 0)
    whole, cut = np.flatnonzero(~split), np.flatnonzero(split)
    level, zero, into = extreme[row[cut]], np.zeros(cut.size), into[cut]
    piece = np.concatenate([whole, cut, cut])
    origin = step * col[piece] + np.concatenate([np.zeros(whole.size), into, into])
    way = np.concatenate([np.ones(whole.size), -np.ones(cut.size), np.ones(cut.size)])
    length = np.concatenate([np.full(whole.size, step), into, step - into])
    fa, fb = (
        np.concatenate([fa[whole], level, level]),
        np.concatenate([fb[whole], fa[cut], fb[cut]]),
    )
    da = length * np.concatenate([sa[whole], zero, zero])
    db = length * way * np.concatenate([sb[whole], sa[cut], sb[cut]])
    row = row[piece]
    # the cubic fa + da u + c2 u^2 + c3 u^3 through f and f' at the ends, and f's bound
    # above it, the cubic plus the error of Hermite's interpolation, bump u^2 (1 - u)^2
    rise = fb - fa
    c2 = 3.0 * rise - 2.0 * da - db
    c3 = da + db - 2.0 * rise
    bump = fourth[row % m] * length**4 / 24.0
    u = _GRID[None, :]
    above = fa[:, None] + u * (da[:, None] + u * (c2[:, None] + u * c3[:, None]))
    above += bump[:, None] * (u * (1.0 - u)) ** 2
    best = np.argmax(above, axis=1)
    # a whole interval: the bound's maximum between the points of the grid is within a
    # grid step's square over 8 times its second derivative of the largest
    pad = (2.0 * np.abs(c2) + 6.0 * np.abs(c3) + 2.0 * bump) / (8.0 * (_GRID.size - 1) ** 2)
    beyond_whole = above[np.arange(row.size), best] + pad > extreme[row] + rounding[row % m]
    # beside a refined extreme the bound less the extreme is u^2 (c2 + c3 u + bump (1 - u)^2),
    # a convex quadratic in the brackets: beyond the extreme somewhere only if beyond at an
    # end, c2 + bump > 0 (c2 + c3 = fb - fa, a sample's excess, is never above 0)
    keep = np.where(np.arange(row.size) < whole.size, beyond_whole, c2 + bump > 0.0)
    keep &= length >= radius[piece]
    row = row[keep]
    if not row.size:
        return
    sense = np.where(row < m, 1.0, -1.0)
    begin = origin[keep] + way[keep] * length[keep] * _GRID[best[keep]]
    value = sense * _newton(x[row % m], h, begin, sense)
    beyond = value > extreme[row] + rounding[row % m]
    np.maximum.at(extreme, row[beyond], value[beyond])


def _newton(x: ComplexArray, h: IntArray, start: FloatArray, sense: FloatArray) -> FloatArray:
    """The value of each sum at the extreme Newton's method finds from ``start``
    (:func:`_refine`)."""
    return _refine(x, h, start, sense)[0]


def _refine(
    x: ComplexArray, h: IntArray, start: FloatArray, sense: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    r"""The value of each trigonometric sum (rows of ``x``) at the extreme (``sense`` +1: a
    maximum, -1: a minimum) found by Newton's method on its derivative from ``start``:
    :data:`NEWTON_STEPS` steps, more while a step is beyond :data:`NEWTON_STEP_TOLERANCE`
    (at most :data:`NEWTON_STEPS_MAX`), then the value at the last point corrected by its
    Taylor series, :math:`f - f'^2/(2f'')`, the value at the next Newton point to third
    order; with it that point and :math:`f''` at the last point times ``sense``.

    :math:`f`, :math:`f'` and :math:`f''` are the real parts of the polynomials
    :math:`\sum_h X_h z^h`, :math:`i\sum_h h X_h z^h` and :math:`-\sum_h h^2 X_h z^h` in
    :math:`z = e^{it}`, evaluated by Horner's rule."""
    t = np.array(start, dtype=np.float64, copy=True)
    top = int(h.max()) if h.size else 1
    dense = np.zeros((top, x.shape[0]), dtype=np.complex128)  # X_h of h = 1..top, rows
    dense[h - 1] = x.T
    last = False  # the value is needed at the last point only
    for step in range(NEWTON_STEPS_MAX + 1):
        z = np.exp(1j * t)
        s0 = np.zeros(t.shape, dtype=np.complex128)
        s1 = np.zeros(t.shape, dtype=np.complex128)
        s2 = np.zeros(t.shape, dtype=np.complex128)
        last = last or step == NEWTON_STEPS_MAX
        for power in range(top, 0, -1):
            c = dense[power - 1]
            if last:
                s0 = s0 * z + c
            s1 = s1 * z + power * c
            s2 = s2 * z + (power * power) * c
        value, d1, d2 = (s0 * z).real, -(s1 * z).imag, -(s2 * z).real
        ok = sense * d2 < 0.0  # curving the right way: a step towards the extreme
        move = np.where(ok, d1 / np.where(ok, d2, 1.0), 0.0)
        if last:
            return np.asarray(value - 0.5 * move * d1, dtype=np.float64), t - move, sense * d2
        t = t - move
        last = step + 1 >= NEWTON_STEPS and float(np.max(np.abs(move), initial=0.0)) <= (
            NEWTON_STEP_TOLERANCE
        )
    raise AssertionError("unreachable")  # pragma: no cover
