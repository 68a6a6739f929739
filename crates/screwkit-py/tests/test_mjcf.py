"""MuJoCo models (MJCF) against MuJoCo itself (the `mujoco` package, an independent oracle):
every body's and every named site's world pose after `mj_kinematics`, and the world-aligned
Jacobians of bodies against `mj_jacBody`, for random configurations within the limits of every
model in ../shared/mjcf. MuJoCo compiles a mesh-free copy (the shared folder's README: the
meshes and textures removed, a small inertial given to bodies without one); screwkit reads the
file as shipped."""

from __future__ import annotations

import pickle
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

from conftest import REPO, shared_file

mujoco = pytest.importorskip("mujoco", reason="MuJoCo (pip install mujoco) is a test dependency")

Array = npt.NDArray[np.float64]

FILES = [
    "robosuite_panda.xml",
    "robosuite_iiwa.xml",
    "robosuite_ur5e.xml",
    "robosuite_tiago.xml",
    "humanoid.xml",
    "ant.xml",
    "pusher.xml",
]


def shared_mjcf() -> Path:
    """The CI data's MJCF folder (the test must be marked ``shared``)."""
    return shared_file("mjcf")


def mesh_free(xml: str) -> str:
    """The model without meshes, textures and files, each body with an inertial."""
    root = ET.fromstring(xml)
    for parent in root.iter():
        for child in list(parent):
            if child.tag in ("mesh", "hfield", "skin") or (
                child.tag == "texture" and "file" in child.attrib
            ):
                parent.remove(child)
            elif child.tag == "geom" and (
                "mesh" in child.attrib
                or "hfield" in child.attrib
                or child.attrib.get("type") in ("mesh", "hfield")
            ):
                parent.remove(child)
    for m in root.iter("material"):
        m.attrib.pop("texture", None)
    for d in root.iter("default"):
        for g in d.findall("geom"):
            if g.attrib.get("type") == "mesh":
                g.attrib["type"] = "sphere"
            g.attrib.pop("mesh", None)
    for body in root.iter("body"):
        if body.find("inertial") is None:
            body.insert(
                0,
                ET.Element("inertial", pos="0 0 0", mass="0.001", diaginertia="1e-6 1e-6 1e-6"),
            )
    for c in root.iter("compiler"):
        for a in ("meshdir", "texturedir", "assetdir"):
            c.attrib.pop(a, None)
    return ET.tostring(root, encoding="unicode")


class MuJoCo:
    """The oracle: the mesh-free model and screwkit's q mapped to its qpos by joint name."""

    def __init__(self, path: Path, robot: screwkit.Robot) -> None:
        text = mesh_free(path.read_text())
        if "<include" in text:
            # Includes are read from the file's folder: MuJoCo compiles a copy beside it.
            copy = path.with_name(path.stem + ".mujoco.xml")
            copy.write_text(text)
            self.model = mujoco.MjModel.from_xml_path(str(copy))
        else:
            self.model = mujoco.MjModel.from_xml_string(text)
        self.data = mujoco.MjData(self.model)
        self.robot = robot
        self.index = {n: k for k, n in enumerate(robot.q_names)}

    def qpos(self, q: Array) -> Any:
        m = self.model
        out = m.qpos0.copy()
        for j in range(m.njnt):
            adr = m.jnt_qposadr[j]
            if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
                out[adr : adr + 3] = q[:3]
                out[adr + 3] = q[6]  # MuJoCo's quaternion is w first
                out[adr + 4 : adr + 7] = q[3:6]
            else:
                out[adr] = q[self.index[m.joint(j).name]]
        return out

    def qpos_with(self, q: Array, coupled: dict[str, tuple[str, float, float]]) -> Any:
        """qpos with each coupled follower f at c0 + c1 q_leader (refs 0 in MuJoCo's
        coupling formula here): {follower: (leader, c1, c0)}."""
        m = self.model
        out = m.qpos0.copy()
        values = dict(zip(self.robot.q_names, q.tolist(), strict=False))
        for j in range(m.njnt):
            name = m.joint(j).name
            adr = m.jnt_qposadr[j]
            if name in coupled:
                leader, c1, c0 = coupled[name]
                ref1 = m.qpos0[adr]
                ref2 = m.qpos0[m.jnt_qposadr[m.joint(leader).id]]
                out[adr] = ref1 + c0 + c1 * (values[leader] - ref2)
            elif m.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE:
                out[adr] = values[name]
        return out

    def run(self, q: Array) -> None:
        self.data.qpos[:] = self.qpos(q)
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)

    def body_name(self, i: int) -> str:
        return self.model.body(i).name or f"body_{i}"


