"""A frame that a mimic joint off the chain moves (the Panda's right finger with the tip on
the left one, whose joint drives it) is found on the whole model once per arm and frame,
and read on one whole-model data per thread: every query gives what a fresh data gives,
bit for bit, whatever was asked before it."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import armik
from armik.model import mimic_frames


def test_a_followed_frame_is_found_once_and_read_as_on_fresh_data(monkeypatch):
    arm = armik.load("panda", tip="panda_leftfinger")
    model = arm.kinematics
    found = []
    original = mimic_frames.frame_id

    def counted(full, frame):
        found.append(frame)
        return original(full, frame)

    monkeypatch.setattr(mimic_frames, "frame_id", counted)
    full = model.chain.full
    fid = full.getFrameId("panda_rightfinger")
    for q in arm.random_q(0, n=6):  # fk and Jacobians of two frames, interleaved
        T = arm.fk(q, "panda_rightfinger")
        J = arm.jacobian(q, "panda_rightfinger", "local")
        arm.fk(q, "panda_link5")
        data = full.createData()
        qf = mimic_frames._full_q(model, q)
        pin.framesForwardKinematics(full, data, qf)
        assert np.array_equal(T.homogeneous, (model.T_base_world * data.oMf[fid]).homogeneous)
        Jf = pin.computeFrameJacobian(full, full.createData(), qf, fid, pin.LOCAL)
        column = [full.joints[full.getJointId(n)].idx_v for n in model.joint_names]
        expected = Jf[:, column].copy()  # the chain's columns, the mimic's folded into its driver
        expected[:, 7] += 1.0 * Jf[:, full.joints[full.getJointId("panda_finger_joint2")].idx_v]
        assert np.array_equal(J, expected)
    assert found.count("panda_rightfinger") <= 1
