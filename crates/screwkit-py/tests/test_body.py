"""The robot's body against coal (Pinocchio's `GeometryModel`, `computeCollisions`,
`computeDistances`) on the Panda and the UR5 as example-robot-data 6.0.0 ships them (collision
meshes and SRDFs): the same pairs checked, the same colliding pairs on random configurations
away from contact, the same distances to 1e-6 relative; and the Python API's shapes, obstacles,
SRDF reading and generation."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

from conftest import ASSETS

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin) is a test dependency")

SHARE = (
    Path(sys.prefix)
    / "lib"
    / f"python{sys.version_info.major}.{sys.version_info.minor}"
    / "site-packages"
    / "cmeel.prefix"
    / "share"
)
ROBOTS = SHARE / "example-robot-data" / "robots"
CASES = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_description/srdf/panda.srdf", []),
    # ee_link is welded to wrist_3_link, which wrist_2's joint moves: adjacent bodies, never
    # checked here (MuJoCo's parent-child rule), checked by coal.
    "ur5": (
        "ur_description/urdf/ur5_robot.urdf",
        "ur_description/srdf/ur5.srdf",
        [("ee_link", "wrist_2_link")],
    ),
}


def files(name: str) -> tuple[Path, Path, list[tuple[str, str]]]:
    urdf, srdf, coal_only = CASES[name]
    if not (ROBOTS / urdf).exists():
        pytest.skip("example-robot-data (pip install example-robot-data) is a test dependency")
    return ROBOTS / urdf, ROBOTS / srdf, coal_only


class Coal:
    """Pinocchio's models of the file, every pair added and the SRDF's removed."""

    def __init__(self, urdf: Path, srdf: Path, robot: screwkit.Robot) -> None:
        self.model, self.cmodel, _ = pin.buildModelsFromUrdf(str(urdf), package_dirs=[str(SHARE)])
        self.cmodel.addAllCollisionPairs()
        pin.removeCollisionPairs(self.model, self.cmodel, str(srdf))
        self.data = self.model.createData()
        self.cdata = pin.GeometryData(self.cmodel)
        self.robot = robot
        self.mimic = {j["name"]: j["mimic"] for j in robot.info()["joints"] if j["mimic"]}

    def link(self, g: int) -> str:
        return str(self.model.frames[self.cmodel.geometryObjects[g].parentFrame].name)

    def pair(self, k: int) -> tuple[str, str]:
        p = self.cmodel.collisionPairs[k]
        a, b = sorted((self.link(p.first), self.link(p.second)))
        return a, b

    def q(self, ours: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Pinocchio's q of ours: each joint by name, a mimic joint by its rule."""
        names = self.robot.q_names
        q = np.zeros(self.model.nq)
        for j in range(1, self.model.njoints):
            name = self.model.names[j]
            if name in names:
                q[self.model.joints[j].idx_q] = ours[names.index(name)]
            else:
                m = self.mimic[name]
                lead = ours[names.index(m["leader"])]
                q[self.model.joints[j].idx_q] = m["multiplier"] * lead + m["offset"]
        return q

    def distances(self, q: npt.NDArray[np.float64]) -> dict[tuple[str, str], float]:
        pin.computeDistances(self.model, self.data, self.cmodel, self.cdata, self.q(q))
        out: dict[tuple[str, str], float] = {}
        for k in range(len(self.cmodel.collisionPairs)):
            d = self.cdata.distanceResults[k].min_distance
            out[self.pair(k)] = min(out.get(self.pair(k), np.inf), d)
        return out

    def colliding(self, q: npt.NDArray[np.float64]) -> set[tuple[str, str]]:
        pin.computeCollisions(self.model, self.data, self.cmodel, self.cdata, self.q(q), False)
        return {
            self.pair(k)
            for k in range(len(self.cmodel.collisionPairs))
            if self.cdata.collisionResults[k].isCollision()
        }


