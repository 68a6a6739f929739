"""Reachability maps: where an arm reaches, and with which orientations.

The workspace is cut into voxels; at every voxel centre K tool orientations are tested by
screwkit's IK (analytic, every solution, for 6R arms of revolute joints that are not
degenerate; numerical within the limits otherwise). A map holds per voxel the reachability
index (reached / K) and the best manipulability, per pose the best manipulability over its
solutions (NaN: not reached).
Maps are ``.npz`` files that numpy reads directly; :func:`reach` computes one on this machine
(the GIL released, on all cores), :func:`screwkit.distributed.reach` on a Ray cluster.
"""

from __future__ import annotations

import dataclasses
import json
import os
import tempfile
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from . import _screwkit
from ._screwkit import Robot

Bounds = tuple[float, float, float, float, float, float]


MAP_FORMAT = "screwkit reachability map 1"
"""The ``format`` of every map's ``meta``."""


@dataclass(frozen=True, repr=False)
class ReachMap:
    """A reachability map read from its ``.npz`` file.

    ``index`` and ``best_manipulability`` are per voxel (V,), ``centres`` (V, 3) in the base
    frame, ``pose_manipulability`` (V, K) per pose (NaN where not reached), ``orientations``
    (K, 3, 3) the tested tool rotations; the grid is ``grid_shape`` voxels of edge
    ``resolution`` from ``grid_origin``, voxel v = (i * ny + j) * nz + k, so
    ``index.reshape(grid_shape)`` is the index on the grid. ``meta`` holds the spec, robot,
    solver and shard.
    """

    index: npt.NDArray[np.float64]
    best_manipulability: npt.NDArray[np.float64]
    pose_manipulability: npt.NDArray[np.float64]
    centres: npt.NDArray[np.float64]
    orientations: npt.NDArray[np.float64]
    grid_origin: npt.NDArray[np.float64]
    grid_shape: tuple[int, int, int]
    resolution: float
    meta: dict[str, Any] = field(default_factory=dict)
    path: str | None = None

    @classmethod
    def load(cls, path: str) -> ReachMap:
        """Reads a map (or shard) written by :func:`reach`, ``screwkit reach`` or a merge.

        Raises ``OSError`` when the file cannot be read and ``ValueError`` naming the file
        when it is not a screwkit map or is damaged (a zip CRC that does not match, a missing
        or malformed array)."""
        try:
            z = np.load(path, allow_pickle=False)
        except OSError:
            raise
        except Exception as e:  # numpy's readers raise many types for a foreign file
            raise ValueError(f"{path}: not a screwkit reachability map ({e})") from e
        if not hasattr(z, "files"):
            raise ValueError(f"{path}: not a screwkit reachability map (a single array)")
        with z:
            try:
                meta = json.loads(str(z["meta"]))
                if not isinstance(meta, dict) or meta.get("format") != MAP_FORMAT:
                    raise ValueError("no screwkit map description")
                shape = tuple(int(s) for s in z["grid_shape"])
                if len(shape) != 3:
                    raise ValueError(f"grid_shape {shape} is not 3 numbers")
                return cls(
                    index=z["index"],
                    best_manipulability=z["best_manipulability"],
                    pose_manipulability=z["pose_manipulability"],
                    centres=z["centres"],
                    orientations=z["orientations"],
                    grid_origin=z["grid_origin"],
                    grid_shape=(shape[0], shape[1], shape[2]),
                    resolution=float(z["resolution"]),
                    meta=meta,
                    path=path,
                )
            except OSError:
                raise
            except Exception as e:  # BadZipFile (CRC), EOFError, KeyError, zlib.error, …
                raise ValueError(f"{path}: not a valid screwkit reachability map ({e})") from e

    def __repr__(self) -> str:
        k = self.orientations.shape[0]
        where = f", path={self.path!r}" if self.path is not None else ""
        return (
            f"ReachMap(voxels={self.index.shape[0]}, orientations={k}, "
            f"resolution={self.resolution}, reached={100 * self.reached_fraction:.1f}%{where})"
        )

    @property
    def reached_fraction(self) -> float:
        """Reached poses over all poses of the map."""
        return float(np.mean(~np.isnan(self.pose_manipulability)))

    def svg(self) -> str:
        """The SVG slices of the index through the base (xy, xz, yz) of a saved, whole map."""
        if self.path is None:
            raise ValueError("the map was not saved: compute it with path=... to draw it")
        return _screwkit._reach_svg(self.path)


