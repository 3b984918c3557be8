"""plan="global" on arms with a joint without limits (the Kinova's continuous joints, a UR5
given an unlimited base): planned, never a silent jump; and the plan's last check against
``max_joint_step``, which holds whatever the dynamic programming returns."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.kernel.ladder import _turn_range
from armik.solve import ladder
from armik.status import Status

from .. import conftest

STEP = 0.3  # rad: max_joint_step of every path here
EDGE = 1e-9  # rad: a step this far over the bound is on it


def _brief_path(arm: armik.Arm, seed: int) -> list[pin.SE3]:
    """The tool spun one turn about its z axis while it moves 4 mm a waypoint (40)."""
    T0 = arm.fk(arm.random_q(seed))
    return [
        T0 * pin.SE3(pin.exp3(np.array([0, 0, 2 * math.pi * k / 39])), np.array([0.004 * k, 0, 0]))
        for k in range(40)
    ]


def _fk(arm: armik.Arm, q: np.ndarray) -> pin.SE3:
    """The tip's placement by Pinocchio, the joint values written into its configuration
    here (a continuous joint as its cosine and sine), not through armik's FK."""
    model = arm.model
    qp = pin.neutral(model)
    for name, value in zip(arm.joint_names, q):
        joint = model.joints[model.getJointId(name)]
        if joint.nq == 2:
            qp[joint.idx_q : joint.idx_q + 2] = math.cos(value), math.sin(value)
        else:
            qp[joint.idx_q] = value
    data = model.createData()
    pin.framesForwardKinematics(model, data, qp)
    return arm.kinematics.T_base_world * data.oMf[arm.kinematics.tip_frame_id]


def _assert_honest(arm: armik.Arm, poses, planned, q0: np.ndarray | None) -> None:
    """Every success on its pose by Pinocchio's FK and within the limits, and within STEP of
    the answer the path went on from (a success or a jump before it; q0 for the first)."""
    prev = q0
    for i, T in enumerate(poses):
        q = planned.q[i]
        if planned.success[i]:
            err = pin.log6(T.actInv(_fk(arm, q))).vector
            assert np.linalg.norm(err) <= 1e-6, (i, err)
            assert ((q >= arm.lower - EDGE) & (q <= arm.upper + EDGE)).all(), (i, q)
            if prev is not None:
                moved = np.abs(q - prev)
                assert moved.max() <= STEP + EDGE, f"a silent jump of {moved.max():.3g} at {i}"
        if planned.success[i] or planned.status[i] == Status.DISCONTINUOUS.value:
            prev = q


def _breaks(arm: armik.Arm, poses) -> list[int]:
    """The waypoints where every path over the ``solve_all`` answers breaks, by brute force:
    the answers reached within STEP from those reached at the waypoint before (a free joint
    by its nearest turn, a limited one as given: the Kinova's limits span less than 2 pi)."""
    free = ~(np.isfinite(arm.lower) & np.isfinite(arm.upper))

    def gap(x, y):
        d = y - x
        d[free] = (d[free] + math.pi) % (2 * math.pi) - math.pi
        return np.abs(d).max()

    answers = [[np.asarray(r.q) for r in arm.solve_all(T) if r.success] for T in poses]
    reached, out = None, []
    for i, here in enumerate(answers):
        if not here:
            continue
        now = (
            here
            if reached is None
            else [y for y in here if any(gap(x, y) <= STEP for x in reached)]
        )
        if not now:
            out.append(i)
            now = here
        reached = now
    return out


def test_a_continuous_joint_arm_is_planned_and_breaks_only_where_every_path_does():
    """The Kinova (joints 1, 4 and 6 continuous): before, no first state was made (the turn
    range of a joint without limits was numba's floor of inf), so no plan was made and every
    waypoint took its own first answer, jumps of 1 to 5 rad reported as successes. Now each
    success is a step within the bound, and the waypoints flagged are those a brute force
    over every answer finds."""
    arm = conftest.arm("kinova")
    poses = _brief_path(arm, 0)
    planned = arm.solve_path(poses, None, max_joint_step=STEP, plan="global")
    _assert_honest(arm, poses, planned, None)
    flagged = np.flatnonzero(planned.status == Status.DISCONTINUOUS.value).tolist()
    assert flagged == _breaks(arm, poses)
    assert planned.success.sum() > 20
    for i in flagged:  # every path, or every one since the plan's last break
        reason = planned[i].reason
        assert "every path breaks here" in reason or "without a jump breaks here" in reason


def test_an_unlimited_base_on_a_ur5_is_planned_end_to_end():
    arm = conftest.arm("ur5").with_limits({"shoulder_pan_joint": (-math.inf, math.inf)})
    poses = _brief_path(arm, 0)
    planned = arm.solve_path(poses, None, max_joint_step=STEP, plan="global")
    assert planned.success.all()
    _assert_honest(arm, poses, planned, None)


