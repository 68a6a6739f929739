"""Cartesian paths (`Robot.cartesian_path`, issue 51 item 2): the tool's pose at every sample
is on the requested screw or line by an independent FK (`Robot.fk`) and the textbook's own
formulas (`modern_robotics`' MatrixExp6/MatrixLog6); no joint moves more than `max_joint_step`
between samples; the UR5 (closed-form IK) keeps its posture; a path through its wrist
singularity stops there and says so; a 7-joint arm is followed by numerical IK; an
unreachable target stops the path (at the reach boundary, where the elbow's branches meet) with
the fraction achieved; the Panda with a locked joint and the KUKA KR 16 (CI data) cross the
workspace on one branch, ending on the goal configuration the target was made from, the
Jacobian's determinant never changing sign (no singular surface crossed); many paths at once
equal their single calls; bad arguments raise."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

from conftest import ASSETS, shared_file

mr = pytest.importorskip("modern_robotics", reason="pip install modern_robotics")
F64 = npt.NDArray[np.float64]

UR5 = ASSETS / "ur5.urdf"
SEED = np.array([0.3, -1.2, 1.4, -1.5, -1.4, 0.4])


def lie_quaternion(r: F64) -> F64:
    """(qx, qy, qz, qw) of a rotation matrix (Shepperd's method, w the largest here)."""
    w = 0.5 * np.sqrt(max(1.0 + np.trace(r), 1e-300))
    return np.array(
        [
            (r[2, 1] - r[1, 2]) / (4 * w),
            (r[0, 2] - r[2, 0]) / (4 * w),
            (r[1, 0] - r[0, 1]) / (4 * w),
            w,
        ]
    )


def on_the_path(a: F64, b: F64, place: float, how: str) -> F64:
    """The textbook's pose at σ between a and b (screw: MR's ScrewTrajectory's formula;
    line: its CartesianTrajectory's)."""
    if how == "screw":
        return np.asarray(a @ mr.MatrixExp6(mr.MatrixLog6(mr.TransInv(a) @ b) * place))
    r = a[:3, :3] @ mr.MatrixExp3(mr.MatrixLog3(a[:3, :3].T @ b[:3, :3]) * place)
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = r, (1 - place) * a[:3, 3] + place * b[:3, 3]
    return out


@pytest.mark.parametrize("how", ["screw", "line"])
def test_the_ur5_follows_the_path_on_one_branch(how: Literal["screw", "line"]) -> None:
    robot = screwkit.Robot.from_urdf(UR5)
    start = robot.fk(SEED)
    turn = np.asarray(mr.MatrixExp3(mr.VecToso3([0.0, 0.3, 0.4])))
    goal = start.copy()
    goal[:3, :3] = start[:3, :3] @ turn
    goal[:3, 3] += [0.1, -0.15, 0.05]
    path = robot.cartesian_path(goal, SEED, interpolation=how)
    assert path.stop == "reached" and path.fraction == 1.0, path.message
    assert path.q.shape == (len(path.place), 6) and len(path.place) > 30
    np.testing.assert_array_equal(path.q[0], SEED)
    assert np.abs(np.diff(path.q, axis=0)).max() <= 0.1
    for q, place in zip(path.q, path.place, strict=True):
        np.testing.assert_allclose(robot.fk(q), on_the_path(start, goal, place, how), atol=1e-9)
    # The posture of the seed throughout: its shoulder, elbow and wrist signs.
    solutions = robot.ik_all(goal, seed=path.q[-1])
    np.testing.assert_allclose(solutions[0], path.q[-1], atol=1e-9)


def test_waypoints_are_passed_in_order() -> None:
    robot = screwkit.Robot.from_urdf(UR5)
    start = robot.fk(SEED)
    targets = np.stack([start.copy() for _ in range(3)])
    targets[0, :3, 3] += [0.08, 0, 0]
    targets[1, :3, 3] += [0.08, 0.08, 0]
    targets[2, :3, 3] += [0, 0.08, 0.05]
    path = robot.cartesian_path(targets, SEED, interpolation="line")
    assert path.stop == "reached", path.message
    for k in range(3):
        at = np.flatnonzero(path.place == k + 1)
        assert len(at) == 1, k
        np.testing.assert_allclose(robot.fk(path.q[at[0]]), targets[k], atol=1e-9)


def test_a_path_through_the_wrist_singularity_stops_there() -> None:
    """The screw from the seed to the same arm with joint 5 at −0.3 instead of +0.3 is joint
    5's rotation: it crosses q5 = 0, where joints 4 and 6 align. The path stops before it."""
    robot = screwkit.Robot.from_urdf(UR5)
    seed = np.array([0.3, -1.2, 1.4, -1.5, 0.3, 0.4])
    through = seed.copy()
    through[4] = -0.3
    path = robot.cartesian_path(robot.fk(through), seed)
    assert path.stop == "singularity", path.message
    assert 0.4 < path.fraction < 0.5
    assert "singular" in path.message
    assert 0 < path.q[-1, 4] < 0.03


def test_a_seven_joint_arm_is_followed_numerically() -> None:
    """Without a lock, a redundant arm's path is numerical IK seeded by the previous sample."""
    robot = screwkit.Robot.from_urdf(ASSETS / "iiwa14.urdf")
    seed = np.array([0.2, 0.6, -0.1, -1.2, 0.3, 0.8, 0.1])
    start = robot.fk(seed)
    goal = start.copy()
    goal[:3, 3] += [0.0, 0.12, -0.08]
    path = robot.cartesian_path(goal, seed, interpolation="line")
    assert path.stop == "reached", path.message
    assert np.abs(np.diff(path.q, axis=0)).max() <= 0.1
    for q, place in zip(path.q[1:], path.place[1:], strict=True):
        np.testing.assert_allclose(robot.fk(q), on_the_path(start, goal, place, "line"), atol=1e-6)


def test_the_panda_with_a_locked_joint_stays_on_one_branch() -> None:
    """Joint 3 locked (held at the seed's value): the other six are the closed-form solution
    nearest the previous sample. The goal is FK of a configuration with the same joint 3 on
    the seed's branch, and the path ends exactly there."""
    robot = screwkit.Robot.from_urdf(ASSETS / "panda.urdf")
    seed = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
    goal_q = np.array([-0.5, 0.3, 0.2, -1.4, -0.4, 1.2, 1.3])
    start, goal = robot.fk(seed), robot.fk(goal_q)
    for how in ("screw", "line"):
        path = robot.cartesian_path(goal, seed, interpolation=how, lock="panda_joint3")
        assert path.stop == "reached", path.message
        assert len(path.place) > 50
        np.testing.assert_array_equal(path.q[:, 2], seed[2])
        assert np.abs(np.diff(path.q, axis=0)).max() <= 0.1
        for q, place in zip(path.q, path.place, strict=True):
            np.testing.assert_allclose(robot.fk(q), on_the_path(start, goal, place, how), atol=1e-9)
        np.testing.assert_allclose(path.q[-1], goal_q, atol=1e-9)
    # By index, the same; a redundant arm without a lock is followed numerically (joint 3
    # moves); a lock the arm cannot take is an error.
    by_index = robot.cartesian_path(goal, seed, lock=2)
    np.testing.assert_array_equal(
        by_index.q, robot.cartesian_path(goal, seed, lock="panda_joint3").q
    )
    free = robot.cartesian_path(goal, seed)
    assert free.stop == "reached" and np.ptp(free.q[:, 2]) > 1e-3
    with pytest.raises(ValueError, match="arm angle"):
        robot.cartesian_path(goal, seed, lock="arm_angle")
    with pytest.raises(ValueError, match="lock"):
        robot.cartesian_path(goal, seed, lock="no_such_joint")


@pytest.mark.shared
def test_the_kr16_crosses_the_workspace_on_one_branch() -> None:
    """The KUKA KR 16 (CI data, xacro expanded): a screw and a line across 1.8 rad of its
    first joint, each ending on the goal configuration; det J keeps its sign throughout."""
    urdf = shared_file("xacro", "expanded", "kr16_2.urdf")
    robot = screwkit.Robot.from_urdf(urdf, "base_link", "tool0")
    seed = np.array([-0.9, -1.2, 1.6, 0.4, 0.8, -0.3])
    goal_q = np.array([0.9, -0.6, 0.7, -0.5, 1.2, 0.5])
    start, goal = robot.fk(seed), robot.fk(goal_q)
    for how in ("screw", "line"):
        path = robot.cartesian_path(goal, seed, interpolation=how)
        assert path.stop == "reached", path.message
        assert len(path.place) > 300
        assert np.abs(np.diff(path.q, axis=0)).max() <= 0.1
        for q, place in zip(path.q, path.place, strict=True):
            np.testing.assert_allclose(robot.fk(q), on_the_path(start, goal, place, how), atol=1e-9)
        det = np.array([np.linalg.det(robot.jacobian(q)) for q in path.q])
        assert np.all(det < -0.05) or np.all(det > 0.05), (det.min(), det.max())
        np.testing.assert_allclose(path.q[-1], goal_q, atol=1e-9)


def test_many_paths_equal_their_single_calls() -> None:
    """`cartesian_paths`: (N, K, 4, 4) targets with one seed or one per path, a list of N
    paths, each equal to its single call bit for bit; a bad row raises BatchError naming it,
    the others computed."""
    robot = screwkit.Robot.from_urdf(UR5)
    rng = np.random.default_rng(5)
    seeds = SEED + rng.uniform(-0.3, 0.3, (12, 6))
    targets = np.stack([robot.fk(s + rng.uniform(-0.4, 0.4, 6))[None] for s in seeds])
    many = robot.cartesian_paths(targets, seeds, interpolation="line")
    assert isinstance(many, list) and len(many) == 12
    for k, path in enumerate(many):
        one = robot.cartesian_path(targets[k], seeds[k], interpolation="line")
        np.testing.assert_array_equal(path.q, one.q)
        np.testing.assert_array_equal(path.place, one.place)
        assert (path.stop, path.fraction, path.message) == (one.stop, one.fraction, one.message)
    shared_seed = robot.cartesian_paths(targets[:3, 0], SEED)
    np.testing.assert_array_equal(shared_seed[2].q, robot.cartesian_path(targets[2], SEED).q)
    bad = targets.copy()
    bad[4, 0, 0, 3] = np.nan
    bad_seeds = seeds.copy()
    bad_seeds[7, 0] = np.nan
    with pytest.raises(screwkit.BatchError, match="row 4") as caught:
        robot.cartesian_paths(bad, bad_seeds)
    assert caught.value.rows == [4, 7]
    result = caught.value.result
    assert result[4] is None and result[7] is None
    np.testing.assert_array_equal(result[3].q, robot.cartesian_path(targets[3], seeds[3]).q)
    with pytest.raises(ValueError, match="seed"):
        robot.cartesian_paths(targets, seeds[:5])
    with pytest.raises(ValueError, match="cartesian_paths"):
        robot.cartesian_path(targets, SEED)
    with pytest.raises(ValueError, match=r"\(N, 4, 4\)"):
        robot.cartesian_paths(targets[0, 0], SEED)


def test_an_unreachable_target_stops_the_path() -> None:
    robot = screwkit.Robot.from_urdf(UR5)
    goal = robot.fk(SEED)
    goal[:3, 3] = [2.0, 0.0, 0.5]  # 2 m away: beyond the UR5's reach
    path = robot.cartesian_path(goal, SEED, interpolation="line")
    # The arm straightens on the way out: its elbow-up and elbow-down branches meet there.
    assert path.stop in ("singularity", "unreachable", "branch ends"), path.message
    assert 0.0 < path.fraction < 1.0
    np.testing.assert_array_equal(path.q[0], SEED)


def test_bad_arguments_are_refused() -> None:
    robot = screwkit.Robot.from_urdf(UR5)
    goal = robot.fk(SEED)
    for kwargs, says in [
        ({"interpolation": "spline"}, "interpolation"),
        ({"max_step": 0.0}, "max_step"),
        ({"max_joint_step": float("nan")}, "max_joint_step"),
    ]:
        with pytest.raises(ValueError, match=says):
            robot.cartesian_path(goal, SEED, **kwargs)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="targets"):
        robot.cartesian_path(goal[:3], SEED)
    with pytest.raises(ValueError, match="seed"):
        robot.cartesian_path(goal, SEED[:3])
    path = robot.cartesian_path(goal, SEED)
    with pytest.raises(ValueError, match=r"\(K, 6\)"):
        robot.plot_joints(path.q[:, :3])
    with pytest.raises(ValueError, match="x"):
        robot.plot_joints(path.q, path.place[:-1])
    with pytest.raises(ValueError, match="decrease"):
        robot.plot_joints(path.q, -path.place)


