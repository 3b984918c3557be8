"""``prefer="limits"`` on an arm with continuous joints (the Kinova's, no middle to their
range): no numpy warning on any route, and the answers of the score's own ranking."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from armik.constraints.base import Check, Constraint
from armik.problem.scores import parse_score
from armik.solve.prefer import continuous_turned
from armik.solve.turning import Turning
from armik.status import Status
from tests.conftest import arm as bundled


@pytest.mark.parametrize("route", ["solve", "solve_all", "solve_batch", "solve_path"])
def test_limits_on_continuous_joints_warns_of_nothing(route):
    kinova = bundled("kinova")
    assert np.isinf(kinova.lower).any()
    rng = np.random.default_rng(1)
    qs = [kinova.random_q(rng) for _ in range(3)]
    T = [kinova.fk(q) for q in qs]
    calls = {
        "solve": lambda: [kinova.solve(T[0], prefer="limits")],
        "solve_all": lambda: kinova.solve_all(T[0], prefer="limits"),
        "solve_batch": lambda: kinova.solve_batch(T, prefer="limits"),
        "solve_path": lambda: kinova.solve_path(T, qs[0], prefer="limits"),
    }
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        got = list(calls[route]())
    assert got[0].success and np.isfinite(got[0].extra["score"])


class _FirstBelow(Constraint):
    """A constraint of the test's own: joint 1 below 3 rad."""

    def check(self, arm, Q):
        return Check(Q[:, 0] < 3.0, Status.NOT_CONVERGED, lambda i: f"q1 {Q[i, 0]:.4f} >= 3")


def test_a_paths_turn_a_constraint_refuses_keeps_the_other_joints_turns():
    """A path's plan scores continuous joints at their best turn (``continuous_turned``):
    where joint 1's turn breaks a constraint, joints 4 and 6 are turned all the same."""
    model = bundled("kinova").kinematics
    q0 = np.array([6.5, 2.0, 2.0, -6.0, 2.0, 6.2])
    Q = np.array([[0.5, 2.0, 2.0, 0.2, 2.0, 0.1], [0.4, 2.1, 1.9, 0.3, 2.2, 0.0]])
    turn = Turning(checks=(_FirstBelow(),))
    got = continuous_turned(model, Q, parse_score("nearest"), q0, turn)
    assert turn.keeps(model, got).all()
    np.testing.assert_array_equal(got[:, 0], Q[:, 0])  # its turn refused
    np.testing.assert_allclose(got[:, 3], Q[:, 3] - 2 * np.pi)  # nearest q0's -6
    np.testing.assert_allclose(got[:, 5], Q[:, 5] + 2 * np.pi)  # nearest q0's 6.2
