"""At an exactly singular target a closed form's double root comes out split by rounding
(1e-6 to 1e-4 rad apart): ``solve_all`` lists it once. Merging only within 1e-6 listed such
a root two or three times as separate branches (the iiwa with joint 6 held, the Panda with
joint 6 locked, joint 5 = 0)."""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.kernel.descent import DUPLICATE_TOL
from tests.conftest import arm


def _wrapped_apart(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(np.angle(np.exp(1j * (a - b)))).max())


def _rows_once(robot, T, **options) -> int:
    rows = [r for r in robot.solve_all(T, **options) if r.success]
    assert rows
    data = robot.model.createData()
    for r in rows:  # each on the target by Pinocchio
        pin.framesForwardKinematics(robot.model, data, robot.kinematics.to_pin(r.q))
        placed = robot.kinematics.T_base_world * data.oMf[robot.model.getFrameId(robot.tip)]
        assert np.linalg.norm(placed.translation - T.translation) < 1e-9
    for i, a in enumerate(rows):
        for b in rows[i + 1 :]:
            assert _wrapped_apart(a.q, b.q) > DUPLICATE_TOL, (a.branch, b.branch)
    return len(rows)


@pytest.mark.parametrize("k", [16, 24, 32])
def test_the_iiwa_held_at_an_exact_wrist_singularity_lists_each_root_once(k):
    iiwa = arm("kuka_iiwa14")
    rng = np.random.default_rng(0)
    for _ in range(k + 1):
        q = iiwa.random_q(rng)
    q[4] = 0.0
    _rows_once(iiwa, iiwa.fk(q), hold={"iiwa_joint_6": q[5]})


def test_the_panda_locked_near_its_far_meeting_lists_each_root_once():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", armik.ArmikWarning)
        panda = armik.load("panda", locked={"panda_joint6": 1e-3})
    rng = np.random.default_rng(4)
    counted = 0
    for _ in range(6):
        q = panda.random_q(rng)
        q[4] = 0.0
        counted += _rows_once(panda, panda.fk(q))
    assert counted >= 6
