"""A position with the tip's axis in a cone (``armik.Position`` with ``armik.Axis``), lowered
to a pose with ``Options.cone``: solved by the compiled step, measured by the verdict as the
``Axis`` task measures it on Pinocchio's FK; bad cones are named."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import OptionError

from ..conftest import arm
from .test_bounds import Independent


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return math.atan2(np.linalg.norm(np.cross(u, v)), float(u @ v))


def _cones(a: armik.Arm, rng, count: int, within: float, axis=(0.0, 0.0, 1.0)):
    """(tasks, q) with an answer: q's tip position, ``axis`` within ``within`` of a
    direction tilted from q's by up to 80 % of the cone."""
    out = []
    for _ in range(count):
        q = a.random_q(rng)
        T = a.fk(q)
        tilt = pin.exp3(rng.uniform(-1.0, 1.0, 3) * 0.8 * within / math.sqrt(3.0))
        d = tilt @ T.rotation @ np.array(axis)
        out.append(([armik.Position(T.translation), armik.Axis(axis, d, within)], q))
    return out


@pytest.mark.parametrize("name", ["ur5", "panda", "abb_irb120", "so101"])
def test_a_cone_is_solved_by_the_compiled_step_within_it(name):
    """Every success within the cone and on the point by yourdfpy's FK of the URDF."""
    a = arm(name)
    independent = Independent(a)
    rng = np.random.default_rng(11)
    for tasks, _ in _cones(a, rng, 10, 0.05):
        r = a.solve(tasks, iteration_budget=5000)
        assert r.success, r.reason
        position, axis = tasks
        assert r.solver == "dls" and "inside the region" in r.reason
        assert f"the tip's axis within its cone of {axis.within:.3g} rad" in r.reason
        T = independent.fk(r.q)
        assert np.linalg.norm(T.translation - position.p) <= 1e-6
        tilt = _angle(T.rotation @ axis.axis, axis.direction)
        assert tilt <= axis.within + 1e-6
        # the distance: the axis' angle to the direction; the verdict's: outside the cone
        assert r.orientation_error == pytest.approx(tilt, abs=1e-9)
        assert r.measured[1] == pytest.approx(max(tilt - axis.within, 0.0), abs=1e-9)
        assert a.within_limits(r.q)


def test_a_slanted_axis_and_an_exact_direction_take_the_cone_too():
    """Any axis of the tip, and ``within=0`` on an axis that is not one of the tip's own:
    the cone's rows, not a free spin."""
    a = arm("panda")
    rng = np.random.default_rng(12)
    axis = np.array([0.6, 0.0, 0.8])
    for within in (0.0, 0.2):
        for tasks, _ in _cones(a, rng, 5, max(within, 1e-9), axis):
            tasks[1] = armik.Axis(axis, tasks[1].direction, within)
            r = a.solve(tasks, iteration_budget=5000)
            assert r.success and r.solver == "dls", r.reason
            tilt = _angle(a.fk(r.q).rotation @ axis, tasks[1].direction)
            assert tilt <= within + 1e-6


def test_an_answer_inside_the_cone_needs_no_step():
    a = arm("ur5")
    q = a.random_q(np.random.default_rng(13))
    T = a.fk(q)
    near = pin.exp3(np.array([0.02, 0.0, 0.0])) @ T.rotation[:, 2]  # 0.02 rad off, cone 0.05
    r = a.solve([armik.Position(T.translation), armik.Axis((0, 0, 1), near, 0.05)], q0=q)
    assert r.success and r.iterations == 0 and np.array_equal(r.q, q)


def test_the_cone_option_on_a_pose_is_the_tasks():
    """``cone=`` on a pose target: what the task list lowers to, the same answer."""
    a = arm("panda")
    rng = np.random.default_rng(14)
    for tasks, _ in _cones(a, rng, 4, 0.1):
        position, axis = tasks
        by_tasks = a.solve(tasks, seed=3)
        R = pin.exp3(_rotation_vector(axis.axis, axis.direction))
        by_option = a.solve(pin.SE3(R, position.p), cone=(*axis.axis, 0.1), seed=3)
        assert by_tasks.success and by_option.success
        np.testing.assert_allclose(by_tasks.q, by_option.q, atol=1e-9)


