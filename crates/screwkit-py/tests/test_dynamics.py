"""Dynamics of the whole tree (issue 50) against Pinocchio 4.1 (`rnea`,
`computeGeneralizedGravity`, `nonLinearEffects`, `crba`, `aba`) on the bundled robots, the UR5,
the Panda (its mimic finger joint: Pinocchio's `mimic=True`) and TALOS of example-robot-data and
the CI data's URDFs, fixed and floating; and the invariants: M symmetric positive definite,
FD(ID(a)) = a, M's columns ID(q, 0, e_i) − g(q), ½ vᵀ M v the kinetic energy, g(q) the gradient of
the potential energy (finite differences)."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from test_body import ROBOTS

import screwkit

from conftest import ASSETS, shared_params

pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin) is a test dependency")

REPO_MJCF = ASSETS.parent / "mjcf"

F64 = npt.NDArray[np.float64]


def load(path: Path, floating: bool) -> screwkit.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # massless links, said once
        return screwkit.Robot.from_urdf(path, floating_base=floating)


class Oracle:
    """Pinocchio's model of the file (mimic joints as mimic joints), and the maps between its
    variables and ours: by joint name; a continuous joint's (cos, sin); a floating base's
    (v, ω) against our (ω, v)."""

    def __init__(self, path: Path, robot: screwkit.Robot, floating: bool) -> None:
        args = (pin.JointModelFreeFlyer(),) if floating else ()
        self.model = pin.buildModelFromUrdf(str(path), *args, mimic=True)
        self.data = self.model.createData()
        self.robot = robot
        off = 6 if floating else 0
        self.floating = floating
        self.v_index: list[int] = [3, 4, 5, 0, 1, 2] if floating else []
        self.joints: list[tuple[int, int]] = []  # (pin idx_q, its nq) per joint variable
        for name in robot.v_names[off:]:
            j = self.model.joints[self.model.getJointId(name)]
            self.v_index.append(j.idx_v)
            self.joints.append((j.idx_q, j.nq))
        assert self.model.nv == robot.nv, (self.model.nv, robot.nv)

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

    def matrix(self, theirs: F64) -> F64:
        m = np.triu(theirs) + np.triu(theirs, 1).T
        return m[np.ix_(self.v_index, self.v_index)]


def configurations(robot: screwkit.Robot, n: int, seed: int) -> list[F64]:
    rng = np.random.default_rng(seed)
    base = 7 if robot.nv > robot.nq - 7 + 6 - 1 and robot.nq != robot.nv else 0
    lo = np.maximum(np.asarray(robot.lower)[-(robot.nq - base) :], -np.pi)
    hi = np.minimum(np.asarray(robot.upper)[-(robot.nq - base) :], np.pi)
    out = []
    for _ in range(n):
        q = np.asarray(robot.neutral(), dtype=float)
        if base:
            quat = rng.normal(size=4)
            q[:7] = np.r_[rng.normal(size=3), quat / np.linalg.norm(quat)]
        if robot.nq > base:
            q[base:] = rng.uniform(lo, hi)
        out.append(q)
    return out


def check(path: Path, floating: bool, samples: int = 4, aba: bool = True) -> None:
    robot = load(path, floating)
    try:
        oracle = Oracle(path, robot, floating)
    except ValueError as e:
        # Pinocchio cannot read a few files (the bundled tricky.urdf's edge cases; TALOS's
        # grippers, whose mimic joints' leaders its parser does not find): ours are held to the
        # invariants alone, and the file's name is printed for the record.
        print(f"{path.name}: Pinocchio refuses it ({e}); invariants only")
        invariants(robot, samples, aba)
        return
    m, d = oracle.model, oracle.data
    rng = np.random.default_rng(7)
    for q in configurations(robot, samples, 3):
        v, a = rng.normal(size=robot.nv), rng.normal(size=robot.nv)
        qp, vp, ap = oracle.q(q), oracle.v(v), oracle.v(a)
        scale = 1.0 + float(np.abs(pin.rnea(m, d, qp, vp, ap)).max())
        tau = robot.inverse_dynamics(q, v, a)
        np.testing.assert_allclose(tau, oracle.ours(pin.rnea(m, d, qp, vp, ap)), atol=1e-9 * scale)
        g = robot.gravity(q)
        np.testing.assert_allclose(
            g, oracle.ours(pin.computeGeneralizedGravity(m, d, qp)), atol=1e-9 * scale
        )
        np.testing.assert_allclose(
            robot.nonlinear_effects(q, v),
            oracle.ours(pin.nonLinearEffects(m, d, qp, vp)),
            atol=1e-9 * scale,
        )
        mass = robot.mass_matrix(q)
        assert np.abs(mass).max() > 1e-4, "a robot with mass"
        np.testing.assert_allclose(mass, oracle.matrix(pin.crba(m, d, qp)), atol=1e-9 * scale)
        np.testing.assert_array_equal(mass, mass.T)
        # The columns of M are ID with unit accelerations, less gravity.
        k = int(rng.integers(robot.nv))
        unit = np.zeros(robot.nv)
        unit[k] = 1.0
        np.testing.assert_allclose(
            mass[:, k], robot.inverse_dynamics(q, np.zeros(robot.nv), unit) - g, atol=1e-9 * scale
        )
        np.testing.assert_allclose(
            robot.kinetic_energy(q, v), 0.5 * v @ mass @ v, rtol=1e-12, atol=1e-12
        )
        if aba:
            assert np.linalg.eigvalsh(mass).min() > 0
            np.testing.assert_allclose(robot.forward_dynamics(q, v, tau), a, atol=1e-7)
            if not any(j.nq == 0 for j in m.joints):  # Pinocchio's aba refuses mimic joints
                want = oracle.ours(pin.aba(m, d, qp, vp, oracle.v(tau)))
                np.testing.assert_allclose(robot.forward_dynamics(q, v, tau), want, atol=1e-7)


def invariants(robot: screwkit.Robot, samples: int, aba: bool) -> None:
    """M symmetric (positive definite with mass on every joint), its columns ID(q, 0, e_i) −
    g(q), FD(ID(a)) = a, ½ vᵀ M v the kinetic energy."""
    rng = np.random.default_rng(5)
    for q in configurations(robot, samples, 4):
        v, a = rng.normal(size=robot.nv), rng.normal(size=robot.nv)
        mass, g = robot.mass_matrix(q), robot.gravity(q)
        np.testing.assert_array_equal(mass, mass.T)
        zero = np.zeros(robot.nv)
        columns = np.stack([robot.inverse_dynamics(q, zero, e) - g for e in np.eye(robot.nv)], 1)
        np.testing.assert_allclose(mass, columns, atol=1e-9 * (1 + np.abs(mass).max()))
        np.testing.assert_allclose(
            robot.kinetic_energy(q, v), 0.5 * v @ mass @ v, rtol=1e-12, atol=1e-12
        )
        if aba:
            assert np.linalg.eigvalsh(mass).min() > 0
            tau = robot.inverse_dynamics(q, v, a)
            np.testing.assert_allclose(robot.forward_dynamics(q, v, tau), a, atol=1e-7)


ERD = {
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "panda": "panda_description/urdf/panda.urdf",
    "talos": "talos_data/robots/talos_reduced.urdf",
}


@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
@pytest.mark.parametrize("name", sorted(ERD))
def test_example_robot_data_equals_pinocchio(name: str, floating: bool) -> None:
    path = ROBOTS / ERD[name]
    if not path.exists():
        pytest.skip("example-robot-data (pip install example-robot-data) is a test dependency")
    check(path, floating)


def with_mass(path: Path) -> bool:
    """Whether every moving joint of the file carries some mass (else M is singular)."""
    robot = load(path, False)
    q = configurations(robot, 1, 1)[0]
    return bool(np.linalg.eigvalsh(robot.mass_matrix(q)).min() > 1e-12)


@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
@pytest.mark.parametrize(
    "file", sorted(p.name for p in ASSETS.glob("*.urdf") if "<inertial" in p.read_text())
)
def test_bundled_robots_equal_pinocchio(file: str, floating: bool) -> None:
    path = ASSETS / file
    check(path, floating, aba=with_mass(path))


SHARED = [
    "panda.urdf",
    "ur5_robot.urdf",
    "xarm7.urdf",
    "z1.urdf",
    "trees/talos_full_v2.urdf",
    "trees/baxter.urdf",
    "trees/allegro_right_hand.urdf",
    "trees/so101.urdf",
]


@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
@pytest.mark.parametrize("path", shared_params("urdf", SHARED))
def test_ci_robots_equal_pinocchio(path: Path, floating: bool) -> None:
    if path.name == "allegro_right_hand.urdf":
        # Its fingertips' principal moments break the triangle inequality: no rigid body has
        # them. Dynamics says so, naming the link; kinematics still loads it.
        robot = load(path, floating)
        with pytest.raises(ValueError, match='link "link_3.0" <inertial>: the principal moments'):
            robot.gravity(robot.neutral())
        assert robot.fk(robot.neutral(), link="link_3.0").shape == (4, 4)
        return
    check(path, floating, samples=2, aba=with_mass(path))


def test_gravity_is_the_gradient_of_the_potential_energy() -> None:
    """g(q) = ∂V/∂q (central differences) on the bundled humanoid: the potential energy and
    the gravity forces agree without Pinocchio."""
    robot = load(ASSETS / "humanoid.urdf", False)
    for q in configurations(robot, 3, 9):
        h = 1e-6
        grad = [
            (robot.potential_energy(q + h * e) - robot.potential_energy(q - h * e)) / (2 * h)
            for e in np.eye(robot.nq)
        ]
        assert np.abs(grad).max() > 1.0
        np.testing.assert_allclose(robot.gravity(q), grad, atol=1e-6)


def test_bad_inputs_are_refused() -> None:
    robot = load(ASSETS / "humanoid.urdf", False)
    q = np.zeros(robot.nq)
    with pytest.raises(ValueError, match="v"):
        robot.inverse_dynamics(q, np.zeros(3), np.zeros(robot.nv))
    with pytest.raises(ValueError, match="not finite"):
        robot.gravity(np.full(robot.nq, np.nan))


def test_the_command_line_reports_the_same_dynamics() -> None:
    """`screwkit dynamics FILE --q --v --a --format json`: the library's numbers (the floor's
    report), the massless links warned about once; a q of the wrong length is one line."""
    import json
    import os
    import subprocess

    exe = os.environ.get("SCREWKIT_CLI")
    if not exe:
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    path = ASSETS / "humanoid.urdf"
    robot = load(path, False)
    rng = np.random.default_rng(2)
    q, v, a = configurations(robot, 1, 8)[0], rng.normal(size=robot.nv), rng.normal(size=robot.nv)

    def arg(x: F64) -> str:
        return ",".join(repr(float(t)) for t in x)

    args = [exe, "dynamics", str(path), "--q", arg(q), "--v", arg(v), "--a", arg(a)]
    done = subprocess.run([*args, "--format", "json"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stderr.count("taken as massless") == 1
    report = json.loads(done.stdout)
    assert report["variables"] == robot.v_names
    np.testing.assert_array_equal(report["tau"], robot.inverse_dynamics(q, v, a))
    np.testing.assert_array_equal(report["gravity"], robot.gravity(q))
    np.testing.assert_array_equal(report["nonlinear_effects"], robot.nonlinear_effects(q, v))
    np.testing.assert_array_equal(report["mass_matrix"], robot.mass_matrix(q))
    assert report["kinetic_energy"] == robot.kinetic_energy(q, v)
    bad = subprocess.run([exe, "dynamics", str(path), "--q", "0,0"], capture_output=True, text=True)
    assert bad.returncode == 1 and len(bad.stderr.strip().splitlines()) == 1, bad.stderr
    assert "expected 23" in bad.stderr or "23" in bad.stderr, bad.stderr
    # Batch mode: JSON lines, v and a optional; a bad line reported with its number, the
    # others computed (exit 1).
    qs = configurations(robot, 3, 12)
    lines = [
        {"q": qs[0].tolist(), "v": v.tolist(), "a": a.tolist()},
        {"q": [0.0, 0.0]},
        {"q": qs[1].tolist()},
        {"q": qs[2].tolist(), "v": v.tolist()},
    ]
    batch = subprocess.run(
        [exe, "dynamics", str(path), "--input", "-"],
        input="\n".join(json.dumps(x) for x in lines) + "\n",
        capture_output=True,
        text=True,
    )
    assert batch.returncode == 1, batch.stderr
    assert batch.stderr.count("taken as massless") == 1
    out = [json.loads(x) for x in batch.stdout.splitlines()]
    assert len(out) == 4 and out[1]["line"] == 2 and "23" in out[1]["error"]
    zero = np.zeros(robot.nv)
    for row, (qq, vv, aa) in zip(
        [out[0], out[2], out[3]],
        [(qs[0], v, a), (qs[1], zero, zero), (qs[2], v, zero)],
        strict=True,
    ):
        np.testing.assert_array_equal(row["tau"], robot.inverse_dynamics(qq, vv, aa))
        np.testing.assert_array_equal(row["mass_matrix"], robot.mass_matrix(qq))
        np.testing.assert_array_equal(row["nonlinear_effects"], robot.nonlinear_effects(qq, vv))


def test_batches_are_rows_of_single_calls() -> None:
    """A leading N: every quantity of a batch equals the single call row by row, bit for bit,
    on one thread and on two; a bad row raises `BatchError` naming it, NaN there, the others
    computed."""
    robot = load(ASSETS / "humanoid.urdf", True)
    qs = np.stack(configurations(robot, 300, 12))
    rng = np.random.default_rng(4)
    vs, xs = rng.normal(size=(300, robot.nv)), rng.normal(size=(300, robot.nv))
    calls = [
        ("inverse_dynamics", (qs, vs, xs)),
        ("gravity", (qs,)),
        ("nonlinear_effects", (qs, vs)),
        ("mass_matrix", (qs,)),
        ("forward_dynamics", (qs, vs, xs)),
        ("kinetic_energy", (qs, vs)),
        ("potential_energy", (qs,)),
    ]
    threads = screwkit.num_threads()
    try:
        for n in (1, 2):
            screwkit.set_num_threads(n)
            for name, args in calls:
                f = getattr(robot, name)
                batch = f(*args)
                assert len(batch) == 300
                for k in (0, 137, 299):
                    np.testing.assert_array_equal(batch[k], f(*(a[k] for a in args)), err_msg=name)
    finally:
        screwkit.set_num_threads(threads)
    bad = qs.copy()
    bad[5, 9] = np.nan
    with pytest.raises(screwkit.BatchError) as e:
        robot.gravity(bad)
    assert e.value.rows == [5]
    result = np.asarray(e.value.result)
    assert np.isnan(result[5]).all() and np.isfinite(np.delete(result, 5, axis=0)).all()
    with pytest.raises(ValueError, match=r"v: expected shape \(300, 29\)"):
        robot.nonlinear_effects(qs, vs[:, :3])


mujoco = pytest.importorskip("mujoco", reason="MuJoCo (pip install mujoco) is a test dependency")


def mujoco_check(path: Path, samples: int = 3) -> None:
    """Against MuJoCo (`mj_rne`, `mj_fullM`, `qfrc_bias`; armature and damping set to 0): the
    file's joints by name; a free joint's velocity is MuJoCo's (linear in the world, angular
    in the body), ours (ω, v) in the body: v_ours = T v_mj, so M_mj = Tᵀ M T and
    g_mj = Tᵀ g."""
    import re

    from test_mjcf import mesh_free

    robot = screwkit.Robot.from_file(path)
    # Armature out of the file itself (zeroing MuJoCo's dof_armature after compiling leaves it
    # in the mass matrix of slide joints: dof_M0).
    text = re.sub(r"""armature\s*=\s*(['"])[^'"]*\1""", "", mesh_free(path.read_text()))
    m = mujoco.MjModel.from_xml_string(text)
    assert not m.dof_armature.any()
    m.dof_damping[:] = 0.0
    d = mujoco.MjData(m)
    free = robot.floating_base
    rng = np.random.default_rng(1)
    for q in configurations(robot, samples, 6):
        t = to_mujoco(m, d, robot, q)
        d.qvel[:] = 0.0
        d.qacc[:] = 0.0
        mujoco.mj_forward(m, d)
        full = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, full)
        scale = 1 + np.abs(full).max()
        np.testing.assert_allclose(full, t.T @ robot.mass_matrix(q) @ t, atol=1e-9 * scale)
        np.testing.assert_allclose(d.qfrc_bias, t.T @ robot.gravity(q), atol=1e-9 * scale)
        if free:
            continue
        v = rng.normal(size=m.nv)
        acc = rng.normal(size=m.nv)
        d.qvel[:] = v
        mujoco.mj_forward(m, d)
        np.testing.assert_allclose(
            d.qfrc_bias, t.T @ robot.nonlinear_effects(q, t @ v), atol=1e-9 * scale
        )
        out = np.zeros(m.nv)
        d.qacc[:] = acc
        mujoco.mj_rne(m, d, 1, out)
        np.testing.assert_allclose(
            out, t.T @ robot.inverse_dynamics(q, t @ v, t @ acc), atol=1e-9 * scale
        )


