"""Analytic IK next to its peers, in one run: EAIK (C++, Python bindings) and ik-geo (IK-Geo's
Rust, Python bindings), given the very same geometry (the H, P vectors of subproblem
decomposition, read from screwkit's screw axes) and the same poses.

For each arm it checks that the three find the same solutions (each posture of one, modulo 2 pi,
is among the others' — solutions ignoring joint limits, so screwkit solves a copy of the URDF
whose revolute joints are made continuous — every solution checked by screwkit's FK), then
times, per pose (minimum over interleaved rounds, one thread):

- screwkit `robot.ik_all(T)` one call at a time, and on all poses at once, `ik_all(Ts)` with
  one thread (both: postures deduplicated, checked by FK, sorted nearest to the seed);
- EAIK `robot.IK(T)` one at a time and `IK_batched(Ts, 1)`;
- ik-geo `robot.get_ik(R, p)` one at a time.

The Rust kernel without Python (`AnalyticIk::postures`) is timed by
`cargo bench -p screwkit-solve --bench analytic`.

Not a test dependency: `pip install eaik ik_geo` in the venv that has screwkit, then, from the
repository root:

    python crates/screwkit-py/benchmarks/analytic_peers.py [--poses 2000] [--rounds 5]
"""

from __future__ import annotations

import argparse
import os
import re
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

import screwkit

REPO = Path(__file__).resolve().parents[3]
F64 = npt.NDArray[np.float64]


def hp(robot: screwkit.Robot) -> tuple[F64, F64, F64]:
    """H (n, 3) unit axes and P (n + 1, 3) offsets between points on consecutive axes (IK-Geo's
    convention), and M's rotation: from the space screw axes S = (w, v), w x v being the point
    of each axis nearest the base origin."""
    s = robot.screw_axes("space")
    w, v = s[:, :3], s[:, 3:]
    o = np.cross(w, v)
    m = robot.home
    p = np.vstack([o[0], np.diff(o, axis=0), m[:3, 3] - o[-1]])
    return w, p, m[:3, :3]


def unlimited(robot_file: Path) -> str:
    """The URDF text with revolute joints made continuous (every posture, limits ignored)."""
    return re.sub(r'type="revolute"', 'type="continuous"', robot_file.read_text())


def same_posture(a: F64, b: F64) -> bool:
    d = np.angle(np.exp(1j * (a - b)))
    return bool(np.all(np.abs(d) < 1e-6))


def best(rounds: int, fns: dict[str, Callable[[], object]], n: int) -> dict[str, float]:
    """Per-pose minimum over interleaved rounds, in microseconds."""
    out = {k: float("inf") for k in fns}
    for _ in range(rounds):
        for k, f in fns.items():
            t0 = time.perf_counter()
            f()
            out[k] = min(out[k], (time.perf_counter() - t0) / n * 1e6)
    return out


