"""``solve_path(..., prefer=)``: continuity first, then the score. Each answer within
``max_joint_step`` of the one before; on a redundant arm the path drifts along the
self-motion toward the score; where one branch alone lies within the step the path is the
followed one (a global plan's preference: tests/solve/test_ladder.py)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.problem.scores import manipulability

from .. import conftest


def line(arm, q: np.ndarray, rng: np.random.Generator, n: int = 20) -> list[pin.SE3]:
    T = arm.fk(q)
    d = rng.normal(size=3)
    d *= 0.005 / np.linalg.norm(d)
    return [pin.SE3(T.rotation, T.translation + k * d) for k in range(n)]


def test_a_redundant_arm_drifts_toward_the_score_within_the_step():
    panda = conftest.arm("panda")
    rng = np.random.default_rng(7)
    panda.random_q(rng)  # the second draw: a line the Panda follows end to end
    q = panda.random_q(rng)
    poses = line(panda, q, rng)
    followed = panda.solve_path(poses, q, max_joint_step=0.3)
    path = panda.solve_path(poses, q, max_joint_step=0.3, prefer="manipulability")
    assert followed.success.all() and path.success.all(), path.summary()
    assert np.abs(np.diff(np.vstack([q, path.q]), axis=0)).max() <= 0.3 + 1e-12
    for pose, x in zip(poses, path.q):
        assert np.abs(pin.log6(pose.actInv(panda.fk(x))).vector).max() <= 1e-6
    first = [manipulability(panda.jacobian(x[0])) for x in (followed.q, path.q)]
    assert first[1] > first[0]  # moved along the self-motion at the first waypoint
    mean = [np.mean([manipulability(panda.jacobian(x)) for x in p.q]) for p in (followed, path)]
    assert mean[1] > mean[0]


def test_one_branch_within_the_step_is_the_followed_path():
    ur5 = conftest.arm("ur5")
    rng = np.random.default_rng(3)
    q = np.array([0.3, -1.2, 1.5, -1.0, 1.0, 0.4])
    poses = line(ur5, q, rng)
    followed = ur5.solve_path(poses, q, max_joint_step=0.3)
    path = ur5.solve_path(poses, q, max_joint_step=0.3, prefer="limits")
    assert followed.success.all() and path.success.all()
    assert np.allclose(path.q, followed.q, atol=1e-9)


def test_an_unknown_preference_is_named():
    ur5 = conftest.arm("ur5")
    T = ur5.fk(ur5.middle)
    for plan in ("follow", "global"):
        with pytest.raises(armik.InputError, match="prefer"):
            ur5.solve_path([T, T], ur5.middle, prefer="most_beautiful", plan=plan)


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_each_waypoint_carries_its_score(plan, tmp_path):
    """``BatchResult.score``: each answer's score with ``prefer=`` (the hand computation's,
    negative manipulability), row by row as ``r[i].score``, kept by slicing and by a saved
    file; NaN without a preference."""
    ur5 = conftest.arm("ur5")
    q = np.array([0.4, -1.2, 1.5, -0.8, 1.1, 0.3])
    T0 = ur5.fk(q)
    poses = [pin.SE3(T0.rotation, T0.translation + [0.0, 0.005 * k, 0.0]) for k in range(12)]
    path = ur5.solve_path(poses, q, max_joint_step=0.3, plan=plan, prefer="manipulability")
    assert path.success.all()
    by_hand = [-manipulability(ur5.jacobian(x)) for x in path.q]
    assert np.allclose(path.score, by_hand, rtol=1e-12, atol=1e-15)
    assert path[4].score == pytest.approx(by_hand[4], rel=1e-12)
    assert np.array_equal(path[2:6].score, path.score[2:6])
    back = armik.BatchResult.load(path.save(tmp_path / "path.npz"))
    assert np.array_equal(back.score, path.score)
    plain = ur5.solve_path(poses, q, max_joint_step=0.3, plan=plan)
    assert np.isnan(plain.score).all() and plain[0].score is None


@pytest.mark.parametrize("plan", ["follow", "global"])
@pytest.mark.parametrize(("name", "turned"), [("kinova", 4 * np.pi), ("ur5", -2 * np.pi)])
def test_a_free_start_takes_the_turn_the_score_prefers(name, turned, plan):
    # a Posture whole turns away on joint 1 (continuous on the Kinova, 720 degrees of range
    # on the UR5): without a start, the first answer is solve's, the posture itself, not the
    # turn next to the mid-limit seed nor another branch nearer that turn
    arm = conftest.arm(name)
    q = arm.middle + 0.2
    T = arm.fk(q)
    poses = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(4)]
    posture = q.copy()
    posture[0] += turned
    one = arm.solve(poses[0], prefer=armik.Posture(posture))
    path = arm.solve_path(poses, prefer=armik.Posture(posture), plan=plan)
    assert path.success.all(), path.summary()
    assert np.abs(path.q[0] - posture).max() < 1e-6, path.q[0] - posture
    assert np.abs(one.q - posture).max() < 1e-6
    assert np.abs(np.diff(path.q, axis=0)).max() <= 0.5 + 1e-12
