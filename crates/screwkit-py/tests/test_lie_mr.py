"""`screwkit.lie` against the library of the textbook's authors (`modern_robotics`, "MR"):
its documented examples, 1,000 random cases per function, and 40-digit references (mpmath)
where the two disagree, near theta = 0 and theta = pi.

Where MR is wrong (each case below is checked, not just stated):
- `MatrixExp3`/`MatrixExp6` return the identity rotation for norm(omega theta) < 1e-6: an error
  of up to 1e-6 in the rotation (and MatrixExp6 drops it entirely).
- `MatrixLog3` (and so `MatrixLog6`) return 0 once (tr R - 1)/2 rounds to 1, for theta below
  about 1.5e-8 (an error of theta), and near pi divide R - R^T by sin(theta), losing digits as
  1/(pi - theta).
- `ProjectToSO3` negates the third column of U V^T when its determinant is negative: proper,
  but not the nearest rotation (U diag(1, 1, -1) V^T is).
- `AxisAng6` takes norm(omega) < 1e-6 for a pure translation: its "S" then has an omega that is
  neither unit nor zero.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import modern_robotics as mr
import mpmath
import numpy as np
import numpy.typing as npt
import pytest

import screwkit
from screwkit import lie

Array = npt.NDArray[np.float64]
N = 1000


def rng(seed: int) -> np.random.Generator:
    return np.random.default_rng(seed)


def unit(g: np.random.Generator, n: int) -> Array:
    v = g.normal(size=(n, 3))
    out: Array = v / np.linalg.norm(v, axis=1, keepdims=True)
    return out


def rotations(g: np.random.Generator, n: int, lo: float = 0.0, hi: float = np.pi) -> Array:
    """n rotations about random axes by angles uniform in [lo, hi], built by MR (not screwkit)."""
    w = unit(g, n) * g.uniform(lo, hi, size=(n, 1))
    return np.array([mr.MatrixExp3(mr.VecToso3(x)) for x in w])


def transforms(g: np.random.Generator, n: int) -> Array:
    r = rotations(g, n, 0.01, 3.1)
    return np.array(
        [mr.RpToTrans(x, p) for x, p in zip(r, g.normal(size=(n, 3)) * 2, strict=False)]
    )


# --- MR's documented examples (the docstrings' inputs and printed outputs) --------------------


def test_documented_examples() -> None:
    r = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0]], dtype=float)
    np.testing.assert_array_equal(lie.rot_inv(r), [[0, 1, 0], [0, 0, 1], [1, 0, 0]])
    np.testing.assert_array_equal(lie.hat([1, 2, 3]), [[0, -3, 2], [3, 0, -1], [-2, 1, 0]])
    np.testing.assert_array_equal(lie.vee([[0, -3, 2], [3, 0, -1], [-2, 1, 0]]), [1, 2, 3])
    w, th = lie.axis_angle3([1, 2, 3])
    np.testing.assert_allclose(w, [0.26726124, 0.53452248, 0.80178373], atol=1e-8)
    assert th == pytest.approx(3.7416573867739413, abs=1e-15)
    np.testing.assert_allclose(
        lie.exp3([1, 2, 3]),
        [
            [-0.69492056, 0.71352099, 0.08929286],
            [-0.19200697, -0.30378504, 0.93319235],
            [0.69297817, 0.6313497, 0.34810748],
        ],
        atol=1e-8,
    )
    np.testing.assert_allclose(
        lie.hat(lie.log3(r)),
        [[0, -1.20919958, 1.20919958], [1.20919958, 0, -1.20919958], [-1.20919958, 1.20919958, 0]],
        atol=1e-8,
    )
    t = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 3], [0, 0, 0, 1]], dtype=float)
    np.testing.assert_array_equal(
        lie.trans_inv(t), [[1, 0, 0, 0], [0, 0, 1, -3], [0, -1, 0, 0], [0, 0, 0, 1]]
    )
    np.testing.assert_array_equal(
        lie.hat([1, 2, 3, 4, 5, 6]), [[0, -3, 2, 4], [3, 0, -1, 5], [-2, 1, 0, 6], [0, 0, 0, 0]]
    )
    np.testing.assert_array_equal(
        lie.vee([[0, -3, 2, 4], [3, 0, -1, 5], [-2, 1, 0, 6], [0, 0, 0, 0]]), [1, 2, 3, 4, 5, 6]
    )
    np.testing.assert_array_equal(
        lie.adjoint(t),
        [
            [1, 0, 0, 0, 0, 0],
            [0, 0, -1, 0, 0, 0],
            [0, 1, 0, 0, 0, 0],
            [0, 0, 3, 1, 0, 0],
            [3, 0, 0, 0, 0, -1],
            [0, 0, 0, 0, 1, 0],
        ],
    )
    np.testing.assert_array_equal(lie.screw_to_axis([3, 0, 0], [0, 0, 1], 2), [0, 0, 1, 0, -3, 2])
    s, th = lie.axis_angle6([1, 0, 0, 1, 2, 3])
    np.testing.assert_array_equal(s, [1, 0, 0, 1, 2, 3])
    assert th == 1.0
    se3mat = np.array(
        [[0, 0, 0, 0], [0, 0, -1.57079632, 2.35619449], [0, 1.57079632, 0, 2.35619449], [0] * 4],
        dtype=float,
    )
    # The docstring's 8 digits of pi/2 leave 1e-8 in the result; MR's own output is the same.
    np.testing.assert_allclose(lie.exp6(lie.vee(se3mat)), t, atol=2e-8)
    np.testing.assert_allclose(lie.exp6(lie.vee(se3mat)), mr.MatrixExp6(se3mat), atol=1e-15)
    np.testing.assert_allclose(
        lie.hat(lie.log6(t)),
        [
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, -1.57079633, 2.35619449],
            [0.0, 1.57079633, 0.0, 2.35619449],
            [0.0, 0.0, 0.0, 0.0],
        ],
        atol=1e-8,
    )
    m = [[0.675, 0.150, 0.720], [0.370, 0.771, -0.511], [-0.630, 0.619, 0.472]]
    expected = [
        [0.67901136, 0.14894516, 0.71885945],
        [0.37320708, 0.77319584, -0.51272279],
        [-0.63218672, 0.61642804, 0.46942137],
    ]
    np.testing.assert_allclose(lie.project_to_so3(m), expected, atol=1e-8)
    m4 = [
        [0.675, 0.150, 0.720, 1.2],
        [0.370, 0.771, -0.511, 5.4],
        [-0.630, 0.619, 0.472, 3.6],
        [0.003, 0.002, 0.010, 0.9],
    ]
    p = lie.project_to_se3(m4)
    np.testing.assert_allclose(p[:3, :3], expected, atol=1e-8)
    np.testing.assert_array_equal(p[:3, 3], [1.2, 5.4, 3.6])
    np.testing.assert_array_equal(p[3], [0, 0, 0, 1])
    d = [[1.0, 0.0, 0.0], [0.0, 0.1, -0.95], [0.0, 1.0, 0.1]]
    assert lie.distance_to_so3(d) == pytest.approx(0.08835298523536149, abs=1e-15)
    assert lie.is_so3(d) is False
    d4 = [[1.0, 0.0, 0.0, 1.2], [0.0, 0.1, -0.95, 1.5], [0.0, 1.0, 0.1, -0.9], [0, 0, 0.1, 0.98]]
    assert lie.distance_to_se3(d4) == pytest.approx(0.13493053768513638, abs=1e-15)
    assert lie.is_se3(d4) is False
    # ad's docstring example.
    np.testing.assert_array_equal(
        lie.ad([1, 2, 3, 4, 5, 6]),
        [
            [0, -3, 2, 0, 0, 0],
            [3, 0, -1, 0, 0, 0],
            [-2, 1, 0, 0, 0, 0],
            [0, -6, 5, 0, -3, 2],
            [6, 0, -4, 3, 0, -1],
            [-5, 4, 0, -2, 1, 0],
        ],
    )
    # The old top-level names are the same functions.
    assert screwkit.exp is lie.exp6 and screwkit.log is lie.log6
    assert screwkit.adjoint is lie.adjoint


# --- 1,000 random cases per function against MR ------------------------------------------------


def rows_equal(
    ours: Callable[..., Any], theirs: Callable[..., Any], args: list[Array], atol: float
) -> None:
    """ours on the stacked args equals theirs row by row (to atol times the size of theirs, at
    least 1), and equals ours row by row bit for bit (a stack is the single calls)."""
    stacked = ours(*args)
    outs = stacked if isinstance(stacked, tuple) else (stacked,)
    for i in range(len(args[0])):
        row = [a[i] for a in args]
        single = ours(*row)
        single = single if isinstance(single, tuple) else (single,)
        expected = theirs(*row)
        expected = expected if isinstance(expected, tuple) else (expected,)
        for o, s, e in zip(outs, single, expected, strict=False):
            np.testing.assert_array_equal(o[i], s)
            tol = atol * max(1.0, float(np.abs(e).max()))
            np.testing.assert_allclose(o[i], e, rtol=0, atol=tol, err_msg=f"row {i}")


def test_random_screws_and_axes() -> None:
    g = rng(1)
    q, s, h = g.normal(size=(N, 3)) * 3, unit(g, N), g.normal(size=N)
    rows_equal(lie.screw_to_axis, mr.ScrewToAxis, [q, s, h], 1e-14)
    rows_equal(lie.axis_angle3, mr.AxisAng3, [g.normal(size=(N, 3))], 1e-15)
    expc6 = g.normal(size=(N, 6))
    rows_equal(lie.axis_angle6, mr.AxisAng6, [expc6], 1e-15)
    rows_equal(lie.hat, mr.VecToso3, [g.normal(size=(N, 3))], 0)
    rows_equal(lie.hat, mr.VecTose3, [expc6], 0)
    rows_equal(lie.vee, mr.so3ToVec, [lie.hat(g.normal(size=(N, 3)))], 0)
    rows_equal(lie.vee, mr.se3ToVec, [lie.hat(expc6)], 0)
    rows_equal(lie.ad, mr.ad, [expc6], 0)


def test_random_exp_log() -> None:
    g = rng(2)
    # Away from 0 and pi, where MR's formulas are well conditioned (its log divides by sin theta:
    # near pi, see the 40-digit tests below).
    w = unit(g, N) * g.uniform(0.01, 3.1, size=(N, 1))
    rows_equal(lie.exp3, lambda x: mr.MatrixExp3(mr.VecToso3(x)), [w], 1e-14)
    r = rotations(g, N, 0.01, 3.0)
    rows_equal(lie.log3, lambda x: mr.so3ToVec(mr.MatrixLog3(x)), [r], 1e-13)
    xi = np.concatenate([w, g.normal(size=(N, 3)) * 2], axis=1)
    rows_equal(lie.exp6, lambda x: mr.MatrixExp6(mr.VecTose3(x)), [xi], 1e-13)
    t = transforms(g, N)
    rows_equal(lie.log6, lambda x: mr.se3ToVec(mr.MatrixLog6(x)), [t], 2e-12)
    theta = g.uniform(-4, 4, size=N)
    np.testing.assert_array_equal(lie.exp6(xi, theta), lie.exp6(xi * theta[:, None]))
    np.testing.assert_array_equal(lie.exp3(w, 0.5), lie.exp3(w * 0.5))


def test_random_adjoint_and_inverses() -> None:
    g = rng(3)
    t = transforms(g, N)
    rows_equal(lie.adjoint, mr.Adjoint, [t], 1e-15)
    rows_equal(lie.trans_inv, mr.TransInv, [t], 1e-15)
    rows_equal(lie.rot_inv, mr.RotInv, [t[:, :3, :3].copy()], 0)


def test_random_distances() -> None:
    g = rng(4)
    m = g.normal(size=(N, 3, 3))
    m[: N // 2] = rotations(g, N // 2) + g.normal(size=(N // 2, 3, 3)) * 1e-3
    ours = lie.distance_to_so3(m)
    theirs = np.array([mr.DistanceToSO3(x) for x in m])
    proper = theirs != 1e9
    assert proper.sum() > N // 2 and (~proper).sum() > N // 5
    # M^T M - I cancels: both are exact to about 1e-16 absolute.
    np.testing.assert_allclose(ours[proper], theirs[proper], rtol=1e-14, atol=1e-15)
    assert np.all(np.isinf(ours[~proper]))
    m4 = np.concatenate([m, g.normal(size=(N, 3, 1))], axis=2)
    m4 = np.concatenate([m4, g.normal(size=(N, 1, 4)) * 0.01 + [0, 0, 0, 1]], axis=1)
    ours4 = lie.distance_to_se3(m4)
    theirs4 = np.array([mr.DistanceToSE3(x) for x in m4])
    np.testing.assert_allclose(ours4[proper], theirs4[proper], rtol=1e-14, atol=1e-15)
    assert np.all(np.isinf(ours4[~proper]))
    assert isinstance(lie.distance_to_so3(m[0]), float)


def test_is_so3_is_se3() -> None:
    g = rng(5)
    r = rotations(g, N)
    eps = 10.0 ** g.uniform(-9, -2, size=(N, 1, 1))
    m = r + g.normal(size=(N, 3, 3)) * eps
    # The definition, by numpy: max |M^T M - I| <= tol and det M > 0.
    err = np.abs(np.einsum("nji,njk->nik", m, m) - np.eye(3)).max(axis=(1, 2))
    det = np.linalg.det(m)
    for tol in (1e-6, 1e-3):
        expected = (err <= tol) & (det > 0)
        assert 0 < expected.sum() < N
        np.testing.assert_array_equal(lie.is_so3(m, tol), expected)
        # MR's TestIfSO3 (Frobenius < 1e-3) agrees wherever the two criteria are not close.
    theirs = np.array([mr.TestIfSO3(x) for x in m])
    clear = (err < 1e-4) | (err > 1e-2)
    np.testing.assert_array_equal(lie.is_so3(m, 1e-3)[clear], theirs[clear])
    assert lie.is_so3(-r[0]) is False  # det -1
    t = transforms(g, N)
    assert lie.is_se3(t).all()
    bad = t.copy()
    bad[::2, 3, 0] = 1e-3
    np.testing.assert_array_equal(lie.is_se3(bad), np.arange(N) % 2 == 1)
    nan = r[0].copy()
    nan[1, 1] = np.nan
    assert lie.is_so3(nan) is False
    with pytest.raises(ValueError, match="tol"):
        lie.is_so3(r[0], -1.0)


def test_random_projections() -> None:
    g = rng(6)
    # Near SO(3): MR and screwkit agree.
    near = rotations(g, N) + g.normal(size=(N, 3, 3)) * 0.05
    rows_equal(lie.project_to_so3, mr.ProjectToSO3, [near], 1e-13)
    near4 = np.concatenate([near, g.normal(size=(N, 3, 1))], axis=2)
    near4 = np.concatenate([near4, np.tile([0.1, 0, 0, 0.8], (N, 1, 1))], axis=1)
    rows_equal(lie.project_to_se3, mr.ProjectToSE3, [near4], 1e-13)
    # Anywhere: screwkit's is a rotation and never farther from M than MR's; where MR negated a
    # column (det(U V^T) < 0), it is the nearest proper rotation U diag(1, 1, -1) V^T and strictly
    # nearer than MR's.
    m = g.normal(size=(N, 3, 3))
    ours = lie.project_to_so3(m)
    assert np.all(lie.is_so3(ours, 1e-14))
    flipped = 0
    for x, p in zip(m, ours, strict=False):
        u, sv, vt = np.linalg.svd(x)
        theirs = mr.ProjectToSO3(x)
        d_ours, d_theirs = np.linalg.norm(x - p), np.linalg.norm(x - theirs)
        if np.linalg.det(u @ vt) < 0:
            flipped += 1
            np.testing.assert_allclose(p, u @ np.diag([1, 1, -1]) @ vt, atol=1e-13)
            if sv[1] - sv[2] > 1e-9:
                assert d_ours < d_theirs
        else:
            np.testing.assert_allclose(p, theirs, atol=1e-13)
        assert d_ours <= d_theirs + 1e-13
    assert flipped > N // 3


# --- 40-digit references where MR and screwkit differ: near theta = 0 and theta = pi -------------

mpmath.mp.dps = 40


def mp_log3(r: Array) -> Array:
    """The principal logarithm of r (a double 3 x 3, taken exactly) at 40 digits, as omega theta:
    r = V diag(lambda) V^-1, log r = V diag(log lambda) V^-1 (the principal log of each
    eigenvalue; mpmath's `logm` can land on another branch near theta = pi)."""
    lam, v = mpmath.eig(mpmath.matrix(r.tolist()))
    log = v * mpmath.diag([mpmath.log(x) for x in lam]) * mpmath.inverse(v)
    m = np.array([[float(mpmath.re(x)) for x in row] for row in log.tolist()])
    return np.array(mr.so3ToVec((m - m.T) / 2))  # r is orthogonal to 1e-16: its skew part


def mp_log6(t: Array) -> Array:
    """log t at 40 digits: omega theta = mp_log3(R), and v solving G(omega theta) v = p with
    G(phi) = I + (1 - cos t)/t^2 [phi] + (t - sin t)/t^3 [phi]^2 (t = |phi|) in 40 digits."""
    w = mp_log3(t[:3, :3])
    phi = mpmath.matrix(mr.VecToso3(w).tolist())
    th = mpmath.sqrt(sum(mpmath.mpf(x) ** 2 for x in w))
    g = (
        mpmath.eye(3)
        + (1 - mpmath.cos(th)) / th**2 * phi
        + (th - mpmath.sin(th)) / th**3 * (phi * phi)
    )
    v = mpmath.lu_solve(g, mpmath.matrix(t[:3, 3].tolist()))
    return np.concatenate([w, [float(x) for x in v]])


def mp_exp(m: Array) -> Array:
    return np.array(mpmath.expm(mpmath.matrix(m.tolist())).tolist(), dtype=float)


# theta, and whether MR is off there: MR's MatrixLog3 returns 0 once (tr R - 1)/2 rounds to 1
# (theta below about 1.5e-8), and divides R - R^T by sin(theta) near pi.
LOG_CASES = [
    (1e-12, True),
    (1e-9, True),
    (1e-7, False),
    (1e-5, False),
    (np.pi - 1e-5, True),
    (np.pi - 1e-8, True),
]


@pytest.mark.parametrize(("theta", "mr_off"), LOG_CASES)
def test_log3_against_40_digits(theta: float, mr_off: bool) -> None:
    g = rng(int(1e6 * theta) % 1000)
    worst_ours = worst_mr = 0.0
    for w in unit(g, 20) * theta:
        r = mp_exp(mr.VecToso3(w))  # the rotation rounded once to doubles
        ref = mp_log3(r)
        worst_ours = max(worst_ours, np.abs(lie.log3(r) - ref).max())
        worst_mr = max(worst_mr, np.abs(mr.so3ToVec(mr.MatrixLog3(r)) - ref).max())
    assert worst_ours <= 4.5e-16 * max(theta, 1)
    if mr_off:
        assert worst_mr > 100 * max(worst_ours, 1e-18)
    else:
        assert worst_mr <= 4.5e-16 * max(theta, 1)


@pytest.mark.parametrize("theta", [1e-12, 1e-9, 1e-7])
def test_exp3_exp6_near_zero_against_40_digits(theta: float) -> None:
    g = rng(7)
    for x in np.concatenate([unit(g, 20) * theta, g.normal(size=(20, 3))], axis=1):
        ref3 = mp_exp(mr.VecToso3(x[:3]))
        np.testing.assert_allclose(lie.exp3(x[:3]), ref3, rtol=0, atol=2.3e-16)
        ref6 = mp_exp(mr.VecTose3(x))
        np.testing.assert_allclose(lie.exp6(x), ref6, rtol=0, atol=1e-15)
        # MR returns the identity rotation below norm 1e-6: wrong by theta.
        assert np.abs(mr.MatrixExp3(mr.VecToso3(x[:3])) - ref3).max() > 0.5 * theta
        assert np.abs(mr.MatrixExp6(mr.VecTose3(x))[:3, :3] - ref6[:3, :3]).max() > 0.5 * theta


@pytest.mark.parametrize(("theta", "mr_off"), LOG_CASES)
def test_log6_against_40_digits(theta: float, mr_off: bool) -> None:
    g = rng(int(1e6 * theta) % 1000 + 1)
    worst_ours = worst_mr = 0.0
    for x in np.concatenate([unit(g, 10) * theta, g.normal(size=(10, 3))], axis=1):
        t = mp_exp(mr.VecTose3(x))
        ref = mp_log6(t)
        worst_ours = max(worst_ours, np.abs(lie.log6(t) - ref).max())
        worst_mr = max(worst_mr, np.abs(mr.se3ToVec(mr.MatrixLog6(t)) - ref).max())
    assert worst_ours <= 2e-15
    if mr_off:
        assert worst_mr > 100 * max(worst_ours, 1e-18)
    else:
        assert worst_mr <= 2e-15


def test_axis_angle6_small_rotation() -> None:
    # norm(omega) = 1e-7: a screw with a rotation. MR takes it for a translation.
    x = np.array([1e-7, 0, 0, 0, 1, 0])
    s, th = lie.axis_angle6(x)
    assert th == 1e-7
    np.testing.assert_array_equal(s, x / 1e-7)
    s_mr, th_mr = mr.AxisAng6(x)
    # MR: theta = norm(v) = 1 and "S" = x, whose omega is neither unit nor zero: not a screw axis.
    assert th_mr == 1.0 and np.linalg.norm(s_mr[:3]) == 1e-7
    np.testing.assert_allclose(lie.exp6(s, th), lie.exp6(x), atol=1e-15)


# --- stacks, errors ------------------------------------------------------------------------------


def test_shapes_and_errors() -> None:
    with pytest.raises(
        ValueError, match=r"T: expected shape \(4, 4\) or \(N, 4, 4\), got \(3, 3\)"
    ):
        lie.log6(np.eye(3))
    with pytest.raises(ValueError, match=r"s: 2 rows where q has 3 rows"):
        lie.screw_to_axis(np.zeros((3, 3)), np.ones((2, 3)))
    with pytest.raises(ValueError, match=r"h: expected a number or shape \(3,\), got shape \(2,\)"):
        lie.screw_to_axis(np.zeros((3, 3)), np.ones((3, 3)), [1.0, 2.0])
    with pytest.raises(ValueError, match=r"screw_to_axis: screw direction"):
        lie.screw_to_axis([0, 0, 0], [0, 0, 0], 1)
    with pytest.raises(ValueError, match=r"axis_angle3: zero rotation"):
        lie.axis_angle3([0, 0, 0])
    with pytest.raises(ValueError, match=r"log3: not a rotation"):
        lie.log3(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match=r"theta: not finite"):
        lie.exp3([0, 0, 1], np.inf)
    with pytest.raises(ValueError, match=r"project_to_so3: matrix contains a non-finite"):
        lie.project_to_so3(np.full((3, 3), np.nan))
    assert np.isnan(lie.distance_to_so3(np.full((3, 3), np.nan)))
    # A stack with bad rows: every good row computed, the bad ones NaN and named.
    t = np.stack([np.eye(4)] * 4)
    t[1, 0, 0] = 2.0
    t[3, 2, 3] = np.inf
    with pytest.raises(screwkit.BatchError, match=r"log6: row 1: not a rotation") as e:
        lie.log6(t)
    assert e.value.rows == [1, 3]
    assert "non-finite" in e.value.messages[1]
    res = e.value.result
    assert res.shape == (4, 6)
    np.testing.assert_array_equal(res[[0, 2]], 0)
    assert np.isnan(res[[1, 3]]).all()
    with pytest.raises(screwkit.BatchError) as e2:
        lie.axis_angle6(np.array([[1.0, 0, 0, 0, 0, 0], [0.0] * 6]))
    s, th = e2.value.result
    np.testing.assert_array_equal(s[0], [1, 0, 0, 0, 0, 0])
    assert th[0] == 1 and np.isnan(th[1])
    # A bad theta or an overflowing product is its row's error, the others computed.
    with pytest.raises(screwkit.BatchError, match=r"exp6: row 1: theta: not finite") as e3:
        lie.exp6(np.ones((3, 6)), [1.0, np.nan, 2.0])
    assert e3.value.rows == [1]
    np.testing.assert_array_equal(e3.value.result[2], lie.exp6(np.ones(6), 2.0))
    with pytest.raises(ValueError, match=r"exp3: exponential coordinates times theta"):
        lie.exp3([1e200, 0, 0], 1e200)
    with pytest.raises(ValueError, match=r"exp3: the result overflows"):
        lie.exp3([1e200, 0, 0])
    with pytest.raises(screwkit.BatchError, match=r"exp6: row 1: the result overflows"):
        lie.exp6(np.array([[0, 0, 1, 0, 0, 0], [1e200, 0, 0, 1e200, 0, 0]]))
    # One bad theta for a whole stack is the call's error.
    with pytest.raises(ValueError, match=r"^theta: not finite"):
        lie.exp6(np.ones((3, 6)), np.inf)
    with pytest.raises(ValueError, match=r"hat: .*non-finite"):
        lie.hat([np.inf, 0, 0])
    with pytest.raises(ValueError, match=r"vee: .*non-finite"):
        lie.vee(np.full((4, 4), np.nan))
    # Empty stacks are fine.
    assert lie.exp6(np.zeros((0, 6))).shape == (0, 4, 4)
    assert lie.distance_to_so3(np.zeros((0, 3, 3))).shape == (0,)
    assert lie.is_so3(np.zeros((0, 3, 3))).dtype == np.bool_


def test_seed_examples_against_independent_formulas() -> None:
    """The worked examples the README's tour prints, against the textbook formulas written
    out in numpy (G^-1(theta) p, Rodrigues, v = r x omega): the lessons round along the way,
    these are the exact values."""
    # screw-motion-lesson.md: T_sb -> S theta. omega = (1, -1, 1)/sqrt(3), theta = 2 pi / 3,
    # v = G^-1(theta) p with G^-1 = I/theta - [w]/2 + (1/theta - cot(theta/2)/2) [w]^2.
    th = 2 * np.pi / 3
    w = np.array([1.0, -1.0, 1.0]) / np.sqrt(3)
    wh = mr.VecToso3(w)
    g_inv = np.eye(3) / th - wh / 2 + (1 / th - 0.5 / np.tan(th / 2)) * wh @ wh
    v = g_inv @ [3.0, 0.0, 0.0]
    t_sb = np.array([[0, -1, 0, 3], [0, 0, -1, 0], [1, 0, 0, 0], [0, 0, 0, 1]], dtype=float)
    s, theta = lie.axis_angle6(lie.log6(t_sb))
    assert theta == pytest.approx(th, abs=1e-15)
    np.testing.assert_allclose(s, np.concatenate([w, v]), atol=1e-15)
    assert s[:3] @ s[3:] == pytest.approx(0.8269933431326882, abs=1e-15)
    # Its second example: S theta = (0, 1, 2, 3, 0, 0), theta = sqrt(5).
    th = np.sqrt(5.0)
    w = np.array([0.0, 1.0, 2.0]) / th
    wh = mr.VecToso3(w)
    r = np.eye(3) + np.sin(th) * wh + (1 - np.cos(th)) * wh @ wh
    g = np.eye(3) * th + (1 - np.cos(th)) * wh + (th - np.sin(th)) * wh @ wh
    t = lie.exp6([0, 1, 2, 3, 0, 0])
    np.testing.assert_allclose(t[:3, :3], r, atol=1e-15)
    np.testing.assert_allclose(t[:3, 3], g @ [3 / th, 0, 0], atol=1e-15)
    # screw-axes-lecture.md: the planar screw from {b} (30 deg at (1, 2)) to {c} (60 deg at
    # (2, 1)): rotation pi/6 about z through the point q with (I - R) q = p_c - R p_b.
    c, s_ = np.cos(np.pi / 6), np.sin(np.pi / 6)
    rot = np.array([[c, -s_], [s_, c]])
    q = np.linalg.solve(np.eye(2) - rot, np.array([2.0, 1.0]) - rot @ [1.0, 2.0])
    t_b = np.eye(4)
    t_b[:2, :2] = rot
    t_b[:2, 3] = [1, 2]
    t_c = np.eye(4)
    t_c[:2, :2] = rot @ rot
    t_c[:2, 3] = [2, 1]
    s, theta = lie.axis_angle6(lie.log6(t_c @ lie.trans_inv(t_b)))
    assert theta == pytest.approx(np.pi / 6, abs=1e-15)
    np.testing.assert_allclose(s, [0, 0, 1, q[1], -q[0], 0], atol=1e-14)  # v = -z x q
    # The lecture's car: v_s = r_s x omega_s, v_b = r_b x omega_b.
    t = np.array([[-1, 0, 0, 4], [0, 1, 0, 0.4], [0, 0, -1, 0], [0, 0, 0, 1]])
    v_b = np.concatenate([[0, 0, -2], np.cross([2, -1.4, 0], [0, 0, -2])])
    v_s = np.concatenate([[0, 0, 2], np.cross([2, -1, 0], [0, 0, 2])])
    np.testing.assert_allclose(lie.adjoint(t) @ v_b, v_s, atol=1e-15)