def compare(
    name: str,
    path: Path,
    base: str | None,
    tip: str | None,
    ikgeo_family: str,
    lock: int | None,
    poses: int,
    rounds: int,
) -> None:
    import eaik.IK_HP
    import ik_geo as _ik_geo

    ik_geo: Any = _ik_geo  # untyped bindings

    robot = screwkit.Robot.from_urdf(path, base, tip)
    free = screwkit.Robot.from_string(unlimited(path), base, tip, source=str(path))
    h, p, rm = hp(robot)
    rng = np.random.default_rng(1)
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    qs = lo + (hi - lo) * rng.random((poses, robot.dof))
    ts = robot.fk(qs)
    # The peers' tool frame is the last joint's orientation at home: T' = (R R_M^T, p).
    tp = ts.copy()
    tp[:, :3, :3] = ts[:, :3, :3] @ rm.T
    fixed: list[tuple[int, float]] | None = None
    if lock is not None:
        # EAIK locks one value per robot: all poses share the first one.
        value = float(qs[0, lock])
        qs[:, lock] = value
        ts = robot.fk(qs)
        tp = ts.copy()
        tp[:, :3, :3] = ts[:, :3, :3] @ rm.T
        fixed = [(lock, value)]
    e = eaik.IK_HP.HPRobot(h, p, fixed_axes=fixed)
    g: Any = None
    if lock is None:
        # IK-Geo wants the points of intersecting axes to coincide (p_i,i+1 = 0): EAIK's
        # remodelled H, P (3 x n) have them. Its rotations are lists of columns (R^T below).
        hr, pr = np.asarray(e.getRemodeled_H()).T, np.asarray(e.getRemodeled_P()).T
        g = getattr(ik_geo.Robot, ikgeo_family)(hr.tolist(), pr.tolist())

    def reached(q: F64, t: F64) -> bool:
        return bool(np.max(np.abs(free.fk(q) - t)) < 1e-8)

    agree = {"eaik": 0, "ik-geo": 0}
    counts: list[int] = []
    for k in range(poses):
        kw: dict[str, Any] = (
            {"lock": lock, "lock_value": float(qs[k, lock])} if lock is not None else {}
        )
        ours = free.ik_all(ts[k], seed=qs[k], **kw)
        assert isinstance(ours, np.ndarray)
        distinct: list[F64] = []
        for s in ours:
            if not any(same_posture(s, d) for d in distinct):
                distinct.append(s)
        counts.append(len(distinct))
        sol = e.IK(tp[k])
        # Every peer solution counts when screwkit's FK says it reaches the target, whatever
        # the peer's own least-squares flag.
        peers = {"eaik": [np.asarray(x) for x in sol.Q]}
        if g is not None:
            r = g.get_ik(tp[k][:3, :3].T.tolist(), tp[k][:3, 3].tolist())
            peers["ik-geo"] = [np.asarray(x) for x, _ in r]
        for peer, sols in peers.items():
            theirs = [x for x in sols if reached(x, ts[k])]
            ok = len(theirs) == len(distinct) and all(
                any(same_posture(a, b) for b in theirs) for a in distinct
            )
            agree[peer] += int(ok)
    print(
        f"{name}: screwkit postures per pose {min(counts)}-{max(counts)} "
        f"(mean {np.mean(counts):.2f}); same solution set as EAIK on "
        f"{agree['eaik']}/{poses} poses"
        + (f", as ik-geo on {agree['ik-geo']}/{poses}" if g is not None else "")
    )
    kw0: dict[str, Any] = (
        {"lock": lock, "lock_value": float(qs[0, lock])} if lock is not None else {}
    )
    screwkit.set_num_threads(1)
    # Timed on the copy without limits: every posture once, as the peers return them (with
    # the limits, screwkit also lists each 2 pi shift inside them: the UR5's +-2 pi limits
    # give up to 8 x 2^6 solutions).
    fns: dict[str, Callable[[], object]] = {
        "screwkit ik_all, one call": lambda: [free.ik_all(t, **kw0) for t in ts],
        "screwkit ik_all, batch": lambda: free.ik_all(ts, **kw0),
        "EAIK IK, one call": lambda: [e.IK(t) for t in tp],
        "EAIK IK_batched": lambda: e.IK_batched(tp, 1),
    }
    if g is not None:
        fns["ik-geo get_ik, one call"] = lambda: (
            [g.get_ik(t[:3, :3].T.tolist(), t[:3, 3].tolist()) for t in tp]
        )
    for label, us in best(rounds, fns, poses).items():
        print(f"  {label:<28} {us:8.2f} us/pose")
    screwkit.set_num_threads(None)


# The general 6R of `cargo bench --bench analytic` (no two consecutive axes parallel or
# meeting): per joint (origin xyz, origin rpy), every axis z of its frame.
GENERAL = [
    ("0 0 0", "0 0 0"),
    ("0.05 0.02 0.27", "1.2 0.1 0"),
    ("0.29 0.03 0.01", "0.1 0.3 0.2"),
    ("0.08 -0.04 0.34", "-1.1 0.2 0.1"),
    ("0.02 0.03 0.09", "1.3 -0.2 0.3"),
    ("0.01 0.07 0.05", "-1.2 0.1 0.2"),
]


