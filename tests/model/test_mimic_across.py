"""A mimic joint among several tips' chains, and a mimic joint named where a free joint is
asked (``hold=``). A mimic joint fixed on one tip's chain whose driver moves on another's
couples the tips: each chain held it at its driver's reference value, so a success put the
tip elsewhere on the robot (checked with yourdfpy, an independent reader); it is refused
where the tips are loaded, and locking the driver is the way round."""

from __future__ import annotations

import io

import numpy as np
import pytest
import yourdfpy

import armik
from armik.errors import JointError

from ..conftest import TOL
from .test_mimic import five_joint_urdf

LIM = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'


def _joint(name, parent, child, xyz, extra=""):
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}"/><axis xyz="0 0 1"/>{LIM}{extra}</joint>'
    )


# two planar arms from the base, sharing no joint: jr on the right arm mimics jl on the left
XML = (
    '<robot name="g">'
    + "".join(f'<link name="{n}"/>' for n in ("base", "la", "lf", "lb", "rf", "rt"))
    + _joint("a1", "base", "la", "0 0.1 0")
    + _joint("jl", "la", "lf", "0.3 0 0")
    + _joint("b1", "base", "lb", "0 -0.1 0")
    + _joint("jr", "lb", "rf", "0.3 0 0", '<mimic joint="jl" multiplier="1" offset="0"/>')
    + '<joint name="t" type="fixed"><parent link="rf"/><child link="rt"/>'
    + '<origin xyz="0.1 0 0"/></joint></robot>'
)


@pytest.mark.parametrize("tips", [["lf", "rt"], ["rt", "lf"]])
def test_tips_coupled_through_a_mimic_joint_are_refused_naming_it(tips):
    """Solved chain by chain, 'rt' was reached with jr at 0 where the robot has jr = jl: a
    success 0.077 m off on the robot."""
    with pytest.raises(JointError) as info:
        armik.load(XML, tips=tips)
    text = str(info.value)
    assert info.value.joint == "jr"
    for words in (
        "joint 'jr' on the chain to 'rt' mimics 'jl'",
        "moves on the chain to 'lf'",
        "tip='rt' or tip='lf'",
        "lock the driver (locked={'jl': value}, --lock jl=VALUE)",
    ):
        assert words in text, text


def test_over_shared_joints_too():
    """The Panda's fingers share the arm's joints: their union held the second finger at the
    first's neutral value, as each chain does."""
    with pytest.raises(JointError, match="'panda_finger_joint2' on the chain to 'panda_right"):
        armik.load("panda", tips=["panda_leftfinger", "panda_rightfinger"])


def test_a_locked_driver_is_the_way_round(rng):
    robot = armik.load(XML, tips=["lf", "rt"], locked={"jl": 0.8})
    assert robot.joint_names == ("a1", "b1")
    reader = yourdfpy.URDF.load(io.StringIO(XML), load_meshes=False)

    def placed(q):  # every tip by yourdfpy at the robot's own configuration
        cfg = {**dict(zip(robot.joint_names, q)), "jl": 0.8, "jr": 0.8}
        reader.update_cfg({n: cfg[n] for n in reader.actuated_joint_names})
        return {t: reader.get_transform(t, "base")[:3, 3] for t in robot.tips}

    for q in robot.random_q(rng, 3):
        targets = placed(q)
        r = robot.solve(targets, q0=np.zeros(2))
        assert r.success, r.reason
        got = placed(r.q)
        for t in robot.tips:
            assert np.linalg.norm(got[t] - targets[t]) < TOL["solve"], (t, r.q, q)


def test_a_mimic_joint_held_names_its_driver():
    """hold= naming a mimic joint said 'unknown joint'."""
    a = armik.load_string(five_joint_urdf(-0.5, 0.2))  # j3 = -0.5 j2 + 0.2
    T = a.fk(a.middle)
    with pytest.raises(
        JointError,
        match=r"'j3' is a mimic joint following 'j2' .*hold 'j2' instead \(j2 = -0.2 holds j3 "
        r"at 0.3\)",
    ):
        a.solve(T, hold={"j3": 0.3})
    with pytest.raises(JointError, match=r"hold 'j2' instead$"):
        a.solve(T, constraints=[armik.Hold("j3")])
    b = armik.load_string(five_joint_urdf(-0.5, 0.2), locked={"j2": 0.4})
    with pytest.raises(JointError, match=r"'j3' mimics 'j2', which does not move on this arm"):
        b.solve(b.fk(b.middle), hold={"j3": 0.3})
    with pytest.raises(JointError, match="hold: unknown joint 'nope'"):
        a.solve(T, hold={"nope": 0.3})


def test_a_mimic_joint_held_over_several_tips_names_its_driver():
    """Each mimic joint follows a driver on its own chain: the tips load, and hold= naming
    the mimic joint names the driver."""
    xml = (
        '<robot name="h">'
        + "".join(f'<link name="{n}"/>' for n in ("base", "la", "lf", "lb", "rt"))
        + _joint("a1", "base", "la", "0 0.1 0")
        + _joint("jl", "la", "lf", "0.3 0 0", '<mimic joint="a1" multiplier="0.5" offset="0.1"/>')
        + _joint("b1", "base", "lb", "0 -0.1 0")
        + _joint("jr", "lb", "rt", "0.3 0 0")
        + "</robot>"
    )
    robot = armik.load(xml, tips=["lf", "rt"])
    assert robot.joint_names == ("a1", "b1", "jr")
    with pytest.raises(JointError, match=r"'jl' is a mimic joint following 'a1' on the chain to "):
        robot.solve(robot.fk(robot.middle), hold={"jl": 0.2})
    with pytest.raises(JointError, match="hold: unknown joint 'nope'; the joints of tips"):
        robot.solve(robot.fk(robot.middle), hold={"nope": 0.2})
