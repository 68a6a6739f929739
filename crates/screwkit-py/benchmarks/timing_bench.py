"""Time-optimal timing of a 1,000-point joint path, next to toppra in one run.

A random smooth 6-joint path of 1,000 waypoints (a random walk, smoothed), random velocity and
acceleration limits: `screwkit.time_parameterize` against toppra's TOPPRA (the same not-a-knot
spline over s = 0 … 1, velocity and acceleration constraints with its interpolation scheme,
`ParametrizeConstAccel`) on screwkit's default grid (40 intervals per waypoint interval,
refined where the 1 kHz check finds an excess; toppra then on 40,000) and on 20,000 and 40,000
intervals. Printed: each one's wall time (the minimum over rounds), the durations side by side,
and the largest excess of a limit sampled at 1 kHz (screwkit checks and tightens; toppra does
not).

    python crates/screwkit-py/benchmarks/timing_bench.py [--rounds 3]
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any

import numpy as np
import numpy.typing as npt

import screwkit

F64 = npt.NDArray[np.float64]


def excess(sample: Any, duration: float, vlim: F64, alim: F64) -> float:
    ts = np.arange(0, duration, 1e-3)
    qd, qdd = sample(ts)
    return float(max((np.abs(qd) / vlim).max(), (np.abs(qdd) / alim).max()))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    try:
        import importlib

        ta: Any = importlib.import_module("toppra")
    except ImportError:
        print("timing_bench: pip install toppra", file=sys.stderr)
        return 2
    ta.setup_logging("WARNING")
    rng = np.random.default_rng(7)
    steps = rng.normal(scale=0.05, size=(1000, 6))
    kernel = np.exp(-0.5 * (np.arange(-20, 21) / 8.0) ** 2)
    kernel /= kernel.sum()
    smooth = np.stack([np.convolve(steps[:, j], kernel, mode="same") for j in range(6)], 1)
    way = np.cumsum(smooth, axis=0)
    vlim, alim = rng.uniform(0.5, 2.0, 6), rng.uniform(1.0, 4.0, 6)
    print(screwkit.host())
    for grid in (None, 20000, 40000):
        best = {"screwkit": np.inf, "toppra": np.inf}
        for _ in range(args.rounds):
            t0 = time.perf_counter()
            ours = screwkit.time_parameterize(way, vlim, alim, grid=grid)
            t1 = time.perf_counter()
            path = ta.SplineInterpolator(np.linspace(0, 1, len(way)), way)
            vel = ta.constraint.JointVelocityConstraint(np.stack([-vlim, vlim], 1))
            acc = ta.constraint.JointAccelerationConstraint(
                np.stack([-alim, alim], 1),
                discretization_scheme=ta.constraint.DiscretizationType.Interpolation,
            )
            inst = ta.algorithm.TOPPRA(
                [vel, acc],
                path,
                gridpoints=np.linspace(0, 1, (grid or 40_000) + 1),
                parametrizer="ParametrizeConstAccel",
            )
            traj = inst.compute_trajectory()
            t2 = time.perf_counter()
            best["screwkit"] = min(best["screwkit"], t1 - t0)
            best["toppra"] = min(best["toppra"], t2 - t1)
        ours_excess = excess(lambda ts, o=ours: o.sample(ts)[1:], ours.duration, vlim, alim)
        their_excess = excess(lambda ts, tr=traj: (tr(ts, 1), tr(ts, 2)), traj.duration, vlim, alim)
        print(
            f"grid {grid or 'default':>7}: screwkit {best['screwkit'] * 1e3:8.1f} ms, duration "
            f"{ours.duration:.4f} s, worst limit {ours_excess:.5f} | toppra "
            f"{best['toppra'] * 1e3:8.1f} ms, duration {traj.duration:.4f} s, worst limit "
            f"{their_excess:.5f} | time ratio {best['toppra'] / best['screwkit']:.1f}x, "
            f"durations {ours.duration / traj.duration:.4f}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
