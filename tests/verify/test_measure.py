"""The FK check that every answer passes through."""

from __future__ import annotations

import numpy as np
import pytest

from armik.options import Options
from armik.targets.pose import parse_target
from armik.verify.measure import measure

from ..conftest import model


def test_known_good_joints_pass(rng):
    a = model("panda")
    q = a.random_q(rng)
    c = measure(a, q, parse_target(a.fk(q)), Options())
    assert c.ok and c.position_error < 1e-14 and c.orientation_error < 1e-14


def test_wrong_joints_fail_with_measured_errors(rng):
    a = model("panda")
    q = a.random_q(rng)
    target = parse_target(a.fk(q))
    q_bad = q.copy()
    q_bad[0] += 1e-3
    c = measure(a, q_bad, target, Options())
    assert not c.ok and c.position_error > 1e-6
    assert c.orientation_error == pytest.approx(1e-3, rel=1e-6)  # one joint turned 1 mrad


def test_limits_are_checked():
    a = model("panda")
    q = a.middle.copy()
    q[3] = 0.5  # joint 4 is limited to [-3.07, -0.07]
    c = measure(a, q, parse_target(a.fk(q)), Options())
    assert c.pose_ok and not c.ok
    assert "panda_joint4" in c.violations[0]


def test_position_only_and_weights(rng):
    a = model("ur5")
    q = a.random_q(rng)
    T = a.fk(q)
    c = measure(a, q, parse_target(T.translation), Options())
    assert c.orientation_error is None and c.ok
    # rotation about the tool's own z axis is free when its weight is zero
    import pinocchio as pin

    T_turned = T * pin.SE3(pin.rpy.rpyToMatrix(0, 0, 0.7), np.zeros(3))
    free_z = Options(weights=(1, 1, 1, 1, 1, 0))
    assert measure(a, q, parse_target(T_turned), free_z).ok
    assert not measure(a, q, parse_target(T_turned), Options()).ok
