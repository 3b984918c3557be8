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
from armik.solve import rungs
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
    rungs = [[np.asarray(r.q) for r in arm.solve_all(T, q0=q0) if r.success] for T in poses]
    lo, hi = arm.lower, arm.upper
    periodic = ~np.array(arm.kinematics._limit_lists[2], dtype=bool)
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


@pytest.mark.parametrize("prefer", ["limits", "manipulability"])
def test_a_preferred_plan_is_the_brute_force_best_score_among_continuous_paths(prefer):
    """With ``prefer=``, the plan is the continuous path (every step within the bound) of
    the least summed score, the motion breaking ties (``ladder.TIE``): equal to a brute
    force over every branch at every turn within the limits on a 3-waypoint IRB 120 path
    from any start (scored against mid-limits); the far-from-limits plan beats the least
    motion's."""
    from armik.problem.scores import parse_score
    from armik.solve.ladder import TIE

    arm = conftest.arm("abb_irb120")
    rng = np.random.default_rng(37)
    T0 = arm.fk(arm.random_q(rng))
    poses = [
        pin.SE3(T0.rotation, T0.translation + np.array([0.0, 0.004 * k, 0.0])) for k in range(3)
    ]
    score = parse_score(prefer)
    planned = arm.solve_path(poses, None, max_joint_step=0.4, plan="global", prefer=prefer)
    assert planned.success.all()

    def summed(path) -> float:
        return sum(score(arm.kinematics, q, arm.middle) for q in path)

    def cost(path) -> float:
        steps = np.diff(path, axis=0)
        if (np.abs(steps) > 0.4 + 1e-12).any():
            return math.inf
        return summed(path) + TIE * float(np.linalg.norm(steps, axis=1).sum())

    lo, hi = arm.lower, arm.upper
    variants = []
    for T in poses:
        found = []
        for r in arm.solve_all(T):
            if not r.success:
                continue
            turns = [
                [
                    v + 2 * math.pi * k
                    for k in range(-2, 3)
                    if lo[j] - 1e-12 <= v + 2 * math.pi * k <= hi[j] + 1e-12
                ]
                for j, v in enumerate(np.asarray(r.q).tolist())
            ]
            found += [np.array(c) for c in itertools.product(*turns)]
        variants.append(found)
    best = min(cost(np.array(choice)) for choice in itertools.product(*variants))
    assert math.isfinite(best) and cost(planned.q) == pytest.approx(best, abs=1e-9)
    least_motion = arm.solve_path(poses, None, max_joint_step=0.4, plan="global")
    if prefer == "limits":  # another branch lies farther from the limits
        assert summed(planned.q) < summed(least_motion.q) - 0.1


def test_a_preference_on_an_arm_with_continuous_joints():
    """The Kinova's continuous joints have no turns to score apart: the plan still turns
    them next to the previous rung (no step above the bound), each waypoint scored."""
    arm = conftest.arm("kinova")
    q = arm.random_q(3)
    T0 = arm.fk(q)
    poses = [pin.SE3(T0.rotation, T0.translation + [0.0, 0.004 * k, 0.0]) for k in range(8)]
    budget = {"iteration_budget": 2000, "seed": 0}  # deterministic, not timed
    planned = arm.solve_path(
        poses, q, max_joint_step=0.3, plan="global", prefer="nearest", **budget
    )
    assert planned.success.all()
    assert np.abs(np.diff(np.vstack([q, planned.q]), axis=0)).max() <= 0.3 + 1e-9
    assert np.allclose(planned.score, np.linalg.norm(planned.q - q, axis=1), atol=1e-9)


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


@pytest.mark.parametrize("robot", ["panda", "xarm7"])
def test_a_break_among_answers_found_claims_no_more(robot):
    """A quarter turn of the tool between two waypoints of a 7-joint arm: the plan over the
    swept closed form's samples (the Panda) or the numeric solver's tracks (the xArm7)
    flags the waypoint, naming the joint, and says the break is among the answers found,
    not that every path breaks (it has not seen every solution)."""
    arm = conftest.arm(robot)
    q = arm.random_q(8)
    T0 = arm.fk(q)
    turn = pin.SE3(pin.exp3(np.array([0.0, 0.0, math.pi / 2])), np.zeros(3))
    poses = [T0 if k <= 10 else T0 * turn for k in range(20)]
    planned = arm.solve_path(
        poses, q, max_joint_step=0.2, plan="global", iteration_budget=3000, seed=0
    )
    assert np.flatnonzero(~planned.success).tolist() == [11]
    reason = planned[11].reason
    assert "every path through the answers found breaks here" in reason
    assert "every path breaks here" not in reason and "joint7 by" in reason


