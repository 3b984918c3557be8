"""A failure's words give the errors of its best attempt only where the task measures
them: a part not asked was said to be "0", as if reached."""

from __future__ import annotations

import numpy as np
import pytest

import armik

from ...conftest import arm


@pytest.mark.parametrize("solver", ["clik", "dls", "qp"])
def test_a_failure_words_only_what_was_asked(solver):
    a = arm("ur5")
    T = a.fk(a.random_q(5))
    few = dict(q0=np.zeros(6), solver=solver, max_iterations=2, max_restarts=0)
    for target, weights, said, unsaid in (
        (T.translation, None, "position error", "orientation error"),
        (T, (1, 1, 1, 0, 0, 0), "position error", "orientation error"),
        (T, (0, 0, 0, 1, 1, 1), "orientation error", "position error"),
        (T, None, "orientation error", "no such words"),
    ):
        r = a.solve(target, weights=weights, **few)
        assert not r.success
        assert said in r.reason and unsaid not in r.reason, (weights, r.reason)


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_target_beyond_reach_by_a_hair_says_by_how_much(solver):
    """1.1e-6 m past the stretched 2-link arm's reach of 1.8 m, beyond tol_position: it
    said 'target is 1.8 m from the first joint, beyond the arm's reach of at most 1.8 m'."""
    a = arm("planar_2link")
    r = a.solve([1.8 + 1.1e-6, 0.0], q0=np.array([0.3, 0.4]), solver=solver)
    assert not r.success and r.status.value == "unreachable"
    assert "at most 1.8 m (by 1.1e-06 m)" in r.reason, r.reason
    near = a.solve([1.8 + 0.5e-6, 0.0], q0=np.array([0.3, 0.4]), solver=solver)
    assert near.success and near.position_error <= 1e-6  # within tol_position: reached


INF = np.inf
LOOK = (0.3, 0.2, 0.1)


def _failures(a, target, **options):
    """The reason of a failed solve, batch row and solve_all answer of ``target``."""
    few = dict(q0=a.middle, max_iterations=1, max_restarts=0, **options)
    rows = a.solve_batch([target, target], **few)
    got = [a.solve(target, **few), rows[0], a.solve_all(target, **few)[0]]
    assert not any(r.success for r in got), [r.reason for r in got]
    return [r.reason for r in got] + [rows.reason(1)]


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_look_at_failure_says_the_axis_angle_not_a_position_error_of_0(solver):
    """A look-at frees the position: it said 'best found: outside the region: position
    error 0 m, orientation error 0.473 rad', the 0 m of nothing asked."""
    a = arm("ur5")
    for said in _failures(a, [armik.LookAt(LOOK)], solver=solver):
        assert "position error" not in said and "orientation error" not in said, said
        angle = float(said.split("the tip's axis ")[1].split(" rad from the line to the point")[0])
        assert "region" not in said, said  # a look-at has none: its sight's words
        assert 0.1 < angle < np.pi, said  # the line of sight's angle, measured below
    r = a.solve([armik.LookAt(LOOK)], q0=a.middle, max_iterations=1, max_restarts=0)
    said = f"the tip's axis {r.orientation_error:.3g} rad from the line to the point;"
    assert said in r.reason, r.reason
    placed = a.fk(r.q)  # the angle by Pinocchio: the tool's z axis to the line of sight
    sight = np.array(LOOK) - placed.translation
    cos = placed.rotation[:, 2] @ sight / np.linalg.norm(sight)
    assert np.arccos(np.clip(cos, -1, 1)) == pytest.approx(r.orientation_error, abs=1e-9)


def test_a_look_at_within_a_cone_says_the_axis_and_its_cone():
    a = arm("ur5")
    T = a.fk(a.random_q(5))
    for said in _failures(a, T, look_at=LOOK, cone=(0, 0, 1, 0.1)):
        assert "position error" in said and "outside its cone of 0.1 rad" in said, said
        assert "orientation error" not in said


@pytest.mark.parametrize(
    ("bounds", "said", "unsaid"),
    [
        ((INF, INF, INF, 0.1, 0.1, 0.1), "outside the region: orientation error", "position"),
        ((0.1, 0.1, 0.1, INF, INF, INF), "outside the region: position error", "orientation"),
        ((INF, 0.1, 0.1, 0.1, INF, 0.1), "position error", "no such words"),
    ],
)
def test_bounds_that_free_a_part_leave_it_unsaid_in_a_failure(bounds, said, unsaid):
    """Infinite bounds on every component of the position (or rotation) said its error 0,
    as if reached; a part with one component held is said."""
    a = arm("ur5")
    T = a.fk(a.random_q(5))
    for reason in _failures(a, T, bounds=bounds):
        assert said in reason and unsaid not in reason, reason
        assert " 0 m" not in reason and " 0 rad" not in reason, reason


def test_the_task_solvers_closest_leaves_out_a_part_its_weights_free():
    """A pose whose position weights are 0 beside a look-at the task solver takes: its
    closest said 'Pose 0 m and 0.215 rad outside', the 0 m of nothing asked."""
    a = arm("ur5")
    T = a.fk(a.random_q(3))
    tasks = [
        armik.Pose(T, weights=(0, 0, 0, 1, 1, 1)),
        armik.LookAt((1, 1, 1), frame="wrist_2_link"),
    ]
    r = a.solve(tasks, q0=a.middle, max_restarts=0, max_iterations=2)
    assert not r.success and "closest: Pose " in r.reason, r.reason
    pose = r.reason.split("closest: Pose ")[1].split(",")[0]
    assert pose.endswith(" rad outside") and " m" not in pose, r.reason


def test_the_closest_task_says_every_part_a_task_measures():
    # a task with no bounds of its own (a Relative's are its pose's, a user's has none) was
    # read as freeing its position: "closest: Relative 0.407 rad outside" for a 4.86 m miss
    import pinocchio as pin

    from armik.problem.tasks.base import Task, TaskError

    class Height(Task):
        """The tip at height h (its z only)."""

        def __init__(self, h):
            self.h = h

        @property
        def rows(self):
            return 1

        def residual(self, T):
            return np.array([T.translation[2] - self.h])

        def jacobian(self, T, J):
            return (T.rotation @ J[:3])[2:3]

        def measure(self, T, tol_position, tol_orientation):
            d = abs(T.translation[2] - self.h)
            return TaskError(position=d, orientation=None, within=d <= tol_position)

    ur5 = arm("ur5")
    budget = {"q0": ur5.middle, "max_restarts": 0, "max_iterations": 5}
    far = pin.SE3(np.eye(3), np.array([5.0, 0.0, 0.0]))
    r = ur5.solve([armik.Relative("tool0", "base_link", far)], **budget)
    pos, ori = r.extra["task_errors"][0].position, r.extra["task_errors"][0].orientation
    assert not r.success and pos > 4.0
    assert f"Relative {pos:.3g} m and {ori:.3g} rad outside" in r.reason, r.reason
    look = armik.LookAt((1, 1, 1), frame="wrist_2_link")
    r = ur5.solve([Height(5.0), look], **{**budget, "max_iterations": 3})
    height = r.extra["task_errors"][0].position
    assert not r.success and f"Height {height:.3g} m outside" in r.reason, r.reason
