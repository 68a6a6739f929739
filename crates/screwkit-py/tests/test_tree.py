"""The whole tree against Pinocchio (`pin`): every link's pose (forwardKinematics +
updateFramePlacements) and frame Jacobians (computeFrameJacobian in LOCAL, WORLD and
LOCAL_WORLD_ALIGNED) on the robots of the CI data's URDF trees and the bundled torso_two_arms, with
a fixed base and with a floating base (Pinocchio's free-flyer: q = (x, y, z, qx, qy, qz, qw) as
screwkit's; its velocity is (v, omega) in the base frame where screwkit's is (omega, v)).

Pinocchio builds mimic joints as ordinary joints here: the test drives them by the <mimic>
rule read from the file itself and sums their columns into the leader's (m * column).
"""

from __future__ import annotations

import json
import pickle
import xml.etree.ElementTree as ET
from collections.abc import Callable
from pathlib import Path
from typing import Literal

import numpy as np
import numpy.typing as npt
import pytest
from test_pinocchio import urdfdom_compatible

import screwkit

from conftest import REPO, shared_params

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin) is a test dependency")

Array = npt.NDArray[np.float64]

TREES = ["talos_full_v2.urdf", "baxter.urdf", "allegro_right_hand.urdf", "so101.urdf"]


def tree_files() -> list[object]:
    files: list[object] = [REPO / "assets" / "urdf" / "torso_two_arms.urdf"]
    return files + shared_params("urdf", [f"trees/{f}" for f in TREES])


def mimic_rules(path: Path) -> dict[str, tuple[str, float, float]]:
    """follower -> (leader, multiplier, offset), as written in the file."""
    out = {}
    for j in ET.parse(path).getroot().iter("joint"):
        m = j.find("mimic")
        if m is not None:
            out[j.get("name", "")] = (
                m.get("joint", ""),
                float(m.get("multiplier", "1")),
                float(m.get("offset", "0")),
            )
    return out


class Peer:
    def __init__(self, path: Path, floating: bool) -> None:
        xml = urdfdom_compatible(path.read_text())
        self.model = (
            pin.buildModelFromXML(xml, pin.JointModelFreeFlyer())
            if floating
            else pin.buildModelFromXML(xml)
        )
        self.data = self.model.createData()
        self.floating = floating
        self.mimic = mimic_rules(path)

    def value(self, name: str, values: dict[str, float]) -> float:
        m, o, cur = 1.0, 0.0, name
        while cur in self.mimic:
            leader, mul, off = self.mimic[cur]
            o += m * off
            m *= mul
            cur = leader
        return m * values[cur] + o

    def q(self, robot: screwkit.Robot, q: Array) -> Array:
        off = 7 if self.floating else 0
        values = dict(zip(robot.variable_names, q[off:].tolist(), strict=False))
        out = pin.neutral(self.model)
        if self.floating:
            out[:7] = q[:7]
        for jid in range(1, self.model.njoints):
            name = self.model.names[jid]
            if name == "root_joint":
                continue
            x = self.value(name, values)
            iq, nq = self.model.joints[jid].idx_q, self.model.joints[jid].nq
            out[iq : iq + nq] = [np.cos(x), np.sin(x)] if nq == 2 else [x]
        return np.asarray(out, dtype=np.float64)

    def columns(self, robot: screwkit.Robot, j: Array) -> Array:
        """Pinocchio's 6 x nv Jacobian with rows (v, omega) as screwkit's: rows (omega, v), one
        column per screwkit velocity entry (mimic columns summed into their leader's)."""
        j = np.vstack([j[3:], j[:3]])
        out = np.zeros((6, robot.nv))
        index = {n: k for k, n in enumerate(robot.v_names)}
        if self.floating:
            # Pinocchio's free-flyer v = (v, omega) in the base frame.
            out[:, 0:3] = j[:, 3:6]
            out[:, 3:6] = j[:, 0:3]
        for jid in range(1, self.model.njoints):
            name = self.model.names[jid]
            if name == "root_joint":
                continue
            m, cur = 1.0, name
            while cur in self.mimic:
                leader, mul, _ = self.mimic[cur]
                m *= mul
                cur = leader
            iv = self.model.joints[jid].idx_v
            out[:, index[cur]] += m * j[:, iv]
        return out


