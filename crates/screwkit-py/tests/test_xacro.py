"""Native xacro expansion against ROS's own xacro (the `xacro` package, run here as a library):
the same robot — links, joints, types, origins, axes, limits, mimic — on the nine real files of
the CI data (SCREWKIT_SHARED_XACRO) and on the cases built in
crates/screwkit-model/tests/xacro_cases."""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import screwkit

from conftest import REPO, configurations, shared_dir, shared_reason

xacro = pytest.importorskip("xacro", reason="ROS's xacro (pip install xacro) is a test oracle")

CASES = REPO / "crates" / "screwkit-model" / "tests" / "xacro_cases"
SHARED_FILES = [
    "kuka_kr3_support/urdf/kr3r540.xacro",
    "kuka_kr5_support/urdf/kr5_arc.xacro",
    "kuka_kr6_support/urdf/kr6r700sixx.xacro",
    "kuka_kr6_support/urdf/kr6r900sixx.xacro",
    "kuka_kr10_support/urdf/kr10r1100sixx.xacro",
    "kuka_kr16_support/urdf/kr16_2.xacro",
    "kuka_kr120_support/urdf/kr120r2500pro.xacro",
    "kuka_kr150_support/urdf/kr150_2.xacro",
    "abb_irb140/urdf/irb140.xacro",
]


def ros_expand(path: Path, packages: Path, args: dict[str, str] | None = None) -> str:
    """ROS's xacro, with $(find pkg) answered from `packages` (its own lookup needs ROS)."""
    import xacro.substitution_args as sa

    def find(pkg: str) -> str:
        for root, dirs, _ in os.walk(packages):
            if pkg in dirs:
                return os.path.join(root, pkg)
        raise LookupError(pkg)

    saved = sa._eval_find
    sa._eval_find = find
    try:
        doc = xacro.process_file(str(path), mappings=args or {})
    finally:
        sa._eval_find = saved
    return str(doc.toxml())


def robot_facts(xml: str) -> dict[str, Any]:
    """Links and joints with every number that matters for kinematics."""
    root = ET.fromstring(xml)

    def nums(e: ET.Element | None, attr: str, default: str) -> list[float]:
        text = e.get(attr, default) if e is not None else default
        return [float(x) for x in text.split()]

    joints = {}
    for j in root.findall("joint"):
        lim = j.find("limit")
        mimic = j.find("mimic")
        parent, child = j.find("parent"), j.find("child")
        assert parent is not None and child is not None
        joints[j.get("name")] = {
            "type": j.get("type"),
            "parent": parent.get("link"),
            "child": child.get("link"),
            "xyz": nums(j.find("origin"), "xyz", "0 0 0"),
            "rpy": nums(j.find("origin"), "rpy", "0 0 0"),
            "axis": nums(j.find("axis"), "xyz", "1 0 0"),
            "limit": None
            if lim is None
            else [float(lim.get(k, "nan")) for k in ("lower", "upper", "velocity", "effort")],
            "mimic": None if mimic is None else dict(mimic.attrib),
        }
    return {"links": sorted(link.get("name") for link in root.findall("link")), "joints": joints}


def assert_same_robot(ours: str, theirs: str) -> None:
    a, b = robot_facts(ours), robot_facts(theirs)
    assert a["links"] == b["links"]
    assert a["joints"].keys() == b["joints"].keys()
    for name, ja in a["joints"].items():
        jb = b["joints"][name]
        for k in ("type", "parent", "child", "mimic"):
            assert ja[k] == jb[k], (name, k)
        for k in ("xyz", "rpy", "axis", "limit"):
            if ja[k] is None or jb[k] is None:
                assert ja[k] is None and jb[k] is None, (name, k)
            else:
                np.testing.assert_allclose(ja[k], jb[k], rtol=0, atol=1e-12, err_msg=f"{name} {k}")


def shared_cases() -> Iterator[Any]:
    d = shared_dir("xacro")
    if d is None:
        skip = pytest.mark.skip(reason=shared_reason("xacro"))
        yield pytest.param(None, None, id="shared", marks=[pytest.mark.shared, skip])
        return
    for f in SHARED_FILES:
        yield pytest.param(d / f, d, id=f.split("/")[-1], marks=pytest.mark.shared)


@pytest.mark.parametrize(("path", "packages"), list(shared_cases()))
def test_real_files_expand_as_ros_xacro_does(path: Path, packages: Path) -> None:
    ours = screwkit.xacro(path, package_paths=[packages])
    assert_same_robot(ours, ros_expand(path, packages))
    robot = screwkit.Robot.from_urdf(path, tip="tool0", package_paths=[packages])
    reference = screwkit.Robot.from_string(ros_expand(path, packages), tip="tool0")
    qs = configurations(robot, 20, seed=61)
    np.testing.assert_allclose(robot.fk(qs), reference.fk(qs), rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("case", "args"),
    [
        ("macros", {}),
        ("expressions", {}),
        ("expressions", {"with_tool": "false", "scale": "1.5"}),
        ("includes", {}),
        ("substitutions", {}),
        ("substitutions", {"prefix": "right_", "len": "0.25"}),
    ],
)
def test_built_cases_expand_as_ros_xacro_does(case: str, args: dict[str, str]) -> None:
    path = CASES / f"{case}.xacro"
    ours = screwkit.xacro(path, package_paths=[CASES / "pkgs"], args=args)
    theirs = ros_expand(path, CASES / "pkgs", args)
    assert_same_robot(ours, theirs)
    # The committed reference is what ROS's xacro makes today.
    if not args:
        assert_same_robot((CASES / f"{case}.expected.urdf").read_text(), theirs)


def test_xacro_errors(tmp_path: Path) -> None:
    bad = tmp_path / "bad.xacro"
    bad.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<link name="${nope}"/></robot>'
    )
    with pytest.raises(ValueError, match=r"bad\.xacro:2: unknown property or name \"nope\""):
        screwkit.Robot.from_urdf(bad)
    with pytest.raises(ValueError, match=r"bad\.xacro:2"):
        screwkit.xacro(bad)
    with pytest.raises(FileNotFoundError):
        screwkit.xacro(tmp_path / "none.xacro")
