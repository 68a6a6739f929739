"""Dynamics from Python, next to Pinocchio's and MuJoCo's bindings, in one run.

Per call, one configuration at a time (each side's own random configurations, rounds
interleaved, the minimum kept; the host is shared and noisy):

- inverse dynamics: `robot.inverse_dynamics(q, v, a)` against `pin.rnea`;
- the mass matrix: `robot.mass_matrix(q)` against `pin.crba` (its upper triangle);
- forward dynamics: `robot.forward_dynamics(q, v, tau)` against `pin.aba` (not on the Panda:
  Pinocchio's `aba` refuses its mimic finger joint);

on example-robot-data's UR5, Panda and TALOS (reduced, floating base; `pip install
example-robot-data pin`). Then MuJoCo on the bundled humanoid MJCF (free joint, nv 27,
contacts disabled): `mj_inverse` and `mj_fwdPosition` + `mj_fullM` per call against ours.
Then batches: N = 100,000 rows of inverse dynamics and of mass matrices, per row, on one thread
and on two (`screwkit.set_num_threads`), next to the per-call loops above.

Before timing, each pair's answers are checked equal at one configuration (Pinocchio by
joint name, its free-flyer's (v, ω) turned to our (ω, v)).

    python crates/screwkit-py/benchmarks/dynamics_bench.py [--rounds 5] [--n 100000]
"""

from __future__ import annotations

import argparse
import sys
import timeit
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

import screwkit

REPO = Path(__file__).resolve().parents[3]
F64 = npt.NDArray[np.float64]


def robots_dir() -> Path | None:
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        share = distribution("example-robot-data").locate_file(
            "cmeel.prefix/share/example-robot-data/robots"
        )
    except PackageNotFoundError:
        return None
    return Path(str(share))


def per_call_ns(f: Callable[[], Any], number: int) -> float:
    return min(timeit.repeat(f, number=number, repeat=3)) / number * 1e9


def random_q(robot: screwkit.Robot, rng: np.random.Generator) -> F64:
    q = np.asarray(robot.neutral(), dtype=float)
    base = 7 if robot.floating_base else 0
    if base:
        quat = rng.normal(size=4)
        q[:7] = np.r_[rng.normal(size=3), quat / np.linalg.norm(quat)]
    lo = np.maximum(np.asarray(robot.lower)[base - robot.nq if base else 0 :], -np.pi)
    hi = np.minimum(np.asarray(robot.upper)[base - robot.nq if base else 0 :], np.pi)
    q[base:] = rng.uniform(lo[-(robot.nq - base) :], hi[-(robot.nq - base) :])
    return q


class Pin:
    """Pinocchio's model of a URDF and the maps to ours (by joint name; continuous joints as
    (cos, sin); the free-flyer's velocity (v, ω) against our (ω, v))."""

    def __init__(self, pin: Any, path: Path, robot: screwkit.Robot) -> None:
        floating = robot.floating_base
        args = (pin.JointModelFreeFlyer(),) if floating else ()
        self.model = pin.buildModelFromUrdf(str(path), *args, mimic=True)
        self.data = self.model.createData()
        off = 6 if floating else 0
        self.v_index = [3, 4, 5, 0, 1, 2] if floating else []
        self.joints: list[tuple[int, int]] = []
        for name in robot.v_names[off:]:
            j = self.model.joints[self.model.getJointId(name)]
            self.v_index.append(j.idx_v)
            self.joints.append((j.idx_q, j.nq))
        self.floating = floating

    def q(self, ours: F64) -> F64:
        q = np.zeros(self.model.nq)
        off = 7 if self.floating else 0
        q[:off] = ours[:off]
        for (i, n), x in zip(self.joints, ours[off:], strict=True):
            q[i : i + n] = [np.cos(x), np.sin(x)] if n == 2 else [x]
        return q

    def v(self, ours: F64) -> F64:
        out = np.zeros(self.model.nv)
        out[self.v_index] = ours
        return out

    def ours(self, theirs: F64) -> F64:
        return np.asarray(theirs)[self.v_index]


def compare_pinocchio(name: str, path: Path, floating: bool, rounds: int) -> None:
    import pinocchio as pin

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = screwkit.Robot.from_urdf(path, floating_base=floating)
        robot.gravity(robot.neutral())
    p = Pin(pin, path, robot)
    m, d = p.model, p.data
    rng = np.random.default_rng(1)
    q = random_q(robot, rng)
    v, a = rng.normal(size=robot.nv), rng.normal(size=robot.nv)
    qp, vp, ap = p.q(q), p.v(v), p.v(a)
    tau = robot.inverse_dynamics(q, v, a)
    assert np.allclose(tau, p.ours(pin.rnea(m, d, qp, vp, ap)), atol=1e-8), name
    taup = p.v(tau)
    number = 20_000 if robot.nv < 20 else 4_000
    calls: dict[str, tuple[Callable[[], Any], Callable[[], Any]]] = {
        "inverse dynamics (rnea)": (
            lambda: robot.inverse_dynamics(q, v, a),
            lambda: pin.rnea(m, d, qp, vp, ap),
        ),
        "mass matrix (crba)": (lambda: robot.mass_matrix(q), lambda: pin.crba(m, d, qp)),
    }
    if not any(j.nq == 0 for j in m.joints):  # Pinocchio's aba refuses mimic joints
        calls["forward dynamics (aba)"] = (
            lambda: robot.forward_dynamics(q, v, tau),
            lambda: pin.aba(m, d, qp, vp, taup),
        )
    best = {k: [np.inf, np.inf] for k in calls}
    for _ in range(rounds):
        for k, (ours, theirs) in calls.items():
            best[k][0] = min(best[k][0], per_call_ns(ours, number))
            best[k][1] = min(best[k][1], per_call_ns(theirs, number))
    label = f"{name} ({'floating' if floating else 'fixed'}, nv {robot.nv})"
    for k, (a_ns, b_ns) in best.items():
        print(
            f"  {label:<28} {k:<26} screwkit {a_ns / 1e3:7.2f} µs  "
            f"pinocchio {b_ns / 1e3:7.2f} µs  ratio {b_ns / a_ns:5.2f}x"
        )


