"""``solve_all`` lists two exact solutions a hair apart as two: a closed form's rows are one
only where rounding split one root (``tolerances.SAME_ROOT``), not within a numeric
solver's wider ``DUPLICATE_TOL``. Near a singular configuration two solutions come close:
the KUKA iiwa with joint 6 held (or locked) and joint 5 at 1e-5 rad has two 6.5e-5 rad
apart, and the target's own was dropped as the other's duplicate."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik

from ..solvers.closed_form.random_arms import wrapped_distance

Q = np.array([0.8734401444668087, 0.4833240247508619, -0.690271288514877, 2.0827081087563175,
              1e-5, 0.7771964471693624, 0.9191034163655864])  # fmt: skip


def _reaches(arm: armik.Arm, q: np.ndarray, T: pin.SE3) -> bool:
    M = arm.fk(q)
    rotation = np.linalg.norm(pin.log3(M.rotation.T @ T.rotation))
    return bool(np.linalg.norm(M.translation - T.translation) < 1e-9 and rotation < 1e-9)


@pytest.mark.parametrize("joint_5", [1e-5, -3e-5, 2e-6])
def test_two_solutions_a_hair_apart_are_two_with_a_joint_held(joint_5):
    arm = armik.load("kuka_iiwa14")
    q = Q.copy()
    q[4] = joint_5
    T = arm.fk(q)
    got = [r for r in arm.solve_all(T, hold={"iiwa_joint_6": q[5]}) if r.success]
    assert all(_reaches(arm, r.q, T) for r in got)
    assert min(wrapped_distance(r.q, q) for r in got) < 1e-9  # the target's own
    near = [r for r in got if 1e-6 < wrapped_distance(r.q, q) < 1e-3]
    assert near and near[0].q[4] * joint_5 < 0  # and its twin, joint 5 on the other side


@pytest.mark.parametrize("joint_5", [1e-5, -3e-5, 2e-6])
def test_two_solutions_a_hair_apart_are_two_on_a_locked_arm(joint_5):
    arm = armik.load("kuka_iiwa14", locked={"iiwa_joint_6": float(Q[5])})
    q = np.delete(Q, 5)
    q[4] = joint_5
    T = arm.fk(q)
    results = arm.solve_all(T)
    assert {r.solver for r in results} == {"spherical_shoulder"}
    got = [r for r in results if r.success]
    assert all(_reaches(arm, r.q, T) for r in got)
    assert min(wrapped_distance(r.q, q) for r in got) < 1e-9
    assert any(1e-6 < wrapped_distance(r.q, q) < 1e-3 for r in got)


def test_a_numeric_solver_keeps_its_own_duplicate_tolerance():
    """dls's answers stop anywhere within the tolerance: two within DUPLICATE_TOL are one."""
    arm = armik.load("panda")
    T = arm.fk(arm.random_q(np.random.default_rng(2)))
    got = [r.q for r in arm.solve_all(T, solver="dls", max_solutions=8, seed=1) if r.success]
    assert got
    for i in range(len(got)):
        for j in range(i):
            assert np.abs(got[i] - got[j]).max() >= 1e-4
