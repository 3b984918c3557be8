"""A task of a test's own, written by CONTRIBUTING's recipe: a ``Task`` subclass with its
``rows``, ``residual``, ``jacobian`` and ``measure`` and nothing else (no ``kernel_row``,
no form for the plain-pose path), solved through ``solve``, ``solve_all``, ``solve_batch``
(a list of task lists), a followed ``solve_path``, ``prefer=`` and several tips, each
answer checked by an FK computed here."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.problem.tasks.base import Task, TaskError
from tests.conftest import arm as bundled


class Height(Task):
    """``frame``'s origin at height ``z`` (m) above the base: one row."""

    def __init__(self, z: float, frame: str | None = None) -> None:
        self.z = float(z)
        self.frame = frame

    @property
    def rows(self) -> int:
        return 1

    def residual(self, T: pin.SE3) -> np.ndarray:
        return np.array([T.translation[2] - self.z])

    def jacobian(self, T: pin.SE3, J: np.ndarray) -> np.ndarray:
        return (T.rotation @ J[:3])[2:3]  # the origin's velocity in the base's axes, its z

    def measure(self, T: pin.SE3, tol_position: float, tol_orientation: float) -> TaskError:
        off = abs(float(T.translation[2]) - self.z)
        return TaskError(off, None, off <= tol_position)


def _height(arm, q, frame=None) -> float:
    """The frame's height by Pinocchio, computed here (``arm.fk``'s placement)."""
    return float(arm.fk(q, frame=frame).translation[2])


def test_residual_and_jacobian_by_finite_differences():
    ur5 = bundled("ur5")
    q = np.array([0.3, -1.1, 1.2, -0.4, 0.8, 0.2])
    task = Height(0.2)
    J = ur5.jacobian(q, reference="local")
    analytic = task.jacobian(ur5.fk(q), J)
    h = 1e-6
    numeric = np.empty((1, 6))
    for j in range(6):
        dq = np.zeros(6)
        dq[j] = h
        up = task.residual(ur5.fk(q + dq))
        down = task.residual(ur5.fk(q - dq))
        numeric[:, j] = (up - down) / (2 * h)
    np.testing.assert_allclose(analytic, numeric, atol=1e-6)


def test_solve_and_solve_all():
    ur5 = bundled("ur5")
    q = np.array([0.3, -1.1, 1.2, -0.4, 0.8, 0.2])
    p = ur5.fk(q).translation
    # alone, and with a position of the same frame in x and y only
    for tasks in ([Height(0.25)], [Height(p[2] + 0.05), armik.Position(p, bounds=(0, 0, 1))]):
        r = ur5.solve(tasks, q0=q)
        assert r.success, r.reason
        assert abs(_height(ur5, r.q) - tasks[0].z) < 1e-6
        found = ur5.solve_all(tasks, q0=q)
        assert found and all(abs(_height(ur5, a.q) - tasks[0].z) < 1e-6 for a in found if a.success)
        assert found[0].success
    # another frame: the forearm's origin
    r = ur5.solve([Height(0.3, frame="forearm_link")], q0=q)
    assert r.success and abs(_height(ur5, r.q, "forearm_link") - 0.3) < 1e-6


def test_a_height_out_of_reach_is_a_failure():
    ur5 = bundled("ur5")
    r = ur5.solve([Height(5.0)], iteration_budget=300)
    assert not r.success and _height(ur5, r.q) < 5.0 - 1.0


def test_solve_batch_of_task_lists():
    ur5 = bundled("ur5")
    heights = [0.1, 0.2, 0.3, 0.4]
    res = ur5.solve_batch([[Height(z)] for z in heights], q0=ur5.middle)
    assert res.success.all()
    for i, z in enumerate(heights):
        assert abs(_height(ur5, res.q[i]) - z) < 1e-6


