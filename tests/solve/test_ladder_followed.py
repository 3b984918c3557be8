"""plan="global" where the rungs are not every solution (an SRS arm's swivel, a numeric
solver's tracks): the followed path's answers are rungs, so the plan breaks nowhere
following goes through, and says its breaks are among the answers found."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

import armik

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


def test_a_plan_with_collisions_follows_as_following_does():
    """The Panda along a line past a sphere, its own links checked too (margin 1 cm): a
    followed path slides a colliding answer clear near the previous one and goes through
    waypoint 5; the plan's own followed path, whose answers are its rungs, did not slide,
    and the plan broke there. It now follows as ``plan="follow"`` does."""
    panda = conftest.arm("panda")
    q = panda.random_q(424)
    T0 = panda.fk(q)
    d = np.array([0.16285073, -0.18298902, -0.96953322])
    poses = [pin.SE3(T0.rotation, T0.translation + d * 0.01 * k) for k in range(12)]
    scene = [
        armik.Sphere(0.08, (0.1232466, -0.23728116, 0.48909041)),
        armik.HalfSpace((0, 0, 1), -0.05),
    ]
    kw = {"obstacles": scene, "self_collision": True, "margin": 0.01}
    kw |= {"iteration_budget": 3000, "seed": 0}  # deterministic, not timed
    followed = panda.solve_path(poses, q, max_joint_step=0.3, **kw)
    planned = panda.solve_path(poses, q, max_joint_step=0.3, plan="global", **kw)
    assert followed.success[5], followed.summary()
    assert not (followed.success & ~planned.success).any(), planned.summary()
    _verified(panda, poses, q, planned, 0.3)
    for x in planned.q[planned.success]:
        assert panda.min_distance(x, obstacles=scene, self_collision=True)[0] >= 0.01 - 1e-9


def test_a_spin_sweep_s_plan_goes_where_following_goes():
    """The UR5's tool free to spin about its x axis (``bounds``), along a line: the rungs
    are the ``spin`` sweep's answers at spins sampled over the bound, which may miss the
    one following takes. Following (by ``dls``) goes through every waypoint; the plan over
    the sweep's answers alone broke at one. With the followed answers among its rungs it
    goes where following goes."""
    ur5 = conftest.arm("ur5")
    q = ur5.random_q(9)
    T = ur5.fk(q)
    d = np.array([0.005, 0.0, 0.003])
    poses = [pin.SE3(T.rotation, T.translation + d * k) for k in range(30)]
    kw = {"bounds": (0, 0, 0, math.inf, 0, 0), "iteration_budget": 3000, "seed": 0}
    followed = ur5.solve_path(poses, q, max_joint_step=0.3, **kw)
    planned = ur5.solve_path(poses, q, max_joint_step=0.3, plan="global", **kw)
    assert followed.success.all(), followed.summary()
    assert planned.success.all() and planned.solver == "spin", planned.summary()
    prev = q
    for pose, x in zip(poses, planned.q):
        F = ur5.fk(x)
        assert np.linalg.norm(F.translation - pose.translation) <= 1e-6
        w = pin.log3(pose.rotation.T @ F.rotation)  # about x only
        assert abs(w[1]) <= 1e-6 and abs(w[2]) <= 1e-6
        assert ur5.within_limits(x) and np.abs(x - prev).max() <= 0.3 + 1e-9
        prev = x


def test_a_7r_waypoint_every_branch_of_which_collides_says_collision():
    # the Panda's rungs are its swept branches: where none was clear, the waypoint took the
    # first swept failure, "joint_limits" with q outside the limits, where solve, solve_all
    # and plan="follow" all say the tool is in the ball (or the hand in the base)
    arm = conftest.arm("panda")
    T_ball = arm.fk(arm.random_q(2))
    ball = {"obstacles": [armik.Sphere(0.03, tuple(T_ball.translation))]}
    T_self = arm.fk(arm.random_q(0))  # the hand inside link 0
    for T, options in ((T_ball, ball), (T_self, {"self_collision": True})):
        every = arm.solve_all(T, **options)
        assert {r.status for r in every} == {"collision"}
        for q0 in (every[0].q, None):
            r = arm.solve_path([T], q0, plan="global", **options)[0]
            assert r.status == "collision" and not r.success, r.reason
            assert arm.within_limits(r.q)
