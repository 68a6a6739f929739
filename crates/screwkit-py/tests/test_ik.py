"""IK: every answer checked by an independent FK (the numpy URDF composition), within limits."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import screwkit

from conftest import ChainSpec, all_chains, configurations
from urdf_oracle import UrdfChain


@pytest.mark.parametrize("spec", all_chains())
def test_ik_answers_reach_their_targets_within_limits(spec: ChainSpec) -> None:
    robot = spec.robot()
    oracle = UrdfChain(str(spec.path), robot.base, robot.tip)
    targets = robot.fk(configurations(robot, 30, seed=21))
    position_only = robot.dof < 6
    result = robot.ik(targets, position_only=position_only, seed_rng=1)
    assert isinstance(result, screwkit.IkBatchResult)
    assert result.q.shape == (30, robot.dof)
    assert result.converged.dtype == np.bool_ and result.iterations.dtype == np.int64
    assert result.converged.mean() >= 0.9, result.stop
    for q, ok, t in zip(result.q, result.converged, targets, strict=False):
        assert np.all(q >= robot.lower - 1e-12) and np.all(q <= robot.upper + 1e-12)
        if ok:
            reached = oracle.fk(robot.joint_names, q)
            np.testing.assert_allclose(reached[:3, 3], t[:3, 3], atol=1e-8)
            if not position_only:
                np.testing.assert_allclose(reached[:3, :3], t[:3, :3], atol=1e-8)


def test_single_ik_result(ur5: screwkit.Robot) -> None:
    q = np.array([0.1, -0.5, 1.0, 0.2, 0.3, -0.4])
    r = ur5.ik(ur5.fk(q), seed=q + 0.05, tol_rot=1e-12, tol_pos=1e-12)
    assert isinstance(r, screwkit.IkResult)
    assert r.converged and r.stop == "converged" and r.restarts == 0
    assert r.error_rot <= 1e-12 and r.error_pos <= 1e-12
    np.testing.assert_allclose(r.q, q, atol=1e-9)
    assert "converged=True" in repr(r)


def test_methods_and_options(panda: screwkit.Robot) -> None:
    target = panda.fk(configurations(panda, 1, seed=22)[0])
    for method in ("lm", "dls", "nr"):
        r = panda.ik(target, method=method, tol_rot=1e-8, tol_pos=1e-8)
        assert isinstance(r, screwkit.IkResult)
        assert r.converged, (method, r)
    r = panda.ik(target, method="dls", damping=0.05)
    assert isinstance(r, screwkit.IkResult) and r.converged
    # Position only: the position is reached, the orientation is free.
    r = panda.ik(target, position_only=True)
    assert isinstance(r, screwkit.IkResult) and r.converged
    np.testing.assert_allclose(panda.fk(r.q)[:3, 3], target[:3, 3], atol=1e-9)
    # Weights: masking z makes z free.
    r = panda.ik(target, weights=[1, 1, 1, 1, 1, 0])
    assert isinstance(r, screwkit.IkResult) and r.converged


def test_unreachable_target_is_a_result_not_an_exception(ur5: screwkit.Robot) -> None:
    far = np.eye(4)
    far[0, 3] = 5.0  # the UR5 reaches under 1 m
    r = ur5.ik(far, max_iterations=200, max_restarts=5)
    assert isinstance(r, screwkit.IkResult)
    assert not r.converged
    assert r.stop in ("iteration limit", "restart limit")
    assert r.error_pos > 3.9
    assert np.all(r.q >= ur5.lower) and np.all(r.q <= ur5.upper)
    t = ur5.ik(far, timeout_ms=1.0, max_iterations=10**9, max_restarts=10**9)
    assert isinstance(t, screwkit.IkResult) and t.stop == "time limit" and not t.converged


def test_one_seed_for_many_targets(ur5: screwkit.Robot) -> None:
    targets = ur5.fk(configurations(ur5, 6, seed=23))
    seed = np.full(6, 0.3)
    a = ur5.ik(targets, seed)
    b = ur5.ik(targets, np.tile(seed, (6, 1)))
    assert isinstance(a, screwkit.IkBatchResult) and isinstance(b, screwkit.IkBatchResult)
    np.testing.assert_array_equal(a.q, b.q)


def test_ik_all_gives_every_solution(ur5: screwkit.Robot) -> None:
    """Analytic IK: every solution reaches the target (by the numpy URDF oracle), the source
    configuration is among them, nearest-to-seed order; a 7R arm is refused by family."""
    from conftest import ASSETS

    oracle = UrdfChain(str(ASSETS / "ur5.urdf"), ur5.base, ur5.tip)
    for q in configurations(ur5, 20, seed=71):
        t = ur5.fk(q)
        sols = ur5.ik_all(t, seed=q)
        assert isinstance(sols, np.ndarray)
        assert sols.ndim == 2 and sols.shape[1] == 6 and len(sols) >= 2
        np.testing.assert_allclose(sols[0], q, atol=1e-8)  # the nearest to q is q itself
        for s in sols:
            np.testing.assert_allclose(oracle.fk(ur5.joint_names, s), t, atol=1e-10)
            assert np.all(s >= ur5.lower) and np.all(s <= ur5.upper)
    planar = screwkit.Robot.from_urdf(ASSETS / "planar_3r.urdf")
    with pytest.raises(ValueError, match="no analytic solver"):
        planar.ik_all(planar.home)


def test_ik_all_seven_r_with_a_locked_joint() -> None:
    """The Panda with joint 7 locked at the seed's value (default), at a given value, swept;
    every solution checked by the numpy URDF oracle; bad locks raise ValueError."""
    from conftest import ASSETS

    panda = screwkit.Robot.from_urdf(ASSETS / "panda.urdf")
    oracle = UrdfChain(str(ASSETS / "panda.urdf"), panda.base, panda.tip)
    for q in configurations(panda, 10, seed=5):
        t = panda.fk(q)
        sols = panda.ik_all(t, seed=q)
        assert isinstance(sols, np.ndarray)
        np.testing.assert_allclose(sols[0], q, atol=1e-7)
        assert np.all(sols[:, 6] == q[6])
        for s in sols:
            np.testing.assert_allclose(oracle.fk(panda.joint_names, s), t, atol=1e-10)
            assert np.all(s >= panda.lower) and np.all(s <= panda.upper)
        by_name = panda.ik_all(t, seed=q, lock="panda_joint4", lock_value=float(q[3]))
        assert isinstance(by_name, np.ndarray)
        assert np.any(np.all(np.abs(by_name - q) < 1e-6, axis=1))
    t = panda.fk(q)
    swept = panda.ik_all(t, lock=6, sweep=7)
    assert isinstance(swept, np.ndarray)
    values = np.linspace(panda.lower[6], panda.upper[6], 7)
    assert len(swept) > 0 and all(np.any(np.abs(values - v) < 1e-12) for v in swept[:, 6])
    for s in swept:
        np.testing.assert_allclose(oracle.fk(panda.joint_names, s), t, atol=1e-10)
    # Joint 5 locked: a spherical wrist only, read from the tip (subproblem 5).
    by_five = panda.ik_all(t, lock=4)
    assert isinstance(by_five, np.ndarray) and len(by_five) > 0
    for s in by_five:
        np.testing.assert_allclose(oracle.fk(panda.joint_names, s), t, atol=1e-10)
    with pytest.raises(ValueError, match="for 7R chains"):
        screwkit.Robot.from_urdf(ASSETS / "ur5.urdf").ik_all(t, lock=0)
    with pytest.raises(ValueError, match="no joint"):
        panda.ik_all(t, lock="elbow")
    with pytest.raises(ValueError, match="exclude each other"):
        panda.ik_all(t, lock_value=0.1, sweep=3)
    with pytest.raises(ValueError, match="outside its limits"):
        panda.ik_all(t, lock_value=9.0)


def test_ik_all_batch(ur5: screwkit.Robot) -> None:
    """(N, 4, 4) targets: a list of arrays equal to the single calls; a row out of reach or
    bad (as its single call raises): BatchError naming it, carrying the other rows."""
    qs = configurations(ur5, 30, seed=3)
    targets = ur5.fk(qs)
    got = ur5.ik_all(targets, seed=qs[0])
    assert isinstance(got, list) and len(got) == 30
    for t, sols in zip(targets, got, strict=False):
        np.testing.assert_array_equal(sols, ur5.ik_all(t, seed=qs[0]))
    far = np.eye(4)
    far[0, 3] = 5.0
    with pytest.raises(ValueError, match="out of reach"):
        ur5.ik_all(far)
    # Before: the batch gave an empty array for the row the single call raises on.
    with pytest.raises(screwkit.BatchError, match="row 1: out of reach") as far_rows:
        ur5.ik_all(np.stack([targets[0], far]))
    assert far_rows.value.rows == [1]
    out = far_rows.value.result
    assert isinstance(out, list) and out[1].shape == (0, 6) and len(out[0]) > 0
    bad = targets.copy()
    bad[4, 0, 3] = np.nan
    with pytest.raises(screwkit.BatchError) as e:
        ur5.ik_all(bad, seed=qs[0])
    assert e.value.rows == [4]
    result = e.value.result
    assert result[4].shape == (0, 6)
    np.testing.assert_array_equal(result[5], got[5])


def test_ik_all_lists_postures_not_copies(ur5: screwkit.Robot) -> None:
    """The bundled UR5 has ±2π limits: every posture at up to 2⁶ angles. By default one row
    per posture, each joint at its representative nearest the seed; "all" lists every one;
    "none" keeps the angles in (−π, π]."""
    qs = configurations(ur5, 20, seed=8)
    for q in qs:
        t = ur5.fk(q)
        seed = np.clip(q + 2.5, ur5.lower, ur5.upper)
        near = ur5.ik_all(t, seed=seed)
        every = ur5.ik_all(t, seed=seed, representatives="all")
        none = ur5.ik_all(t, seed=seed, representatives="none")
        assert isinstance(near, np.ndarray) and isinstance(every, np.ndarray)
        assert isinstance(none, np.ndarray)
        assert len(near) == len(none) <= 8 < len(every)
        for rows in (near, none):
            for row in rows:
                assert np.abs(every - row).max(axis=1).min() < 1e-12  # one of "all"'s rows
                np.testing.assert_allclose(ur5.fk(row), t, atol=1e-10)
        assert np.all(np.abs(none) <= np.pi + 1e-12)
        # Per joint, no other representative inside the limits is nearer the seed.
        for row in near:
            for k in (-1.0, 1.0):
                other = row + k * 2 * np.pi
                inside = (other >= ur5.lower) & (other <= ur5.upper)
                assert np.all(~inside | (np.abs(row - seed) <= np.abs(other - seed) + 1e-12))
        # The configuration the pose came from is a posture nearest to itself.
        assert np.abs(ur5.ik_all(t, seed=q) - q).max(axis=1).min() < 1e-8
    with pytest.raises(ValueError, match="representatives"):
        ur5.ik_all(ur5.fk(qs[0]), representatives="some")  # type: ignore[call-overload]


GENERAL_6R = """<robot name="gen6"><link name="l0"/>{joints}</robot>"""
GENERAL_JOINTS = [
    ("0 0 0", "0 0 0"),
    ("0.05 0.02 0.27", "1.2 0.1 0"),
    ("0.29 0.03 0.01", "0.1 0.3 0.2"),
    ("0.08 -0.04 0.34", "-1.1 0.2 0.1"),
    ("0.02 0.03 0.09", "1.3 -0.2 0.3"),
    ("0.01 0.07 0.05", "-1.2 0.1 0.2"),
]


def test_ik_all_general_6r(tmp_path: Path) -> None:
    """A 6R arm of no special geometry (no two consecutive axes parallel or meeting): every
    solution checked by the numpy URDF oracle, the sampled configuration among them, and every
    solution numerical IK finds from 300 random seeds is one of them (modulo 2π)."""
    joints = "".join(
        f'<link name="l{i + 1}"/><joint name="j{i + 1}" type="revolute"><parent link="l{i}"/>'
        f'<child link="l{i + 1}"/><origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="0 0 1"/>'
        f'<limit lower="-3.1" upper="3.1" effort="1" velocity="1"/></joint>'
        for i, (xyz, rpy) in enumerate(GENERAL_JOINTS)
    )
    path = tmp_path / "gen6.urdf"
    path.write_text(GENERAL_6R.format(joints=joints))
    robot = screwkit.Robot.from_urdf(path)
    oracle = UrdfChain(str(path), robot.base, robot.tip)

    def wrap(a: np.ndarray) -> np.ndarray:
        return np.asarray((a + np.pi) % (2 * np.pi) - np.pi)

    for q in configurations(robot, 10, seed=8):
        t = robot.fk(q)
        sols = robot.ik_all(t, seed=q)
        assert isinstance(sols, np.ndarray) and sols.shape[1] == 6
        np.testing.assert_allclose(sols[0], q, atol=1e-7)
        for s in sols:
            np.testing.assert_allclose(oracle.fk(robot.joint_names, s), t, atol=1e-10)
    numerical = robot.ik(
        np.repeat(t[None], 300, axis=0), seed=configurations(robot, 300, seed=2), max_restarts=0
    )
    assert isinstance(numerical, screwkit.IkBatchResult)
    found = numerical.q[numerical.converged]
    assert len(found) > 0
    for x in found:
        assert np.min(np.max(np.abs(wrap(sols - x)), axis=1)) < 1e-6, x


def test_ik_all_by_arm_angle() -> None:
    """The iiwa by its arm angle: Robot.arm_angle equals the definition computed here from
    the oracle's link poses; every solution at ψ reaches the target (oracle), has arm angle ψ,
    and the sampled configuration comes first; lock="arm_angle" sweeps; misuse raises."""
    from conftest import ASSETS

    iiwa = screwkit.Robot.from_urdf(ASSETS / "iiwa14.urdf")
    oracle = UrdfChain(str(ASSETS / "iiwa14.urdf"), iiwa.base, iiwa.tip)
    s = np.array([0.0, 0.0, 0.36])
    home = oracle.poses(iiwa.joint_names, np.zeros(7))
    elbow, wrist = np.array([0.0, 0.0, 0.78]), np.array([0.0, 0.0, 1.18])

    def by_links(q: np.ndarray) -> float:
        now = oracle.poses(iiwa.joint_names, q)

        def carry(i: int, x: np.ndarray) -> np.ndarray:
            return np.asarray((now[i] @ np.linalg.inv(home[i]) @ np.append(x, 1.0))[:3])

        e, w = carry(4, elbow), carry(5, wrist)
        u = (w - s) / np.linalg.norm(w - s)
        r = np.array([0.0, 0.0, 1.0]) - u[2] * u
        r /= np.linalg.norm(r)
        off = (e - s) - np.dot(e - s, u) * u
        return float(np.arctan2(np.dot(u, np.cross(r, off)), np.dot(r, off)))

    for q in configurations(iiwa, 20, seed=12):
        psi = iiwa.arm_angle(q)
        assert abs(psi - by_links(q)) < 1e-9
        t = iiwa.fk(q)
        sols = iiwa.ik_all(t, seed=q, arm_angle=psi)
        assert isinstance(sols, np.ndarray)
        np.testing.assert_allclose(sols[0], q, atol=1e-7)
        for x in sols:
            np.testing.assert_allclose(oracle.fk(iiwa.joint_names, x), t, atol=1e-10)
            assert abs(np.angle(np.exp(1j * (by_links(x) - psi)))) < 1e-7
    swept = iiwa.ik_all(t, lock="arm_angle", sweep=8)
    assert isinstance(swept, np.ndarray) and len(swept) > 0
    for x in swept:
        np.testing.assert_allclose(oracle.fk(iiwa.joint_names, x), t, atol=1e-10)
    with pytest.raises(ValueError, match="give it alone"):
        iiwa.ik_all(t, arm_angle=0.1, lock=2)
    with pytest.raises(ValueError, match="not a finite number"):
        iiwa.ik_all(t, arm_angle=float("nan"))
    with pytest.raises(ValueError, match="expected 7 joint values"):
        iiwa.arm_angle(np.zeros(6))
    with pytest.raises(ValueError, match="not finite"):
        iiwa.arm_angle(np.full(7, np.nan))
    panda = screwkit.Robot.from_urdf(ASSETS / "panda.urdf")
    with pytest.raises(ValueError, match="no arm angle"):
        panda.arm_angle(np.zeros(7))
    with pytest.raises(ValueError, match="no arm angle"):
        panda.ik_all(panda.fk(np.zeros(7)), arm_angle=0.0)