def test_a_followed_path_of_task_lists():
    # the task solver's, waypoint by waypoint from the one before: small moves, each held
    # to max_joint_step; the global plan (every solution at each waypoint) refused by name
    ur5 = bundled("ur5")
    heights = [0.30, 0.31, 0.32, 0.33]
    rows = [[Height(z)] for z in heights]
    budget = {"iteration_budget": 500}  # not timed: the same answers on a busy machine
    start = ur5.solve([Height(0.30)], q0=ur5.middle + 0.3, **budget).q  # at the first height
    path = ur5.solve_path(rows, start, max_joint_step=0.2, **budget)
    assert path.success.all(), path.summary()
    for i, z in enumerate(heights):
        assert abs(_height(ur5, path.q[i]) - z) < 1e-6
    assert np.abs(np.diff(np.vstack([start, path.q]), axis=0)).max() <= 0.2 + 1e-12
    jumped = ur5.solve_path(
        [[Height(0.3)], [Height(-0.3)]], ur5.middle, max_joint_step=0.05, **budget
    )
    assert jumped.status[1] in ("discontinuous", "not_converged"), jumped.summary()
    with pytest.raises(armik.TargetError, match="plan='global' plans over every solution"):
        ur5.solve_path(rows, ur5.middle, plan="global")


def test_a_preference_scores_its_answer():
    """The task solver gives one answer: ``prefer=`` scores it (a task list without a
    compiled form is not searched for the score)."""
    ur5 = bundled("ur5")
    posture = np.array([0.0, -1.0, 1.0, -1.0, 0.5, 0.0])
    for every in (False, True):
        got = (ur5.solve_all if every else ur5.solve)(
            [Height(0.3)], q0=ur5.middle, prefer=armik.Posture(posture)
        )
        r = got[0] if every else got
        assert r.success and abs(_height(ur5, r.q) - 0.3) < 1e-6
        assert r.extra["score"] == pytest.approx(float(np.sum((r.q - posture) ** 2)))
        assert "prefer=posture" in r.reason


def test_several_tips():
    """A flat list of tasks, each naming its frame, on a robot of two tips: the hand at
    a height, the fifth link lower too."""
    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    q = robot.middle
    hand = robot.fk(q, "panda_hand").translation[2]
    link5 = robot.fk(q, "panda_link5").translation[2]
    tasks = [Height(hand - 0.1, frame="panda_hand"), Height(link5 - 0.05, frame="panda_link5")]
    r = robot.solve(tasks, q0=q)
    assert r.success, r.reason
    assert abs(float(robot.fk(r.q, "panda_hand").translation[2]) - (hand - 0.1)) < 1e-6
    assert abs(float(robot.fk(r.q, "panda_link5").translation[2]) - (link5 - 0.05)) < 1e-6


@pytest.mark.parametrize("bad", [[Height(0.3, frame="no_such_link")]])
def test_an_unknown_frame_names_the_frame(bad):
    ur5 = bundled("ur5")
    with pytest.raises(armik.ArmikError, match="no_such_link"):
        ur5.solve(bad)


class TwoRows(Height):
    def residual(self, T: pin.SE3) -> np.ndarray:
        return np.array([T.translation[2] - self.z, 0.0])  # rows says 1


class WideJacobian(Height):
    def jacobian(self, T: pin.SE3, J: np.ndarray) -> np.ndarray:
        return J[:2]


class FloatMeasure(Height):
    def measure(self, T: pin.SE3, tol_position: float, tol_orientation: float):
        return 0.0


class RaisingResidual(Height):
    def residual(self, T: pin.SE3) -> np.ndarray:
        return np.array([self.table[T.translation[2]]])  # no such attribute


@pytest.mark.parametrize(
    ("cls", "said"),
    [
        (TwoRows, r"its residual must be an array of shape \(1,\) .* got shape \(2,\)"),
        (WideJacobian, r"its jacobian must be an array of shape \(1, 6\) .* got shape \(2, 6\)"),
        (FloatMeasure, r"its measure must return a TaskError.* got 0.0"),
        (RaisingResidual, "its residual raised AttributeError: .*'table'"),
    ],
)
def test_a_member_of_another_shape_or_that_raises_is_named(cls, said):
    """A task of the user's own whose residual, Jacobian or measure gives another shape
    than its rows say, or raises: a ``TargetError`` naming its class, where numpy's matmul
    and concatenate errors (or the bare AttributeError) came out of the task solver."""
    ur5 = bundled("ur5")
    tasks = [cls(0.3), armik.Axis((0, 0, 1), (0, 0, -1), 0.1)]
    with pytest.raises(armik.TargetError, match=f"task {cls.__name__}: {said}"):
        ur5.solve(tasks, iteration_budget=100)
    assert Height.residual._armik_checked and not hasattr(armik.Axis.residual, "_armik_checked")
