"""The steps of a path judged by one rule in both plans (``ladder._jumps``): a small,
straight joint motion past a singularity is continuous, a flip within the step is not,
whether the path is followed or planned."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pinocchio as pin
import pytest

import armik

from ..conftest import arm


def _half(Ta: pin.SE3, Tb: pin.SE3) -> pin.SE3:
    """The pose halfway: the translation's mean, the rotation halfway along its geodesic."""
    w = pin.log3(Ta.rotation.T @ Tb.rotation)
    return pin.SE3(Ta.rotation @ pin.exp3(0.5 * w), 0.5 * (Ta.translation + Tb.translation))


@pytest.mark.parametrize("start", [True, False])
@pytest.mark.parametrize("prefer", [None, "nearest"])
def test_a_small_straight_motion_past_the_wrist_singularity_is_continuous(start, prefer):
    """Every joint of a UR5 moves 0.02 rad a waypoint, wrist 2 passing 2 mrad from pi:
    the pose halfway between two waypoints has its solutions swing wrist 1 by more than
    max_joint_step (the global plan called the step a hidden jump, following did not check),
    but the joints moved straight keep the tip as near the path there as elsewhere. Both
    plans go through, from q0 and from any start."""
    ur5 = arm("ur5")
    q = np.array([-3.60087364, -6.21539958, 1.98408923, 4.79639694, 3.11335642, 5.80784677])
    path_q = [q + 0.02 * k for k in range(8)]
    poses = [ur5.fk(x) for x in path_q]
    # the swing the check sees halfway between waypoints 1 and 2: every solution far away
    middle = 0.5 * (path_q[1] + path_q[2])
    near = [
        np.abs(ur5.kinematics.nearest_equivalent(np.asarray(r.q), middle) - middle).max()
        for r in ur5.solve_all(_half(poses[1], poses[2]), q0=middle)
        if r.success
    ]
    assert min(near) > 0.5
    q0 = path_q[0] if start else None
    for plan in ("follow", "global"):
        r = ur5.solve_path(poses, q0, prefer=prefer, plan=plan)
        assert r.success.all(), (plan, r.summary())
        for T, x in zip(poses, r.q):
            assert np.abs(pin.log6(T.actInv(ur5.fk(x))).vector).max() <= 1e-6
        assert np.abs(np.diff(r.q, axis=0)).max() <= 0.5


def test_following_reports_the_jump_the_global_plan_reports():
    """A UR5 step whose wrist 2 goes from 0.2 to -0.2 rad through the singularity, wrist 1
    turned 0.1: within max_joint_step, but halfway the wrist swings. Following went on as
    if it were continuous; now both plans, from q0, say it is a jump, by the same rule."""
    ur5 = arm("ur5")
    qa = np.array([0.3, -1.2, 1.5, -1.0, 0.2, 0.4])
    qb = qa + np.array([0.0, 0.0, 0.0, 0.1, -0.4, 0.0])
    poses = [ur5.fk(qa), ur5.fk(qb)]
    for plan in ("follow", "global"):
        r = ur5.solve_path(poses, qa, max_joint_step=0.5, plan=plan)
        assert r.success.tolist() == [True, False], (plan, r.summary())
        assert r.status[1] == "discontinuous"
        assert "hide" in r[1].reason


def _every_turn(arm, q: np.ndarray) -> list[np.ndarray]:
    """``q`` at every turn of each joint (2 pi apart) within the limits."""
    out = []
    for k in itertools.product(range(-2, 3), repeat=len(q)):
        c = q + 2.0 * np.pi * np.array(k)
        if (c >= arm.lower - 1e-9).all() and (c <= arm.upper + 1e-9).all():
            out.append(c)
    return out