def pose(p: Array, r: Array) -> Array:
    out = np.eye(4)
    out[:3, :3] = r.reshape(3, 3)
    out[:3, 3] = p
    return out


@pytest.mark.shared
@pytest.mark.parametrize("name", FILES)
def test_bodies_and_sites_equal_mujoco(name: str) -> None:
    assert_bodies_and_sites_equal_mujoco(shared_mjcf() / name)


HUMANOID = REPO / "assets" / "mjcf" / "humanoid.xml"
HUMANOID_URDF = REPO / "assets" / "urdf" / "humanoid.urdf"


def test_the_bundled_humanoid_equals_mujoco() -> None:
    assert_bodies_and_sites_equal_mujoco(HUMANOID)


def test_the_bundled_humanoid_urdf_and_mjcf_are_one_robot() -> None:
    """assets/urdf/humanoid.urdf is assets/mjcf/humanoid.xml joint for joint: every link, the
    mass and the centre of mass (MuJoCo's own, from the MJCF's inertials) agree."""
    mjcf = screwkit.Robot.from_file(HUMANOID)
    urdf = screwkit.Robot.from_urdf(HUMANOID_URDF, floating_base=True)
    assert mjcf.floating_base and mjcf.nq == urdf.nq == 30 and mjcf.nv == 29
    assert list(mjcf.q_names) == list(urdf.q_names)
    np.testing.assert_array_equal(mjcf.lower, urdf.lower)
    np.testing.assert_array_equal(mjcf.upper, urdf.upper)
    assert sorted(mjcf.link_names) == sorted(urdf.link_names)
    peer = MuJoCo(HUMANOID, mjcf)
    assert mjcf.total_mass == pytest.approx(float(peer.model.body_subtreemass[0]), rel=1e-14)
    worst = worst_com = 0.0
    for seed in range(100):
        q = mjcf.random_configuration(seed)
        for link in mjcf.link_names:
            worst = max(worst, float(np.abs(mjcf.fk(q, link=link) - urdf.fk(q, link=link)).max()))
        peer.run(q)
        worst_com = max(worst_com, float(np.abs(urdf.com(q) - peer.data.subtree_com[0]).max()))
    assert worst < 1e-13, worst
    assert worst_com < 1e-13, worst_com
    # Standing: with the pelvis at 0.71 m and every joint at 0, both soles are on the floor.
    q = mjcf.neutral()
    q[2] = 0.71
    for sole in ("left_sole", "right_sole"):
        assert abs(urdf.fk(q, link=sole)[2, 3]) < 1e-12


def assert_bodies_and_sites_equal_mujoco(path: Path) -> None:
    """Every body and site of `path` equals MuJoCo's pose at 200 random configurations."""
    robot = screwkit.Robot.from_urdf(path)
    peer = MuJoCo(path, robot)
    m = peer.model
    assert robot.floating_base == any(
        m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE for j in range(m.njnt)
    )
    # MuJoCo's joint order, the coupled followers excluded (none in these files).
    hinges = [m.joint(j).name for j in range(m.njnt) if m.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE]
    assert list(robot.variable_names) == hinges
    sites = [m.site(s).name for s in range(m.nsite) if m.site(s).name]
    worst = 0.0
    for seed in range(200):
        q = robot.random_configuration(seed)
        peer.run(q)
        for b in range(1, m.nbody):
            want = pose(peer.data.xpos[b], peer.data.xmat[b])
            got = robot.fk(q, link=peer.body_name(b))
            worst = max(worst, float(np.abs(got - want).max()))
        for s in sites:
            sid = m.site(s).id
            want = pose(peer.data.site_xpos[sid], peer.data.site_xmat[sid])
            worst = max(worst, float(np.abs(robot.fk(q, link=s) - want).max()))
    assert worst < 1e-12, worst


