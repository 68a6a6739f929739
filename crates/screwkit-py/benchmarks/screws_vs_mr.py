"""Robots given by (M, S) next to the library of the textbook's authors (`modern_robotics`), in
one run, on the very same arm and configurations: a random 6-joint arm of revolute, helical
and prismatic joints (seeded), built once by `Robot.from_screws`.

Times, per configuration (minimum over interleaved rounds, one thread):

- FK: MR `FKinSpace(M, Slist, q)` and screwkit `robot.fk(q)` one call at a time, and
  `robot.fk(Q)` on all configurations at once;
- the space Jacobian: MR `JacobianSpace(Slist, q)` and screwkit `robot.jacobian(q, "space")`;
- IK on reachable targets (FK of random configurations within the limits): MR `IKinSpace`
  (Newton-Raphson from the limits' midpoint, 1e-9 rad / 1e-9 m, its 20 iterations) and
  screwkit `robot.ik(Ts)` (defaults: LM with restarts, within the limits); solved counts and
  how many of MR's answers are within the limits.

Not a test dependency beyond the test requirements (`modern_robotics` is one): from the
repository root,

    python crates/screwkit-py/benchmarks/screws_vs_mr.py [--configurations 200] [--rounds 3]
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path

import modern_robotics as mr
import numpy as np

import screwkit

# The arm generator of the test suite (tests/test_screws.py), so both use the same arms.
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_screws import random_arm  # noqa: E402


def best(f: Callable[[], object], reps: int = 5) -> float:
    out = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        f()
        out = min(out, time.perf_counter() - t0)
    return out


def main() -> None:
    print(f"host: {screwkit.host()}")
    ap = argparse.ArgumentParser()
    ap.add_argument("--configurations", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--targets", type=int, default=100)
    a = ap.parse_args()
    screwkit.set_num_threads(1)
    g = np.random.default_rng(7)
    m, s, lim = random_arm(g, 6, kinds=["revolute", "helical", "prismatic"])
    robot = screwkit.Robot.from_screws(m, s, limits=lim)
    n = a.configurations
    qs = g.uniform(lim[:, 0], lim[:, 1], size=(n, 6))
    worst = max(np.abs(robot.fk(q) - mr.FKinSpace(m, s.T, q)).max() for q in qs)
    print(f"arm: 6 joints (revolute, helical, prismatic x 2); FK vs MR: {worst:.1e}")
    calls: dict[str, Callable[[], object]] = {
        "MR FKinSpace": lambda: [mr.FKinSpace(m, s.T, q) for q in qs],
        "screwkit fk, one call each": lambda: [robot.fk(q) for q in qs],
        "screwkit fk, batch": lambda: robot.fk(qs),
        "MR JacobianSpace": lambda: [mr.JacobianSpace(s.T, q) for q in qs],
        "screwkit jacobian, one call each": lambda: [robot.jacobian(q, "space") for q in qs],
    }
    times: dict[str, float] = {}
    for _ in range(a.rounds):  # interleaved rounds, minimum of each
        for name, f in calls.items():
            times[name] = min(times.get(name, float("inf")), best(f) / n)
    for name, t in times.items():
        print(f"{name:34s} {t * 1e6:9.3f} us per configuration")
    print(f"FK: screwkit {times['MR FKinSpace'] / times['screwkit fk, one call each']:.0f}x MR")
    targets = robot.fk(qs[: a.targets])
    seed = lim.mean(axis=1)
    t0 = time.perf_counter()
    answers = [mr.IKinSpace(s.T, m, t, seed, 1e-9, 1e-9) for t in targets]
    t_mr = time.perf_counter() - t0
    solved_mr = sum(bool(ok) for _, ok in answers)
    within = sum(
        bool(ok) and bool(np.all((th >= lim[:, 0]) & (th <= lim[:, 1]))) for th, ok in answers
    )
    t0 = time.perf_counter()
    res = robot.ik(targets)
    t_sk = time.perf_counter() - t0
    print(
        f"IK, {len(targets)} reachable targets: MR IKinSpace {solved_mr} solved ({within} within "
        f"the limits) in {t_mr * 1e3:.1f} ms; screwkit {int(np.asarray(res.converged).sum())} "
        f"solved (all within the limits) in {t_sk * 1e3:.2f} ms"
    )


if __name__ == "__main__":
    main()
