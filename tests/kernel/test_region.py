"""The compiled error of a pose within bounds equals ``armik.problem.Pose``'s residual and
Jacobian, and with a cone ``armik.Position`` and ``armik.Axis``'s (which the problem tests
hold against finite differences)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from armik.kernel.problem import LOOK_POINT, LOOK_TOWARD, NO_CONE, NO_LOOK, workspace
from armik.kernel.region import evaluate_region
from armik.problem import Axis, LookAt, Pose, Position
from armik.problem.problem import Problem, lower

from ..conftest import model

EXACT = 1e-12
AXIS = np.array([0.0, 0.0, 1.0])  # read only with a cone
ORIGIN = np.zeros(3)  # the look-at point, read only with ``look``
EYE = np.eye(3)
BOUNDS = [
    (0.0,) * 6,
    (0.005, 0.005, 0.005, 0.05, 0.05, 0.05),
    (0.01, 0.0, math.inf, 0.0, 0.2, math.inf),
    (math.inf, math.inf, math.inf, 0.0, 0.0, 0.0),
]


@pytest.mark.parametrize("robot", ["panda", "ur5", "kinova"])
@pytest.mark.parametrize("bounds", BOUNDS)
def test_the_region_error_is_the_pose_task(robot, bounds):
    a = model(robot)
    ch = a.kernel_chain.flat
    ws = workspace(a.dof, 1, a.kernel_chain.chain.joint_kind.shape[0])
    rng = np.random.default_rng(21)
    weights = np.array([1.0, 2.0, 0.5, 1.0, 0.0, 3.0])
    for k in range(10):
        q = a.random_q(rng)
        T = a.fk(q)
        T_t = T * pin.exp6(pin.Motion(rng.normal(scale=0.05, size=6)))
        w = np.ones(6) if k % 2 else weights
        task = Pose(T_t, bounds=bounds, weights=w)
        ws.q[0][:] = q
        b = np.array(bounds, dtype=float)
        R_t, p_t = np.ascontiguousarray(T_t.rotation), np.ascontiguousarray(T_t.translation)
        evaluate_region(ch, b, w, NO_CONE, AXIS, NO_LOOK, ORIGIN, R_t, p_t, ws, 0)
        np.testing.assert_allclose(ws.e[0], -task.residual(T), rtol=0, atol=EXACT)
        J = a.jacobian(q)
        np.testing.assert_allclose(ws.A[0], task.jacobian(T, J), rtol=0, atol=EXACT)
        m = task.measure(T, 0.0, 0.0)
        free = w == 0  # a weight of 0 frees its axis: not measured
        assert ws.val[0, 0] == pytest.approx(m.position, abs=EXACT) or free[:3].any()
        assert ws.val[0, 1] == pytest.approx(m.orientation, abs=EXACT) or free[3:].any()
        assert ws.val[0, 2] == pytest.approx(float(ws.e[0] @ ws.e[0]), abs=EXACT)


def test_inside_the_region_the_error_is_zero():
    a = model("ur5")
    ws = workspace(a.dof, 1, a.kernel_chain.chain.joint_kind.shape[0])
    q = a.random_q(np.random.default_rng(4))
    T = a.fk(q) * pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.04])), np.array([0.003, 0.0, 0.0]))
    ws.q[0][:] = q
    bounds = np.array([0.005, 0.005, 0.005, 0.05, 0.05, 0.05])
    R_t, p_t = np.ascontiguousarray(T.rotation), np.ascontiguousarray(T.translation)
    evaluate_region(
        a.kernel_chain.flat, bounds, np.ones(6), NO_CONE, AXIS, NO_LOOK, ORIGIN, R_t, p_t, ws, 0
    )
    assert not ws.e[0].any() and not ws.A[0].any() and not ws.val[0].any()


def _rows(a, ws, q, target, said, cone=None, bounds=None):
    """(e, A, orientation error): the compiled rows of a lowered target (``target`` with
    its aim, the options ``said``; ``cone`` and ``bounds`` given where they are not said)
    at ``q``."""
    aim = getattr(target, "aim", None)  # a cone lowers onto the target (``Target.aim``)
    cone = aim.cone if cone is None else cone
    look, x = NO_LOOK, ORIGIN
    if aim is not None and aim.point is not None:
        look, x = LOOK_POINT, np.array(aim.point)
    if aim is not None and aim.toward is not None:
        look, x = LOOK_TOWARD, np.array(aim.toward)
    # a parsed ``Target`` (an aim, or an ``Axis`` exactly along a base axis: ``along``), or
    # a pose
    p = target.position if hasattr(target, "position") else target.translation
    ws.q[0][:] = q
    evaluate_region(
        a.kernel_chain.flat, np.array(said["bounds"]) if bounds is None else bounds,
        np.ones(6), cone[3], np.array(cone[:3]), look, x,
        np.ascontiguousarray(target.rotation), np.ascontiguousarray(p), ws, 0,
    )  # fmt: skip
    return ws.e[0], ws.A[0], ws.val[0, 1]


def _same_rows(rows, position, aimed, T, J, R_t=EYE) -> bool:
    """The compiled ``rows`` equal the tasks': ``position``'s (None: free) in the target
    frame ``R_t``, ``aimed``'s (an ``Axis`` or a ``LookAt``) and its measure; whether the
    axis lay outside its cone."""
    e, A, ori = rows
    if position is None:
        assert not e[:3].any() and not A[:3].any()
    else:
        np.testing.assert_allclose(R_t @ e[:3], -position.residual(T), rtol=0, atol=EXACT)
        np.testing.assert_allclose(R_t @ A[:3], position.jacobian(T, J), rtol=0, atol=EXACT)
    np.testing.assert_allclose(e[3:], -aimed.residual(T), rtol=0, atol=EXACT)
    np.testing.assert_allclose(A[3:], aimed.jacobian(T, J), rtol=0, atol=1e-10)
    m = aimed.measure(T, 0.0, 0.0)
    assert ori == pytest.approx(m.orientation, abs=EXACT)
    return m.orientation > 0.0


def _axis_case(a, rng, k, within, bounds=None):
    """(q, T, [Position, Axis]): a random configuration, a point near its tip (within
    ``bounds``), an axis (the tip's z every third case) and a direction (the tip's z every
    other case)."""
    q = a.random_q(rng)
    T = a.fk(q)
    axis = (0.0, 0.0, 1.0) if k % 3 == 0 else rng.normal(size=3)
    direction = rng.normal(size=3) if k % 2 else T.rotation @ np.array([0.0, 0.0, 1.0])
    near = T.translation + rng.normal(scale=0.02, size=3)
    return q, T, [Position(near, bounds=bounds), Axis(axis, direction, within)]


@pytest.mark.parametrize("robot", ["panda", "ur5", "so101"])
@pytest.mark.parametrize("within", [0.0, 0.05, 0.6])
def test_the_cone_rows_are_the_axis_task(robot, within):
    """A position with an axis in a cone, lowered (``lower``) to a pose, bounds and a cone:
    the compiled rows equal the two tasks' residuals and Jacobians, stacked."""
    a = model(robot)
    ws = workspace(a.dof, 1, a.kernel_chain.chain.joint_kind.shape[0])
    rng = np.random.default_rng(5)
    outside = 0
    for k in range(12):
        q, T, tasks = _axis_case(a, rng, k, within)
        target, said = lower(Problem(tuple(tasks)))
        # exactly along a coordinate axis it lowers to a free spin: the cone rows all the same
        aim = getattr(target, "aim", None)
        cone = (*tasks[1].axis, within) if aim is None else aim.cone
        rows = _rows(a, ws, q, target, said, cone, bounds=np.zeros(6))  # the position exact
        outside += _same_rows(rows, tasks[0], tasks[1], T, a.jacobian(q), target.rotation)
    assert outside >= 4  # the cone's rows were tested outside it, not only at zero


