"""A 6R closed form's ``solve_all`` by its judged rows (``armik.verify.judged``) gives what
the general path gives, field for field, on every family: targets within reach, from
configurations outside the limits, too far and too close, from the middle and from
random starts."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from armik.targets.pose import parse_target

from ..conftest import arm, assert_same_result
from ..solvers.closed_form.random_arms import load_arm

# random arms of each family the judged rows serve (general_6r has none)
KINDS = ("parallel_23", "meeting_12", "three_parallel", "spherical", "three_parallel_free",
         "two_parallel", "two_intersecting")  # fmt: skip


def _targets(a, rng: np.random.Generator, n: int) -> list:
    out = []
    for i in range(n):
        q = a.random_q(rng)
        if i % 4 == 1:  # a pose only configurations outside the limits reach
            q = q + rng.uniform(-2.0, 2.0, a.dof)
        T = a.fk(q)
        if i % 4 == 2:  # too far or too close
            T = pin.SE3(T.rotation, T.translation * (3.0 if i % 8 == 2 else 0.05))
        out.append((T, None if i % 3 else a.random_q(rng)))
    return out


@pytest.mark.parametrize("kind", ["ur5", "abb_irb120", *KINDS])
def test_judged_rows_are_the_general_verdicts(kind):
    rng = np.random.default_rng(11)
    a = arm(kind) if kind in ("ur5", "abb_irb120") else load_arm(kind, rng)
    # the searches asked by name: "auto" takes the elimination on their arms
    solver = kind if kind in ("two_parallel", "two_intersecting") else "auto"
    judged = 0
    for T, q0 in _targets(a, rng, 24):
        fast = a.solve_all(T, q0=q0, solver=solver)
        judged += fast._make is not None  # the judged rows' route
        general = a.solve_all(parse_target(T, a.kinematics), q0=q0, solver=solver)
        assert len(fast) == len(general)
        for x, y in zip(fast, general):
            assert_same_result(x, y)
            assert x.reason == y.reason
    assert judged >= 12