@pytest.mark.parametrize("path", tree_files(), ids=lambda p: getattr(p, "name", "shared"))
@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
def test_whole_tree_equals_pinocchio(path: Path, floating: bool) -> None:
    robot = screwkit.Robot.from_urdf(path, floating_base=floating)
    peer = Peer(path, floating)
    assert robot.nq == len(robot.q_names) == robot.nv + (1 if floating else 0)
    links = robot.link_names
    fids = [peer.model.getFrameId(name, pin.BODY) for name in links]
    assert all(f < len(peer.model.frames) for f in fids)
    worst_fk = worst_j = 0.0
    for seed in range(40):
        q = robot.random_configuration(seed)
        pq = peer.q(robot, q)
        pin.forwardKinematics(peer.model, peer.data, pq)
        pin.updateFramePlacements(peer.model, peer.data)
        mine = robot.fk_all_links(q)
        assert mine.shape == (len(links), 4, 4)
        for k, f in enumerate(fids):
            worst_fk = max(worst_fk, float(np.abs(mine[k] - peer.data.oMf[f].homogeneous).max()))
        # Frame Jacobians of a few links, three forms.
        for k in (len(links) - 1, seed % len(links), (7 * seed + 3) % len(links)):
            forms: list[tuple[Literal["body", "space", "world-aligned"], object]] = [
                ("body", pin.LOCAL),
                ("space", pin.WORLD),
                ("world-aligned", pin.LOCAL_WORLD_ALIGNED),
            ]
            for form, ref in forms:
                want = peer.columns(
                    robot, pin.computeFrameJacobian(peer.model, peer.data, pq, fids[k], ref)
                )
                got = robot.jacobian(q, form, link=links[k])
                assert got.shape == (6, robot.nv)
                worst_j = max(worst_j, float(np.abs(got - want).max()))
    assert worst_fk < 1e-12, f"{path.name}: FK vs Pinocchio {worst_fk:.3e}"
    assert worst_j < 1e-12, f"{path.name}: Jacobians vs Pinocchio {worst_j:.3e}"


def test_many_leaf_robot_python_api() -> None:
    path = REPO / "assets" / "urdf" / "torso_two_arms.urdf"
    robot = screwkit.Robot.from_urdf(path)
    assert "whole tree" in repr(robot)
    assert robot.variable_names == robot.q_names == robot.v_names
    assert robot.frame_names == robot.link_names
    q = np.linspace(-0.3, 0.3, robot.nq)
    # fk and jacobian without link= on a many-leaf file say what to do (the floor's message,
    # naming the keyword).
    calls: list[Callable[[], object]] = [lambda: robot.fk(q), lambda: robot.jacobian(q)]
    for call in calls:
        with pytest.raises(ValueError, match="^link: this robot is a whole tree .* name the frame"):
            call()
    with pytest.raises(ValueError, match="unknown frame"):
        robot.fk(q, link="nope")
    with pytest.raises(ValueError, match="cannot choose a tip"):
        robot.ik(np.eye(4))
    left = robot.fk(q, link="left_hand")
    right = robot.fk(q, link="right_hand")
    rel = robot.fk(q, link="left_hand", relative_to="right_hand")
    assert np.allclose(rel, np.linalg.inv(right) @ left, atol=1e-14)
    # Batches equal single calls.
    qs = np.stack([q, 0.5 * q, -q])
    assert np.array_equal(robot.fk(qs, link="left_hand")[0], left)
    assert np.array_equal(robot.fk(qs, link="left_hand", relative_to="right_hand")[0], rel)
    j = robot.jacobian(qs, "world-aligned", link="left_hand", relative_to="head")
    assert j.shape == (3, 6, robot.nv)
    assert np.array_equal(
        j[1], robot.jacobian(qs[1], "world-aligned", link="left_hand", relative_to="head")
    )
    assert robot.fk_all_links(qs).shape == (3, len(robot.link_names), 4, 4)
    # An added frame: a tool on the left hand; pickling keeps it.
    tool = np.eye(4)
    tool[:3, 3] = [0.0, 0.0, 0.1]
    robot.add_frame("left_tcp", "left_hand", tool)
    assert robot.frame_names[-1] == "left_tcp"
    assert np.allclose(robot.fk(q, link="left_tcp"), left @ tool, atol=1e-15)
    assert robot.fk_all_frames(q).shape == (len(robot.link_names) + 1, 4, 4)
    assert robot.fk_all_links(q).shape == (len(robot.link_names), 4, 4)
    with pytest.raises(ValueError, match="duplicate frame"):
        robot.add_frame("left_tcp", "left_hand", tool)
    again = pickle.loads(pickle.dumps(robot))
    assert np.array_equal(again.fk(q, link="left_tcp"), robot.fk(q, link="left_tcp"))
    # A chain still narrows: tip given, the chain's API as before.
    arm = screwkit.Robot.from_urdf(path, tip="left_hand")
    assert arm.dof == len(arm.joint_names)


