"""A cone, a look-at's point and a direction belong to the target (``Target.aim``): the
keywords ``cone=``, ``look_at=`` and ``toward=`` are read once into the parsed target's aim,
the same as what ``armik.Axis`` and ``armik.LookAt`` lower to, and the options hold none of
them."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.options import Options
from armik.solve.read import read, read_batch, read_path
from armik.targets.aim import Aim
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target
from tests.conftest import arm as bundled

BUDGET = {"iteration_budget": 3000}


def test_the_options_hold_no_part_of_the_target():
    assert not {f.name for f in dataclasses.fields(Options)} & {"cone", "look_at", "toward"}


def test_the_keywords_and_the_tasks_are_one_target_with_its_aim():
    panda = bundled("panda")
    T = panda.fk(panda.middle)
    p, point = T.translation, T.translation + [0.0, 0.0, -0.3]
    asked = {"cone": (0, 0, 2, 0.1), "look_at": point, "bounds": (0.01,) * 3 + (0.0,) * 3}
    by_keywords = read(panda.kinematics, T, None, "auto", asked)
    target = by_keywords.target
    assert type(target) is Target and target.aim == Aim((0.0, 0.0, 1.0), 0.1, tuple(point))
    assert by_keywords.opts.bounds == asked["bounds"]  # the options: the rest
    tasks = [armik.Position(p, bounds=(0.01,) * 3), armik.LookAt(point, (0, 0, 1), 0.1)]
    by_tasks = read(panda.kinematics, tasks, None, "auto", {})
    assert by_tasks.target.aim == target.aim and by_tasks.opts == by_keywords.opts
    # a direction whatever the rotation; a batch's and a path's targets share one aim
    toward = read(panda.kinematics, p, None, "auto", {"cone": (0, 0, 1, 0.2), "toward": (0, 0, -2)})
    assert toward.target.aim == Aim((0.0, 0.0, 1.0), 0.2, None, (0.0, 0.0, -1.0))
    poses = [T, T]
    batch = read_batch(panda.kinematics, poses, None, "auto", asked).target
    path = read_path(panda.kinematics, poses, None, "auto", "follow", asked)[0].target
    for many in (batch, path):
        assert type(many) is TargetBatch and many.aim == target.aim
        assert many.target(1).aim == target.aim and many[1:].aim == target.aim


def test_an_aim_keyword_answers_as_the_task_it_spells():
    panda = bundled("panda")
    rng = np.random.default_rng(5)
    for _ in range(4):
        T = panda.fk(panda.random_q(rng))
        z = T.rotation[:, 2]
        point = T.translation + 0.4 * z
        tasks = [armik.Position(T.translation), armik.LookAt(point, (0, 0, 1), 0.05)]
        by_tasks = panda.solve(tasks, q0=panda.middle, **BUDGET)
        pose = (T.translation, np.eye(3))  # the keyword spelling: the rotation is not read
        sight = {"cone": (0, 0, 1, 0.05), "look_at": point}
        by_keywords = panda.solve(pose, q0=panda.middle, **sight, **BUDGET)
        assert by_tasks.success and by_keywords.success
        np.testing.assert_array_equal(by_tasks.q, by_keywords.q)
        batch = panda.solve_batch([pose] * 2, q0=panda.middle, workers=1, **sight, **BUDGET)
        np.testing.assert_array_equal(batch.q[1], by_keywords.q)


def test_an_aim_said_twice_or_where_it_cannot_be_kept_is_refused_by_name():
    panda = bundled("panda")
    T = panda.fk(panda.middle)
    axis = armik.Axis((0, 0, 1), T.rotation[:, 2], 0.1)
    with pytest.raises(armik.OptionError, match="cone is given both by the task and as an"):
        panda.solve([armik.Position(T.translation), axis], cone=(0, 0, 1, 0.2))
    elbow = armik.Position(T.translation, frame="panda_link4")  # no compiled form
    with pytest.raises(armik.OptionError, match="cone does not apply to a list of tasks"):
        panda.solve([elbow, axis], cone=(0, 0, 1, 0.2))
    with pytest.raises(armik.OptionError, match="unknown option 'cones'.*'cone'"):
        panda.solve(T, cones=(0, 0, 1, 0.2))


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_a_global_path_checks_its_steps_against_the_aimed_targets(name):
    """The plan's check for a jump hidden in a step solves the pose halfway with the path's
    aim (a cone leaves the spin free): a waypoint given twice, reached by following without
    a move, is reached by the plan too, never refused as a hidden jump."""
    a = bundled(name)
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(4):
        T = a.fk(a.random_q(rng))
        aimed = {"cone": (0, 0, 1, 0.1), **BUDGET}
        followed = a.solve_path([T, T], a.middle, **aimed)
        planned = a.solve_path([T, T], a.middle, plan="global", **aimed)
        if followed.success[1]:
            assert planned.success[1], planned[1].reason
            checked += 1
    assert checked >= 2


def test_the_prepared_plan_measures_a_miss_against_the_aim():
    """A prepared solve whose answer the general verdict decides (a miss under a small
    budget) is measured against the target with its aim: outside the cone what the
    verdict measured, the angle of the tip's axis to its direction less the cone's; its
    distance the angle to the pose's rotation (an FK here)."""
    panda = bundled("panda")
    rng = np.random.default_rng(2)
    for _ in range(3):
        T = panda.fk(panda.random_q(rng))
        asked = {"cone": (0, 0, 1, 0.05), "iteration_budget": 3, "max_restarts": 0}
        r = panda.solve(T, q0=panda.middle, **asked)
        tip = panda.fk(r.q)
        angle = float(np.arccos(np.clip(tip.rotation[:, 2] @ T.rotation[:, 2], -1.0, 1.0)))
        assert not r.success and r.measured is not None, r.reason
        geodesic = float(np.linalg.norm(pin.log3(tip.rotation.T @ T.rotation)))
        assert r.orientation_error == pytest.approx(geodesic, abs=1e-9)
        assert r.measured[1] == pytest.approx(max(angle - 0.05, 0.0), abs=1e-9)
        distance = float(np.linalg.norm(tip.translation - T.translation))
        assert r.position_error == pytest.approx(distance, abs=1e-9)


