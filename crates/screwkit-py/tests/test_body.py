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
    # Links joined by one movable joint through the grippers' mimic joints: adjacent bodies,
    # not checked here, checked by coal.
    "talos": (
        "talos_data/robots/talos_reduced.urdf",
        "talos_data/srdf/talos.srdf",
        sorted(
            [
                (f"gripper_{s}_{a}_link", f"gripper_{s}_motor_double_link")
                for s in ("left", "right")
                for a in ("fingertip_3", "inner_single")
            ]
        ),
    ),
}
SAMPLES = {"panda": 600, "ur5": 600, "talos": 12}


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
        # coal's GJK at 1e-12 (its default 1e-6 leaves 2e-6 relative on TALOS's cylinders).
        for r in self.cdata.distanceRequests:
            r.gjk_tolerance = 1e-12
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


@pytest.mark.parametrize("name", ["panda", "ur5", "talos"])
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
    compared = colliding_pairs = 0
    for _ in range(SAMPLES[name]):
        q = rng.uniform(lo, hi)
        d_coal = coal.distances(q)
        d_ours = by_link(*(lambda d: (d.pairs, d.distance))(robot.distances(q)))
        for key, d in d_coal.items():
            if key in ours and d > 1e-3:
                assert d_ours[key] == pytest.approx(d, rel=1e-6, abs=1e-9), (key, q)
                compared += 1
        # Colliding pairs, each away from contact (coal's distance beyond 1e-4 of touching).
        hit = {(min(a, b), max(a, b)) for a, b in robot.collisions(q)}
        theirs_hit = coal.colliding(q) & ours
        clear = {k for k, d in d_coal.items() if k in ours and abs(d) > 1e-4}
        assert hit & clear == theirs_hit & clear, q
        colliding_pairs += len(hit & clear)
        if clear == ours:
            assert robot.in_collision(q) == bool(hit)
    assert compared > 2000
    assert colliding_pairs >= 3


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
        (
            '{"obstacles": [{"name": "far", "shape": "sphere", "radius": 1,'
            ' "xyz": [1e300, 0, 0]}]}',
            "not within 1000000 m",
        ),
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


def _coal_shape(kind: str, dims: tuple[float, ...]) -> object:
    coal = pytest.importorskip("coal", reason="coal (pip install coal) is a test dependency")

    if kind == "box":
        return coal.Box(*dims)
    if kind == "sphere":
        return coal.Sphere(dims[0])
    if kind == "capsule":
        return coal.Capsule(dims[0], dims[1])
    return coal.Cylinder(dims[0], dims[1])


def _our_shape(
    kind: str, dims: tuple[float, ...]
) -> screwkit.Box | screwkit.Sphere | screwkit.Capsule | screwkit.Cylinder:
    if kind == "box":
        return screwkit.Box(dims)
    if kind == "sphere":
        return screwkit.Sphere(dims[0])
    if kind == "capsule":
        return screwkit.Capsule(dims[0], dims[1])
    return screwkit.Cylinder(dims[0], dims[1])


def _urdf_geometry(kind: str, dims: tuple[float, ...]) -> str:
    if kind == "box":
        return f'<box size="{dims[0]} {dims[1]} {dims[2]}"/>'
    if kind == "sphere":
        return f'<sphere radius="{dims[0]}"/>'
    return f'<{kind} radius="{dims[0]}" length="{dims[1]}"/>'


SHAPES: dict[str, tuple[float, ...]] = {
    "box": (0.3, 0.2, 0.1),
    "sphere": (0.12,),
    "capsule": (0.08, 0.3),
    "cylinder": (0.1, 0.25),
}


def _mujoco_geom(kind: str, dims: tuple[float, ...], pose: npt.NDArray[np.float64]) -> str:
    mujoco = pytest.importorskip("mujoco", reason="MuJoCo (pip install mujoco) is a test tool")

    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, pose[:3, :3].flatten())
    if kind == "box":
        size = " ".join(str(d / 2) for d in dims)
    elif kind == "sphere":
        size = str(dims[0])
    else:
        size = f"{dims[0]} {dims[1] / 2}"
    pos, q = " ".join(map(str, pose[:3, 3])), " ".join(map(str, quat))
    return f'<geom type="{kind}" size="{size}" pos="{pos}" quat="{q}"/>'


