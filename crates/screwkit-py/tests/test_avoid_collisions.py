"""Numerical IK that keeps clear of contact (`Robot.ik(avoid_collisions=True, margin=…)`,
`screwkit ik --avoid-collisions`), checked by coal: the Panda and the UR5 as example-robot-data
ships them (collision meshes, SRDFs) beside a table and a box. Targets are reachable and clear
by construction (FK of random q* that coal finds at least the margin from contact, the tool
near the table); every answer is checked by Pinocchio's FK and coal's distances, never by
screwkit's own distance code. Plain IK's answers are shown to collide on the same targets, so
the checks can fail."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from test_body import SHARE, files, pin

import screwkit

coal = pytest.importorskip("coal", reason="coal (pip install coal) is a test dependency")

MARGIN = 0.01
# (name, size, centre): a table in front of the robot and a box above it.
OBSTACLES = [
    ("table", (0.6, 1.2, 0.05), (0.6, 0.0, 0.1)),
    ("box", (0.15, 0.15, 0.15), (0.45, -0.3, 0.35)),
]
TIPS = {"panda": ("panda_link0", "panda_hand"), "ur5": ("base_link", "ee_link")}


def scene(tmp_path: Path) -> Path:
    """The obstacles as a scene file."""
    path = tmp_path / "scene.json"
    obstacles = [
        {"name": n, "shape": "box", "size": list(s), "xyz": list(c)} for n, s, c in OBSTACLES
    ]
    path.write_text(json.dumps({"obstacles": obstacles}))
    return path


class Oracle:
    """Pinocchio's model of the file and coal's shapes: the SRDF's pairs removed, the obstacles
    on the world checked against every link's shape."""

    def __init__(self, urdf: Path, srdf: Path, robot: screwkit.Robot, tip: str) -> None:
        self.model, self.cmodel, _ = pin.buildModelsFromUrdf(str(urdf), package_dirs=[str(SHARE)])
        self.cmodel.addAllCollisionPairs()
        pin.removeCollisionPairs(self.model, self.cmodel, str(srdf))
        links = self.cmodel.ngeoms
        for name, size, centre in OBSTACLES:
            box = pin.GeometryObject(name, 0, pin.SE3(np.eye(3), np.array(centre)), coal.Box(*size))
            box.parentFrame = 0
            self.cmodel.addGeometryObject(box)
            k = self.cmodel.ngeoms - 1
            for g in range(links):
                self.cmodel.addCollisionPair(pin.CollisionPair(g, k))
        self.data = self.model.createData()
        self.cdata = pin.GeometryData(self.cmodel)
        for r in self.cdata.distanceRequests:
            r.gjk_tolerance = 1e-12
        self.names = robot.joint_names
        self.tip = self.model.getFrameId(tip)

    def q(self, ours: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Pinocchio's q: the chain's joints by name, the others (fingers) at 0."""
        q = np.zeros(self.model.nq)
        for j in range(1, self.model.njoints):
            name = self.model.names[j]
            if name in self.names:
                q[self.model.joints[j].idx_q] = ours[self.names.index(name)]
        return q

    def min_distance(self, ours: npt.NDArray[np.float64]) -> float:
        pin.computeDistances(self.model, self.data, self.cmodel, self.cdata, self.q(ours))
        return float(min(r.min_distance for r in self.cdata.distanceResults))

    def fk(self, ours: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        pin.framesForwardKinematics(self.model, self.data, self.q(ours))
        return np.asarray(self.data.oMf[self.tip].homogeneous)


def setup(name: str) -> tuple[screwkit.Robot, Oracle, Path, Path]:
    urdf, srdf, _ = files(name)
    base, tip = TIPS[name]
    robot = screwkit.Robot.from_urdf(urdf, base, tip, package_paths=[SHARE])
    robot.srdf(srdf)
    for n, size, centre in OBSTACLES:
        pose = np.eye(4)
        pose[:3, 3] = centre
        robot.add_obstacle(n, screwkit.Box(size), pose)
    return robot, Oracle(urdf, srdf, robot, tip), urdf, srdf


def clear_targets(
    robot: screwkit.Robot, oracle: Oracle, count: int, seed: int
) -> npt.NDArray[np.float64]:
    """FK of random q* (within the limits) that coal finds at least the margin (and 2 mm) from
    contact, with the tool over the table, at most 0.25 m above its top."""
    rng = np.random.default_rng(seed)
    lo, hi = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    out: list[npt.NDArray[np.float64]] = []
    while len(out) < count:
        q = rng.uniform(lo, hi)
        t = oracle.fk(q)
        x, y, z = t[:3, 3]
        if 0.3 < x < 0.9 and abs(y) < 0.6 and z < 0.375 and oracle.min_distance(q) >= MARGIN + 2e-3:
            out.append(t)
    return np.stack(out)


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_answers_are_clear_by_coal(name: str) -> None:
    robot, oracle, _, _ = setup(name)
    targets = clear_targets(robot, oracle, 100, seed=1)
    got = robot.ik(targets, avoid_collisions=True, margin=MARGIN)
    plain = robot.ik(targets)
    assert isinstance(got, screwkit.IkBatchResult) and isinstance(plain, screwkit.IkBatchResult)
    solved, plain_colliding = 0, 0
    for k, t in enumerate(targets):
        if got.converged[k]:
            solved += 1
            q = got.q[k]
            np.testing.assert_allclose(oracle.fk(q), t, atol=1e-8)
            assert np.all(q >= robot.lower) and np.all(q <= robot.upper)
            d = oracle.min_distance(q)
            assert d >= MARGIN - 1e-6, f"target {k}: coal finds {d} m, margin {MARGIN}"
        else:
            assert got.stop[k] in ("in collision", "iteration limit", "restart limit")
        if plain.converged[k] and oracle.min_distance(plain.q[k]) < MARGIN:
            plain_colliding += 1
    assert solved >= 0.99 * len(targets), f"{solved} of {len(targets)}"
    assert plain_colliding >= 3, f"plain IK collided on {plain_colliding}"
    # One target alone equals its batch row (row k's restart seed is row_seed(0, k)).
    for k in (0, 1, 2):
        one = robot.ik(
            targets[k], avoid_collisions=True, margin=MARGIN, seed_rng=screwkit.row_seed(0, k)
        )
        np.testing.assert_array_equal(one.q, got.q[k])
        assert one.stop == got.stop[k]
    print(f"{name}: solved {solved} of {len(targets)}; plain IK collided on {plain_colliding}")


def test_the_command_line_answers_as_python(tmp_path: Path) -> None:
    """`screwkit ik --avoid-collisions --margin --srdf --obstacles` gives Python's answers, one
    target and a batch of JSON lines."""
    exe = os.environ.get("SCREWKIT_CLI")
    if not exe or not Path(exe).exists():
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    robot, oracle, urdf, srdf = setup("panda")
    targets = clear_targets(robot, oracle, 6, seed=2)
    py = robot.ik(targets, avoid_collisions=True, margin=MARGIN)
    first = robot.ik(targets[0], avoid_collisions=True, margin=MARGIN)
    assert isinstance(py, screwkit.IkBatchResult) and isinstance(first, screwkit.IkResult)
    base = [exe, "ik", str(urdf), "--package-path", str(SHARE), "--tip", "panda_hand"]
    base += ["--avoid-collisions", "--margin", str(MARGIN), "--srdf", str(srdf)]
    base += ["--obstacles", str(scene(tmp_path)), "--format", "json"]
    one = subprocess.run(
        [*base, "--target-matrix", ",".join(repr(float(x)) for x in targets[0].flatten())],
        capture_output=True,
        text=True,
    )
    assert one.returncode == 0, one.stderr
    np.testing.assert_array_equal(json.loads(one.stdout)["q"], first.q)
    lines = tmp_path / "targets.jsonl"
    lines.write_text("".join(json.dumps({"target": t.tolist()}) + "\n" for t in targets))
    out = subprocess.run([*base, "--input", str(lines)], capture_output=True, text=True)
    rows = [json.loads(x) for x in out.stdout.splitlines()]
    np.testing.assert_array_equal([r["q"] for r in rows], py.q)
    assert [r["stop"] for r in rows] == list(py.stop)
    # The scene without a mode that uses it: one line, non-zero.
    target = ",".join(repr(float(x)) for x in targets[0].flatten())
    plain = [exe, "ik", str(urdf), "--package-path", str(SHARE), "--tip", "panda_hand"]
    bad = subprocess.run(
        [*plain, "--obstacles", str(scene(tmp_path)), "--target-matrix", target],
        capture_output=True,
        text=True,
    )
    assert bad.returncode != 0 and "--avoid-collisions" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1


# A UR5 tool 0.24 m above the table top... and a straight line 0.4 m down through it.
PATH_SEED = np.array([0.0, -1.2, 1.6, -1.9, -1.57, 0.0])


def test_a_path_into_the_table_stops_before_contact_by_coal() -> None:
    """`cartesian_path(avoid_collisions=True, margin)`: the UR5's tool on a line down into the
    table stops with "collision", naming the pair; every sample keeps the margin by coal; the
    same path without the body goes on, and coal finds its first sample inside the margin
    just past where the checked path stopped (within one step), so the stop is not early."""
    robot, oracle, _, _ = setup("ur5")
    goal = robot.fk(PATH_SEED)
    goal[:3, 3] += [0.0, 0.0, -0.4]
    path = robot.cartesian_path(
        goal, PATH_SEED, interpolation="line", avoid_collisions=True, margin=MARGIN
    )
    assert path.stop == "collision", path.message
    assert "table" in path.message and 0.1 < path.fraction < 0.5
    for q in path.q:
        assert oracle.min_distance(q) >= MARGIN - 1e-6
    free = robot.cartesian_path(goal, PATH_SEED, interpolation="line")
    assert free.stop == "reached", free.message
    np.testing.assert_array_equal(free.q[: len(path.q)], path.q)
    inside = [k for k, q in enumerate(free.q) if oracle.min_distance(q) < MARGIN]
    assert inside and inside[0] == len(path.q), (inside[:3], len(path.q))
    # Margin 0: contact itself stops it, later on the same line.
    touching = robot.cartesian_path(goal, PATH_SEED, interpolation="line", avoid_collisions=True)
    assert touching.stop == "collision" and touching.fraction > path.fraction
    assert all(oracle.min_distance(q) >= -1e-6 for q in touching.q)
    # A seed in contact gives no path; the margin without the body is refused.
    low = robot.cartesian_path(
        goal, free.q[-1], interpolation="line", avoid_collisions=True, margin=MARGIN
    )
    assert low.stop == "collision" and low.fraction == 0.0 and len(low.q) == 1
    with pytest.raises(ValueError, match="margin"):
        robot.cartesian_path(goal, PATH_SEED, margin=MARGIN)


def test_paths_from_the_command_line_avoid_collisions(tmp_path: Path) -> None:
    """`screwkit path --avoid-collisions --margin --srdf --obstacles`, one path and JSON lines
    (`--input`, with a per-line error for a bad line) = Python's."""
    exe = os.environ.get("SCREWKIT_CLI")
    if not exe or not Path(exe).exists():
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    robot, _, urdf, srdf = setup("ur5")
    goal = robot.fk(PATH_SEED)
    goal[:3, 3] += [0.0, 0.0, -0.4]
    aside = robot.fk(PATH_SEED)
    aside[:3, 3] += [0.0, 0.1, 0.1]
    py = robot.cartesian_path(
        goal, PATH_SEED, interpolation="line", avoid_collisions=True, margin=MARGIN
    )

    def arg(x: npt.NDArray[np.float64]) -> str:
        return ",".join(repr(float(v)) for v in np.ravel(x))

    base = [exe, "path", str(urdf), "--package-path", str(SHARE), "--tip", "ee_link", "--line"]
    base += ["--avoid-collisions", "--margin", str(MARGIN), "--srdf", str(srdf)]
    base += ["--obstacles", str(scene(tmp_path)), "--format", "json"]
    one = subprocess.run(
        [*base, "--from", arg(PATH_SEED), "--to", arg(goal)], capture_output=True, text=True
    )
    assert one.returncode == 0, one.stderr
    report = json.loads(one.stdout)
    np.testing.assert_array_equal(report["q"], py.q)
    assert (report["stop"], report["message"]) == ("collision", py.message)
    lines = tmp_path / "paths.jsonl"
    rows = [
        {"from": PATH_SEED.tolist(), "to": goal.ravel().tolist()},
        {"from": PATH_SEED.tolist(), "via": [aside.ravel().tolist()], "to": goal.ravel().tolist()},
        {"from": PATH_SEED.tolist(), "to": [1, 2, 3]},
    ]
    lines.write_text("".join(json.dumps(r) + "\n" for r in rows))
    out = subprocess.run([*base, "--input", str(lines)], capture_output=True, text=True)
    assert out.returncode != 0 and "1 line(s) failed" in out.stderr
    got = [json.loads(x) for x in out.stdout.splitlines()]
    np.testing.assert_array_equal(got[0]["q"], py.q)
    via = robot.cartesian_path(
        np.stack([aside, goal]),
        PATH_SEED,
        interpolation="line",
        avoid_collisions=True,
        margin=MARGIN,
    )
    np.testing.assert_array_equal(got[1]["q"], via.q)
    assert got[1]["stop"] == via.stop == "collision"
    assert got[2]["line"] == 3 and "to" in got[2]["error"]


def test_bad_requests_are_refused(tmp_path: Path) -> None:
    robot, _, urdf, _ = setup("panda")
    t = robot.fk(np.zeros(robot.dof))
    for m in (-0.1, float("nan"), 1e9):
        with pytest.raises(ValueError, match="margin"):
            robot.ik(t, avoid_collisions=True, margin=m)
    with pytest.raises(ValueError, match="margin applies"):
        robot.ik(t, margin=0.1)
    # A robot without a body has nothing to keep apart: said, not a silent "clear".
    bare = screwkit.Robot.from_urdf(urdf, "panda_link0", "panda_hand", geometry="none")
    with pytest.raises(ValueError, match="no pair of shapes"):
        bare.ik(t, avoid_collisions=True)


# Whole-body differential IK with `CollisionAvoidance`: TALOS (collision meshes, exact) beside a
# table, its right arm driven under the table top and across its own torso. Checked by coal on
# every step: the constrained pairs never come closer than the margin.
TALOS_TABLE = ((0.4, 1.0, 0.05), (0.45, 0.0, -0.25))
TALOS_OTHERS = ["table", "torso_1_link", "torso_2_link", "base_link"]
TALOS_MARGIN = 0.005


def talos(
    meshes: str = "exact",
) -> tuple[screwkit.Robot, npt.NDArray[np.float64], list[tuple[str, str]], Any]:
    """TALOS with a table (its meshes read as `meshes` says), its start (arms forward,
    clear), the constrained pairs (the right arm's links against the table, the torso and the
    base) and coal's model of those pairs (exact meshes: a hull holds its mesh, so coal's
    distance is at least screwkit's on hulls)."""
    from test_body import ROBOTS, Coal

    urdf = ROBOTS / "talos_data/robots/talos_reduced.urdf"
    srdf = ROBOTS / "talos_data/srdf/talos.srdf"
    if not urdf.exists():
        pytest.skip("example-robot-data (pip install example-robot-data) is a test dependency")
    robot = screwkit.Robot.from_urdf(
        urdf, package_paths=[SHARE], meshes="convex" if meshes == "convex" else "exact"
    )
    size, centre = TALOS_TABLE
    pose = np.eye(4)
    pose[:3, 3] = centre
    robot.add_obstacle("table", screwkit.Box(size), pose)
    arm = sorted({a for p in robot.collision_pairs for a in p if "right" in a and "leg" not in a})
    checked = {(min(p), max(p)) for p in robot.collision_pairs}
    pairs: list[tuple[str, str]] = sorted(
        {(min(a, b), max(a, b)) for a in arm for b in TALOS_OTHERS} & checked
    )
    q0 = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
    for name, value in [
        ("arm_left_2_joint", 0.4),
        ("arm_right_2_joint", -0.4),
        ("arm_left_4_joint", -1.2),
        ("arm_right_4_joint", -1.2),
    ]:
        q0[robot.q_names.index(name)] = value
    c = Coal(urdf, srdf, robot)
    box = pin.GeometryObject("table", 0, pin.SE3(np.eye(3), np.array(centre)), coal.Box(*size))
    box.parentFrame = 0
    c.cmodel.addGeometryObject(box)
    c.cmodel.removeAllCollisionPairs()
    owner = ["table" if g == c.cmodel.ngeoms - 1 else c.link(g) for g in range(c.cmodel.ngeoms)]
    wanted = set(pairs)
    for i in range(c.cmodel.ngeoms):
        for j in range(i + 1, c.cmodel.ngeoms):
            if tuple(sorted((owner[i], owner[j]))) in wanted:
                c.cmodel.addCollisionPair(pin.CollisionPair(i, j))
    c.cdata = pin.GeometryData(c.cmodel)
    for r in c.cdata.distanceRequests:
        r.gjk_tolerance = 1e-12
    return robot, q0, pairs, c


def coal_min(c: Any, q: npt.NDArray[np.float64]) -> float:
    return float(min(c.distances(q).values()))


@pytest.mark.parametrize(
    ("goal", "meshes"),
    [
        ((0.45, -0.2, -0.45), "exact"),
        ((0.0, 0.1, 0.0), "exact"),
        ((0.45, -0.2, -0.45), "convex"),
    ],
    ids=["under the table", "into the torso", "under the table, hulls"],
)
def test_whole_body_steps_keep_the_margin(goal: tuple[float, float, float], meshes: str) -> None:
    """Every `ik_step` with `CollisionAvoidance` ends at least the margin from contact (coal,
    every step, 1e-6 m), the hand still moves towards its goal (it stops short, not frozen),
    and the velocity changes smoothly where the limit becomes active (the step-to-step change
    of v stays below the velocity's own size; with hulls, whose faces lie flat on the table,
    it settles: the contact patch's rows, not the witness alone)."""
    robot, q0, pairs, c = talos(meshes)
    hand = "gripper_right_base_link"
    target = np.eye(4)
    target[:3, :3] = robot.fk(q0, hand)[:3, :3]
    target[:3, 3] = goal
    tasks = robot.task_set(
        [
            screwkit.FrameTask(hand, target, gain=0.05, orientation_weight=0.0),
            screwkit.PostureTask(q0, weight=1e-2),
            screwkit.DampingTask(0.3),
        ]
    )
    avoid = [screwkit.CollisionAvoidance(pairs, margin=TALOS_MARGIN, detection_distance=0.05)]
    assert coal_min(c, q0) > TALOS_MARGIN
    q, vs, closest = q0.copy(), [], np.inf
    start = np.linalg.norm(robot.fk(q0, hand)[:3, 3] - goal)
    # On hulls, long enough for the gripper to ride on the table top a while.
    for _ in range(400 if meshes == "convex" else 150):
        v = robot.ik_step(q, tasks, 0.01, limits=avoid)
        q = robot.integrate(q, v, 0.01)
        vs.append(v)
        d = coal_min(c, q)
        closest = min(closest, d)
        assert d >= TALOS_MARGIN - 1e-6, f"coal finds {d} m, margin {TALOS_MARGIN}"
    # The limit was active (the goal is inside an obstacle) and the hand got closer.
    assert closest < TALOS_MARGIN + 1e-3
    assert np.linalg.norm(robot.fk(q, hand)[:3, 3] - goal) < start
    v = np.array(vs)
    change = np.linalg.norm(np.diff(v[10:], axis=0), axis=1)
    print(
        f"closest {closest:.6f} m; ‖Δv‖ max {change.max():.3g}, p99"
        f" {np.percentile(change, 99):.3g}; ‖v‖ max {np.linalg.norm(v, axis=1).max():.3g}"
    )
    assert change.max() < np.linalg.norm(v, axis=1).max()
    if meshes == "convex":
        # Riding on the table top: no step-to-step alternation (with a row on GJK's witness
        # alone, the 99th percentile here was 0.17 rad/s, 5 % of the peak speed; 0.6 rad/s in
        # the benchmark's run).
        assert np.percentile(change, 99) < 0.03 * np.linalg.norm(v, axis=1).max()


def test_the_step_qp_with_its_rows_is_the_problem_solved() -> None:
    """`ik_step_qp(…, with_rows=True)` near the table: (H, c, lower, upper, G, h), and the step
    `ik_step` takes satisfies that problem's optimality conditions (KKT, checked by scipy's
    non-negative least squares on the active constraints' multipliers): feasible within 1e-9,
    stationary within 1e-7 of the gradient's size. Without with_rows, such a step raises."""
    from scipy.optimize import nnls  # type: ignore[import-untyped]  # (with toppra)

    robot, q0, pairs, _ = talos("convex")
    hand = "gripper_right_base_link"
    target = np.eye(4)
    target[:3, :3] = robot.fk(q0, hand)[:3, :3]
    target[:3, 3] = (0.45, -0.2, -0.45)
    tasks = robot.task_set(
        [
            screwkit.FrameTask(hand, target, gain=0.05, orientation_weight=0.0),
            screwkit.PostureTask(q0, weight=1e-2),
            screwkit.DampingTask(0.3),
        ]
    )
    avoid = [screwkit.CollisionAvoidance(pairs, margin=TALOS_MARGIN, detection_distance=0.05)]
    q, dt, checked, binding = q0.copy(), 0.01, 0, 0
    for _ in range(120):
        v = robot.ik_step(q, tasks, dt, limits=avoid)
        h_, c_, lo, hi, g, h = robot.ik_step_qp(q, tasks, dt, limits=avoid, with_rows=True)
        assert g.shape == (len(h), len(c_))
        if len(h):
            with pytest.raises(ValueError, match="with_rows"):
                robot.ik_step_qp(q, tasks, dt, limits=avoid)
            x = v * dt
            assert np.all(x >= lo - 1e-9) and np.all(x <= hi + 1e-9)
            assert np.all(g @ x >= h - 1e-9)
            grad = h_ @ x + c_
            active = [g[k] for k in range(len(h)) if g[k] @ x - h[k] < 1e-9]
            binding += bool(active)
            eye = np.eye(len(x))
            active += [eye[i] for i in range(len(x)) if x[i] - lo[i] < 1e-12]
            active += [-eye[i] for i in range(len(x)) if hi[i] - x[i] < 1e-12]
            a = np.array(active).T if active else np.zeros((len(x), 0))
            if a.shape[1]:
                _, residual = nnls(a, grad)
            else:
                residual = float(np.linalg.norm(grad))
            assert residual <= 1e-7 * max(1.0, float(np.linalg.norm(grad))), residual
            checked += 1
        q = robot.integrate(q, v, dt)
    # Rows bound the step on some of them (without the rows, those would not be optimal).
    assert checked >= 20 and binding >= 5, (checked, binding)


def test_tasks_and_trajectories_keep_the_margin() -> None:
    """`ik_tasks` and `ik_trajectory` with `CollisionAvoidance`: every answer at least the
    margin from contact by coal, whether its goal is clear (converged) or under the table."""
    robot, q0, pairs, c = talos()
    hand = "gripper_right_base_link"
    avoid = [screwkit.CollisionAvoidance(pairs, margin=TALOS_MARGIN)]

    def goal(xyz: tuple[float, float, float]) -> list[screwkit.FrameTask]:
        t = np.eye(4)
        t[:3, :3] = robot.fk(q0, hand)[:3, :3]
        t[:3, 3] = xyz
        return [screwkit.FrameTask(hand, t, orientation_weight=0.0)]

    clear = robot.ik_tasks(goal((0.4, -0.35, 0.0)), q0, limits=avoid, restarts=2)
    assert clear.converged
    assert coal_min(c, clear.q) >= TALOS_MARGIN - 1e-6
    blocked = robot.ik_tasks(goal((0.45, -0.2, -0.45)), q0, limits=avoid, restarts=2)
    assert not blocked.converged
    assert coal_min(c, blocked.q) >= TALOS_MARGIN - 1e-6
    sets = [goal((0.4, -0.35, z)) for z in (0.0, -0.1, -0.2, -0.3)]
    for r in robot.ik_trajectory(sets, q0, limits=avoid, restarts=2):
        assert coal_min(c, r.q) >= TALOS_MARGIN - 1e-6


def test_collision_avoidance_refuses_bad_settings() -> None:
    robot, q0, _, _ = talos()
    for kw in ({"margin": -1.0}, {"detection_distance": 0.0}, {"gain": 1.5}, {"gain": 0.0}):
        with pytest.raises(ValueError):
            screwkit.CollisionAvoidance(**kw)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="no checked pair"):
        robot.ik_step(q0, [], 0.01, limits=[screwkit.CollisionAvoidance([("table", "nowhere")])])
    with pytest.raises(TypeError, match="CollisionAvoidance"):
        robot.ik_step(q0, [], 0.01, limits=[1])  # type: ignore[list-item]
    assert "margin=0.005" in repr(screwkit.CollisionAvoidance())


