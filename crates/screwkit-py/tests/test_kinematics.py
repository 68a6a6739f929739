"""FK, all-link FK, Jacobians and screw axes against independent oracles: the URDF composed joint
by joint in numpy (urdf_oracle), central finite differences, and Pinocchio."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

from conftest import REPO, ChainSpec, all_chains, configurations, ur5_space_screws
from urdf_oracle import UrdfChain, adjoint

Array = npt.NDArray[np.float64]


def oracle(spec: ChainSpec, robot: screwkit.Robot) -> UrdfChain:
    return UrdfChain(str(spec.path), robot.base, robot.tip)


def vee(m: Array) -> Array:
    """se(3) matrix -> twist (omega, v)."""
    return np.array([m[2, 1], m[0, 2], m[1, 0], m[0, 3], m[1, 3], m[2, 3]])


@pytest.mark.parametrize("spec", all_chains())
def test_fk_equals_urdf_composition(spec: ChainSpec) -> None:
    robot = spec.robot()
    chain = oracle(spec, robot)
    qs = configurations(robot, 50, seed=1)
    batch = robot.fk(qs)
    assert batch.shape == (50, 4, 4)
    for q, t in zip(qs, batch, strict=False):
        np.testing.assert_allclose(t, chain.fk(robot.joint_names, q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(robot.home, chain.home(), rtol=0, atol=1e-12)


@pytest.mark.parametrize("spec", all_chains())
def test_all_links_equal_urdf_composition(spec: ChainSpec) -> None:
    robot = spec.robot()
    chain = oracle(spec, robot)
    assert robot.link_names == chain.links
    qs = configurations(robot, 10, seed=2)
    batch = robot.fk_all_links(qs)
    assert batch.shape == (10, len(chain.links), 4, 4)
    for q, poses in zip(qs, batch, strict=False):
        expected = chain.poses(robot.joint_names, q)
        np.testing.assert_allclose(poses, np.array(expected), rtol=0, atol=1e-12)
        np.testing.assert_array_equal(poses[-1], robot.fk(q))


@pytest.mark.parametrize("spec", all_chains())
def test_jacobians_equal_finite_differences(spec: ChainSpec) -> None:
    robot = spec.robot()
    h = 1e-6
    for q in configurations(robot, 5, seed=3):
        t = robot.fk(q)
        t_inv = np.linalg.inv(t)
        js = robot.jacobian(q, "space")
        jb = robot.jacobian(q, frame="body")
        assert js.shape == jb.shape == (6, robot.dof)
        for k in range(robot.dof):
            dq = np.zeros(robot.dof)
            dq[k] = h
            dt = (robot.fk(q + dq) - robot.fk(q - dq)) / (2 * h)
            np.testing.assert_allclose(js[:, k], vee(dt @ t_inv), atol=1e-8)
            np.testing.assert_allclose(jb[:, k], vee(t_inv @ dt), atol=1e-8)


@pytest.mark.parametrize("spec", all_chains())
def test_world_aligned_jacobian_is_the_tip_point_velocity(spec: ChainSpec) -> None:
    robot = spec.robot()
    qs = configurations(robot, 4, seed=4)
    batch = robot.jacobian(qs, "world-aligned")
    h = 1e-6
    for q, jwa in zip(qs, batch, strict=False):
        np.testing.assert_array_equal(jwa, robot.jacobian(q, "world-aligned"))
        np.testing.assert_array_equal(jwa[:3], robot.jacobian(q, "space")[:3])
        for k in range(robot.dof):
            dq = np.zeros(robot.dof)
            dq[k] = h
            dp = (robot.fk(q + dq)[:3, 3] - robot.fk(q - dq)[:3, 3]) / (2 * h)
            np.testing.assert_allclose(jwa[3:, k], dp, atol=1e-8)


@pytest.mark.parametrize("spec", all_chains())
def test_screw_axes_at_home_are_jacobian_columns_at_zero(spec: ChainSpec) -> None:
    """S_i and B_i are the Jacobian columns at q = 0 (one per joint when no joint mimics)."""
    robot = spec.robot()
    s, b = robot.screw_axes("space"), robot.screw_axes("body")
    assert s.shape == b.shape == (len(robot.axis_names), 6)
    # S_i = Ad_M B_i, with M from the oracle.
    m = oracle(spec, robot).home()
    np.testing.assert_allclose(s, (adjoint(m) @ b.T).T, atol=1e-12)
    if robot.axis_names == robot.joint_names:
        z = np.zeros(robot.dof)
        np.testing.assert_allclose(s.T, robot.jacobian(z, "space"), atol=1e-12)
        np.testing.assert_allclose(b.T, robot.jacobian(z, "body"), atol=1e-12)


def test_ur5_screw_axes_closed_form(ur5: screwkit.Robot) -> None:
    """The UR5's space screw axes from its published dimensions (Modern Robotics, Ex. 4.5 with
    the URDF's shoulder and wrist offsets)."""
    h1, l1, l2, w1, w2 = 0.089159, 0.425, 0.39225, 0.10915, 0.09465
    expected = ur5_space_screws(h1, w2, l1, l2, w1)
    np.testing.assert_allclose(ur5.screw_axes(), expected, atol=1e-12)
    assert ur5.joint_names == [
        "shoulder_pan_joint",
        "shoulder_lift_joint",
        "elbow_joint",
        "wrist_1_joint",
        "wrist_2_joint",
        "wrist_3_joint",
    ]
    assert (ur5.base, ur5.tip, ur5.dof) == ("base_link", "tool0", 6)