def test_a_cone_alone_on_a_position_is_refused_with_the_way_to_say_it():
    """``cone=`` without ``look_at=`` or ``toward=`` on a position: no rotation carries
    the axis anywhere (it was held about the base frame's own axis); named, on every
    route, with ``toward=`` spelled out. On a pose it is the rotation's axis, as before."""
    a = bundled("ur5")
    T = a.fk(a.middle)
    p = T.translation
    for call in (
        lambda: a.solve(p, cone=(0, 0, 2, 0.1)),
        lambda: a.solve_all(p, cone=(0, 0, 2, 0.1)),
        lambda: a.solve_batch([p, p], cone=(0, 0, 2, 0.1), progress=False),
        lambda: a.solve_path([p, p], a.middle, cone=(0, 0, 2, 0.1)),
    ):
        with pytest.raises(armik.OptionError, match=r"toward=\(0, 0, 1\)") as info:
            call()
        assert info.value.option == "cone" and "position target" in str(info.value)
    assert a.solve(p, cone=(0, 0, 1, 0.1), toward=(0, 0, -1)).success
    assert a.solve(T, cone=(0, 0, 1, 0.1)).success


def test_position_only_beside_an_aim_is_refused_with_joints_the_task_solver_holds():
    """``position_only=True`` beside ``cone=``/``toward=`` is refused by name; with a joint
    of a 6-joint arm held (the task solver's: the aimed target becomes its tasks) it was
    dropped unsaid, the request solved as if it had not been given."""
    ur5 = bundled("ur5")
    q = np.array([0.2, -1.0, 1.4, -0.6, 1.1, 0.3])
    T = ur5.fk(q)
    p = T.translation
    aim = {"cone": (0, 0, 1, 0.1), "toward": tuple(T.rotation[:, 2])}
    kw = {**aim, "position_only": True, "hold": {"wrist_3_joint": float(q[5])}}
    for call in (
        lambda: ur5.solve(p, q0=q, **kw),
        lambda: ur5.solve_batch([p, p], q0=q, progress=False, **kw),
        lambda: ur5.solve_path([p, p], q, **kw),
    ):
        with pytest.raises(
            armik.OptionError, match="position_only does not apply to a target"
        ) as e:
            call()
        assert e.value.option == "position_only"


