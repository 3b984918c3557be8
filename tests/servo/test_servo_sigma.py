"""The servo's sigma: the smallest singular value of the unweighted rows the task asks for,
a row zero at this q included (a stretched arm's), a direction the arm never moves in (a
planar arm's normal) left out."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import armik
from armik.servo.streams import START
from tests.conftest import arm as load


def test_a_stretched_arm_is_a_singularity():
    """The 2-link stretched along x: the x row of its Jacobian is zero, sigma is 0 (it
    read 1.97, the y row's alone, and said 'tracking' for ever)."""
    arm = load("planar_2link")
    s = arm.servo(np.zeros(2)).step([1.5, 0.3])
    assert s.sigma < 1e-9
    rec = arm.servo(np.zeros(2)).track([[1.7, 0.0]] * 20)
    assert rec.sigma.max() < 1e-9
    assert set(rec.status.tolist()) == {"singularity"}
    scara = load("scara")  # shoulder and elbow stretched
    q0 = scara.middle
    s = scara.servo(q0).step(scara.fk(q0).translation + [0.05, 0.0, 0.02])
    assert s.sigma < 1e-9


def _true_sigma(J, rows):
    return np.linalg.svd(J[rows], compute_uv=False)[min(len(rows), J.shape[1]) - 1]


def test_a_planar_arm_is_not_singular_for_the_rows_it_never_moves():
    """A planar arm's tip never leaves its plane: the position's row along the normal is
    zero at every q and left out, so a bent planar arm's sigma is its in-plane rows'."""
    for name, q0 in (("planar_2link", [0.3, 0.8]), ("planar_3link", [0.3, 0.8, -0.5])):
        arm = load(name)
        q0 = np.array(q0)
        J = arm.jacobian(q0, "base")
        s = arm.servo(q0).step(arm.fk(q0).translation + [0.01, 0.01, 0.0])
        assert abs(s.sigma - _true_sigma(J, [0, 1])) < 1e-9
        assert s.sigma > 0.05 and s.status != "singularity"
        pose = arm.fk(q0)  # a pose: x, y and the turn about the normal (3 rows, n >= 2)
        s = arm.servo(q0).step(pin.SE3(pose.rotation, pose.translation + [0.01, 0.0, 0.0]))
        assert abs(s.sigma - _true_sigma(J, [0, 1, 5])) < 1e-9 and s.sigma > 0.05


def test_a_position_on_a_spatial_arm_reads_its_position_rows():
    ur5, q0 = load("ur5"), START["ur5"]
    J = ur5.jacobian(q0, reference="base")
    s = ur5.servo(q0).step(ur5.fk(q0).translation + [0.01, 0.0, 0.0])
    assert abs(s.sigma - _true_sigma(J, [0, 1, 2])) < 1e-9


def test_a_tip_on_its_joints_axis_reads_the_rank_th_singular_value():
    """``panda_link4`` lies on joint 4's axis: it moves on a sphere around the shoulder,
    its position rows of rank 2 at every q. Sigma is their second singular value (it was
    the third, always 0: 'singularity' at every posture, the step damped for good); sent
    off the sphere, the servo rests at its nearest point saying 'stalled'."""
    arm = armik.load("panda", tip="panda_link4")
    q0 = np.array([0.0, -0.3, 0.0, -2.2])
    J = arm.jacobian(q0, "base")
    target = arm.fk(q0).translation + [0.0, 0.03, 0.0]
    s = arm.servo(q0).step(target)
    assert abs(s.sigma - np.linalg.svd(J[:3], compute_uv=False)[1]) < 1e-9
    assert s.sigma > 0.05 and s.status != "singularity"
    record = arm.servo(q0).track([target] * 600)
    assert "singularity" not in set(record.status.tolist())
    assert record.status[-1] == "stalled"
    centre = arm.fk(q0, frame="panda_link2").translation  # joints 1 and 2 meet there
    radius = np.linalg.norm(arm.fk(q0).translation - centre)
    nearest = abs(np.linalg.norm(target - centre) - radius)
    reached = np.linalg.norm(_pinocchio_position(arm, record.q[-1]) - target)
    assert abs(reached - nearest) < 1e-6 and abs(record.position_error[-1] - reached) < 1e-12


def test_over_shared_joints_the_rank_counts_each_tips_rows():
    """The union of ``panda_link4`` and the hand (joints 1-4 shared), a position each:
    six rows of which five can be independent; sigma is the fifth singular value (it was
    the sixth, always 0)."""
    both = armik.load("panda", tips=["panda_link4", "panda_hand"])
    link4, hand = both.tips
    for q0 in (START["panda"], both.middle):
        J = both.jacobian(q0)
        rows = np.vstack([J[link4][:3], J[hand][:3]])
        goal = {tip: both.fk(q0, tip).translation + [0.0, 0.02, 0.0] for tip in both.tips}
        s = both.servo(q0).step(goal)
        assert abs(s.sigma - np.linalg.svd(rows, compute_uv=False)[4]) < 1e-9
        assert s.sigma > 1e-3


def _pinocchio_position(arm, q):
    """The tip's position at q by Pinocchio's own FK on the arm's URDF (the whole model,
    the chain's joints set by name, every other at zero)."""
    model = pin.buildModelFromUrdf(str(arm.source))
    data = model.createData()
    full = pin.neutral(model)
    for name, value in zip(arm.joint_names, q):
        full[model.joints[model.getJointId(name)].idx_q] = value
    pin.framesForwardKinematics(model, data, full)
    return data.oMf[model.getFrameId(arm.tip)].translation.copy()