def to_mujoco(m: Any, d: Any, robot: screwkit.Robot, q: F64) -> F64:
    """Puts our q into MuJoCo's `d.qpos` (its joints by name; a free joint's quaternion
    (x, y, z, w) as MuJoCo's (w, x, y, z)) and returns T with v_ours = T qvel: a free joint's
    velocity is MuJoCo's (linear in the world, angular in the body), ours (ω, v) in the body, so
    M_mj = Tᵀ M T and g_mj = Tᵀ g."""
    assert m.nv == robot.nv
    free = robot.floating_base
    off = 6 if free else 0
    njnt = m.njnt
    dof = {m.joint(j).name: int(m.jnt_dofadr[j]) for j in range(njnt)}
    qadr = {m.joint(j).name: int(m.jnt_qposadr[j]) for j in range(njnt)}
    qpos = m.qpos0.copy()
    t = np.zeros((robot.nv, robot.nv))
    if free:
        fj = next(j for j in range(njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE)
        a = m.jnt_qposadr[fj]
        qpos[a : a + 3] = q[:3]
        qpos[a + 3] = q[6]
        qpos[a + 4 : a + 7] = q[3:6]
        fa = m.jnt_dofadr[fj]
        r = np.array(pin_quat_to_matrix(q[3:7]))
        t[0:3, fa + 3 : fa + 6] = np.eye(3)  # ω in the body
        t[3:6, fa : fa + 3] = r.T  # v_b = Rᵀ v_world
    for n, x in zip(robot.q_names[7 if free else 0 :], q[7 if free else 0 :], strict=True):
        qpos[qadr[n]] = x
    for k, name in enumerate(robot.v_names[off:]):
        t[off + k, dof[name]] = 1.0
    d.qpos[:] = qpos
    return t


def pin_quat_to_matrix(xyzw: F64) -> F64:
    x, y, z, w = xyzw / np.linalg.norm(xyzw)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def test_the_bundled_humanoid_equals_mujoco() -> None:
    """The bundled MJCF humanoid (a free joint, every body with its <inertial>): M and g."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mujoco_check(REPO_MJCF / "humanoid.xml")


@pytest.mark.parametrize(
    "path", shared_params("mjcf", ["robosuite_panda.xml", "ant.xml", "humanoid.xml", "pusher.xml"])
)
def test_mjcf_models_equal_mujoco(path: Path) -> None:
    """robosuite's Panda (every body with its <inertial>), and gym's ant, humanoid and pusher
    (every body's inertia from its geoms: MuJoCo's `inertiafromgeom`, spheres, capsules,
    cylinders, boxes at density 1000 or their `mass`): M and g against MuJoCo, and h and ID
    on a fixed base."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mujoco_check(path)


def test_wrenches_at_frames_against_pinocchio() -> None:
    """Statics and external wrenches (issue 50): `static_torques(q, {frame: F})` is Σ J_fᵀ F_f
    with Pinocchio's frame Jacobians (LOCAL: the wrench in the frame's own coordinates), and
    `inverse_dynamics(q, v, a, f_ext=…)` subtracts the same for wrenches on the robot; the
    UR5 of example-robot-data, two frames."""
    path = ROBOTS / ERD["ur5"]
    if not path.exists():
        pytest.skip("example-robot-data (pip install example-robot-data) is a test dependency")
    robot = load(path, False)
    oracle = Oracle(path, robot, False)
    m, d = oracle.model, oracle.data
    rng = np.random.default_rng(3)
    frames = ["ee_link", "forearm_link"]
    for q in configurations(robot, 3, 2):
        qp = oracle.q(q)
        pin.computeJointJacobians(m, d, qp)
        pin.framesForwardKinematics(m, d, qp)
        wrenches = {f: rng.normal(size=6) for f in frames}
        want = np.zeros(robot.nv)
        for f, w in wrenches.items():
            jac = pin.getFrameJacobian(m, d, m.getFrameId(f), pin.LOCAL)  # rows (v, ω)
            want += oracle.ours(jac.T @ np.r_[w[3:], w[:3]])  # our (m, f) as Pinocchio's (f, m)
        got = robot.static_torques(q, wrenches)
        np.testing.assert_allclose(got, want, atol=1e-10)
        np.testing.assert_allclose(
            robot.static_torques(q, wrenches, gravity=True), want + robot.gravity(q), atol=1e-10
        )
        v, a = rng.normal(size=robot.nv), rng.normal(size=robot.nv)
        np.testing.assert_allclose(
            robot.inverse_dynamics(q, v, a, f_ext=wrenches),
            robot.inverse_dynamics(q, v, a) - want,
            atol=1e-10,
        )
    with pytest.raises(ValueError, match="no_such_frame"):
        robot.static_torques(q, {"no_such_frame": np.zeros(6)})
    with pytest.raises(ValueError, match="wrenches"):
        robot.static_torques(q, {"ee_link": np.zeros(5)})


def test_forward_dynamics_with_external_wrenches_against_pinocchio() -> None:
    """`forward_dynamics(q, v, tau, f_ext={frame: F})` = M⁻¹ (τ − h + Σ J_fᵀ F_f), every term
    Pinocchio's (`crba`, `nonLinearEffects`, LOCAL frame Jacobians) on the UR5, and ID of the
    answer with the same wrenches gives τ back."""
    path = ROBOTS / ERD["ur5"]
    if not path.exists():
        pytest.skip("example-robot-data (pip install example-robot-data) is a test dependency")
    robot = load(path, False)
    oracle = Oracle(path, robot, False)
    m, d = oracle.model, oracle.data
    rng = np.random.default_rng(4)
    for q in configurations(robot, 3, 5):
        qp = oracle.q(q)
        v, tau = rng.normal(size=robot.nv), rng.normal(size=robot.nv)
        pin.computeJointJacobians(m, d, qp)
        pin.framesForwardKinematics(m, d, qp)
        wrenches = {"ee_link": rng.normal(size=6), "upper_arm_link": rng.normal(size=6)}
        jt_f = np.zeros(robot.nv)
        for f, w in wrenches.items():
            jac = pin.getFrameJacobian(m, d, m.getFrameId(f), pin.LOCAL)  # rows (v, ω)
            jt_f += oracle.ours(jac.T @ np.r_[w[3:], w[:3]])
        mass = oracle.matrix(pin.crba(m, d, qp))
        h = oracle.ours(pin.nonLinearEffects(m, d, qp, oracle.v(v)))
        want = np.linalg.solve(mass, tau - h + jt_f)
        got = robot.forward_dynamics(q, v, tau, f_ext=wrenches)
        np.testing.assert_allclose(got, want, atol=1e-9 * (1 + np.abs(want).max()))
        assert np.abs(got - robot.forward_dynamics(q, v, tau)).max() > 1e-3, "the wrenches act"
        np.testing.assert_allclose(
            robot.inverse_dynamics(q, v, got, f_ext=wrenches), tau, atol=1e-9
        )
    with pytest.raises(ValueError, match="no_such_frame"):
        robot.forward_dynamics(q, v, tau, f_ext={"no_such_frame": np.zeros(6)})


@pytest.mark.parametrize(
    ("where", "floating"),
    [("ur5", False), ("talos", True), ("humanoid", True), ("humanoid", False)],
)
def test_centroidal_momentum_equals_pinocchio(where: str, floating: bool) -> None:
    """The centroidal momentum map and momentum (angular about the centre of mass, then
    linear; world axes) against Pinocchio's `computeCentroidalMap` and
    `computeCentroidalMomentum` ((linear, angular) rows), fixed and floating."""
    path = ASSETS / "humanoid.urdf" if where == "humanoid" else ROBOTS / ERD[where]
    if not path.exists():
        pytest.skip("example-robot-data (pip install example-robot-data) is a test dependency")
    robot = load(path, floating)
    oracle = Oracle(path, robot, floating)
    m, d = oracle.model, oracle.data
    rng = np.random.default_rng(8)
    for q in configurations(robot, 3, 6):
        qp = oracle.q(q)
        v = rng.normal(size=robot.nv)
        theirs = pin.computeCentroidalMap(m, d, qp)
        # Ours is about the centre of mass of every link (`Robot.com`); Pinocchio's leaves out
        # the links fixed to the world (a fixed base's): its angular rows are moved to ours,
        # k = k_pin − (c − c_pin) × p.
        c = robot.com(q)
        shift = c - d.com[0]
        assert floating == (np.abs(shift).max() < 1e-12)
        linear = np.stack([oracle.ours(row) for row in theirs[:3]])
        angular = np.stack([oracle.ours(row) for row in theirs[3:]])
        angular -= np.cross(shift, linear.T).T
        want = np.r_[angular, linear]
        got = robot.centroidal_map(q)
        assert got.shape == (6, robot.nv)
        scale = 1 + np.abs(want).max()
        np.testing.assert_allclose(got, want, atol=1e-9 * scale)
        hg = pin.computeCentroidalMomentum(m, d, qp, oracle.v(v))
        np.testing.assert_allclose(
            robot.centroidal_momentum(q, v),
            np.r_[hg.angular - np.cross(shift, hg.linear), hg.linear],
            atol=1e-9 * scale,
        )
        # The linear momentum is the total mass times the centre of mass's velocity.
        np.testing.assert_allclose(
            robot.centroidal_momentum(q, v)[3:],
            robot.total_mass * (robot.com_jacobian(q) @ v),
            atol=1e-9 * scale,
        )


@pytest.mark.parametrize(
    "path",
    [REPO_MJCF / "humanoid.xml"]
    + shared_params("mjcf", ["robosuite_panda.xml", "ant.xml", "humanoid.xml", "pusher.xml"]),
)
def test_armature_and_damping_equal_mujoco(path: Path) -> None:
    """With `set_dynamics_options(armature=True, damping=True)`: M equals MuJoCo's `mj_fullM`
    with the file's armature, the damping force is MuJoCo's `qfrc_passive` (springs, fluid and
    gravity compensation off), and on a fixed base forward dynamics equals M⁻¹ (τ + passive −
    bias) from MuJoCo's own terms; off by default (M without armature)."""
    from test_mjcf import mesh_free

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = screwkit.Robot.from_file(path)
        plain = screwkit.Robot.from_file(path)
    robot.set_dynamics_options(armature=True, damping=True)
    m = mujoco.MjModel.from_xml_string(mesh_free(path.read_text()))
    m.jnt_stiffness[:] = 0.0
    m.opt.density = 0.0
    m.opt.viscosity = 0.0
    m.body_gravcomp[:] = 0.0
    free = robot.floating_base
    if free:
        # Our armature and damping are the joints' own; a free joint's are not read.
        fa = next(int(m.jnt_dofadr[j]) for j in range(m.njnt) if m.jnt_type[j] == 0)
        assert not m.dof_armature[fa : fa + 6].any()
        m.dof_damping[fa : fa + 6] = 0.0
    assert m.dof_armature.any() or m.dof_damping.any(), "the file has some"
    d = mujoco.MjData(m)
    rng = np.random.default_rng(2)
    for q in configurations(robot, 3, 11):
        t = to_mujoco(m, d, robot, q)
        v = rng.normal(size=m.nv)
        d.qvel[:] = v
        mujoco.mj_forward(m, d)
        full = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, full)
        scale = 1 + np.abs(full).max()
        mass = robot.mass_matrix(q)
        np.testing.assert_allclose(full, t.T @ mass @ t, atol=1e-9 * scale)
        if m.dof_armature.any():
            assert np.abs(mass - plain.mass_matrix(q)).max() > 1e-6, "armature off by default"
        ours_v = t @ v
        damper = robot.nonlinear_effects(q, ours_v) - plain.nonlinear_effects(q, ours_v)
        np.testing.assert_allclose(-(t.T @ damper), d.qfrc_passive, atol=1e-9 * scale)
        if not free:
            tau = rng.normal(size=m.nv)
            want = np.linalg.solve(full, tau + d.qfrc_passive - d.qfrc_bias)
            got = robot.forward_dynamics(q, ours_v, t @ tau)
            np.testing.assert_allclose(got, t @ want, atol=1e-8 * (1 + np.abs(want).max()))
            np.testing.assert_allclose(
                robot.inverse_dynamics(q, ours_v, got), t @ tau, atol=1e-8 * scale
            )


