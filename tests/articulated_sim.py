"""An independent simulation of crank trains with master and link rods, for the tests.

Written from CONTRACT §1, §2, §5 and §6 alone, without the code of :mod:`balance.core.links`:
it shares nothing with the package but numpy.  Positions come from the loop closure solved
in closed form (each piston on its bore line at its rod's length from the rod's lower end);
velocities and accelerations from second-order Taylor jets (truncated power series in the
crank angle carried through every operation, so the derivatives are exact to rounding, with
no step size); forces, moments and roll from those, by two routes for the roll:

- energy and angular momentum: the block receives ``T_drive - dL/dt``, where the drive torque
  that keeps the crank at constant speed is ``dE/dtheta`` (it does all the work on the moving
  parts; the walls and bearings do none) and ``L`` is the moving parts' angular momentum about
  the crank axis;
- Newton-Euler of every rigid body (pistons, link rods, master rods) with the wall reactions:
  the block receives the reactions of the wall forces about the crank axis; the same solve
  gives the force that each master rod's big end puts on its crank pin (CONTRACT §6).

The transverse plane is complex, ``y + i x`` (CONTRACT §1): a direction at angle ``a``
(measured from +y with the rotation) is ``exp(i a)``; the forward torque of a force ``F`` at
``p`` is ``Im(conj(p) F)``, and a body's forward angular momentum ``m Im(conj(p) p')``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


class Jet:
    """A truncated Taylor series ``c0 + c1 h + c2 h^2`` in the crank angle (arrays, complex)."""

    __slots__ = ("c",)

    def __init__(self, c0, c1=0.0, c2=0.0):
        self.c = tuple(np.asarray(v, dtype=complex) for v in np.broadcast_arrays(c0, c1, c2))

    @staticmethod
    def of(value):
        return value if isinstance(value, Jet) else Jet(value)

    def __add__(self, other):
        o = Jet.of(other)
        return Jet(*(a + b for a, b in zip(self.c, o.c, strict=True)))

    __radd__ = __add__

    def __neg__(self):
        return Jet(*(-a for a in self.c))

    def __sub__(self, other):
        return self + (-Jet.of(other))

    def __rsub__(self, other):
        return Jet.of(other) + (-self)

    def __mul__(self, other):
        if not isinstance(other, Jet):
            return Jet(*(a * other for a in self.c))
        a, b = self.c, other.c
        return Jet(a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[0] * b[2] + a[1] * b[1] + a[2] * b[0])

    __rmul__ = __mul__

    def __truediv__(self, other):
        if not isinstance(other, Jet):
            return Jet(*(a / other for a in self.c))
        a, b = self.c, other.c
        q0 = a[0] / b[0]
        q1 = (a[1] - q0 * b[1]) / b[0]
        q2 = (a[2] - q0 * b[2] - q1 * b[1]) / b[0]
        return Jet(q0, q1, q2)

    @property
    def real(self):
        return Jet(*(a.real for a in self.c))

    @property
    def imag(self):
        return Jet(*(a.imag for a in self.c))

    def conj(self):
        return Jet(*(a.conj() for a in self.c))

    def sqrt(self):
        s0 = np.sqrt(self.c[0])
        s1 = self.c[1] / (2 * s0)
        return Jet(s0, s1, (self.c[2] - s1 * s1) / (2 * s0))

    def exp(self):
        e0 = np.exp(self.c[0])
        return Jet(e0, self.c[1] * e0, (self.c[2] + self.c[1] ** 2 / 2) * e0)

    def log(self):
        l1 = self.c[1] / self.c[0]
        return Jet(np.log(self.c[0]), l1, self.c[2] / self.c[0] - l1 * l1 / 2)

    def d1(self):
        """First derivative in the crank angle."""
        return self.c[1]

    def d2(self):
        """Second derivative in the crank angle."""
        return 2 * self.c[2]


def cis(angle):
    """``exp(i angle)`` of a Jet or a number."""
    return (Jet.of(angle) * 1j).exp() if isinstance(angle, Jet) else np.exp(1j * angle)


@dataclass
class Cylinder:
    """One cylinder in SI units and radians (CONTRACT §1, §5).

    A cylinder without ``master`` has its rod (``rod_*``: mass, CG from the big end, inertia
    about the CG, length ``rod_length``) on its crank pin; with ``master`` (0-based) its link
    rod (CG from the link pin, length ``rod_length``) hangs on that cylinder's rod at
    ``pin_radius``, ``pin_angle`` from the master rod's centre line.
    """

    throw: float
    bank: float
    z: float
    piston: float
    rod_mass: float
    rod_cg: float
    rod_inertia: float
    rod_length: float
    offset: float = 0.0
    master: int | None = None
    pin_radius: float = 0.0
    pin_angle: float = 0.0


@dataclass
class Mechanism:
    """A crank train: crank radius [m], speed [rev/min], cylinders, and the crank unbalance
    of every throw [kg at the crank-pin radius] (a throw: the pins at one angle and plane)."""

    crank_radius: float
    rpm: float
    cylinders: list[Cylinder]
    crank_unbalance: float = 0.0
    reference_z: float | None = None

    @property
    def omega(self):
        return 2 * np.pi * self.rpm / 60

    @property
    def z_ref(self):
        if self.reference_z is not None:
            return self.reference_z
        zs = [c.z for c in self.cylinders]
        return (min(zs) + max(zs)) / 2

    @property
    def throws(self):
        """(throw angle [rad], z [m]) of every throw, once each."""
        seen = []
        for c in self.cylinders:
            key = (c.throw, c.z)
            if key not in seen:
                seen.append(key)
        return seen


@dataclass
class Body:
    mass: float
    inertia: float
    position: Jet  # of the CG, complex y + i x [m]
    angle: Jet | None  # forward angle [rad], None for a body that does not turn
    z: float


@dataclass
class State:
    """Positions of everything at the crank angles ``theta``."""

    theta: np.ndarray
    crank_pin: list[Jet]  # per cylinder
    piston: list[Jet]  # piston pin per cylinder
    piston_travel: list[Jet]  # s along the bore per cylinder
    lower_end: list[Jet]  # rod's lower end: crank pin or link pin
    rod_cg: list[Jet]
    rod_angle: list[Jet]
    bodies: list[Body]


def positions(mech: Mechanism, theta: np.ndarray) -> State:
    """Every body's position at the crank angles ``theta`` [rad] (loop closure in closed form)."""
    th = Jet(theta, np.ones_like(theta), 0.0)
    r = mech.crank_radius
    n = len(mech.cylinders)
    crank_pin: list = [None] * n
    piston: list = [None] * n
    travel: list = [None] * n
    lower: list = [None] * n
    rod_dir: list = [None] * n
    order = [i for i, c in enumerate(mech.cylinders) if c.master is None]
    order += [i for i, c in enumerate(mech.cylinders) if c.master is not None]
    for i in order:
        cyl = mech.cylinders[i]
        if cyl.master is None:
            pin = cis(th + cyl.throw) * r
            end = pin
        else:
            m = mech.cylinders[cyl.master]
            assert m.master is None and m.throw == cyl.throw and m.z == cyl.z
            pin = crank_pin[cyl.master]
            # link pin: pin_radius from the crank pin, pin_angle from the master's centre line
            end = pin + rod_dir[cyl.master] * cis(cyl.pin_angle) * cyl.pin_radius
        # the lower end in the bore's frame: q = a + i b, a along the bore, b towards the
        # offset side; the piston pin is at s + i e with |s + i e - q| = rod length
        q = end * cis(-cyl.bank)
        b = q.imag
        s = q.real + (((b - cyl.offset) * (b - cyl.offset)) * -1 + cyl.rod_length**2).sqrt()
        p = (s + 1j * cyl.offset) * cis(cyl.bank)
        crank_pin[i], piston[i], travel[i], lower[i] = pin, p, s, end
        rod_dir[i] = (p - end) / cyl.rod_length
    bodies, rod_cg, rod_angle = [], [], []
    for i, cyl in enumerate(mech.cylinders):
        g = lower[i] + rod_dir[i] * cyl.rod_cg
        ang = rod_dir[i].log().imag
        rod_cg.append(g)
        rod_angle.append(ang)
        bodies.append(Body(cyl.piston, 0.0, piston[i], None, cyl.z))
        bodies.append(Body(cyl.rod_mass, cyl.rod_inertia, g, ang, cyl.z))
    for throw, z in mech.throws:
        bodies.append(Body(mech.crank_unbalance, 0.0, cis(th + throw) * r, None, z))
    return State(theta, crank_pin, piston, travel, lower, rod_cg, rod_angle, bodies)