def _rotation_vector(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    axis = np.cross(u, v)
    return _angle(u, v) * axis / np.linalg.norm(axis)


def test_a_batch_of_cones_is_the_loop_of_solves():
    a = arm("so101")
    rng = np.random.default_rng(15)
    rows = [tasks for tasks, _ in _cones(a, rng, 8, 0.05)]
    b = a.solve_batch(rows, workers=1, progress=False, iteration_budget=5000)
    assert b.success.all()
    for i, tasks in enumerate(rows):
        r = a.solve(tasks, iteration_budget=5000)
        np.testing.assert_allclose(b.q[i], r.q, atol=1e-12)
        assert _angle(a.fk(b.q[i]).rotation[:, 2], tasks[1].direction) <= 0.05 + 1e-6


def test_a_batch_of_cones_with_a_held_joint_is_the_loop_of_solves():
    """Each row holds its cone, as its own solve does, where the row's lowered pose made
    a held joint's task held the exact rotation, its aim dropped."""
    a = arm("ur5")
    rng = np.random.default_rng(11)
    cones = _cones(a, rng, 3, 0.1)
    hold = {a.joint_names[-1]: float(cones[0][1][-1])}
    rows = [tasks for tasks, _ in cones]
    b = a.solve_batch(rows, workers=1, progress=False, hold=hold, iteration_budget=5000)
    for i, tasks in enumerate(rows):
        r = a.solve(tasks, hold=hold, iteration_budget=5000)
        assert r.success and b.success[i]
        np.testing.assert_allclose(b.q[i], r.q, atol=1e-12)
        assert _angle(a.fk(b.q[i]).rotation[:, 2], tasks[1].direction) <= 0.1 + 1e-6


def test_an_unreachable_cone_fails_with_a_reason():
    a = arm("ur5")
    far = [armik.Position((3.0, 0.0, 0.5)), armik.Axis((0, 0, 1), (0, 0, -1), 0.1)]
    r = a.solve(far)
    assert not r.success and r.status == "unreachable" and "reach" in r.reason


@pytest.mark.parametrize(
    "cone", [(0.0, 0.0, 0.0, 0.1), (0.0, 0.0, 1.0, -0.1), (0.0, 0.0, 1.0, 4.0),
             (0.0, math.nan, 1.0, 0.1), (0.0, 0.0, 1.0), "down"],
)  # fmt: skip
def test_bad_cones_are_named(cone):
    with pytest.raises(OptionError, match="cone must be") as info:
        arm("ur5").solve(np.eye(4), cone=cone)
    assert info.value.option == "cone"


def test_an_axis_alone_is_a_cone_with_the_position_free():
    """``[armik.Axis(...)]``: the tip's direction only, lowered to a cone with unbounded
    position rows; every success within the cone by yourdfpy's FK."""
    a = arm("so101")
    independent = Independent(a)
    rng = np.random.default_rng(16)
    for _ in range(8):
        d = a.fk(a.random_q(rng)).rotation[:, 2]  # a direction the tool takes somewhere
        r = a.solve([armik.Axis((0, 0, 1), d, 0.05)], iteration_budget=5000)
        assert r.success and r.solver == "dls" and r.position_error is None, r.reason
        assert _angle(independent.fk(r.q).rotation[:, 2], d) <= 0.05 + 1e-6


@pytest.mark.parametrize("name", ["ur5", "so101"])
def test_a_look_at_from_a_held_position_is_the_cone_around_the_line_of_sight(name):
    """``[armik.Position(p), armik.LookAt(point, axis, within)]``: the cone around the line
    from the tip to the point, solved by the compiled step, and the look-at itself holding
    on Pinocchio's FK (the task's measure) and on yourdfpy's."""
    a = arm(name)
    independent = Independent(a)
    rng = np.random.default_rng(17)
    for _ in range(8):
        T = a.fk(a.random_q(rng))
        point = T.translation + rng.uniform(0.2, 1.0) * T.rotation[:, 2]
        point = point + rng.normal(scale=0.01, size=3)
        tasks = [armik.Position(T.translation), armik.LookAt(point, (0, 0, 1), 0.05)]
        r = a.solve(tasks, iteration_budget=5000)
        assert r.success and r.solver == "dls", r.reason
        assert all(t.measure(a.fk(r.q), 1e-6, 1e-6).within for t in tasks)
        X = independent.fk(r.q)
        assert np.linalg.norm(X.translation - T.translation) <= 1e-6
        sight = (point - X.translation) / np.linalg.norm(point - X.translation)
        assert _angle(X.rotation[:, 2], sight) <= 0.05 + 1e-6


def test_a_look_at_of_the_point_it_stands_on_is_refused_by_name():
    a = arm("ur5")
    p = a.fk(a.middle).translation
    with pytest.raises(armik.TargetError, match="no direction is left"):  # no line of sight
        a.solve([armik.Position(p), armik.LookAt(p, (0, 0, 1), 0.0)])


_FREEING = [{"position_only": True}, {"weights": (1, 1, 1, 0, 0, 0)}, {"weights": (1,) * 5 + (0,)}]


@pytest.mark.parametrize("option", _FREEING)
def test_an_option_that_frees_an_aim_is_refused_in_either_spelling(option):
    """``position_only`` or a rotation weight of 0 with an aim: the verdict measures the
    axis whatever they say, so they would be overruled unseen. One rule refuses them by
    name for a keyword cone and for an Axis in a task list alike, on solve, batches and
    paths, with the same words."""
    a = arm("ur5")
    T = a.fk(a.middle)
    z = T.rotation[:, 2]
    tasks = [armik.Position(T.translation), armik.Axis((0, 0, 1), z, 0.05)]
    cone = {"cone": (0, 0, 1, 0.05), "toward": z}
    (name,) = option
    said = []
    for call in (
        lambda: a.solve(tasks, **option),
        lambda: a.solve(T.translation, **cone, **option),
        lambda: a.solve_batch([tasks, tasks], progress=False, **option),
        lambda: a.solve_batch([T.translation] * 2, progress=False, **cone, **option),
        lambda: a.solve_path([tasks, tasks], a.middle, **option),
        lambda: a.solve_path([T.translation] * 2, a.middle, **cone, **option),
    ):
        with pytest.raises(OptionError, match=f"{name} does not apply to a target with an aim"):
            call()
        said.append(str(pytest.raises(OptionError, call).value))
        assert pytest.raises(OptionError, call).value.option == name
    assert len(set(said)) == 1


def test_weights_that_free_no_rotation_go_with_an_aim_in_either_spelling():
    """Position weights beside an aim (an axis pointed from anywhere along x) are taken in
    either spelling: the answers are the same, verified with the axis in its cone."""
    a = arm("ur5")
    T = a.fk(a.middle)
    z = T.rotation[:, 2]
    tasks = [armik.Position(T.translation), armik.Axis((0, 0, 1), z, 0.05)]
    weights = (0, 1, 1, 1, 1, 1)
    by_tasks = a.solve(tasks, weights=weights, seed=1)
    by_keywords = a.solve(T.translation, cone=(0, 0, 1, 0.05), toward=z, weights=weights, seed=1)
    assert by_tasks.success and by_keywords.success
    np.testing.assert_array_equal(by_tasks.q, by_keywords.q)
