"""Joint values in degrees by mistake are said, as ``with_limits`` refuses limits in degrees
(``limit_units``): a revolute joint's value beyond four turns each way and beyond its
limits is named with its radians, in q0's clipping warning (``solve``, ``solve_batch``, a
robot's ``solve``, the command line), for a ``Posture``'s reference (``prefer=``,
``secondary=``), and where ``fk`` or ``jacobian`` is given one. A value merely outside the
limits, and a joint without limits (continuous) at many turns, are not degrees."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import armik
from armik.errors import ArmikWarning
from armik.tools.cli import main

from ..conftest import arm, two_link_urdf, write_urdf

DEGREES = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # a UR5 posture, in degrees
SAID = [  # each joint beyond four turns and its limits, with its radians
    f"{name} {v:g} ({math.radians(v):.6g} rad)"
    for name, v in zip(arm("ur5").joint_names, DEGREES)
    if v
]


def said(record) -> list[str]:
    return [str(w.message) for w in record if issubclass(w.category, ArmikWarning)]


def assert_said_in_radians(texts: list[str]) -> None:
    """One warning, naming every joint in degrees and its radians."""
    assert len(texts) == 1, texts
    assert "radians are meant" in texts[0], texts[0]
    assert all(part in texts[0] for part in SAID), texts[0]


@pytest.fixture(scope="module")
def ur5():
    return arm("ur5")


@pytest.fixture(scope="module")
def target(ur5):
    return ur5.fk(np.radians(DEGREES))


def test_q0_in_degrees_is_said_with_its_radians(ur5, target):
    """It said only 'q0 outside the joint limits was clipped into them: ...'."""
    for solve in (
        lambda: ur5.solve(target, q0=DEGREES),
        lambda: ur5.solve_all(target, q0=DEGREES),
        lambda: ur5.solve_batch([target, target], q0=[DEGREES, DEGREES]),
    ):
        with pytest.warns(ArmikWarning) as record:
            solve()
        assert_said_in_radians(said(record))
        assert "clipped" in said(record)[0]


def test_q0_merely_outside_the_limits_is_not_degrees(ur5, target):
    with pytest.warns(ArmikWarning, match="clipped") as record:
        ur5.solve(target, q0=[0.0, -7.0, 3.5, 0.0, 0.0, 0.0])  # 1.1 turns, past the limits
    assert not any("radians are meant" in text for text in said(record))


def test_a_robots_q0_in_degrees_is_said():
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    q0 = robot.middle.copy()
    q0[robot.joint_names.index("panda_joint2")] = 45.0
    with pytest.warns(ArmikWarning) as record:
        robot.solve({"panda_hand": robot.fk(robot.middle, "panda_hand")}, q0=q0)
    assert any("panda_joint2 45 (0.785398 rad)" in text for text in said(record)), said(record)


@pytest.mark.parametrize("option", ["prefer", "secondary"])
def test_a_posture_in_degrees_is_said_with_its_radians(ur5, target, option):
    """``armik.Posture([0, -90, 90, ...])`` was taken silently."""
    posture = armik.Posture(DEGREES)
    given = {"prefer": posture} if option == "prefer" else {"secondary": [posture]}
    with pytest.warns(ArmikWarning) as record:
        ur5.solve(target, q0=np.radians(DEGREES), **given)
    assert_said_in_radians(said(record))
    assert said(record)[0].startswith(f"{option}=Posture(q_ref)")
    with warnings.catch_warnings():  # in radians: nothing said
        warnings.simplefilter("error", ArmikWarning)
        ur5.solve(target, q0=np.radians(DEGREES), prefer=armik.Posture(np.radians(DEGREES)))


def test_fk_of_degrees_is_said_and_of_values_outside_the_limits_is_not(ur5, tmp_path):
    """fk needs no limits: a value past them is evaluated silently; one beyond them and
    four turns is no angle the joint can hold, and its pose would be taken for a target."""
    with pytest.warns(ArmikWarning) as record:
        ur5.fk(DEGREES)
    assert_said_in_radians(said(record))
    with pytest.warns(ArmikWarning, match="radians are meant"):
        ur5.jacobian(DEGREES)
    with pytest.warns(ArmikWarning, match="radians are meant"):
        ur5.fk(DEGREES, "forearm_link")
    continuous = two_link_urdf().replace('name="j1" type="revolute"', 'name="j1" type="continuous"')
    wheel = armik.load(write_urdf(tmp_path, continuous), tip="tip")
    assert not np.isfinite(wheel.kinematics.upper[0])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ArmikWarning)
        ur5.fk([0.0, -7.0, 3.5, 0.0, 0.0, 0.0])  # outside the limits: fk's to evaluate
        wheel.fk([60.0, 0.3])  # a continuous joint at ten turns: an angle it holds


def test_the_command_lines_q0_in_degrees_is_said(capsys):
    code = main(
        ["solve", "ur5", "--xyz", "0.4", "0.1", "0.4", "--q0", *(f"{v:g}" for v in DEGREES)]
    )
    err = capsys.readouterr().err
    assert code in (0, 1) and "radians are meant" in err
    assert all(part in err for part in SAID), err