def compare_mujoco(rounds: int) -> None:
    import importlib

    mujoco: Any = importlib.import_module("mujoco")

    path = REPO / "assets" / "mjcf" / "humanoid.xml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = screwkit.Robot.from_file(path)
        robot.gravity(robot.neutral())
    robot.set_dynamics_options(armature=True, damping=True)
    mj = mujoco.MjModel.from_xml_path(str(path))
    mj.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(2)
    q = random_q(robot, rng)
    v, a = rng.normal(size=robot.nv), rng.normal(size=robot.nv)
    d.qpos[:] = mj.qpos0
    d.qvel[:] = rng.normal(size=mj.nv)
    d.qacc[:] = rng.normal(size=mj.nv)
    full = np.zeros((mj.nv, mj.nv))

    def mass_mj() -> None:
        mujoco.mj_fwdPosition(mj, d)
        mujoco.mj_fullM(mj, d, full)

    calls = {
        "inverse dynamics (mj_inverse)": (
            lambda: robot.inverse_dynamics(q, v, a),
            lambda: mujoco.mj_inverse(mj, d),
        ),
        "mass matrix (mj_fwdPosition + mj_fullM)": (lambda: robot.mass_matrix(q), mass_mj),
    }
    best = {k: [np.inf, np.inf] for k in calls}
    for _ in range(rounds):
        for k, (ours, theirs) in calls.items():
            best[k][0] = min(best[k][0], per_call_ns(ours, 5_000))
            best[k][1] = min(best[k][1], per_call_ns(theirs, 5_000))
    for k, (a_ns, b_ns) in best.items():
        print(
            f"  humanoid.xml (MuJoCo, nv {robot.nv}) {k:<40} screwkit {a_ns / 1e3:7.2f} µs  "
            f"mujoco {b_ns / 1e3:7.2f} µs  ratio {b_ns / a_ns:5.2f}x"
        )


def batches(path: Path, floating: bool, n: int, rounds: int) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = screwkit.Robot.from_urdf(path, floating_base=floating)
        robot.gravity(robot.neutral())
    rng = np.random.default_rng(3)
    qs = np.stack([random_q(robot, rng) for _ in range(n)])
    vs, acc = rng.normal(size=(n, robot.nv)), rng.normal(size=(n, robot.nv))
    threads = screwkit.num_threads()
    try:
        jobs: list[tuple[str, Callable[[], Any]]] = [
            ("inverse dynamics", lambda: robot.inverse_dynamics(qs, vs, acc)),
            ("mass matrix", lambda: robot.mass_matrix(qs)),
        ]
        for what, f in jobs:
            per_row = {1: np.inf, 2: np.inf}
            for _ in range(rounds):
                for t in (1, 2):
                    screwkit.set_num_threads(t)
                    f()  # the pool warmed up
                    best = min(timeit.repeat(f, number=1, repeat=3)) / n * 1e9
                    per_row[t] = min(per_row[t], best)
            print(
                f"  {path.name} batch of {n} {what:<17} 1 thread {per_row[1]:6.0f} ns/row  "
                f"2 threads {per_row[2]:6.0f} ns/row  speed-up {per_row[1] / per_row[2]:4.2f}x"
            )
    finally:
        screwkit.set_num_threads(threads)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--n", type=int, default=100_000)
    args = parser.parse_args()
    robots = robots_dir()
    if robots is None:
        print("dynamics_bench: pip install example-robot-data (and pin, mujoco)", file=sys.stderr)
        return 2
    cases = [
        ("UR5", robots / "ur_description/urdf/ur5_robot.urdf", False),
        ("Panda", robots / "panda_description/urdf/panda.urdf", False),
        ("TALOS", robots / "talos_data/robots/talos_reduced.urdf", True),
    ]
    print("per call (one configuration), minimum over rounds:")
    for name, path, floating in cases:
        compare_pinocchio(name, path, floating, args.rounds)
    compare_mujoco(args.rounds)
    print(f"batches (N = {args.n}), per row:")
    for _, path, floating in cases:
        batches(path, floating, args.n, args.rounds)
    return 0


if __name__ == "__main__":
    sys.exit(main())