ARM = """<mujoco model="constructs">
  {compiler}
  <default>
    <joint axis="0 1 0" range="-90 90"/>
    <site size="0.01"/>
    <default class="roll">
      <joint axis="1 0 0"/>
      <default class="slider"><joint type="slide" range="-0.2 0.3"/></default>
    </default>
  </default>
  <worldbody>
    <body name="base" pos="0.1 0.2 0.3" {orient}>
      <joint name="j1" pos="0.05 0 0.02" ref="{ref}"/>
      <geom size="0.05"/>
      <frame pos="0 0 0.1" euler="{frame_euler}">
        <site name="tool_a" pos="0.01 0.02 0.03" zaxis="1 1 0"/>
        <body name="upper" pos="0 0.1 0.4" childclass="roll">
          <joint name="j2" pos="0 0 -0.1"/>
          <joint name="j3" class="slider" axis="0 0 1" ref="0.05"/>
          <joint name="j4" axis="0 1 1" pos="0.02 0.03 0" range="-45 60"/>
          <geom size="0.04"/>
          <site name="tool_b" pos="0 0 0.2" xyaxes="0 1 0 -1 0 0.2"/>
          <body name="lower" pos="0.3 0 0" axisangle="1 2 3 {angle}">
            <joint name="j5" type="hinge" limited="false" axis="1 1 1"/>
            <geom size="0.03"/>
            <site name="tool_c" quat="0.3 0.1 -0.5 0.8"/>
          </body>
        </body>
      </frame>
      <body name="welded" pos="0 0 -0.2" euler="{euler}"><geom size="0.02"/></body>
    </body>
  </worldbody>
  <equality>{equality}</equality>
</mujoco>"""


def compare(xml: str, tmp: Path, name: str = "m.xml", configurations: int = 50) -> float:
    path = tmp / name
    path.write_text(xml)
    robot = screwkit.Robot.from_urdf(path)
    peer = MuJoCo(path, robot)
    m = peer.model
    worst = 0.0
    for seed in range(configurations):
        q = robot.random_configuration(seed)
        peer.run(q)
        # A coupled follower's qpos as MuJoCo's equality would hold it (from screwkit's FK of
        # the follower's body: every body is compared below, so a wrong coupling shows).
        for b in range(1, m.nbody):
            want = pose(peer.data.xpos[b], peer.data.xmat[b])
            worst = max(worst, float(np.abs(robot.fk(q, link=peer.body_name(b)) - want).max()))
        for s in range(m.nsite):
            want = pose(peer.data.site_xpos[s], peer.data.site_xmat[s])
            worst = max(worst, float(np.abs(robot.fk(q, link=m.site(s).name) - want).max()))
    return worst


@pytest.mark.parametrize("degree", [True, False], ids=["degree", "radian"])
@pytest.mark.parametrize("eulerseq", ["xyz", "zyx", "XYZ", "zXy"])
def test_constructs_equal_mujoco(degree: bool, eulerseq: str, tmp_path: Path) -> None:
    """Classes and childclass, frames, every orientation form, both angle units, euler
    sequences (rotating and fixed axes), several joints in one body with anchors off its
    origin, ref on hinges and slides, limited/unlimited, sites."""
    a = 40.0 if degree else np.radians(40.0)
    compiler = f'<compiler angle="{"degree" if degree else "radian"}" eulerseq="{eulerseq}"/>'
    xml = ARM.format(
        compiler=compiler,
        orient=f'euler="{a} {-a / 2} {a / 3}"',
        ref=a / 4,
        frame_euler=f"{a / 2} 0 {a}",
        angle=a,
        euler=f"{-a} {a} 0",
        equality="",
    )
    assert compare(xml, tmp_path) < 1e-12


