"""`screwkit.dynamics` against the `modern_robotics` package (the textbook's own library) on
random open chains of revolute, prismatic and helical joints: every function equal to its
namesake to 1e-12 (relative to the largest entry); bad lists refused by name."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest

from screwkit import dynamics

mr = pytest.importorskip("modern_robotics", reason="modern_robotics is a test dependency")

F64 = npt.NDArray[np.float64]


def rotation(rng: np.random.Generator) -> F64:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    out: F64 = q if np.linalg.det(q) > 0 else -q
    return out


def chain(seed: int, n: int = 5) -> tuple[list[F64], list[F64], F64]:
    """A random chain: link frames anywhere, rigid-body inertias (a tensor turned off its
    principal axes is still diagonal in MR's convention: the CoM frame's), and joints of
    each kind."""
    rng = np.random.default_rng(seed)
    mlist = []
    for _ in range(n + 1):
        t = np.eye(4)
        t[:3, :3] = rotation(rng)
        t[:3, 3] = rng.normal(size=3) * 0.4
        mlist.append(t)
    glist = []
    for _ in range(n):
        a, b = rng.uniform(0.05, 0.5, size=2)
        principal = np.array([a, b, rng.uniform(abs(a - b), a + b)])
        glist.append(np.diag(np.r_[principal, [rng.uniform(0.5, 3.0)] * 3]))
    home = np.eye(4)
    slist = np.zeros((6, n))
    for i in range(n):
        home = home @ mlist[i]
        w = rng.normal(size=3)
        w /= np.linalg.norm(w)
        p = home[:3, 3]
        kind = i % 3
        if kind == 0:  # revolute
            slist[:, i] = np.r_[w, -np.cross(w, p)]
        elif kind == 1:  # prismatic
            slist[:, i] = np.r_[0, 0, 0, w]
        else:  # helical, pitch 0.1 m/rad
            slist[:, i] = np.r_[w, -np.cross(w, p) + 0.1 * w]
    return mlist, glist, slist


def close(a: object, b: object) -> None:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * (1 + np.abs(b).max()))


@pytest.mark.parametrize("seed", range(6))
def test_every_function_equals_modern_robotics(seed: int) -> None:
    mlist, glist, slist = chain(seed)
    rng = np.random.default_rng(100 + seed)
    n = slist.shape[1]
    th, dth, ddth = rng.normal(size=n), rng.normal(size=n), rng.normal(size=n)
    g = np.array([0.0, -3.0, -9.8])
    ftip = rng.normal(size=6)
    tau = rng.normal(size=n) * 5
    args = (mlist, glist, slist)
    close(
        dynamics.inverse_dynamics(th, dth, ddth, g, ftip, *args),
        mr.InverseDynamics(th, dth, ddth, g, ftip, *args),
    )
    close(dynamics.mass_matrix(th, *args), mr.MassMatrix(th, *args))
    close(dynamics.vel_quadratic_forces(th, dth, *args), mr.VelQuadraticForces(th, dth, *args))
    close(dynamics.gravity_forces(th, g, *args), mr.GravityForces(th, g, *args))
    close(dynamics.end_effector_forces(th, ftip, *args), mr.EndEffectorForces(th, ftip, *args))
    close(
        dynamics.forward_dynamics(th, dth, tau, g, ftip, *args),
        mr.ForwardDynamics(th, dth, tau, g, ftip, *args),
    )
    rows = rng.normal(size=(4, n)), rng.normal(size=(4, n)), rng.normal(size=(4, n))
    ftips = rng.normal(size=(4, 6))
    close(
        dynamics.inverse_dynamics_trajectory(*rows, g, ftips, *args),
        mr.InverseDynamicsTrajectory(*rows, g, ftips, *args),
    )


def test_the_textbooks_example() -> None:
    """*Modern Robotics*' own example (the UR5 of §8.5's code listing, `help(mr.MassMatrix)`):
    the same mass matrix."""
    m01 = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.089159], [0, 0, 0, 1]])
    m12 = np.array([[0, 0, 1, 0.28], [0, 1, 0, 0.13585], [-1, 0, 0, 0], [0, 0, 0, 1]])
    m23 = np.array([[1, 0, 0, 0], [0, 1, 0, -0.1197], [0, 0, 1, 0.395], [0, 0, 0, 1]])
    m34 = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.14225], [0, 0, 0, 1]])
    g1 = np.diag([0.010267, 0.010267, 0.00666, 3.7, 3.7, 3.7])
    g2 = np.diag([0.22689, 0.22689, 0.0151074, 8.393, 8.393, 8.393])
    g3 = np.diag([0.0494433, 0.0494433, 0.004095, 2.275, 2.275, 2.275])
    s = np.array([[1, 0, 1, 0, 1, 0], [0, 1, 0, -0.089, 0, 0], [0, 1, 0, -0.089, 0, 0.425]]).T
    th = [0.1, 0.1, 0.1]
    want = [
        [2.25433380e01, -3.07146754e-01, -7.18426391e-03],
        [-3.07146754e-01, 1.96850717e00, 4.32157368e-01],
        [-7.18426391e-03, 4.32157368e-01, 1.91630858e-01],
    ]
    got = dynamics.mass_matrix(th, [m01, m12, m23, m34], [g1, g2, g3], s)
    np.testing.assert_allclose(got, want, rtol=1e-8)


def test_bad_lists_are_refused() -> None:
    mlist, glist, slist = chain(0, 3)
    th = np.zeros(3)
    with pytest.raises(ValueError, match="Mlist: expected shape \\(4, 4, 4\\)"):
        dynamics.mass_matrix(th, mlist[:3], glist, slist)
    with pytest.raises(ValueError, match="Slist: expected shape \\(6, n\\)"):
        dynamics.mass_matrix(th, mlist, glist, slist.T)
    bad = [g.copy() for g in glist]
    bad[1][3, 4] = 1.0
    with pytest.raises(ValueError, match="Glist\\[1\\]"):
        dynamics.mass_matrix(th, mlist, bad, slist)
    with pytest.raises(ValueError, match="thetalist: expected shape \\(3,\\)"):
        dynamics.mass_matrix(np.zeros(2), mlist, glist, slist)
    with pytest.raises(ValueError, match="Mlist\\[2\\]"):
        dynamics.mass_matrix(
            th, [m if k != 2 else 2 * m for k, m in enumerate(mlist)], glist, slist
        )


def test_the_module_examples_print_what_they_say() -> None:
    import doctest

    import screwkit.lie

    for module in (dynamics, screwkit.lie):
        result = doctest.testmod(module)
        assert result.attempted > 0 and result.failed == 0, module.__name__
