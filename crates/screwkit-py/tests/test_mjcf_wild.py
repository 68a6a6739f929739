"""MJCF files from the wild against MuJoCo: every model of dm_control's suite, robosuite's robots
and gymnasium's MuJoCo environments, read as their packages ship them (the wheels, pinned and
hash-checked, downloaded from PyPI into target/wheels once; nothing is copied into the repository).
For random configurations within the limits, every body of the robot and every named site equals
MuJoCo's `xpos`/`xmat` (`site_xpos`/`site_xmat`) to 1e-12, MuJoCo compiling a mesh-free copy
(test_mjcf's `mesh_free`) and screwkit's q written into the model's `qpos0` by
`to_mujoco_qpos(q, qpos)`. Bodies the reader reads past (props beside the robot) are exactly
the top-level bodies it names in its warnings."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_mjcf import mesh_free, mujoco, pose

import screwkit

from conftest import wheel_files

# (distribution, version, sha256 of its PyPI wheel, the model files in it)
WHEELS = [
    (
        "dm_control",
        "1.0.52",
        "342505f32e041532dcdda0368b61df935ca04efa853b27dae522f615877a0fc3",
        "dm_control/suite/",
    ),
    (
        "robosuite",
        "1.5.2",
        "b9e02df55de8949739de6ba1d196d2ba59cf33c51a76efcfbe5c2f73cdcf99ce",
        "robosuite/models/assets/robots/",
    ),
    (
        "gymnasium",
        "1.4.0",
        "1cb947c59e7c72d8eabb2c2274c00cd20948e69f8452a9ef4092223be24fdf0e",
        "gymnasium/envs/mujoco/assets/",
    ),
]


def models() -> list[tuple[str, Path]]:
    """(id, path) of every model: dm_control's and gymnasium's top-level files, robosuite's
    robot.xml files."""
    out = []
    for dist, version, sha256, prefix in WHEELS:
        root = wheel_files(dist, version, sha256, prefix, ".xml")
        files = (
            sorted(root.glob("*/robot.xml")) if dist == "robosuite" else sorted(root.glob("*.xml"))
        )
        out += [
            (f"{dist}:{p.relative_to(root)}", p)
            for p in files
            if not p.name.endswith(".mujoco.xml")  # the mesh-free copies compiled below
        ]
    return out


# Files that are not a robot, with the reason.
NOT_MODELS = {
    "dm_control:lqr.xml": "a floor only: the suite builds the LQR chain in code",
}


@pytest.fixture(scope="module")
def wild() -> dict[str, Path]:
    return dict(models())


def test_the_wheels_hold_the_models_expected(wild: dict[str, Path]) -> None:
    counts = {dist: sum(k.startswith(dist + ":") for k in wild) for dist, *_ in WHEELS}
    assert counts == {"dm_control": 19, "robosuite": 12, "gymnasium": 14}, counts


def compile_mesh_free(path: Path) -> Any:
    text = mesh_free(path.read_text())
    # Includes are read from the file's folder: MuJoCo compiles a copy beside it.
    copy = path.with_name(path.stem + ".mujoco.xml")
    copy.write_text(text)
    return mujoco.MjModel.from_xml_path(str(copy))


def check(path: Path, configurations: int) -> float:
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = screwkit.Robot.from_file(path)
    read_past = {
        str(w.message).split("top-level body ")[1].split(" read past")[0]
        for w in said
        if "top-level body " in str(w.message)
    }
    model = compile_mesh_free(path)
    data = mujoco.MjData(model)
    names = set(robot.frame_names)
    # MuJoCo names bodies and sites apart; screwkit's frame of a site named like a body is
    # `site:NAME`, and an unnamed body is `body_K` (K counting the robot's bodies from 1).
    body_names = {model.body(b).name for b in range(model.nbody)}
    bodies: list[tuple[int, str]] = []
    for b in range(1, model.nbody):
        top = b
        while model.body_parentid[top] != 0:
            top = model.body_parentid[top]
        if model.body(top).name in read_past:
            continue
        name = model.body(b).name or f"body_{len(bodies) + 1}"
        assert name in names, f"{path.name}: body {name} is not in the robot"
        bodies.append((b, name))
    robot_bodies = {b for b, _ in bodies}
    if not robot.floating_base:
        robot_bodies.add(0)  # the world's sites are frames of the world link
    sites = [
        (s, f"site:{n}" if n in body_names else n)
        for s in range(model.nsite)
        if (n := model.site(s).name) and model.site_bodyid[s] in robot_bodies
    ]
    assert bodies, path.name
    worst = 0.0
    for seed in range(configurations):
        q = robot.random_configuration(seed)
        data.qpos[:] = robot.to_mujoco_qpos(q, model.qpos0)
        np.testing.assert_array_equal(robot.from_mujoco_qpos(data.qpos), q)
        mujoco.mj_kinematics(model, data)
        for b, name in bodies:
            want = pose(data.xpos[b], data.xmat[b])
            worst = max(worst, float(np.abs(robot.fk(q, link=name) - want).max()))
        for s, name in sites:
            want = pose(data.site_xpos[s], data.site_xmat[s])
            worst = max(worst, float(np.abs(robot.fk(q, link=name) - want).max()))
    return worst


@pytest.mark.parametrize("dist", [w[0] for w in WHEELS])
def test_every_model_in_the_wild_equals_mujoco(dist: str, wild: dict[str, Path]) -> None:
    results = {}
    for key, path in wild.items():
        if not key.startswith(dist + ":") or key in NOT_MODELS:
            continue
        results[key] = check(path, configurations=20)
    bad = {k: v for k, v in results.items() if not v < 1e-12}
    assert not bad, bad
    assert len(results) == {"dm_control": 18, "robosuite": 12, "gymnasium": 14}[dist], results