def test_impossible_inertias_are_refused_taken_or_balanced_as_mujoco_does() -> None:
    """A body whose principal moments break the triangle inequality: refused by default, naming
    it; `inertias="as-given"` takes it; `inertias="balance"` gives MuJoCo's own M and bias with
    `<compiler balanceinertia="true">` (the three moments set to their mean)."""
    body = """<mujoco><compiler angle="radian" {c}/><worldbody>
      <body name="upper"><joint name="a" type="hinge" axis="0 1 0"/>
        <inertial pos="0.1 0 0" mass="2" diaginertia="0.02 0.03 0.04"/>
        <body name="bad" pos="0.3 0 0"><joint name="b" type="hinge" axis="1 0 0"/>
          <inertial pos="0.05 0.01 0" mass="1" fullinertia="0.1 0.01 0.02 0.001 0.002 0.003"/>
        </body></body></worldbody></mujoco>"""
    path = Path(__file__).parent / "_impossible_inertia.xml"
    path.write_text(body.format(c=""))
    try:
        robot = screwkit.Robot.from_file(path)
        with pytest.raises(ValueError, match='link "bad" <inertial>: the principal moments'):
            robot.mass_matrix([0.1, 0.2])
        robot.set_dynamics_options(inertias="as-given")
        robot.mass_matrix([0.1, 0.2])
        with pytest.raises(ValueError, match="inertias"):
            robot.set_dynamics_options(inertias="guess")  # type: ignore[arg-type]
        robot.set_dynamics_options(inertias="balance")
        m = mujoco.MjModel.from_xml_string(body.format(c='balanceinertia="true"'))
        d = mujoco.MjData(m)
        for q in ([0.1, 0.2], [-1.0, 2.5]):
            d.qpos[:] = q
            d.qvel[:] = 0.0
            mujoco.mj_forward(m, d)
            full = np.zeros((2, 2))
            mujoco.mj_fullM(m, d, full)
            np.testing.assert_allclose(robot.mass_matrix(q), full, atol=1e-12)
            np.testing.assert_allclose(robot.gravity(q), d.qfrc_bias, atol=1e-12)
    finally:
        path.unlink()


