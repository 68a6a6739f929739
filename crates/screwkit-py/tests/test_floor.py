"""One floor for every front end: the same file, option words, defaults and joints give the same
answers from Python and from the command line, and the stubs show the floor's words and
defaults."""

from __future__ import annotations

import ast
import inspect
import json
import os
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import screwkit
from screwkit import _screwkit, distributed

from conftest import ASSETS

UR5 = ASSETS / "ur5.urdf"
PANDA = ASSETS / "panda.urdf"
STUB = Path(screwkit.__file__).with_name("_screwkit.pyi")


def cli(*args: str) -> Any:
    """The CLI's JSON answer (SCREWKIT_CLI: the binary `cargo xtask test` builds)."""
    exe = os.environ.get("SCREWKIT_CLI")
    if not exe or not Path(exe).exists():
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    out = subprocess.run([exe, *args, "--format", "json"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def encodings(tmp_path: Path) -> list[Path]:
    """The UR5 as UTF-8 with a byte-order mark and as declared Latin-1 with a non-ASCII name."""
    text = UR5.read_text()
    body = text.split("?>", 1)[1] if text.startswith("<?xml") else text
    bom = tmp_path / "bom.urdf"
    bom.write_bytes(b"\xef\xbb\xbf" + text.encode())
    latin = tmp_path / "latin.urdf"
    latin.write_bytes(
        b'<?xml version="1.0" encoding="ISO-8859-1"?>'
        + body.replace('name="ur5"', 'name="ur5_\xe9"').encode("latin-1")
    )
    return [bom, latin]


def test_bom_and_latin1_files_load_the_same_from_python_and_the_cli(tmp_path: Path) -> None:
    q = [0.1, -0.5, 1.0, 0.2, 0.3, -0.4]
    plain = screwkit.Robot.from_urdf(UR5).fk(np.array(q))
    want = cli("fk", str(UR5), "--q", ",".join(map(str, q)))["pose"]
    np.testing.assert_array_equal(plain, np.array(want))
    for path in encodings(tmp_path):
        np.testing.assert_array_equal(screwkit.Robot.from_urdf(path).fk(np.array(q)), plain)
        got = cli("fk", str(path), "--q", ",".join(map(str, q)))["pose"]
        np.testing.assert_array_equal(np.array(got), plain)


def test_a_lock_by_name_or_index_gives_the_same_solutions_everywhere() -> None:
    panda = screwkit.Robot.from_urdf(PANDA)
    q = np.array([0.1, -0.5, 0.2, -2.0, 0.3, 1.6, 0.8])
    t = panda.fk(q)
    by_name = panda.ik_all(t, q, lock="panda_joint6", lock_value=1.5)
    by_index = panda.ik_all(t, q, lock=5, lock_value=1.5)
    assert isinstance(by_name, np.ndarray) and len(by_name) > 0
    np.testing.assert_array_equal(by_name, by_index)
    assert np.all(by_name[:, 5] == 1.5)
    seed = ",".join(repr(float(x)) for x in q)
    target = ",".join(repr(float(x)) for x in t.ravel())
    for lock in ["panda_joint6=1.5", "5=1.5"]:
        v = cli(
            "ik", str(PANDA), "--target-matrix", target, "--all", "--seed", seed, "--lock", lock
        )
        assert v["locked"] == {"joint": "panda_joint6", "index": 5, "values": [1.5]}
        np.testing.assert_array_equal(np.array([s["q"] for s in v["solutions"]]), by_name)


def test_signature_defaults_are_the_floors() -> None:
    d = _screwkit._defaults()
    ik = inspect.signature(screwkit.Robot.ik).parameters
    for name, value in d["ik"].items():
        assert ik[name].default == value, name
    fns: list[Callable[..., object]] = [screwkit.reach, distributed.reach]
    for fn in fns:
        reach = inspect.signature(fn).parameters
        for name, value in d["reach"].items():
            assert reach[name].default == value, (fn, name)
    viewer = inspect.signature(screwkit.Robot.viewer).parameters
    for name, value in d["viewer"].items():
        assert viewer[name].default == value, name
    srdf = inspect.signature(screwkit.Robot.write_srdf).parameters
    for name, value in d["write_srdf"].items():
        assert srdf[name].default == value, name
    # Whole-body IK: the library's TasksOptions, Limits and Task defaults.
    tasks_methods: list[Callable[..., object]] = [
        screwkit.Robot.ik_tasks,
        screwkit.Robot.ik_trajectory,
    ]
    for method in tasks_methods:
        params = inspect.signature(method).parameters
        for name, value in d["ik_tasks"].items():
            assert params[name].default == value, (method, name)
    step_methods: list[Callable[..., object]] = [screwkit.Robot.ik_step, screwkit.Robot.ik_step_qp]
    for method in step_methods:
        params = inspect.signature(method).parameters
        for name, value in d["ik_step"].items():
            assert params[name].default == value, (method, name)
    # Every task class against its JSON type, field by field: a default the signature shows
    # is the floor's (a weight of None leaves the floor's per-axis weights), and a field the
    # class does not expose is left to the floor (checked on the resolved tasks below).
    classes: dict[str, type] = {
        "frame": screwkit.FrameTask,
        "relative": screwkit.RelativeFrameTask,
        "axis": screwkit.AxisTask,
        "com": screwkit.ComTask,
        "posture": screwkit.PostureTask,
        "damping": screwkit.DampingTask,
    }
    assert sorted(classes) == sorted(d["tasks"])
    for kind, cls in classes.items():
        params = inspect.signature(cls).parameters
        fields = d["tasks"][kind]
        assert set(fields) == {
            "gain",
            "weight",
            "position_weight",
            "orientation_weight",
            "tol_pos",
            "tol_rot",
        }
        shown = [name for name in fields if name in params]
        assert "weight" in shown, cls
        for name in shown:
            default = params[name].default
            if default is None:
                assert name.endswith("_weight"), (cls, name)
            elif isinstance(fields[name], list):
                assert [default] * 3 == fields[name], (cls, name)
            else:
                assert default == fields[name], (cls, name)
    assert d["tasks"]["damping"]["weight"] == 1e-3 and d["tasks"]["frame"]["weight"] == 1.0
    # The numbers behind them are the library's (IkOptions::default, ReachSpec::default).
    assert d["ik"]["tol_rot"] == 1e-9 and d["ik"]["max_restarts"] == 200
    assert d["reach"]["resolution"] == 0.05 and d["reach"]["orientations"] == 50


def stub_literals() -> dict[str, list[str]]:
    """The `_Name: TypeAlias = Literal[...]` aliases of the stub."""
    out: dict[str, list[str]] = {}
    for node in ast.parse(STUB.read_text()).body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            v = node.value
            if isinstance(v, ast.Subscript) and getattr(v.value, "id", "") == "Literal":
                elts = v.slice.elts if isinstance(v.slice, ast.Tuple) else [v.slice]
                out[node.target.id] = [
                    e.value
                    for e in elts
                    if isinstance(e, ast.Constant) and isinstance(e.value, str)
                ]
    return out


def test_stub_words_are_the_floors() -> None:
    words = _screwkit._words()
    lit = stub_literals()
    for alias, family in [
        ("_Frame", "screw_frame"),
        ("_JacobianFrame", "jacobian_frame"),
        ("_TableFormat", "table_format"),
        ("_TableFrames", "table_frames"),
        ("_Views", "views"),
        ("_Labels", "labels"),
        ("_Method", "method"),
        ("_Geometry", "geometry"),
        ("_Meshes", "meshes"),
        ("_Collisions", "collisions"),
        ("_Inertias", "inertias"),
        ("_Interpolation", "interpolation"),
    ]:
        assert sorted(lit[alias]) == sorted(words[family]), alias
    for family in ["orientation_mode", "solver_choice"]:
        for w in words[family]:
            assert f'"{w}"' in inspect.getsource(screwkit.reach), (family, w)


def test_an_unknown_word_lists_the_floors_words() -> None:
    robot = screwkit.Robot.from_urdf(UR5)
    with pytest.raises(ValueError, match='method: unknown IK method "newton": expected "lm"'):
        robot.ik(robot.home, method="newton")  # type: ignore[call-overload]
    with pytest.raises(ValueError, match='view: unknown view "back"'):
        robot.draw(view="back")  # type: ignore[arg-type]


def test_the_tool_frame_reaches_python(tmp_path: Path) -> None:
    tool = [0.0, 0.0, 0.1, 0.0, 0.0, 0.0]
    robot = screwkit.Robot.from_urdf(UR5, tool=tool)
    q = np.array([0.1, -0.5, 1.0, 0.2, 0.3, -0.4])
    want = cli("fk", str(UR5), "--q", ",".join(map(str, q)), "--tool", "0,0,0.1,0,0,0")["pose"]
    np.testing.assert_array_equal(robot.fk(q), np.array(want))
    import pickle

    again = pickle.loads(pickle.dumps(robot))
    np.testing.assert_array_equal(again.fk(q), robot.fk(q))
    with pytest.raises(ValueError, match="tool: needs 6 numbers"):
        screwkit.Robot.from_urdf(UR5, tool=[0.0, 0.1])


def test_reprs_are_one_short_line(tmp_path: Path) -> None:
    robot = screwkit.Robot.from_urdf(UR5)
    t = robot.fk(robot.midpoint)
    results: list[object] = [
        robot.ik(t),
        robot.ik(np.stack([t, t])),
        robot.analyze(robot.midpoint),
        screwkit.reach(robot, resolution=0.4, orientations=4),
        robot,
    ]
    for r in results:
        text = repr(r)
        assert "\n" not in text and len(text) < 200, text


@pytest.mark.parametrize(
    ("name", "tip"),
    [
        ("ur5.urdf", None),
        ("panda.urdf", None),
        ("humanoid.urdf", None),
        ("panda.urdf", "panda_link5"),
    ],
)
def test_info_is_the_clis_report(name: str, tip: str | None) -> None:
    """`Robot.info()` is the floor's report, the CLI's `info --format json` to the last key and
    number: one chain's (default or asked), or a tree's without one."""
    path = ASSETS / name
    robot = screwkit.Robot.from_urdf(path, tip=tip)
    args = ["info", str(path)] + (["--tip", tip] if tip else [])
    want = cli(*args)
    got = robot.info()
    assert got == want
    if name == "humanoid.urdf":
        assert got["default_chain"] is None and len(got["leaves"]) > 2
    else:
        chain = got["default_chain"]
        assert chain["tip"] == robot.tip and chain["dof"] == robot.dof
        assert [v["name"] for v in got["variables"]] == robot.variable_names


def test_collide_and_srdf_are_the_same_from_the_cli_and_python(tmp_path: Path) -> None:
    """`screwkit srdf` writes what `Robot.write_srdf` returns, and `screwkit collide` with that
    SRDF answers as `Robot.collisions`, `min_distance` and `distances` do with it, on the
    bundled humanoid's primitives (its hip shapes overlap in every pose: the SRDF disables
    them)."""
    path = ASSETS / "humanoid.urdf"
    robot = screwkit.Robot.from_urdf(path)
    exe = os.environ.get("SCREWKIT_CLI")
    if not exe or not Path(exe).exists():
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    srdf = tmp_path / "humanoid.srdf"
    subprocess.run(
        [exe, "srdf", str(path), "--samples", "300", "--seed", "3", "-o", str(srdf)], check=True
    )
    assert srdf.read_text() == robot.write_srdf(samples=300, seed=3)
    assert 'reason="Always"' in srdf.read_text()
    robot.srdf(srdf)
    rng = np.random.default_rng(11)
    lo, hi = np.maximum(robot.lower, -2.0), np.minimum(robot.upper, 2.0)
    seen = set()
    for _ in range(16):
        q = rng.uniform(lo, hi)
        got = cli(
            "collide", str(path), "--srdf", str(srdf), "--q", ",".join(repr(float(x)) for x in q)
        )
        seen.add(got["in_collision"])
        assert got["in_collision"] == robot.in_collision(q)
        assert [tuple(p) for p in got["collisions"]] == robot.collisions(q)
        assert got["pairs"] == len(robot.collision_pairs)
        assert got["min_distance"]["distance"] == robot.min_distance(q)
        d = robot.distances(q)
        k = int(np.argmin(d.distance))
        assert tuple(got["min_distance"]["pair"]) == d.pairs[k]
        np.testing.assert_array_equal(got["min_distance"]["points"], d.points[k])
    assert seen == {True, False}, "the configurations collide and do not"


def test_scene_obstacles_are_the_same_from_the_cli_and_python(tmp_path: Path) -> None:
    """`screwkit collide --obstacles scene.json` and `Robot.add_obstacles(scene.json)` read one
    scene (the floor's reader) and answer alike; the obstacles take part in the pairs."""
    exe = os.environ.get("SCREWKIT_CLI")
    if not exe or not Path(exe).exists():
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    path = ASSETS / "humanoid.urdf"
    scene = tmp_path / "scene.json"
    scene.write_text(
        json.dumps(
            {
                "obstacles": [
                    {"name": "floor", "shape": "box", "size": [4, 4, 0.1], "xyz": [0, 0, -1.0]},
                    {"name": "ball", "shape": "sphere", "radius": 0.15, "xyz": [0.35, 0, 0.1]},
                    {
                        "name": "bar",
                        "shape": "capsule",
                        "radius": 0.03,
                        "length": 1.0,
                        "rpy": [1.5707963267948966, 0, 0],
                        "xyz": [0.3, 0, 0.4],
                    },
                ]
            }
        )
    )
    robot = screwkit.Robot.from_urdf(path)
    before = len(robot.collision_pairs)
    assert robot.add_obstacles(scene) == ["floor", "ball", "bar"]
    assert robot.obstacles == ["floor", "ball", "bar"]
    assert len(robot.collision_pairs) > before
    rng = np.random.default_rng(5)
    lo, hi = np.maximum(robot.lower, -2.0), np.minimum(robot.upper, 2.0)
    hits = set()
    for _ in range(12):
        q = rng.uniform(lo, hi)
        got = cli(
            "collide",
            str(path),
            "--obstacles",
            str(scene),
            "--q",
            ",".join(repr(float(x)) for x in q),
        )
        assert got["pairs"] == len(robot.collision_pairs)
        assert [tuple(p) for p in got["collisions"]] == robot.collisions(q)
        assert got["min_distance"]["distance"] == robot.min_distance(q)
        hits |= {name for p in got["collisions"] for name in p if name in robot.obstacles}
        # --distances: every pair with its Jacobian row, as Python's distances(jacobians=True).
        every = cli(
            "collide",
            str(path),
            "--obstacles",
            str(scene),
            "--distances",
            "--q",
            ",".join(repr(float(x)) for x in q),
        )["distances"]
        d = robot.distances(q, jacobians=True)
        assert [tuple(p["pair"]) for p in every] == d.pairs
        np.testing.assert_array_equal([p["distance"] for p in every], d.distance)
        np.testing.assert_array_equal([p["jacobian"] for p in every], d.jacobian)
    assert hits, "some configuration touches an obstacle"
