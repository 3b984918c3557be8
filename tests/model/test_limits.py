"""``with_limits`` on every joint kind: a revolute or continuous joint's limits are in rad,
and one beyond four turns each way (degrees by mistake) is refused naming the joint, the
value and the radians meant, on one arm and on several tips, as ``hold=`` refuses a value
beyond the limits; a prismatic joint's are metres; a mimic joint is named as one."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armik
from armik.errors import ArmikWarning, JointError
from armik.model.limit_units import MAX_ANGLE

from ..conftest import arm, two_link_urdf, write_urdf


def test_degrees_on_a_revolute_joint_are_refused_by_name():
    panda = arm("panda")
    with pytest.raises(JointError, match=r"'panda_joint1'.*-170 rad.*\(-2\.96706, 2\.96706\)"):
        panda.with_limits({"panda_joint1": (-170, 170)})
    with pytest.raises(JointError, match="'panda_joint4'.*90 rad"):
        panda.with_limits({"panda_joint4": (0, 90)})
    # as hold= refuses the value itself
    with pytest.raises(JointError, match="panda_joint1"):
        panda.solve(panda.fk(panda.middle), hold={"panda_joint1": 170.0})


def test_radians_and_no_limit_are_taken():
    panda = arm("panda")
    wide = panda.with_limits({"panda_joint1": (-MAX_ANGLE, MAX_ANGLE), "panda_joint2": (-1, 1)})
    assert wide.kinematics.lower[0] == -MAX_ANGLE and wide.kinematics.upper[1] == 1.0
    free = panda.with_limits({"panda_joint1": (-math.inf, math.inf)})
    assert np.isinf(free.kinematics.lower[0]) and np.isinf(free.kinematics.upper[0])


def test_every_joint_kind_of_a_scara():
    scara = arm("scara")  # shoulder, elbow revolute; quill prismatic; tool_roll continuous
    with pytest.raises(JointError, match="'tool_roll'.*360 rad.*of a continuous joint"):
        scara.with_limits({"tool_roll": (-360, 360)})
    with pytest.raises(JointError, match="'elbow'"):
        scara.with_limits({"elbow": (-150, 150)})
    slid = scara.with_limits({"quill": (0.0, 30.0), "tool_roll": (-3.0, 3.0)})  # m; rad
    k = slid.joint_names.index("quill")
    assert slid.kinematics.upper[k] == 30.0
    assert slid.kinematics.upper[slid.joint_names.index("tool_roll")] == 3.0


def test_several_tips_refuse_degrees_too():
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    with pytest.raises(JointError, match="'panda_joint2'.*100 rad"):
        robot.with_limits({"panda_joint2": (-100, 100)})


def test_a_mimic_joint_is_named_as_one(tmp_path):
    limit = '<limit lower="-3.14159" upper="3.14159" effort="1" velocity="1"/>'
    text = two_link_urdf().replace(
        f'{limit}</joint>\n  <joint name="tool"',
        f'{limit}<mimic joint="j1" multiplier="1"/></joint>\n  <joint name="tool"',
    )
    a = armik.load(write_urdf(tmp_path, text), tip="tip")
    with pytest.raises(JointError, match="'j2'.*mimic"):
        a.with_limits({"j2": (-1.0, 1.0)})
    with pytest.raises(JointError, match="'j1'.*170 rad"):
        a.with_limits({"j1": (-170.0, 170.0)})


def test_a_multi_turn_joint_of_its_urdf_may_be_narrowed(tmp_path):
    text = two_link_urdf().replace('lower="-3.14159" upper="3.14159"', 'lower="-60" upper="60"', 1)
    with pytest.warns(ArmikWarning, match="'j1' has limits \\[-60, 60\\] rad, beyond four turns"):
        a = armik.load(write_urdf(tmp_path, text), tip="tip")
    assert a.kinematics.upper[0] == 60.0  # its own limits, beyond four turns
    assert a.with_limits({"j1": (-50.0, 50.0)}).kinematics.upper[0] == 50.0
    with pytest.raises(JointError, match="'j1'.*61 rad"):
        a.with_limits({"j1": (-61.0, 61.0)})