def test_joint_coupling_and_includes_equal_mujoco(tmp_path: Path) -> None:
    """`<equality><joint polycoef>` (a linear coupling with refs: a mimic joint) and
    `<include>` of a file in a subfolder (paths from the main file's folder)."""
    xml = ARM.format(
        compiler="",
        orient='quat="0.9 0.1 0.2 0.3"',
        ref=10,
        frame_euler="0 0 0",
        angle=30,
        euler="10 20 30",
        equality='<joint joint1="j4" joint2="j2" polycoef="0.1 -0.7 0 0 0"/>',
    )
    robot_path = tmp_path / "m.xml"
    robot_path.write_text(xml)
    robot = screwkit.Robot.from_urdf(robot_path)
    assert "j4" not in robot.variable_names, "the follower is not a variable"
    # MuJoCo keeps j4 a dof and holds the equality by constraint: give it the coupled value.
    peer = MuJoCo(robot_path, robot)
    m = peer.model
    worst = 0.0
    for seed in range(50):
        q = robot.random_configuration(seed)
        qpos = peer.qpos_with(q, {"j4": ("j2", -0.7, 0.1)})
        peer.data.qpos[:] = qpos
        mujoco.mj_kinematics(m, peer.data)
        for b in range(1, m.nbody):
            want = pose(peer.data.xpos[b], peer.data.xmat[b])
            worst = max(worst, float(np.abs(robot.fk(q, link=peer.body_name(b)) - want).max()))
    assert worst < 1e-12, worst
    # The model (without the coupling) split over an include in a subfolder.
    (tmp_path / "parts").mkdir()
    head, rest = xml.replace(
        '<joint joint1="j4" joint2="j2" polycoef="0.1 -0.7 0 0 0"/>', ""
    ).split("<worldbody>", 1)
    (tmp_path / "parts" / "defaults.xml").write_text(
        "<mujoco>" + head.split('<mujoco model="constructs">', 1)[1] + "</mujoco>"
    )
    main = '<mujoco model="constructs"><include file="parts/defaults.xml"/><worldbody>' + rest
    assert compare(main, tmp_path, "main.xml") < 1e-12
    # A pickled robot carries the model with its includes spliced in: it loads where the
    # included file is gone (another machine, a Ray worker).
    robot = screwkit.Robot.from_file(tmp_path / "main.xml")
    data = pickle.dumps(robot)
    (tmp_path / "parts" / "defaults.xml").unlink()
    with pytest.raises(ValueError, match="defaults.xml"):
        screwkit.Robot.from_file(tmp_path / "main.xml")
    copy = pickle.loads(data)
    assert copy.variable_names == robot.variable_names
    for seed in range(5):
        q = robot.random_configuration(seed)
        np.testing.assert_array_equal(copy.fk_all_frames(q), robot.fk_all_frames(q))


def test_the_bundled_construct_model_equals_mujoco() -> None:
    """assets/mjcf/two_arm_constructs.xml, compiled by MuJoCo as it is (no copy): bodies and
    sites, the coupled right shoulder roll given MuJoCo's coupled value, and the centre of
    mass of its inertials against MuJoCo's subtree centre of mass."""
    path = REPO / "assets" / "mjcf" / "two_arm_constructs.xml"
    robot = screwkit.Robot.from_urdf(path)
    assert "right_shoulder_roll" not in robot.variable_names
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    peer = MuJoCo.__new__(MuJoCo)
    peer.model, peer.data, peer.robot = model, data, robot
    peer.index = {n: k for k, n in enumerate(robot.q_names)}
    worst = 0.0
    for seed in range(100):
        q = robot.random_configuration(seed)
        data.qpos[:] = peer.qpos_with(q, {"right_shoulder_roll": ("left_shoulder_roll", -1.0, 0.0)})
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        for b in range(1, model.nbody):
            want = pose(data.xpos[b], data.xmat[b])
            worst = max(worst, float(np.abs(robot.fk(q, link=model.body(b).name) - want).max()))
        for s in range(model.nsite):
            want = pose(data.site_xpos[s], data.site_xmat[s])
            worst = max(worst, float(np.abs(robot.fk(q, link=model.site(s).name) - want).max()))
        worst = max(worst, float(np.abs(robot.com(q) - data.subtree_com[0]).max()))
    assert worst < 1e-12, worst
    assert robot.total_mass == pytest.approx(float(np.sum(model.body_mass)), rel=1e-14)