def test_rotation_bounds_beside_an_aim_are_refused_not_dropped_unread():
    """A cone replaces the rotation's components: bounds of 0.01 rad on them beside a cone
    of 0.5 rad were dropped, and an answer 0.2 rad off the target's rotation was a success.
    They are refused by name on every route; 0 and inf (no width, free) say nothing beside a
    cone and are taken, as the lowered task lists and the command line give them."""
    import pinocchio as pin

    ur5 = bundled("ur5")
    q = ur5.random_q(2)
    T = ur5.fk(q)
    X = pin.SE3(T.rotation @ pin.exp3(np.array([0.2, 0.0, 0.0])), T.translation)
    point = T.translation + 0.3 * T.rotation[:, 2]
    box = (0.0, 0.0, 0.0, 0.01, 0.01, 0.01)
    cone = {"cone": (0.0, 0.0, 1.0, 0.5), "bounds": box}
    calls = [
        lambda: ur5.solve(X, q0=q, **cone),
        lambda: ur5.solve(T.translation, q0=q, toward=T.rotation[:, 2], **cone),
        lambda: ur5.solve_batch([X, X], q0=q, **cone),
        lambda: ur5.solve_path([X, X], q, **cone),
        lambda: ur5.solve(
            [armik.Position(T.translation), armik.LookAt(point, (0, 0, 1), 0.5)], bounds=box
        ),
    ]
    for call in calls:
        with pytest.raises(armik.OptionError, match=r"bound the rotation's components"):
            call()
    for rotation in ((0.0, 0.0, 0.0), (np.inf, np.inf, np.inf)):
        r = ur5.solve(X, q0=q, cone=(0, 0, 1, 0.5), bounds=(0.01, 0.01, 0.01, *rotation))
        assert r.success, r.reason


def test_huge_cone_and_toward_keywords_are_their_direction_without_a_numpy_warning():
    """``cone=`` and ``toward=`` with components whose squares overflow are read as their
    direction, as ``armik.Axis`` reads one: they were refused as no "non-zero" axis, with a
    numpy overflow warning."""
    import warnings

    from armik.targets.aim import aim_of

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for huge, plain in (
            ((1e308, 1e308, 0.0), (1.0, 1.0, 0.0)),
            ((-1.7e308, 1.7e308, 1.7e308), (-1.0, 1.0, 1.0)),
            ((0.0, 0.0, 1e200), (0.0, 0.0, 1.0)),
        ):
            unit = np.array(plain) / np.linalg.norm(plain)
            aim = aim_of(cone=(*huge, 0.1))
            assert np.allclose(aim.axis, unit, atol=1e-15) and aim.within == 0.1
            along = aim_of(cone=(0, 0, 1, 0.1), toward=huge)
            assert np.allclose(along.toward, unit, atol=1e-15)
            assert np.allclose(along.toward, armik.Axis((0, 0, 1), huge).direction, atol=1e-15)
        for zero in ((0.0, 0.0, 0.0), (1e-10, 0.0, 0.0)):
            with pytest.raises(armik.OptionError, match="non-zero"):
                aim_of(cone=(*zero, 0.1))
            with pytest.raises(armik.OptionError, match="non-zero"):
                aim_of(cone=(0, 0, 1, 0.1), toward=zero)


