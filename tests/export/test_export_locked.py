"""A 6R arm with a spherical shoulder (the Panda and the iiwa with joint 7 locked) exported:
``N_ik(T, q)`` against Pinocchio, the arm's ``solve_all`` and ``solve_all(T, hold={joint 7:
value})`` on the 7-joint arm, which has the same kinematics."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from tests.export.build import Solver
from tests.export.test_export_c import check_solutions, same_as_solve_all
from tests.solvers.closed_form.random_arms import wrapped_distance

TARGETS = 30
LOCKED = {"panda": ("panda_joint7", 0.3), "kuka_iiwa14": ("iiwa_joint_7", -0.7)}


@pytest.fixture(scope="module", params=sorted(LOCKED))
def locked(request, tmp_path_factory):
    robot = request.param
    joint, value = LOCKED[robot]
    arm = armik.load(robot, locked={joint: value})
    return armik.load(robot), joint, value, arm, Solver(arm, "arm", tmp_path_factory.mktemp("lk"))


def test_header_and_fk(locked):
    full, joint, value, arm, solver = locked
    header = solver.files["arm_ik.h"]
    assert "#define ARM_IK_DOF 6" in header and "spherical shoulder" in header
    assert solver.held is None
    rng = np.random.default_rng(4)
    for _ in range(TARGETS):
        q = arm.random_q(rng)
        assert np.abs(solver.fk(q) - arm.fk(q).homogeneous).max() < 1e-12


def test_every_solution_as_solve_all_and_hold(locked):
    full, joint, value, arm, solver = locked
    rng = np.random.default_rng(9)
    found = 0
    for _ in range(TARGETS):
        q = arm.random_q(rng)
        T = arm.fk(q).homogeneous
        Q = solver.ik(T)
        check_solutions(arm, Q, T)
        same_as_solve_all(arm, Q, T)
        held = [np.delete(r.q, 6) for r in full.solve_all(T, hold={joint: value}) if r.success]
        assert len(held) == len(Q)
        for got in Q:
            assert min(wrapped_distance(got, h) for h in held) < 1e-7
        found += len(Q)
    assert found >= TARGETS