def signals(mech: Mechanism, theta: np.ndarray):
    """Shaking force on the block [N], its moment ``sum (z - z_ref) F`` [N m] (complex
    ``y + i x``) and the roll torque on the block [N m] by energy and angular momentum."""
    st = positions(mech, theta)
    w2 = mech.omega**2
    force = np.zeros_like(theta, dtype=complex)
    moment = np.zeros_like(force)
    roll = np.zeros_like(theta)
    for b in st.bodies:
        p, v, a = b.position.c[0], b.position.d1(), b.position.d2()
        f = -b.mass * w2 * a
        force += f
        moment += (b.z - mech.z_ref) * f
        # drive power per omega (dE/dtheta) minus dL/dt, both per omega^2
        roll += b.mass * w2 * ((np.conj(v) * a).real - (np.conj(p) * a).imag)
        if b.angle is not None:
            av, aa = b.angle.d1().real, b.angle.d2().real
            roll += b.inertia * w2 * (av * aa - aa)
    return force, moment, roll


def newton_euler(mech: Mechanism, theta: np.ndarray, gas=None):
    """Rigid-body Newton-Euler with the wall reactions.

    ``gas``, if given, holds per cylinder the gas force [N] at ``theta`` that pushes its
    piston towards the crank (and its head the other way).  Returns the roll on the block
    (the torque about the crank axis of the wall reactions and of the gas force on the
    heads) [N m] and, per cylinder without a master, the force its rod's big end puts on its
    crank pin [N] (complex ``y + i x``), each an array over ``theta``.
    """
    st = positions(mech, theta)
    w2 = mech.omega**2

    def acc(jet):
        return w2 * jet.d2()

    def cross(arm, force):  # forward torque of ``force`` applied at ``arm``
        return (np.conj(arm) * force).imag

    cyls = mech.cylinders
    wall = [None] * len(cyls)  # wall force on each piston (normal to its bore)
    link_force = [None] * len(cyls)  # force of the link pin on each link rod
    pin_load = {}
    normal = [1j * np.exp(1j * c.bank) for c in cyls]
    bore = [np.exp(1j * c.bank) for c in cyls]
    push = [np.zeros(len(theta)) for _ in cyls] if gas is None else gas
    for i, c in enumerate(cyls):  # link rods first: their pin forces load the master rods
        if c.master is None:
            continue
        P, Q, G = st.piston[i].c[0], st.lower_end[i].c[0], st.rod_cg[i].c[0]
        A = c.piston * acc(st.piston[i]) + push[i] * bore[i]  # = F_rod_on_piston + N n
        B = c.rod_mass * acc(st.rod_cg[i]) + A  # = F_linkpin_on_rod + N n
        alpha = w2 * st.rod_angle[i].d2().real
        # link rod about its CG: I alpha = -(P-G) x F_rp + (Q-G) x F_kl, F_rp = A - N n,
        # F_kl = B - N n
        coeff = cross(P - G, normal[i]) - cross(Q - G, normal[i])
        N = (c.rod_inertia * alpha + cross(P - G, A) - cross(Q - G, B)) / coeff
        wall[i] = N * normal[i]
        link_force[i] = B - wall[i]
    for i, c in enumerate(cyls):
        if c.master is not None:
            continue
        P, C, G = st.piston[i].c[0], st.crank_pin[i].c[0], st.rod_cg[i].c[0]
        links = [j for j, d in enumerate(cyls) if d.master == i]
        A = c.piston * acc(st.piston[i]) + push[i] * bore[i]
        on_links = sum((link_force[j] for j in links), np.zeros_like(A))
        D = c.rod_mass * acc(st.rod_cg[i]) + A + on_links  # = F_pin_on_rod + N n
        alpha = w2 * st.rod_angle[i].d2().real
        # master rod about its CG: I alpha = -(P-G) x F_rp - sum (Q_j-G) x F_kl_j
        #                                     + (C-G) x F_c, F_rp = A - N n, F_c = D - N n
        links_torque = sum(
            (cross(st.lower_end[j].c[0] - G, link_force[j]) for j in links), np.zeros(len(theta))
        )
        coeff = cross(P - G, normal[i]) - cross(C - G, normal[i])
        N = (c.rod_inertia * alpha + cross(P - G, A) + links_torque - cross(C - G, D)) / coeff
        wall[i] = N * normal[i]
        pin_load[i] = -(D - wall[i])
    # the head takes the gas force outwards along the bore axis, at the offset e from it
    roll = sum(cross(st.piston[i].c[0], -wall[i]) - push[i] * c.offset for i, c in enumerate(cyls))
    return roll, pin_load


