"""Whole-body differential IK with collision avoidance: screwkit's `CollisionAvoidance` next to
mink's `CollisionAvoidanceLimit`, the same robot, pairs, tasks and settings.

TALOS as example-robot-data ships it (collision meshes; screwkit reads them as convex hulls,
as MuJoCo does), compiled by MuJoCo from the same URDF for mink, with a table in front of it.
The right gripper is driven to a point under the table top (position task, gain 0.05, a
posture task of weight 0.01 and velocity damping of weight 0.3 (`DAMPING=`) beside it), dt =
5 ms, 1,000 steps: the arm must stop short of the table and of
the torso. Constrained pairs: every checked pair between the right arm's links and the table,
the torso and the base (the same pairs on both sides, checked), margin 5 mm, detection distance
5 cm, gain 0.85; position limits and the file's velocity limits on both (without the velocity
limits both libraries' steps reach hundreds of rad/s where the constraints fight the task, and
their rows, linear in the step, stop meaning anything: both then cut through the table).

Prints per library: the mean time of a step (the call alone; the fastest of three interleaved
runs), the closest the constrained pairs came (measured for both trajectories by MuJoCo's
`mj_geomDistance`, the referee), the steps that ended closer than the margin, and the
step-to-step change of the velocity (max and 99th percentile of ‖v_k − v_{k−1}‖, after the first
20 steps) with the velocity's own size, to show chatter or its absence.

Run (needs mink, daqp and example-robot-data besides screwkit and mujoco):

    pip install mink daqp
    python crates/screwkit-py/benchmarks/collision_avoidance_bench.py
"""

from __future__ import annotations

import re
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import mink  # type: ignore[import-not-found]
import mujoco  # type: ignore[import-untyped]
import numpy as np
import numpy.typing as npt

import screwkit

SHARE = (
    Path(sys.prefix)
    / "lib"
    / f"python{sys.version_info.major}.{sys.version_info.minor}"
    / "site-packages"
    / "cmeel.prefix"
    / "share"
)
URDF = SHARE / "example-robot-data" / "robots" / "talos_data" / "robots" / "talos_reduced.urdf"
DT = 0.005
STEPS = int(__import__("os").environ.get("STEPS", 1000))
MARGIN = 0.005
DETECTION = 0.05
GAIN = 0.85
TABLE_SIZE = (0.4, 1.0, 0.05)
TABLE_AT = (0.45, 0.0, -0.25)
HAND = "gripper_right_base_link"
TARGET = (0.45, -0.2, -0.45)
OTHERS = ["table", "torso_1_link", "torso_2_link", "base_link"]
DAMPING = float(__import__("os").environ.get("DAMPING", 0.3))


PAIRS = __import__("os").environ.get("PAIRS", "arm")


def right_arm(robot: screwkit.Robot) -> list[str]:
    """The right arm's links with shapes (PAIRS=hand: the wrist and gripper's only)."""
    links = {a for pair in robot.collision_pairs for a in pair if "right" in a and "leg" not in a}
    if PAIRS == "hand":
        links = {a for a in links if "arm_" not in a}
    return sorted(links)


def mujoco_model(urdf: Path) -> Any:
    """The URDF compiled by MuJoCo: its collision meshes (gathered under unique names, as
    MuJoCo reads a mesh by its file name), no visuals, fixed links kept as bodies; a table."""
    text = re.sub(r"<visual>.*?</visual>", "", urdf.read_text(), flags=re.S)
    folder = Path(tempfile.mkdtemp())

    def gather(m: re.Match[str]) -> str:
        real = SHARE / m.group(1).removeprefix("package://")
        name = "_".join(real.parts[-2:])
        if not (folder / name).exists():
            (folder / name).symlink_to(real)
        return f'filename="{name}"'

    text = re.sub(r'filename="(package://[^"]+)"', gather, text)
    text = text.replace(
        "</robot>",
        f'<mujoco><compiler meshdir="{folder}" fusestatic="false" discardvisual="true"'
        ' balanceinertia="true" strippath="false"/></mujoco></robot>',
    )
    spec = mujoco.MjSpec.from_string(text)
    spec.worldbody.add_geom(
        name="table",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[s / 2 for s in TABLE_SIZE],
        pos=list(TABLE_AT),
    )
    return spec.compile()


