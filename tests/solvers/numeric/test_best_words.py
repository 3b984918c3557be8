"""A failure's words give the errors of its best attempt only where the task measures
them: a part not asked was said to be "0", as if reached."""

from __future__ import annotations

import numpy as np
import pytest

from ...conftest import arm


@pytest.mark.parametrize("solver", ["clik", "dls", "qp"])
def test_a_failure_words_only_what_was_asked(solver):
    a = arm("ur5")
    T = a.fk(a.random_q(5))
    few = dict(q0=np.zeros(6), solver=solver, max_iterations=2, max_restarts=0)
    for target, weights, said, unsaid in (
        (T.translation, None, "position error", "orientation error"),
        (T, (1, 1, 1, 0, 0, 0), "position error", "orientation error"),
        (T, (0, 0, 0, 1, 1, 1), "orientation error", "position error"),
        (T, None, "orientation error", "no such words"),
    ):
        r = a.solve(target, weights=weights, **few)
        assert not r.success
        assert said in r.reason and unsaid not in r.reason, (weights, r.reason)


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_target_beyond_reach_by_a_hair_says_by_how_much(solver):
    """1.1e-6 m past the stretched 2-link arm's reach of 1.8 m, beyond tol_position: it
    said 'target is 1.8 m from the first joint, beyond the arm's reach of at most 1.8 m'."""
    a = arm("planar_2link")
    r = a.solve([1.8 + 1.1e-6, 0.0], q0=np.array([0.3, 0.4]), solver=solver)
    assert not r.success and r.status.value == "unreachable"
    assert "at most 1.8 m (by 1.1e-06 m)" in r.reason, r.reason
    near = a.solve([1.8 + 0.5e-6, 0.0], q0=np.array([0.3, 0.4]), solver=solver)
    assert near.success and near.position_error <= 1e-6  # within tol_position: reached
