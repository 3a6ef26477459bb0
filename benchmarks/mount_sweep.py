"""Speed of the mount response over a speed sweep: 200 speeds x 8 orders.

Run from the repository root:

    python benchmarks/mount_sweep.py

Times (best of several runs) each step of :mod:`balance.core.mounts` for a four-mount
system with damping and products of inertia: the loads of every (speed, order) from
unit-speed phasors scaled by omega**2 (:func:`crank_loads`), the one batched solve of
(K - W^2 M + i W C) X = F (:func:`harmonic_response`), the mount forces
(:func:`mount_forces`), and the six modes (:func:`normal_modes`).  The phasors of
the first rows are synthetic (random, of an inline-4's size: the time does not depend on
their values); the last rows use the real phasors of ``layouts/inline-4-mounts.yaml``
(:func:`speed_sweep`, what ``balance mounts`` runs).
The issue's target: under 50 ms of compute for the whole sweep.
"""

from __future__ import annotations

import platform
import time
from collections.abc import Callable

import numpy as np

from balance.core import mounts as mt

SPEEDS, ORDERS = 200, 8


def best_of(func: Callable[[], object], repeats: int = 20) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        func()
        times.append(time.perf_counter() - t)
    return min(times)


def system() -> mt.MountSystem:
    k = np.array([2.5e5, 4.0e5, 1.5e5])
    points = tuple(
        mt.MountPoint(position=(sx * 0.22, -0.12, z), stiffness=k, damping=0.02 * k)
        for sx in (-1.0, 1.0)
        for z in (0.0, 0.3)
    )
    return mt.MountSystem(
        mass=160.0,
        cg=(0.0, 0.06, 0.14),
        inertia=mt.inertia_tensor(7.5, 9.0, 4.0, xy=0.3, xz=-0.6, yz=0.2),
        points=points,
    )


def real_engine() -> list[tuple[str, float]]:
    """The sweep of ``balance mounts inline-4-mounts``: the phasors of the real engine
    (its analysis once, at the layout speed), then :func:`speed_sweep` over 200 speeds."""
    from balance.core.analysis import compute
    from balance.io.layout_file import load_layout
    from balance.io.request import build_request

    engine = load_layout("inline-4-mounts")
    request = build_request(engine, ORDERS)  # its mounts: section turns the mounts on
    base = compute(engine, request).part("mounts").response
    assert base is not None
    speeds = np.linspace(800, 8000, SPEEDS) * np.pi / 30
    sweep = mt.speed_sweep(base, speeds)
    assert sweep.forces.shape == (SPEEDS, ORDERS, 4, 3)
    return [
        ("inline-4-mounts: analysis with mounts (once)", best_of(lambda: compute(engine, request))),
        ("inline-4-mounts: speed_sweep, 200 x 8", best_of(lambda: mt.speed_sweep(base, speeds))),
    ]


def main() -> None:
    s = system()
    m, k, c = mt.mass_matrix(s.mass, s.inertia), mt.stiffness_matrix(s), mt.damping_matrix(s)
    rng = np.random.default_rng(1)
    speeds = np.linspace(800, 8000, SPEEDS) * np.pi / 30
    orders = np.arange(1, ORDERS + 1, dtype=float)
    unit = {
        name: (rng.normal(size=ORDERS) + 1j * rng.normal(size=ORDERS)) * 1e-3
        for name in ("pf", "pb", "qf", "qb", "roll")
    }
    w2 = (speeds**2)[:, None]
    omega = mt.order_frequencies(speeds, orders)

    def loads() -> np.ndarray:
        return mt.crank_loads(
            0.14,
            s.cg,
            force_forward=unit["pf"] * w2,
            force_backward=unit["pb"] * w2,
            moment_forward=unit["qf"] * w2,
            moment_backward=unit["qb"] * w2,
            roll=unit["roll"] * w2,
        )

    f = loads()
    x = mt.harmonic_response(m, k, c, omega, f)

    def whole() -> None:
        response = mt.harmonic_response(m, k, c, omega, loads())
        mt.mount_forces(s, response, omega)

    rows = [
        ("loads (crank_loads)", best_of(loads)),
        ("response (one batched solve)", best_of(lambda: mt.harmonic_response(m, k, c, omega, f))),
        ("mount forces", best_of(lambda: mt.mount_forces(s, x, omega))),
        ("modes", best_of(lambda: mt.normal_modes(m, k))),
        ("whole sweep: loads + response + mount forces", best_of(whole)),
    ]
    rows += real_engine()
    print(f"{SPEEDS} speeds x {ORDERS} orders, {s.n_mounts} mounts")
    print(f"numpy {np.__version__}, Python {platform.python_version()}, {platform.machine()}")
    for name, seconds in rows:
        print(f"  {name:46s} {seconds * 1e3:8.3f} ms")


if __name__ == "__main__":
    main()
