"""A 2 pi turn of an answer keeps the pose but not a joint's value: the preferences, the
global path and a followed path turn only what the request allows (``solve.turning``): no
held joint turns, and no turned answer breaks a constraint of the user's own."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.base import Check, Constraint
from armik.status import Status


class PanNonNegative(Constraint):
    """The UR5's shoulder pan at 0 or above: a check that reads a joint's value."""

    def check(self, arm, Q):
        return Check(Q[:, 0] >= 0.0, Status.JOINT_LIMITS, lambda i: f"pan {Q[i, 0]:.3f} < 0")


@pytest.fixture(scope="module")
def ur5():
    return armik.load("ur5")


def _pose(arm, seed):
    q = arm.random_q(np.random.default_rng(seed))
    q[0] = abs(q[0]) % np.pi + 0.5  # a pan in (0.5, 3.7): its turn by -2 pi is below 0
    return q, arm.fk(q)


# a preference toward -3 on every joint: without the constraints, the pan turns by -2 pi
TOWARD = (
    "nearest",
    armik.Posture(np.full(6, -3.0)),
    lambda q: float((q[0] + 3.0) ** 2),
)


@pytest.mark.parametrize("prefer", TOWARD, ids=["nearest", "posture", "callable"])
def test_a_preference_does_not_turn_a_held_joint(ur5, prefer):
    q, T = _pose(ur5, 1)
    q0 = np.full(6, -3.0)
    for spelled in ({"hold": {"shoulder_pan_joint": float(q[0])}},
                    {"constraints": [armik.Hold("shoulder_pan_joint", float(q[0]))]}):  # fmt: skip
        r = ur5.solve(T, q0=q0, prefer=prefer, **spelled)
        assert r.success
        assert r.q[0] == pytest.approx(q[0], abs=1e-9)


@pytest.mark.parametrize("prefer", TOWARD[1:], ids=["posture", "callable"])
def test_a_preference_does_not_turn_past_a_users_constraint(ur5, prefer):
    """From q0 = 0 the closed form's answers keep their pan; the score pulls it to -3."""
    _, T = _pose(ur5, 1)
    c = PanNonNegative()
    q0 = np.zeros(6)
    r = ur5.solve(T, q0=q0, constraints=[c], prefer=prefer)
    assert r.success and r.q[0] >= 0.0
    every = ur5.solve_all(T, q0=q0, constraints=[c], prefer=prefer)
    assert any(x.success for x in every)
    assert all(x.q[0] >= 0.0 for x in every if x.success)
    b = ur5.solve_batch([T, T], q0=q0, constraints=[c], prefer=prefer)
    assert b.success.all() and (b.q[:, 0] >= 0.0).all()


@pytest.mark.parametrize("prefer", TOWARD[1:], ids=["posture", "callable"])
def test_the_same_preference_turns_where_nothing_forbids_it(ur5, prefer):
    """The test above could fail: without the constraint, the pan does turn below 0."""
    _, T = _pose(ur5, 1)
    r = ur5.solve(T, q0=np.zeros(6), prefer=prefer)
    assert r.success and r.q[0] < 0.0


def _line(arm, seed):
    _, T = _pose(arm, seed)
    return [pin.SE3(T.rotation, T.translation + [0.0, 0.01 * k, 0.0]) for k in range(6)]


@pytest.mark.parametrize("plan", ["follow", "global"])
@pytest.mark.parametrize("prefer", [None, TOWARD[1]], ids=["motion", "posture"])
def test_a_path_does_not_turn_past_a_users_constraint(ur5, plan, prefer):
    out = ur5.solve_path(
        _line(ur5, 1), None, constraints=[PanNonNegative()], plan=plan, prefer=prefer
    )
    assert out.success.all()
    assert (out.q[:, 0] >= 0.0).all()


def test_a_global_path_turns_where_nothing_forbids_it(ur5):
    out = ur5.solve_path(_line(ur5, 1), None, plan="global", prefer=TOWARD[1])
    assert out.success.all() and (out.q[:, 0] < 0.0).all()


class Anything(Constraint):
    """A user's check every configuration passes."""

    def check(self, arm, Q):
        return Check(np.ones(len(Q), dtype=bool), Status.JOINT_LIMITS, lambda i: "never")