def general_6r(poses: int, peer_poses: int, rounds: int) -> None:
    """The general 6R: screwkit's algebraic elimination next to ik-geo's `gen_six_dof` (its
    2D search: EAIK has no decomposition for it), same geometry and poses; solution sets
    compared on `peer_poses` poses (the 2D search takes long), timed on as many."""
    import ik_geo as _ik_geo

    ik_geo: Any = _ik_geo
    joints = "".join(
        f'<link name="l{i + 1}"/><joint name="j{i + 1}" type="continuous"><parent link="l{i}"/>'
        f'<child link="l{i + 1}"/><origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="0 0 1"/></joint>'
        for i, (xyz, rpy) in enumerate(GENERAL)
    )
    free = screwkit.Robot.from_string(f'<robot name="g"><link name="l0"/>{joints}</robot>')
    h, p, rm = hp(free)
    g = ik_geo.Robot.gen_six_dof(h.tolist(), p.tolist())
    rng = np.random.default_rng(1)
    qs = -np.pi + 2 * np.pi * rng.random((poses, 6))
    ts = free.fk(qs)
    tp = ts.copy()
    tp[:, :3, :3] = ts[:, :3, :3] @ rm.T
    agree, more, counts = 0, 0, []
    for k in range(peer_poses):
        ours = free.ik_all(ts[k], seed=qs[k])
        assert isinstance(ours, np.ndarray)
        counts.append(len(ours))
        r = g.get_ik(tp[k][:3, :3].T.tolist(), tp[k][:3, 3].tolist())
        theirs = [
            np.asarray(x) for x, _ in r if np.max(np.abs(free.fk(np.asarray(x)) - ts[k])) < 1e-8
        ]
        distinct: list[F64] = []
        for x in theirs:
            if not any(same_posture(x, d) for d in distinct):
                distinct.append(x)
        agree += int(all(any(same_posture(x, o) for o in ours) for x in distinct))
        more += int(len(ours) > len(distinct))
    print(
        f"general 6R: screwkit postures per pose {min(counts)}-{max(counts)}; every ik-geo "
        f"gen_six_dof solution among screwkit's on {agree}/{peer_poses} poses, screwkit found "
        f"more on {more}"
    )
    screwkit.set_num_threads(1)
    fns: dict[str, Callable[[], object]] = {
        "screwkit ik_all, one call": lambda: [free.ik_all(t) for t in ts[:peer_poses]],
        "screwkit ik_all, batch": lambda: free.ik_all(ts[:peer_poses]),
        "ik-geo gen_six_dof, one call": lambda: (
            [g.get_ik(t[:3, :3].T.tolist(), t[:3, 3].tolist()) for t in tp[:peer_poses]]
        ),
    }
    for label, us in best(rounds, fns, peer_poses).items():
        print(f"  {label:<28} {us:10.2f} us/pose")
    screwkit.set_num_threads(None)


def main() -> None:
    print(f"host: {screwkit.host()}")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=2000)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--general-poses", type=int, default=20)
    a = ap.parse_args()
    general_6r(a.poses, a.general_poses, a.rounds)
    assets = REPO / "assets" / "urdf"
    compare(
        "ur5",
        assets / "ur5.urdf",
        None,
        None,
        "three_parallel_two_intersecting",
        None,
        a.poses,
        a.rounds,
    )
    # A KUKA KR 16 of the CI data, when SCREWKIT_SHARED_XACRO names it.
    xacro_dir = os.environ.get("SCREWKIT_SHARED_XACRO")
    kr16 = Path(xacro_dir) / "expanded" / "kr16_2.urdf" if xacro_dir else None
    if kr16 is not None and kr16.exists():
        compare(
            "kr16_2",
            kr16,
            "base_link",
            "tool0",
            "spherical_two_parallel",
            None,
            a.poses,
            a.rounds,
        )
    panda = assets / "panda.urdf"
    compare("panda, joint 7 locked", panda, None, None, "", 6, a.poses, a.rounds)
    # Joint 5 locked: a spherical wrist only (subproblem 5), read from the tip.
    compare("panda, joint 5 locked", panda, None, None, "", 4, a.poses, a.rounds)


if __name__ == "__main__":
    main()