def _check(resolution: float, orientations: int) -> None:
    if not (resolution > 0):
        raise ValueError(f"resolution: expected a positive length in metres, got {resolution}")
    if orientations < 1:
        raise ValueError(f"orientations: expected at least 1, got {orientations}")


def _collision_margin(
    avoid_collisions: bool, margin: float, obstacles: str | os.PathLike[str] | None
) -> float | None:
    """The spec's collision margin (None: the body is not looked at)."""
    if not avoid_collisions:
        if margin != 0.0:
            raise ValueError("margin applies with avoid_collisions=True")
        if obstacles is not None:
            raise ValueError("obstacles apply with avoid_collisions=True")
        return None
    return float(margin)


def reach(
    robot: Robot,
    resolution: float = 0.05,
    orientations: int = 50,
    *,
    mode: Literal["free", "directions"] = "free",
    bounds: Bounds | None = None,
    solver: Literal["auto", "analytic", "numerical"] = "auto",
    seed: int = 0,
    restarts: int = 5,
    iterations: int = 100,
    path: str | None = None,
    shard: tuple[int, int] | None = None,
    avoid_collisions: bool = False,
    margin: float = 0.0,
    obstacles: str | os.PathLike[str] | None = None,
) -> ReachMap:
    """The reachability map of ``robot`` on this machine.

    ``mode``: ``"free"`` (K rotations over SO(3)) or ``"directions"`` (the tool's z axis
    pointing at the voxel centre from K directions, as in capability maps). ``bounds``:
    (xmin, ymin, zmin, xmax, ymax, zmax) in metres, default the ball the chain can reach.
    ``solver``: ``"auto"``, ``"analytic"`` or ``"numerical"`` (``restarts`` and ``iterations``
    apply to it). ``path``: where the ``.npz`` is written (default: a temporary file, removed
    after reading). ``shard``: (i, N) computes the i-th of N parts (see
    :func:`merge`). ``avoid_collisions``: count only solutions whose body keeps every
    checked pair (the chain against itself, the rest of the robot at its neutral pose, the
    robot's obstacles and those of the scene file ``obstacles``) ``margin`` metres apart; every
    analytic posture is checked, numerical IK steers away from contact (as
    :meth:`Robot.ik` with ``avoid_collisions=True``). Deterministic: the same arguments give
    the same arrays whatever the thread count. Raises ``ValueError`` for bad arguments,
    ``OSError`` when the file cannot be written.
    """
    _check(resolution, orientations)
    collision_margin = _collision_margin(avoid_collisions, margin, obstacles)
    index, count = shard if shard is not None else (0, 1)
    keep = path is not None
    target = path if path is not None else _temp_path()
    try:
        _screwkit._reach_build(
            robot,
            target,
            resolution=resolution,
            orientations=orientations,
            mode=mode,
            bounds=None if bounds is None else tuple(float(b) for b in bounds),
            solver=solver,
            seed=seed,
            restarts=restarts,
            iterations=iterations,
            shard_index=index,
            shard_count=count,
            collision_margin=collision_margin,
            obstacles=None if obstacles is None else os.fspath(obstacles),
        )
        m = ReachMap.load(target)
        return m if keep else _unsaved(m)
    finally:
        if not keep and os.path.exists(target):
            os.remove(target)


def merge(shards: list[str], path: str) -> ReachMap:
    """Joins shard files (any order) into the map ``path``: the file the unsharded run writes,
    byte for byte. Raises ``ValueError`` naming the file when a shard belongs to another map,
    is missing or appears twice."""
    _screwkit._reach_merge(list(shards), path)
    return ReachMap.load(path)


def _temp_path() -> str:
    fd, p = tempfile.mkstemp(suffix=".npz", prefix="screwkit-reach-")
    os.close(fd)
    return p


def _unsaved(m: ReachMap) -> ReachMap:
    """The same map without a file behind it."""
    return dataclasses.replace(m, path=None)
