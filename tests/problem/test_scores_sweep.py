"""The Panda's self-motion searched for a score (``armik.solve.prefer.sweep_held``): its
answer against a dense scan of joint 7 over its range, every branch in closed form at each
value, on targets whose best configuration lies where a grid over joint 7 alone does not
look: at the edge of a branch's reachable interval, or in an interval narrower than the
grid's step where one branch is within the limits."""

from __future__ import annotations

import numpy as np
import pytest

from armik.constraints.base import Check, Constraint
from armik.problem.scores import parse_score
from armik.solvers.closed_form import swept_7r
from armik.status import Status
from armik.targets.pose import parse_target

from .. import conftest


def _dense_best(arm, T, q0: np.ndarray, score, count: int = 2001, keep=None) -> float:
    """The least score over every branch within the limits (and ``keep(Q)``'s rows, where
    given) at ``count`` values of joint 7."""
    model = arm.kinematics
    target = parse_target(T, model)
    exact = swept_7r.exact_at(model, target, q0)
    lo, hi = swept_7r.sweep_range(model, float(q0[6]))
    best = np.inf
    for theta in np.linspace(lo, hi, count):
        Q = exact(float(theta))
        Q = Q[((Q >= model.lower - 1e-9) & (Q <= model.upper + 1e-9)).all(axis=1)]
        Q = Q if keep is None else Q[keep(Q)]
        if len(Q):
            best = min(best, float(score.many(model, Q, q0).min()))
    return best


@pytest.mark.parametrize(
    "prefer, seeds",
    [
        # best in two intervals 0.02 rad wide, between grid values
        ("manipulability", (1053, 6053)),
        ("manipulability", (1031, 6031)),  # best where one branch reaches its interval's edge
        # best in an interval 0.015 rad wide, one wrist flip within limits
        ("nearest", (1273, 6273)),
        # best in an interval 0.04 rad wide at the edge of a branch's reach, next to a grid
        # value outside the limits that is no dip (the violation falls on toward the next)
        ("nearest", (7019, 8019)),
        ("manipulability", (7052, 8052)),
        # best at a value of joint 7 one group's search tried, by another group's branch
        ("limits", (1159, 6159)),
    ],
)
def test_the_sweep_finds_the_best_the_grid_steps_over(prefer, seeds):
    arm = conftest.arm("panda")
    T = arm.fk(arm.random_q(seeds[0]))
    q0 = np.asarray(arm.random_q(seeds[1]), dtype=float)
    r = arm.solve(T, q0=q0, prefer=prefer)
    assert r.success and r.solver == "swept"
    score = parse_score(prefer)
    assert r.score == pytest.approx(score(arm.kinematics, r.q, q0), abs=1e-12)
    best = _dense_best(arm, T, q0, score)
    assert r.score <= best + 0.01 * abs(best)


class _WristUp(Constraint):
    """A constraint of the test's own: joint 6 at 2 rad or more."""

    def check(self, arm, Q):
        return Check(Q[:, 5] >= 2.0, Status.NOT_CONVERGED, lambda i: f"q6 {Q[i, 5]:.4f} < 2")


@pytest.mark.parametrize("case", [0, 22])
def test_the_sweep_searches_only_what_a_constraint_of_the_request_allows(case):
    """With ``constraints=[...]``, the value of joint 7 is chosen among the branches the
    constraint keeps: the best of those, not the best of all (which it then refuses)."""
    arm = conftest.arm("panda")
    q = arm.random_q(3000 + case)
    q[5] = 2.0 + abs(q[5] - 2.0) * 0.3
    T = arm.fk(q)
    q0 = np.asarray(arm.middle, dtype=float)
    r = arm.solve(T, q0=q0, prefer="manipulability", constraints=[_WristUp()])
    assert r.success and r.q[5] >= 2.0
    score = parse_score("manipulability")
    best = _dense_best(arm, T, q0, score, keep=lambda Q: Q[:, 5] >= 2.0)
    assert r.score <= best + 0.01 * abs(best)
