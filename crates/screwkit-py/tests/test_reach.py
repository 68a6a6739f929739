"""Reachability maps from Python: numpy reads them, shards and threads give the same file, the
index agrees with IK pose by pose, errors raise the documented exceptions; and on a local Ray
cluster the distributed map equals the one-machine map, also when workers are killed mid-run."""

from __future__ import annotations

import json
import subprocess
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import screwkit

from conftest import ASSETS


def test_map_arrays_and_shards(ur5: screwkit.Robot, tmp_path: Path) -> None:
    whole = tmp_path / "whole.npz"
    m = screwkit.reach(ur5, 0.2, 12, path=str(whole))
    nv = int(np.prod(m.grid_shape))
    assert m.index.shape == (nv,) and m.pose_manipulability.shape == (nv, 12)
    assert m.centres.shape == (nv, 3) and m.orientations.shape == (12, 3, 3)
    assert m.meta["solver"] == "analytic" and m.meta["spec"]["orientations"] == 12
    # The index is the reached fraction of each voxel's poses.
    reached = ~np.isnan(m.pose_manipulability)
    np.testing.assert_array_equal(m.index, reached.mean(axis=1))
    assert 0.05 < m.reached_fraction < 0.9
    # Voxel centres on the grid, C order.
    i, j, k = np.unravel_index(np.arange(nv), m.grid_shape)
    expected = m.grid_origin + np.stack([i, j, k], axis=1) * m.resolution
    np.testing.assert_allclose(m.centres, expected, atol=1e-12)
    # Orientations are rotations.
    for r in m.orientations:
        np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
    # Shards merged = the whole file, byte for byte; thread count does not matter.
    parts = []
    for s in (1, 0, 2):
        p = tmp_path / f"s{s}.npz"
        screwkit.reach(ur5, 0.2, 12, path=str(p), shard=(s, 3))
        parts.append(str(p))
    merged = tmp_path / "merged.npz"
    screwkit.merge(parts, str(merged))
    assert merged.read_bytes() == whole.read_bytes()
    screwkit.set_num_threads(1)
    try:
        one = tmp_path / "one.npz"
        screwkit.reach(ur5, 0.2, 12, path=str(one))
    finally:
        screwkit.set_num_threads(None)
    assert one.read_bytes() == whole.read_bytes()
    svg = m.svg()
    assert svg.startswith("<svg") and svg.count('class="panel"') == 3


def test_reached_poses_have_solutions(ur5: screwkit.Robot) -> None:
    """Every pose the map reaches has analytic solutions whose FK is the pose, within the
    limits; every pose it does not reach has none (ik_all's FK-checked answers)."""
    m = screwkit.reach(ur5, 0.25, 6)
    rng = np.random.default_rng(3)
    voxels = rng.choice(len(m.index), 300, replace=False)
    targets = np.tile(np.eye(4), (len(voxels) * 6, 1, 1))
    for n, (v, k) in enumerate((v, k) for v in voxels for k in range(6)):
        targets[n, :3, :3] = m.orientations[k]
        targets[n, :3, 3] = m.centres[v]
    # The poses out of reach are the batch's bad rows (as the single call raises on them).
    with pytest.raises(screwkit.BatchError) as e:
        ur5.ik_all(targets)
    sols = e.value.result
    assert isinstance(sols, list)
    unreached = [
        n
        for n, (v, k) in enumerate((v, k) for v in voxels for k in range(6))
        if np.isnan(m.pose_manipulability[v, k])
    ]
    assert e.value.rows == unreached
    for n, (v, k) in enumerate((v, k) for v in voxels for k in range(6)):
        assert (len(sols[n]) > 0) == (not np.isnan(m.pose_manipulability[v, k])), (v, k)
        for q in sols[n]:
            np.testing.assert_allclose(ur5.fk(q), targets[n], atol=1e-9)
            assert np.all(q >= ur5.lower - 1e-9) and np.all(q <= ur5.upper + 1e-9)
    assert sum(len(s) > 0 for s in sols) > 100


