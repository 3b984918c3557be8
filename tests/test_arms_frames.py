"""A frame of one arm that a shared torso also carries (TALOS's right forearm: the left
chain holds it still, the right one moves it) is placed by the chain that moves it as the
robot does: ``fk``, ``jacobian`` and a flat task list's tip, against Pinocchio's FK of the
whole URDF computed here."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import armik
from armik.arms_tasks import by_tip

from .test_arms_parity import HANDS, TALOS


def test_a_frame_the_torso_carries_is_placed_by_the_chain_that_moves_it():
    robot = armik.load(TALOS, tips=HANDS)
    model = pin.buildModelFromUrdf(str(TALOS))
    data = model.createData()

    def whole(q: np.ndarray, frame: str) -> pin.SE3:
        qf = pin.neutral(model)
        for name, v in zip(robot.joint_names, q):
            qf[model.joints[model.getJointId(name)].idx_q] = v
        pin.framesForwardKinematics(model, data, qf)
        return data.oMf[model.getFrameId(frame)].copy()

    q = robot.random_q(5)
    for frame in ("arm_right_7_link", "arm_right_4_link", "arm_left_4_link", "torso_2_link"):
        assert np.allclose(robot.fk(q, frame=frame).homogeneous, whole(q, frame).homogeneous)
        J = robot.jacobian(q, frame=frame, reference="base")
        for k in range(robot.dof):
            dq = np.zeros(robot.dof)
            dq[k] = 1e-6
            moved = (whole(q + dq, frame).translation - whole(q - dq, frame).translation) / 2e-6
            assert np.allclose(J[:3, k], moved, atol=1e-5)
    T = whole(q, "arm_right_4_link")
    tasks = [
        armik.Pose(whole(q, HANDS[0]), frame=HANDS[0]),
        armik.Position(T.translation, frame="arm_right_4_link"),
    ]
    assert list(by_tip(robot._chains, tasks)) == HANDS  # the forearm's task is the right hand's
    r = robot.solve(tasks)
    assert r.success
    assert np.linalg.norm(whole(r.q, "arm_right_4_link").translation - T.translation) < 1e-5