@pytest.mark.shared
@pytest.mark.parametrize("name", FILES)
def test_mujoco_qpos_both_ways(name: str) -> None:
    path = shared_mjcf() / name
    robot = screwkit.Robot.from_file(path)
    peer = MuJoCo(path, robot)
    for seed in range(20):
        q = robot.random_configuration(seed)
        qpos = robot.to_mujoco_qpos(q)
        np.testing.assert_array_equal(qpos, peer.qpos(q))  # the test's own mapping, by name
        np.testing.assert_array_equal(robot.from_mujoco_qpos(qpos), q)
    with pytest.raises(ValueError, match="qpos"):
        robot.from_mujoco_qpos(np.zeros(peer.model.nq + 1))


def test_mujoco_qpos_of_a_coupled_model() -> None:
    path = REPO / "assets" / "mjcf" / "two_arm_constructs.xml"
    robot = screwkit.Robot.from_file(path)
    model = mujoco.MjModel.from_xml_path(str(path))
    peer = MuJoCo.__new__(MuJoCo)
    peer.model, peer.robot = model, robot
    for seed in range(10):
        q = robot.random_configuration(seed)
        qpos = robot.to_mujoco_qpos(q)
        assert qpos.shape == (model.nq,)
        want = peer.qpos_with(q, {"right_shoulder_roll": ("left_shoulder_roll", -1.0, 0.0)})
        np.testing.assert_allclose(qpos, want, rtol=0, atol=1e-15)
        np.testing.assert_array_equal(robot.from_mujoco_qpos(qpos), q)


@pytest.mark.shared
@pytest.mark.parametrize("name", [*FILES, "two_arm_constructs.xml"])
def test_the_written_urdf_gives_the_same_fk(name: str, tmp_path: Path) -> None:
    """`Robot.to_urdf()` (the `screwkit urdf` text) loaded back: every link's pose equals the
    MJCF robot's to 1e-12, the variables and limits are the same."""
    path = (
        REPO / "assets" / "mjcf" / name
        if name == "two_arm_constructs.xml"
        else shared_mjcf() / name
    )
    robot = screwkit.Robot.from_file(path)
    out = tmp_path / "robot.urdf"
    text = robot.to_urdf(out)
    assert out.read_text() == text
    again = screwkit.Robot.from_file(out, floating_base=robot.floating_base)
    assert list(again.q_names) == list(robot.q_names)
    np.testing.assert_array_equal(np.array(again.lower), np.array(robot.lower))
    np.testing.assert_array_equal(np.array(again.upper), np.array(robot.upper))
    links = robot.frame_names
    worst = 0.0
    for seed in range(50):
        q = robot.random_configuration(seed)
        a, b = robot.fk_all_frames(q), again.fk_all_frames(q)
        assert a.shape == b.shape and again.frame_names == links
        worst = max(worst, float(np.abs(a - b).max()))
    assert worst < 1e-12, worst