def test_table_formats(ur5: screwkit.Robot) -> None:
    import json

    doc = json.loads(ur5.table("json"))
    assert [j["name"] for j in doc["joints"]] == ur5.joint_names
    np.testing.assert_allclose([j["screw_space"] for j in doc["joints"]], ur5.screw_axes("space"))
    np.testing.assert_allclose([j["screw_body"] for j in doc["joints"]], ur5.screw_axes("body"))
    np.testing.assert_allclose(doc["home"], ur5.home)
    csv = ur5.table("csv", frame="space").splitlines()
    assert csv[0].startswith("frame,index,joint")
    assert sum(line.startswith("space,") for line in csv) == 6
    assert not any(line.startswith("body,") for line in csv)
    assert "shoulder_pan_joint" in ur5.table()


def test_analyze_ur5(ur5: screwkit.Robot) -> None:
    q = np.array([0.1, -0.5, 1.0, 0.2, 0.3, -0.4])
    a = ur5.analyze(q)
    j = ur5.jacobian(q)
    sv = np.linalg.svd(j, compute_uv=False)
    np.testing.assert_allclose(a.singular_values, sv, rtol=1e-12)
    np.testing.assert_array_equal(a.jacobian, j)
    assert a.rank == 6
    assert a.manipulability == pytest.approx(np.prod(sv), rel=1e-12)
    assert a.condition_number == pytest.approx(sv[0] / sv[-1], rel=1e-12)
    assert a.determinant == pytest.approx(np.linalg.det(j), rel=1e-10)
    assert a.verdict.startswith("well-conditioned")
    # Position only: the tip point's velocity Jacobian (linear rows of J_b).
    jv = ur5.jacobian(q, "body")[3:]
    np.testing.assert_allclose(a.position_singular_values, np.linalg.svd(jv, compute_uv=False))
    assert a.position_rank == 3
    assert a.position_manipulability == pytest.approx(np.sqrt(np.linalg.det(jv @ jv.T)))
    # The home pose of the UR5 is singular (wrist axes 4 and 6 parallel): rank 5.
    s = ur5.analyze(np.zeros(6), frame="body")
    assert s.rank == 5
    assert s.verdict.startswith("singular (rank 5 of 6)")
    assert s.lost_directions.shape == (1, 6)
    jb = ur5.jacobian(np.zeros(6), "body")
    np.testing.assert_allclose(s.lost_directions[0] @ jb, np.zeros(6), atol=1e-12)


@pytest.mark.parametrize("spec", all_chains())
def test_analyze_equals_numpy_svd(spec: ChainSpec) -> None:
    robot = spec.robot()
    for q in configurations(robot, 3, seed=5):
        for frame in ("space", "body"):
            a = robot.analyze(q, frame)
            sv = np.linalg.svd(robot.jacobian(q, frame), compute_uv=False)
            np.testing.assert_allclose(a.singular_values, sv, rtol=1e-10, atol=1e-14)
            assert a.rank == int((sv > a.rank_tolerance).sum())
            assert a.frame == frame
            assert isinstance(a.verdict, str) and a.verdict


def test_analyze_a_frame_of_the_whole_tree() -> None:
    """`analyze(q, frame, link=…, relative_to=…)`: the floor's analysis of the Jacobian
    `jacobian` gives for that frame, its singular values numpy's; the position-only figures of
    the frame point's velocity (the world-aligned Jacobian's linear rows, whatever the frame)."""
    path = REPO / "assets" / "urdf" / "torso_two_arms.urdf"
    robot = screwkit.Robot.from_urdf(path)
    q = np.linspace(-0.4, 0.5, robot.nq)
    for frame in ("space", "body", "world-aligned"):
        for reference in (None, "right_hand"):
            a = robot.analyze(q, frame, link="left_hand", relative_to=reference)
            j = robot.jacobian(q, frame, link="left_hand", relative_to=reference)
            np.testing.assert_array_equal(a.jacobian, j)
            sv = np.linalg.svd(j, compute_uv=False)
            np.testing.assert_allclose(a.singular_values, sv, rtol=1e-10, atol=1e-14)
            assert a.rank == int((sv > a.rank_tolerance).sum()) == np.linalg.matrix_rank(j)
            jv = robot.jacobian(q, "world-aligned", link="left_hand", relative_to=reference)[3:]
            np.testing.assert_allclose(
                a.position_singular_values, np.linalg.svd(jv, compute_uv=False), rtol=1e-10
            )
            assert a.frame == frame
    with pytest.raises(ValueError, match="^link: this robot is a whole tree"):
        robot.analyze(q)
    with pytest.raises(ValueError, match="analyze takes one configuration"):
        robot.analyze(np.stack([q, q]), link="left_hand")


def test_chain_without_joints() -> None:
    xml = """<robot name="rigid"><link name="a"/><link name="b"/>
      <joint name="j" type="fixed"><parent link="a"/><child link="b"/>
      <origin xyz="1 0 0" rpy="0 0 1.5707963267948966"/></joint></robot>"""
    robot = screwkit.Robot.from_string(xml)
    assert robot.dof == 0 and robot.joint_names == [] and robot.link_names == ["a", "b"]
    t = robot.fk([])
    np.testing.assert_allclose(t[:3, 3], [1, 0, 0])
    np.testing.assert_allclose(t[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)
    assert robot.fk(np.zeros((3, 0))).shape == (3, 4, 4)
    assert robot.jacobian(np.zeros((2, 0))).shape == (2, 6, 0)
    r = robot.ik(t)
    assert isinstance(r, screwkit.IkResult) and r.q.shape == (0,) and r.converged
    assert robot.analyze([]).verdict == "no joints: the tip cannot move"
    far = robot.ik(np.eye(4), max_restarts=2)
    assert isinstance(far, screwkit.IkResult) and not far.converged and far.error_pos == 1.0
