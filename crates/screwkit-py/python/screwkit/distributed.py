"""Reachability maps on a Ray cluster: the shards of a map run as Ray tasks, each loading the
robot once and solving its part with the GIL released on all the cores it gets; the driver
merges them into the map one machine computes, byte for byte. A task whose worker dies is
retried by Ray (``max_retries``); a shard's result depends only on the spec and its voxels, so
a retry gives the same bytes.

Needs Ray: ``pip install "screwkit[ray]"``.
"""

from __future__ import annotations

import os
import pickle
import tempfile
from typing import Any, Literal

from . import _screwkit
from ._screwkit import Robot
from .reach import Bounds, ReachMap, _check, _collision_margin, _unsaved, merge


def _shard_task(
    robot: Robot, spec: dict[str, Any], index: int, count: int
) -> bytes:  # pragma: no cover - runs in a Ray worker
    fd, path = tempfile.mkstemp(suffix=".npz", prefix=f"screwkit-shard{index}-")
    os.close(fd)
    try:
        _screwkit._reach_build(robot, path, shard_index=index, shard_count=count, **spec)
        with open(path, "rb") as f:
            return f.read()
    finally:
        os.remove(path)


def reach(
    robot: Robot | str,
    resolution: float = 0.05,
    orientations: int = 50,
    *,
    base: str | None = None,
    tip: str | None = None,
    mode: Literal["free", "directions"] = "free",
    bounds: Bounds | None = None,
    solver: Literal["auto", "analytic", "numerical"] = "auto",
    seed: int = 0,
    restarts: int = 5,
    iterations: int = 100,
    shards: int | None = None,
    address: str | None = None,
    path: str | None = None,
    max_retries: int = 3,
    avoid_collisions: bool = False,
    margin: float = 0.0,
    obstacles: str | os.PathLike[str] | None = None,
) -> ReachMap:
    """The reachability map of ``robot`` (a :class:`screwkit.Robot`, or a URDF path with
    ``base``/``tip``) computed as ``shards`` Ray tasks (default: 4 per CPU of the cluster).

    Uses the running Ray session, or connects to ``address`` (``"auto"``, ``"ray://…"``;
    ``None`` starts a local one). Each task is retried up to ``max_retries`` times when its
    worker dies. The other arguments are those of :func:`screwkit.reach`; the result equals its
    map exactly. ``path``: where the merged map is written (default: a temporary file).
    ``obstacles`` (a scene file) is read here, on the driver: the tasks get the robot with
    them.
    """
    import ray

    _check(resolution, orientations)
    collision_margin = _collision_margin(avoid_collisions, margin, obstacles)
    arm: Robot = Robot.from_urdf(robot, base, tip) if isinstance(robot, str) else robot
    if obstacles is not None:
        # A copy (the caller's robot keeps its body), pickled to the tasks with the obstacles.
        arm = pickle.loads(pickle.dumps(arm))
        arm.add_obstacles(os.fspath(obstacles))
    if not ray.is_initialized():
        ray.init(address=address, ignore_reinit_error=True, log_to_driver=False)
    if shards is None:
        cpus = ray.cluster_resources().get("CPU", 1)  # type: ignore[no-untyped-call]
        shards = max(1, 4 * int(cpus))
    spec: dict[str, Any] = dict(
        resolution=resolution,
        orientations=orientations,
        mode=mode,
        bounds=None if bounds is None else tuple(float(b) for b in bounds),
        solver=solver,
        seed=seed,
        restarts=restarts,
        iterations=iterations,
        collision_margin=collision_margin,
    )
    task = ray.remote(max_retries=max_retries, retry_exceptions=False)(_shard_task)
    robot_ref = ray.put(arm)
    refs = [task.remote(robot_ref, spec, i, shards) for i in range(shards)]
    with tempfile.TemporaryDirectory(prefix="screwkit-reach-") as tmp:
        files = []
        for i, ref in enumerate(refs):
            f = os.path.join(tmp, f"shard{i}.npz")
            with open(f, "wb") as out:
                out.write(ray.get(ref))
            files.append(f)
        if path is not None:
            return merge(files, path)
        merged = os.path.join(tmp, "map.npz")
        return _unsaved(merge(files, merged))
