"""Batches equal single calls bit for bit, whatever the thread count; inputs of any form."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

import screwkit

from conftest import BUNDLED, ChainSpec, configurations


@pytest.fixture
def threads() -> Iterator[None]:
    yield
    screwkit.set_num_threads(None)


@pytest.mark.parametrize("spec", [pytest.param(c, id=c.id) for c in BUNDLED])
def test_batch_equals_single_calls_bit_for_bit(spec: ChainSpec) -> None:
    robot = spec.robot()
    qs = configurations(robot, 64, seed=11)
    poses = robot.fk(qs)
    links = robot.fk_all_links(qs)
    js = robot.jacobian(qs, "space")
    jb = robot.jacobian(qs, "body")
    for k, q in enumerate(qs):
        np.testing.assert_array_equal(poses[k], robot.fk(q))
        np.testing.assert_array_equal(links[k], robot.fk_all_links(q))
        np.testing.assert_array_equal(js[k], robot.jacobian(q, "space"))
        np.testing.assert_array_equal(jb[k], robot.jacobian(q, "body"))


def test_same_results_with_one_and_two_threads(threads: None, panda: screwkit.Robot) -> None:
    qs = configurations(panda, 3000, seed=12)
    targets = panda.fk(configurations(panda, 200, seed=13))
    results = []
    for n in (1, 2, 1):
        screwkit.set_num_threads(n)
        assert screwkit.num_threads() == n
        ik = panda.ik(targets, seed_rng=5)
        assert isinstance(ik, screwkit.IkBatchResult)
        results.append(
            (panda.fk(qs), panda.jacobian(qs, "body"), panda.fk_all_links(qs), ik.q, ik.iterations)
        )
    for other in results[1:]:
        for a, b in zip(results[0], other, strict=False):
            np.testing.assert_array_equal(a, b)


def test_ik_batch_row_equals_single_call_with_its_row_seed(panda: screwkit.Robot) -> None:
    targets = panda.fk(configurations(panda, 40, seed=14))
    seeds = configurations(panda, 40, seed=15)
    batch = panda.ik(targets, seeds, seed_rng=9)
    assert isinstance(batch, screwkit.IkBatchResult)
    for k in range(len(targets)):
        one = panda.ik(targets[k], seeds[k], seed_rng=screwkit.row_seed(9, k))
        assert isinstance(one, screwkit.IkResult)
        np.testing.assert_array_equal(batch.q[k], one.q)
        assert batch.converged[k] == one.converged
        assert batch.iterations[k] == one.iterations
        assert batch.restarts[k] == one.restarts
        assert batch.error_rot[k] == one.error_rot
        assert batch.error_pos[k] == one.error_pos
        assert batch.stop[k] == one.stop


def test_any_array_like_input_gives_the_same_float64_result(ur5: screwkit.Robot) -> None:
    q = np.array([0.1, -0.5, 1.0, 0.2, 0.3, -0.4])
    expected = ur5.fk(q)
    assert expected.dtype == np.float64 and expected.flags.c_contiguous
    strided = np.zeros(12)
    strided[::2] = q
    fortran = np.asfortranarray(np.stack([q, q, q]))
    for given in (list(q), tuple(q), strided[::2], q.reshape(1, 6)[0]):
        np.testing.assert_array_equal(ur5.fk(given), expected)
    np.testing.assert_array_equal(
        ur5.fk(q.astype(np.float32)), ur5.fk(q.astype(np.float32).astype(float))
    )
    np.testing.assert_array_equal(
        ur5.fk([0, 1, 0, 0, 0, 0]), ur5.fk(np.array([0.0, 1, 0, 0, 0, 0]))
    )
    out = ur5.fk(fortran)
    assert out.flags.c_contiguous and out.dtype == np.float64 and out.shape == (3, 4, 4)
    np.testing.assert_array_equal(out, np.stack([expected] * 3))
    j = ur5.jacobian(np.stack([q, q])[:, ::-1][:, ::-1])
    assert j.flags.c_contiguous and j.shape == (2, 6, 6)
    # Targets in any form too.
    t = expected.T.copy().T  # Fortran-ordered
    r = ur5.ik(t.tolist(), seed=q)
    assert isinstance(r, screwkit.IkResult) and r.converged
    np.testing.assert_allclose(ur5.fk(r.q), expected, atol=1e-9)


def test_empty_batch(ur5: screwkit.Robot) -> None:
    assert ur5.fk(np.zeros((0, 6))).shape == (0, 4, 4)
    assert ur5.jacobian(np.zeros((0, 6))).shape == (0, 6, 6)
    r = ur5.ik(np.zeros((0, 4, 4)))
    assert isinstance(r, screwkit.IkBatchResult) and r.q.shape == (0, 6) and len(r) == 0


def test_a_bad_row_is_reported_and_the_rest_finished(ur5: screwkit.Robot) -> None:
    qs = configurations(ur5, 10, seed=16)
    qs[3, 2] = np.nan
    qs[7, 0] = np.inf
    with pytest.raises(screwkit.BatchError) as info:
        ur5.fk(qs)
    e = info.value
    assert isinstance(e, ValueError)
    assert e.rows == [3, 7]
    assert "elbow_joint" in e.messages[0] and "NaN" in e.messages[0]
    assert "shoulder_pan_joint" in e.messages[1]
    assert str(e).startswith("row 3: ")
    assert np.isnan(e.result[3]).all() and np.isnan(e.result[7]).all()
    for k in (0, 1, 2, 4, 5, 6, 8, 9):
        np.testing.assert_array_equal(e.result[k], ur5.fk(qs[k]))
    with pytest.raises(screwkit.BatchError) as jinfo:
        ur5.jacobian(qs, "body")
    assert jinfo.value.rows == [3, 7]

    targets = ur5.fk(configurations(ur5, 5, seed=17))
    targets[1, 0, 3] = np.nan
    targets[2, :3, :3] *= 2.0  # not a rotation
    with pytest.raises(screwkit.BatchError) as iinfo:
        ur5.ik(targets)
    r = iinfo.value.result
    assert isinstance(r, screwkit.IkBatchResult)
    assert iinfo.value.rows == [1, 2]
    assert "not a finite rigid transform" in iinfo.value.messages[0]
    assert r.stop[1] == r.stop[2] == "invalid input"
    assert not r.converged[1] and np.isnan(r.q[1]).all()
    assert r.converged[[0, 3, 4]].all()
