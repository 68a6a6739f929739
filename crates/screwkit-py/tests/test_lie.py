"""exp, log and adjoint against closed forms and a Taylor-series matrix exponential."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

import screwkit

from conftest import expm

Array = npt.NDArray[np.float64]


def hat(x: Array) -> Array:
    w, v = x[:3], x[3:]
    m = np.zeros((4, 4))
    m[:3, :3] = [[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]
    m[:3, 3] = v
    return m


def test_exp_equals_series() -> None:
    rng = np.random.default_rng(41)
    for _ in range(100):
        xi = rng.normal(size=6)
        theta = rng.uniform(-2, 2)
        np.testing.assert_allclose(screwkit.exp(xi, theta), expm(hat(xi) * theta), atol=1e-12)


def test_exp_closed_forms() -> None:
    rz = screwkit.exp([0, 0, 1, 0, 0, 0], np.pi / 2)
    np.testing.assert_allclose(
        rz, [[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], atol=1e-15
    )
    # A revolute screw about z through (1, 0, 0): v = -w x q = (0, -1, 0); half a turn moves the
    # origin to (2, 0, 0).
    t = screwkit.exp([0, 0, 1, 0, -1, 0], np.pi)
    np.testing.assert_allclose(t[:3, 3], [2, 0, 0], atol=1e-15)
    np.testing.assert_allclose(screwkit.exp([0, 0, 0, 1, 2, 3], 0.5)[:3, 3], [0.5, 1, 1.5])


def test_log_inverts_exp() -> None:
    rng = np.random.default_rng(42)
    for _ in range(100):
        w = rng.normal(size=3)
        w *= rng.uniform(0, 3.0) / np.linalg.norm(w)  # angle below pi
        xi = np.concatenate([w, rng.normal(size=3)])
        np.testing.assert_allclose(screwkit.log(screwkit.exp(xi)), xi, atol=1e-10)
    np.testing.assert_array_equal(screwkit.log(np.eye(4)), np.zeros(6))


def test_adjoint_definition() -> None:
    rng = np.random.default_rng(43)
    for _ in range(20):
        t = screwkit.exp(rng.normal(size=6))
        v = rng.normal(size=6)
        # [Ad_T] V = vee(T [V] T^-1)
        m = t @ hat(v) @ np.linalg.inv(t)
        expected = np.array([m[2, 1], m[0, 2], m[1, 0], m[0, 3], m[1, 3], m[2, 3]])
        np.testing.assert_allclose(screwkit.adjoint(t) @ v, expected, atol=1e-12)
