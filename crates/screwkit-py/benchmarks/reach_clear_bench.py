"""Reachability maps clear of contact: example-robot-data's Panda (numerical IK, steered away
from contact) and UR5 (analytic IK, every posture checked) beside a table and a box (the scene
of test_avoid_collisions.py), margin 1 cm, meshes exact and as convex hulls. Per map: the
time (interleaved rounds, the fastest kept), the poses reached without and with the body, and
the fraction of the reached poses lost to collisions.

Run: python crates/screwkit-py/benchmarks/reach_clear_bench.py [--resolution 0.05]
[--orientations 20] [--rounds 2] (needs pin, coal and example-robot-data: `cargo xtask test`
installs them in its venv).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Literal

import numpy as np

import screwkit

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from test_avoid_collisions import MARGIN, OBSTACLES, TIPS  # noqa: E402
from test_body import SHARE, files  # noqa: E402

# The table's and the box's side of the robot, from below the table to above the box.
BOUNDS = (0.0, -0.7, -0.1, 1.0, 0.7, 0.8)


def robot_with_scene(name: str, meshes: Literal["exact", "convex"]) -> screwkit.Robot:
    urdf, srdf, _ = files(name)
    robot = screwkit.Robot.from_urdf(urdf, *TIPS[name], package_paths=[SHARE], meshes=meshes)
    robot.srdf(srdf)
    for n, size, centre in OBSTACLES:
        pose = np.eye(4)
        pose[:3, 3] = centre
        robot.add_obstacle(n, screwkit.Box(size), pose)
    return robot


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--resolution", type=float, default=0.05)
    ap.add_argument("--orientations", type=int, default=20)
    ap.add_argument("--rounds", type=int, default=2)
    args = ap.parse_args()
    print(screwkit.host())
    for name in ("panda", "ur5"):
        kinds = {
            "plain": (robot_with_scene(name, "exact"), False),
            "exact meshes": (robot_with_scene(name, "exact"), True),
            "convex hulls": (robot_with_scene(name, "convex"), True),
        }
        best = {k: np.inf for k in kinds}
        maps: dict[str, screwkit.ReachMap] = {}
        for _ in range(args.rounds):
            for kind, (robot, avoid) in kinds.items():
                t0 = time.perf_counter()
                maps[kind] = screwkit.reach(
                    robot,
                    args.resolution,
                    args.orientations,
                    bounds=BOUNDS,
                    avoid_collisions=avoid,
                    margin=MARGIN if avoid else 0.0,
                )
                best[kind] = min(best[kind], time.perf_counter() - t0)
        plain = maps["plain"]
        reached = int(np.sum(~np.isnan(plain.pose_manipulability)))
        poses = plain.pose_manipulability.size
        print(
            f"{name} ({plain.meta['solver']} IK): {poses} poses, {args.resolution} m voxels x "
            f"{args.orientations} orientations; plain {best['plain']:.2f} s, {reached} reached"
        )
        for kind in ("exact meshes", "convex hulls"):
            clear = int(np.sum(~np.isnan(maps[kind].pose_manipulability)))
            print(
                f"  clear of contact, {kind}: {best[kind]:.2f} s "
                f"({best[kind] / best['plain']:.0f}x), {clear} reached, "
                f"{100 * (reached - clear) / reached:.1f} % of the reached poses lost"
            )


if __name__ == "__main__":
    main()
