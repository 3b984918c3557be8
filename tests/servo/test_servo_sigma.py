"""The servo's sigma: the smallest singular value of the unweighted rows the task asks for,
a row zero at this q included (a stretched arm's), a direction the arm never moves in (a
planar arm's normal) left out."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

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
    J = ur5.jacobian(q0, "base")
    s = ur5.servo(q0).step(ur5.fk(q0).translation + [0.01, 0.0, 0.0])
    assert abs(s.sigma - _true_sigma(J, [0, 1, 2])) < 1e-9
