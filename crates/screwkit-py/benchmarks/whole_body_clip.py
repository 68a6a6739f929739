"""A motion clip retargeted frame by frame: TALOS with a floating base, 10,000 frames (100 s
at 100 Hz), both feet and both grippers to 6-D poses plus a posture task. Each frame's targets
are the FK of a smooth motion q(t) inside the joint limits (reachable by construction). The
clip is solved by `Robot.ik_trajectory` in order on one core (each frame seeded by the
previous answer) and in segments on all cores (`segment`, `warm_up`); frames per second,
convergence, the largest error of every answer checked by Pinocchio's FK (an independent
library) and the limit violations are printed as `RESULT` lines.

    python crates/screwkit-py/benchmarks/whole_body_clip.py ../shared/urdf/trees/talos_full_v2.urdf
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

import screwkit

FRAMES = ["left_sole_link", "right_sole_link", "gripper_left_base_link", "gripper_right_base_link"]


def motion(robot: screwkit.Robot, n: int, hz: float = 100.0) -> np.ndarray:
    """q(t) for n frames: every joint swinging about the middle of its range (a quarter of
    the range, its own frequency and phase), the base swaying a few centimetres and degrees."""
    lo, hi = np.array(robot.lower[7:]), np.array(robot.upper[7:])
    rng = np.random.default_rng(2)
    freq = rng.uniform(0.1, 0.5, lo.size)
    phase = rng.uniform(0, 2 * np.pi, lo.size)
    t = np.arange(n)[:, None] / hz
    joints = (lo + hi) / 2 + (hi - lo) / 8 * np.sin(2 * np.pi * freq * t + phase)
    sway = 0.05 * np.sin(2 * np.pi * 0.2 * t[:, 0])
    yaw = 0.1 * np.sin(2 * np.pi * 0.1 * t[:, 0])
    base = np.zeros((n, 7))
    base[:, 0], base[:, 1], base[:, 2] = sway, 0.5 * sway, 1.0
    base[:, 5], base[:, 6] = np.sin(yaw / 2), np.cos(yaw / 2)
    return np.hstack([base, joints])


def main(path: Path, n: int = 10_000) -> None:
    print(f"host: {screwkit.host()}")
    robot = screwkit.Robot.from_urdf(path, floating_base=True)
    clip = motion(robot, n)
    lo, hi = np.array(robot.lower), np.array(robot.upper)
    assert np.all(clip[:, 7:] >= lo[7:]) and np.all(clip[:, 7:] <= hi[7:])
    poses = robot.fk(clip, link=FRAMES[0])  # warm the tree's views
    targets = {f: robot.fk(clip, link=f) for f in FRAMES}
    rest = np.clip(robot.neutral(), lo, hi)
    t0 = time.perf_counter()
    sets = [
        [screwkit.FrameTask(f, targets[f][k]) for f in FRAMES]
        + [screwkit.PostureTask(rest, weight=1e-2)]
        for k in range(n)
    ]
    build = time.perf_counter() - t0
    del poses

    # Pinocchio with a free flyer, the joints mapped by name: the independent check.
    model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    data = model.createData()
    names = list(robot.q_names[7:])
    index = [model.joints[model.getJointId(m)].idx_q for m in names]
    fids = [model.getFrameId(f, pin.BODY) for f in FRAMES]

    def check(q: np.ndarray, k: int) -> float:
        qp = pin.neutral(model)
        qp[:7] = q[:7]
        qp[index] = q[7:]
        pin.framesForwardKinematics(model, data, qp)
        return max(
            float(np.abs(data.oMf[fid].homogeneous - targets[f][k]).max())
            for fid, f in zip(fids, FRAMES, strict=False)
        )

    threads = screwkit.num_threads()
    runs: list[tuple[str, dict[str, Any]]] = [
        ("sequential", {"segment": 0}),
        ("segments", {"segment": 500, "warm_up": 20}),
    ]
    best: dict[str, float] = {}
    answers: dict[str, list[screwkit.TasksResult]] = {}
    for _ in range(3):  # interleaved rounds, minimum
        for name, options in runs:
            t0 = time.perf_counter()
            result = robot.ik_trajectory(sets, rest, **options)
            seconds = time.perf_counter() - t0
            best[name] = min(best.get(name, np.inf), seconds)
            answers[name] = result
    for name, _ in runs:
        result = answers[name]
        converged = sum(r.converged for r in result)
        errors = [check(r.q, k) for k, r in enumerate(result)]
        q = np.array([r.q for r in result])
        violations = int(np.sum((q[:, 7:] < lo[7:] - 1e-12) | (q[:, 7:] > hi[7:] + 1e-12)))
        iterations = np.array([r.iterations for r in result])
        print(
            f"RESULT robot={path.name} mode={name} frames={n} threads={threads} "
            f"seconds={best[name]:.3f} fps={n / best[name]:.0f} converged={converged} "
            f"max_error={max(errors):.1e} limit_violations={violations} "
            f"mean_iterations={iterations.mean():.2f} max_iterations={iterations.max()}"
        )
    same = all(
        np.array_equal(a.q, b.q)
        for a, b in zip(answers["sequential"], answers["segments"], strict=False)
    )
    print(
        f"NOTE task objects built in {build:.2f} s (not timed); segments equal sequential: {same}"
    )


if __name__ == "__main__":
    main(Path(sys.argv[1]))
