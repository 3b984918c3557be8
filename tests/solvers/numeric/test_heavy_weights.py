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


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_heavy_weights_still_choose_what_an_unreachable_pose_trades(solver):
    """Wrist limits that leave the pose out of reach: 1e6 on the position keeps the
    position and gives up orientation, 1e6 on the rotation the other way round."""
    a = arm("ur5").with_limits({"wrist_3_joint": (-0.2, 0.2), "wrist_2_joint": (0.5, 1.0)})
    q = arm("ur5").random_q(3)
    q[4], q[5] = 0.7, 1.0  # outside the narrowed limits
    target = pinocchio_tip("ur5", q)
    found = {}
    for heavy, w in (("position", (1e6,) * 3 + (1,) * 3), ("rotation", (1,) * 3 + (1e6,) * 3)):
        r = a.solve(target, q0=a.middle, solver=solver, weights=w, max_restarts=50, seed=0)
        assert not r.success and r.status.value == "not_converged"
        reached = pinocchio_tip("ur5", r.q)
        rot = np.linalg.norm(pin.log3(reached.rotation.T @ target.rotation))
        found[heavy] = (np.linalg.norm(reached.translation - target.translation), rot)
    assert found["position"][0] < 1e-5 < found["rotation"][0]
    assert found["rotation"][1] < found["position"][1]
