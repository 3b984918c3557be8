"""``track`` reads every target before its first tick: a bad one is refused naming its
tick (and tip), the servo left where it was; one target given alone is refused with the
way round (``step``, or a list)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import OptionError, TargetError
from armik.servo.streams import START

from ..test_arms import dual_irb120


def test_one_target_alone_is_refused_with_the_way_round():
    ur5, q0 = armik.load("ur5"), START["ur5"]
    T0 = ur5.fk(q0)
    for one in (T0, T0.homogeneous, list(T0.translation), T0.translation, armik.Pose(T0)):
        with pytest.raises(OptionError, match=r"use step\(\.\.\.\) .* or pass a list"):
            ur5.servo(q0).track(one)
    with pytest.raises(OptionError, match="at least one"):
        ur5.servo(q0).track([])


def test_no_sequence_at_all_is_not_called_one_target():
    """None or a string is no target: the refusal says what was given, not that one target
    (on several tips, one mapping) came alone."""
    ur5, q0 = armik.load("ur5"), START["ur5"]
    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    both = np.concatenate([START["abb_irb120"]] * 2)
    for servo in (ur5.servo(q0), cell.servo(both)):
        for nothing in (None, "targets"):
            with pytest.raises(OptionError, match="sequence of targets.*got (NoneType|str)") as e:
                servo.track(nothing)
            assert "alone" not in str(e.value)
    T = cell.fk(both, "l_tool0")  # one pose, not a mapping, on several tips
    with pytest.raises(OptionError, match=r"each a mapping \{tip: target\}.*got SE3") as e:
        cell.servo(both).track(T)
    assert "alone" not in str(e.value)


def test_a_bad_target_is_named_by_its_tick_before_any_tick_runs():
    ur5, q0 = armik.load("ur5"), START["ur5"]
    T0 = ur5.fk(q0)
    H = np.array(
        [pin.SE3(T0.rotation, T0.translation + [0, 0.001 * k, 0]).homogeneous for k in range(6)]
    )
    H[3] = np.nan
    servo = ur5.servo(q0)
    with pytest.raises(TargetError, match="^target 3: .*NaN"):
        servo.track(H)
    np.testing.assert_array_equal(servo.q, q0)  # no tick ran
    np.testing.assert_array_equal(servo.step(T0).q, ur5.servo(q0).step(T0).q)
    mixed = [T0, T0.translation, "nonsense"]
    with pytest.raises(TargetError, match="^target 2: "):
        servo.track(mixed)
    # the good ones are followed as ``step`` follows them
    rec = ur5.servo(q0).track(list(H[:3]) + [armik.Pose(T0)])
    fresh = ur5.servo(q0)
    steps = [fresh.step(t) for t in list(H[:3]) + [armik.Pose(T0)]]
    np.testing.assert_array_equal(rec.q, np.array([s.q for s in steps]))


@pytest.mark.parametrize("tips", [["l_tool0", "r_tool0"], ["panda_link4", "panda_hand"]])
def test_several_tips_track_reads_every_mapping_first(tips):
    robot = (
        armik.load(dual_irb120(), tips=tips)
        if tips[0] == "l_tool0"
        else armik.load("panda", tips=tips)
    )
    q0 = robot.middle
    goal = {tip: robot.fk(q0, tip).translation for tip in robot.tips}
    servo = robot.servo(q0)
    with pytest.raises(OptionError, match=r"use step\(\.\.\.\)"):
        servo.track(goal)
    bad = dict(goal)
    bad[tips[1]] = [np.nan, 0.0, 0.0]
    with pytest.raises(TargetError, match=rf"^target 2: the target of tip '{tips[1]}'"):
        servo.track([goal, goal, bad])
    with pytest.raises(TargetError, match="^target 1: "):
        servo.track([goal, {tips[0]: goal[tips[0]]}])
    np.testing.assert_array_equal(servo.q, q0)  # no tick ran
    assert servo.track([goal] * 3).q.shape == (3, robot.dof)