def test_tasks_from_the_command_line_avoid_collisions(tmp_path: Path) -> None:
    """`screwkit ik --tasks --avoid-collisions --margin --obstacles` answers as `ik_tasks` with
    `CollisionAvoidance(margin=…)` on every checked pair (the same q), clear by coal."""
    exe = os.environ.get("SCREWKIT_CLI")
    if not exe or not Path(exe).exists():
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    robot, q0, _, c = talos()
    hand = "gripper_right_base_link"
    target = np.eye(4)
    target[:3, :3] = robot.fk(q0, hand)[:3, :3]
    target[:3, 3] = (0.45, -0.2, -0.45)
    avoid = [screwkit.CollisionAvoidance(margin=TALOS_MARGIN)]
    py = robot.ik_tasks(
        [screwkit.FrameTask(hand, target, orientation_weight=0.0)], q0, limits=avoid, restarts=2
    )
    tasks = tmp_path / "tasks.json"
    spec = {"type": "frame", "frame": hand, "orientation_weight": 0}
    tasks.write_text(json.dumps({"tasks": [{**spec, "target": target.flatten().tolist()}]}))
    size, centre = TALOS_TABLE
    scene = tmp_path / "scene.json"
    table = {"name": "table", "shape": "box", "size": list(size), "xyz": list(centre)}
    scene.write_text(json.dumps({"obstacles": [table]}))
    from test_body import ROBOTS

    urdf = ROBOTS / "talos_data/robots/talos_reduced.urdf"
    out = subprocess.run(
        [exe, "ik", str(urdf), "--package-path", str(SHARE), "--tasks", str(tasks)]
        + ["--avoid-collisions", "--margin", str(TALOS_MARGIN), "--obstacles", str(scene)]
        + ["--seed", ",".join(repr(float(x)) for x in q0), "--restarts", "2"]
        + ["--format", "json"],
        capture_output=True,
        text=True,
    )
    got = json.loads(out.stdout)
    np.testing.assert_array_equal(got["q"], py.q)
    assert coal_min(c, py.q) >= TALOS_MARGIN - 1e-6