def test_a_step_is_checked_halfway_at_the_turn_the_plan_takes():
    """UR5 waypoints with wrist 3 at its upper limit (2 pi), the elbow swinging 0.25 rad a
    waypoint, planned from any start: the plan checked a step from a rung at one turn and
    took it at another (shoulder pan, wrists 2 and 3 a turn apart), where halfway wrist 3
    leaves its limit (the waypoint after a break called converged). Every success's step
    now has a solution halfway within max_joint_step of both ends, within the limits (each
    solution of ``solve_all`` at every turn)."""
    ur5 = arm("ur5")
    Q = np.array(
        [
            [
                -6.0449362002668305,
                4.235107433011836,
                0.9989569989199284,
                -1.8615394208543612,
                -0.3361943940998727,
                6.28318530718,
            ],
            [
                -5.896481693333798,
                4.250424626020186,
                0.7514022648267725,
                -1.8843203396406347,
                -0.47375309510165353,
                6.28318530718,
            ],
            [
                -5.748228286509616,
                4.263052106424951,
                0.5003712274177362,
                -1.908750415459228,
                -0.6059031021214577,
                6.28318530718,
            ],
            [
                -5.602569669668831,
                4.275764969155315,
                0.24919626815147933,
                -1.9317156765496752,
                -0.741346007994039,
                6.106085808359209,
            ],
        ]
    )  # wrist 3 at 2 pi (its upper limit) on the first three
    poses = [ur5.fk(x) for x in Q]
    r = ur5.solve_path(poses, None, max_joint_step=0.5, plan="global")
    checked = 0
    for i in range(1, len(poses)):
        if not r.success[i] or r.status[i - 1] not in ("converged", "discontinuous"):
            continue  # a success's step from the answer the path went on from
        qa, qb = np.asarray(r.q[i - 1]), np.asarray(r.q[i])
        H = _half(ur5.fk(qa), ur5.fk(qb))
        halfway = [
            c for s in ur5.solve_all(H) if s.success for c in _every_turn(ur5, np.asarray(s.q))
        ]
        assert any(
            (np.abs(c - qa) <= 0.5).all() and (np.abs(c - qb) <= 0.5).all() for c in halfway
        ), (i, qa, qb)
        checked += 1
    assert checked >= 1


def test_the_move_from_q0_is_held_to_the_step_alone():
    """One waypoint, the shoulder turned half a turn from q0 and a bound of 10 rad: a
    point-to-point move. The line between q0's pose and the waypoint passes next to the
    shoulder's axis, where the poses have no solution; q0's pose is where the arm is, not
    a pose of the path, so neither plan judges the move along that line (the global plan
    called it a hidden jump)."""
    ur5 = arm("ur5")
    q0 = np.array([0.0, -1.2, 1.5, -1.0, 1.0, 0.4])
    T = ur5.fk(q0 + np.array([math.pi, 0, 0, 0, 0, 0]))
    middle = _half(ur5.fk(q0), T)
    assert not any(r.success for r in ur5.solve_all(middle))  # out of reach halfway
    for plan in ("follow", "global"):
        r = ur5.solve_path([T], q0, max_joint_step=10.0, plan=plan)
        assert r.success.all(), (plan, r.summary())
        assert np.abs(pin.log6(T.actInv(ur5.fk(r.q[0]))).vector).max() <= 1e-6


def test_a_bound_that_lets_every_joint_flip_looks_for_no_hidden_jump():
    """Two waypoints, the shoulder turned 3 rad between them, the line between their poses
    next to the shoulder's axis (no solution there): with ``max_joint_step=10`` every joint
    may flip within a step, so no jump can hide and both plans go through, from q0 and from
    any start; with a bound of 3.1 rad, below a half turn, the step hides one."""
    ur5 = arm("ur5")
    q = np.array([0.0, -1.2, 1.5, -1.0, 1.0, 0.4])
    poses = [ur5.fk(q), ur5.fk(q + np.array([3.0, 0, 0, 0, 0, 0]))]
    assert not any(r.success for r in ur5.solve_all(_half(*poses)))  # out of reach halfway
    for plan in ("follow", "global"):
        for start in (q, None):
            r = ur5.solve_path(poses, start, max_joint_step=10.0, plan=plan)
            assert r.success.all(), (plan, r.summary())
            for T, x in zip(poses, r.q):
                assert np.abs(pin.log6(T.actInv(ur5.fk(x))).vector).max() <= 1e-6
        tight = ur5.solve_path(poses, q, max_joint_step=3.1, plan=plan)
        assert tight.status.tolist() == ["converged", "discontinuous"], (plan, tight.summary())


@pytest.mark.parametrize("hold", [None, {"wrist_3_joint": None}])
def test_a_path_followed_by_rows_is_checked_halfway(hold):
    """UR5 positions, the shoulder turned 2.5 rad between two waypoints: the line between
    them passes by the shoulder's axis, where no solution lies within a bound of 3 rad of
    both ends. A held wrist 3 follows the path row by row through the task solver, which
    went on as if the step were continuous; both routes now say it hides a jump, and with
    a bound that lets every joint flip both go through, on their positions by FK."""
    ur5 = arm("ur5")
    q = np.array([0.48, -1.97, -0.823, -1.577, 6.125, 1.668])
    P = np.array([ur5.fk(q).translation, ur5.fk(q + np.array([2.5, 0, 0, 0, 0, 0])).translation])
    held = {} if hold is None else {"hold": hold}
    tight = ur5.solve_path(P, q, max_joint_step=3.0, **held)
    assert tight.status.tolist() == ["converged", "discontinuous"], tight.summary()
    assert "hide" in tight[1].reason
    loose = ur5.solve_path(P, q, max_joint_step=10.0, **held)
    assert loose.success.all(), loose.summary()
    for p, x in zip(P, loose.q):
        assert np.linalg.norm(ur5.fk(x).translation - p) <= 1e-6
        if hold is not None:
            assert x[5] == pytest.approx(q[5], abs=1e-9)
    assert (tight.solver == "tasks") == (hold is not None)


