"""The robot's body from Python next to Pinocchio + coal, in one run: per configuration, the
all-pairs collision check (`robot.in_collision(q)` against `computeCollisions(…, True)`, both
stopping at the first colliding pair) and the all-pairs distances (`robot.distances(q)`, every
pair's signed distance with its witness points, against `computeDistances`), on the Panda and
the UR5 as example-robot-data ships them (collision meshes and SRDFs); then a batch of N
configurations on the pool's threads against one thread, per row.

Both sides get the same configurations (Pinocchio's q built from ours: mimic joints by their
rule). Rounds are interleaved and the minimum of each kept (shared, noisy hosts). Also printed:
the pairs checked, the share of pairs the bounding-box broad phase leaves to the narrow phase in
the collision check.

    python crates/screwkit-py/benchmarks/body_bench.py [--rounds 5] [--configs 200]
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

import screwkit

SHARE = (
    Path(sys.prefix)
    / "lib"
    / f"python{sys.version_info.major}.{sys.version_info.minor}"
    / "site-packages"
    / "cmeel.prefix"
    / "share"
)
ROBOTS = SHARE / "example-robot-data" / "robots"
CASES = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_description/srdf/panda.srdf"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "ur_description/srdf/ur5.srdf"),
}


def per_call(f: Callable[[Any], Any], qs: list[Any]) -> float:
    t0 = time.perf_counter()
    for q in qs:
        f(q)
    return (time.perf_counter() - t0) / len(qs)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--configs", type=int, default=200)
    args = ap.parse_args()
    print(screwkit.host())
    for name, (urdf, srdf) in CASES.items():
        run(name, urdf, srdf, args.rounds, args.configs)


def run(name: str, urdf: str, srdf: str, rounds: int, configs: int) -> None:
    """One robot's figures."""
    robot = screwkit.Robot.from_urdf(ROBOTS / urdf, package_paths=[SHARE])
    robot.srdf(ROBOTS / srdf)
    model, cmodel, _ = pin.buildModelsFromUrdf(str(ROBOTS / urdf), package_dirs=[str(SHARE)])
    cmodel.addAllCollisionPairs()
    pin.removeCollisionPairs(model, cmodel, str(ROBOTS / srdf))
    data, cdata = model.createData(), pin.GeometryData(cmodel)
    mimic = {j["name"]: j["mimic"] for j in robot.info()["joints"] if j["mimic"]}
    names = robot.q_names

    def pin_q(ours: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        q = np.zeros(model.nq)
        for j in range(1, model.njoints):
            n = model.names[j]
            if n in names:
                q[model.joints[j].idx_q] = ours[names.index(n)]
            else:
                m = mimic[n]
                q[model.joints[j].idx_q] = (
                    m["multiplier"] * ours[names.index(m["leader"])] + m["offset"]
                )
        return q

    rng = np.random.default_rng(0)
    lo, hi = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    ours_q = [rng.uniform(lo, hi) for _ in range(configs)]
    theirs_q = [pin_q(q) for q in ours_q]
    best = dict.fromkeys(["ours_col", "coal_col", "ours_dist", "coal_dist"], np.inf)
    for _ in range(rounds):
        best["ours_col"] = min(best["ours_col"], per_call(robot.in_collision, ours_q))
        best["coal_col"] = min(
            best["coal_col"],
            per_call(
                lambda q: pin.computeCollisions(model, data, cmodel, cdata, q, True), theirs_q
            ),
        )
        best["ours_dist"] = min(best["ours_dist"], per_call(robot.distances, ours_q))
        best["coal_dist"] = min(
            best["coal_dist"],
            per_call(lambda q: pin.computeDistances(model, data, cmodel, cdata, q), theirs_q),
        )
    colliding = sum(bool(robot.in_collision(q)) for q in ours_q)
    print(
        f"{name}: {len(robot.collision_pairs)} pairs (coal {len(cmodel.collisionPairs)}), "
        f"{colliding}/{len(ours_q)} configurations in collision"
    )
    for label, key in (("collision check", "col"), ("distances      ", "dist")):
        ours, coal = best[f"ours_{key}"], best[f"coal_{key}"]
        print(
            f"  {label}  ours {ours * 1e6:8.1f} µs   coal {coal * 1e6:8.1f} µs"
            f"   coal/ours {coal / ours:.2f}x"
        )
    qs = np.stack(ours_q * 10)
    threads = screwkit.num_threads()
    t_many = t_one = np.inf
    for _ in range(rounds):
        screwkit.set_num_threads(threads)
        t0 = time.perf_counter()
        robot.min_distance(qs)
        t_many = min(t_many, (time.perf_counter() - t0) / len(qs))
        screwkit.set_num_threads(1)
        t0 = time.perf_counter()
        robot.min_distance(qs)
        t_one = min(t_one, (time.perf_counter() - t0) / len(qs))
    screwkit.set_num_threads(threads)
    print(
        f"  batch min_distance, per row: {threads} threads {t_many * 1e6:.1f} µs, 1 thread "
        f"{t_one * 1e6:.1f} µs ({t_one / t_many:.2f}x)"
    )


if __name__ == "__main__":
    main()
