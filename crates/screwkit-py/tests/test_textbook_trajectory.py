"""The textbook's trajectory functions (`screwkit.trajectory`, *Modern Robotics* ch. 9)
against the `modern_robotics` package of its authors, to 1e-12, on random durations, joint
values and poses, both time scalings; batches equal to the single calls; bad arguments
refused."""

from __future__ import annotations

import doctest
from collections.abc import Callable

import numpy as np
import numpy.typing as npt
import pytest

import screwkit
from screwkit import lie, trajectory

mr = pytest.importorskip("modern_robotics", reason="pip install modern_robotics")


def random_pose(rng: np.random.Generator) -> npt.NDArray[np.float64]:
    xi = rng.normal(size=6)
    xi[:3] *= 2.5 / max(float(np.linalg.norm(xi[:3])), 1e-9) * rng.uniform(0.1, 1.0)
    return np.asarray(lie.exp6(xi), dtype=float)


def test_time_scalings_equal_the_textbooks() -> None:
    rng = np.random.default_rng(1)
    for _ in range(50):
        tf = rng.uniform(0.1, 10)
        t = rng.uniform(0, tf)
        assert abs(trajectory.cubic_time_scaling(tf, t) - mr.CubicTimeScaling(tf, t)) < 1e-12
        assert abs(trajectory.quintic_time_scaling(tf, t) - mr.QuinticTimeScaling(tf, t)) < 1e-12
    ts = np.linspace(0, 3, 7)
    np.testing.assert_allclose(
        trajectory.quintic_time_scaling(3, ts),
        [mr.QuinticTimeScaling(3, t) for t in ts],
        atol=1e-15,
    )
    assert trajectory.cubic_time_scaling(2, np.zeros((2, 3))).shape == (2, 3)


@pytest.mark.parametrize("method", [3, 5])
def test_joint_trajectories_equal_the_textbooks(method: int) -> None:
    rng = np.random.default_rng(2)
    starts, ends = rng.normal(size=(5, 7)), rng.normal(size=(5, 7))
    for a, b in zip(starts, ends, strict=True):
        tf, n = rng.uniform(0.5, 5), int(rng.integers(2, 40))
        got = trajectory.joint_trajectory(a, b, tf, n, method)
        np.testing.assert_allclose(got, mr.JointTrajectory(a, b, tf, n, method), atol=1e-12)
        assert got.shape == (n, 7)
        np.testing.assert_array_equal(got[0], a)
    batch = trajectory.joint_trajectory(starts, ends, 2.0, 11, method)
    assert batch.shape == (5, 11, 7)
    for k in range(5):
        np.testing.assert_array_equal(
            batch[k], trajectory.joint_trajectory(starts[k], ends[k], 2.0, 11, method)
        )


@pytest.mark.parametrize("method", [3, 5])
@pytest.mark.parametrize("which", ["screw", "cartesian"])
def test_pose_trajectories_equal_the_textbooks(which: str, method: int) -> None:
    ours = getattr(trajectory, f"{which}_trajectory")
    theirs = getattr(mr, f"{which.capitalize()}Trajectory")
    rng = np.random.default_rng(3)
    starts = np.stack([random_pose(rng) for _ in range(6)])
    ends = np.stack([random_pose(rng) for _ in range(6)])
    for a, b in zip(starts, ends, strict=True):
        tf, n = rng.uniform(0.5, 5), int(rng.integers(2, 30))
        got = ours(a, b, tf, n, method)
        assert got.shape == (n, 4, 4)
        np.testing.assert_allclose(got, np.array(theirs(a, b, tf, n, method)), atol=1e-12)
        np.testing.assert_allclose(got[-1], b, atol=1e-12)
    batch = ours(starts, ends, 3.0, 9, method)
    assert batch.shape == (6, 9, 4, 4)
    for k in range(6):
        np.testing.assert_array_equal(batch[k], ours(starts[k], ends[k], 3.0, 9, method))


def test_the_textbooks_examples() -> None:
    """The worked examples printed in the textbook's package (three decimals)."""
    xs = np.array([[1, 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, 1], [0, 0, 0, 1]], dtype=float)
    xe = np.array([[0, 0, 1, 0.1], [1, 0, 0, 0], [0, 1, 0, 4.1], [0, 0, 0, 1]], dtype=float)
    screw = trajectory.screw_trajectory(xs, xe, 5, 4, 3)
    np.testing.assert_allclose(
        screw[1],
        [
            [0.904, -0.25, 0.346, 0.441],
            [0.346, 0.904, -0.25, 0.529],
            [-0.25, 0.346, 0.904, 1.601],
            [0.0, 0.0, 0.0, 1.0],
        ],
        atol=5e-4,
    )
    cart = trajectory.cartesian_trajectory(xs, xe, 5, 4, 5)
    np.testing.assert_allclose(
        cart[1],
        [
            [0.937, -0.214, 0.277, 0.811],
            [0.277, 0.937, -0.214, 0.0],
            [-0.214, 0.277, 0.937, 1.651],
            [0.0, 0.0, 0.0, 1.0],
        ],
        atol=5e-4,
    )


def test_bad_arguments_are_refused() -> None:
    xs = np.eye(4)
    cases: list[tuple[Callable[[], object], str]] = [
        (lambda: trajectory.joint_trajectory([0, 1], [1, 2], 1.0, 5, 4), "method 4"),
        (lambda: trajectory.joint_trajectory([0, 1], [1, 2], 0.0, 5, 3), "Tf"),
        (lambda: trajectory.joint_trajectory([0, 1], [1, 2], 1.0, 1, 3), "N 1"),
        (lambda: trajectory.joint_trajectory([0, 1], [1, 2, 3], 1.0, 5, 3), "same shape"),
        (lambda: trajectory.joint_trajectory([0, np.nan], [1, 2], 1.0, 5, 3), "finite"),
        (lambda: trajectory.screw_trajectory(xs, 2 * xs, 1.0, 5, 3), "Xend"),
        (lambda: trajectory.cartesian_trajectory(xs, xs[:3], 1.0, 5, 3), "shape"),
        (lambda: trajectory.cubic_time_scaling(-1.0, 0.5), "Tf"),
    ]
    for call, says in cases:
        with pytest.raises(ValueError, match=says):
            call()


def test_the_modules_examples_run() -> None:
    result = doctest.testmod(trajectory)
    assert result.attempted > 0 and result.failed == 0
    assert "trajectory" in screwkit.__all__