def test_floating_base_configuration() -> None:
    path = REPO / "assets" / "urdf" / "torso_two_arms.urdf"
    robot = screwkit.Robot.from_urdf(path, floating_base=True)
    assert robot.floating_base and robot.nq == robot.nv + 1
    assert robot.q_names[:7] == [
        "floating_base." + s for s in ("x", "y", "z", "qx", "qy", "qz", "qw")
    ]
    q0 = robot.neutral()
    assert np.array_equal(q0[:7], [0, 0, 0, 0, 0, 0, 1])
    v = np.zeros(robot.nv)
    v[2] = 1.0  # omega_z
    q1 = robot.integrate(q0, v, np.pi / 2)
    h = np.sqrt(0.5)
    assert np.allclose(q1[3:7], [0, 0, h, h], atol=1e-15)
    assert np.allclose(robot.difference(q0, q1), v * np.pi / 2, atol=1e-14)
    # Against Pinocchio's own integrate (its v is (v, omega)).
    peer = Peer(path, True)
    rng = np.random.default_rng(4)
    for seed in range(20):
        q = robot.random_configuration(seed)
        v = rng.uniform(-1, 1, robot.nv)
        pv = np.concatenate([v[3:6], v[0:3], v[6:]])
        want = pin.integrate(peer.model, peer.q(robot, q), pv * 0.3)
        got = robot.integrate(q, v, 0.3)
        # The same rotation (a quaternion and its negative are one rotation).
        sign = np.sign(np.dot(got[3:7], want[3:7]))
        assert np.allclose(got[:3], want[:3], atol=1e-14)
        assert np.allclose(got[3:7], sign * want[3:7], atol=1e-14)
    bad = q0.copy()
    bad[6] = 0.5
    with pytest.raises(ValueError, match="quaternion"):
        robot.fk(bad, link="left_hand")


def test_pictures_of_a_whole_tree(tmp_path: Path) -> None:
    path = REPO / "assets" / "urdf" / "torso_two_arms.urdf"
    robot = screwkit.Robot.from_urdf(path)
    q = np.linspace(-0.3, 0.3, robot.nq)
    svg = robot.draw(q, tmp_path / "torso.svg", view="all")
    assert (tmp_path / "torso.svg").read_text() == svg
    doc = ET.fromstring(svg)
    ns = "{http://www.w3.org/2000/svg}"
    ids = {g.get("id") for g in doc.iter(f"{ns}g")}
    for leaf in ["head", "left_hand", "right_hand"]:
        assert f"iso-leaf-{leaf}" in ids and f"top-leaf-{leaf}" in ids
    for name in robot.link_names[1:]:
        assert f"front-link-{name}" in ids
    # The left hand's title carries its pose from fk, to 6 decimals.
    p = robot.fk(q, link="left_hand")[:3, 3]
    title = next(g for g in doc.iter(f"{ns}g") if g.get("id") == "side-leaf-left_hand")
    assert f"({p[0]:.6f}, {p[1]:.6f}, {p[2]:.6f})" in (title.findtext(f"{ns}title") or "")
    page = robot.viewer(q)
    model = json.loads(page.split('id="model">')[1].split("</script>")[0])
    assert model["subject"].startswith("whole tree from pelvis")
    assert [f["name"] for f in model["frames"]] == ["head", "left_hand", "right_hand"]
    assert model["q"] == q.tolist()
    with pytest.raises(ValueError, match=r"expected shape \(7,\)"):
        robot.draw(q[:3])
    # A floating base: q has the base's seven values first.
    free = screwkit.Robot.from_urdf(path, floating_base=True)
    qf = np.concatenate([[0.1, 0.2, 0.3, 0.0, 0.0, 0.0, 1.0], q])
    assert "iso-leaf-left_hand" in free.draw(qf)
    assert '"floating":true' in free.viewer(qf)
    with pytest.raises(ValueError, match=r"expected shape \(14,\)"):
        free.viewer(q)