@pytest.mark.shared
@pytest.mark.parametrize(
    "name, solutions",
    [("robosuite_ur5e.xml", None), ("robosuite_panda.xml", 6), ("robosuite_iiwa.xml", 6)],
)
def test_ik_on_mjcf_arms(name: str, solutions: int | None) -> None:
    """Numerical IK and every analytic solution on the MJCF arms (the family read from the
    screw axes, as for URDF: UR-type for the UR5e, a locked joint for the 7R arms); every
    answer checked by MuJoCo's own FK of the file."""
    path = shared_mjcf() / name
    robot = screwkit.Robot.from_file(path, tip="right_hand")
    peer = MuJoCo(path, screwkit.Robot.from_file(path))
    hand = peer.model.body("right_hand").id
    lo, hi = np.array(robot.lower), np.array(robot.upper)
    rng = np.random.default_rng(7)

    def mujoco_pose(q: Array) -> Array:
        peer.run(q)
        return pose(peer.data.xpos[hand], peer.data.xmat[hand])

    for _ in range(20):
        q = lo + (hi - lo) * rng.uniform(0.1, 0.9, robot.dof)
        target = mujoco_pose(q)
        r = robot.ik(target)
        assert r.converged
        assert np.abs(mujoco_pose(r.q) - target).max() < 1e-8
        every = robot.ik_all(target, q, lock=solutions)
        assert len(every) >= 1
        for s in every:
            assert np.abs(mujoco_pose(s) - target).max() < 1e-9


@pytest.mark.shared
def test_whole_body_tasks_on_the_mujoco_humanoid() -> None:
    """Both feet held and both hands reaching on gymnasium's humanoid (a free root), checked
    by MuJoCo's FK."""
    path = shared_mjcf() / "humanoid.xml"
    robot = screwkit.Robot.from_file(path)
    peer = MuJoCo(path, robot)
    names = ["left_foot", "right_foot", "left_lower_arm", "right_lower_arm"]
    bodies = [peer.model.body(n).id for n in names]
    for seed in range(5):
        star = robot.random_configuration(seed)
        peer.run(star)
        targets = [pose(peer.data.xpos[b], peer.data.xmat[b]) for b in bodies]
        tasks: list[screwkit.FrameTask | screwkit.PostureTask] = [
            screwkit.FrameTask(n, t) for n, t in zip(names, targets, strict=False)
        ]
        tasks.append(screwkit.PostureTask(robot.neutral(), weight=1e-2))
        r = robot.ik_tasks(tasks)
        assert r.converged, r
        peer.run(r.q)
        for b, t in zip(bodies, targets, strict=False):
            assert np.abs(pose(peer.data.xpos[b], peer.data.xmat[b]) - t).max() < 1e-8


@pytest.mark.shared
@pytest.mark.parametrize("name", FILES)
def test_every_jacobian_column_equals_mujoco(name: str) -> None:
    """Every column of every body's and named site's world-aligned Jacobian against
    `mj_jacBody` / `mj_jacSite`, the floating base's six included: MuJoCo's free-joint velocity
    is (ṗ in the world, ω in the body), screwkit's base twist (ω, v) in the base frame, so
    screwkit's ω columns are MuJoCo's and its v columns are MuJoCo's linear ones times R."""
    path = shared_mjcf() / name
    robot = screwkit.Robot.from_file(path)
    peer = MuJoCo(path, robot)
    m = peer.model
    columns = {n: k for k, n in enumerate(robot.v_names)}
    joints = [
        (m.jnt_dofadr[j], columns[m.joint(j).name])
        for j in range(m.njnt)
        if m.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE
    ]
    free = [m.jnt_dofadr[j] for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]
    sites = [s for s in range(m.nsite) if m.site(s).name]
    worst = 0.0
    for seed in range(20):
        q = robot.random_configuration(2000 + seed)
        peer.run(q)
        targets = [(peer.body_name(b), b, mujoco.mj_jacBody) for b in range(1, m.nbody)]
        targets += [(m.site(s).name, s, mujoco.mj_jacSite) for s in sites]
        for link, i, jac in targets:
            jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
            jac(m, peer.data, jacp, jacr, i)
            mj = np.vstack([jacr, jacp])  # screwkit's row order (ω, v)
            want = np.zeros((6, robot.nv))
            for d, k in joints:
                want[:, k] = mj[:, d]
            if free:
                d = free[0]
                # The free joint's body is the file's single top-level body: MuJoCo's body 1.
                rot = peer.data.xmat[1].reshape(3, 3)
                want[:, 0:3] = mj[:, d + 3 : d + 6]
                want[:, 3:6] = mj[:, d : d + 3] @ rot
            got = robot.jacobian(q, "world-aligned", link=link)
            worst = max(worst, float(np.abs(got - want).max()))
    assert worst < 1e-12, worst


