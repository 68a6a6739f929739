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
from collections.abc import Callable
from pathlib import Path
from typing import Any

import mink  # type: ignore[import-not-found]
import mujoco  # type: ignore[import-untyped]
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
    print(f"host: {screwkit.host()}")
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
    # The prepared form a control loop uses (as mink's tasks above): frames found once, the
    # first hand's target set anew every tick.
    task_set = robot.task_set(tasks)
    first = targets[HANDS[0]]

    def set_and_step() -> object:
        task_set.set_target(0, first)
        return robot.ik_step(q0, task_set, DT)

    runs: dict[str, Callable[[], object]] = {
        "screwkit": lambda: robot.ik_step(q0, tasks, DT),
        "screwkit_task_set": lambda: robot.ik_step(q0, task_set, DT),
        "screwkit_task_set_new_target": set_and_step,
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

    convergence(path, robot, names, model, data, mj, to_pin, to_mj)


def convergence(
    path: Path,
    robot: screwkit.Robot,
    names: list[str],
    model: Any,
    data: Any,
    mj: Any,
    to_pin: Callable[[np.ndarray], Any],
    to_mj: Callable[[np.ndarray], Any],
    sets: int = 100,
    peer_steps: int = 200,
) -> None:
    """To convergence on reachable target sets: both grippers to the 6-D poses of a random
    q* (10–90 % of every range), from the middle of the limits, position limits only.
    screwkit's `ik_tasks` (its tolerance, 1e-9, without and with restarts) next to pink and
    mink iterated the way their documentation loops them (a step with dt = 1, integrated,
    until the error is below a tolerance, at most `peer_steps` steps; their default damping,
    no posture task, which would hold them off the targets). Every answer is checked by
    Pinocchio's FK; limit violations are counted on every iteration of every library."""
    lo, hi = np.array(robot.lower), np.array(robot.upper)
    mid = np.clip(np.zeros(robot.nq), lo, hi)
    rng = np.random.default_rng(1)
    fids = [model.getFrameId(h, pin.BODY) for h in HANDS]
    plo, phi = model.lowerPositionLimit, model.upperPositionLimit

    def hand_errors(q_pin: Any, targets: list[np.ndarray]) -> tuple[float, float]:
        pin.framesForwardKinematics(model, data, q_pin)
        pos, rot = 0.0, 0.0
        for f, t in zip(fids, targets, strict=False):
            err = pin.log6(data.oMf[f].actInv(pin.SE3(t[:3, :3], t[:3, 3]))).vector
            pos, rot = (
                max(pos, float(np.linalg.norm(err[:3]))),
                max(rot, float(np.linalg.norm(err[3:]))),
            )
        return pos, rot

    problems = []
    for _ in range(sets):
        qstar = lo + (hi - lo) * rng.uniform(0.1, 0.9, robot.nq)
        problems.append([robot.fk(qstar, link=h) for h in HANDS])
    counts: dict[str, dict[str, float]] = {}

    def record(name: str, ok6: bool, ok9: bool, bad: int, seconds: float) -> None:
        c = counts.setdefault(name, {"1e-6": 0, "1e-9": 0, "violations": 0, "seconds": 0.0})
        c["1e-6"] += ok6
        c["1e-9"] += ok9
        c["violations"] += bad
        c["seconds"] += seconds

    for targets in problems:
        tasks = [screwkit.FrameTask(h, t) for h, t in zip(HANDS, targets, strict=False)]
        for name, restarts in [("screwkit_no_restarts", 0), ("screwkit", 50)]:
            t0 = time.perf_counter()
            r = robot.ik_tasks(tasks, seed=mid, restarts=restarts)
            dt = time.perf_counter() - t0
            bad = int(np.sum((r.q < lo - 1e-12) | (r.q > hi + 1e-12)))
            pos, rot = hand_errors(to_pin(r.q), targets)
            record(name, max(pos, rot) < 1e-6, max(pos, rot) < 1e-9, bad, dt)
        # pink
        ptasks = []
        for h, t in zip(HANDS, targets, strict=False):
            task = pink.tasks.FrameTask(h, position_cost=1.0, orientation_cost=1.0)
            task.set_target(pin.SE3(t[:3, :3], t[:3, 3]))
            ptasks.append(task)
        plimits = [PinkConfigurationLimit(model)]
        c = pink.Configuration(model, data, to_pin(mid))
        bad, t0 = 0, time.perf_counter()
        for _ in range(peer_steps):
            v = pink.solve_ik(c, ptasks, 1.0, solver="daqp", limits=plimits)
            c.integrate_inplace(v, 1.0)
            bad += int(np.sum((c.q < plo - 1e-12) | (c.q > phi + 1e-12)))
            if max(hand_errors(c.q, targets)) < 1e-9:
                break
        dt = time.perf_counter() - t0
        pos, rot = hand_errors(c.q, targets)
        record("pink", max(pos, rot) < 1e-6, max(pos, rot) < 1e-9, bad, dt)
        # mink
        mtasks = []
        for h, t in zip(HANDS, targets, strict=False):
            task = mink.FrameTask(h, "body", position_cost=1.0, orientation_cost=1.0)
            task.set_target(mink.SE3.from_matrix(t))
            mtasks.append(task)
        mlimits = [mink.ConfigurationLimit(mj)]
        mc = mink.Configuration(mj)
        mc.update(to_mj(mid))
        bad, t0 = 0, time.perf_counter()
        q_pin = to_pin(mid)
        for _ in range(peer_steps):
            v = mink.solve_ik(mc, mtasks, 1.0, solver="daqp", limits=mlimits)
            mc.integrate_inplace(v, 1.0)
            for j in range(mj.njnt):
                if mj.jnt_limited[j]:
                    x = mc.q[mj.jnt_qposadr[j]]
                    bad += int(x < mj.jnt_range[j, 0] - 1e-12 or x > mj.jnt_range[j, 1] + 1e-12)
            q_pin = to_pin(np.array([mc.q[mj.jnt_qposadr[mj.joint(n).id]] for n in names]))
            if max(hand_errors(q_pin, targets)) < 1e-9:
                break
        dt = time.perf_counter() - t0
        pos, rot = hand_errors(q_pin, targets)
        record("mink", max(pos, rot) < 1e-6, max(pos, rot) < 1e-9, bad, dt)
    for name, c in counts.items():
        print(
            f"CONVERGE robot={path.name} what={name} sets={sets} "
            f"within_1e-6={int(c['1e-6'])} within_1e-9={int(c['1e-9'])} "
            f"limit_violations={int(c['violations'])} mean_ms={c['seconds'] / sets * 1e3:.2f}"
        )


if __name__ == "__main__":
    main(Path(sys.argv[1]))
