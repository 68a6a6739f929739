"""A 1,000-sample Cartesian path on the UR5, next to a loop of numerical IK, in one run.

The tool of the bundled UR5 moves along a straight line while turning (19 cm and 0.36 rad, clear
of singularities; then 30 cm and 0.6 rad, ending near the stretched-out arm's singularity),
sampled 1,000 times (`max_step` = the larger of the two / 1,000):

1. `robot.cartesian_path(goal, seed, interpolation="line", max_step=…)`: closed-form IK at
   every sample, the nearest solution to the previous kept, steps checked (joint step,
   midpoint deviation);
2. a loop of `robot.ik(pose_k, seed=q_{k-1})` (numerical, seeded by the previous sample) over
   the same 1,000 poses (`screwkit.trajectory.cartesian_trajectory`'s, linear time scaling);
3. Robotics Toolbox's `ctraj` + `ikine_LM` seeded by the previous sample, when
   `roboticstoolbox-python` is installed (its own UR5 model, `models.DH.UR5`, the same motion
   from its own start).

Printed: the time per sample (minimum over rounds) and the joint jumps (a step of more than
0.1 in any joint) each gives.

    python crates/screwkit-py/benchmarks/path_bench.py [--rounds 3]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

import screwkit
from screwkit import lie

REPO = Path(__file__).resolve().parents[3]
F64 = npt.NDArray[np.float64]
SAMPLES = 1000


def jumps(q: F64) -> int:
    return int((np.abs(np.diff(q, axis=0)).max(axis=1) > 0.1).sum())


def line_poses(start: F64, goal: F64, n: int) -> F64:
    """n poses from start to goal: the origin on the line, the rotation about one axis."""
    out = np.empty((n, 4, 4))
    xi = lie.log3(start[:3, :3].T @ goal[:3, :3])
    for k, s in enumerate(np.linspace(0, 1, n)):
        out[k] = np.eye(4)
        out[k, :3, :3] = start[:3, :3] @ lie.exp3(xi * s)
        out[k, :3, 3] = (1 - s) * start[:3, 3] + s * goal[:3, 3]
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    robot = screwkit.Robot.from_urdf(REPO / "assets" / "urdf" / "ur5.urdf")
    seed = np.array([0.3, -1.2, 1.4, -1.5, -1.4, 0.4])
    start = robot.fk(seed)
    print(screwkit.host())
    # An easy line, then one that ends near the arm's stretched-out singularity.
    cases = [
        ("clear of singularities", [0.0, 0.2, 0.3], [0.12, -0.1, 0.1]),
        ("into a singularity", [0.0, 0.36, 0.48], [0.18, -0.18, 0.15]),
    ]
    for label, rot, shift in cases:
        turn = np.array(rot)
        goal = start.copy()
        goal[:3, :3] = start[:3, :3] @ lie.exp3(turn)
        goal[:3, 3] += shift
        length = max(float(np.linalg.norm(shift)), float(np.linalg.norm(turn)))
        step = length / SAMPLES
        poses = line_poses(start, goal, SAMPLES + 1)
        best = {"path": np.inf, "ik loop": np.inf}
        for _ in range(args.rounds):
            t0 = time.perf_counter()
            path = robot.cartesian_path(goal, seed, interpolation="line", max_step=step)
            t1 = time.perf_counter()
            q = [seed]
            for pose in poses[1:]:
                q.append(robot.ik(pose, seed=q[-1]).q)
            t2 = time.perf_counter()
            best["path"] = min(best["path"], (t1 - t0) / (len(path.place) - 1))
            best["ik loop"] = min(best["ik loop"], (t2 - t1) / SAMPLES)
        loop = np.array(q)
        print(f"{label}:")
        print(
            f"  screwkit cartesian_path: {len(path.place) - 1} samples, "
            f"{best['path'] * 1e6:.1f} µs per sample, {jumps(path.q)} jumps, "
            f"stop {path.stop!r} at {100 * path.fraction:.1f} %"
        )
        print(
            f"  loop of numerical IK:    {SAMPLES} samples, {best['ik loop'] * 1e6:.1f} µs "
            f"per sample, {jumps(loop)} jumps"
        )
    try:
        import importlib

        rtb: Any = importlib.import_module("roboticstoolbox")
        SE3: Any = importlib.import_module("spatialmath").SE3
    except ImportError:
        print("Robotics Toolbox: not installed (pip install roboticstoolbox-python)")
        return 0
    ur5: Any = rtb.models.DH.UR5()
    t_start = ur5.fkine(seed)
    # The same motion from its own start: goal = start · (start⁻¹ goal).
    t_goal = SE3(np.asarray(t_start.A) @ np.linalg.inv(start) @ goal)
    rtb_best = np.inf
    for _ in range(args.rounds):
        t0 = time.perf_counter()
        traj = rtb.ctraj(t_start, t_goal, SAMPLES + 1)
        qs = [seed]
        for pose in traj[1:]:
            qs.append(ur5.ikine_LM(pose, q0=qs[-1]).q)
        rtb_best = min(rtb_best, (time.perf_counter() - t0) / SAMPLES)
    print(
        f"Robotics Toolbox ctraj + ikine_LM: {SAMPLES} samples, {rtb_best * 1e6:.1f} µs per "
        f"sample, {jumps(np.array(qs))} jumps"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
