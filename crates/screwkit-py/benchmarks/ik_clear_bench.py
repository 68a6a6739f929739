"""Numerical IK clear of contact, checked by coal: example-robot-data's Panda and UR5 (collision
meshes, SRDFs) beside a table and a box, margin 1 cm. Targets are FK(q*) of random q* that coal
finds at least the margin from contact, the tool over the table. Each target is solved alone
from the midpoint by `Robot.ik` (plain) and `Robot.ik(avoid_collisions=True, margin=0.01)`;
per target the mean time (interleaved rounds, the fastest kept), the targets solved, and how
many answers coal finds closer than the margin (plain IK's, and ours: 0 expected).

Run: python crates/screwkit-py/benchmarks/ik_clear_bench.py [--targets 200] [--rounds 3]
(needs pin, coal and example-robot-data: `cargo xtask test` installs them in its venv).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import screwkit

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from test_avoid_collisions import MARGIN, clear_targets, setup  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--targets", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    print(screwkit.host())
    for name in ("panda", "ur5"):
        robot, oracle, _, _ = setup(name)
        targets = clear_targets(robot, oracle, args.targets, seed=7)
        kinds = {"plain": False, "clear": True}
        best = {k: np.inf for k in kinds}
        answers: dict[str, list[screwkit.IkResult]] = {}
        for _ in range(args.rounds):
            for kind, avoid in kinds.items():
                margin = MARGIN if avoid else 0.0
                t0 = time.perf_counter()
                answers[kind] = [
                    robot.ik(t, avoid_collisions=avoid, margin=margin) for t in targets
                ]
                best[kind] = min(best[kind], (time.perf_counter() - t0) / len(targets) * 1e6)
        line = f"{name:<6} {len(targets)} targets clear by coal:"
        for kind in kinds:
            solved = [r for r in answers[kind] if r.converged]
            close = sum(oracle.min_distance(r.q) < MARGIN - 1e-6 for r in solved)
            line += (
                f" {kind} {best[kind]:.1f} µs/target, {len(solved)} solved,"
                f" {close} closer than the margin by coal;"
            )
        print(f"{line} ratio {best['clear'] / best['plain']:.1f}x")


if __name__ == "__main__":
    main()