def test_the_first_step_honours_q0():
    arm = conftest.arm("ur5")
    q = arm.random_q(9)
    poses = _spun(arm, q, 0.2, 10)
    other = [r.q for r in arm.solve_all(poses[0], q0=q) if r.success][-1]  # another branch
    planned = arm.solve_path(poses, other, max_joint_step=0.3, plan="global")
    assert planned.success.all()
    assert np.abs(planned.q[0] - other).max() <= 0.3


def test_an_empty_path_is_an_empty_plan():
    arm = conftest.arm("ur5")
    assert len(arm.solve_path(np.zeros((0, 4, 4)), arm.middle, plan="global")) == 0


def test_a_plan_must_be_known():
    xarm = conftest.arm("xarm7")
    T = xarm.fk(xarm.middle)
    with pytest.raises(armik.InputError, match="plan must be"):
        xarm.solve_path([T, T], xarm.middle, plan="best")


def test_a_numeric_arm_plans_over_tracked_answers():
    """The xArm7 (no closed form, none with a joint held): rungs tracked along the line
    from the followed path, from solve_all's answers at the start and where following
    breaks, forward and backward. On a line where following from q flags a jump of joint
    7, the plan from the same q goes through: every waypoint verified by Pinocchio's FK,
    no step above the bound, from q0 within it too."""
    xarm = conftest.arm("xarm7")
    rng = np.random.default_rng(3)
    for _ in range(12):  # the 12th of these seeded lines: following breaks at waypoint 36
        q = xarm.random_q(rng)
        T0 = xarm.fk(q)
        d = rng.normal(size=3)
        d *= 0.005 / np.linalg.norm(d)
    poses = [pin.SE3(T0.rotation, T0.translation + k * d) for k in range(100)]
    budget = {"iteration_budget": 3000, "seed": 0}  # deterministic, not timed
    followed = xarm.solve_path(poses, q, max_joint_step=0.3, **budget)
    assert not followed.success.all() and "discontinuous" in set(followed.status.tolist())
    planned = xarm.solve_path(poses, q, max_joint_step=0.3, plan="global", **budget)
    assert planned.success.all()
    steps = np.abs(np.diff(np.vstack([q, planned.q]), axis=0))
    assert steps.max() <= 0.3 + 1e-9
    for T, x in zip(poses, planned.q):
        assert np.abs(pin.log6(T.actInv(xarm.fk(x))).vector).max() <= 1e-6


def test_a_7r_plan_samples_joint_7_and_moves_no_more_than_following():
    """The Panda: rungs at joint 7 values about the followed path's and on a grid, every
    branch of the swept closed form at each, and the followed answers themselves; the plan
    is verified, within the step bound, and moves no more than following."""
    panda = conftest.arm("panda")
    rng = np.random.default_rng(5)
    for _ in range(5):  # the fifth line drawn: one the Panda follows end to end
        q = panda.random_q(rng)
        T = panda.fk(q)
        d = rng.normal(size=3)
        d *= 0.005 / np.linalg.norm(d)
    poses = [pin.SE3(T.rotation, T.translation + k * d) for k in range(40)]
    follow = panda.solve_path(poses, q, max_joint_step=0.3)
    planned = panda.solve_path(poses, q, max_joint_step=0.3, plan="global")
    assert follow.success.all() and planned.success.all(), planned.summary()
    assert planned.solver == "swept"
    for pose, x in zip(poses, planned.q):
        err = pin.log6(pose.actInv(panda.fk(x))).vector
        assert np.abs(err).max() <= 1e-6 and panda.within_limits(x)
    steps = np.abs(np.diff(np.vstack([q, planned.q]), axis=0))
    assert steps.max() <= 0.3 + 1e-12
    assert motion(q, planned.q) <= motion(q, follow.q) + 1e-9
    assert len({round(x, 6) for x in planned.q[:, 6]}) > 1  # joint 7 moves with the path


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_7r_plan_by_a_named_numeric_solver_tracks_its_answers(solver, monkeypatch):
    """``solver="dls"`` on the Panda: the rungs are that solver's answers tracked along the
    path (``rungs.tracked``), not the swept closed form's "auto" would take, and the plan
    is labelled with it; verified, within the step bound."""
    panda = conftest.arm("panda")
    rng = np.random.default_rng(5)
    q = panda.random_q(rng)
    T = panda.fk(q)
    poses = [pin.SE3(T.rotation, T.translation + [0.005 * k, 0.0, 0.0]) for k in range(6)]
    asked = []
    tracked = rungs.tracked

    def spy(arm, batch, q_start, name, followed, request):
        asked.append(name)
        return tracked(arm, batch, q_start, name, followed, request)

    def unswept(*args):
        raise AssertionError("the sweep ran for a named numeric solver")

    monkeypatch.setattr(rungs, "tracked", spy)
    monkeypatch.setattr(rungs, "held", unswept)
    planned = panda.solve_path(poses, q, max_joint_step=0.3, plan="global", solver=solver)
    assert asked == [solver] and planned.solver == solver, planned.summary()
    assert planned.success.all(), planned.summary()
    for pose, x in zip(poses, planned.q):
        assert np.abs(pin.log6(pose.actInv(panda.fk(x))).vector).max() <= 1e-6
    assert np.abs(np.diff(np.vstack([q, planned.q]), axis=0)).max() <= 0.3 + 1e-12


