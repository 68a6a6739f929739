"""Batch calls release the GIL: another Python thread keeps running during a large batch."""

from __future__ import annotations

import threading
import time

import numpy as np

import screwkit

from conftest import configurations


def test_another_thread_runs_during_a_batch(panda: screwkit.Robot) -> None:
    qs = configurations(panda, 1_000_000, seed=31)
    stamps: list[float] = []
    stop = threading.Event()

    def count() -> None:
        n = 0
        while not stop.is_set():
            n += 1
            if n % 100 == 0:
                stamps.append(time.perf_counter())

    worker = threading.Thread(target=count)
    worker.start()
    try:
        time.sleep(0.05)
        spans = []
        for _ in range(3):  # until a batch lasts long enough to judge (a loaded host varies)
            t0 = time.perf_counter()
            poses = panda.jacobian(qs, "space")
            t1 = time.perf_counter()
            spans.append((t0, t1))
            if t1 - t0 > 0.2:
                break
    finally:
        stop.set()
        worker.join()
    t0, t1 = max(spans, key=lambda s: s[1] - s[0])
    assert t1 - t0 > 0.1, "the batch was too short to judge"
    # Inside the call, away from its ends (where a thread switch may let the counter in even
    # with the GIL held), the counting thread must have run.
    inside = [s for s in stamps if t0 + 0.02 < s < t1 - 0.02]
    assert len(inside) > 50, (
        f"the other thread made {len(inside) * 100} iterations in {t1 - t0:.3f} s"
    )
    assert poses.shape == (len(qs), 6, 7)
    np.testing.assert_array_equal(poses[123], panda.jacobian(qs[123], "space"))
