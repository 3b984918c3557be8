"""plan="global" where every path breaks: the plan goes on from every rung at every turn
within the limits (``kernel.ladder._every_turn``), so a break leaves room for the rest of
the path where one jump can."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from .. import conftest


def test_a_spin_past_a_wrist_limit_breaks_once():
    """The UR5's tool spun two turns from a configuration with wrist 3 at 5.38 rad (limits
    +-2 pi): 0.9 rad of room, then one jump of wrist 3 two turns down leaves room for the
    remaining 11.7 rad. The plan took each rung after the jump only at the turn nearest
    the answer before, and broke again half way through; it now breaks once, at the
    limit, and fewer times than following (a wrist flip each half turn)."""
    ur5 = conftest.arm("ur5")
    q = ur5.random_q(11)
    room = ur5.upper[5] - q[5]
    assert room < 1.0 and 4 * math.pi - room < ur5.upper[5] - ur5.lower[5]  # one jump will do
    T0 = ur5.fk(q)
    poses = [
        T0 * pin.SE3(pin.exp3(np.array([0.0, 0.0, 4 * math.pi * k / 80])), np.zeros(3))
        for k in range(80)
    ]
    followed = ur5.solve_path(poses, q, max_joint_step=0.3)
    planned = ur5.solve_path(poses, q, max_joint_step=0.3, plan="global")
    breaks = np.flatnonzero(~planned.success).tolist()
    assert len(breaks) == 1, breaks
    assert (~followed.success).sum() > 1
    assert planned.status[breaks[0]] == "discontinuous"
    prev = q
    for i, (pose, x) in enumerate(zip(poses, planned.q)):
        assert np.abs(pin.log6(pose.actInv(ur5.fk(x))).vector).max() <= 1e-6
        assert ur5.within_limits(x)
        if i not in breaks:
            assert np.abs(x - prev).max() <= 0.3 + 1e-9
        prev = x


def test_a_break_says_which_paths_break_when_another_solution_goes_on():
    """The IRB 120 along a tilted arc: the plan breaks at waypoints 1 and 10, following at 1
    and 2. At 10 the plan's reason said "every path breaks here: from every solution of
    the waypoint before", yet following's answer at 9, a verified solution, goes on to 10
    within the bound: it breaks on its way to 9 instead. The reason now says every path
    from the plan's last break without a jump breaks here."""
    arm = conftest.arm("abb_irb120")
    q = arm.random_q(104)
    T0 = arm.fk(q)
    d = np.array([0.06199234, -0.07392795, -0.99533492])
    axis = np.array([-0.97481011, -0.08776654, 0.20504214])
    poses = [
        T0 * pin.SE3(pin.exp3(axis * 1.5 * math.pi * k / 40), d * 0.1 * math.sin(k / 8))
        for k in range(40)
    ]
    followed = arm.solve_path(poses, q, max_joint_step=0.3)
    planned = arm.solve_path(poses, q, max_joint_step=0.3, plan="global")
    verified = followed.success | (followed.status == "discontinuous")
    claims = 0
    for i in np.flatnonzero(planned.status == "discontinuous").tolist():
        reason = planned[i].reason
        goes_on = (
            i > 0
            and verified[i - 1]
            and followed.success[i]
            and np.abs(followed.q[i] - followed.q[i - 1]).max() <= 0.3
        )
        if goes_on:  # a solution of the waypoint before reaches this one in a step
            claims += 1
            assert "from every solution of the waypoint before" not in reason, reason
            assert "without a jump breaks here" in reason, reason
    assert claims >= 1
    assert (planned.status == "discontinuous").sum() <= (followed.status == "discontinuous").sum()