def _across_the_wrist_singularity(arm):
    """Two UR5 poses whose wrist 2 goes from 0.2 to -0.2 rad with wrist 1 turned 0.1 rad:
    the pose halfway lies next to the wrist singularity, where wrist 1 swings."""
    qa = np.array([0.3, -1.2, 1.5, -1.0, 0.2, 0.4])
    qb = qa + np.array([0.0, 0.0, 0.0, 0.1, -0.4, 0.0])
    return qa, arm.fk(qa), arm.fk(qb)


def test_a_jump_hidden_between_two_waypoints_is_reported():
    """The step from qa to a solution of the second pose moves no joint by more than 0.5,
    but halfway the wrist swings: the plan refuses the step, and the same poses sampled
    65 times show the swing the check saw."""
    arm = conftest.arm("ur5")
    qa, Ta, Tb = _across_the_wrist_singularity(arm)
    near = [r.q for r in arm.solve_all(Tb, q0=qa) if r.success]
    assert min(np.abs(np.asarray(q) - qa).max() for q in near) <= 0.5  # the step rule: fine
    planned = arm.solve_path([Ta, Tb], qa, max_joint_step=0.5, plan="global")
    assert planned.success.tolist() == [True, False]
    assert planned.status[1] == Status.DISCONTINUOUS.value
    assert "every step within max_joint_step hides a jump" in planned[1].reason
    w = pin.log3(Ta.rotation.T @ Tb.rotation)
    dense = [
        pin.SE3(
            Ta.rotation @ pin.exp3(w * t), Ta.translation + t * (Tb.translation - Ta.translation)
        )
        for t in np.linspace(0.0, 1.0, 65)
    ]
    followed = arm.solve_path(dense, qa, max_joint_step=0.5)
    assert not followed.success.all()
    assert np.abs(np.diff(followed.q[:, 3])).max() > 0.5  # wrist 1 swings between samples


_HELD = {"panda_joint3": 0.2}
# (qa, qb) on the Panda with joint 3 at 0.2, no joint apart by more than 0.45: across its
# wrist's singular line (a jump with joint 3 held, none with it free), and a clean step
_ACROSS = (
    [1.6998, -0.6397, 0.2, -1.963, -1.1733, -0.0049, -1.9236],
    [2.0339, -0.3081, 0.2, -1.7935, -0.8469, -0.0175, -1.733],
)
_CLEAN = (
    [-1.9485, -1.6786, 0.2, -0.1765, 0.8444, 3.5523, -0.8728],
    [-1.7188, -1.7628, 0.2, -0.3771, 0.8897, 3.604, -0.8737],
)


def _between(Ta, Tb, n: int) -> list:
    """``n`` poses from ``Ta`` to ``Tb``: the translation along its line, the rotation along
    its geodesic (as the halfway check takes them)."""
    w = pin.log3(Ta.rotation.T @ Tb.rotation)
    return [
        pin.SE3(Ta.rotation @ pin.exp3(w * t), (1 - t) * Ta.translation + t * Tb.translation)
        for t in np.linspace(0.0, 1.0, n)
    ]


