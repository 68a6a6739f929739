"""The stubs' single-versus-batch overloads: nested lists of one matrix or of a stack pick the
overload whose type the call really returns. `assert_type` is checked by mypy (the suite's type
check runs on this file); the isinstance checks hold the same at run time."""

from __future__ import annotations

import sys
from typing import Any

if sys.version_info >= (3, 11):
    from typing import assert_type
else:  # mypy's own dependency, in every venv the suite runs in
    from typing_extensions import assert_type

import numpy as np
import numpy.typing as npt

import screwkit
from screwkit import lie

from conftest import ASSETS


def test_one_target_and_a_stack_of_lists_have_their_own_types() -> None:
    robot = screwkit.Robot.from_urdf(ASSETS / "ur5.urdf")
    q = [0.1, -0.5, 1.0, 0.2, 0.3, -0.4]
    pose: list[list[float]] = robot.fk(np.array(q)).tolist()
    one = assert_type(robot.ik(pose), screwkit.IkResult)
    assert isinstance(one, screwkit.IkResult) and one.converged
    many = assert_type(robot.ik([pose, pose]), screwkit.IkBatchResult)
    assert isinstance(many, screwkit.IkBatchResult) and many.q.shape == (2, 6)
    sols = assert_type(robot.ik_all(pose), npt.NDArray[np.float64])
    assert isinstance(sols, np.ndarray) and sols.shape[1] == 6
    lists = assert_type(robot.ik_all([pose, pose]), list[npt.NDArray[np.float64]])
    assert isinstance(lists, list) and len(lists) == 2
    # A numpy array: either answer, by its shape at run time.
    either = robot.ik(np.array(pose))
    assert_type(either, screwkit.IkResult | screwkit.IkBatchResult)
    assert isinstance(either, screwkit.IkResult)


def test_scalar_answers_of_the_screw_calculus_are_typed_by_their_input() -> None:
    r: list[list[float]] = np.eye(3).tolist()
    t: list[list[float]] = np.eye(4).tolist()
    d = assert_type(lie.distance_to_so3(r), float)
    assert isinstance(d, float) and d == 0.0
    assert isinstance(assert_type(lie.distance_to_se3(t), float), float)
    assert assert_type(lie.is_so3(r), bool) is True
    assert assert_type(lie.is_se3(t), bool) is True
    ds = assert_type(lie.distance_to_so3([r, r]), npt.NDArray[np.float64])
    assert isinstance(ds, np.ndarray) and ds.shape == (2,)
    flags = assert_type(lie.is_se3([t, t]), npt.NDArray[np.bool_])
    assert isinstance(flags, np.ndarray) and flags.dtype == np.bool_ and flags.all()
    anything = assert_type(lie.is_so3(np.eye(3)), Any)
    assert anything is True
