"""plan="global" where the rungs are not every solution (an SRS arm's swivel, a numeric
solver's tracks): the followed path's answers are rungs, so the plan breaks nowhere
following goes through, and says its breaks are among the answers found."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from .. import conftest


def _verified(arm, poses, q0, planned, step):
    """Every success on its pose by Pinocchio's FK, within the limits, no step above
    ``step`` from the answer before it (or from q0)."""
    prev = q0
    for i, (pose, q) in enumerate(zip(poses, planned.q)):
        if planned.success[i]:
            assert np.abs(pin.log6(pose.actInv(arm.fk(q))).vector).max() <= 1e-6
            assert arm.within_limits(q)
            assert np.abs(q - prev).max() <= step + 1e-9
        if planned.success[i] or planned.status[i] == "discontinuous":
            prev = q


def test_an_srs_plan_goes_where_following_goes():
    """The iiwa (``srs``: every branch at one swivel angle): the tool tilted about its x
    axis from a random configuration. Following drifts the swivel with the path and solves
    every waypoint; the plan, whose rungs were every branch at the start's swivel only,
    broke at waypoint 13. Its rungs now hold the followed answers and every branch at
    their swivel too."""
    arm = conftest.arm("kuka_iiwa14")
    q = arm.random_q(13)
    T0 = arm.fk(q)
    poses = [T0 * pin.SE3(pin.exp3(np.array([0.05 * k, 0.0, 0.0])), np.zeros(3)) for k in range(16)]
    followed = arm.solve_path(poses, q, max_joint_step=0.3)
    planned = arm.solve_path(poses, q, max_joint_step=0.3, plan="global")
    assert followed.success.all(), followed.summary()
    assert planned.success.all(), planned.summary()
    assert planned.solver == "srs"
    _verified(arm, poses, q, planned, 0.3)


def test_an_srs_break_claims_only_the_answers_found():
    """A quarter turn of the tool between two waypoints of the iiwa: the plan flags the
    waypoint, and says the break is among the answers found (one swivel angle's branches
    are not every solution of a 7-joint arm), not that every path breaks."""
    arm = conftest.arm("kuka_iiwa14")
    q = arm.random_q(8)
    T0 = arm.fk(q)
    turn = pin.SE3(pin.exp3(np.array([0.0, 0.0, math.pi / 2])), np.zeros(3))
    poses = [T0 if k <= 5 else T0 * turn for k in range(10)]
    planned = arm.solve_path(poses, q, max_joint_step=0.2, plan="global")
    assert np.flatnonzero(~planned.success).tolist() == [6], planned.summary()
    reason = planned[6].reason
    assert "every path through the answers found breaks here" in reason, reason


def test_a_followed_jump_s_answer_is_a_rung():
    """The Panda by ``dls``, the tool spun a whole turn: following flags one jump
    (waypoint 11) and goes on from that jump's verified answer through the rest. The plan,
    whose rungs left out the answer of a jump, broke again at waypoint 26, where following
    does not; with that answer a rung it solves every waypoint following solves."""
    panda = conftest.arm("panda")
    q = panda.random_q(4)
    T0 = panda.fk(q)
    poses = [
        T0 * pin.SE3(pin.exp3(np.array([0.0, 0.0, 2 * math.pi * k / 60])), np.zeros(3))
        for k in range(60)
    ]
    budget = {"iteration_budget": 3000, "seed": 0}  # deterministic, not timed
    followed = panda.solve_path(poses, q, max_joint_step=0.3, solver="dls", **budget)
    planned = panda.solve_path(poses, q, max_joint_step=0.3, solver="dls", plan="global", **budget)
    assert not followed.success.all(), followed.summary()
    assert not (followed.success & ~planned.success).any(), planned.summary()
    assert planned.success.sum() >= followed.success.sum()
    _verified(panda, poses, q, planned, 0.3)