class Referee:
    """MuJoCo's distances of the constrained pairs at screwkit's or mink's configuration."""

    def __init__(self, model: Any, robot: screwkit.Robot, pairs: list[tuple[int, int]]) -> None:
        self.model, self.data, self.pairs = model, mujoco.MjData(model), pairs
        self.index = [model.jnt_qposadr[model.joint(n).id] for n in robot.q_names]

    def qpos(self, q: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        out = np.zeros(self.model.nq)
        out[self.index] = q
        return out

    def min_distance(self, qpos: npt.NDArray[np.float64]) -> float:
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_collision(self.model, self.data)
        fromto = np.zeros(6)
        return float(
            min(
                mujoco.mj_geomDistance(self.model, self.data, a, b, 1.0, fromto)
                for a, b in self.pairs
            )
        )


def chatter(vs: npt.NDArray[np.float64]) -> str:
    dv = np.linalg.norm(np.diff(vs[20:], axis=0), axis=1)
    size = np.linalg.norm(vs[20:], axis=1).max()
    return f"‖Δv‖ max {dv.max():.3g}, p99 {np.percentile(dv, 99):.3g} (‖v‖ max {size:.3g})"


def main() -> None:
    print(f"host: {screwkit.host()}")
    robot = screwkit.Robot.from_urdf(URDF, package_paths=[SHARE], meshes="convex")
    table = np.eye(4)
    table[:3, 3] = TABLE_AT
    robot.add_obstacle("table", screwkit.Box(TABLE_SIZE), table)
    arm = right_arm(robot)
    checked = {(min(p), max(p)) for p in robot.collision_pairs}
    others = ["table"] if PAIRS == "hand" else OTHERS
    ours: list[tuple[str, str]] = sorted(
        {(min(a, b), max(a, b)) for a in arm for b in others} & checked
    )
    model = mujoco_model(URDF)
    body_geoms = {
        model.body(b).name: [g for g in range(model.ngeom) if model.geom_bodyid[g] == b]
        for b in range(model.nbody)
    }
    body_geoms["table"] = [model.geom("table").id]
    body_geoms["world"] = []
    limit = mink.CollisionAvoidanceLimit(
        model,
        [([g for a in arm for g in body_geoms[a]], [g for b in others for g in body_geoms[b]])],
        gain=GAIN,
        minimum_distance_from_collisions=MARGIN,
        collision_detection_distance=DETECTION,
    )

    def owner(g: int) -> str:
        return "table" if g == model.geom("table").id else model.body(model.geom_bodyid[g]).name

    theirs = sorted({tuple(sorted((owner(a), owner(b)))) for a, b in limit.geom_id_pairs})
    assert ours == theirs, (set(ours) ^ set(theirs), len(ours), len(theirs))
    print(
        f"{len(ours)} link pairs constrained on both sides ({len(limit.geom_id_pairs)} geom pairs)"
    )
    referee = Referee(model, robot, limit.geom_id_pairs)

    # The start: arms forward and out, clear of everything by the margin.
    q0 = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
    for name, value in [
        ("arm_left_2_joint", 0.4),
        ("arm_right_2_joint", -0.4),
        ("arm_left_4_joint", -1.2),
        ("arm_right_4_joint", -1.2),
    ]:
        q0[robot.q_names.index(name)] = value
    target = np.eye(4)
    target[:3, :3] = robot.fk(q0, HAND)[:3, :3]
    target[:3, 3] = TARGET

    # screwkit
    tasks = robot.task_set(
        [
            screwkit.FrameTask(HAND, target, gain=0.05, orientation_weight=0.0),
            screwkit.PostureTask(q0, weight=1e-2),
            screwkit.DampingTask(DAMPING),
        ]
    )
    avoid = [screwkit.CollisionAvoidance(ours, MARGIN, DETECTION, GAIN)]

    def run_screwkit() -> tuple[float, npt.NDArray[np.float64], list[npt.NDArray[np.float64]]]:
        q, vs, qs, spent = q0.copy(), [], [], 0.0
        for _ in range(STEPS):
            t0 = time.perf_counter()
            v = robot.ik_step(q, tasks, DT, limits=avoid)
            spent += time.perf_counter() - t0
            q = robot.integrate(q, v, DT)
            vs.append(v)
            qs.append(referee.qpos(q))
        return spent / STEPS * 1e6, np.array(vs), qs

    # mink
    conf = mink.Configuration(model)
    mtask = mink.FrameTask(HAND, "body", position_cost=1.0, orientation_cost=0.0, gain=0.05)
    mtask.set_target(mink.SE3.from_matrix(target))
    mpost = mink.PostureTask(model, cost=1e-2)
    mdamp = mink.DampingTask(model, cost=DAMPING)
    speeds = {
        j["name"]: j["velocity"] for j in robot.info()["joints"] if j["name"] in robot.q_names
    }
    limits = [mink.ConfigurationLimit(model), mink.VelocityLimit(model, speeds), limit]

    def run_mink() -> tuple[float, npt.NDArray[np.float64], list[npt.NDArray[np.float64]]]:
        conf.update(referee.qpos(q0))
        mpost.set_target(referee.qpos(q0))
        vs, qs, spent = [], [], 0.0
        for _ in range(STEPS):
            t0 = time.perf_counter()
            v = mink.solve_ik(conf, [mtask, mpost, mdamp], DT, solver="daqp", limits=limits)
            spent += time.perf_counter() - t0
            conf.integrate_inplace(v, DT)
            vs.append(v)
            qs.append(conf.q.copy())
        return spent / STEPS * 1e6, np.array(vs), qs

    print(f"start: {referee.min_distance(referee.qpos(q0)):.4f} m from contact (MuJoCo)")
    runs: dict[str, Any] = {}
    for _ in range(3):
        for name, run in (("screwkit", run_screwkit), ("mink", run_mink)):
            us, vs, qs = run()
            if name not in runs or us < runs[name][0]:
                runs[name] = (us, vs, qs)
    for name, (us, vs, qs) in runs.items():
        d = np.array([referee.min_distance(q) for q in qs])
        print(
            f"{name:<8} {us:8.1f} µs/step; closest {d.min() * 1e3:.3f} mm (margin"
            f" {MARGIN * 1e3:.0f} mm), {int((d < MARGIN).sum())} of {STEPS} steps closer than"
            f" the margin; {chatter(vs)}"
        )
    print(f"ratio: mink / screwkit = {runs['mink'][0] / runs['screwkit'][0]:.1f}x")


if __name__ == "__main__":
    main()
