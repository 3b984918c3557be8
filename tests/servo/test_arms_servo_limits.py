"""A servo on chains that share no joint (``Arms.servo``) reads ``velocity_limits`` and
``acceleration_limits`` over the robot's joints (``Arms.joint_names``), as the servo over
shared joints does: a number, one per robot joint, or a mapping by robot joint name, each
chain given its joints' part; the commanded sequence keeps each joint within its own."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.errors import JointError, OptionError
from armik.servo.streams import circle, violations

from ..test_arms import dual_irb120

DT = 0.002
START = np.array([0.0, 0.2, 0.2, 0.0, 0.8, 0.0])  # each IRB 120 of the cell


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def _track(cell, **limits):
    q0 = np.concatenate([START, START])
    TL, TR = cell.fk(q0, "l_tool0"), cell.fk(q0, "r_tool0")
    left = circle(TL, 300, DT, radius=0.1)
    right = circle(TR, 300, DT, radius=0.1)
    servo = cell.servo(q0, dt=DT, **limits)
    rec = servo.track([{"l_tool0": a, "r_tool0": b} for a, b in zip(left, right)])
    return q0, servo, rec


def _within(cell, q0, rec, vmax, amax) -> None:
    over = violations(q0, rec.q, cell.lower, cell.upper, vmax, amax, DT)
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}


def test_one_velocity_limit_per_robot_joint_is_split_onto_each_chain(cell):
    assert cell.dof == 12 and not cell.shared
    vmax = np.array([0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.25, 0.35, 0.45, 0.55, 0.65, 0.75])
    q0, servo, rec = _track(cell, velocity_limits=vmax.tolist(), acceleration_limits=10.0)
    np.testing.assert_array_equal(servo.velocity_limits, vmax)
    np.testing.assert_array_equal(servo.acceleration_limits, np.full(12, 10.0))
    np.testing.assert_array_equal(servo.servo("r_tool0").velocity_limits, vmax[6:])
    speed = np.abs(np.diff(np.vstack([q0, rec.q]), axis=0)) / DT
    assert (speed <= vmax + 1e-9).all()
    assert np.isclose(speed.max(axis=0), vmax).any()  # a limit binds: the test can fail
    _within(cell, q0, rec, vmax, np.full(12, 10.0))


def test_a_mapping_by_robot_joint_name_reaches_the_chain_that_has_the_joint(cell):
    left, right = cell.chain("l_tool0").joint_names, cell.chain("r_tool0").joint_names
    q0, servo, rec = _track(
        cell, velocity_limits={right[0]: 0.1, left[2]: 0.2}, acceleration_limits={right[5]: 3.0}
    )
    vmax, amax = servo.velocity_limits, servo.acceleration_limits
    names = list(cell.joint_names)
    assert vmax[names.index(right[0])] == 0.1 and vmax[names.index(left[2])] == 0.2
    assert amax[names.index(right[5])] == 3.0
    assert (np.delete(amax, names.index(right[5])) == 20.0).all()  # the others the default's
    _within(cell, q0, rec, vmax, amax)


def test_one_number_holds_on_every_joint_of_both_chains(cell):
    q0, servo, rec = _track(cell, velocity_limits=0.4, acceleration_limits=8.0)
    np.testing.assert_array_equal(servo.velocity_limits, np.full(12, 0.4))
    _within(cell, q0, rec, np.full(12, 0.4), np.full(12, 8.0))


def test_one_chain_s_count_or_another_joint_is_refused_naming_the_robot_s(cell):
    q0 = np.concatenate([START, START])
    for name in ("velocity_limits", "acceleration_limits"):
        with pytest.raises(OptionError, match=r"one per joint of the robot \(12: ") as caught:
            cell.servo(q0, **{name: [1.0] * 6})
        assert caught.value.option == name and cell.joint_names[-1] in str(caught.value)
    with pytest.raises(JointError, match=r"\['wrist'\], not joints of this robot") as caught:
        cell.servo(q0, acceleration_limits={"wrist": 3.0})
    assert caught.value.joint == "wrist"
    with pytest.raises(OptionError, match="velocity_limits must be positive"):
        cell.servo(q0, velocity_limits=[1.0] * 11 + [-1.0])


@pytest.mark.parametrize("shared", [False, True])
def test_a_bad_q0_is_refused_as_q0_naming_the_joints_outside(cell, shared):
    """Chains side by side and over shared joints alike: q0 (named so, not ``q``) must
    hold one finite value per robot joint, None included, and a q0 outside the limits is
    refused naming each joint outside and its limits."""
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"]) if shared else cell
    for bad in (None, np.zeros(3), "abc"):
        with pytest.raises(OptionError, match="^q0 must") as e:
            robot.servo(bad)
        assert e.value.option == "q0"
    q0 = robot.middle.copy()
    q0[1] = robot.upper[1] + 0.1
    with pytest.raises(OptionError, match=f"within the joint limits.*{robot.joint_names[1]}"):
        robot.servo(q0)
