"""The tasks' residuals, Jacobians and measures: Jacobians against finite differences
through ``pin.integrate`` (continuous joints included), bounds against a hand-built error
twist, regions that need no step, and bad input named."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import TargetError
from armik.model.arm_model import ArmModel
from armik.problem import Axis, LookAt, Pose, Position
from armik.targets.pose import parse_target

from ..conftest import arm as bundled

H = 1e-6


def numeric_jacobian(a: ArmModel, task, q: np.ndarray) -> np.ndarray:
    """Central differences of the residual, stepping Pinocchio's configuration with
    ``pin.integrate`` along each joint's velocity (on the arm model)."""
    qp = a.to_pin(q)
    columns = []
    for i in range(a.dof):
        dv = np.zeros(a.model.nv)
        dv[i] = H
        plus = task.residual(a.fk_pin(pin.integrate(a.model, qp, dv)))
        minus = task.residual(a.fk_pin(pin.integrate(a.model, qp, -dv)))
        columns.append((plus - minus) / (2 * H))
    return np.array(columns).T


def tasks_for(a: armik.Arm, rng: np.random.Generator) -> list:
    """Tasks whose residual is away from zero (and from the dead zones' edges) at the
    configurations the test draws."""
    T = a.fk(a.random_q(rng))
    return [
        Pose(T),
        Pose(T, bounds=(0.01, 0.0, math.inf, 0.05, 0.0, math.inf)),
        Pose(T, weights=(1, 2, 0.5, 1, 1, 0)),
        Position(T.translation),
        Position(T.translation, bounds=(0.02, math.inf, 0.0)),
        Axis((0, 0, 1), (0.3, -0.2, -1.0)),
        Axis((1, 0, 0), (0.0, 1.0, 0.2), within=0.1),
        LookAt(T.translation + np.array([0.5, 0.3, -0.4])),
        LookAt(T.translation + np.array([0.0, 0.8, 0.1]), axis=(0, 1, 0), within=0.05),
    ]


@pytest.mark.parametrize("robot", ["panda", "ur5", "kinova"])  # kinova: continuous joints
def test_jacobians_match_finite_differences(robot):
    a = bundled(robot)
    rng = np.random.default_rng(3)
    tasks = tasks_for(a, rng)
    for _ in range(4):
        q = a.random_q(rng)
        T, J = a.fk(q), a.jacobian(q)
        for task in tasks:
            r = task.residual(T)
            assert r.shape == (task.rows,)
            analytic = task.jacobian(T, J)
            numeric = numeric_jacobian(a.kinematics, task, q)
            np.testing.assert_allclose(analytic, numeric, atol=2e-6, err_msg=repr(task))


def hand_built(e: np.ndarray, T_t: pin.SE3) -> pin.SE3:
    """The placement whose error twist relative to ``T_t``, in ``T_t``'s frame, is ``e``."""
    R = T_t.rotation @ pin.exp3(e[3:])
    return pin.SE3(R, T_t.translation + T_t.rotation @ e[:3])


def test_bounds_mean_the_error_twist_in_the_target_frame():
    T_t = pin.SE3.Random()
    e = np.array([0.004, -0.003, 0.02, 0.03, -0.01, 0.5])
    T = hand_built(e, T_t)
    task = Pose(T_t, bounds=(0.005, 0.005, 0.005, 0.05, 0.05, math.inf))
    np.testing.assert_allclose(task.twist(T), e, atol=1e-12)
    r = task.residual(T)  # only z is outside its bound, by 0.015 m
    np.testing.assert_allclose(r, [0, 0, 0.015, 0, 0, 0], atol=1e-12)
    m = task.measure(T, 1e-6, 1e-6)
    assert not m.within and m.position == pytest.approx(0.015) and m.orientation == 0.0
    wider = Pose(T_t, bounds=(0.005, 0.005, 0.021, 0.05, 0.05, math.inf))
    assert wider.measure(T, 1e-6, 1e-6).within
    tight_spin = Pose(T_t, bounds=(0.005, 0.005, 0.021, 0.05, 0.05, 0.4))
    assert tight_spin.measure(T, 1e-6, 1e-6).orientation == pytest.approx(0.1)


def test_a_target_inside_its_region_needs_no_step():
    a = bundled("panda")
    q = a.random_q(np.random.default_rng(8))
    T, J = a.fk(q), a.jacobian(q)
    R = T.rotation
    inside = [
        Pose(
            hand_built(np.array([0.001, 0, -0.002, 0.01, 0, 2.0]), T),
            bounds=[0.005] * 3 + [0.05, 0.05, math.inf],
        ),
        Position(T.translation + [0.003, 0, 0], bounds=(0.005, 0.005, 0.005)),
        Axis((0, 0, 1), R @ [0.0, 0.05, 1.0], within=0.06),
        LookAt(T.translation + R @ [0.02, 0.0, 0.7], within=0.05),
    ]
    for task in inside:
        assert not task.residual(T).any() and not task.jacobian(T, J).any(), task
        assert task.measure(T, 1e-9, 1e-9).within, task


