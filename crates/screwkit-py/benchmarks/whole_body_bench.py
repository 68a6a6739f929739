"""Whole-body differential IK: screwkit next to pink (Pinocchio + a QP from qpsolvers) and mink
(MuJoCo, the robot compiled from the same URDF), same robot, tasks, targets and limits, one
thread, interleaved rounds, minimum per call. Also the step's QP handed to general QP solvers
(Clarabel, DAQP, ...) through qpsolvers, to compare with screwkit's whole step (Jacobians +
box-constrained active set).

Run with a venv holding screwkit, pin, pin-pink, mink, mujoco, qpsolvers and the solvers:

    python crates/screwkit-py/benchmarks/whole_body_bench.py ../shared/urdf/trees/talos_full_v2.urdf

Prints one `RESULT` line per measurement and the limit violations counted on every step of a
control loop run by each library.
"""

from __future__ import annotations

import re
import sys
import time
from pathlib import Path
from typing import Any, Callable

import mink  # type: ignore[import-not-found]
import mujoco  # type: ignore[import-not-found]
import numpy as np
import pink  # type: ignore[import-not-found]
import pinocchio as pin
import qpsolvers  # type: ignore[import-not-found]
from pink.limits import (  # type: ignore[import-not-found]
    ConfigurationLimit as PinkConfigurationLimit,
)
from pink.limits import (
    VelocityLimit as PinkVelocityLimit,
)

import screwkit

HANDS = ["gripper_left_base_link", "gripper_right_base_link"]
DT = 0.01


def best(f: Callable[[], object], rounds: int = 7, inner: int = 200) -> float:
    """Minimum over rounds of the mean time per call, in µs."""
    out = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        for _ in range(inner):
            f()
        out.append((time.perf_counter() - t0) / inner * 1e6)
    return min(out)


def mujoco_model(urdf: str) -> Any:
    """The URDF compiled by MuJoCo, geometry dropped, fixed links kept as bodies."""
    xml = re.sub(r"<(visual|collision)>.*?</\1>", "", urdf, flags=re.S)
    xml = xml.replace(
        "</robot>",
        '<mujoco><compiler fusestatic="false" discardvisual="true" balanceinertia="true"/>'
        "</mujoco></robot>",
    )
    return mujoco.MjModel.from_xml_string(xml)


