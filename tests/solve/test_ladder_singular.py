"""plan="global" through a waypoint that lies exactly on a singularity: its closed form's
singular rows keep their free angle (a wrist's two in-line joints share one sum; a wrist
point on the first axis leaves that joint free) at the seed's value. Solved from the path's
start, the plan broke there ("every path breaks here") or detoured, where following went
straight through; the rows now continue the waypoints beside them
(``armik.solve.singular_rungs``)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from .. import conftest

STEP = 0.3


def _motion(q0, Q) -> float:
    """The total joint motion from ``q0`` through the rows of ``Q`` (the plan's measure)."""
    return float(np.linalg.norm(np.diff(np.vstack([q0, Q]), axis=0), axis=1).sum())


def _verified(arm, poses, q0, path) -> None:
    """Every answer reaches its pose (Pinocchio's FK) within the limits, each step within
    ``STEP`` of the one before (the first from ``q0``)."""
    prev = q0
    for pose, q in zip(poses, path.q):
        assert np.abs(pin.log6(pose.actInv(arm.fk(q))).vector).max() <= 1e-6
        assert arm.within_limits(q)
        assert np.abs(q - prev).max() <= STEP + 1e-9
        prev = q


def _through(arm, qa: np.ndarray, qb: np.ndarray, n: int = 41):
    """Poses of the joints moved straight from ``qa`` to ``qb`` in ``n`` waypoints."""
    Q = np.linspace(qa, qb, n)
    return Q, [arm.fk(q) for q in Q]


WRIST = {  # the wrist joint that crosses its singular value, and that value
    "ur5": (4, 0.0),
    "ur10": (4, 0.0),
    "abb_irb120": (4, 0.0),
    "kinova": (4, math.pi),  # its wrist lines up at joint 5 = pi
}


@pytest.mark.parametrize("name", list(WRIST))
def test_a_waypoint_on_a_wrist_singularity_continues_its_neighbours(name):
    """Wrist 2 from 0.2 to -0.2 rad over 41 waypoints, exactly singular at waypoint 20,
    wrist 1 and 3 moving too: the UR5's plan broke there ("the smallest possible jump
    moves wrist_1_joint by 0.303 rad", then a 2.86 rad elbow change), the UR10's, IRB
    120's and Kinova's detoured (1.1-1.3 rad of motion, steps of 0.16-0.26 rad, against
    following's 0.71). Now no break, and no more motion than following or the joints'
    own straight motion."""
    arm = conftest.arm(name)
    j, singular = WRIST[name]
    if name == "ur5":
        qa = np.array([0.3, -1.2, 1.4, -1.5, 0.2, 0.2])
    else:
        qa = arm.random_q(4)
        qa[j] = singular + 0.2
    qb = qa + np.array([0.0, 0.0, 0.0, 0.3, -0.4, -0.5])
    Q, poses = _through(arm, qa, qb)
    assert any(r.singular for r in arm.solve_all(poses[20], q0=qa) if r.success)
    followed = arm.solve_path(poses, qa, max_joint_step=STEP)
    planned = arm.solve_path(poses, qa, max_joint_step=STEP, plan="global")
    assert planned.success.all(), [planned.reason(i) for i in np.flatnonzero(~planned.success)]
    _verified(arm, poses, qa, planned)
    least = min(_motion(qa, followed.q), _motion(qa, Q))
    assert _motion(qa, planned.q) <= least + 1e-3


@pytest.mark.parametrize("name", ["ur5", "abb_irb120"])
def test_a_run_of_singular_waypoints_moves_the_free_angle_along_it(name):
    """Wrist 2 held exactly at 0 over 20 waypoints while wrist 1 and 3 move: every pose of
    the run leaves the wrist's free angle to the solver, and the rows solved from the
    start keep it there, from the run's neighbours kept it constant, so the 0.24 rad the
    free angle moves over the run came as one step at its end (the UR5's plan broke there,
    the IRB 120's took it in one step). The free angle now moves by a share a waypoint
    from the run's one end to the other, as the joints do."""
    arm = conftest.arm(name)
    n = 60
    q0 = np.array([0.3, -1.2, 1.4, -1.5, 0.2, 0.2]) if name == "ur5" else arm.random_q(4)
    Q = np.tile(q0, (n, 1))
    Q[:, 3] += 0.01 * np.arange(n)
    Q[:, 5] -= 0.012 * np.arange(n)
    into = np.linspace(0.2, 0.0, 20, endpoint=False)  # wrist 2 down to 0, held, then on
    Q[:, 4] = np.concatenate((into, np.zeros(20), -into[::-1]))
    poses = [arm.fk(q) for q in Q]
    followed = arm.solve_path(poses, Q[0], max_joint_step=STEP)
    planned = arm.solve_path(poses, Q[0], max_joint_step=STEP, plan="global")
    assert planned.success.all(), [planned.reason(i) for i in np.flatnonzero(~planned.success)]
    _verified(arm, poses, Q[0], planned)
    least = min(_motion(Q[0], followed.q), _motion(Q[0], Q))
    assert _motion(Q[0], planned.q) <= least + 1e-3


def test_a_waypoint_on_a_shoulder_singularity_continues_its_neighbours():
    """The IRB 120's wrist point crossing joint 1's axis exactly at waypoint 20 (joint 1
    free there, kept at the start's value): the plan said "every path breaks here" at 20
    and 21 (a 0.53 rad jump of joint 4); following goes through. Now so does the plan."""
    arm = conftest.arm("abb_irb120")
    base = np.array([0.3, 0.0, -1.0, 0.4, 0.6, 0.2])

    def off_axis(q2: float) -> float:  # the wrist point's signed distance from axis 1
        q = base.copy()
        q[1] = q2
        p = arm.fk(q, frame="link_5").translation
        return float(p[0] * math.cos(base[0]) + p[1] * math.sin(base[0]))

    lo, hi = -0.5, 0.0
    assert off_axis(lo) < 0.0 < off_axis(hi)
    for _ in range(60):  # bisection onto the axis
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if off_axis(mid) < 0.0 else (lo, mid)
    qa, qb = base.copy(), base + np.array([0.4, 0.0, 0.0, 0.3, -0.2, 0.4])
    qa[1], qb[1] = lo + 0.2, lo - 0.2
    Q, poses = _through(arm, qa, qb)
    assert any(r.singular for r in arm.solve_all(poses[20], q0=qa) if r.success)
    followed = arm.solve_path(poses, qa, max_joint_step=STEP)
    planned = arm.solve_path(poses, qa, max_joint_step=STEP, plan="global")
    assert planned.success.all(), [planned.reason(i) for i in np.flatnonzero(~planned.success)]
    _verified(arm, poses, qa, planned)
    assert _motion(qa, planned.q) <= min(_motion(qa, followed.q), _motion(qa, Q)) + 1e-3


@pytest.mark.parametrize("name", ["ur5", "abb_irb120"])
def test_a_path_that_truly_breaks_at_a_singular_waypoint_still_breaks(name):
    """Wrist 2 from 0.2 to 0 on one member of the singular waypoint's family, then from 0
    to -0.2 on another, whose free angle lies half a right angle (and more) away: the
    family joins them only by a move of 1.6-1.8 rad, no path from q0 within 0.3 rad a step
    passes (the other arm branches are further still). The rows that continue each side
    do not hide it: the plan breaks, once, where following does. Its reason says every path
    from q0 without a jump breaks there, one through another solution of the waypoint
    before going on (the IRB 120's said "from every solution of the waypoint before",
    which the singular waypoint's family, a row of it near the far side's, belies)."""
    arm = conftest.arm(name)
    qs = np.array(
        [0.3, -1.2, 1.4, -1.35, 0.0, -0.05] if name == "ur5" else [0.3, 0.2, 0.3, 0.5, 0.0, -0.4]
    )
    seed = qs + np.array([0.0, 0.0, 0.0, 0.5 * math.pi, 0.0, 0.5 * math.pi])
    other = [r for r in arm.solve_all(arm.fk(qs), q0=seed) if r.success and r.singular]
    qo = np.array(min(other, key=lambda r: np.abs(r.q[:3] - qs[:3]).max()).q)
    assert np.abs(arm.fk(qo).homogeneous - arm.fk(qs).homogeneous).max() <= 1e-12
    e5 = np.eye(6)[4]
    Q = np.array([(qs if t <= 0.0 else qo) + t * e5 for t in np.linspace(-0.2, 0.2, 41)])
    poses = [arm.fk(q) for q in Q]
    followed = arm.solve_path(poses, Q[0], max_joint_step=STEP)
    planned = arm.solve_path(poses, Q[0], max_joint_step=STEP, plan="global")
    breaks = np.flatnonzero(~planned.success).tolist()
    assert breaks == np.flatnonzero(~followed.success).tolist() and len(breaks) == 1
    assert breaks[0] in (20, 21)
    assert planned.status[breaks[0]] == "discontinuous"
    assert "every path from q0 without a jump breaks here" in planned.reason(breaks[0])