@pytest.mark.parametrize("far", [(2e6, 0.0, 0.0), (1e200, 1e200, 0.0), (0.0, -1e160, 0.0)])
def test_a_look_at_point_beyond_a_million_metres_is_refused_by_name(far):
    """A point farther than a target position may be (1e6 m a coordinate) is refused in both
    spellings: at 1e160 m and beyond, the line of sight from the tip overflowed, the verdict
    measured it as no direction at all, any axis "looking at" it, and ``[Position(p, box),
    LookAt(far)]`` was a success with the tool's axis 1.5 rad off the point."""
    import warnings

    ur5 = bundled("ur5")
    p = ur5.fk(ur5.random_q(1)).translation
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(armik.TargetError, match="LookAt point .* beyond 1e\\+06 m"):
            ur5.solve([armik.Position(p, bounds=(0.1,) * 3), armik.LookAt(far)])
        with pytest.raises(armik.OptionError, match="look_at .* beyond 1e\\+06 m") as got:
            ur5.solve(p, look_at=far, cone=(0, 0, 1, 0.0), bounds=(0.1,) * 3 + (0,) * 3)
        assert got.value.option == "look_at"
        with pytest.raises(armik.OptionError, match="look_at .* beyond 1e\\+06 m"):
            ur5.solve(p, look_at=tuple(map(float, far)), cone=(0, 0, 1, 0.0))
    # a point a million metres away is taken, and looked at
    point = np.array([1e6, 0.0, 0.0])
    r = ur5.solve([armik.Position(p, bounds=(0.1,) * 3), armik.LookAt(point)], **BUDGET)
    assert r.success, r.reason
    F = ur5.fk(r.q)
    sight = point - F.translation
    assert float(F.rotation[:, 2] @ sight) >= np.linalg.norm(sight) * np.cos(2e-6)


@pytest.mark.parametrize("spin", [0.0, np.inf])
def test_an_aimed_target_with_a_held_joint_takes_rotation_bounds_of_zero_or_inf(spin):
    """A held joint the compiled path cannot hold sends an aimed target to the task solver
    as the tasks it lowers from (``read_aim.aimed_tasks``): rotation bounds of inf, which say
    nothing beside a cone as 0 says nothing, were read as more than those tasks say and the
    solve refused, naming a 7-joint arm's closed form."""
    ur5 = bundled("ur5")
    q = ur5.random_q(2)
    T = ur5.fk(q)
    p, z = T.translation, T.rotation[:, 2]
    point = p + 0.3 * z
    hold = {"shoulder_pan_joint": float(q[0])}
    bounds = (0.05,) * 3 + (spin,) * 3
    for aim, along in (
        ({"look_at": point, "cone": (0, 0, 1, 0.0)}, None),
        ({"toward": z, "cone": (0, 0, 1, 0.01)}, z),
    ):
        r = ur5.solve(p, q0=ur5.middle, bounds=bounds, hold=hold, **aim, **BUDGET)
        assert r.success, r.reason
        F = ur5.fk(r.q)
        assert abs(r.q[0] - q[0]) <= 1e-9
        assert np.all(np.abs(F.translation - p) <= 0.05 + 1e-6)
        sight = point - F.translation if along is None else along
        within = aim["cone"][3]
        cos = float(F.rotation[:, 2] @ sight) / np.linalg.norm(sight)
        assert cos >= np.cos(within + 2e-6)


@pytest.mark.parametrize("spin", [math.nan, -math.inf, 0.1])
def test_an_aimed_target_with_a_held_joint_refuses_rotation_bounds_that_are_no_bounds(spin):
    """NaN, -inf, or a finite width beside the aim: refused by name with a held joint as
    without one (NaN and -inf were read as saying nothing, dropped, and solved)."""
    ur5 = bundled("ur5")
    T = ur5.fk(ur5.random_q(2))
    p, z = T.translation, T.rotation[:, 2]
    for hold in ({"shoulder_pan_joint": 0.3}, {}):
        with pytest.raises(armik.OptionError, match="bounds"):
            ur5.solve(
                p,
                bounds=(0.05,) * 3 + (spin,) * 3,
                look_at=p + 0.3 * z,
                cone=(0, 0, 1, 0.0),
                hold=hold or None,
            )