def test_the_cone_residual_is_the_angle_beyond_the_cone():
    T = pin.SE3(pin.exp3(np.array([0.0, 0.3, 0.0])), np.zeros(3))  # tip z tilted by 0.3 rad
    for within in (0.0, 0.1, 0.29):
        task = Axis((0, 0, 1), (0, 0, 1), within=within)
        assert np.linalg.norm(task.residual(T)) == pytest.approx(0.3 - within)
        assert task.measure(T, 1e-9, 1e-9).orientation == pytest.approx(0.3 - within)
    assert Axis((0, 0, 1), (0, 0, 1), within=0.31).measure(T, 1e-9, 1e-9).within
    upside_down = Axis((0, 0, 1), (0, 0, -1))
    assert np.linalg.norm(upside_down.residual(pin.SE3.Identity())) == pytest.approx(math.pi)


@pytest.mark.parametrize(
    ("build", "words"),
    [
        (lambda: Pose(np.eye(4), bounds=(0.1, -0.1, 0, 0, 0, 0)), "must be >= 0"),
        (lambda: Pose(np.eye(4), bounds=(0.1, math.nan, 0, 0, 0, 0)), "nan"),
        (lambda: Pose(np.eye(4), bounds=(0.1, 0.1)), "6 numbers"),
        (lambda: Pose(np.zeros(3)), "armik.Position"),
        (lambda: Pose(np.eye(4), weights=(0, 0, 0, 0, 0, 0)), "not all 0"),
        (lambda: Position((0, 0, math.nan)), "NaN"),
        (lambda: Position((0, 0, 1), bounds=(-1, 0, 0)), "-1.0"),
        (lambda: Axis((0, 0, 0), (0, 0, 1)), "zero length"),
        (lambda: Axis((0, 0, 1), (0, 0, 1), within=4.0), "[0, pi]"),
        (lambda: Axis((0, 0, 1), (0, 0, 1), within=-0.1), "[0, pi]"),
        (lambda: LookAt((1, 0, 0), axis=(0, 0, 0)), "zero length"),
        (lambda: Axis((0, 0, 1), (0, 0, 1), frame=3), "frame"),
    ],
)
def test_bad_input_is_named(build, words):
    with pytest.raises(TargetError) as info:
        build()
    assert words.lower() in str(info.value).lower()


def test_a_pose_of_a_parsed_target_is_the_pose_built_from_it():
    """``Pose.of`` (a parsed full pose, not read again) builds what ``Pose(T, frame=)``
    builds: the same placement, frame, bounds, weights and free axes, the same measure."""
    T = pin.SE3(pin.rpy.rpyToMatrix(0.3, -0.2, 1.1), np.array([0.4, -0.1, 0.5]))
    built, of = Pose(T, frame="hand"), Pose.of(parse_target(T), "hand")
    assert of.frame == built.frame == "hand" and type(of) is Pose
    assert np.array_equal(of.T.homogeneous, built.T.homogeneous)
    for name in ("bounds", "weights", "_free"):
        assert np.array_equal(getattr(of, name), getattr(built, name)), name
    X = pin.SE3(pin.rpy.rpyToMatrix(0.31, -0.2, 1.1), np.array([0.41, -0.1, 0.5]))
    assert of.measure(X, 1e-6, 1e-6) == built.measure(X, 1e-6, 1e-6)
    assert of.shrunk(0.9) is of and of.kernel_row() is not None


@pytest.mark.parametrize("huge", [1e308, 1e200])
def test_an_axis_of_huge_entries_is_its_direction(huge):
    """A direction spelled with entries whose squares overflow (``(1e308, 1e308, 0)``) is
    that direction: its unit vector was (0, 0, 0), which every placement "held" (the angle
    of the zero vector to any is 0), and a task list of it was a success pointing anywhere."""
    along = np.array([1.0, 1.0, 0.0]) / math.sqrt(2.0)
    for task in (
        Axis((huge, huge, 0), (0, 0, 1)),
        Axis((0, 0, 1), (huge, huge, 0)),
        LookAt((0, 0, 1), (huge, huge, 0)),
    ):
        unit = task.axis if not np.array_equal(task.axis, (0, 0, 1)) else task.direction
        np.testing.assert_allclose(unit, along, atol=1e-15)
    ur5 = bundled("ur5")
    T = ur5.fk(ur5.random_q(1))
    tasks = [armik.Position(T.translation), Axis((huge, huge, 0), T.rotation[:, 2])]
    assert not tasks[1].measure(T, 1e-6, 1e-6).within  # the tool's z is along it, not x + y
    r = ur5.solve(tasks, q0=ur5.middle, iteration_budget=300)
    if r.success:
        F = ur5.fk(r.q)
        assert float((F.rotation @ along) @ T.rotation[:, 2]) >= math.cos(1e-6)


def test_a_finite_task_bound_beyond_any_reach_is_refused_by_its_task():
    """A task's bounds follow the ``bounds=`` option's rule (at most 1e6 where finite,
    ``math.inf`` frees an axis), refused where the task is built and named by it: a
    ``Pose`` of such bounds was refused at the solve in the option's words, a ``Position``
    of them taken."""
    T = pin.SE3(np.eye(3), np.array([0.3, 0.1, 0.4]))
    for build, name in (
        (lambda b: Position(T.translation, bounds=(b,) * 3), "Position bounds"),
        (lambda b: Pose(T, bounds=(b,) * 3 + (0, 0, 0)), "Pose bounds"),
        (lambda b: armik.Relative("a", "b", T, bounds=(0,) * 3 + (b,) * 3), "Pose bounds"),
    ):
        for b in (1e7, 1e300):
            with pytest.raises(TargetError, match=rf"{name} must be at most 1e6 .*math.inf frees"):
                build(b)
        build(1e6)
        build(math.inf)