@pytest.mark.parametrize(("ends", "continuous"), [(_ACROSS, False), (_CLEAN, True)])
def test_the_halfway_check_solves_the_held_problem(ends, continuous):
    """With a joint held (``hold=``), a step is checked halfway on the problem solved, the
    joint held: the check solved it with the joint free, so a step the held arm cannot make
    (the poses between out of its reach) was a success, and a clean one was refused where
    the free arm's nearest answer lay elsewhere. The same poses sampled 33 times, followed
    with the joint held, say which is which."""
    arm = conftest.arm("panda")
    qa, qb = np.array(ends[0]), np.array(ends[1])
    Ta, Tb = arm.fk(qa), arm.fk(qb)
    planned = arm.solve_path([Ta, Tb], qa, plan="global", hold=_HELD)
    assert planned.success.tolist() == [True, continuous]
    assert np.allclose(planned.q[planned.success, 2], 0.2, atol=1e-12)
    if not continuous:
        assert planned.status[1] == Status.DISCONTINUOUS.value
        assert "hides a jump" in planned[1].reason
    followed = arm.solve_path(_between(Ta, Tb, 33), qa, hold=_HELD)
    assert followed.success.all() == continuous


def test_a_line_through_the_inner_hole_is_a_hidden_jump():
    """Planar 2-link (links 1 and 0.8 m: a hole of 0.2 m), positions 0.21 m out at +-0.4
    rad: the elbow stays folded and joint 1 turns 0.8 rad, within the step, but the
    line between passes 0.193 m from the base, out of reach. Its closed form has no compiled
    batch: the check solves the poses halfway one by one. The same turn 1 m out is clean."""
    arm = conftest.arm("planar_2link")
    for r, ok in ((0.21, False), (1.0, True)):
        pts = np.array([[r * math.cos(0.4), s * r * math.sin(0.4), 0.0] for s in (1, -1)])
        q0 = [x.q for x in arm.solve_all(pts[0]) if x.success][0]
        planned = arm.solve_path(pts, q0, max_joint_step=1.0, plan="global")
        assert planned.success.tolist() == [True, ok]
        if not ok:
            assert "hides a jump" in planned[1].reason


def test_a_refused_step_is_dropped_and_the_path_planned_again():
    """From any start, the least motion crosses the singularity on the shoulder-front
    branches (a refused step); the plan goes round it on a shoulder-back branch."""
    arm = conftest.arm("ur5")
    qa, Ta, Tb = _across_the_wrist_singularity(arm)
    planned = arm.solve_path([Ta, Tb], None, max_joint_step=0.7, plan="global")
    assert planned.success.all()
    assert np.abs(np.diff(planned.q, axis=0)).max() <= 0.7
    assert abs(math.remainder(planned.q[0, 0] - qa[0], 2 * math.pi)) > 2.0  # the other shoulder
    for T, qi in zip([Ta, Tb], planned.q):
        assert np.allclose(arm.fk(qi).homogeneous, T.homogeneous, atol=1e-9)
    motion = float(np.linalg.norm(planned.q[1] - planned.q[0]))
    assert motion > float(np.linalg.norm([0.1, 0.4]))  # more than the refused step's


def _elbow(arm, q, radius=0.06):
    """A sphere around the elbow joint at ``q``, in the base frame."""
    arm.fk(q)
    return armik.Sphere(radius, arm.T_base_world.act(arm.data.oMi[3].translation))


def test_collisions_remove_rungs():
    """A sphere at the elbow of the plan's answer halfway up a line: with the obstacle the
    plan takes branches clear of it; from q0, inside it, the first step is a jump."""
    arm = conftest.arm("ur5")
    q = arm.random_q(3)
    T0 = arm.fk(q)
    poses = [
        pin.SE3(T0.rotation, T0.translation + np.array([0.0, 0.0, 0.01 * k])) for k in range(20)
    ]
    free = arm.solve_path(poses, None, max_joint_step=0.3, plan="global")
    ball = _elbow(arm.kinematics, free.q[10])
    assert free.success.all() and arm.in_collision(free.q[10], [ball])
    clear = arm.solve_path(poses, None, max_joint_step=0.3, plan="global", obstacles=[ball])
    assert clear.success.all()
    assert np.abs(np.diff(clear.q, axis=0)).max() <= 0.3
    assert not any(arm.in_collision(qi, [ball]) for qi in clear.q)
    assert (clear.min_distance >= 0).all()
    stuck = arm.solve_path(poses, q, max_joint_step=0.3, plan="global", obstacles=[ball])
    assert arm.in_collision(q, [ball])
    assert stuck.status[0] == Status.DISCONTINUOUS.value and "q0 (the start)" in stuck[0].reason
    assert not any(arm.in_collision(qi, [ball]) for qi in stuck.q)


