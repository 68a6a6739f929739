"""Time-optimal timing of a joint path (`screwkit.time_parameterize`, TOPP-RA) against the
`toppra` package of the method's authors: on random 6-joint paths of 5 to 50 waypoints (joined
by the same not-a-knot spline over s = 0 … 1), the duration is within 1 % of toppra's on a
2,000-interval grid, and no 1 kHz sample exceeds a velocity or acceleration limit (toppra's own
answer does, by up to a few percent); the timed path passes through the waypoints in order,
starts and ends at rest; and closed forms: a straight line is bang-coast-bang."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

import screwkit

F64 = npt.NDArray[np.float64]


def toppra_duration(way: F64, vlim: F64, alim: F64) -> tuple[float, float]:
    """toppra's duration and its largest limit excess sampled at 1 kHz."""
    ta: Any = pytest.importorskip(
        "toppra", reason="toppra (pip install toppra) is a test dependency"
    )
    algorithm, constraint = ta.algorithm, ta.constraint

    ta.setup_logging("WARNING")
    path = ta.SplineInterpolator(np.linspace(0, 1, len(way)), way)
    vel = constraint.JointVelocityConstraint(np.stack([-vlim, vlim], 1))
    acc = constraint.JointAccelerationConstraint(
        np.stack([-alim, alim], 1),
        discretization_scheme=constraint.DiscretizationType.Interpolation,
    )
    inst = algorithm.TOPPRA(
        [vel, acc], path, gridpoints=np.linspace(0, 1, 2001), parametrizer="ParametrizeConstAccel"
    )
    traj = inst.compute_trajectory()
    ts = np.arange(0, traj.duration, 1e-3)
    excess = max((np.abs(traj(ts, 1)) / vlim).max(), (np.abs(traj(ts, 2)) / alim).max())
    return float(traj.duration), float(excess)


@pytest.mark.parametrize("waypoints", [5, 10, 20, 50])
def test_durations_equal_toppras_and_no_sample_exceeds_a_limit(waypoints: int) -> None:
    rng = np.random.default_rng(waypoints)
    way = np.cumsum(rng.normal(scale=0.4, size=(waypoints, 6)), axis=0)
    vlim, alim = rng.uniform(0.5, 2.0, 6), rng.uniform(1.0, 4.0, 6)
    theirs, their_excess = toppra_duration(way, vlim, alim)
    ours = screwkit.time_parameterize(way, vlim, alim)
    assert abs(ours.duration / theirs - 1) < 0.01, (ours.duration, theirs)
    ts = np.arange(0, ours.duration, 1e-3)
    q, qd, qdd = ours.sample(ts)
    assert (np.abs(qd) / vlim).max() <= 1 + 1e-9
    assert (np.abs(qdd) / alim).max() <= 1 + 1e-9
    print(
        f"{waypoints} waypoints: ours {ours.duration:.4f} s, toppra {theirs:.4f} s "
        f"(toppra exceeds a limit by {100 * (their_excess - 1):.2f} % at 1 kHz)"
    )
    # Through the waypoints in order, at rest at both ends.
    np.testing.assert_allclose(ours(0.0), way[0], atol=1e-12)
    np.testing.assert_allclose(ours(ours.duration), way[-1], atol=1e-12)
    _, v0, _ = ours.sample(0.0)
    _, v1, _ = ours.sample(ours.duration)
    assert np.abs(v0).max() < 1e-12 and np.abs(v1).max() < 1e-9
    grid = ours.grid_times
    assert np.all(np.diff(grid) > 0) and grid[0] == 0 and grid[-1] == ours.duration
    # Every waypoint is passed: some sample comes within the path's sampling distance of it.
    dense = ours(np.linspace(0, ours.duration, 20_000))
    for w in way:
        assert np.linalg.norm(dense - w, axis=1).min() < 0.01


def test_a_straight_line_is_bang_coast_bang() -> None:
    """Two joints along one line, |Δq| = (1, 2) rad, v = (1, 1), a = (2, 2): joint 2 binds,
    T = d/v + v/a = 2.5 s (within the grid's 1 %)."""
    way = np.linspace([0.0, 0.0], [1.0, 2.0], 6)
    timed = screwkit.time_parameterize(way, [1.0, 1.0], [2.0, 2.0])
    assert abs(timed.duration - 2.5) < 0.025
    _, qd, _ = timed.sample(1.25)
    np.testing.assert_allclose(qd, [0.5, 1.0], atol=1e-6)


def test_bad_inputs_are_refused() -> None:
    way = np.zeros((4, 2))
    way[:, 0] = np.linspace(0, 1, 4)
    cases: list[tuple[tuple[Any, Any, Any], str]] = [
        ((way[:1], [1, 1], [1, 1]), "at least 2 waypoints"),
        ((way, [1, 1, 1], [1, 1]), r"vel_limits: expected shape \(2,\)"),
        ((way, [1, 0], [1, 1]), "velocity limit of joint 1"),
        ((way, [1, 1], [1, np.inf]), "acceleration limit of joint 1"),
        ((np.where(way == 1, np.nan, way), [1, 1], [1, 1]), "not finite"),
        ((way[0], [1, 1], [1, 1]), "path: expected shape"),
    ]
    for args, says in cases:
        with pytest.raises(ValueError, match=says):
            screwkit.time_parameterize(*args)
    with pytest.raises(ValueError, match="not a finite time"):
        screwkit.time_parameterize(way, [1, 1], [1, 1]).sample(np.array([np.nan]))