def test_a_global_path_with_a_check_no_turn_fails_plans_as_without_it(ur5, monkeypatch):
    """Each turn a rung of its own only where a turn fails a check: a check every turn
    passes leaves the plan the one without it."""
    from armik.solve import ladder

    plain = ur5.solve_path(_line(ur5, 1), None, plan="global")
    expanded = []
    turns = ladder._turns
    monkeypatch.setattr(ladder, "_turns", lambda *a: expanded.append(a) or turns(*a))
    out = ur5.solve_path(_line(ur5, 1), None, plan="global", constraints=[Anything()])
    assert not expanded
    assert out.success.all() and np.array_equal(out.q, plain.q)
    # the count could fail: a check some turn fails makes each turn a rung
    ur5.solve_path(_line(ur5, 1), None, plan="global", constraints=[PanNonNegative()])
    assert expanded


def test_a_path_row_a_plan_turned_past_a_constraint_is_refused_by_it(ur5):
    """The last guard: a success whose answer breaks a check becomes that check's failure."""
    from armik.solve.turning import Turning, refuse_broken

    out = ur5.solve_path(_line(ur5, 1), None, constraints=[PanNonNegative()])
    assert out.success.all()
    out.q[2, 0] -= 2 * np.pi
    refuse_broken(ur5.kinematics, out, Turning(checks=(PanNonNegative(),)))
    assert not out.success[2] and out.success[[0, 1, 3, 4, 5]].all()
    assert out.status[2] == Status.JOINT_LIMITS.value
    assert "pan" in out.reasons[2]


def test_an_answer_a_check_refuses_stands_at_a_turn_that_passes(ur5):
    """From q0 = -3 the closed form turns the pan toward q0, below 0: the verdict takes the
    turn of it that passes the check (the same pose) rather than refuse the pose."""
    _, T = _pose(ur5, 2)
    q0 = np.full(6, -3.0)
    c = PanNonNegative()
    bare = ur5.solve(T, q0=q0)
    assert bare.success and bare.q[0] < 0.0  # the test below could fail
    r = ur5.solve(T, q0=q0, constraints=[c])
    assert r.success and r.q[0] >= 0.0
    assert np.allclose(ur5.fk(r.q).homogeneous, T.homogeneous, atol=1e-9)
    every = [x for x in ur5.solve_all(T, q0=q0, constraints=[c]) if x.success]
    assert every and all(x.q[0] >= 0.0 for x in every)
    b = ur5.solve_batch([T, T], q0=q0, constraints=[c])
    assert b.success.all() and (b.q[:, 0] >= 0.0).all()


class FarFromEverything(Constraint):
    """A check of the links' placements that every answer fails (as a collision check can),
    counting the answers it is asked about."""

    pose_only = True

    def __init__(self):
        self.asked = 0

    def check(self, arm, Q):
        self.asked += len(Q)
        return Check(np.zeros(len(Q), bool), Status.COLLISION, lambda i: "too near")


def test_a_check_of_the_pose_alone_is_not_tried_at_the_answers_turns(ur5):
    """A turn by 2 pi leaves every link where it was: an answer such a check refuses is
    refused as it is, its turns (up to 255 of them on the UR5) not checked."""
    _, T = _pose(ur5, 2)
    c = FarFromEverything()
    r = ur5.solve(T, constraints=[c])
    assert not r.success and r.status is Status.COLLISION
    found = len(ur5.solve_all(T))
    assert c.asked <= 2 * found  # each answer once or twice, never its turns


class RollWindow(Constraint):
    """The SCARA's tool roll, a joint without limits, within [0, 1] rad."""

    def check(self, arm, Q):
        ok = (Q[:, 3] >= 0.0) & (Q[:, 3] <= 1.0)
        return Check(ok, Status.JOINT_LIMITS, lambda i: "roll outside [0, 1]")


def test_a_joint_without_limits_is_turned_to_pass_a_check():
    """Seeded a turn away on a continuous joint, the answer stands at the turn that passes,
    as a joint with limits wider than a turn does, on every route."""
    scara = armik.load("scara")
    assert scara.lower[3] == -np.inf and scara.upper[3] == np.inf
    q = np.array([0.4, 0.8, 0.1, 0.5])
    T = scara.fk(q)
    q0 = q.copy()
    q0[3] -= 2 * np.pi
    c = RollWindow()
    r = scara.solve(T, q0=q0, constraints=[c])
    assert r.success and r.q[3] == pytest.approx(0.5, abs=1e-6)
    assert any(x.success for x in scara.solve_all(T, q0=q0, constraints=[c]))
    assert scara.solve_batch([T], q0=q0, constraints=[c]).success.all()