def test_errors(ur5: screwkit.Robot, panda: screwkit.Robot, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="resolution"):
        screwkit.reach(ur5, 0.0, 5)
    with pytest.raises(ValueError, match="orientations"):
        screwkit.reach(ur5, 0.1, 0)
    with pytest.raises(ValueError, match="mode"):
        screwkit.reach(ur5, 0.3, 5, mode="sideways")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="numerical"):
        screwkit.reach(panda, 0.3, 5, solver="analytic")
    with pytest.raises(ValueError, match="shard"):
        screwkit.reach(ur5, 0.3, 5, shard=(2, 2))
    with pytest.raises(OSError):
        screwkit.reach(ur5, 0.3, 5, path=str(tmp_path / "no" / "such" / "dir.npz"))
    p = tmp_path / "s0.npz"
    screwkit.reach(ur5, 0.3, 5, path=str(p), shard=(0, 2))
    with pytest.raises(ValueError, match="1 of 2 shards"):
        screwkit.merge([str(p)], str(tmp_path / "m.npz"))
    with pytest.raises(ValueError, match="shard"):
        screwkit.ReachMap.load(str(p)).svg()


def test_ray_cluster_equals_one_machine(ur5: screwkit.Robot, tmp_path: Path) -> None:
    import ray

    from screwkit import distributed

    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        local = screwkit.reach(ur5, 0.2, 10)
        far = distributed.reach(ur5, 0.2, 10, shards=5)
        for name in ("index", "best_manipulability", "pose_manipulability", "centres"):
            np.testing.assert_array_equal(getattr(far, name), getattr(local, name))
        # From a file name, as on a cluster whose workers load the robot themselves.
        by_path = distributed.reach(str(ASSETS / "ur5.urdf"), 0.2, 10, shards=3)
        np.testing.assert_array_equal(by_path.pose_manipulability, local.pose_manipulability)

        # A map clear of contact (the UR5 with a sphere on its flange, a box from a scene file
        # read on the driver and pickled to the tasks with the robot): the same on the cluster.
        urdf = tmp_path / "ur5.urdf"
        sphere = '<collision><geometry><sphere radius="0.05"/></geometry></collision>'
        urdf.write_text(
            (ASSETS / "ur5.urdf")
            .read_text()
            .replace('<link name="wrist_3_link"/>', f'<link name="wrist_3_link">{sphere}</link>')
        )
        arm = screwkit.Robot.from_urdf(str(urdf))
        scene = tmp_path / "scene.json"
        box = {"name": "box", "shape": "box", "size": [0.6, 0.6, 0.6], "xyz": [0.5, 0.0, 0.0]}
        scene.write_text(json.dumps({"obstacles": [box]}))
        spec: dict[str, Any] = dict(avoid_collisions=True, obstacles=scene)
        near = screwkit.reach(arm, 0.2, 10, **spec)
        clear = distributed.reach(arm, 0.2, 10, shards=3, **spec)
        np.testing.assert_array_equal(clear.pose_manipulability, near.pose_manipulability)
        assert clear.meta["body"] == near.meta["body"] and arm.obstacles == []
        kept = np.sum(~np.isnan(near.pose_manipulability))
        assert 0 < kept < np.sum(~np.isnan(local.pose_manipulability))

        # Workers killed mid-run: Ray retries their tasks and the map is still the same.
        big = screwkit.reach(ur5, 0.07, 16)
        result: dict[str, screwkit.ReachMap] = {}
        run = threading.Thread(
            target=lambda: result.setdefault(
                "map", distributed.reach(ur5, 0.07, 16, shards=4, max_retries=3)
            )
        )
        run.start()
        killed = False
        deadline = time.time() + 60
        while time.time() < deadline and run.is_alive() and not killed:
            pids = subprocess.run(
                ["pgrep", "-f", "_shard_task"], capture_output=True, text=True
            ).stdout.split()
            if pids:
                time.sleep(0.3)  # let them start computing
                subprocess.run(["kill", "-9", *pids], check=False)
                killed = True
            time.sleep(0.05)
        run.join(timeout=300)
        assert killed, "no shard worker seen running"
        got = result["map"]
        np.testing.assert_array_equal(got.pose_manipulability, big.pose_manipulability)
        np.testing.assert_array_equal(got.index, big.index)
    finally:
        ray.shutdown()
