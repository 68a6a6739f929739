"""Whole-body differential IK and the centre of mass against Pinocchio (`pin`): the centre of
mass and its Jacobian (centerOfMass, jacobianCenterOfMass on the free-flyer model, which counts
the root link as screwkit does), every IK answer's frames recomputed by Pinocchio's FK, every
step's QP checked by its KKT conditions and the limits on every step."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest
from test_tree import Peer

import screwkit

from conftest import REPO, shared_file

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin) is a test dependency")

Array = npt.NDArray[np.float64]


def shared(name: str) -> Path:
    """A whole robot of the CI data's URDF trees (the test must be marked ``shared``)."""
    return shared_file("urdf", "trees", name)


@pytest.mark.shared
@pytest.mark.parametrize(
    "name", ["talos_full_v2.urdf", "baxter.urdf", "allegro_right_hand.urdf", "so101.urdf"]
)
@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
def test_com_equals_pinocchio(name: str, floating: bool) -> None:
    path = shared(name)
    robot = screwkit.Robot.from_urdf(path, floating_base=floating)
    # Pinocchio's fixed-base model leaves the root link out: compare with its free-flyer model,
    # the base at the identity for screwkit's fixed base.
    peer = Peer(path, True)
    model, data = peer.model, peer.data
    assert robot.total_mass == pytest.approx(pin.computeTotalMass(model), rel=1e-14)
    worst = 0.0
    for seed in range(20):
        q = robot.random_configuration(seed)
        full = q if floating else np.concatenate([[0, 0, 0, 0, 0, 0, 1.0], q])
        probe = screwkit.Robot.from_urdf(path, floating_base=True)
        pq = peer.q(probe, full)
        c_pin = pin.centerOfMass(model, data, pq)
        j_pin = pin.jacobianCenterOfMass(model, data, pq)
        c = robot.com(q)
        j = robot.com_jacobian(q)
        assert c.shape == (3,) and j.shape == (3, robot.nv)
        worst = max(worst, float(np.abs(c - c_pin).max()))
        # Pinocchio's columns as screwkit's (rows (v, omega) there: the linear rows land in 3:).
        cols = peer.columns(probe, np.vstack([j_pin, np.zeros((3, model.nv))]))[3:]
        want = cols if floating else cols[:, 6:]
        worst = max(worst, float(np.abs(j - want).max()))
    assert worst < 1e-12, worst


def kkt(h: Array, c: Array, lo: Array, hi: Array, x: Array) -> int:
    """Checks the KKT conditions of x; returns how many bounds are active."""
    g = h @ x + c
    tol = 1e-9 * max(1.0, float(np.abs(c).max()))
    # x is v * dt: within rounding of the bound it is at the bound.
    at_lo = np.abs(x - lo) <= 1e-12 * np.maximum(1.0, np.abs(lo))
    at_hi = np.abs(x - hi) <= 1e-12 * np.maximum(1.0, np.abs(hi))
    assert np.all((x >= lo) | at_lo) and np.all((x <= hi) | at_hi)
    free = ~at_lo & ~at_hi
    assert np.all(np.abs(g[free]) <= tol)
    assert np.all(g[at_lo & (lo < hi)] >= -tol)
    assert np.all(g[at_hi & (lo < hi)] <= tol)
    return int(np.sum(~free))


@pytest.mark.shared
def test_talos_floating_reaches_feet_and_hands_checked_by_pinocchio() -> None:
    path = shared("talos_full_v2.urdf")
    robot = screwkit.Robot.from_urdf(path, floating_base=True)
    peer = Peer(path, True)
    names = [
        "left_sole_link",
        "right_sole_link",
        "gripper_left_base_link",
        "gripper_right_base_link",
    ]
    fids = [peer.model.getFrameId(n, pin.BODY) for n in names]
    lo, hi = np.array(robot.lower), np.array(robot.upper)
    converged = 0
    for seed in range(10):
        qs = robot.random_configuration(100 + seed)
        pin.framesForwardKinematics(peer.model, peer.data, peer.q(robot, qs))
        targets = [peer.data.oMf[f].homogeneous.copy() for f in fids]
        tasks: list[screwkit.FrameTask | screwkit.PostureTask] = [
            screwkit.FrameTask(n, t) for n, t in zip(names, targets, strict=False)
        ]
        tasks.append(screwkit.PostureTask(robot.neutral(), weight=1e-2))
        r = robot.ik_tasks(tasks)
        assert r.task_errors.shape == (5, 2)
        pin.framesForwardKinematics(peer.model, peer.data, peer.q(robot, r.q))
        for f, t in zip(fids, targets, strict=False):
            err = float(np.abs(peer.data.oMf[f].homogeneous - t).max())
            if r.converged:
                assert err < 1e-8, err
        assert np.all(r.q[7:] >= lo[7:] - 1e-12) and np.all(r.q[7:] <= hi[7:] + 1e-12)
        converged += r.converged
    assert converged == 10


