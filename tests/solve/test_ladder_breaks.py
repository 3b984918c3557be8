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
