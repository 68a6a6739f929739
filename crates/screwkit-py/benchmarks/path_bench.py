"""A 1,000-sample Cartesian path on the UR5, next to a loop of numerical IK, in one run.

The tool of the bundled UR5 moves along a straight line while turning (19 cm and 0.36 rad, clear
of singularities; then 30 cm and 0.6 rad, ending near the stretched-out arm's singularity),
sampled 1,000 times (`max_step` = the larger of the two / 1,000):

1. `robot.cartesian_path(goal, seed, interpolation="line", max_step=…)`: closed-form IK at
   every sample, the nearest solution to the previous kept, steps checked (joint step,
   midpoint deviation);
2. a loop of `robot.ik(pose_k, seed=q_{k-1})` (numerical, seeded by the previous sample) over
   the same 1,000 poses (`screwkit.trajectory.cartesian_trajectory`'s, linear time scaling);
3. Robotics Toolbox's `ctraj` + `ikine_LM` (its Python solver) and + `ik_LM` (its C++ one),
   seeded by the previous sample, when `roboticstoolbox-python` is installed (its own UR5
   model, `models.DH.UR5`, the same motion from its own start). Install it in a venv of its
   own (it moves numpy's version) with the screwkit wheel beside it.

Printed: the time per sample (minimum over rounds) and the joint jumps (a step of more than
0.1 in any joint) each gives. Then 1,024 short paths at once (`cartesian_paths`) on one and on
every pool thread, next to a loop of single calls.

    python crates/screwkit-py/benchmarks/path_bench.py [--rounds 3]
"""

from __future__ import annotations

import os

# numpy's BLAS threads spin after each call and would take the cores from the batch's own.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

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


def robotics_toolbox() -> tuple[Any, Any] | None:
    """Robotics Toolbox's module and spatialmath's SE3, when installed."""
    try:
        import importlib

        return (
            importlib.import_module("roboticstoolbox"),
            importlib.import_module("spatialmath").SE3,
        )
    except ImportError:
        return None


def rtb_path(rtb: Any, se3: Any, seed: F64, start: F64, goal: F64, rounds: int) -> None:
    """Robotics Toolbox's ctraj and IK seeded by the previous sample on its own UR5
    (`models.DH.UR5`), the same motion from its own start: `ikine_LM` (the Python solver the
    issue names) and `ik_LM` (its C++ one)."""
    ur5: Any = rtb.models.DH.UR5()
    t_start = ur5.fkine(seed)
    # The same motion from its own start: goal = start · (start⁻¹ goal).
    t_goal = se3(np.asarray(t_start.A) @ np.linalg.inv(start) @ goal)
    ets = ur5.ets()
    for name in ("ikine_LM", "ik_LM"):
        best = np.inf
        for _ in range(rounds):
            t0 = time.perf_counter()
            traj = rtb.ctraj(t_start, t_goal, SAMPLES + 1)
            qs = [seed]
            for pose in traj[1:]:
                if name == "ikine_LM":
                    qs.append(ur5.ikine_LM(pose, q0=qs[-1]).q)
                else:
                    qs.append(ets.ik_LM(pose.A, q0=qs[-1])[0])
            best = min(best, (time.perf_counter() - t0) / SAMPLES)
        q = np.array(qs)
        err = max(
            float(np.abs(np.asarray(ur5.fkine(x).A) - np.asarray(p.A)).max())
            for x, p in zip(q[1:], traj[1:], strict=True)
        )
        print(
            f"  Robotics Toolbox ctraj + {name}: {SAMPLES} samples, {best * 1e6:.1f} µs per "
            f"sample, {jumps(q)} jumps, largest pose error {err:.1e}"
        )


def many_paths(robot: screwkit.Robot, seed: F64, rounds: int) -> None:
    """1,024 paths of the UR5 (random 10-25 cm lines from random seeds near `seed`, 5 mm steps):
    `cartesian_paths` on one and on every pool thread, next to a loop of `cartesian_path`."""
    rng = np.random.default_rng(7)
    seeds = seed + rng.uniform(-0.3, 0.3, (1024, 6))
    targets = np.empty((1024, 1, 4, 4))
    for k, s in enumerate(seeds):
        targets[k, 0] = robot.fk(s)
        direction = rng.normal(size=3)
        targets[k, 0, :3, 3] += direction / np.linalg.norm(direction) * rng.uniform(0.1, 0.25)
    threads = screwkit.num_threads()
    best = {"loop": np.inf, "1 thread": np.inf, f"{threads} threads": np.inf}
    for _ in range(rounds):
        t0 = time.perf_counter()
        one = [
            robot.cartesian_path(t, s, interpolation="line")
            for t, s in zip(targets, seeds, strict=True)
        ]
        best["loop"] = min(best["loop"], time.perf_counter() - t0)
        for n in (1, threads):
            screwkit.set_num_threads(n)
            t0 = time.perf_counter()
            many = robot.cartesian_paths(targets, seeds, interpolation="line")
            key = "1 thread" if n == 1 else f"{threads} threads"
            best[key] = min(best[key], time.perf_counter() - t0)
        screwkit.set_num_threads(None)
    samples = sum(len(p.place) - 1 for p in one)
    same = all(np.array_equal(a.q, b.q) for a, b in zip(one, many, strict=True))
    print(f"1,024 paths ({samples} samples), equal to their single calls: {same}")
    for key, t in best.items():
        print(f"  {key:>10}: {t * 1e3:.1f} ms ({t / samples * 1e6:.2f} µs per sample)")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    robot = screwkit.Robot.from_urdf(REPO / "assets" / "urdf" / "ur5.urdf")
    seed = np.array([0.3, -1.2, 1.4, -1.5, -1.4, 0.4])
    start = robot.fk(seed)
    print(screwkit.host())
    toolbox = robotics_toolbox()
    if toolbox is None:
        print("Robotics Toolbox: not installed (pip install roboticstoolbox-python)")
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
        if toolbox is not None:
            rtb_path(*toolbox, seed, start, goal, args.rounds)
    many_paths(robot, seed, args.rounds)
    return 0


if __name__ == "__main__":
    sys.exit(main())