def test_the_command_line_takes_the_same_dynamics_options() -> None:
    """`screwkit dynamics --armature --damping --inertias WORD` = `set_dynamics_options`."""
    import json
    import os
    import subprocess

    exe = os.environ.get("SCREWKIT_CLI")
    if not exe:
        pytest.skip("SCREWKIT_CLI (the screwkit binary) not given: run `cargo xtask test`")
    path = REPO_MJCF / "humanoid.xml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = screwkit.Robot.from_file(path)
    robot.set_dynamics_options(inertias="balance", armature=True, damping=True)
    rng = np.random.default_rng(3)
    q, v = configurations(robot, 1, 13)[0], rng.normal(size=robot.nv)
    args = [exe, "dynamics", str(path), "--q", ",".join(map(repr, map(float, q)))]
    args += ["--v", ",".join(map(repr, map(float, v))), "--format", "json"]
    done = subprocess.run(
        [*args, "--armature", "--damping", "--inertias", "balance"], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    np.testing.assert_array_equal(report["mass_matrix"], robot.mass_matrix(q))
    np.testing.assert_array_equal(report["nonlinear_effects"], robot.nonlinear_effects(q, v))
    bad = subprocess.run([*args, "--inertias", "guess"], capture_output=True, text=True)
    assert bad.returncode != 0 and "balance" in bad.stderr, bad.stderr


def test_urdf_damping_is_the_files_as_pinocchio_reads_it() -> None:
    """`set_dynamics_options(damping=True)` adds D v to h with D the file's
    `<dynamics damping>` per joint, as Pinocchio's parser reads it (`model.damping`), on
    TALOS (floating: the base's six entries undamped); M and gravity unchanged."""
    path = ROBOTS / ERD["talos"]
    if not path.exists():
        pytest.skip("example-robot-data (pip install example-robot-data) is a test dependency")
    robot, plain = load(path, True), load(path, True)
    robot.set_dynamics_options(damping=True)
    oracle = Oracle(path, robot, True)
    damping = oracle.ours(oracle.model.damping)
    assert damping[6:].max() > 0.5 and not damping[:6].any()
    rng = np.random.default_rng(9)
    for q in configurations(robot, 2, 14):
        v = rng.normal(size=robot.nv)
        np.testing.assert_allclose(
            robot.nonlinear_effects(q, v) - plain.nonlinear_effects(q, v), damping * v, atol=1e-9
        )
        np.testing.assert_array_equal(robot.mass_matrix(q), plain.mass_matrix(q))
        np.testing.assert_array_equal(robot.gravity(q), plain.gravity(q))


def l_prism_obj(path: Path) -> None:
    """An L-shaped prism (non-convex, closed, outward triangles) as an OBJ file."""
    profile = [(0, 0), (0.3, 0), (0.3, 0.1), (0.1, 0.1), (0.1, 0.3), (0, 0.3)]
    n = len(profile)
    verts = [(x, y, 0.0) for x, y in profile] + [(x, y, 0.1) for x, y in profile]
    cap = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]
    faces = [(a, c, b) for a, b, c in cap] + [(a + n, b + n, c + n) for a, b, c in cap]
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, j + n), (i, j + n, i + n)]
    lines = [f"v {x} {y} {z}" for x, y, z in verts]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("mode", ["", "legacy", "exact", "shell"])