def phasors(signal: np.ndarray, orders):
    """Forward and backward phasors of a complex signal sampled uniformly over a
    revolution (CONTRACT §2): ``Q = sum P+ exp(ik theta) + P- exp(-ik theta)``."""
    n = len(signal)
    theta = 2 * np.pi * np.arange(n) / n
    fwd = np.array([np.mean(signal * np.exp(-1j * k * theta)) for k in orders])
    bwd = np.array([np.mean(signal * np.exp(1j * k * theta)) for k in orders])
    return fwd, bwd


def roll_phasors(roll: np.ndarray, orders):
    """Roll per order as ``R_k`` with ``roll = sum Re(R_k exp(ik theta))`` (CONTRACT §2)."""
    fwd, _ = phasors(roll.astype(complex), orders)
    return 2 * fwd


def dead_centres(mech: Mechanism, samples: int = 720):
    """Each piston's stroke [m] and the crank angle [rad, in [0, 2 pi)] at which it is farthest
    from the crank axis: the extremes of its squared distance from the axis over ``samples``
    crank angles, refined by Newton steps on the distance's derivative (exact, from the jets).
    """
    n = len(mech.cylinders)
    theta = 2 * np.pi * np.arange(samples) / samples
    st = positions(mech, theta)
    start = []
    for i in range(n):
        d2 = (st.piston[i] * st.piston[i].conj()).real.c[0].real
        start += [theta[np.argmax(d2)], theta[np.argmin(d2)]]
    th = np.array(start)
    owner = np.repeat(np.arange(n), 2)
    for _ in range(12):  # quadratic convergence from within half a sampling step
        st = positions(mech, th)
        step = np.empty_like(th)
        for i in range(n):
            sq = (st.piston[i] * st.piston[i].conj()).real
            mine = owner == i
            step[mine] = (sq.d1().real / sq.d2().real)[mine]
        th = th - step
        if np.max(np.abs(step)) < 1e-14:
            break
    st = positions(mech, th)
    travel = np.array([st.piston_travel[i].c[0].real[2 * i : 2 * i + 2] for i in range(n)])
    return np.abs(travel[:, 0] - travel[:, 1]), np.mod(th[0::2], 2 * np.pi)