@pytest.mark.parametrize(
    "qa, qb",
    [
        (
            [2.877, 0.492, -0.47, -1.393, 2.094, 3.728, -2.473],
            [2.897, 1.027, -0.528, -1.747, 1.695, 3.286, -2.571],
        ),
        (
            [-2.472, 0.187, -1.981, -2.201, 0.45, 1.147, -0.421],
            [-2.553, -0.611, -1.089, -1.502, 1.199, 0.691, -0.611],
        ),
        (  # joint 4 at its limit: the descents from the middle and the ends stall on it
            [0.609, -0.926, 2.2664, -0.1279, 1.3405, 0.942, -2.3083],
            [1.0912, -1.0016, 2.0384, -0.0698, 0.8029, 0.6119, -1.9365],
        ),
    ],
)
def test_a_panda_step_with_a_solution_halfway_near_both_ends_is_continuous(qa, qb):
    """Two Panda waypoints, every joint within 0.9 rad of the first: the halfway pose has
    a solution within max_joint_step (1 rad) of both answers, found by descents from the
    ends and from about the middle, but not as the solution nearest the step's middle
    (the sweep's and one descent from the middle missed it): the step was called a
    hidden jump. Both plans now go
    through, on the poses by FK, within the bound."""
    panda = arm("panda")
    qa, qb = np.array(qa), np.array(qb)
    poses = [panda.fk(qa), panda.fk(qb)]
    for plan in ("follow", "global"):
        r = panda.solve_path(poses, qa, max_joint_step=1.0, plan=plan)
        assert r.success.all(), (plan, r.summary())
        for T, x in zip(poses, r.q):
            assert np.abs(pin.log6(T.actInv(panda.fk(x))).vector).max() <= 1e-6
        a, b = np.asarray(r.q[0]), np.asarray(r.q[1])
        assert np.abs(b - a).max() <= 1.0
        H = _half(*poses)  # a solution there within the bound of both answers
        rng = np.random.default_rng(1)
        seeds = [a, b] + [0.5 * (a + b) + rng.normal(0.0, 0.3, 7) for _ in range(40)]
        seeds = [np.clip(x, panda.lower, panda.upper) for x in seeds]
        found = [panda.solve(H, q0=x, solver="dls", max_restarts=0) for x in seeds]
        assert any(
            s.success
            and np.abs(pin.log6(H.actInv(panda.fk(s.q))).vector).max() <= 1e-6
            and np.abs(np.asarray(s.q) - a).max() <= 1.0
            and np.abs(np.asarray(s.q) - b).max() <= 1.0
            for s in found
        )


def test_a_panda_step_whose_halfway_solutions_are_far_hides_a_jump():
    """Beside the case above, a step of the Panda whose halfway pose has no solution near
    both ends (none within 1.6 rad of both from 40 seeds about the middle) stays a hidden
    jump in both plans."""
    panda = arm("panda")
    qa = np.array([1.943, 1.525, -0.015, -0.696, -0.894, 1.503, 1.632])
    qb = np.array([2.478, 0.858, 0.465, -0.07, -1.439, 1.635, 1.882])
    for plan in ("follow", "global"):
        r = panda.solve_path([panda.fk(qa), panda.fk(qb)], qa, max_joint_step=1.0, plan=plan)
        assert r.status.tolist() == ["converged", "discontinuous"], (plan, r.summary())
        assert "hide" in r[1].reason


def test_a_held_paths_step_with_a_solution_halfway_near_its_ends_is_continuous():
    # the Panda held at joints 1 and 7, positions (the task solver's rows): the halfway
    # answer nearest the step's middle lies 1.03 rad from one end, one found from an end
    # lies within the bound of both; it was called a hidden jump
    panda = arm("panda")
    hold = {"panda_joint1": None, "panda_joint7": None}
    qa = np.array([-2.4035, -0.1753, -2.4381, -0.566, 2.4433, 2.2248, -1.0084])
    qb = np.array([-2.4035, -0.8306, -2.3177, -1.1828, 1.9386, 2.6199, -1.0084])
    P = np.array([panda.fk(qa).translation, panda.fk(qb).translation])
    got = panda.solve_path(P, qa, max_joint_step=1.0, hold=hold)
    assert got.status.tolist() == ["converged", "converged"], got.reason(1)
    a, b = np.asarray(got.q[0]), np.asarray(got.q[1])
    halfway = panda.solve(0.5 * (P[0] + P[1]), q0=a, hold=hold)  # a solution near both ends
    assert halfway.success
    assert np.abs(halfway.q - a).max() <= 1.0 and np.abs(halfway.q - b).max() <= 1.0
    model = panda.model  # on the halfway point by Pinocchio
    data = model.createData()
    pin.framesForwardKinematics(model, data, panda.kinematics.to_pin(halfway.q))
    placed = panda.kinematics.T_base_world * data.oMf[model.getFrameId(panda.tip)]
    assert np.linalg.norm(placed.translation - 0.5 * (P[0] + P[1])) < 1e-6