def by_link(
    pairs: list[tuple[str, str]], values: npt.NDArray[np.float64]
) -> dict[tuple[str, str], float]:
    out: dict[tuple[str, str], float] = {}
    for (a, b), d in zip(pairs, values, strict=True):
        key = (min(a, b), max(a, b))
        out[key] = min(out.get(key, np.inf), float(d))
    return out


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_the_body_equals_coal(name: str) -> None:
    urdf, srdf, coal_only = files(name)
    robot = screwkit.Robot.from_urdf(urdf, package_paths=[SHARE])
    robot.srdf(srdf)
    coal = Coal(urdf, srdf, robot)
    ours = {(min(a, b), max(a, b)) for a, b in robot.collision_pairs}
    theirs = {coal.pair(k) for k in range(len(coal.cmodel.collisionPairs))}
    assert sorted(theirs - ours) == coal_only and not ours - theirs
    rng = np.random.default_rng(3)
    lo, hi = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    compared = colliding_configurations = 0
    for _ in range(600):
        q = rng.uniform(lo, hi)
        d_coal = coal.distances(q)
        d_ours = by_link(*(lambda d: (d.pairs, d.distance))(robot.distances(q)))
        for key, d in d_coal.items():
            if key in ours and d > 1e-3:
                assert d_ours[key] == pytest.approx(d, rel=1e-6, abs=1e-9), (key, q)
                compared += 1
        # Colliding pairs, away from contact (no checked pair within 1e-4 of touching).
        if all(abs(d) > 1e-4 for k, d in d_coal.items() if k in ours):
            hit = {(min(a, b), max(a, b)) for a, b in robot.collisions(q)}
            assert hit == coal.colliding(q) & ours, q
            assert robot.in_collision(q) == bool(hit)
            colliding_configurations += bool(hit)
    assert compared > 2000
    assert colliding_configurations >= 3


def test_batches_and_minimum() -> None:
    urdf, srdf, _ = files("panda")
    robot = screwkit.Robot.from_urdf(urdf, package_paths=[SHARE])
    robot.srdf(srdf)
    rng = np.random.default_rng(5)
    qs = rng.uniform(
        np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi), (64, robot.nq)
    )
    hits = robot.in_collision(qs)
    mins = robot.min_distance(qs)
    pairs = robot.collisions(qs)
    all_d = robot.distances(qs)
    assert len(pairs) == len(all_d) == 64
    assert hits.dtype == np.bool_ and hits.shape == (64,) and mins.shape == (64,)
    for k in range(0, 64, 7):
        assert hits[k] == robot.in_collision(qs[k])
        d = robot.distances(qs[k])
        assert mins[k] == pytest.approx(d.distance.min(), abs=1e-12)
        assert mins[k] == robot.min_distance(qs[k])
        assert pairs[k] == robot.collisions(qs[k])
        np.testing.assert_array_equal(all_d[k].distance, d.distance)
        np.testing.assert_array_equal(all_d[k].points, d.points)
        assert d.points.shape == (len(d), 2, 3) and d.normal.shape == (len(d), 3)
        # The witness points are as far apart as the distance says (mesh against mesh, and a
        # mesh against the fingers' boxes: both by exact closest-feature formulas), along the
        # normal.
        sep = d.distance > 1e-6
        gap = d.points[sep, 1] - d.points[sep, 0]
        np.testing.assert_allclose(np.linalg.norm(gap, axis=1), d.distance[sep], rtol=1e-12)
        cos = np.einsum("ij,ij->i", gap, d.normal[sep]) / np.linalg.norm(gap, axis=1)
        np.testing.assert_allclose(cos, 1.0, atol=1e-9)
    assert hits.any() and not hits.all()