def main(path: Path) -> None:
    urdf = path.read_text()
    robot = screwkit.Robot.from_urdf(path)
    n = robot.nq
    lo, hi = np.array(robot.lower), np.array(robot.upper)
    mid = np.clip(np.zeros(n), lo, hi)
    rng = np.random.default_rng(0)
    qstar = lo + (hi - lo) * rng.uniform(0.3, 0.7, n)
    targets = {h: robot.fk(qstar, link=h) for h in HANDS}

    # screwkit
    tasks: list[screwkit.FrameTask | screwkit.PostureTask | screwkit.DampingTask] = [
        screwkit.FrameTask(h, targets[h]) for h in HANDS
    ]
    tasks.append(screwkit.PostureTask(mid, weight=1e-2))
    tasks.append(screwkit.DampingTask(1e-6))

    # pink (Pinocchio): the joints in the same order by name
    model = pin.buildModelFromXML(urdf)
    data = model.createData()
    names = list(robot.variable_names)

    def to_pin(q: np.ndarray) -> Any:
        out = pin.neutral(model)
        for k, name in enumerate(names):
            jid = model.getJointId(name)
            out[model.joints[jid].idx_q] = q[k]
        return out

    config = pink.Configuration(model, data, to_pin(mid))
    ptasks = []
    for h in HANDS:
        t = pink.tasks.FrameTask(h, position_cost=1.0, orientation_cost=1.0)
        t.set_target(pin.SE3(targets[h][:3, :3], targets[h][:3, 3]))
        ptasks.append(t)
    post = pink.tasks.PostureTask(cost=1e-2)
    post.set_target(to_pin(mid))
    ptasks.append(post)
    plimits = [PinkConfigurationLimit(model), PinkVelocityLimit(model)]

    # mink (MuJoCo)
    mj = mujoco_model(urdf)
    mconf = mink.Configuration(mj)

    def to_mj(q: np.ndarray) -> Any:
        out = mj.qpos0.copy()
        for k, name in enumerate(names):
            out[mj.jnt_qposadr[mj.joint(name).id]] = q[k]
        return out

    mconf.update(to_mj(mid))
    mtasks = []
    for h in HANDS:
        t = mink.FrameTask(h, "body", position_cost=1.0, orientation_cost=1.0)
        t.set_target(mink.SE3.from_matrix(targets[h]))
        mtasks.append(t)
    mpost = mink.PostureTask(mj, cost=1e-2)
    mpost.set_target(to_mj(mid))
    mtasks.append(mpost)
    mlimits = [mink.ConfigurationLimit(mj)]

    q0 = mid.copy()
    runs: dict[str, Callable[[], object]] = {
        "screwkit": lambda: robot.ik_step(q0, tasks, DT),
        "pink_daqp": lambda: pink.solve_ik(config, ptasks, DT, solver="daqp", limits=plimits),
        "mink_daqp": lambda: mink.solve_ik(mconf, mtasks, DT, solver="daqp", limits=mlimits),
    }
    hq, cq, lower, upper = robot.ik_step_qp(q0, tasks, DT)

    def qp_only(solver: str) -> Callable[[], object]:
        return lambda: qpsolvers.solve_qp(hq, cq, lb=lower, ub=upper, solver=solver)

    for solver in ["clarabel", "daqp", "quadprog", "proxqp", "osqp"]:
        runs[f"qp_only_{solver}"] = qp_only(solver)
    # Interleaved: every library once per round, minima kept.
    times = {k: float("inf") for k in runs}
    for _ in range(5):
        for k, f in runs.items():
            times[k] = min(times[k], best(f, rounds=1, inner=100 if "screwkit" in k else 30))
    for k, t in times.items():
        print(
            f"RESULT robot={path.name} what={k} step_us={t:.2f} "
            f"ratio_to_screwkit={t / times['screwkit']:.1f}"
        )
    # The step agrees with the general solvers on the same QP.
    v = robot.ik_step(q0, tasks, DT)
    for solver in ["clarabel", "daqp", "quadprog"]:
        x = qpsolvers.solve_qp(hq, cq, lb=lower, ub=upper, solver=solver)
        print(f"AGREE solver={solver} max_abs_diff={np.abs(x - v * DT).max():.2e}")

    # Control loops: limit violations on every step, and where the hands end.
    def violations_screwkit() -> tuple[int, float]:
        q, bad = mid.copy(), 0
        for _ in range(300):
            v = robot.ik_step(q, tasks, DT)
            q = robot.integrate(q, v, DT)
            bad += int(np.sum((q < lo - 1e-12) | (q > hi + 1e-12)))
        err = max(np.abs(robot.fk(q, link=hh) - targets[hh]).max() for hh in HANDS)
        return bad, float(err)

    def violations_pink() -> tuple[int, float]:
        c = pink.Configuration(model, data, to_pin(mid))
        bad = 0
        for _ in range(300):
            v = pink.solve_ik(c, ptasks, DT, solver="daqp", limits=plimits)
            c.integrate_inplace(v, DT)
            bad += int(
                np.sum(
                    (c.q < model.lowerPositionLimit - 1e-12)
                    | (c.q > model.upperPositionLimit + 1e-12)
                )
            )
        err = max(
            np.abs(c.get_transform_frame_to_world(hh).homogeneous - targets[hh]).max()
            for hh in HANDS
        )
        return bad, float(err)

    def violations_mink() -> tuple[int, float]:
        c = mink.Configuration(mj)
        c.update(to_mj(mid))
        bad = 0
        lim = mj.jnt_range
        for _ in range(300):
            v = mink.solve_ik(c, mtasks, DT, solver="daqp", limits=mlimits)
            c.integrate_inplace(v, DT)
            for j in range(mj.njnt):
                if mj.jnt_limited[j]:
                    x = c.q[mj.jnt_qposadr[j]]
                    bad += int(x < lim[j, 0] - 1e-12 or x > lim[j, 1] + 1e-12)
        err = max(
            np.abs(c.get_transform_frame_to_world(hh, "body").as_matrix() - targets[hh]).max()
            for hh in HANDS
        )
        return bad, float(err)

    for name, f in [
        ("screwkit", violations_screwkit),
        ("pink", violations_pink),
        ("mink", violations_mink),
    ]:
        bad, err = f()
        print(
            f"LOOP robot={path.name} what={name} steps=300 limit_violations={bad} "
            f"final_hand_error={err:.2e}"
        )


if __name__ == "__main__":
    main(Path(sys.argv[1]))