class Window(Constraint):
    def __init__(self, j, lo, hi):
        self.j, self.lo, self.hi = j, lo, hi

    def check(self, arm, Q):
        ok = (Q[:, self.j] >= self.lo) & (Q[:, self.j] <= self.hi)
        return Check(ok, Status.JOINT_LIMITS, lambda i: "outside the window")


def test_two_answers_2_pi_apart_are_not_turned_into_one():
    """solve_all's numeric answers two of which lie 2 pi apart, both refused by a check:
    one turn of them stands, the other stays refused; no configuration is listed twice."""
    ur5 = armik.load("ur5")
    q = ur5.random_q(2)
    T = ur5.fk(q)
    checks = [Window(5, -1.0, 1.0), Window(0, -1.0, 6.3)]
    found = ur5.solve_all(T, q0=q, solver="dls", max_solutions=16, constraints=checks)
    ok = [x.q for x in found if x.success]
    assert ok
    for i in range(len(ok)):
        for j in range(i):
            assert np.abs(ok[i] - ok[j]).max() >= 1e-4


class PanWindow(Constraint):
    """The UR5's pan within 0.01 rad of a value: only one turn of it passes."""

    def __init__(self, pan: float):
        self.pan = pan

    def check(self, arm, Q):
        ok = np.abs(Q[:, 0] - self.pan) <= 0.01
        return Check(ok, Status.JOINT_LIMITS, lambda i: f"pan {Q[i, 0]:.3f} off the window")


@pytest.mark.parametrize(
    "prefer", ["nearest", "manipulability", TOWARD[1]], ids=["nearest", "manipulability", "posture"]
)
def test_a_followed_paths_preference_does_not_turn_past_a_users_constraint(ur5, prefer):
    """The preference's candidates (every branch at a waypoint) are turned next to the
    previous answer only as far as the check allows: a pan of 4.49 was turned to -1.79."""
    q = ur5.random_q(np.random.default_rng(0))
    q[0] = 4.49
    T = ur5.fk(q)
    out = ur5.solve_path([T, T], None, constraints=[PanWindow(4.49)], prefer=prefer)
    assert out.success.all(), out.reasons
    assert np.allclose(out.q[:, 0], 4.49, atol=0.01)


def test_a_followed_paths_preference_moves_no_held_joint_along_the_self_motion():
    """On the Panda the preference moves the followed answer along its self-motion; a held
    joint stays out of that motion (it moved and every waypoint failed its hold)."""
    arm = armik.load("panda")
    q = arm.random_q(np.random.default_rng(2))
    T = arm.fk(q)
    line = [pin.SE3(T.rotation, T.translation + [0.0, 0.005 * k, 0.0]) for k in range(4)]
    for joint in (0, 6):
        hold = {arm.joint_names[joint]: float(q[joint])}
        out = arm.solve_path(line, None, hold=hold, prefer="manipulability")
        assert out.success.all(), out.reasons
        assert np.allclose(out.q[:, joint], q[joint], atol=1e-9)


@pytest.mark.parametrize("name, joint", [("scara", 3), ("kinova", 0)])
def test_a_preference_turns_a_continuous_joint_toward_it(name, joint):
    """A joint without limits turns by any whole turn: a posture 4 pi away on it is met (the
    answer stayed 4 pi off, its score 158); a callable score turns it up to two turns."""
    arm = armik.load(name)
    q = arm.random_q(np.random.default_rng(4))
    T = arm.fk(q)
    q_ref = q.copy()
    q_ref[joint] += 4 * np.pi
    for prefer in (armik.Posture(q_ref), lambda x: float(np.sum((x - q_ref) ** 2))):
        r = arm.solve(T, q0=q, prefer=prefer)
        assert r.success and r.q[joint] == pytest.approx(q_ref[joint], abs=1e-6)
    b = arm.solve_batch([T], q0=q, prefer=armik.Posture(q_ref))
    assert b.success[0] and b.q[0, joint] == pytest.approx(q_ref[joint], abs=1e-6)
