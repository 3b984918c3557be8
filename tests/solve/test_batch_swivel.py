"""``solve_batch(..., swivel=)`` on an SRS arm: each row solved at the swivel angle asked,
as ``solve`` solves it, on every route of a batch."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.solvers.closed_form import srs

from ..conftest import arm


def _same_angle(a: float, b: float, tol: float = 1e-9) -> bool:
    return abs(float(np.arctan2(np.sin(a - b), np.cos(a - b)))) < tol


@pytest.mark.parametrize(
    "route",
    [
        {"workers": 1},
        {"workers": 2, "chunk_size": 2},
        {"workers": 2, "chunk_size": 2, "backend": "threads"},
        {"workers": 1, "prefer": "limits"},
    ],
    ids=["one-worker", "two-workers", "backend", "prefer"],
)
def test_each_row_is_solve_at_the_swivel_asked(route):
    a = arm("kuka_iiwa14")
    rng = np.random.default_rng(11)
    T = a.fk_batch(np.array([a.random_q(rng) for _ in range(5)]))
    q0 = np.array([a.random_q(rng) for _ in range(5)])
    swivel = 0.3
    batch = a.solve_batch(T, q0=q0, swivel=swivel, seed=4, **route)
    prefer = {"prefer": route["prefer"]} if "prefer" in route else {}
    for i in range(len(T)):
        r = a.solve(T[i], q0=q0[i], swivel=swivel, seed=4, **prefer)
        b = batch[i]
        assert b.success == r.success and b.status is r.status, (i, b, r)
        np.testing.assert_array_equal(b.q, r.q)
        if r.success:
            assert _same_angle(srs.swivel_of(a.kinematics, b.q), swivel), i
    assert batch.success.all()


def test_a_bad_swivel_on_a_batch_is_the_solve_s_error():
    a = arm("kuka_iiwa14")
    T = a.fk_batch(np.array([a.random_q(1)]))
    with pytest.raises(armik.OptionError, match="swivel must be finite"):
        a.solve_batch(T, swivel=float("nan"), workers=1)
