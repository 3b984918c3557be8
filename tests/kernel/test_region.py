"""The compiled error of a pose within bounds equals ``armik.problem.Pose``'s residual and
Jacobian (which the problem tests hold against finite differences)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from armik.kernel.problem import workspace
from armik.kernel.region import evaluate_region
from armik.problem import Pose

from ..conftest import arm

EXACT = 1e-12
BOUNDS = [
    (0.0,) * 6,
    (0.005, 0.005, 0.005, 0.05, 0.05, 0.05),
    (0.01, 0.0, math.inf, 0.0, 0.2, math.inf),
    (math.inf, math.inf, math.inf, 0.0, 0.0, 0.0),
]


@pytest.mark.parametrize("robot", ["panda", "ur5", "kinova"])
@pytest.mark.parametrize("bounds", BOUNDS)
def test_the_region_error_is_the_pose_task(robot, bounds):
    a = arm(robot)
    ch = a.kernel_chain.flat
    ws = workspace(a.dof, 1, a.kernel_chain.chain.joint_kind.shape[0])
    rng = np.random.default_rng(21)
    weights = np.array([1.0, 2.0, 0.5, 1.0, 0.0, 3.0])
    for k in range(10):
        q = a.random_q(rng)
        T = a.fk(q)
        T_t = T * pin.exp6(pin.Motion(rng.normal(scale=0.05, size=6)))
        w = np.ones(6) if k % 2 else weights
        task = Pose(T_t, bounds=bounds, weights=w)
        ws.q[0][:] = q
        b = np.array(bounds, dtype=float)
        R_t, p_t = np.ascontiguousarray(T_t.rotation), np.ascontiguousarray(T_t.translation)
        evaluate_region(ch, b, w, R_t, p_t, ws, 0)
        np.testing.assert_allclose(ws.e[0], -task.residual(T), rtol=0, atol=EXACT)
        J = a.jacobian(q)
        np.testing.assert_allclose(ws.A[0], task.jacobian(T, J), rtol=0, atol=EXACT)
        m = task.measure(T, 0.0, 0.0)
        free = w == 0  # a weight of 0 frees its axis: not measured
        assert ws.val[0, 0] == pytest.approx(m.position, abs=EXACT) or free[:3].any()
        assert ws.val[0, 1] == pytest.approx(m.orientation, abs=EXACT) or free[3:].any()
        assert ws.val[0, 2] == pytest.approx(float(ws.e[0] @ ws.e[0]), abs=EXACT)


def test_inside_the_region_the_error_is_zero():
    a = arm("ur5")
    ws = workspace(a.dof, 1, a.kernel_chain.chain.joint_kind.shape[0])
    q = a.random_q(np.random.default_rng(4))
    T = a.fk(q) * pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.04])), np.array([0.003, 0.0, 0.0]))
    ws.q[0][:] = q
    bounds = np.array([0.005, 0.005, 0.005, 0.05, 0.05, 0.05])
    R_t, p_t = np.ascontiguousarray(T.rotation), np.ascontiguousarray(T.translation)
    evaluate_region(a.kernel_chain.flat, bounds, np.ones(6), R_t, p_t, ws, 0)
    assert not ws.e[0].any() and not ws.A[0].any() and not ws.val[0].any()