def test_a_held_ur5_path_of_poses_is_judged_halfway_on_the_arm_free():
    """A UR5 held at wrist 3 (``hold=``: the task solver, row by row) through the wrist flip
    above: wrist 2 from 0.2 to -0.2 rad, wrist 3 unchanged. The held arm reaches neither the
    pose halfway nor any near it, and its steps were not judged halfway: the step was called
    converged. It is judged on the arm free now (every held configuration is one of the free
    arm's): no solution there lies within max_joint_step of both ends, a hidden jump. A
    held path moving every free joint by up to 0.3 rad a waypoint away from singularities
    stays converged, each answer on its pose by FK, wrist 3 where it was held."""
    ur5 = arm("ur5")
    hold = {"wrist_3_joint": None}
    qa = np.array([0.3, -1.2, 1.5, -1.0, 0.2, 0.4])
    qb = qa + np.array([0.0, 0.0, 0.0, 0.1, -0.4, 0.0])
    poses = [ur5.fk(qa), ur5.fk(qb)]
    got = ur5.solve_path(poses, qa, hold=hold)
    assert got.status.tolist() == ["converged", "discontinuous"], got.summary()
    assert "hide" in got.reason(1)
    a, b = np.asarray(got.q[0]), np.asarray(got.q[1])
    assert np.abs(a - qa).max() < 1e-6 and np.abs(b - qb).max() < 1e-6
    H = _half(*poses)  # every solution halfway, on it by FK, far from one end or the other
    every = [np.asarray(r.q) for r in ur5.solve_all(H) if r.success]
    assert len(every) == 8
    for x in every:
        assert np.abs(pin.log6(H.actInv(ur5.fk(x))).vector).max() <= 1e-6
        x = ur5.kinematics.nearest_equivalent(x, 0.5 * (a + b))
        assert max(np.abs(x - a).max(), np.abs(x - b).max()) > 0.5
    d = np.array([0.25, -0.2, 0.3, 0.25, -0.3, 0.0])
    Q = [np.array([0.3, -1.2, 1.5, -1.0, 1.2, 0.4]) + k * d for k in range(4)]
    smooth = [ur5.fk(x) for x in Q]
    fine = ur5.solve_path(smooth, Q[0], hold=hold)
    assert fine.success.all(), fine.summary()
    for T, x in zip(smooth, fine.q):
        assert np.abs(pin.log6(T.actInv(ur5.fk(x))).vector).max() <= 1e-6
        assert x[5] == pytest.approx(0.4, abs=1e-9)


@pytest.mark.parametrize(
    "loosened, hidden",
    [({"weights": [1, 1, 1, 0.5, 0.5, 0.5]}, True), ({"bounds": [0.001] * 3 + [0.01] * 3}, False)],
)
def test_a_held_ur5_path_of_loosened_poses_is_judged_halfway_as_the_arm_free(loosened, hidden):
    """The held wrist flip above given as armik.Pose(T, weights=...) or Pose(T, bounds=...):
    such rows were not judged halfway (converged). Judged on the arm free under the same
    weights or bounds (the region halfway the free arm reaches holds every held answer
    there), the held path says what the free arm's path says: with the weights a hidden
    jump; bounds of 10 mrad let the free arm pass the flip halfway, and the held step is
    continuous, each answer within its bounds by FK and wrist 3 where it was held."""
    ur5 = arm("ur5")
    qa = np.array([0.3, -1.2, 1.5, -1.0, 0.2, 0.4])
    qb = qa + np.array([0.0, 0.0, 0.0, 0.1, -0.4, 0.0])
    poses = [ur5.fk(qa), ur5.fk(qb)]
    rows = [armik.Pose(T, **loosened) for T in poses]
    held = ur5.solve_path(rows, qa, hold={"wrist_3_joint": None})
    free = ur5.solve_path(rows, qa)
    want = ["converged", "discontinuous"] if hidden else ["converged", "converged"]
    assert held.status.tolist() == free.status.tolist() == want, held.summary()
    bound = np.array(loosened.get("bounds", [0.0] * 6)) + 1e-6
    for T, x in zip(poses, held.q):
        assert (np.abs(pin.log6(T.actInv(ur5.fk(x))).vector) <= bound).all()
        assert x[5] == pytest.approx(0.4, abs=1e-9)
