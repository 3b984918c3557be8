"""A batch backend may give its jobs' results in any order (``as_completed``'s, reversed):
each job's rows name the row they start at and land there, so every answer belongs to its
own target; a result given twice or not a job's own is refused by name."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor, as_completed

import numpy as np
import pytest

import armik
from armik.batch_result import BatchResult
from tests.conftest import TOL
from tests.conftest import arm as bundled

BUDGET = {"iteration_budget": 400, "seed": 3}


def reversed_results(jobs, workers):
    return [job() for job in jobs][::-1]


def completion_order(jobs, workers):
    """Results as they complete, the first job made the slowest."""

    def run(k, job):
        if k == 0:
            time.sleep(0.2)
        return job()

    with ThreadPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(run, k, job) for k, job in enumerate(jobs)]
        return [f.result() for f in as_completed(futures)]


@pytest.mark.parametrize("name", ["ur5", "panda"])
@pytest.mark.parametrize("backend", [reversed_results, completion_order])
@pytest.mark.parametrize("chunk", [3, 4])
def test_results_in_any_order_land_on_their_own_targets(name, backend, chunk):
    arm = bundled(name)
    rng = np.random.default_rng(3)
    targets = [arm.fk(arm.random_q(rng)) for _ in range(8)]
    default = arm.solve_batch(targets, chunk_size=chunk, workers=1, **BUDGET)
    got = arm.solve_batch(targets, chunk_size=chunk, workers=2, backend=backend, **BUDGET)
    np.testing.assert_array_equal(got.q, default.q)
    np.testing.assert_array_equal(got.success, default.success)
    assert got.success.any()
    for i in np.flatnonzero(got.success):
        tip = arm.fk(got.q[i])
        assert np.linalg.norm(tip.translation - targets[i].translation) < TOL["solve"]


def test_a_repeated_or_foreign_result_is_refused_by_name():
    arm = bundled("ur5")
    rng = np.random.default_rng(4)
    targets = [arm.fk(arm.random_q(rng)) for _ in range(6)]

    def twice(jobs, workers):
        return [jobs[0](), jobs[0]()]

    with pytest.raises(armik.ArmikError, match="batch backend .*twice.* at row 0 twice"):
        arm.solve_batch(targets, chunk_size=3, backend=twice)

    def plain(jobs, workers):  # rows, but not as the job returned them: no row of their own
        rows = [vars(job()) for job in jobs]
        return [BatchResult(**{k: v for k, v in r.items() if k != "start"}) for r in rows]

    with pytest.raises(armik.ArmikError, match="batch backend .*plain.* for job 0"):
        arm.solve_batch(targets, chunk_size=3, backend=plain)


def _rows_batches(name):
    """(targets, options) of batches the compiled batch has no form for, solved row by
    row: a preference to rank each row's answers by, and look-ats at different points."""
    arm = bundled(name)
    rng = np.random.default_rng(6)
    poses = [arm.fk(arm.random_q(rng)) for _ in range(6)]
    looks = [
        [armik.Position(T.translation), armik.LookAt(T * np.array([0.0, 0.0, 0.3 + k / 10]))]
        for k, T in enumerate(poses)
    ]
    return [(poses, {"prefer": "manipulability"}), (looks, {})]


@pytest.mark.parametrize("name", ["ur5", "panda"])
@pytest.mark.parametrize("backend", [reversed_results, completion_order, "threads"])
def test_a_batch_solved_row_by_row_runs_on_any_backend_as_here(name, backend):
    """``backend=`` runs a batch without a compiled form too: chunks of rows
    (``batch_rows.RowsChunk``), each row solved from its own seed as the local batch solves
    it, in whatever order the backend gives them back."""
    arm = bundled(name)
    for targets, options in _rows_batches(name):
        here = arm.solve_batch(targets, workers=1, **options, **BUDGET)
        got = arm.solve_batch(
            targets, chunk_size=4, workers=2, backend=backend, **options, **BUDGET
        )
        np.testing.assert_array_equal(got.q, here.q)
        np.testing.assert_array_equal(got.success, here.success)
        assert got.reasons == here.reasons and got.solver == here.solver
        assert here.success.sum() >= 4, here.summary()
