r"""Articulated (master-and-link) connecting rods: kinematics, Fourier coefficients, inertia
forces (the forces at the pistons and pins are :mod:`balance.core.link_forces`').

A *link cylinder* j hangs its rod on a pin of its *master* cylinder m's rod (docs/layout-format.md,
"Articulated rods"): both share the crank pin :math:`C`; the master rod runs from :math:`C` to the
master piston pin, and carries the link pin :math:`L` at ``pin_radius`` :math:`\rho` from
:math:`C`, at ``pin_angle`` :math:`\alpha` from its centre line; the link rod of length :math:`l_j`
runs from :math:`L` to the link piston pin on cylinder j's bore.

Notation
--------
Lengths are divided by the crank radius :math:`r`.  :math:`\beta_j = \theta + \varphi -
\psi_j` is the crank angle from cylinder j's nominal TDC direction, :math:`\beta_m =
\beta_j + \Delta` the master's with :math:`\Delta = \psi_j - \psi_m`; the master rod's angle
:math:`\gamma` from its bore axis has :math:`\sin\gamma = \lambda_m(\sin\beta_m -
\varepsilon_m)` (:func:`balance.core.kinematics.conrod_angle_derivatives`).  In cylinder j's
frame, as the complex number :math:`Y + iX` (Y along the bore, X across it towards where the
pin goes after TDC, docs/conventions.md, "Frame and angles"), the link pin is

.. math::

    \Lambda(\beta_j) = L/r = e^{i\beta_j} + \kappa\, e^{i(\delta - \gamma)}, \qquad
    \kappa = \rho/r, \quad \delta = \psi_m - \psi_j + \alpha,

and, with :math:`h = \operatorname{Im}\Lambda - \varepsilon_j` and :math:`\lambda_j = r/l_j`,
the link piston pin is at

.. math::

    s_j/r = \operatorname{Re}\Lambda + \sqrt{1 - \lambda_j^2 h^2}/\lambda_j .

Derivatives follow by the chain rule (:func:`link_motion`), so sampling gives velocity and
acceleration to rounding; the Fourier coefficients of every order come from the sampled
exact functions with :func:`balance.core.kinematics.fourier_coefficients` (adaptive doubling
until the aliased tail is below rounding; the functions are analytic and periodic, so the
tail falls geometrically).

Forces and roll
---------------
By static equivalence the link rod (mass :math:`m_L`, centre of gravity at :math:`c` from the
link pin on its centre line) is the mass :math:`m_L c/l_j` at the piston pin (with the piston,
the link cylinder's ``reciprocating_mass``) and :math:`m_L(1 - c/l_j)` at the link pin, whose
orbit :math:`L = C + \rho e^{i(\psi_m + \alpha - \gamma)}` (engine frame) is no circle.  Its
inertia force :math:`-m\omega^2 L''` is the centrifugal force of the mass at the crank pin
(counted with the rotating masses) plus

.. math::

    m\,\omega^2 \rho\, e^{i(\psi_m + \alpha)}\, q(\beta_m), \qquad
    q = e^{-i\gamma}\left(\gamma'^2 + i\gamma''\right),

which has forward and backward phasors at every order (:func:`pin_series`).  The roll torque
of a point mass moving on :math:`z(\theta)` at constant :math:`\omega` is
:math:`m\omega^2[\operatorname{Re}(\bar z' z'') - \operatorname{Im}(\bar z z'')]`
(:math:`-\mathrm dH/\mathrm dt + (\mathrm dT/\mathrm dt)/\omega`), which is
:math:`m\omega^2 s''(s' + e)` for a piston on its bore; a rod's inertia beyond its two-mass
model adds :math:`\Delta I\,\omega^2\gamma_l''(1 + \gamma_l')` with :math:`\gamma_l` the rod's
angle from its bore.  The derivation is on the theory page; :mod:`balance.core.sampled`
checks all of it against a Newton–Euler solution of the rigid bodies.

.. rubric:: References

Fearn, "The articulated connecting rod", Journal of the Royal Aeronautical Society, 1927
(the link piston's displacement as a Fourier series; the forces at the crank pin and on the
master rod).  C. F. Taylor, *The Internal-Combustion Engine in Theory and Practice*, vol. 2,
2nd ed., MIT Press 1985, ch. 8 (engine balance: the plain crank slider's treatment that this
module extends).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from balance.core import crank_train, phasors
from balance.core._numerics import newton_stationary, sampled_max_bound, sampled_vertex, unique_rows
from balance.core.engine import Engine, Links
from balance.core.kinematics import (
    conrod_angle_derivatives,
    fourier_coefficients,
    offset_ratio,
    rod_ratio,
    rounding_floor,
)

__all__ = [
    "LinkGeometry",
    "LinkMotion",
    "articulated_free_phasors",
    "engine_geometry",
    "link_dead_centres",
    "link_geometry",
    "link_motion",
    "link_reach",
    "link_torque_coefficients",
    "pin_masses",
    "pin_roll",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Crank angles per revolution of the first sampling of the dead-centre search.
DEAD_CENTRE_GRID = 64
#: Newton iterations of a dead centre (quadratic convergence from a grid point).
DEAD_CENTRE_ITERATIONS = 30
#: Crank angles per revolution of the reach check (:func:`link_reach`).
REACH_GRID = 128
#: Newton step [rad] after which a dead centre has converged: quadratic convergence puts
#: the next step below rounding; that one more step is taken.
DEAD_CENTRE_DONE = 1e-8


@dataclass(frozen=True)
class LinkGeometry:
    r"""Dimensionless geometry of the link cylinders, one entry per link cylinder.

    Attributes
    ----------
    cylinder, master : ndarray of int
        Index of the link cylinder and of its master.
    ratio_master, offset_master : ndarray
        :math:`\lambda_m = r/l_m` and :math:`\varepsilon_m = e_m/r` of the master rod.
    pin : ndarray
        :math:`\kappa = \rho/r`.
    pin_turn : ndarray
        :math:`\delta = \psi_m - \psi_j + \alpha` [rad]: the link pin's direction from the
        crank pin, relative to the link bore, when the master rod lies along its bore.
    shift : ndarray
        :math:`\Delta = \psi_j - \psi_m` [rad], so that :math:`\beta_m = \beta_j + \Delta`.
    ratio, offset : ndarray
        :math:`\lambda_j = r/l_j` and :math:`\varepsilon_j = e_j/r` of the link rod and bore.
    """

    cylinder: NDArray[np.intp]
    master: NDArray[np.intp]
    ratio_master: FloatArray
    offset_master: FloatArray
    pin: FloatArray
    pin_turn: FloatArray
    shift: FloatArray
    ratio: FloatArray
    offset: FloatArray

    @property
    def size(self) -> int:
        """Number of link cylinders."""
        return int(self.cylinder.size)

    def columns(self) -> tuple[FloatArray, ...]:
        """The seven parameters of :func:`link_motion`, each as a column (links, 1)."""
        return tuple(
            np.asarray(a, dtype=np.float64)[:, None]
            for a in (
                self.ratio_master,
                self.offset_master,
                self.pin,
                self.pin_turn,
                self.shift,
                self.ratio,
                self.offset,
            )
        )


def link_geometry(
    crank_radius: ArrayLike,
    conrod_length: ArrayLike,
    offset: ArrayLike,
    bank: ArrayLike,
    links: Links,
) -> LinkGeometry:
    """The :class:`LinkGeometry` of an engine's link cylinders from its per-cylinder arrays.

    Parameters
    ----------
    crank_radius, conrod_length, offset : array_like
        Per cylinder [m] (``conrod_length`` of a link cylinder is its link rod's length).
    bank : array_like
        Per cylinder [rad].
    links : Links
        The articulated rods (master, pin radius [m] and pin angle [rad] of each cylinder).

    Returns
    -------
    LinkGeometry
        One entry per link cylinder.
    """
    r = np.asarray(crank_radius, dtype=np.float64)
    length = np.asarray(conrod_length, dtype=np.float64)
    e = np.asarray(offset, dtype=np.float64)
    psi = np.asarray(bank, dtype=np.float64)
    j = links.link_indices
    m = links.master[j]
    return LinkGeometry(
        cylinder=j,
        master=m,
        ratio_master=rod_ratio(r[m], length[m]),
        offset_master=offset_ratio(e[m], r[m]),
        pin=np.asarray(links.pin_radius[j] / r[j], dtype=np.float64),
        pin_turn=np.asarray(psi[m] - psi[j] + links.pin_angle[j], dtype=np.float64),
        shift=np.asarray(psi[j] - psi[m], dtype=np.float64),
        ratio=rod_ratio(r[j], length[j]),
        offset=offset_ratio(e[j], r[j]),
    )


def engine_geometry(engine: Engine) -> LinkGeometry:
    """The :class:`LinkGeometry` of an engine with link rods (:func:`link_geometry` of its
    per-cylinder arrays).

    Parameters
    ----------
    engine : Engine
        An engine with link rods.

    Returns
    -------
    LinkGeometry
    """
    assert engine.links is not None
    return link_geometry(
        engine.crank_radius, engine.conrod_length, engine.offset, engine.bank, engine.links
    )


# --------------------------------------------------------------------------- kinematics


@dataclass(frozen=True)
class LinkMotion:
    r"""Motion of link cylinders over crank angles, lengths divided by :math:`r`.

    Derivatives are with respect to the crank angle (:math:`\times\omega` and
    :math:`\times\omega^2` for time derivatives at constant speed).

    Attributes
    ----------
    s, ds, d2s : ndarray
        Link piston pin's distance from the crank axis along its bore and derivatives.
    pin_y, pin_x, dpin_y, dpin_x, d2pin_y, d2pin_x : ndarray
        Link pin :math:`\Lambda = L/r` and its derivatives along (Y) and across (X) the link
        cylinder's bore (:attr:`pin` and so on as complex numbers :math:`Y + iX`).
    sin_rod, cos_rod : ndarray
        :math:`\sin\gamma_l = \lambda_j h` and :math:`\cos\gamma_l` of the link rod's angle
        from its bore (positive with its lower end towards +X).
    drod, d2rod : ndarray
        :math:`\gamma_l'` and :math:`\gamma_l''`.
    sin_master, cos_master, dmaster, d2master : ndarray
        :math:`\sin\gamma`, :math:`\cos\gamma`, :math:`\gamma'`, :math:`\gamma''` of the
        master rod.
    """

    s: FloatArray
    ds: FloatArray
    d2s: FloatArray
    pin_y: FloatArray
    pin_x: FloatArray
    dpin_y: FloatArray
    dpin_x: FloatArray
    d2pin_y: FloatArray
    d2pin_x: FloatArray
    sin_rod: FloatArray
    cos_rod: FloatArray
    drod: FloatArray
    d2rod: FloatArray
    sin_master: FloatArray
    cos_master: FloatArray
    dmaster: FloatArray
    d2master: FloatArray

    @property
    def pin(self) -> ComplexArray:
        r""":math:`\Lambda` as :math:`Y + iX`."""
        return np.asarray(self.pin_y + 1j * self.pin_x)

    @property
    def dpin(self) -> ComplexArray:
        r""":math:`\Lambda'` as :math:`Y + iX`."""
        return np.asarray(self.dpin_y + 1j * self.dpin_x)

    @property
    def d2pin(self) -> ComplexArray:
        r""":math:`\Lambda''` as :math:`Y + iX`."""
        return np.asarray(self.d2pin_y + 1j * self.d2pin_x)


def link_motion(
    beta: ArrayLike,
    ratio_master: ArrayLike,
    offset_master: ArrayLike,
    pin: ArrayLike,
    pin_turn: ArrayLike,
    shift: ArrayLike,
    ratio: ArrayLike,
    offset: ArrayLike,
) -> LinkMotion:
    r"""Exact motion of a link piston, its link pin and both rods (all arguments broadcast).

    Parameters
    ----------
    beta : array_like
        :math:`\beta_j`, crank angle from the link cylinder's nominal TDC direction [rad].
    ratio_master, offset_master, pin, pin_turn, shift, ratio, offset : array_like
        :math:`\lambda_m, \varepsilon_m, \kappa, \delta, \Delta, \lambda_j, \varepsilon_j`
        (:class:`LinkGeometry`).

    Returns
    -------
    LinkMotion

    Notes
    -----
    With :math:`u = \sin\beta_m - \varepsilon_m`, :math:`\sin\gamma = \lambda_m u`,
    :math:`\cos\gamma = \sqrt{1 - \lambda_m^2u^2}`, :math:`\gamma'` and :math:`\gamma''` as
    for a plain rod, and :math:`w = e^{i(\delta-\gamma)}`:

    .. math::

        w' &= -i\gamma' w, \qquad w'' = (-i\gamma'' - \gamma'^2)\,w, \\
        \Lambda &= e^{i\beta} + \kappa w, \quad \Lambda' = ie^{i\beta} + \kappa w', \quad
        \Lambda'' = -e^{i\beta} + \kappa w'', \\
        h &= \operatorname{Im}\Lambda - \varepsilon_j, \quad D = \sqrt{1 - \lambda_j^2h^2},
        \\
        s/r &= \operatorname{Re}\Lambda + D/\lambda_j, \qquad
        s'/r = \operatorname{Re}\Lambda' - \lambda_j h h'/D, \\
        s''/r &= \operatorname{Re}\Lambda'' - \lambda_j\frac{h'^2 + h h''}{D}
                 - \lambda_j^3\frac{h^2h'^2}{D^3}, \\
        \gamma_l' &= \lambda_j h'/D, \qquad
        \gamma_l'' = \lambda_j h''/D + \lambda_j^3 h h'^2/D^3 .

    With :math:`\kappa = 0` these are the plain slider's formulas
    (:func:`balance.core.kinematics.normalised_slider`) term for term.
    """
    b = np.asarray(beta, dtype=np.float64)
    lam_m = np.asarray(ratio_master, dtype=np.float64)
    kappa = np.asarray(pin, dtype=np.float64)
    delta = np.asarray(pin_turn, dtype=np.float64)
    lam = np.asarray(ratio, dtype=np.float64)
    beta_m = b + np.asarray(shift, dtype=np.float64)
    sin_m, cos_m = np.sin(beta_m), np.cos(beta_m)
    u = sin_m - np.asarray(offset_master, dtype=np.float64)
    sin_g = lam_m * u
    cos_g = np.sqrt(1.0 - sin_g * sin_g)
    dg = lam_m * cos_m / cos_g
    d2g = (lam_m * lam_m * u * cos_m * dg - lam_m * sin_m * cos_g) / (cos_g * cos_g)
    cos_d, sin_d = np.cos(delta), np.sin(delta)
    # kappa w = kappa e^{i delta} (cos g - i sin g): Y and X components
    kw_y = kappa * (cos_d * cos_g + sin_d * sin_g)
    kw_x = kappa * (sin_d * cos_g - cos_d * sin_g)
    dg2 = dg * dg
    sin_b, cos_b = np.sin(b), np.cos(b)
    pin_y = cos_b + kw_y
    pin_x = sin_b + kw_x
    dpin_y = dg * kw_x - sin_b
    dpin_x = cos_b - dg * kw_y
    d2pin_y = d2g * kw_x - dg2 * kw_y - cos_b
    d2pin_x = -d2g * kw_y - dg2 * kw_x - sin_b
    h = pin_x - np.asarray(offset, dtype=np.float64)
    sin_l = lam * h
    D = np.sqrt(1.0 - sin_l * sin_l)
    slope = lam * dpin_x / D  # the link rod's angle rate, gamma_l'
    s = pin_y + D / lam
    ds = dpin_y - h * slope
    d2rod = lam * d2pin_x / D + sin_l * slope * slope / D
    d2s = d2pin_y - dpin_x * slope - h * d2rod
    return LinkMotion(
        s=s,
        ds=ds,
        d2s=d2s,
        pin_y=pin_y,
        pin_x=pin_x,
        dpin_y=dpin_y,
        dpin_x=dpin_x,
        d2pin_y=d2pin_y,
        d2pin_x=d2pin_x,
        sin_rod=sin_l,
        cos_rod=D,
        drod=slope,
        d2rod=d2rod,
        sin_master=sin_g,
        cos_master=cos_g,
        dmaster=dg,
        d2master=d2g,
    )


def pin_roll(motion: LinkMotion) -> FloatArray:
    r""":math:`\operatorname{Re}(\bar\Lambda'\Lambda'') - \operatorname{Im}(\bar\Lambda
    \Lambda'')`: the roll of a unit mass at the link pin per :math:`r^2\omega^2`.

    Parameters
    ----------
    motion : LinkMotion
        The link pin's motion (:func:`link_motion`).

    Returns
    -------
    ndarray
        The roll per unit mass [1], shaped as the motion's arrays.
    """
    m = motion
    return np.asarray(
        m.dpin_y * m.d2pin_y + m.dpin_x * m.d2pin_x - (m.pin_y * m.d2pin_x - m.pin_x * m.d2pin_y)
    )


# --------------------------------------------------------------------------- reach, dead centres


def link_reach(geometry: LinkGeometry) -> FloatArray:
    r"""Largest :math:`|\lambda_j h|` over a revolution of each link cylinder [1].

    The link rod reaches its piston pin while this is below 1 (:math:`|h| < l_j/r`).  The
    maximum is sampled on :data:`REACH_GRID` crank angles; between samples :math:`|h|` can
    exceed the sampled maximum by at most :math:`\max|h''|\,(\pi/N)^2/2`, which is added.
    Infinite where the master rod itself cannot move.

    Parameters
    ----------
    geometry : LinkGeometry
        The link cylinders.

    Returns
    -------
    ndarray
        The bound per link cylinder [1].
    """
    if geometry.size == 0:
        return np.zeros(0)
    beta = 2.0 * np.pi * np.arange(REACH_GRID) / REACH_GRID
    cols = geometry.columns()
    lam, eps = cols[5], cols[6]
    # the link rod's own terms are NaN where it does not reach (what this measures), and
    # everything where the master rod cannot move: neither is read then
    with np.errstate(invalid="ignore", divide="ignore"):
        m = link_motion(beta, *cols)
    if np.any(np.abs(m.sin_master) >= 1.0):
        return np.full(geometry.size, np.inf)
    return np.asarray(lam[:, 0] * sampled_max_bound(m.pin_x - eps, m.d2pin_x))  # h, h''


def link_dead_centres(geometry: LinkGeometry) -> tuple[FloatArray, FloatArray, FloatArray]:
    r"""Top and bottom dead centres of link pistons.

    Parameters
    ----------
    geometry : LinkGeometry
        The link cylinders.

    Returns
    -------
    beta_top, s_top, s_bottom : ndarray
        :math:`\beta_j` of the top dead centre (farthest from the crank axis) [rad], and the
        piston pin's distance from the crank axis at both dead centres, divided by
        :math:`r`.

    Notes
    -----
    :math:`s` is sampled on :data:`DEAD_CENTRE_GRID` angles; from the largest and smallest
    sample Newton's method on :math:`s' = 0` (with the exact :math:`s''`) converges
    quadratically to the dead centres, to rounding.
    """
    if geometry.size == 0:
        empty = np.zeros(0)
        return empty, empty, empty
    cols = geometry.columns()
    grid = 2.0 * np.pi * np.arange(DEAD_CENTRE_GRID) / DEAD_CENTRE_GRID
    s = link_motion(grid, *cols).s
    picks = np.stack([np.argmax(s, axis=-1), np.argmin(s, axis=-1)], axis=-1)
    # a parabola through the best sample and its neighbours: Newton on s' then starts close
    start = sampled_vertex(s, picks)

    def slopes(b: FloatArray) -> tuple[FloatArray, FloatArray]:
        m = link_motion(b, *cols)
        return m.ds, m.d2s

    beta = newton_stationary(
        slopes, start, DEAD_CENTRE_ITERATIONS, DEAD_CENTRE_DONE, extra_step=True
    )
    at = link_motion(beta, *cols).s
    return np.mod(beta[:, 0], 2.0 * np.pi), at[:, 0], at[:, 1]


# --------------------------------------------------------------------------- Fourier series


@dataclass(frozen=True)
class LinkCoefficients:
    r"""Fourier coefficients of the link cylinders' functions (rows: link cylinders).

    ``G_k = a_k - i b_k`` of real functions of :math:`\beta_j`; ``pin_forward`` and
    ``pin_backward`` are the coefficients :math:`c_k` and :math:`c_{-k}` of the complex
    :math:`q(\beta_m) = \sum_k c_k e^{ik\beta_m}` of each link cylinder's master.

    Attributes
    ----------
    acceleration : ndarray of complex
        Of :math:`-s''/r`.
    roll_piston, roll_pin, roll_rod : ndarray of complex
        Of :math:`(s''/r)(s'/r + \varepsilon_j)`, of :func:`pin_roll` and of
        :math:`\gamma_l''(1 + \gamma_l')`.
    pin_forward, pin_backward : ndarray of complex
        :math:`c_k` and :math:`c_{-k}` of :math:`q`.
    samples : int
        Largest number of samples per revolution used.
    """

    acceleration: ComplexArray
    roll_piston: ComplexArray
    roll_pin: ComplexArray
    roll_rod: ComplexArray
    pin_forward: ComplexArray
    pin_backward: ComplexArray
    samples: int


def _link_coefficients(
    geometry: LinkGeometry,
    orders: ArrayLike,
    plain: tuple[ArrayLike, ArrayLike] | None = None,
) -> LinkCoefficients:
    r"""Fourier coefficients of every link function, exact to machine precision.

    Each distinct link geometry's four functions (:class:`LinkCoefficients`) and each
    distinct master geometry's :math:`\operatorname{Re} q`, :math:`\operatorname{Im} q` are
    sampled together and transformed by
    :func:`balance.core.kinematics.fourier_coefficients`, which doubles the samples of each
    function until its aliased tail is below its rounding floor; every function is decided
    on by itself, so the coefficients do not depend on what else is in the batch.

    ``plain`` (rod ratios and offset ratios of plain cylinders) adds their functions to the
    same batch, as link pistons with a zero pin radius (:func:`link_motion` is then the
    plain slider): their rows follow the link cylinders' in every array.
    """
    ks = np.asarray(orders, dtype=np.intp).ravel()
    link_params = np.stack(geometry.columns(), axis=0)[..., 0].T  # (links, 7)
    if plain is not None:
        lam_p = np.asarray(plain[0], dtype=np.float64).ravel()
        rows_p = np.zeros((lam_p.size, 7))
        rows_p[:, 5] = lam_p
        rows_p[:, 6] = np.asarray(plain[1], dtype=np.float64).ravel()
        link_params = np.concatenate([link_params, rows_p], axis=0)
    unique_l, inverse_l = unique_rows(link_params)
    master_params = np.stack([geometry.ratio_master, geometry.offset_master], axis=-1)
    unique_m, inverse_m = unique_rows(master_params)
    n_l, n_m = unique_l.shape[0], unique_m.shape[0]
    cols = tuple(unique_l[:, i : i + 1] for i in range(7))
    lam_mu = unique_m[:, :1]
    eps_mu = unique_m[:, 1:]

    def sample(beta: FloatArray) -> FloatArray:
        m = link_motion(beta, *cols)
        eps = cols[6]
        sin_g, cos_g = crank_train.rod_direction(beta, lam_mu, eps_mu)
        q_re, q_im = crank_train.rod_point_inertia(
            sin_g, cos_g, *conrod_angle_derivatives(beta, lam_mu, eps_mu)
        )
        return np.concatenate(
            [
                -m.d2s,
                m.d2s * (m.ds + eps),
                pin_roll(m),
                m.d2rod * (1.0 + m.drod),
                q_re,
                q_im,
            ],
            axis=0,
        )

    # rounding of the samples: the plain estimate with the larger of the two rods' reach,
    # one more factor 1/D for the roll functions (as in kinematics.roll_coefficients)
    reach_link = np.minimum(unique_l[:, 5] * (1.0 + unique_l[:, 2] + np.abs(unique_l[:, 6])), 0.999)
    reach_master = unique_l[:, 0] * (1.0 + np.abs(unique_l[:, 1]))
    x_l = np.maximum(reach_link, reach_master)
    floor_l = rounding_floor(x_l, 0.0)
    floor_roll = floor_l / np.sqrt(1.0 - x_l)
    floor_m = rounding_floor(unique_m[:, 0], unique_m[:, 1])
    noise = np.concatenate([floor_l, floor_roll, floor_roll, floor_roll, floor_m, floor_m])
    coeffs, used = fourier_coefficients(sample, ks, (4 * n_l + 2 * n_m,), noise_floor=noise)

    def rows(block: int) -> ComplexArray:
        return np.asarray(coeffs[block * n_l : (block + 1) * n_l][inverse_l])

    g_re = coeffs[4 * n_l : 4 * n_l + n_m][inverse_m]
    g_im = coeffs[4 * n_l + n_m :][inverse_m]
    return LinkCoefficients(
        acceleration=rows(0),
        roll_piston=rows(1),
        roll_pin=rows(2),
        roll_rod=rows(3),
        pin_forward=0.5 * (g_re + 1j * g_im),
        pin_backward=0.5 * (np.conj(g_re) + 1j * np.conj(g_im)),
        samples=used,
    )


def link_torque_coefficients(
    geometry: LinkGeometry, orders: ArrayLike
) -> tuple[ComplexArray, ComplexArray, ComplexArray]:
    r"""Fourier coefficients of the rates of kinetic energy of link cylinders' parts: the
    torque the rods put on their crank, in its own sense, is minus the rate of the kinetic
    energy they drive, :math:`M_j = -\omega^2[m_{rec} r^2 (s''/r)(s'/r) + m r^2
    \operatorname{Re}(\bar\Lambda'\Lambda'') + \Delta I\,\gamma_l'\gamma_l'']` with the
    piston, link-pin mass (:func:`pin_masses`) and rod inertia beyond its two masses (the
    energy parts of the roll's functions, :class:`LinkCoefficients`).

    Parameters
    ----------
    geometry : LinkGeometry
        The link cylinders (at least one).
    orders : array_like of int
        The orders.

    Returns
    -------
    piston, pin, rod : ndarray of complex
        :math:`G_k` of :math:`(s''/r)(s'/r)`, :math:`\operatorname{Re}(\bar\Lambda'\Lambda'')`
        and :math:`\gamma_l'\gamma_l''` in :math:`\beta_j`, shape (links, orders).
    """
    ks = np.asarray(orders, dtype=np.intp).ravel()
    unique, inverse = unique_rows(np.stack(geometry.columns(), axis=0)[..., 0].T)
    cols = tuple(unique[:, i : i + 1] for i in range(7))
    n_l = unique.shape[0]

    def sample(beta: FloatArray) -> FloatArray:
        m = link_motion(beta, *cols)
        return np.concatenate(
            [m.d2s * m.ds, m.dpin_y * m.d2pin_y + m.dpin_x * m.d2pin_x, m.drod * m.d2rod], axis=0
        )

    # the rounding of the samples as for the roll's functions (:func:`_link_coefficients`)
    reach_link = np.minimum(unique[:, 5] * (1.0 + unique[:, 2] + np.abs(unique[:, 6])), 0.999)
    x_l = np.maximum(reach_link, unique[:, 0] * (1.0 + np.abs(unique[:, 1])))
    floor = rounding_floor(x_l, 0.0) / np.sqrt(1.0 - x_l)
    coeffs, _ = fourier_coefficients(sample, ks, (3 * n_l,), noise_floor=np.tile(floor, 3))
    piston, pin, rod = (np.asarray(coeffs[i * n_l : (i + 1) * n_l][inverse]) for i in range(3))
    return piston, pin, rod


# --------------------------------------------------------------------------- phasor sums


def pin_masses(engine: Engine) -> FloatArray:
    """The link rods' shares at their link pins, one per cylinder (0 elsewhere).

    A link cylinder's ``rotating_mass`` is its link rod's link-pin share plus its share of
    the throw's ``crank_unbalance`` (:func:`balance.core.masses.two_mass_split`); the
    link-pin share is that less the crank's.

    Parameters
    ----------
    engine : Engine
        The engine (its links and masses).

    Returns
    -------
    ndarray
        The link-pin mass per cylinder [kg].
    """
    out = np.zeros(engine.rotating_mass.shape)
    if engine.links is None:
        return out
    linked = engine.links.master >= 0
    share: FloatArray | float = 0.0
    parts = engine.mass_parts
    if parts is not None:
        share = np.nan_to_num(parts.crank_unbalance) / parts.rods_per_throw
    return np.asarray(np.where(linked, engine.rotating_mass - share, 0.0), dtype=np.float64)


def _column_of(values: ArrayLike, index: NDArray[np.intp]) -> FloatArray:
    """Entries ``index`` of the last axis (cylinders) of ``values`` (leading axes kept)."""
    return np.asarray(np.asarray(values, dtype=np.float64)[..., index])


def articulated_free_phasors(
    *,
    reciprocating_mass: ArrayLike,
    rotating_mass: ArrayLike,
    pin_mass: ArrayLike,
    crank_radius: ArrayLike,
    conrod_length: ArrayLike,
    offset: ArrayLike,
    throw: ArrayLike,
    bank: ArrayLike,
    lever: ArrayLike,
    conrod_inertia_correction: ArrayLike,
    links: Links,
    orders: NDArray[np.intp],
    model: str = "exact",
    terms: int = 3,
    moments: bool = True,
    roll: bool = True,
) -> dict[str, ComplexArray | None]:
    r"""Free force, moment and roll phasors at unit crank speed of an engine with link rods.

    The masses, the lever and the inertia corrections may carry leading grid axes (a sweep of
    masses); the geometry is one engine's (1-D).

    Parameters
    ----------
    reciprocating_mass, rotating_mass, pin_mass : array_like
        Per cylinder [kg]; ``pin_mass`` the link rods' link-pin shares (:func:`pin_masses`).
    crank_radius, conrod_length, offset, throw, bank, lever, conrod_inertia_correction
        Per cylinder, as :func:`balance.core.analysis.free_phasors` [m, rad, kg m²].
    links : Links
        The articulated rods.
    orders : ndarray of int
        The K orders.
    model, terms
        Acceleration model and series terms (see the notes).
    moments, roll : bool
        Whether to form the moment and roll sums.

    Returns
    -------
    dict
        ``force_forward``, ``force_backward``, ``rotating_force``, ``coefficients``,
        ``pin_forward``, ``pin_backward`` (each cylinder's link-pin phasors, shape
        ``(..., n, K)``, zero for the other cylinders), and (as asked) ``moment_*``,
        ``rotating_moment``, ``roll``: the arrays of
        :class:`balance.core.result.FreeForces` [kg m, kg m²].

    Notes
    -----
    Plain cylinders (masters included) are summed as in :mod:`balance.core.phasors`.  A
    link cylinder adds its piston along its bore with the coefficients :math:`G_k` of its
    :math:`-s''/r` in :math:`\beta_j`, and its link-pin mass' motion relative to the crank
    pin,

    .. math::

        P_k^{+} \mathrel{+}= m r\kappa\,e^{i(\psi_m+\alpha)}\,c_k\,e^{ik(\varphi-\psi_m)},
        \qquad
        P_k^{-} \mathrel{+}= m r\kappa\,e^{i(\psi_m+\alpha)}\,c_{-k}\,e^{-ik(\varphi-\psi_m)}

    (:math:`\times\omega^2`; times :math:`z - z_{ref}` for moments), while its centrifugal
    part is among the rotating masses.  The ``exact`` model uses the exact link
    coefficients; ``series`` and ``textbook`` treat a link piston as a plain slider of
    crank radius :math:`r`, rod :math:`l_j` and offset :math:`e_j` on the crank pin and
    leave out the link pin's relative motion (the idealised radial; their error bound adds
    what that leaves out, :func:`balance.core.accuracy.articulation_bound`).  The roll is
    exact in every model, as for plain engines.  Every sum is cleaned of rounding noise
    once, against all of its terms (:func:`balance.core.phasors.cancel_to_zero`).
    """
    from balance.core.kinematics import acceleration_coefficients

    r = np.asarray(crank_radius, dtype=np.float64)
    length = np.asarray(conrod_length, dtype=np.float64)
    e = np.asarray(offset, dtype=np.float64)
    phi = np.asarray(throw, dtype=np.float64)
    psi = np.asarray(bank, dtype=np.float64)
    assert r.ndim == length.ndim == e.ndim == phi.ndim == psi.ndim == 1, (
        "link engines: one geometry (studies refuse geometry fields)"
    )
    ks = np.asarray(orders, dtype=np.intp)
    k = ks.astype(np.float64)
    n = r.size
    geometry = link_geometry(r, length, e, psi, links)
    j = geometry.cylinder
    plain = np.flatnonzero(links.master < 0)
    coefficients = np.zeros((n, ks.size), dtype=np.complex128)
    ratio = rod_ratio(r, length)
    eps = offset_ratio(e, r)
    exact_links = None
    if model == "exact" or roll:  # one batch: link cylinders, then the plain ones
        exact_links = _link_coefficients(geometry, ks, (ratio[plain], eps[plain]))
    at_plain = slice(j.size, None)
    if model == "exact":
        assert exact_links is not None
        coefficients[j] = exact_links.acceleration[: j.size]
        coefficients[plain] = exact_links.acceleration[at_plain]
    else:
        coefficients[j] = acceleration_coefficients(ratio[j], eps[j], ks, model=model, terms=terms)
        if plain.size:
            coefficients[plain] = acceleration_coefficients(
                ratio[plain], eps[plain], ks, model=model, terms=terms
            )

    m_rec = np.asarray(reciprocating_mass, dtype=np.float64)
    amp = m_rec * r
    lever_arr = np.asarray(lever, dtype=np.float64)
    # reciprocating units (as in phasors.reciprocating_force_and_moment)
    c = 0.5 * coefficients
    turn = c * np.exp(1j * k * (phi - psi)[:, None])
    along = np.exp(1j * psi)[:, None]
    rec_fwd = turn * along
    rec_bwd = np.conj(turn) * along
    pin_terms: list[tuple[FloatArray, ComplexArray, ComplexArray]] = []
    if model == "exact":
        assert exact_links is not None
        m_idx = geometry.master
        direction = np.exp(1j * (psi[m_idx] + links.pin_angle[j]))[:, None]
        phase = k * (phi[j] - psi[m_idx])[:, None]
        pin_fwd = geometry.pin[:, None] * direction * exact_links.pin_forward * np.exp(1j * phase)
        pin_bwd = geometry.pin[:, None] * direction * exact_links.pin_backward * np.exp(-1j * phase)
        pin_amp = _column_of(pin_mass, j) * r[j]
        pin_terms.append((pin_amp, pin_fwd, pin_bwd))

    def sums(weight: FloatArray, pin_lever: FloatArray | None) -> tuple[ComplexArray, ...]:
        out = []
        for unit_index in (0, 1):
            terms = [(weight, (rec_fwd, rec_bwd)[unit_index])]
            for pin_amp, fwd, bwd in pin_terms:
                w = pin_amp if pin_lever is None else pin_amp * pin_lever
                terms.append((w, (fwd, bwd)[unit_index]))
            out.append(phasors.weighted_phasor_sum(terms))
        return tuple(out)

    force_forward, force_backward = sums(amp, None)
    rot_amp = np.asarray(rotating_mass, dtype=np.float64) * r
    out: dict[str, ComplexArray | None] = {
        "force_forward": force_forward,
        "force_backward": force_backward,
        "rotating_force": phasors.rotating_phasor(rot_amp, phi),
        "coefficients": coefficients,
    }
    # each cylinder's link-pin phasors (the proposal's counterweights take the forward
    # first order of every cylinder, these included)
    per_fwd = np.zeros((*np.broadcast_shapes(np.shape(pin_mass), (n,)), ks.size), complex)
    per_bwd = np.zeros_like(per_fwd)
    for pin_amp, fwd, bwd in pin_terms:
        per_fwd[..., j, :] = pin_amp[..., None] * fwd
        per_bwd[..., j, :] = pin_amp[..., None] * bwd
    out["pin_forward"] = per_fwd
    out["pin_backward"] = per_bwd
    if moments:
        moment_forward, moment_backward = sums(amp * lever_arr, _column_of(lever_arr, j))
        out.update(
            moment_forward=moment_forward,
            moment_backward=moment_backward,
            rotating_moment=phasors.rotating_phasor(rot_amp, phi, lever_arr),
        )
    if roll:
        assert exact_links is not None
        g_rec = np.zeros((n, ks.size), dtype=np.complex128)
        g_rod = np.zeros((n, ks.size), dtype=np.complex128)
        g_rec[j], g_rod[j] = exact_links.roll_piston[: j.size], exact_links.roll_rod[: j.size]
        g_rec[plain] = exact_links.roll_piston[at_plain]
        g_rod[plain] = exact_links.roll_rod[at_plain]
        g_pin = exact_links.roll_pin[: j.size]
        roll_turn = np.exp(1j * k * (phi - psi)[:, None])
        a_rec = m_rec * r**2
        a_rod = np.asarray(conrod_inertia_correction, dtype=np.float64)
        a_pin = _column_of(pin_mass, j) * r[j] ** 2
        out["roll"] = phasors.weighted_phasor_sum(
            [
                (a_rec, g_rec * roll_turn),
                (a_rod, g_rod * roll_turn),
                (a_pin, g_pin * roll_turn[j]),
            ]
        )
    return out