@pytest.mark.parametrize("link_shape", list(SHAPES))
@pytest.mark.parametrize("obstacle_shape", list(SHAPES))
def test_primitive_pairs_as_coal_and_mujoco(
    tmp_path: Path, link_shape: str, obstacle_shape: str
) -> None:
    """Every primitive against every other at random poses, apart and overlapping: the signed
    distance equals coal's and MuJoCo's (`mj_geomDistance`), both at GJK/EPA tolerance 1e-12,
    and collision agrees. Where an oracle measures something else it is not asked: coal's
    penetration of a cylinder differs from screwkit's and MuJoCo's (which agree to 1e-10; coal
    fails outright on some cylinder pairs), and MuJoCo's box–capsule routine reports a contact
    depth, not the penetration (screwkit's equals coal's)."""
    coal = pytest.importorskip("coal", reason="coal (pip install coal) is a test dependency")

    mujoco = pytest.importorskip("mujoco", reason="MuJoCo (pip install mujoco) is a test tool")
    dims = SHAPES[link_shape]
    urdf = tmp_path / "one.urdf"
    urdf.write_text(
        f"""<robot name="one"><link name="world"/><link name="a"><collision><origin xyz="0.1 0 0"
        rpy="0.3 0.2 0.1"/><geometry>{_urdf_geometry(link_shape, dims)}</geometry></collision>
        </link><link name="b"/><joint name="j" type="revolute"><parent link="world"/>
        <child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
        </joint><joint name="f" type="fixed"><parent link="world"/><child link="a"/></joint>
        </robot>"""
    )
    robot = screwkit.Robot.from_urdf(urdf)
    link_pose = np.eye(4)
    link_pose[:3, :3] = _rpy(0.3, 0.2, 0.1)
    link_pose[:3, 3] = [0.1, 0.0, 0.0]
    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-12
    request.epa_tolerance = 1e-12
    request.enable_signed_distance = True
    rng = np.random.default_rng(3)
    odims = SHAPES[obstacle_shape]
    pair = {link_shape, obstacle_shape}
    signs = set()
    for _ in range(100):
        pose = np.eye(4)
        pose[:3, :3] = _rpy(*rng.uniform(-np.pi, np.pi, 3))
        pose[:3, 3] = rng.uniform(-0.45, 0.45, 3) + [0.1, 0.0, 0.0]
        robot.add_obstacle("o", _our_shape(obstacle_shape, odims), pose)
        ours = float(robot.distances(np.zeros(1)).distance[0])
        with_coal = coal.distance(
            _coal_shape(link_shape, dims),
            coal.Transform3s(link_pose[:3, :3], link_pose[:3, 3]),
            _coal_shape(obstacle_shape, odims),
            coal.Transform3s(pose[:3, :3], pose[:3, 3]),
            request,
            coal.DistanceResult(),
        )
        m = mujoco.MjModel.from_xml_string(
            "<mujoco><option ccd_tolerance='1e-13' ccd_iterations='10000'/><worldbody>"
            + _mujoco_geom(link_shape, dims, link_pose)
            + _mujoco_geom(obstacle_shape, odims, pose)
            + "</worldbody></mujoco>"
        )
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        with_mujoco = mujoco.mj_geomDistance(m, d, 0, 1, 10.0, None)
        apart = with_mujoco > 0
        if apart or "cylinder" not in pair:
            assert abs(ours - with_coal) < 1e-8, ("coal", pose, ours, with_coal)
        if apart or pair != {"box", "capsule"}:
            assert abs(ours - with_mujoco) < 1e-9, ("mujoco", pose, ours, with_mujoco)
        if abs(with_mujoco) > 1e-9:
            assert robot.in_collision(np.zeros(1)) == (not apart)
        signs.add(apart)
    assert signs == {True, False}, "apart and overlapping both seen"


