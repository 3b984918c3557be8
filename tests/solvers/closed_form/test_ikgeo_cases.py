"""IK-Geo's public test cases (tests/data/ikgeo: its ``test_cases`` folder, BSD-3-Clause):
on each, armik's ``solve_all`` on the arm written from IK-Geo's H and P returns the
configuration IK-Geo drew, each joint within 1e-6 rad modulo 2 pi, among its verified
answers; every answer it returns as a success reaches the target by Pinocchio's FK
computed here. The three 7R robots are solved with their joint held as IK-Geo holds it.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik

from ...ikgeo_cases import CLASSES, FILES, ROBOTS, cases, found

SAME = 1e-6  # rad, each joint modulo 2 pi
REACHED = 1e-9  # m and rad: an answer's tip from the target


def test_the_data_is_every_case_of_every_file():
    assert len(FILES) == len(CLASSES) + len(ROBOTS) == 16
    assert [len(cases(name)) for name in FILES] == [10] * 16


def _reaches(arm: armik.Arm, q: np.ndarray, target: np.ndarray) -> bool:
    m = arm.kinematics
    pin.forwardKinematics(m.model, m.data, m.to_pin(q))
    tip = m.T_base_world * pin.updateFramePlacement(m.model, m.data, m.tip_frame_id)
    error = pin.log6(tip.actInv(pin.SE3(target))).vector
    return bool(np.linalg.norm(error[:3]) <= REACHED and np.linalg.norm(error[3:]) <= REACHED)


@pytest.mark.parametrize("name", FILES)
def test_every_drawn_configuration_is_among_solve_alls_answers(name):
    missed, false = [], 0
    for i, case in enumerate(cases(name)):
        arm = armik.load_string(case.urdf, base="world", tip="tool")
        options = {} if case.hold is None else {"hold": case.hold}
        answers = [r.q for r in arm.solve_all(case.target, **options) if r.success]
        if not found(case.q, answers, SAME):
            missed.append(i)
        false += sum(not _reaches(arm, q, case.target) for q in answers)
    assert missed == []
    assert false == 0