# Reachability maps clear of contact: the UR5 (analytic IK, every posture checked) beside the
# table and the box. A pose is reached exactly when one of its postures is clear by coal.
MAP_BOUNDS = (0.2, -0.6, 0.0, 0.9, 0.6, 0.5)


def test_reach_maps_count_only_clear_postures_by_coal(tmp_path: Path) -> None:
    robot, oracle, _, _ = setup("ur5")
    clear = screwkit.reach(robot, 0.1, 6, bounds=MAP_BOUNDS, avoid_collisions=True, margin=MARGIN)
    plain = screwkit.reach(robot, 0.1, 6, bounds=MAP_BOUNDS)
    assert clear.meta["solver"] == "analytic" and clear.meta["spec"]["collision_margin"] == MARGIN
    assert "body" in clear.meta and "body" not in plain.meta
    reached = ~np.isnan(plain.pose_manipulability)
    kept = ~np.isnan(clear.pose_manipulability)
    assert not np.any(kept & ~reached), "reached clear of contact but not at all"
    v, k = np.nonzero(reached)
    pick = np.random.default_rng(3).choice(len(v), size=min(300, len(v)), replace=False)
    targets = np.tile(np.eye(4), (len(pick), 1, 1))
    targets[:, :3, :3] = clear.orientations[k[pick]]
    targets[:, :3, 3] = clear.centres[v[pick]]
    lost = found = 0
    for i, postures in enumerate(robot.ik_all(targets)):
        d = np.array([oracle.min_distance(q) for q in postures])
        if d.size == 0 or np.any(np.abs(d - MARGIN) < 1e-5):
            continue  # at the margin: either verdict is right
        assert kept[v[pick[i]], k[pick[i]]] == bool(np.any(d >= MARGIN)), (
            f"pose {v[pick[i]]}, {k[pick[i]]}: coal finds {d}"
        )
        lost += int(np.all(d < MARGIN))
        found += int(np.any(d >= MARGIN))
    assert lost >= 20 and found >= 20, f"lost {lost}, found {found}"
    # The scene's obstacles given to the map equal the same obstacles added to the robot.
    bare = screwkit.Robot.from_urdf(files("ur5")[0], *TIPS["ur5"], package_paths=[SHARE])
    bare.srdf(files("ur5")[1])
    again = screwkit.reach(
        bare,
        0.1,
        6,
        bounds=MAP_BOUNDS,
        avoid_collisions=True,
        margin=MARGIN,
        obstacles=scene(tmp_path),
    )
    assert bare.obstacles == []
    np.testing.assert_array_equal(again.pose_manipulability, clear.pose_manipulability)
    assert again.meta == clear.meta
    with pytest.raises(ValueError, match="obstacles apply"):
        screwkit.reach(bare, 0.3, 2, obstacles=scene(tmp_path))
    with pytest.raises(ValueError, match="margin applies"):
        screwkit.reach(bare, 0.3, 2, margin=0.1)
    with pytest.raises(ValueError, match="margin"):
        screwkit.reach(bare, 0.3, 2, avoid_collisions=True, margin=-1.0)
    plain_robot = screwkit.Robot.from_urdf(files("ur5")[0], *TIPS["ur5"], geometry="none")
    with pytest.raises(ValueError, match="no pair of shapes"):
        screwkit.reach(plain_robot, 0.3, 2, avoid_collisions=True)


