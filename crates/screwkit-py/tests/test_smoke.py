"""Smoke tests of an installed package: what a user does first, with real values checked.

`cargo xtask wheel` runs this file alone in a new venv where the abi3 wheel was installed with
no Rust toolchain on the PATH (the wheel a cluster node or a machine without a compiler gets);
it also runs with the rest of the suite. It needs only numpy, pytest and the bundled assets.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

import screwkit
from screwkit import lie

REPO = Path(__file__).resolve().parents[3]
ASSETS = REPO / "assets"


def test_the_package_is_the_installed_one() -> None:
    """Imported from site-packages (the wheel), not from the sources beside the tests."""
    where = Path(screwkit.__file__).resolve()
    assert "site-packages" in where.parts, where
    assert sys.prefix in str(where) or os.environ.get("VIRTUAL_ENV", "") in str(where)


def test_planar_3r_from_screws_equals_its_closed_form() -> None:
    L1, L2, L3 = 1.0, 0.8, 0.5
    M = np.eye(4)
    M[0, 3] = L1 + L2 + L3
    S = np.array([[0, 0, 1, 0, 0, 0], [0, 0, 1, 0, -L1, 0], [0, 0, 1, 0, -(L1 + L2), 0]])
    arm = screwkit.Robot.from_screws(M, S)
    q = np.array([0.3, -0.7, 1.1])
    a = np.cumsum(q)
    x = L1 * np.cos(a[0]) + L2 * np.cos(a[1]) + L3 * np.cos(a[2])
    y = L1 * np.sin(a[0]) + L2 * np.sin(a[1]) + L3 * np.sin(a[2])
    T = arm.fk(q)
    np.testing.assert_allclose(T[:3, 3], [x, y, 0.0], atol=1e-14)
    np.testing.assert_allclose(
        T[:2, :2], [[np.cos(a[2]), -np.sin(a[2])], [np.sin(a[2]), np.cos(a[2])]], atol=1e-14
    )


def test_ur5_fk_jacobian_ik_and_every_analytic_solution() -> None:
    robot = screwkit.Robot.from_urdf(ASSETS / "urdf" / "ur5.urdf")
    assert robot.dof == 6
    q = np.array([0.1, -0.5, 1.0, 0.2, 0.3, -0.4])
    T = robot.fk(q)
    # The Jacobian's linear rows against central differences of FK (space Jacobian: v_s).
    J = robot.jacobian(q, frame="space")
    h = 1e-6
    for i in range(6):
        dq = np.zeros(6)
        dq[i] = h
        dT = (robot.fk(q + dq) - robot.fk(q - dq)) / (2 * h)
        twist = dT @ np.linalg.inv(T)  # [V_s] = T' T^-1
        np.testing.assert_allclose(J[:3, i], [twist[2, 1], twist[0, 2], twist[1, 0]], atol=1e-8)
        np.testing.assert_allclose(J[3:, i], twist[:3, 3], atol=1e-8)
    sol = robot.ik(T)
    assert sol.converged
    np.testing.assert_allclose(robot.fk(sol.q), T, atol=1e-9)
    every = robot.ik_all(T, seed=q)
    assert isinstance(every, np.ndarray) and every.shape[1] == 6 and len(every) >= 1
    np.testing.assert_allclose(every[0], q, atol=1e-9)  # nearest to the seed first
    for s in every:
        np.testing.assert_allclose(robot.fk(s), T, atol=1e-9)


def test_batches_equal_single_calls() -> None:
    robot = screwkit.Robot.from_urdf(ASSETS / "urdf" / "panda.urdf")
    qs = np.random.default_rng(3).uniform(-1, 1, (257, robot.dof))
    poses = robot.fk(qs)
    assert poses.shape == (257, 4, 4)
    for k in (0, 100, 256):
        assert np.array_equal(poses[k], robot.fk(qs[k]))


def test_a_whole_tree_and_an_mjcf_model() -> None:
    tree = screwkit.Robot.from_urdf(ASSETS / "urdf" / "torso_two_arms.urdf")
    assert tree.nq == 7
    assert tree.fk(np.zeros(7), link="head")[:3, 3] == pytest.approx([0, 0, 1.4], abs=1e-12)
    mjcf = screwkit.Robot.from_file(ASSETS / "mjcf" / "two_arm_constructs.xml")
    assert mjcf.nq == 7


def test_the_screw_calculus() -> None:
    T = lie.exp6([0, 0, 1, 0, -1, 0.1], np.pi / 2)
    np.testing.assert_allclose(T[:3, 3], [1, -1, 0.05 * np.pi], atol=1e-15)
    S, theta = lie.axis_angle6(lie.log6(T))
    assert theta == pytest.approx(np.pi / 2, abs=1e-15)
    np.testing.assert_allclose(S, [0, 0, 1, 0, -1, 0.1], atol=1e-15)


def test_a_picture_and_an_error() -> None:
    robot = screwkit.Robot.from_urdf(ASSETS / "urdf" / "planar_3r.urdf")
    svg = robot.draw([0.1, 0.2, 0.3])
    assert "<svg" in svg[:200] and svg.rstrip().endswith("</svg>")
    with pytest.raises(ValueError, match="expected shape"):
        robot.fk([0.1])
    with pytest.raises(FileNotFoundError):
        screwkit.Robot.from_urdf(ASSETS / "urdf" / "no_such_robot.urdf")


def test_where_it_runs() -> None:
    """The host line benchmarks print: the kernel path is one of the two, and the line names
    it and the pool's threads."""
    assert screwkit.kernel_path() in ("avx512", "avx2+fma", "portable")
    line = screwkit.host()
    assert line.endswith(f"kernels {screwkit.kernel_path()}")
    assert f"{screwkit.num_threads()} pool threads" in line