@pytest.mark.parametrize("from_q0", [True, False])
def test_a_continuous_joint_turns_on_past_two_turns(from_q0):
    """Joint 6 of the Kinova turned three times (18.85 rad) in 130 waypoints: its turn is
    not bounded by the -2 .. 2 a limited joint's state holds."""
    arm = conftest.arm("kinova")
    q = arm.random_q(1)
    T0 = arm.fk(q)
    turned = q.copy()
    turned[5] += 0.1
    xi = pin.log6(T0.actInv(arm.fk(turned))).vector / 0.1  # joint 6's screw in the tip frame
    poses = [T0 * pin.exp6(xi * 6 * math.pi * k / 129) for k in range(130)]
    q0 = q if from_q0 else None
    planned = arm.solve_path(poses, q0, max_joint_step=STEP, plan="global")
    assert planned.success.all()
    _assert_honest(arm, poses, planned, q0)
    assert abs(planned.q[-1, 5] - planned.q[0, 5]) == pytest.approx(6 * math.pi, abs=1e-6)


def test_the_turns_of_a_joint_without_limits_are_finite():
    inf = math.inf
    assert _turn_range(0.3, -inf, inf, True) == (0, 0)  # free: its rung's own value
    assert _turn_range(0.3, -inf, 1.0, True) == (-2, 0)  # limited on one side
    assert _turn_range(0.3, -1.0, inf, True) == (0, 2)
    assert _turn_range(0.3, -1.0, 1.0, True) == (0, 0)
    first, last = _turn_range(0.3, 20.0, inf, True)  # no turn of it within the limits
    assert last < first


def test_a_broken_plan_is_never_a_silent_jump(monkeypatch):
    """The dynamic programming replaced by one that takes each waypoint's first answer, as
    the old plan did on a continuous joint: the last check against max_joint_step reports
    every step over it ``discontinuous``, naming the joint and the move."""
    arm = conftest.arm("kinova")
    poses = _brief_path(arm, 0)

    def first_answers(B, offs, q0, has_q0, lo, hi, periodic, step, forbidden, node, weight):
        n, d = len(offs) - 1, B.shape[1]
        rung = np.where(offs[1:] > offs[:-1], offs[:-1], -1)
        Q = np.full((n, d), np.nan)
        Q[rung >= 0] = B[rung[rung >= 0]]
        no = np.zeros(n, dtype=bool)
        return rung, Q, no, no.copy(), np.full(n, -1), np.zeros(n)

    monkeypatch.setattr(ladder.kernel, "plan", first_answers)
    for q0 in (None, arm.random_q(5)):
        planned = arm.solve_path(poses, q0, max_joint_step=STEP, plan="global")
        _assert_honest(arm, poses, planned, q0)
        over = [i for i in range(len(planned)) if "over the bound" in planned.reason(i)]
        assert over and all(planned.status[i] == Status.DISCONTINUOUS.value for i in over)
        assert "rad from" in planned.reason(over[0])


def test_a_posture_plan_jumps_onto_the_turns_it_scored():
    """The Kinova's tool spun a turn where part of the spin is out of reach: the plan breaks
    after the gap. A posture's plan scored each rung there with its continuous joints at
    their best turns, so the answers after the jump take those turns (the same poses), and
    its summed score is no worse than the least-motion plan's over the same waypoints."""
    arm = conftest.arm("kinova")
    ref, weights = arm.random_q(5), np.linspace(0.5, 2.0, arm.dof)
    q = arm.random_q(41)
    T0 = arm.fk(q)
    poses = [
        T0 * pin.SE3(pin.exp3(np.array([0, 0, 2 * math.pi * k / 29])), np.zeros(3))
        for k in range(30)
    ]
    posture = armik.Posture(ref, weights)
    planned = arm.solve_path(poses, q, max_joint_step=STEP, plan="global", prefer=posture)
    plain = arm.solve_path(poses, q, max_joint_step=STEP, plan="global")
    assert (planned.status == Status.DISCONTINUOUS).any()  # the case: a jump after a gap
    assert np.array_equal(planned.success, plain.success)

    def cost(Q):
        return float((((Q - ref) ** 2) @ weights).sum())

    ok = planned.success
    assert np.allclose(planned.score[ok], ((planned.q[ok] - ref) ** 2) @ weights)
    assert cost(planned.q[ok]) <= cost(plain.q[ok]) + 1e-9
    for i in np.flatnonzero(ok):
        assert np.abs(pin.log6(poses[i].actInv(arm.fk(planned.q[i]))).vector).max() <= 1e-6
    last = None
    for i in range(len(planned)):  # within the step of the answer the path went on from
        if planned.success[i] and last is not None:
            assert np.abs(planned.q[i] - last).max() <= STEP + EDGE
        if planned.success[i] or planned.status[i] == Status.DISCONTINUOUS:
            last = planned.q[i]


def test_a_scored_plan_without_any_answer_is_every_row_s_failure():
    """No waypoint of the Kinova's path has an answer (out of reach): a plan with a score
    that a turn changes gives each row its own failure."""
    arm = conftest.arm("kinova")
    T0 = arm.fk(arm.random_q(3))
    far = [pin.SE3(T0.rotation, T0.translation + [4.0 + 0.01 * k, 0, 0]) for k in range(3)]
    planned = arm.solve_path(far, None, max_joint_step=STEP, plan="global", prefer="nearest")
    assert not planned.success.any()
    assert all(s == "unreachable" for s in planned.status)