def test_mesh_bodies_are_weighed_as_mujoco_does(tmp_path: Path, mode: str) -> None:
    """MJCF bodies weighed from mesh geoms (`inertiafromgeom`): MuJoCo's pyramids from the
    triangles' centroid (`legacy`, its default, overcounting a non-convex mesh; `exact`;
    `shell`), on a non-convex L prism, scaled, placed off the body's origin and turned, one with
    a `mass` instead of the density, beside a box: total mass, M and g equal MuJoCo's (to its
    float32 vertices)."""
    l_prism_obj(tmp_path / "l.obj")
    inertia = f'inertia="{mode}"' if mode else ""
    xml = f"""<mujoco><compiler angle="radian"/>
      <asset><mesh name="l" file="l.obj" scale="1 1.5 0.8" {inertia}/></asset>
      <worldbody><body name="a"><joint name="j1" type="hinge" axis="0 1 0"/>
        <geom type="mesh" mesh="l" pos="0.1 0 0.05" quat="0.9 0.1 0.3 0.2"/>
        <geom type="box" size="0.05 0.05 0.05" pos="0 0 -0.1"/>
        <body name="b" pos="0.4 0 0"><joint name="j2" type="hinge" axis="1 0 0"/>
          <geom type="mesh" mesh="l" mass="2.5" euler="0.3 0 1"/>
        </body></body></worldbody></mujoco>"""
    path = tmp_path / "mesh_bodies.xml"
    path.write_text(xml)
    robot = screwkit.Robot.from_file(path)
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    np.testing.assert_allclose(robot.total_mass, m.body_mass.sum(), rtol=1e-6)
    for q in ([0.0, 0.0], [0.7, -1.2], [2.0, 0.4]):
        d.qpos[:] = q
        mujoco.mj_forward(m, d)
        full = np.zeros((2, 2))
        mujoco.mj_fullM(m, d, full)
        np.testing.assert_allclose(robot.mass_matrix(q), full, rtol=1e-5, atol=1e-9)
        np.testing.assert_allclose(robot.gravity(q), d.qfrc_bias, rtol=1e-5, atol=1e-8)


