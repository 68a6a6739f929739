"""MJCF geoms and MuJoCo's contact rules against MuJoCo itself (the `mujoco` package): the
pairs MuJoCo checks (its collision pass with every margin raised, so that each pair its rules
let through reports a contact) are the pairs screwkit checks, and each pair's signed distance
equals `mj_geomDistance`'s, on random configurations.

The model is ours (written here): every geom type (sphere, capsule and cylinder by `fromto`, box
by `fromto`, ellipsoids, a plane, a non-convex mesh read as its hull, as MuJoCo does), a body
with two joints, a body welded to its parent, a body welded to the world, `contype` /
`conaffinity` bits, a visual-only class, `<contact><exclude>` and `<pair>`. The CI data's MJCF
files (the humanoid, the ant, the pusher: primitives, planes, a free-floating root) are checked
the same way when SCREWKIT_SHARED_MJCF is set."""

from __future__ import annotations

import struct
from collections import defaultdict
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

from conftest import shared_params

mujoco = pytest.importorskip("mujoco", reason="MuJoCo (pip install mujoco) is a test dependency")

MODEL = """<mujoco model="bodytest">
  <compiler angle="radian" meshdir="meshes"/>
  <default>
    <geom contype="1" conaffinity="1"/>
    <default class="visual"><geom contype="0" conaffinity="0" group="2"/></default>
  </default>
  <asset>
    <mesh name="ell" file="ell.stl" scale="1 1 1.5"/>
    <material name="red" rgba="1 0 0 1"/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1" pos="0 0 -0.05"/>
    <geom name="post" type="cylinder" size="0.05 0.2" pos="0.6 0.3 0.2"/>
    <body name="base" pos="0 0 0.1">
      <geom name="base_geom" type="cylinder" size="0.1 0.05"/>
      <body name="link1" pos="0 0 0.11">
        <joint name="j1" axis="0 0 1"/>
        <geom name="l1" type="capsule" fromto="0 0 0 0 0 0.3" size="0.05"/>
        <body name="link2" pos="0 0 0.35">
          <joint name="j2a" axis="0 1 0" pos="0 0 0.02"/>
          <joint name="j2b" axis="1 0 0"/>
          <geom name="l2" type="cylinder" fromto="0 0 0 0.3 0 0" size="0.04"/>
          <geom name="l2e" type="ellipsoid" size="0.06 0.04 0.03" pos="0.3 0 0" euler="0.3 0.2 0.1"/>
          <geom name="l2f" type="ellipsoid" fromto="0 0.05 0 0.1 0.05 0.02" size="0.02"/>
          <body name="weld2" pos="0.15 0 0.05">
            <geom name="w2" type="sphere" size="0.03"/>
          </body>
          <body name="link3" pos="0.35 0 0">
            <joint name="j3" axis="0 1 0"/>
            <geom name="l3" type="box" fromto="0 0 0 0.05 0.02 -0.25" size="0.03 0.02" material="red"/>
            <geom name="l3m" type="mesh" mesh="ell" pos="0 0.05 -0.3" quat="0.9 0.1 0.2 0.3"/>
            <geom name="l3v" class="visual" type="sphere" size="0.02" pos="0 0 -0.1"/>
            <body name="link4" pos="0 0 -0.3">
              <joint name="j4" axis="1 0 0"/>
              <geom name="l4" type="sphere" size="0.04" pos="0 0 -0.05" contype="2" conaffinity="2"/>
              <geom name="l4b" type="ellipsoid" size="0.02 0.05 0.03" pos="0.05 0 -0.05" contype="2" conaffinity="1"/>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <contact>
    <exclude body1="link1" body2="link3"/>
    <pair geom1="l3v" geom2="floor"/>
  </contact>
</mujoco>
"""  # noqa: E501


