"""The servo's weights: read by their ratios only, and no false singularity from small
ones (sigma is measured on the unweighted rows)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.servo.streams import START
from tests.conftest import arm as load


def test_weights_by_their_ratios_and_no_false_singularity():
    """Small rotation weights stalled 3e-5 m and 0.11 rad off a reachable target, called a
    singularity (the weighted rows' sigma, 5.8e-3); the same ratios scaled by 100 reached
    it. Sigma is the unweighted rows' and the weights are read by their ratios."""
    ur5, q0 = load("ur5"), START["ur5"]
    T0 = ur5.fk(q0)
    R = pin.rpy.rpyToMatrix(0.5, 0.2, 0.1) @ T0.rotation
    target = pin.SE3(R, T0.translation + [0.05, 0.05, 0.0])
    plain = ur5.servo(q0).step(target)
    records = []
    for w in [(1, 1, 1, 0.01, 0.01, 0.01), (100, 100, 100, 1, 1, 1)]:
        pose = armik.Pose(target, weights=w)
        assert abs(ur5.servo(q0).step(pose).sigma - plain.sigma) < 1e-12
        records.append(ur5.servo(q0).track([pose] * 3000))
    small, large = records
    np.testing.assert_array_equal(small.q, large.q)
    assert small.status[-1] == "on_target"
    assert small.position_error[-1] < 1e-6 and small.orientation_error[-1] < 1e-6
    assert "singularity" not in set(small.status.tolist())


def test_weights_too_far_apart_refused_as_solve_refuses_them():
    """Weights more than ``MAX_WEIGHT`` apart are refused by the servo as by ``solve``
    (their message, the servo's ``TargetError``); at the limit they are taken."""
    ur5, q0 = load("ur5"), START["ur5"]
    T0 = ur5.fk(q0)
    far = armik.Pose(T0, weights=(1, 1, 1, 1e-7, 1e-7, 1e-7))
    with pytest.raises(armik.OptionError, match="at most 1e\\+06 times the smallest") as solved:
        ur5.solve(far, max_iterations=5)
    servo = ur5.servo(q0)
    with pytest.raises(armik.TargetError, match="at most 1e\\+06 times the smallest") as served:
        servo.step(far)
    assert str(served.value) == str(solved.value)
    with pytest.raises(armik.TargetError, match="target 1: weights must be"):
        servo.track([T0, far])
    np.testing.assert_array_equal(servo.q, q0)  # nothing commanded
    servo.step(armik.Pose(T0, weights=(1, 1, 1, 1e-6, 1e-6, 1e-6)))


def test_equal_weights_step_as_none_and_too_large_ones_are_refused():
    """Equal weights (a task's default) step as no weights do, whatever their value; equal
    but above ``MAX_WEIGHT`` they are refused as ``solve`` refuses them."""
    ur5, q0 = load("ur5"), START["ur5"]
    T = ur5.fk(q0 + 0.05)
    plain = ur5.servo(q0).track([T] * 20)
    for w in (1.0, 2.5, 1e6):
        got = ur5.servo(q0).track([armik.Pose(T, weights=(w,) * 6)] * 20)
        np.testing.assert_array_equal(got.q, plain.q)
    with pytest.raises(armik.TargetError, match="weights must be") as served:
        ur5.servo(q0).step(armik.Pose(T, weights=(1e7,) * 6))
    with pytest.raises(armik.OptionError, match="weights must be") as solved:
        ur5.solve(armik.Pose(T, weights=(1e7,) * 6), max_iterations=5)
    assert str(served.value) == str(solved.value)