def motion(q0: np.ndarray, Q: np.ndarray) -> float:
    """A path's total joint motion: the sum of its steps' Euclidean norms, from q0."""
    return float(np.linalg.norm(np.diff(np.vstack([q0, Q]), axis=0), axis=1).sum())


def test_a_spin_off_the_last_axis_is_planned_over_the_spin_sweep():
    """A free spin the last joint does not give (a tool off its axis): the rungs are the
    ``spin`` sweep's, every branch nearest over the spin; each answer holds the tool's
    position and z axis exactly."""
    arm = armik.load("ur5", tip_offset=(0.05, 0.0, 0.1))
    q = np.array([0.3, -1.2, 1.5, -1.0, 1.0, 0.4])
    T = arm.fk(q)
    poses = [pin.SE3(T.rotation, T.translation + [0.0, 0.005 * k, 0.0]) for k in range(8)]
    free = (0.0, 0.0, 0.0, 0.0, 0.0, math.inf)
    planned = arm.solve_path(poses, q, max_joint_step=0.3, plan="global", bounds=free)
    assert planned.success.all() and planned.solver == "spin", planned.summary()
    for pose, x in zip(poses, planned.q):
        M = pose.actInv(arm.fk(x))
        assert np.abs(M.translation).max() <= 1e-6
        assert np.abs(M.rotation[:, 2] - [0.0, 0.0, 1.0]).max() <= 1e-6
    assert np.abs(np.diff(np.vstack([q, planned.q]), axis=0)).max() <= 0.3 + 1e-12


class _Unclaimed:
    """A solver's spec whose one answer is ``q``, claimed not converged: the halfway check
    then measures it itself (``ladder._nearest``)."""

    run_batch = None

    def __init__(self, q) -> None:
        self.q = np.asarray(q, dtype=float)

    def run(self, arm, target, seed, opts, every):
        from armik.solvers.answers import Answers

        return Answers.of([self.q], [Status.NOT_CONVERGED], ["best found"], arm.dof)


def test_the_halfway_check_judges_an_answer_by_its_target_s_aim():
    """An answer the solver does not claim is measured as the verdict measures it: with a
    cone, on the tip's axis within the cone (taken: it was refused for the rotation beside
    the aim), with a look-at on its line of sight (refused where its rotation is the
    target's but its axis looks elsewhere: it was taken)."""
    from armik.options import Options
    from armik.solve import ladder
    from armik.solve.turning import ANY
    from armik.targets.aim import aim_of
    from armik.targets.batch import TargetBatch

    panda = conftest.model("panda")
    q = panda.random_q(np.random.default_rng(4))
    T = panda.fk(q)
    P = T.translation[None].copy()
    tilted = (T.rotation @ pin.exp3(np.array([0.25, 0.0, 0.0])))[None]
    opts = Options()
    seeds = q[None].copy()

    def nearest(R, aim):  # the halfway check's solve of pose P, R by _Unclaimed
        half = ladder._Halfway(_Unclaimed(q), opts, TargetBatch(P, R, aim), None, ANY)
        return ladder._nearest(panda, half, P, R, seeds)

    inside = aim_of((0.0, 0.0, 1.0, 0.3))
    got = nearest(tilted, inside)
    np.testing.assert_array_equal(got[0], q)  # its axis is 0.25 rad off: within 0.3
    outside = aim_of((0.0, 0.0, 1.0, 0.2))
    assert np.isnan(nearest(tilted, outside)).all()
    aside = T * np.array([0.3, 0.0, 0.0])  # a point along the tip's x axis, not its z
    look = aim_of((0.0, 0.0, 1.0, 0.0), look_at=aside)
    exact = T.rotation[None].copy()
    assert np.isnan(nearest(exact, look)).all()
    ahead = aim_of((0.0, 0.0, 1.0, 0.0), look_at=T * np.array([0.0, 0.0, 0.3]))
    got = nearest(exact, ahead)
    np.testing.assert_array_equal(got[0], q)