def test_reach_from_the_command_line_is_the_same_file(tmp_path: Path) -> None:
    """`screwkit reach --avoid-collisions --margin --srdf --obstacles` writes Python's map,
    byte for byte, and says how many poses only contact reached."""
    exe = os.environ.get("SCREWKIT_CLI")
    if not exe or not Path(exe).exists():
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    robot, _, urdf, srdf = setup("ur5")
    py = tmp_path / "py.npz"
    screwkit.reach(
        robot, 0.15, 4, bounds=MAP_BOUNDS, avoid_collisions=True, margin=MARGIN, path=str(py)
    )
    cli = tmp_path / "cli.npz"
    base, tip = TIPS["ur5"]
    args = [exe, "reach", str(urdf), "--package-path", str(SHARE), "--base", base, "--tip", tip]
    args += ["--resolution", "0.15", "--orientations", "4"]
    args += ["--bounds", ",".join(str(b) for b in MAP_BOUNDS)]
    args += ["--avoid-collisions", "--margin", str(MARGIN), "--srdf", str(srdf)]
    args += ["--obstacles", str(scene(tmp_path)), "-o", str(cli), "--format", "json"]
    out = subprocess.run(args, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert cli.read_bytes() == py.read_bytes()
    report = json.loads(out.stdout)
    plain = screwkit.reach(robot, 0.15, 4, bounds=MAP_BOUNDS)
    reached = int(np.sum(~np.isnan(plain.pose_manipulability)))
    assert report["lost_to_collisions"] == reached - report["reached"] > 0
    # The body's files without --avoid-collisions: one line, non-zero.
    bad = subprocess.run(
        [exe, "reach", str(urdf), "--obstacles", str(scene(tmp_path)), "-o", str(cli)],
        capture_output=True,
        text=True,
    )
    assert bad.returncode != 0 and "--avoid-collisions" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1


def test_the_page_shows_the_contacts_coal_finds() -> None:
    """Issue 49, item 1: `viewer(show_distances=True)` embeds, at the first pose and at each
    frame of a motion, the link pairs in collision and the pairs closer than 5 cm with their
    distances. Against coal (the UR5 beside the table and box, on the link pairs the body checks:
    `collision_pairs`, the SRDF's and adjacent links left out): the same pairs collide, every
    pair coal finds 0–5 cm apart is listed, and each listed distance is coal's for that pair of
    links (the least over their shapes) to 1e-6."""
    robot, oracle, _, _ = setup("ur5")
    rng = np.random.default_rng(11)
    lo, hi = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    frames = rng.uniform(lo, hi, size=(40, 6))
    page = robot.viewer(frames[3], motion=frames, show_distances=True)
    start = page.index('id="model">') + len('id="model">')
    contacts = json.loads(page[start : page.index("</script>", start)])["contacts"]
    assert contacts["within"] == 0.05
    assert len(contacts["frames"]) == len(frames)
    assert contacts["q"] == contacts["frames"][3]
    owner = [
        oracle.model.frames[g.parentFrame].name if g.parentFrame else g.name
        for g in oracle.cmodel.geometryObjects
    ]
    checked = {frozenset(p) for p in robot.collision_pairs}
    colliding_frames = 0
    for q, found in zip(frames, contacts["frames"], strict=True):
        pin.computeDistances(oracle.model, oracle.data, oracle.cmodel, oracle.cdata, oracle.q(q))
        pin.computeCollisions(
            oracle.model, oracle.data, oracle.cmodel, oracle.cdata, oracle.q(q), False
        )
        coal_pairs: dict[frozenset[str], float] = {}
        want: set[frozenset[str]] = set()
        results = zip(oracle.cdata.distanceResults, oracle.cdata.collisionResults, strict=True)
        for p, (r, c) in zip(oracle.cmodel.collisionPairs, results, strict=True):
            key = frozenset((owner[p.first], owner[p.second]))
            if key in checked:
                # (coal's distance of two meshes that cross is 0, not their depth.)
                coal_pairs[key] = min(coal_pairs.get(key, np.inf), float(r.min_distance))
                if c.isCollision():
                    want.add(key)
        got = {frozenset(p) for p in found["collisions"]}
        assert got == want, (q, got ^ want)
        colliding_frames += bool(got)
        listed = {frozenset(p["pair"]): p["distance"] for p in found["close"]}
        for pair, d in listed.items():
            if d >= 0:
                assert abs(d - coal_pairs[pair]) < 1e-6, (pair, d, coal_pairs[pair])
            else:
                assert coal_pairs[pair] <= 0 and pair in want, pair
        for pair, d in coal_pairs.items():
            if 1e-6 < d < 0.05 - 1e-6:
                assert pair in listed, (pair, d)
    assert 5 <= colliding_frames <= 35, colliding_frames

    # Without the option no contacts ride along; show_collisions alone lists no distances.
    def model(page: str) -> dict[str, Any]:
        start = page.index('id="model">') + len('id="model">')
        out: dict[str, Any] = json.loads(page[start : page.index("</script>", start)])
        return out

    assert "contacts" not in model(robot.viewer(frames[0]))
    only = model(robot.viewer(frames[0], show_collisions=True))["contacts"]
    assert only["within"] is None and "close" not in only["q"]
    assert only["q"]["collisions"] == contacts["frames"][0]["collisions"]


def test_the_command_line_page_shows_the_same_contacts(tmp_path: Path) -> None:
    """`screwkit view --srdf --obstacles --show-distances --motion` writes Python's page byte for
    byte."""
    exe = os.environ.get("SCREWKIT_CLI")
    if not exe:
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    robot, _, urdf, srdf = setup("ur5")
    frames = np.random.default_rng(5).uniform(-2.0, 2.0, size=(12, 6))
    motion = tmp_path / "motion.npy"
    np.save(motion, frames)
    out = tmp_path / "page.html"
    base, tip = TIPS["ur5"]
    args = [exe, "view", str(urdf), "--base", base, "--tip", tip, "--package-path", str(SHARE)]
    args += ["--srdf", str(srdf), "--obstacles", str(scene(tmp_path)), "--show-distances"]
    args += ["--motion", str(motion), "-o", str(out)]
    done = subprocess.run(args, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert out.read_text() == robot.viewer(motion=frames, show_distances=True)