def test_obstacles_srdf_and_errors(tmp_path: Path) -> None:
    urdf, srdf, _ = files("panda")
    robot = screwkit.Robot.from_urdf(urdf, package_paths=[SHARE])
    q = np.zeros(robot.nq)
    q[3] = -1.5
    pairs = len(robot.collision_pairs)
    table = np.eye(4)
    table[2, 3] = 0.2
    robot.add_obstacle("table", screwkit.Box((1.0, 1.0, 0.05)), table)
    assert robot.obstacles == ["table"]
    assert len(robot.collision_pairs) > pairs
    assert any("table" in p for p in robot.collisions(q))
    table[2, 3] = -0.5
    robot.add_obstacle("table", screwkit.Box((1.0, 1.0, 0.05)), table)
    assert not any("table" in p for p in robot.collisions(q))
    assert robot.remove_obstacle("table") and not robot.remove_obstacle("table")
    assert len(robot.collision_pairs) == pairs
    with pytest.raises(ValueError, match="radius"):
        screwkit.Sphere(-1.0)
    with pytest.raises(ValueError, match="pose"):
        robot.add_obstacle("x", screwkit.Sphere(0.1), np.ones((4, 4)))
    # The SRDF: applied, generated deterministically, a link the robot lacks named.
    robot.srdf(srdf)
    text = robot.write_srdf(tmp_path / "panda.srdf", samples=300, seed=1)
    assert text == robot.write_srdf(samples=300, seed=1)
    assert (tmp_path / "panda.srdf").read_text() == text
    assert 'link1="panda_link0" link2="panda_link1" reason="Adjacent"' in text
    bad = tmp_path / "bad.srdf"
    bad.write_text(
        '<robot name="p"><disable_collisions link1="panda_link0" link2="ghost"/></robot>'
    )
    with pytest.raises(ValueError, match='"ghost"'):
        robot.srdf(bad)
    with pytest.raises(ValueError, match="q: expected"):
        robot.in_collision(np.zeros(3))
    # A frame added (a new tree) and the SRDF applied (a new model): the kept scratch follows.
    before = (robot.in_collision(q), robot.min_distance(q))
    robot.add_frame("tcp", "panda_hand", np.eye(4))
    assert (robot.in_collision(q), robot.min_distance(q)) == before
    # A robot without collision shapes: nothing to hit.
    ur5 = screwkit.Robot.from_urdf(ASSETS / "ur5.urdf")
    assert ur5.collision_pairs == [] and ur5.in_collision(np.zeros(6)) is False
    assert ur5.min_distance(np.zeros(6)) == np.inf


@pytest.mark.parametrize(
    ("scene", "message"),
    [
        ('{"obstacles": [{"name": "a", "shape": "cone", "radius": 1}]}', 'shape "cone"'),
        ('{"obstacles": [{"name": "a", "shape": "box", "radius": 1}]}', 'a box takes no "radius"'),
        ('{"obstacles": [{"name": "a", "shape": "sphere"}]}', 'a sphere needs "radius"'),
        ('{"obstacles": [{"name": "a", "shape": "sphere", "radius": -1}]}', "radius -1"),
        ('{"obstacles": [{"name": "a", "shape": "sphere", "radius": 1, "colour": 1}]}', "colour"),
        (
            '{"obstacles": [{"name": "a", "shape": "sphere", "radius": 1},'
            ' {"name": "a", "shape": "sphere", "radius": 2}]}',
            'obstacle 1 \\("a"\\): the name is given twice',
        ),
        (
            '{"obstacles": [{"name": "a", "shape": "sphere", "radius": 1, "xyz": [0, 0, 0],'
            ' "pose": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}]}',
            "not both",
        ),
        (
            '{"obstacles": [{"name": "a", "shape": "sphere", "radius": 1,'
            ' "pose": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}]}',
            "pose",
        ),
        ('{"obstacles": [{"name": "m", "shape": "mesh", "path": "none.stl"}]}', "none.stl"),
        ('{"obstacles": [}', "line 1 column"),
    ],
)
def test_a_bad_scene_names_the_file_and_obstacle(tmp_path: Path, scene: str, message: str) -> None:
    robot = screwkit.Robot.from_urdf(ASSETS / "humanoid.urdf")
    path = tmp_path / "scene.json"
    path.write_text(scene)
    with pytest.raises((ValueError, OSError), match=message):
        robot.add_obstacles(path)
    # Nothing half-added.
    assert robot.obstacles == []
