"""A batch the compiled batch has no form for (task lists on two frames, ``prefer=``) on a
Dask cluster: each row solved on a worker as the local batch solves it, the same answers
bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.solve import distributed as on_dask

from ..conftest import arm

distributed = pytest.importorskip("distributed", reason="Dask is the optional cluster extra")

FIELDS = ("q", "success", "status_code", "position_error", "orientation_error", "iterations")


def _same(remote, local) -> None:
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(remote, field), getattr(local, field), err_msg=field)
    assert remote.reasons == local.reasons and remote.solver == local.solver


def test_task_lists_on_two_frames_give_the_local_answers(client):
    a = arm("panda")
    qs = a.random_q(4, n=5)
    rows = [
        [
            armik.Position(a.fk(q).translation),
            armik.Position(a.fk(q, "panda_link4").translation, frame="panda_link4"),
        ]
        for q in qs
    ]
    rows[2] = [armik.Position((3.0, 0.0, 0.5)), rows[2][1]]  # out of reach
    budget = dict(iteration_budget=400, max_restarts=3, seed=1)
    local = a.solve_batch(rows, q0=qs[::-1], workers=1, progress=False, **budget)
    remote = on_dask.solve_batch(a, rows, q0=qs[::-1], client=client, chunk_size=2, **budget)
    assert local.solver == "tasks" and local.success.sum() >= 3 and not local.success[2]
    _same(remote, local)


def test_a_preference_gives_the_local_answers(client):
    a = arm("ur5")
    T = a.fk_batch(a.random_q(5, n=4))
    local = a.solve_batch(T, prefer="manipulability", workers=1, progress=False)
    remote = on_dask.solve_batch(a, T, prefer="manipulability", client=client, chunk_size=3)
    assert local.success.all() and local.solver.endswith("prefer")
    _same(remote, local)


def test_several_tips_solved_row_by_row_give_the_local_answers(client):
    """``Arms.solve_batch`` over a shared joint and with a cost of the whole configuration
    (a lambda, which Dask sends as its code) on the cluster: chunks of rows
    (``armik.arms_rows.ArmsRows``), the robot sent once per worker as its chains' recipes,
    each row solved there as ``Arms.solve`` solves it."""
    shared = armik.load("panda", tips=["panda_link4", "panda_hand"])
    qs = shared.random_q(6, n=5)
    rows = shared.fk_batch(qs)
    rows["panda_hand"][2, :3, 3] = [3.0, 0.0, 0.5]  # out of reach
    options = {"hold": {"panda_joint2": None}, "prefer": lambda q: float(q @ q), "seed": 2}
    local = shared.solve_batch(rows, q0=qs, progress=False, **options)
    remote = shared.solve_batch(
        rows, q0=qs, backend=on_dask.OnDask(client), chunk_size=2, progress=False, **options
    )
    assert local.solver == "arms" and local.success.sum() == 4 and not local.success[2]
    _same(remote, local)
    assert np.isfinite(local._scores[local.success]).all()
    np.testing.assert_array_equal(remote._scores, local._scores)
