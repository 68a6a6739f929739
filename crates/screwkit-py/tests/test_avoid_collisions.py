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