@pytest.mark.parametrize("robot", ["panda", "ur5", "so101"])
@pytest.mark.parametrize("within", [0.0, 0.05, 0.6])
def test_the_look_rows_are_the_look_at_task(robot, within):
    """A look-at lowered to a cone around the line of sight (``look``): the compiled rows
    equal the ``LookAt`` task's residual and Jacobian, whose direction moves with the tip's
    position too, and its measure."""
    a = model(robot)
    ws = workspace(a.dof, 1, a.kernel_chain.chain.joint_kind.shape[0])
    rng = np.random.default_rng(8)
    outside = 0
    for k in range(12):
        q = a.random_q(rng)
        T = a.fk(q)
        axis = (0.0, 0.0, 1.0) if k % 3 == 0 else rng.normal(size=3)
        point = T.translation + rng.normal(scale=0.4, size=3)
        if k % 4 == 1:  # nearly along the tip's own z axis: the near-parallel branch
            point = T.translation + 0.3 * T.rotation[:, 2] + rng.normal(scale=1e-14, size=3)
        task = LookAt(point, axis, within)
        target, said = lower(Problem((task,)))
        assert np.array_equal(target.aim.point, point)
        outside += _same_rows(_rows(a, ws, q, target, said), None, task, T, a.jacobian(q))
    assert outside >= 4


@pytest.mark.parametrize("robot", ["panda", "ur5", "so101"])
@pytest.mark.parametrize("within", [0.0, 0.05, 0.6])
def test_the_toward_rows_are_a_box_and_the_axis_task(robot, within):
    """A position within a box with an axis in a cone, lowered to the identity rotation,
    the box's bounds and the cone around the direction itself (``toward``): the compiled
    rows equal the ``Position`` task's (its dead zone) and the ``Axis`` task's."""
    a = model(robot)
    ws = workspace(a.dof, 1, a.kernel_chain.chain.joint_kind.shape[0])
    rng = np.random.default_rng(12)
    outside = 0
    for k in range(12):
        q, T, tasks = _axis_case(a, rng, k, within, bounds=(0.01, 0.005, math.inf))
        target, said = lower(Problem(tuple(tasks)))
        assert np.array_equal(target.rotation, np.eye(3))
        rows = _rows(a, ws, q, target, said)
        outside += _same_rows(rows, tasks[0], tasks[1], T, a.jacobian(q))
    assert outside >= 4
