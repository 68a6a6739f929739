"""Every documented error: the documented exception, with a message naming the thing at fault."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

import screwkit

from conftest import ASSETS

UR5 = ASSETS / "ur5.urdf"


def test_missing_file() -> None:
    with pytest.raises(FileNotFoundError, match=r"no_such\.urdf: cannot read the file"):
        screwkit.Robot.from_urdf("no_such.urdf")


def test_directory_is_not_a_file(tmp_path: Path) -> None:
    with pytest.raises(IsADirectoryError, match=str(tmp_path)):
        screwkit.Robot.from_urdf(tmp_path)


def test_bad_urdf(tmp_path: Path) -> None:
    f = tmp_path / "broken.urdf"
    f.write_text("<robot name='x'><link name='a'/><joint name='j' type='revolute'>")
    with pytest.raises(ValueError, match=r"broken\.urdf: malformed XML"):
        screwkit.Robot.from_urdf(f)
    f.write_text("")
    with pytest.raises(ValueError, match=r"broken\.urdf: the file is empty"):
        screwkit.Robot.from_urdf(f)
    bad_axis = """<robot name="r"><link name="a"/><link name="b"/>
      <joint name="elbow" type="revolute"><parent link="a"/><child link="b"/>
      <axis xyz="0 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"""
    with pytest.raises(ValueError, match=r"mine\.urdf: .*elbow"):
        screwkit.Robot.from_string(bad_axis, source="mine.urdf")
    with pytest.raises(ValueError, match="<string>"):
        screwkit.Robot.from_string("<robot name='x'>")


def test_unknown_links() -> None:
    with pytest.raises(ValueError, match=r'unknown link "hand"'):
        screwkit.Robot.from_urdf(UR5, tip="hand")
    with pytest.raises(ValueError, match=r'unknown link "plinth"'):
        screwkit.Robot.from_urdf(UR5, base="plinth")
    with pytest.raises(ValueError, match=r"not an ancestor"):
        screwkit.Robot.from_urdf(UR5, base="tool0", tip="base_link")
    # A file with several leaves loads as the whole tree; what needs a chain says why.
    whole = screwkit.Robot.from_urdf(ASSETS / "torso_two_arms.urdf")
    with pytest.raises(ValueError, match=r"cannot choose a tip link"):
        whole.ik_all(np.eye(4))
    with pytest.raises(ValueError, match=r"cannot choose a tip link"):
        _ = whole.tip


def test_wrong_shapes(ur5: screwkit.Robot) -> None:
    for bad in ([0.1, 0.2], np.zeros((2, 5)), np.zeros((2, 3, 6)), 1.0):
        with pytest.raises(
            ValueError,
            match=r"q: expected shape \(6,\) or \(N, 6\) for the joints shoulder_pan_joint",
        ):
            ur5.fk(bad)
        with pytest.raises(ValueError, match=r"q: expected shape"):
            ur5.jacobian(bad)
        with pytest.raises(ValueError, match=r"q: expected shape"):
            ur5.fk_all_links(bad)
    with pytest.raises(
        ValueError, match=r"target: expected shape \(4, 4\) or \(N, 4, 4\), got \(3, 4\)"
    ):
        ur5.ik(np.eye(4)[:3])
    with pytest.raises(ValueError, match=r"seed: expected shape \(6,\)"):
        ur5.ik(np.eye(4), seed=[0.0] * 5)
    with pytest.raises(ValueError, match=r"seed: 2 seeds for 3 targets"):
        ur5.ik(np.stack([np.eye(4)] * 3), seed=np.zeros((2, 6)))
    with pytest.raises(ValueError, match=r"analyze takes one configuration"):
        ur5.analyze(np.zeros((2, 6)))
    with pytest.raises(ValueError, match=r"T: expected shape \(4, 4\)"):
        screwkit.log(np.eye(3))
    with pytest.raises(ValueError, match=r"twist"):
        screwkit.exp([1.0, 2.0])


def test_not_numbers(ur5: screwkit.Robot) -> None:
    with pytest.raises(ValueError, match=r"q: expected real numbers, got an array of dtype <U"):
        ur5.fk(["a"] * 6)
    with pytest.raises(
        ValueError, match=r"q: expected real numbers, got an array of dtype complex128"
    ):
        ur5.fk(np.zeros(6, dtype=complex))
    with pytest.raises(ValueError, match=r"q: expected real numbers, got an array of dtype bool"):
        ur5.fk([True] * 6)
    with pytest.raises(ValueError, match=r"q: not an array of numbers"):
        ur5.fk([[0.0] * 6, [0.0] * 5])


def test_nan(ur5: screwkit.Robot) -> None:
    q = np.zeros(6)
    q[4] = np.nan
    with pytest.raises(ValueError, match=r"joint value #4 \(wrist_2_joint\) is not finite: NaN"):
        ur5.fk(q)
    with pytest.raises(ValueError, match=r"wrist_2_joint"):
        ur5.jacobian(q, "body")
    with pytest.raises(ValueError, match=r"wrist_2_joint"):
        ur5.analyze(q)
    with pytest.raises(ValueError, match=r"wrist_2_joint"):
        ur5.ik(np.eye(4), seed=q)
    t = np.eye(4)
    t[1, 3] = np.nan
    with pytest.raises(ValueError, match=r"target"):
        ur5.ik(t)
    with pytest.raises(ValueError, match=r"target: not a rigid transform"):
        ur5.ik(np.diag([2.0, 1.0, 1.0, 1.0]))
    with pytest.raises(ValueError, match=r"theta"):
        screwkit.exp([0, 0, 1, 0, 0, 0], float("nan"))


def test_bad_options(ur5: screwkit.Robot) -> None:
    t = ur5.home
    with pytest.raises(
        ValueError, match=r'frame: .*"sky".*expected "space", "body" or "world-aligned"'
    ):
        ur5.jacobian(np.zeros(6), frame="sky")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r'method: unknown IK method "bfgs"'):
        ur5.ik(t, method="bfgs")  # type: ignore[call-overload]
    with pytest.raises(ValueError, match=r"timeout_ms"):
        ur5.ik(t, timeout_ms=-1.0)
    with pytest.raises(ValueError, match=r"weights: needs 6 numbers"):
        ur5.ik(t, weights=[1.0, 1.0])
    with pytest.raises(ValueError, match=r"tol"):
        ur5.ik(t, tol_rot=-1.0)
    with pytest.raises(ValueError, match=r"damping"):
        ur5.ik(t, method="nr", damping=0.1)
    with pytest.raises(ValueError, match=r"fmt: unknown table format"):
        ur5.table("xml")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"threads"):
        screwkit.set_num_threads(-2)
    with pytest.raises(OverflowError):
        ur5.ik(t, seed_rng=-1)


def test_robot_pickles(ur5: screwkit.Robot) -> None:
    again = pickle.loads(pickle.dumps(ur5))
    assert repr(again) == repr(ur5)
    q = np.linspace(-1, 1, 6)
    np.testing.assert_array_equal(again.fk(q), ur5.fk(q))
