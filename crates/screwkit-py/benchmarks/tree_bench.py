"""The whole tree from Python, next to Pinocchio's Python bindings, in one run.

On a whole robot (default: TALOS as example-robot-data ships it, `pip install
example-robot-data`; 32 variables, 60 links):

1. every link's pose: `robot.fk_all_links(q)` (returns the (L, 4, 4) array) against
   `forwardKinematics` + `updateFramePlacements` (every frame, no array read out);
2. one frame's pose: `robot.fk(q, link=F)` against `forwardKinematics` +
   `updateFramePlacement(F)` + reading the placement as a 4x4 array;
3. one frame's world-aligned Jacobian: `robot.jacobian(q, "world-aligned", link=F)` against
   `computeFrameJacobian(…, LOCAL_WORLD_ALIGNED)`;
4. a batch: `robot.fk_all_links(qs)` of N configurations (all cores), per row, next to one
   call of 1.

Each side runs on its own random configurations (Pinocchio's q layout differs: it keeps mimic
followers as joints). Before timing, both sides' pose of F at the file's zero configuration is
checked equal. Rounds are interleaved and the minimum of each is kept (the host is shared and
noisy).

Run from the repository root (Pinocchio: `pip install pin`):

    python crates/screwkit-py/benchmarks/tree_bench.py [--rounds 7] [--urdf FILE] [--frame F]
"""

from __future__ import annotations

import argparse
import sys
import time
import timeit
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

import screwkit

REPO = Path(__file__).resolve().parents[3]


def talos() -> Path | None:
    """example-robot-data's TALOS (talos_full_v2.urdf), when that package is installed."""
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        robots = distribution("example-robot-data").locate_file(
            "cmeel.prefix/share/example-robot-data/robots"
        )
    except PackageNotFoundError:
        return None
    return Path(str(robots)) / "talos_data" / "robots" / "talos_full_v2.urdf"


def per_call_ns(f: Callable[[], Any], number: int) -> float:
    return min(timeit.repeat(f, number=number, repeat=3)) / number * 1e9


def configurations(robot: screwkit.Robot, n: int, seed: int) -> npt.NDArray[np.float64]:
    return np.stack([robot.random_configuration(seed + k) for k in range(n)])


def main() -> int:
    print(f"host: {screwkit.host()}")
    import pinocchio as pin

    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--rounds", type=int, default=7)
    p.add_argument("--urdf", type=Path, default=talos())
    p.add_argument("--frame", default="gripper_left_base_link")
    p.add_argument("--batch", type=int, default=10_000)
    a = p.parse_args()
    if a.urdf is None:
        p.error("give --urdf FILE, or pip install example-robot-data for TALOS")
    robot = screwkit.Robot.from_urdf(a.urdf)
    model = pin.buildModelFromUrdf(str(a.urdf))
    data = model.createData()
    fid = model.getFrameId(a.frame)
    if fid >= len(model.frames):
        raise SystemExit(f"{a.urdf}: Pinocchio has no frame {a.frame}")

    # The same pose at the file's zero configuration (both sides' neutral, fixed base).
    pin.forwardKinematics(model, data, pin.neutral(model))
    pin.updateFramePlacement(model, data, fid)
    zero = robot.fk(np.zeros(robot.nq), link=a.frame)
    diff = float(np.abs(zero - data.oMf[fid].homogeneous).max())
    assert diff < 1e-12, f"{a.frame}: screwkit and Pinocchio differ by {diff:.3e} at zero"

    qs = configurations(robot, 256, seed=1)
    qs_pin = [pin.randomConfiguration(model) for _ in range(256)]
    k = {"i": 0}

    def q() -> Any:
        k["i"] = (k["i"] + 1) & 255
        return qs[k["i"]]

    def q_pin() -> Any:
        k["i"] = (k["i"] + 1) & 255
        return qs_pin[k["i"]]

    def pin_all() -> None:
        pin.forwardKinematics(model, data, q_pin())
        pin.updateFramePlacements(model, data)

    def pin_one() -> Any:
        pin.forwardKinematics(model, data, q_pin())
        pin.updateFramePlacement(model, data, fid)
        return data.oMf[fid].homogeneous

    def pin_jac() -> Any:
        return pin.computeFrameJacobian(model, data, q_pin(), fid, pin.LOCAL_WORLD_ALIGNED)

    cases: list[tuple[str, Callable[[], Any], Callable[[], Any]]] = [
        ("every link's pose", lambda: robot.fk_all_links(q()), pin_all),
        ("one frame's pose", lambda: robot.fk(q(), link=a.frame), pin_one),
        (
            "one frame's Jacobian",
            lambda: robot.jacobian(q(), "world-aligned", link=a.frame),
            pin_jac,
        ),
    ]
    best = {name: [float("inf"), float("inf")] for name, _, _ in cases}
    batch = configurations(robot, a.batch, seed=7)
    best_batch = best_touch = float("inf")
    for _ in range(a.rounds):
        for name, ours, theirs in cases:
            best[name][0] = min(best[name][0], per_call_ns(ours, 20_000))
            best[name][1] = min(best[name][1], per_call_ns(theirs, 20_000))
        t0 = time.perf_counter()
        robot.fk_all_links(batch)
        best_batch = min(best_batch, (time.perf_counter() - t0) / a.batch * 1e9)
        # The floor under a batch: a new array of the same shape, every page touched once.
        t0 = time.perf_counter()
        np.empty((a.batch, len(robot.link_names), 4, 4)).fill(0.0)
        best_touch = min(best_touch, (time.perf_counter() - t0) / a.batch * 1e9)

    print(
        f"screwkit {screwkit.__version__}, Pinocchio {pin.__version__}, "
        f"Python {sys.version.split()[0]}, numpy {np.__version__}"
    )
    print(
        f"{a.urdf.name}: {len(robot.link_names)} links, nq {robot.nq} "
        f"(Pinocchio: nq {model.nq}, {len(model.frames)} frames); frame {a.frame}"
    )
    print(f"\n{'ns per call, min of rounds':28} {'screwkit':>9} {'pinocchio':>10} {'ratio':>7}")
    for name, (ours_ns, theirs_ns) in best.items():
        print(f"{name:28} {ours_ns:9.0f} {theirs_ns:10.0f} {theirs_ns / ours_ns:7.2f}")
    threads = screwkit.num_threads()
    print(
        f"\nfk_all_links of {a.batch:,} rows ({threads} threads): {best_batch:.0f} ns per row; "
        f"allocating and first touching an array of that shape alone: {best_touch:.0f} ns per row"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
