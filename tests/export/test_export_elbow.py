"""An elbow stretched or folded onto a joint limit, the wrist at its singularity: the
exported solver lists the rows ``solve_all`` verifies there (the closed forms and the C
keep the same one of the elbow's two exact roots)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armik
from tests.export.build import Solver
from tests.solvers.closed_form.random_arms import wrapped_distance

CASES = [  # (arm, limits, elbow value, wrist_2 at 0)
    ("ur5", {"elbow_joint": (0.0, math.pi)}, 0.0, True),
    ("ur5", None, math.pi, True),
    ("kinova", None, math.pi, False),
]


@pytest.mark.parametrize(("name", "limits", "elbow", "wrist"), CASES)
def test_the_c_lists_what_solve_all_verifies_at_an_elbow_on_its_limit(
    name, limits, elbow, wrist, tmp_path
):
    arm = armik.load(name)
    if limits is not None:
        arm = arm.with_limits(limits)
    solver = Solver(arm, "s", tmp_path)
    rng = np.random.default_rng(7)
    for k in range(12):
        q = arm.random_q(rng)
        q[2] = elbow
        if wrist:
            q[4] = 0.0
        elif name == "kinova":  # joint 2 or 5 on its lower limit
            j = 1 if k % 2 else 4
            q[j] = arm.lower[j]
        T = arm.fk(q).homogeneous
        Q = solver.ik(T)
        expected = [r.q for r in arm.solve_all(T) if r.success]
        assert len(Q) == len(expected), (q.tolist(), len(Q), len(expected))
        for row in Q:
            assert min(wrapped_distance(row, e) for e in expected) < 1e-7