def test_a_mesh_that_cannot_be_weighed_is_named(tmp_path: Path) -> None:
    """`inertia="convex"` (the hull's, not computed here) and a flat mesh (no volume, which
    MuJoCo refuses too): the body is named in the massless warning and left massless, never
    guessed."""
    l_prism_obj(tmp_path / "l.obj")
    square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\nf 1 3 2\nf 1 4 3\n"
    (tmp_path / "flat.obj").write_text(square)
    for asset, says in [
        ('file="l.obj" inertia="convex"', "convex"),
        ('file="flat.obj" inertia="exact"', "volume is too small"),
    ]:
        xml = f"""<mujoco><asset><mesh name="l" {asset}/></asset><worldbody>
          <body name="a"><joint name="j" type="hinge"/><geom type="mesh" mesh="l"/></body>
          </worldbody></mujoco>"""
        path = tmp_path / "m.xml"
        path.write_text(xml)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            robot = screwkit.Robot.from_file(path)
            g = robot.gravity([0.0])
        text = " ".join(str(w.message) for w in caught)
        assert "body a takes its mass from geoms" in text and says in text, text
        assert g.shape == (1,) and g[0] == 0.0, "massless, nothing guessed"
        # One variable: still a vector, and a batch (N, 1).
        assert robot.mass_matrix([0.0]).shape == (1, 1)
        assert robot.gravity(np.zeros((3, 1))).shape == (3, 1)
