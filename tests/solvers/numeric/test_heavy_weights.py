"""Weights of any ratio the options allow solve a reachable full pose: they change what is
traded off, not whether the pose is found."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from ...conftest import TOL, arm

# random_q seeds of poses that 1e6 on the rotation left unsolved after 1000 restarts each
# (with seed=0), beside two that any weights solved
HARD = {"ur5": (246, 248, 3), "panda": (274, 14, 43, 214, 3)}
RATIOS = (1e-6, 1e-3, 1.0, 1e3, 1e6)


def pinocchio_tip(name: str, q: np.ndarray) -> pin.SE3:
    """The tip pose by Pinocchio itself, on its own Data (T_base_tip: these bases are the
    world)."""
    m = arm(name).kinematics
    return pin.updateFramePlacement(
        m.model, _forward(m.model, m.to_pin(np.asarray(q))), m.tip_frame_id
    ).copy()


def _forward(model: pin.Model, qp: np.ndarray) -> pin.Data:
    data = model.createData()
    pin.forwardKinematics(model, data, qp)
    return data


@pytest.mark.parametrize("solver", ["dls", "qp"])
@pytest.mark.parametrize("name", sorted(HARD))
@pytest.mark.parametrize("ratio", RATIOS)
def test_any_weight_ratio_solves_a_reachable_pose(name, solver, ratio):
    a = arm(name)
    for s in HARD[name]:
        q_true = a.random_q(s)
        target = pinocchio_tip(name, q_true)
        for w in ((ratio,) * 3 + (1.0,) * 3, (1.0, ratio, 1.0, ratio, 1.0, 1.0)):
            r = a.solve(target, solver=solver, weights=w, seed=0)
            assert r.success, (s, w, r.reason)
            err = pin.log6(pinocchio_tip(name, r.q).actInv(target))
            assert np.linalg.norm(err.linear) <= TOL["solve"]
            assert np.linalg.norm(err.angular) <= TOL["solve"]
            assert a.within_limits(np.asarray(r.q), tol=0.0)
