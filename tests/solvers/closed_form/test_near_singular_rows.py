"""An elbow almost stretched (6e-5 to 9e-5 rad) has two exact roots which the closed form
solves as one merged root and its mirror: both rows are listed where they lie
``DUPLICATE_TOL`` (1e-4) or more apart, as two solutions; ``keep_nearer`` kept one of
them, so the target's own configuration could be missing. Every row reaches the target
by Pinocchio's FK."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from armik.kernel.descent import DUPLICATE_TOL
from tests.conftest import arm


def _apart(a, b) -> float:
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max())


def _off(robot, q, T: pin.SE3) -> float:
    """The tip's distance from ``T`` at ``q`` by Pinocchio (m and rad, the larger)."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.kinematics.to_pin(q))
    placed = robot.kinematics.T_base_world * data.oMf[robot.model.getFrameId(robot.tip)]
    turned = np.linalg.norm(pin.log3(placed.rotation.T @ T.rotation))
    return max(np.linalg.norm(placed.translation - T.translation), turned)


@pytest.mark.parametrize("name", ["ur5", "ur10"])
def test_both_roots_of_an_elbow_almost_stretched_are_listed(name):
    robot = arm(name)
    rng = np.random.default_rng(7)
    for k in range(10):
        q = robot.random_q(rng)
        q[2] = (-1) ** k * rng.uniform(6e-5, 9e-5)
        T = robot.fk(q)
        rows = [r for r in robot.solve_all(T) if r.success]
        for r in rows:
            assert _off(robot, r.q, T) < 1e-9, (q, r.q)
        for i, r in enumerate(rows):  # none twice
            assert all(_apart(r.q, other.q) >= DUPLICATE_TOL for other in rows[i + 1 :])
        assert min(_apart(r.q, q) for r in rows) < 1e-6, q