@pytest.mark.shared
def test_what_is_read_past_is_a_warning() -> None:
    with pytest.warns(UserWarning, match=r"humanoid.xml: line \d+: 2 tendon\(s\) read past"):
        screwkit.Robot.from_file(shared_mjcf() / "humanoid.xml")


SCENE = """<mujoco>
  <worldbody>
    <body name="ball" pos="1 0 0.2"><freejoint/><geom size="0.1"/></body>
    <body name="torso" pos="0 0 0.5">
      <freejoint name="root"/>
      <geom size="0.2"/>
      <site name="torso" pos="0.1 0 0"/>
      <site name="beam" fromto="0.4 -0.02 0.11 0.34 0 0.115" size="0.01" type="capsule"/>
      <site name="down" fromto="0 0 0.3 0 0 -0.3" size="0.01" type="cylinder"/>
      <body name="leg" pos="0.2 0 -0.1" euler="0 0 30">
        <joint name="hip" axis="0 1 0" pos="0 0 0.05"/>
        <geom size="0.05"/>
        <site name="foot" fromto="0 0 0 0.1 0.2 -0.3" size="0.01" type="capsule"/>
      </body>
    </body>
    <body name="box" pos="-1 0 0.2"><joint type="free"/><geom type="box" size="0.1 0.1 0.1"/></body>
  </worldbody>
</mujoco>"""


def test_fromto_sites_site_names_and_props_equal_mujoco(tmp_path: Path) -> None:
    """Sites given by `fromto` (as dm_control's rangefinders), a site named like its body (the
    frame `site:NAME`), and a free prop beside the free robot (read past with a warning, as
    dm_control's quadruped and its ball)."""
    path = tmp_path / "scene.xml"
    path.write_text(SCENE)
    with pytest.warns(UserWarning, match="top-level body ball read past"):
        robot = screwkit.Robot.from_file(path)
    assert robot.floating_base and "ball" not in robot.frame_names
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    assert model.nq == 7 + 8 + 7 and robot.nq == 8
    robot_free = model.joint("root").qposadr[0]
    rng = np.random.default_rng(3)
    worst = 0.0
    for seed in range(30):
        q = robot.random_configuration(seed)
        # The whole model's qpos, the props moved too: the robot's entries are written at
        # their addresses and read back from there, the props' kept.
        props = rng.normal(size=model.nq)
        qpos = robot.to_mujoco_qpos(q, props)
        np.testing.assert_array_equal(qpos[robot_free : robot_free + 8], robot.to_mujoco_qpos(q))
        np.testing.assert_array_equal(
            np.delete(qpos, range(robot_free, robot_free + 8)),
            np.delete(props, range(robot_free, robot_free + 8)),
        )
        np.testing.assert_array_equal(robot.from_mujoco_qpos(qpos), q)
        data.qpos[:] = qpos
        mujoco.mj_kinematics(model, data)
        for name, link in [("torso", "torso"), ("leg", "leg")]:
            b = model.body(name).id
            want = pose(data.xpos[b], data.xmat[b])
            worst = max(worst, float(np.abs(robot.fk(q, link=link) - want).max()))
        for name, link in [
            ("torso", "site:torso"),
            ("beam", "beam"),
            ("down", "down"),
            ("foot", "foot"),
        ]:
            s = model.site(name).id
            want = pose(data.site_xpos[s], data.site_xmat[s])
            worst = max(worst, float(np.abs(robot.fk(q, link=link) - want).max()))
    assert worst < 1e-12, worst
    with pytest.raises(ValueError, match=r"expected 8 MuJoCo qpos values \(the robot's\) or 22"):
        robot.from_mujoco_qpos(np.zeros(21))
    with pytest.raises(ValueError, match="expected shape \\(22,\\)"):
        robot.to_mujoco_qpos(robot.neutral(), np.zeros(8))
