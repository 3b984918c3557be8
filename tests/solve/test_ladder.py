"""plan="global": the least-motion path over every branch at every waypoint
(``armik.solve.ladder``), checked against brute force, greedy following and q0."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.kernel.ladder import _child
from armik.solve.single import solve
from armik.status import Status

from .. import conftest


def _spun(arm, q, turns, n):
    T0 = arm.fk(q)
    return [
        T0 * pin.SE3(pin.exp3(np.array([0, 0, turns * math.pi * k / (n - 1)])), np.zeros(3))
        for k in range(n)
    ]


def test_a_tool_spun_past_its_joint_limit_is_planned_through():
    """UR5, the tool spun 1.5 turns: following from the middle runs wrist 3 into its
    limit; the global plan starts it at the turn that leaves room (2 pi variants)."""
    arm = conftest.arm("ur5")
    q = arm.middle.copy()
    q[4] = 1.0
    poses = _spun(arm, q, 3.0, 120)
    follow = arm.solve_path(poses, q, max_joint_step=0.3)
    assert not follow.success.all()
    planned = arm.solve_path(poses, None, max_joint_step=0.3, plan="global")
    assert planned.success.all()
    assert np.abs(np.diff(planned.q, axis=0)).max() <= 0.3
    assert (planned.q >= arm.lower).all() and (planned.q <= arm.upper).all()
    for T, qi in zip(poses, planned.q):
        assert np.allclose(arm.fk(qi).homogeneous, T.homogeneous, atol=1e-9)


def test_the_plan_is_the_brute_force_optimum_on_a_short_path():
    """Every sequence of branches (each joint turned next to the one before, as the ladder
    does) on a 4-waypoint path of the IRB 120: the ladder's total motion is the least."""
    arm = conftest.arm("abb_irb120")
    rng = np.random.default_rng(35)
    q0 = arm.random_q(rng)
    T0 = arm.fk(q0)
    poses = [
        pin.SE3(T0.rotation, T0.translation + np.array([0.004 * k, 0.0, 0.0])) for k in range(4)
    ]
    step = np.full(arm.dof, 0.4)
    planned = arm.solve_path(poses, q0, max_joint_step=0.4, plan="global")
    assert planned.success.all()
    total = np.linalg.norm(np.diff(np.vstack([q0, planned.q]), axis=0), axis=1).sum()
    rungs = [
        [np.asarray(r.q) for r in solve(arm, T, q0=q0, all_solutions=True) if r.success]
        for T in poses
    ]
    lo, hi = arm.lower, arm.upper
    periodic = ~np.array(arm._limit_lists[2], dtype=bool)
    best = math.inf
    for choice in itertools.product(*rungs):
        prev, cost = q0, 0.0
        for b in choice:
            nxt, turn = np.empty(arm.dof), np.zeros(arm.dof, np.int64)
            if not _child(b[None, :], 0, prev, lo, hi, periodic, nxt, turn):
                cost = math.inf
                break
            if (np.abs(nxt - prev) > step).any():
                cost = math.inf
                break
            cost += float(np.linalg.norm(nxt - prev))
            prev = nxt
        best = min(best, cost)
    assert total == pytest.approx(best, abs=1e-9)


def test_a_forced_flip_is_reported_at_its_waypoint():
    """The tool turned a quarter turn between waypoints 10 and 11: every path breaks at 11,
    and only there; the reason names the joint and the jump."""
    arm = conftest.arm("ur5")
    q = arm.random_q(8)
    T0 = arm.fk(q)
    flip = pin.SE3(pin.exp3(np.array([math.pi / 2, 0.0, 0.0])), np.zeros(3))
    poses = [T0 if k <= 10 else T0 * flip for k in range(20)]
    planned = arm.solve_path(poses, q, max_joint_step=0.2, plan="global")
    bad = np.flatnonzero(~planned.success)
    assert bad.tolist() == [11]
    assert planned.status[11] == Status.DISCONTINUOUS.value
    assert "every path breaks here" in planned[11].reason and "rad" in planned[11].reason


def test_the_first_step_honours_q0():
    arm = conftest.arm("ur5")
    q = arm.random_q(9)
    poses = _spun(arm, q, 0.2, 10)
    other = [r.q for r in arm.solve_all(poses[0], q0=q) if r.success][-1]  # another branch
    planned = arm.solve_path(poses, other, max_joint_step=0.3, plan="global")
    assert planned.success.all()
    assert np.abs(planned.q[0] - other).max() <= 0.3


def test_plans_need_a_closed_form_and_a_known_plan():
    panda = conftest.arm("panda")
    T = panda.fk(panda.middle)
    with pytest.raises(armik.InputError, match="plan='global' needs every solution"):
        panda.solve_path([T, T], panda.middle, plan="global")
    with pytest.raises(armik.InputError, match="plan must be"):
        panda.solve_path([T, T], panda.middle, plan="best")