def _rpy(r: float, p: float, y: float) -> npt.NDArray[np.float64]:
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return np.asarray(rz @ ry @ rx, dtype=np.float64)


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_distance_jacobians_are_pinocchios_point_jacobians(name: str) -> None:
    """Each row of `distances(q, jacobians=True).jacobian` is n · (J_b(p_b) − J_a(p_a)), the
    velocity of the witness points along the normal, with each point's Jacobian from
    Pinocchio's (the link frame's LOCAL_WORLD_ALIGNED Jacobian moved to the point; a mimic
    finger's columns summed into its leader's with the multiplier)."""
    urdf, srdf, _ = files(name)
    robot = screwkit.Robot.from_urdf(urdf, package_paths=[SHARE])
    robot.srdf(srdf)
    c = Coal(urdf, srdf, robot)
    names = robot.q_names
    # Pinocchio's velocity columns onto ours.
    fold = np.zeros((c.model.nv, len(names)))
    for j in range(1, c.model.njoints):
        jn = c.model.names[j]
        col = c.model.joints[j].idx_v
        if jn in names:
            fold[col, names.index(jn)] = 1.0
        else:
            m = c.mimic[jn]
            fold[col, names.index(m["leader"])] = m["multiplier"]
    rng = np.random.default_rng(4)
    lo, hi = np.maximum(robot.lower, -2.5), np.minimum(robot.upper, 2.5)
    for _ in range(5):
        q = rng.uniform(lo, hi)
        d = robot.distances(q, jacobians=True)
        assert d.jacobian is not None and d.jacobian.shape == (len(d), len(names))
        qp = c.q(q)
        pin.computeJointJacobians(c.model, c.data, qp)
        pin.updateFramePlacements(c.model, c.data)

        def point_jacobian(link: str, p: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
            f = c.model.getFrameId(link)
            j = pin.getFrameJacobian(c.model, c.data, f, pin.LOCAL_WORLD_ALIGNED)
            o = c.data.oMf[f].translation
            # v_p = v_o + omega x (p - o) = v_o - [p - o]x omega
            r = p - o
            skew = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
            return np.asarray((j[:3] - skew @ j[3:]) @ fold)

        for k, (a, b) in enumerate(d.pairs):
            n = d.normal[k]
            expected = n @ (point_jacobian(b, d.points[k, 1]) - point_jacobian(a, d.points[k, 0]))
            np.testing.assert_allclose(d.jacobian[k], expected, atol=1e-12, err_msg=str((a, b)))
    batch = robot.distances(np.stack([q, q]), jacobians=True)
    np.testing.assert_array_equal(batch[1].jacobian, d.jacobian)
    assert robot.distances(q).jacobian is None


def test_a_pickled_robot_keeps_its_body() -> None:
    """Pickling keeps the body's state: the SRDF's disabled pairs and the obstacles added (a
    mesh's path included), so a copy (a Ray worker's) answers as the original."""
    import pickle

    urdf, srdf, _ = files("panda")
    robot = screwkit.Robot.from_urdf(urdf, package_paths=[SHARE])
    robot.srdf(srdf)
    table = np.eye(4)
    table[:3, 3] = [0.5, 0.0, 0.2]
    robot.add_obstacle("table", screwkit.Box((0.6, 1.0, 0.04)), table)
    robot.add_obstacle("ball", screwkit.Sphere(0.1), np.eye(4) + np.diag([0, 0, 0, 0]))
    stl = next((ROBOTS / "panda_description" / "meshes").rglob("*.stl"))
    turned = np.eye(4)
    turned[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    turned[:3, 3] = [0.3, 0.4, 0.5]
    robot.add_obstacle("part", screwkit.Mesh(stl, (1.0, 1.0, 2.0)), turned)
    copy = pickle.loads(pickle.dumps(robot))
    assert copy.obstacles == robot.obstacles == ["table", "ball", "part"]
    assert copy.collision_pairs == robot.collision_pairs
    rng = np.random.default_rng(2)
    qs = rng.uniform(np.maximum(robot.lower, -2.0), np.minimum(robot.upper, 2.0), (20, robot.nq))
    np.testing.assert_array_equal(copy.min_distance(qs), robot.min_distance(qs))
    assert copy.collisions(qs) == robot.collisions(qs)
    # A robot whose body was never asked for pickles without one.
    plain = screwkit.Robot.from_urdf(urdf, package_paths=[SHARE])
    assert pickle.loads(pickle.dumps(plain)).obstacles == []


def flagged(
    robot: screwkit.Robot, target: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """`ik_all(target, collisions="flag")` of one target: (q, collides)."""
    answer = robot.ik_all(target, collisions="flag")
    assert isinstance(answer, tuple)
    return answer


def solutions(
    robot: screwkit.Robot, target: npt.NDArray[np.float64], mode: str
) -> npt.NDArray[np.float64]:
    """`ik_all(target, collisions=mode)` of one target ("ignore" or "filter")."""
    answer = robot.ik_all(target, collisions="filter" if mode == "filter" else "ignore")
    assert isinstance(answer, np.ndarray)
    return answer


def test_ik_all_flags_and_filters_collisions_as_coal() -> None:
    """`ik_all(collisions="flag")` flags each solution as coal finds its configuration (the
    UR5 with its SRDF and a table under it; solutions away from contact), "filter" keeps the
    unflagged ones in order, batches equal single calls, and the CLI's JSON says the same."""
    urdf, srdf, _ = files("ur5")
    robot = screwkit.Robot.from_urdf(urdf, "base_link", "ee_link", package_paths=[SHARE])
    robot.srdf(srdf)
    table = np.eye(4)
    table[:3, 3] = [0.4, 0.0, -0.05]
    robot.add_obstacle("table", screwkit.Box((1.0, 1.0, 0.04)), table)
    coal = Coal(urdf, srdf, robot)
    hppfcl = pytest.importorskip("coal", reason="coal (pip install coal) is a test dependency")

    obstacle = pin.GeometryObject(
        "table", 0, pin.SE3(np.eye(3), table[:3, 3]), hppfcl.Box(1.0, 1.0, 0.04)
    )
    obstacle.parentFrame = 0  # the world
    coal.cmodel.addGeometryObject(obstacle)
    table_id = coal.cmodel.ngeoms - 1
    for g in range(table_id):
        coal.cmodel.addCollisionPair(pin.CollisionPair(g, table_id))
    coal.cdata = pin.GeometryData(coal.cmodel)
    rng = np.random.default_rng(6)
    counts = {True: 0, False: 0}
    targets = []
    for _ in range(12):
        q_star = rng.uniform(-np.pi, np.pi, robot.dof)
        target = robot.fk(q_star)
        targets.append(target)
        q, collides = flagged(robot, target)
        assert collides.dtype == np.bool_ and collides.shape == (len(q),)
        for qk, c in zip(q, collides, strict=True):
            d = coal.distances(qk)
            if min(d.values()) < -1e-4 or min(d.values()) > 1e-4:
                assert bool(c) == bool(coal.colliding(qk)), (qk, d)
            counts[bool(c)] += 1
        np.testing.assert_array_equal(solutions(robot, target, "filter"), q[~collides])
        np.testing.assert_array_equal(solutions(robot, target, "ignore"), q)
    assert counts[True] > 3 and counts[False] > 3, counts
    batch = robot.ik_all(np.stack(targets), collisions="flag")
    assert isinstance(batch, list)
    for (bq, bc), t in zip(batch, targets, strict=True):
        q, c = flagged(robot, t)
        np.testing.assert_array_equal(bq, q)
        np.testing.assert_array_equal(bc, c)


def test_ik_all_collisions_from_the_cli(tmp_path: Path) -> None:
    """`screwkit ik --all --collisions flag|filter` (with --srdf and --obstacles) answers as
    `Robot.ik_all` does (JSON "collides" per solution; filter drops them)."""
    import json
    import os
    import subprocess

    exe = os.environ.get("SCREWKIT_CLI")
    if not exe or not Path(exe).exists():
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    urdf, srdf, _ = files("ur5")
    robot = screwkit.Robot.from_urdf(urdf, "base_link", "ee_link", package_paths=[SHARE])
    robot.srdf(srdf)
    scene = tmp_path / "scene.json"
    scene.write_text(
        '{"obstacles": [{"name": "table", "shape": "box", "size": [1, 1, 0.04],'
        ' "xyz": [0.4, 0, -0.05]}]}'
    )
    robot.add_obstacles(scene)
    # A target whose solutions both collide and do not.
    rng = np.random.default_rng(8)
    for _ in range(100):
        target = robot.fk(rng.uniform(-np.pi, np.pi, robot.dof))
        q, collides = flagged(robot, target)
        if collides.any() and not collides.all():
            break
    assert collides.any() and not collides.all()
    base = [exe, "ik", str(urdf), "--package-path", str(SHARE), "--base", "base_link"]
    base += ["--tip", "ee_link", "--all", "--srdf", str(srdf), "--obstacles", str(scene)]
    base += ["--target-matrix", ",".join(repr(float(x)) for x in target.flatten())]
    for mode in ("flag", "filter"):
        out = subprocess.run(
            [*base, "--collisions", mode, "--format", "json"], capture_output=True, text=True
        )
        got = json.loads(out.stdout)["solutions"]
        if mode == "flag":
            np.testing.assert_array_equal([s["q"] for s in got], q)
            assert [s["collides"] for s in got] == collides.tolist()
        else:
            np.testing.assert_array_equal([s["q"] for s in got], q[~collides])
            assert all("collides" not in s for s in got)