def _box(x0: float, x1: float, y0: float, y1: float, z0: float, z1: float) -> list[np.ndarray]:
    v = np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1)]
    faces += [(2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    return [v[list(f)] for f in faces]


def write_model(folder: Path) -> Path:
    """The test model and its mesh (an L-shaped prism off its origin: not convex, not centred)."""
    (folder / "meshes").mkdir()
    tris = _box(0.02, 0.08, -0.02, 0.02, 0.0, 0.03) + _box(0.02, 0.04, -0.02, 0.02, 0.03, 0.09)
    with open(folder / "meshes" / "ell.stl", "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(tris)))
        for t in tris:
            n = np.cross(t[1] - t[0], t[2] - t[0])
            f.write(struct.pack("<12fH", *(n / np.linalg.norm(n)), *t[0], *t[1], *t[2], 0))
    path = folder / "model.xml"
    path.write_text(MODEL)
    return path


def mujoco_pairs(m: object, d: object, q: npt.NDArray[np.float64]) -> set[tuple[int, int]]:
    """The geom pairs MuJoCo's collision pass checks at q: every margin raised to 100 m, each
    pair its rules let through reports a contact. (Not two boxes: MuJoCo's box-box routine
    reports no contact for some boxes well apart, whatever the margin; the models here have no
    box-box pair.)"""
    m.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_OVERRIDE  # type: ignore[attr-defined]
    m.opt.o_margin = 100.0  # type: ignore[attr-defined]
    # (MuJoCo's explicit pairs keep their own margin under the override.)
    pair_margin = m.pair_margin.copy()  # type: ignore[attr-defined]
    m.pair_margin[:] = 100.0  # type: ignore[attr-defined]
    d.qpos[:] = q  # type: ignore[attr-defined]
    mujoco.mj_forward(m, d)
    found = {
        tuple(sorted((int(c.geom1), int(c.geom2))))
        for c in d.contact[: d.ncon]  # type: ignore[attr-defined]
    }
    m.opt.enableflags &= ~int(mujoco.mjtEnableBit.mjENBL_OVERRIDE)  # type: ignore[attr-defined]
    m.pair_margin[:] = pair_margin  # type: ignore[attr-defined]
    return found  # type: ignore[return-value]


def body_of(m: object, g: int, floating: bool) -> str:
    """A geom's owner as screwkit names it: its body (an unnamed one `body_ID`); on the world
    body, `world` for a fixed base, else the geom's own name (an obstacle's)."""
    b = int(m.geom_bodyid[g])  # type: ignore[attr-defined]
    if b == 0 and floating:
        return str(m.geom(g).name)  # type: ignore[attr-defined]
    return str(m.body(b).name) or f"body_{b}"  # type: ignore[attr-defined]


def screwkit_q(robot: screwkit.Robot, m: object, qpos: npt.NDArray[np.float64]) -> np.ndarray:
    """MuJoCo's qpos as screwkit's whole-tree q (a free joint's quaternion w, x, y, z becomes
    x, y, z, w after the position)."""
    names = [m.joint(j).name for j in range(m.njnt)]  # type: ignore[attr-defined]
    q = []
    for j in range(len(names)):
        adr = int(m.jnt_qposadr[j])  # type: ignore[attr-defined]
        if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:  # type: ignore[attr-defined]
            w, x, y, z = qpos[adr + 3 : adr + 7]
            q += [*qpos[adr : adr + 3], x, y, z, w]
        else:
            q.append(qpos[adr])
    assert len(q) == len(robot.q_names), (names, robot.q_names)
    return np.array(q)


def compare(path: Path, samples: int, seed: int, tol: float) -> None:
    """Pairs and distances of `path` in screwkit and MuJoCo, on `samples` random qpos."""
    robot = screwkit.Robot.from_file(path)
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    m.opt.ccd_tolerance = 1e-13
    m.opt.ccd_iterations = 10000
    rng = np.random.default_rng(seed)
    floating = robot.floating_base
    lo, hi = m.jnt_range[:, 0], m.jnt_range[:, 1]
    for _ in range(samples):
        qpos = m.qpos0.copy()
        for j in range(m.njnt):
            adr = m.jnt_qposadr[j]
            if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
                qpos[adr : adr + 3] = [0.0, 0.0, rng.uniform(0.3, 1.5)]
                quat = rng.normal(size=4)
                qpos[adr + 3 : adr + 7] = quat / np.linalg.norm(quat)
            elif m.jnt_limited[j]:
                qpos[adr] = rng.uniform(lo[j], hi[j])
            else:
                qpos[adr] = rng.uniform(-np.pi, np.pi)
        pairs = mujoco_pairs(m, d, qpos)
        mj: dict[tuple[str, str], list[float]] = defaultdict(list)
        d.qpos[:] = qpos
        mujoco.mj_forward(m, d)
        for g1, g2 in pairs:
            dist = mujoco.mj_geomDistance(m, d, g1, g2, 100.0, None)
            x, y = sorted((body_of(m, g1, floating), body_of(m, g2, floating)))
            mj[(x, y)].append(dist)
        result = robot.distances(screwkit_q(robot, m, qpos))
        ours: dict[tuple[str, str], list[float]] = defaultdict(list)
        for (a, b), dist in zip(result.pairs, result.distance, strict=True):
            x, y = sorted((a, b))
            ours[(x, y)].append(float(dist))
        assert sorted(ours) == sorted(mj), (path.name, sorted(set(ours) ^ set(mj)))
        for key, theirs in mj.items():
            a, b = np.sort(ours[key]), np.sort(theirs)
            assert len(a) == len(b), (path.name, key, a, b)
            assert np.allclose(a, b, rtol=tol, atol=tol), (path.name, key, a, b)
        # Collision: some pair at a negative distance in MuJoCo (none within 1e-9 of contact).
        closest = min((x for v in mj.values() for x in v), default=np.inf)
        if abs(closest) > 1e-9:
            assert robot.in_collision(screwkit_q(robot, m, qpos)) == (closest < 0)


def test_every_geom_type_and_rule_as_mujoco(tmp_path: Path) -> None:
    compare(write_model(tmp_path), samples=200, seed=1, tol=1e-7)


def test_geometry_read(tmp_path: Path) -> None:
    """The geoms as the tree reads them: a visual-only geom is no collision shape unless a
    <pair> names it; MuJoCo's viewer groups 0-2 are drawn."""
    robot = screwkit.Robot.from_file(write_model(tmp_path))
    info = robot.info()
    shapes = [(g["link"], g["role"], g["shape"]) for g in info["geometry"]]
    assert ("link3", "collision", "sphere") in shapes  # l3v, named by the <pair>
    assert ("link2", "collision", "ellipsoid") in shapes
    assert ("world", "collision", "plane") in shapes
    assert ("link3", "visual", "mesh") in shapes
    assert len(robot.collision_pairs) == 30  # as MuJoCo checks them (the test above)


@pytest.mark.parametrize("name", shared_params("mjcf", ["humanoid.xml", "ant.xml", "pusher.xml"]))
def test_shared_mjcf_as_mujoco(name: Path) -> None:
    compare(name, samples=50, seed=2, tol=1e-7)


def test_bad_geoms_name_their_line(tmp_path: Path) -> None:
    """A geom that cannot be read does not stop the kinematics; a body query names its line."""
    path = tmp_path / "bad.xml"
    path.write_text(
        """<mujoco><worldbody><body name="b"><joint name="j"/>
        <geom type="capsule" size="0.1"/>
        <geom type="mesh" mesh="nowhere"/>
        </body></worldbody></mujoco>"""
    )
    robot = screwkit.Robot.from_file(path)
    assert robot.q_names == ["j"]
    with pytest.raises(ValueError, match=r"bad.xml:2: <geom>: a capsule needs 2"):
        robot.in_collision([0.0])


def test_load_options_geometry_and_meshes(tmp_path: Path) -> None:
    """`geometry=` keeps the shapes asked for; `meshes=` reads the mesh exactly or as its hull
    (the L-shaped mesh's hull reaches into its notch: a point there is closer to the hull); a
    pickled robot keeps both, and finds its meshes again."""
    import pickle

    path = write_model(tmp_path)
    none = screwkit.Robot.from_file(path, geometry="none")
    assert none.info()["geometry"] == [] and none.collision_pairs == []
    visual = screwkit.Robot.from_file(path, geometry="visual")
    assert {g["role"] for g in visual.info()["geometry"]} == {"visual"}
    assert visual.collision_pairs == []
    q = np.zeros(5)
    hull = screwkit.Robot.from_file(path)
    exact = screwkit.Robot.from_file(path, meshes="exact")
    # A ball in the mesh's notch, inside its hull (scaled mesh frame: the L is x in (0.02,
    # 0.08) for z < 0.045, x in (0.02, 0.04) up to z = 0.135; the hull's slanted face passes
    # x = 0.069 at z = 0.07), placed by the mesh geom's pose at q = 0: 0.01 m from the L.
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    g = m.geom("l3m").id
    pose = np.eye(4)
    pose[:3, :3] = d.geom_xmat[g].reshape(3, 3)
    # MuJoCo centres a mesh on its inertial frame: the file's origin is at -mesh_pos there.
    quat = m.mesh_quat[m.geom_dataid[g]]
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, quat)
    file_to_geom = np.eye(4)
    file_to_geom[:3, :3] = rot.reshape(3, 3).T
    file_to_geom[:3, 3] = -rot.reshape(3, 3).T @ m.mesh_pos[m.geom_dataid[g]]
    pose[:3, 3] = d.geom_xpos[g]
    ball = pose @ file_to_geom @ np.array([0.05, 0.0, 0.07, 1.0])
    at = np.eye(4)
    at[:3, 3] = ball[:3]
    for r in (hull, exact):
        r.add_obstacle("ball", screwkit.Sphere(0.005), at)
    near = {
        name: dict(zip(r.distances(q).pairs, r.distances(q).distance, strict=True))[
            ("link3", "ball")
        ]
        for name, r in [("hull", hull), ("exact", exact)]
    }
    assert near["hull"] < 0 and abs(near["exact"] - 0.005) < 1e-9, near
    restored = pickle.loads(pickle.dumps(exact))
    restored.add_obstacle("ball", screwkit.Sphere(0.005), at)
    again = dict(zip(restored.distances(q).pairs, restored.distances(q).distance, strict=True))
    assert again[("link3", "ball")] == near["exact"]
    assert pickle.loads(pickle.dumps(none)).collision_pairs == []
