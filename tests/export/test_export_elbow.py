"""An elbow stretched or folded onto a joint limit, the wrist at its singularity: the
exported solver lists the rows ``solve_all`` verifies there (the closed forms and the C
keep the same one of the elbow's two exact roots)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armik
from armik.solvers.closed_form import three_parallel_general
from armik.solvers.closed_form.sixr import Chain6R
from armik.solvers.closed_form.subproblems import elbow_extreme
from tests.export.build import Solver
from tests.export.test_export_c import check_solutions
from tests.solvers.closed_form.random_arms import load_arm, wrapped_distance

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


def test_the_general_wrist_c_keeps_the_root_within_the_limits(tmp_path):
    # three_parallel_general's C (a random arm with axes 2, 3, 4 parallel and a general
    # wrist), stretched onto an elbow limit with joint 2 or 5 on its lower limit: the C kept
    # the first of the two roots rounding splits the double root into, past the limit, and
    # listed one solution fewer than solve_all. Its rounding differs from the compiled
    # kernel's, which may find the double root whole, so rows agree to 1e-5 (both exact)
    arm = load_arm("three_parallel_free", np.random.default_rng(6))
    geo = three_parallel_general.classify(arm.kinematics)
    assert isinstance(geo, Chain6R)
    e = elbow_extreme(tuple(geo.p[3]), tuple(-geo.p[2]), tuple(geo.h[2]), 0.0)
    arm = arm.with_limits({arm.joint_names[2]: (e - 1.5, e)})
    solver = Solver(arm, "s", tmp_path)
    rng = np.random.default_rng(7)
    for k in range(60):
        q = arm.random_q(rng)
        q[2] = e
        j = 1 if k % 2 else 4
        q[j] = arm.lower[j]
        T = arm.fk(q).homogeneous
        Q = solver.ik(T)
        expected = [r.q for r in arm.solve_all(T) if r.success]
        assert len(Q) == len(expected), (q.tolist(), Q.tolist())
        check_solutions(arm, Q, T)
        for row in Q:
            assert min(wrapped_distance(row, x) for x in expected) < 1e-5
