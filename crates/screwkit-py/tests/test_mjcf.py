"""MuJoCo models (MJCF) against MuJoCo itself (the `mujoco` package, an independent oracle):
every body's and every named site's world pose after `mj_kinematics`, and the world-aligned
Jacobians of bodies against `mj_jacBody`, for random configurations within the limits of every
model in ../shared/mjcf. MuJoCo compiles a mesh-free copy (the shared folder's README: the
meshes and textures removed, a small inertial given to bodies without one); screwkit reads the
file as shipped."""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

from conftest import REPO

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
    d = Path(os.environ.get("SCREWKIT_SHARED_MJCF", REPO.parent / "shared" / "mjcf"))
    if not d.is_dir():
        pytest.skip("../shared/mjcf not found")
    return d


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
                "mesh" in child.attrib or child.attrib.get("type") == "mesh"
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
        self.model = mujoco.MjModel.from_xml_string(mesh_free(path.read_text()))
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


@pytest.mark.parametrize("name", FILES)
def test_bodies_and_sites_equal_mujoco(name: str) -> None:
    path = shared_mjcf() / name
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


@pytest.mark.parametrize("name", FILES)
def test_body_jacobians_equal_mujoco(name: str) -> None:
    path = shared_mjcf() / name
    robot = screwkit.Robot.from_urdf(path)
    peer = MuJoCo(path, robot)
    m = peer.model
    # screwkit's velocity entry of each MuJoCo hinge/slide dof (the base's six are compared
    # only through the joints' columns: MuJoCo's free-joint velocity is (v world, ω local)).
    columns = {n: k for k, n in enumerate(robot.v_names)}
    dofs = [
        (m.jnt_dofadr[j], columns[m.joint(j).name])
        for j in range(m.njnt)
        if m.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE
    ]
    bodies = list(range(1, m.nbody))[-3:]
    worst = 0.0
    for seed in range(50):
        q = robot.random_configuration(1000 + seed)
        peer.run(q)
        for b in bodies:
            jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
            mujoco.mj_jacBody(m, peer.data, jacp, jacr, b)
            got = robot.jacobian(q, "world-aligned", link=peer.body_name(b))
            for d, k in dofs:
                worst = max(worst, float(np.abs(got[:3, k] - jacr[:, d]).max()))
                worst = max(worst, float(np.abs(got[3:, k] - jacp[:, d]).max()))
    assert worst < 1e-12, worst