def test_control_loop_steps_are_qp_optima_within_limits() -> None:
    robot = screwkit.Robot.from_urdf(REPO / "assets" / "urdf" / "torso_two_arms.urdf")
    far = np.eye(4)
    far[:3, 3] = [2.0, 1.0, 0.5]
    tasks: list[screwkit.FrameTask | screwkit.DampingTask] = [
        screwkit.FrameTask("left_hand", far),
        screwkit.FrameTask("right_hand", far, weight=0.5, orientation_weight=0.0),
        screwkit.DampingTask(1e-3),
    ]
    q = np.zeros(robot.nq)
    lo, hi = np.array(robot.lower), np.array(robot.upper)
    dt = 0.02
    active = 0
    for _ in range(100):
        v = robot.ik_step(q, tasks, dt)
        h, c, lower, upper = robot.ik_step_qp(q, tasks, dt)
        np.testing.assert_array_equal(h, h.T)
        active += kkt(h, c, lower, upper, v * dt)
        q = robot.integrate(q, v, dt)
        assert np.all(q >= lo - 1e-12) and np.all(q <= hi + 1e-12)
    assert active > 0, "the loop drives joints into their limits"


def test_a_prepared_task_set_steps_as_the_list_and_takes_new_targets() -> None:
    robot = screwkit.Robot.from_urdf(REPO / "assets" / "urdf" / "humanoid.urdf")
    q0 = np.array(robot.neutral())
    q = q0.copy()
    target = np.eye(4)
    target[:3, 3] = [0.3, 0.3, 1.1]

    def tasks(t: npt.NDArray[np.float64], c: list[float]) -> list[object]:
        return [
            screwkit.FrameTask("left_hand", t),
            screwkit.ComTask(c, weight=0.1),
            screwkit.AxisTask("head", axis=[0, 0, 1], direction=[0, 0, 1], point=[0, 0, 1.5]),
            screwkit.PostureTask(q0, weight=1e-2),
            screwkit.DampingTask(),
        ]

    ts = robot.task_set(tasks(target, [0.0, 0.0, 0.8]))  # type: ignore[arg-type]
    assert len(ts) == 5 and 'frame task on "left_hand"' in repr(ts)
    for k in range(10):
        target[1, 3] = 0.3 - 0.01 * k
        c = [0.01 * k, 0.0, 0.8]
        ts.set_target(0, target)
        ts.set_target(1, c)
        ts.set_target(2, [0.0, 0.01 * k, 1.5])
        ts.set_target(2, [0.0, 0.1, 1.0], direction=True)
        listed = tasks(target, c)
        listed[2] = screwkit.AxisTask(
            "head", axis=[0, 0, 1], direction=[0, 0.1, 1.0], point=[0, 0.01 * k, 1.5]
        )
        v = robot.ik_step(q, ts, 0.01)
        np.testing.assert_array_equal(v, robot.ik_step(q, listed, 0.01))  # type: ignore[arg-type]
        np.testing.assert_array_equal(
            robot.ik_step_qp(q, ts, 0.01)[1],
            robot.ik_step_qp(q, listed, 0.01)[1],  # type: ignore[arg-type]
        )
        assert np.any(v != 0.0)
        q = robot.integrate(q, v, 0.01)
    # Refused targets: the task keeps its own.
    before = robot.ik_step(q, ts, 0.01)
    with pytest.raises(IndexError, match="out of range"):
        ts.set_target(5, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"\(4, 4\) pose"):
        ts.set_target(0, np.eye(3))
    with pytest.raises(ValueError, match="rigid"):
        ts.set_target(0, np.full((4, 4), np.nan))
    with pytest.raises(ValueError, match="no target"):
        ts.set_target(4, [1.0])
    with pytest.raises(ValueError, match="is for an axis task"):
        ts.set_target(1, [0.0, 0.0, 1.0], direction=True)
    with pytest.raises(ValueError, match="no direction"):
        ts.set_target(2, [0.0, 0.0, 0.0], direction=True)
    with pytest.raises(ValueError, match="q_ref has 3 values"):
        ts.set_target(3, [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(robot.ik_step(q, ts, 0.01), before)
    with pytest.raises(TypeError, match=r"tasks\[0\]"):
        robot.task_set(["nope"])  # type: ignore[list-item]
    # A frame added makes a new model: the set is prepared again.
    robot.add_frame("tool", "left_hand", np.eye(4))
    with pytest.raises(ValueError, match="prepare it again"):
        robot.ik_step(q, ts, 0.01)
    assert len(robot.ik_step(q, robot.task_set([screwkit.DampingTask()]), 0.01)) == robot.nv


def test_task_errors_are_named() -> None:
    robot = screwkit.Robot.from_urdf(REPO / "assets" / "urdf" / "torso_two_arms.urdf")
    q = np.zeros(robot.nq)
    with pytest.raises(TypeError, match=r"tasks\[1\]"):
        robot.ik_step(q, [screwkit.DampingTask(), "nope"], 0.01)  # type: ignore[list-item]
    with pytest.raises(ValueError, match="unknown frame"):
        robot.ik_step(q, [screwkit.FrameTask("nowhere", np.eye(4))], 0.01)
    with pytest.raises(ValueError, match=r"\(4, 4\)"):
        screwkit.FrameTask("left_hand", np.eye(3))
    with pytest.raises(ValueError, match="gain"):
        robot.ik_step(q, [screwkit.FrameTask("left_hand", np.eye(4), gain=2.0)], 0.01)
    with pytest.raises(ValueError, match="dt"):
        robot.ik_step(q, [screwkit.DampingTask()], 0.0)
    bad = q.copy()
    bad[1] = 10.0
    with pytest.raises(ValueError, match="outside its limits"):
        robot.ik_step(bad, [screwkit.DampingTask()], 0.01)


def test_hostile_task_values_raise_value_errors_naming_them() -> None:
    robot = screwkit.Robot.from_urdf(REPO / "assets" / "urdf" / "torso_two_arms.urdf")
    q = np.zeros(robot.nq)
    nan_pose = np.eye(4)
    nan_pose[0, 3] = np.nan
    n = len(robot.variable_names)
    cases: list[tuple[list[object], str]] = [
        ([screwkit.FrameTask("left_hand", nan_pose)], "finite rigid transform"),
        ([screwkit.FrameTask("left_hand", np.eye(4), weight=np.inf)], "weight inf"),
        ([screwkit.AxisTask("left_hand", axis=[0, 0, 0], direction=[0, 0, 1])], "no direction"),
        ([screwkit.PostureTask([np.nan] * robot.nq)], r"q_ref\[0\] \(waist\) is not finite"),
        ([screwkit.ComTask([0, 0, 0])], "no link has a mass"),
    ]
    for tasks, words in cases:
        with pytest.raises(ValueError, match=words):
            robot.ik_step(q, tasks, 0.01)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"velocity_caps\[0\] = -1"):
        robot.ik_step(q, [screwkit.DampingTask()], 0.01, velocity_caps=[-1.0] * n)
    with pytest.raises(ValueError, match="not finite"):
        robot.ik_step(np.full(robot.nq, np.nan), [screwkit.DampingTask()], 0.01)
    assert robot.ik_tasks([]).stop == "converged"


def within_limits(robot: screwkit.Robot, q: Array) -> bool:
    lo, hi = np.array(robot.lower), np.array(robot.upper)
    off = 7 if robot.floating_base else 0
    return bool(np.all(q[off:] >= lo[off:] - 1e-12) and np.all(q[off:] <= hi[off:] + 1e-12))


@pytest.mark.shared
def test_relative_frame_task_holds_one_gripper_in_the_other_checked_by_pinocchio() -> None:
    path = shared("baxter.urdf")
    robot = screwkit.Robot.from_urdf(path)
    peer = Peer(path, False)
    fl, fr = (peer.model.getFrameId(n, pin.BODY) for n in ("left_gripper", "right_gripper"))

    def relative(q: Array) -> Array:
        pin.framesForwardKinematics(peer.model, peer.data, peer.q(robot, q))
        return np.asarray((peer.data.oMf[fr].inverse() * peer.data.oMf[fl]).homogeneous)

    for seed in range(10):
        want = relative(robot.random_configuration(200 + seed))
        r = robot.ik_tasks([screwkit.RelativeFrameTask("left_gripper", "right_gripper", want)])
        assert r.converged, r
        assert np.abs(relative(r.q) - want).max() < 1e-8
        assert within_limits(robot, r.q)


@pytest.mark.shared
def test_axis_task_points_a_five_axis_arm_checked_by_pinocchio() -> None:
    path = shared("so101.urdf")
    robot = screwkit.Robot.from_urdf(path)
    peer = Peer(path, False)
    fid = peer.model.getFrameId("gripper_frame_link", pin.BODY)

    def pose(q: Array) -> Array:
        pin.framesForwardKinematics(peer.model, peer.data, peer.q(robot, q))
        return np.asarray(peer.data.oMf[fid].homogeneous)

    for seed in range(10):
        star = pose(robot.random_configuration(300 + seed))
        d, p = star[:3, 2], star[:3, 3]
        r = robot.ik_tasks(
            [screwkit.AxisTask("gripper_frame_link", axis=(0, 0, 1), direction=d, point=p)]
        )
        assert r.converged, r
        got = pose(r.q)
        assert float(got[:3, 2] @ d) > 1 - 1e-12
        assert np.abs(got[:3, 3] - p).max() < 1e-8
        assert within_limits(robot, r.q)


@pytest.mark.shared
def test_com_task_balances_a_floating_humanoid_checked_by_pinocchio() -> None:
    path = shared("talos_full_v2.urdf")
    robot = screwkit.Robot.from_urdf(path, floating_base=True)
    peer = Peer(path, True)
    feet = ["left_sole_link", "right_sole_link"]
    fids = [peer.model.getFrameId(n, pin.BODY) for n in feet]
    for seed in range(5):
        star = peer.q(robot, robot.random_configuration(400 + seed))
        pin.framesForwardKinematics(peer.model, peer.data, star)
        soles = [peer.data.oMf[f].homogeneous.copy() for f in fids]
        c = pin.centerOfMass(peer.model, peer.data, star).copy()
        tasks: list[screwkit.FrameTask | screwkit.ComTask | screwkit.PostureTask] = [
            screwkit.FrameTask(n, t) for n, t in zip(feet, soles, strict=False)
        ]
        tasks.append(screwkit.ComTask(c))
        tasks.append(screwkit.PostureTask(robot.neutral(), weight=1e-2))
        r = robot.ik_tasks(tasks)
        assert r.converged, r
        got = peer.q(robot, r.q)
        assert np.abs(pin.centerOfMass(peer.model, peer.data, got) - c).max() < 1e-8
        pin.framesForwardKinematics(peer.model, peer.data, got)
        for f, t in zip(fids, soles, strict=False):
            assert np.abs(peer.data.oMf[f].homogeneous - t).max() < 1e-8
        assert within_limits(robot, r.q)


@pytest.mark.shared
def test_a_floating_base_pose_task_is_a_frame_task_on_the_root_link() -> None:
    path = shared("talos_full_v2.urdf")
    robot = screwkit.Robot.from_urdf(path, floating_base=True)
    peer = Peer(path, True)
    root, foot = (peer.model.getFrameId(n, pin.BODY) for n in ("base_link", "left_sole_link"))
    for seed in range(5):
        star = robot.random_configuration(500 + seed)
        pin.framesForwardKinematics(peer.model, peer.data, peer.q(robot, star))
        base = peer.data.oMf[root].homogeneous.copy()
        sole = peer.data.oMf[foot].homogeneous.copy()
        r = robot.ik_tasks(
            [
                screwkit.FrameTask("base_link", base),
                screwkit.FrameTask("left_sole_link", sole),
                screwkit.PostureTask(robot.neutral(), weight=1e-2),
            ]
        )
        assert r.converged, r
        pin.framesForwardKinematics(peer.model, peer.data, peer.q(robot, r.q))
        assert np.abs(peer.data.oMf[root].homogeneous - base).max() < 1e-8
        assert np.abs(peer.data.oMf[foot].homogeneous - sole).max() < 1e-8
        assert within_limits(robot, r.q)
