"""Small batches from Python next to a loop of single calls, in one run: what a batch of N rows
costs over the N single calls it replaces.

For N in 1, 2, 4, 8, 16, 64: the bundled Panda's `fk(qs)`, `jacobian(qs)` and `ik(targets)`, and
the bundled humanoid's (a tree) `fk(qs, link)`, `fk_all_frames(qs)` and `jacobian(qs, link)`,
each against `[f(q) for q in qs]` on the same rows. Rounds are interleaved and the minimum of
each is kept (the host is shared and noisy). A batch of at most 256 cheap rows, or 8 IK
targets, runs on the calling thread with the GIL released; larger ones go to the pool.

Run from the repository root, in a venv with screwkit (threads: `--threads`, default 1):

    python crates/screwkit-py/benchmarks/small_batches.py [--rounds 5] [--threads 1]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

import screwkit

REPO = Path(__file__).resolve().parents[3]
SIZES = (1, 2, 4, 8, 16, 64)


def configurations(robot: screwkit.Robot, n: int, seed: int) -> npt.NDArray[np.float64]:
    rng = np.random.default_rng(seed)
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    return np.asarray(lo + (hi - lo) * rng.random((n, robot.dof)), dtype=np.float64)


def per_call_us(f: Callable[[], Any], budget_s: float = 0.02) -> float:
    """Mean µs of one call of `f`, over enough calls to fill about `budget_s`."""
    f()
    t0 = time.perf_counter()
    f()
    once = max(time.perf_counter() - t0, 1e-7)
    reps = max(3, int(budget_s / once))
    t0 = time.perf_counter()
    for _ in range(reps):
        f()
    return (time.perf_counter() - t0) / reps * 1e6


def cases() -> list[tuple[str, Callable[[int], tuple[Callable[[], Any], Callable[[], Any]]]]]:
    panda = screwkit.Robot.from_urdf(REPO / "assets" / "urdf" / "panda.urdf")
    humanoid = screwkit.Robot.from_urdf(REPO / "assets" / "urdf" / "humanoid.urdf")
    hand = "left_hand"
    pq = configurations(panda, max(SIZES), seed=1)
    targets = panda.fk(configurations(panda, max(SIZES), seed=2))
    hq = configurations(humanoid, max(SIZES), seed=3)

    def pair(
        batch: Callable[[Any], Any],
        single: Callable[[Any], Any],
        rows: Any,
        indexed: bool = False,
    ) -> Callable[[int], tuple[Callable[[], Any], Callable[[], Any]]]:
        def at(n: int) -> tuple[Callable[[], Any], Callable[[], Any]]:
            some = rows[:n]
            each = list(enumerate(some)) if indexed else list(some)
            return (lambda: batch(some)), (lambda: [single(r) for r in each])

        return at

    return [
        ("panda fk", pair(panda.fk, panda.fk, pq)),
        ("panda jacobian", pair(panda.jacobian, panda.jacobian, pq)),
        # Row k of a batch restarts from `row_seed(0, k)`: the single calls are given the same
        # restart seeds, so both solve the same way (the same answers, the same work).
        (
            "panda ik",
            pair(
                panda.ik,
                lambda kt: panda.ik(kt[1], seed_rng=screwkit.row_seed(0, kt[0])),
                targets,
                indexed=True,
            ),
        ),
        (
            "humanoid fk(link)",
            pair(lambda q: humanoid.fk(q, hand), lambda q: humanoid.fk(q, hand), hq),
        ),
        ("humanoid fk_all_frames", pair(humanoid.fk_all_frames, humanoid.fk_all_frames, hq)),
        (
            "humanoid jacobian(link)",
            pair(
                lambda q: humanoid.jacobian(q, link=hand),
                lambda q: humanoid.jacobian(q, link=hand),
                hq,
            ),
        ),
    ]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    screwkit.set_num_threads(args.threads)
    print(f"host: {screwkit.host()}")
    table = cases()
    best: dict[tuple[str, int], list[float]] = {}
    for _ in range(args.rounds):
        for name, at in table:
            for n in SIZES:
                batch, loop = at(n)
                b, s = per_call_us(batch), per_call_us(loop)
                old = best.get((name, n), [float("inf"), float("inf")])
                best[(name, n)] = [min(old[0], b), min(old[1], s)]
    head = f"{'call':<24} {'N':>3} {'batch µs':>9} {'N single µs':>12} {'over':>8}"
    print(f"{head}  within N single + 1 µs")
    worst = -float("inf")
    for name, _ in table:
        for n in SIZES:
            b, s = best[(name, n)]
            worst = max(worst, b - s)
            mark = "yes" if b <= s + 1.0 else "NO"
            print(f"{name:<24} {n:>3} {b:>9.2f} {s:>12.2f} {b - s:>+8.2f}  {mark}")
    print(f"largest excess over N single calls: {worst:+.2f} µs")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