def test_the_command_line_gives_the_same_path(tmp_path: Path) -> None:
    """`screwkit path FILE --from q --to pose [--via pose] [--line] [--format json]` = Python's
    path sample for sample; `--timed --acc …` = `time_parameterize` with the file's velocity
    limits; `-o path.npy` holds the same numbers (t then q per row when timed)."""
    import json
    import os
    import subprocess

    exe = os.environ.get("SCREWKIT_CLI")
    if not exe:
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    robot = screwkit.Robot.from_urdf(UR5)
    start = robot.fk(SEED)
    via, goal = start.copy(), start.copy()
    via[:3, 3] += [0.05, 0.0, 0.0]
    goal[:3, 3] += [0.05, 0.06, -0.04]

    def arg(x: F64) -> str:
        return ",".join(repr(float(v)) for v in np.ravel(x))

    base = [exe, "path", str(UR5), "--from", arg(SEED), "--to", arg(goal), "--via", arg(via)]
    plot = tmp_path / "joints.svg"
    done = subprocess.run(
        [*base, "--line", "--format", "json", "--plot", str(plot)], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    ours = robot.cartesian_path(np.stack([via, goal]), SEED, interpolation="line")
    # The joint plot: one panel per joint, K points each, the same bytes from both front ends.
    svg = robot.plot_joints(ours.q, ours.place)
    assert plot.read_text() == svg
    assert svg.count('class="joint"') == 6 and all(
        f"<title>{n}</title>" in svg for n in robot.joint_names
    )
    assert svg.count(" L") == 6 * (len(ours.place) - 1)
    np.testing.assert_array_equal(np.array(report["q"]), ours.q)
    np.testing.assert_array_equal(report["place"], ours.place)
    assert report["stop"] == ours.stop == "reached" and report["variables"] == robot.joint_names
    acc = np.full(6, 2.0)
    out = tmp_path / "timed.npy"
    done = subprocess.run(
        [*base, "--timed", "--acc", arg(acc), "-o", str(out), "--format", "json"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    timed = json.loads(done.stdout)["timed"]
    screw = robot.cartesian_path(np.stack([via, goal]), SEED)
    want = robot.time_parameterize(screw.q, acc)
    assert want.duration == screwkit.time_parameterize(screw.q, robot.velocity_limits, acc).duration
    assert timed["duration"] == want.duration
    rows = np.load(out)
    assert rows.shape == (len(timed["t"]), 7)
    plotted = subprocess.run(
        [*base, "--timed", "--acc", arg(acc), "--plot", str(plot)], capture_output=True, text=True
    )
    assert plotted.returncode == 0, plotted.stderr
    assert plot.read_text() == robot.plot_joints(rows[:, 1:], rows[:, 0], x_label="time (s)")
    np.testing.assert_array_equal(rows[:, 0], timed["t"])
    np.testing.assert_array_equal(rows[:, 1:], want(rows[:, 0]))
    bad = subprocess.run([*base[:-2], "--to", "1,2,3"], capture_output=True, text=True)
    assert bad.returncode != 0 and "--to" in bad.stderr and len(bad.stderr.splitlines()) == 1
    # The waypoints from a .npy file ((K, 4, 4), or rows of 7 numbers): the same path.
    stack = tmp_path / "waypoints.npy"
    np.save(stack, np.stack([via, goal]))
    cmd = [exe, "path", str(UR5), "--from", arg(SEED), "--waypoints", str(stack), "--line"]
    done = subprocess.run([*cmd, "--format", "json"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    np.testing.assert_array_equal(json.loads(done.stdout)["q"], ours.q)
    quat = np.array([[*t[:3, 3], *lie_quaternion(t[:3, :3])] for t in (via, goal)])
    np.save(stack, quat)
    done = subprocess.run([*cmd, "--format", "json"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    np.testing.assert_allclose(json.loads(done.stdout)["q"], ours.q, atol=1e-9)
    quat[1, 0] = np.nan
    np.save(stack, quat)
    bad = subprocess.run(cmd, capture_output=True, text=True)
    assert bad.returncode != 0 and "row 1" in bad.stderr and len(bad.stderr.splitlines()) == 1
    np.save(stack, np.zeros((2, 5)))
    bad = subprocess.run(cmd, capture_output=True, text=True)
    assert bad.returncode != 0 and "shape" in bad.stderr
    # A 7R arm with a locked joint: the same path as Python's.
    panda = screwkit.Robot.from_urdf(ASSETS / "panda.urdf")
    seed = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
    goal = panda.fk(np.array([-0.5, 0.3, 0.2, -1.4, -0.4, 1.2, 1.3]))
    cmd = [exe, "path", str(ASSETS / "panda.urdf"), "--from", arg(seed), "--to", arg(goal)]
    done = subprocess.run(
        [*cmd, "--lock", "panda_joint3", "--format", "json"], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    locked = panda.cartesian_path(goal, seed, lock="panda_joint3")
    np.testing.assert_array_equal(json.loads(done.stdout)["q"], locked.q)
    bad = subprocess.run([*cmd, "--lock", "arm_angle"], capture_output=True, text=True)
    assert bad.returncode != 0 and "arm angle" in bad.stderr
    assert len(bad.stderr.splitlines()) == 1
