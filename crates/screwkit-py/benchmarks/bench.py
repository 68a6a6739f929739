"""screwkit from Python, next to its peers and to its own Rust core, in one run.

1. One FK call from Python: `robot.fk(q)` against Pinocchio's Python bindings doing the same job
   (`forwardKinematics` + `updateFramePlacement` + reading the placement as a 4x4 array).
2. Batched FK of 100,000 configurations and batched IK of 2,000 targets: `robot.fk(qs)` and
   `robot.ik(targets)` against the Rust batch functions on the same inputs (the example
   `batch_timing`, built in release and run as a subprocess that times itself).

Rounds are interleaved and the minimum of each is kept (the host is shared and noisy).

Run from the repository root (Pinocchio: `pip install pin`):

    python crates/screwkit-py/benchmarks/bench.py [--rounds 7] [--robot ur5 panda]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
import timeit
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

import screwkit

REPO = Path(__file__).resolve().parents[3]
TIPS = {"ur5": "tool0", "panda": "panda_hand", "iiwa14": "iiwa_link_ee"}


def configurations(robot: screwkit.Robot, n: int, seed: int) -> npt.NDArray[np.float64]:
    rng = np.random.default_rng(seed)
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    return np.asarray(lo + (hi - lo) * rng.random((n, robot.dof)), dtype=np.float64)


def per_call_ns(f: Any, number: int) -> float:
    return min(timeit.repeat(f, number=number, repeat=3)) / number * 1e9


def single_fk(name: str, rounds: int) -> dict[str, Any]:
    import pinocchio as pin

    path = REPO / "assets" / "urdf" / f"{name}.urdf"
    robot = screwkit.Robot.from_urdf(path)
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    frame = model.getFrameId(robot.tip)
    q = configurations(robot, 1, seed=1)[0]
    q_pin = q.copy()  # the bundled arms have no continuous joints: same q layout

    def ours() -> Any:
        return robot.fk(q)

    def theirs() -> Any:
        pin.forwardKinematics(model, data, q_pin)
        pin.updateFramePlacement(model, data, frame)
        return data.oMf[frame].homogeneous

    assert np.abs(ours() - theirs()).max() < 1e-12
    best = {"screwkit": float("inf"), "pinocchio": float("inf")}
    for _ in range(rounds):
        best["screwkit"] = min(best["screwkit"], per_call_ns(ours, 20_000))
        best["pinocchio"] = min(best["pinocchio"], per_call_ns(theirs, 20_000))
    return {"robot": name, **best, "ratio": best["pinocchio"] / best["screwkit"]}


def batches(name: str, rounds: int, n_fk: int, n_ik: int) -> dict[str, Any]:
    path = REPO / "assets" / "urdf" / f"{name}.urdf"
    robot = screwkit.Robot.from_urdf(path)
    qs = configurations(robot, n_fk, seed=2)
    targets = robot.fk(configurations(robot, n_ik, seed=3))
    with tempfile.TemporaryDirectory() as tmp:
        qs_file, targets_file = Path(tmp) / "qs.f64", Path(tmp) / "targets.f64"
        qs.tofile(qs_file)
        targets.tofile(targets_file)
        cmd = ["cargo", "run", "--quiet", "--release", "--example", "batch_timing", "--"]
        args = [str(path), str(qs_file), str(targets_file), "3"]
        subprocess.run(cmd + ["--help"], cwd=REPO, capture_output=True)  # build first
        best = {"python_fk_s": float("inf"), "rust_fk_s": float("inf")}
        best |= {"python_ik_s": float("inf"), "rust_ik_s": float("inf")}
        for _ in range(rounds):
            for _ in range(3):
                t0 = time.perf_counter()
                robot.fk(qs)
                best["python_fk_s"] = min(best["python_fk_s"], time.perf_counter() - t0)
                t0 = time.perf_counter()
                ik = robot.ik(targets)
                best["python_ik_s"] = min(best["python_ik_s"], time.perf_counter() - t0)
            out = subprocess.run(cmd + args, cwd=REPO, capture_output=True, text=True, check=True)
            rust = json.loads(out.stdout)
            best["rust_fk_s"] = min(best["rust_fk_s"], rust["fk_batch_s"])
            best["rust_ik_s"] = min(best["rust_ik_s"], rust["ik_batch_s"])
    assert isinstance(ik, screwkit.IkBatchResult)
    assert int(ik.converged.sum()) == rust["ik_solved"], "Python and Rust solved different targets"
    return {
        "robot": name,
        "fk_rows": n_fk,
        "ik_rows": n_ik,
        "ik_solved": rust["ik_solved"],
        "threads": screwkit.num_threads(),
        **best,
        "fk_ratio": best["python_fk_s"] / best["rust_fk_s"],
        "ik_ratio": best["python_ik_s"] / best["rust_ik_s"],
    }


def main() -> int:
    print(f"host: {screwkit.host()}")
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--rounds", type=int, default=7)
    p.add_argument("--robot", nargs="+", default=["ur5", "panda"], choices=sorted(TIPS))
    p.add_argument("--fk-rows", type=int, default=100_000)
    p.add_argument("--ik-rows", type=int, default=2_000)
    a = p.parse_args()
    print(
        f"screwkit {screwkit.__version__}, Python {sys.version.split()[0]}, numpy {np.__version__}"
    )
    print("\none FK call from Python (ns, min of rounds)")
    print(f"{'robot':8} {'screwkit':>9} {'pinocchio':>10} {'pinocchio/screwkit':>19}")
    for name in a.robot:
        r = single_fk(name, a.rounds)
        print(f"{name:8} {r['screwkit']:9.0f} {r['pinocchio']:10.0f} {r['ratio']:19.2f}")
    print("\nbatches from Python vs the Rust batch functions (ms, min of rounds)")
    print(f"{'robot':8} {'what':18} {'python':>8} {'rust':>8} {'python/rust':>12}")
    for name in a.robot:
        b = batches(name, a.rounds, a.fk_rows, a.ik_rows)
        fk = f"fk {b['fk_rows']:,}"
        ik = f"ik {b['ik_rows']:,} ({b['ik_solved']} ok)"
        py_fk, rs_fk = b["python_fk_s"] * 1e3, b["rust_fk_s"] * 1e3
        py_ik, rs_ik = b["python_ik_s"] * 1e3, b["rust_ik_s"] * 1e3
        print(f"{name:8} {fk:18} {py_fk:8.2f} {rs_fk:8.2f} {b['fk_ratio']:12.3f}")
        print(f"{name:8} {ik:18} {py_ik:8.2f} {rs_ik:8.2f} {b['ik_ratio']:12.3f}")
    print(f"\nthreads: {screwkit.num_threads()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
