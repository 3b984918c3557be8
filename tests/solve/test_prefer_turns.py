"""A preference's turns of 2 pi under a constraint that reads one joint's value: where each
joint's best turn breaks the constraint, the answer is the best of its variants that keep
it (the other joints still turned), against a brute force over every branch and turn."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint
from armik.problem.scores import parse_score
from armik.status import Status

from .. import conftest


class _FirstUp(Constraint):
    """A constraint of the test's own: joint 1 at 0 rad or more."""

    def check(self, arm, Q):
        return Check(Q[:, 0] >= 0.0, Status.NOT_CONVERGED, lambda i: f"q1 {Q[i, 0]:.4f} < 0")


def _variants(arm, q: np.ndarray) -> list[np.ndarray]:
    lo, hi = arm.lower, arm.upper
    each = [
        [v for v in q[j] + 2 * np.pi * np.arange(-3, 4) if lo[j] - 1e-9 <= v <= hi[j] + 1e-9]
        for j in range(len(q))
    ]
    return [np.array(x) for x in itertools.product(*each)]


@pytest.mark.parametrize(
    ("prefer", "case"), [("limits", 18), ("limits", 23), ("posture", 8), ("posture", 22)]
)
def test_a_turn_a_constraint_refuses_keeps_the_other_joints_turns(prefer, case):
    arm = conftest.arm("ur5")
    q = arm.random_q(9100 + case)
    q[0] = abs(q[0])
    T = arm.fk(q)
    lo, hi = arm.lower, arm.upper
    q0 = lo + np.random.default_rng(100 + case).random(6) * (hi - lo)
    q0[0] = -abs(q0[0])  # joint 1's best turn toward q0 breaks the constraint
    score = parse_score(armik.Posture(np.zeros(6)) if prefer == "posture" else prefer)
    r = arm.solve(T, q0=q0, prefer=score, constraints=[_FirstUp()])
    assert r.success and r.q[0] >= 0.0
    branches = [x.q for x in arm.solve_all(T, q0=q0) if x.success]
    allowed = [v for b in branches for v in _variants(arm, b) if v[0] >= 0.0]
    best = min(score(arm.kinematics, v, q0) for v in allowed)
    assert r.score == pytest.approx(score(arm.kinematics, r.q, q0), abs=1e-12)
    assert r.score <= best + 1e-9
