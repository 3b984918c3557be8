"""The Panda's self-motion searched for a score (``armik.solve.prefer.sweep_held``): its
answer against a dense scan of joint 7 over its range, every branch in closed form at each
value, on targets whose best configuration lies where a grid over joint 7 alone does not
look: at the edge of a branch's reachable interval, or in an interval narrower than the
grid's step where one branch is within the limits."""

from __future__ import annotations

import numpy as np
import pytest

from armik.problem.scores import parse_score
from armik.solvers.closed_form import swept_7r
from armik.targets.pose import parse_target

from .. import conftest


def _dense_best(arm, T, q0: np.ndarray, score, count: int = 2001) -> float:
    """The least score over every branch within the limits at ``count`` values of joint 7."""
    model = arm.kinematics
    target = parse_target(T, model)
    exact = swept_7r.exact_at(model, target, q0)
    lo, hi = swept_7r.sweep_range(model, float(q0[6]))
    best = np.inf
    for theta in np.linspace(lo, hi, count):
        Q = exact(float(theta))
        Q = Q[((Q >= model.lower - 1e-9) & (Q <= model.upper + 1e-9)).all(axis=1)]
        if len(Q):
            best = min(best, float(score.many(model, Q, q0).min()))
    return best


@pytest.mark.parametrize(
    "prefer, case",
    [
        ("manipulability", 53),  # best in two intervals 0.02 rad wide, between grid values
        ("manipulability", 31),  # best where one branch reaches the edge of its interval
        ("nearest", 273),  # best in an interval 0.015 rad wide, one wrist flip within limits
    ],
)
def test_the_sweep_finds_the_best_the_grid_steps_over(prefer, case):
    arm = conftest.arm("panda")
    T = arm.fk(arm.random_q(1000 + case))
    q0 = np.asarray(arm.random_q(6000 + case), dtype=float)
    r = arm.solve(T, q0=q0, prefer=prefer)
    assert r.success and r.solver == "swept"
    score = parse_score(prefer)
    assert r.score == pytest.approx(score(arm.kinematics, r.q, q0), abs=1e-12)
    best = _dense_best(arm, T, q0, score)
    assert r.score <= best + 0.01 * abs(best)
