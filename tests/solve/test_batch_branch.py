"""A batch row's branch label is ``solve``'s: a closed form's compiled batch, its rows solved
again, row by row, on every route, sliced and saved."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from armik import BatchResult
from armik.solvers import registry

from ..conftest import arm


def _targets(name: str, n: int, seed: int):
    a = arm(name)
    rng = np.random.default_rng(seed)
    T = list(a.fk_batch(np.array([a.random_q(rng) for _ in range(n)])))
    T.append(pin.SE3(np.eye(3), np.array([5.0, 0.0, 0.0])).homogeneous)  # out of reach
    q0 = np.array([a.random_q(rng) for _ in range(len(T))])
    return a, np.array(T), q0


def _assert_rows_are_solve_s(a, batch, T, q0, seed, **options):
    labelled = 0
    for i in range(len(T)):
        r = a.solve(T[i], q0=q0[i], seed=seed, **options)
        b = batch[i]
        np.testing.assert_array_equal(b.q, r.q)
        if r.success and b.success:
            assert b.branch == r.branch, (i, b.branch, r.branch)
            assert batch.branch[i] == r.branch
            labelled += r.branch is not None
    assert labelled >= len(T) - 1  # every reached row carries a label


@pytest.mark.parametrize("name", ["ur5", "abb_irb120"])
@pytest.mark.parametrize(
    "route",
    [{"workers": 1}, {"workers": 2, "chunk_size": 3}, {"backend": "serial", "chunk_size": 4}],
    ids=["one-worker", "two-workers", "backend"],
)
def test_a_closed_form_batch_row_carries_solve_s_branch(name, route):
    a, T, q0 = _targets(name, 12, seed=5)
    batch = a.solve_batch(T, q0=q0, seed=3, **route)
    assert registry.get(batch.solver).kind == "analytic"
    _assert_rows_are_solve_s(a, batch, T, q0, 3)
    assert batch.branch[-1] == a.solve(T[-1], q0=q0[-1], seed=3).branch  # the failure's too


def test_a_closed_form_solved_row_by_row_carries_solve_s_branch():
    a = arm("kuka_iiwa14")  # srs: no compiled batch, each row through solve
    rng = np.random.default_rng(2)
    T = a.fk_batch(np.array([a.random_q(rng) for _ in range(4)]))
    q0 = np.array([a.random_q(rng) for _ in range(4)])
    batch = a.solve_batch(T, q0=q0, seed=1, workers=1)
    _assert_rows_are_solve_s(a, batch, T, q0, 1)


def test_labels_survive_slices_merges_and_files(tmp_path):
    a, T, q0 = _targets("ur5", 9, seed=8)
    batch = a.solve_batch(T, q0=q0, seed=2, workers=1)
    words = [a.solve(T[i], q0=q0[i], seed=2).branch for i in range(len(T))]
    part = batch[2:7]
    assert [part[k].branch for k in range(len(part))] == words[2:7]
    assert list(batch[batch.success].branch) == [w for w, s in zip(words, batch.success) if s]
    assert list(batch.branch) == words  # the failure's label too: solve's
    back = BatchResult.load(batch.save(tmp_path / "b.npz"))
    assert [r.branch for r in back] == words


@pytest.mark.parametrize("name", ["ur5", "abb_irb120"])
def test_a_closed_form_rows_reason_is_solves(name):
    """A compiled closed-form batch row's reason is ``solve``'s, its closed form's words
    first ("closed form (spherical wrist); verified ..."), where the batch said only what
    it verified."""
    a = arm(name)
    T = a.fk_batch(a.random_q(5, n=4))
    batch = a.solve_batch(T, q0=a.middle, workers=1)
    for i in range(len(T)):
        r = a.solve(T[i], q0=a.middle)
        assert r.success and batch.reason(i) == r.reason and r.reason.startswith("closed form (")
