"""Several tips over shared joints solved in one model (``armik.model.union``): each tip's
frame there is the one its chain reads, its ``tip_offset`` included, so that a success is
true of the tool points (checked with yourdfpy, an independent reader)."""

from __future__ import annotations

import io

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

import armik

from ..conftest import TOL

LIM = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'


def _joint(name: str, parent: str, child: str, xyz: str, axis: str) -> str:
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="0.1 0 0"/><axis xyz="{axis}"/>{LIM}</joint>'
    )


# a torso joint both arms share, then two 3R arms
XML = (
    '<robot name="two">'
    + "".join(f'<link name="{n}"/>' for n in ("base", "torso", "a1", "a2", "ta", "b1", "b2", "tb"))
    + _joint("t", "base", "torso", "0 0 0.2", "0 0 1")
    + _joint("a_1", "torso", "a1", "0 0.2 0", "0 1 0")
    + _joint("a_2", "a1", "a2", "0.3 0 0", "0 1 0")
    + _joint("a_3", "a2", "ta", "0.25 0 0", "1 0 0")
    + _joint("b_1", "torso", "b1", "0 -0.2 0", "0 1 0")
    + _joint("b_2", "b1", "b2", "0.3 0 0", "0 1 0")
    + _joint("b_3", "b2", "tb", "0.25 0 0", "1 0 0")
    + "</robot>"
)
OFFSET = (0.05, 0.0, 0.1)


def tool_points(robot, q) -> dict[str, pin.SE3]:
    """Each tip's tool point (``OFFSET`` in its frame) at ``q`` by yourdfpy."""
    reader = yourdfpy.URDF.load(io.StringIO(XML), load_meshes=False)
    cfg = dict(zip(robot.joint_names, np.asarray(q, dtype=float)))
    reader.update_cfg({n: cfg[n] for n in reader.actuated_joint_names})
    offset = pin.SE3(np.eye(3), np.array(OFFSET))
    return {t: pin.SE3(reader.get_transform(t, "base")) * offset for t in robot.tips}


def test_shared_joints_solve_the_tool_points_of_a_tip_offset(rng):
    robot = armik.load(XML, tips=["ta", "tb"], tip_offset=OFFSET)
    assert robot.shared == ("t",)
    for q in robot.random_q(rng, 3):
        targets = tool_points(robot, q)
        fk = robot.fk(q)
        assert all(fk[t].isApprox(targets[t], 1e-12) for t in robot.tips)
        r = robot.solve(targets, q0=robot.middle)
        assert r.success, r.reason
        reached = tool_points(robot, r.q)
        for t in robot.tips:
            assert np.linalg.norm(reached[t].translation - targets[t].translation) < TOL["solve"]
        # the tips' links there: a success only where the tool points are there too
        links = armik.load(XML, tips=["ta", "tb"]).fk(q)
        r = robot.solve(links, q0=robot.middle, timeout=0.02)
        if r.success:
            reached = tool_points(robot, r.q)
            for t in robot.tips:
                assert np.linalg.norm(reached[t].translation - links[t].translation) < TOL["solve"]


@pytest.mark.filterwarnings("ignore:joint 't' has:armik.ArmikWarning")
def test_the_union_reads_each_joints_limits_as_its_chain_does(rng):
    """The shared joint's URDF limits "0 0" (not given) or +-1e16 (free) are no limits, on
    the chains and in their one model alike: read as Pinocchio holds them, the torso was
    pinned at 0 (its poses at t = 2 failed) or sampled over +-1e16 rad."""
    for lo, hi in [("0", "0"), ("-1e16", "1e16")]:
        torso = f'<limit lower="{lo}" upper="{hi}" effort="1" velocity="1"/>'
        robot = armik.load(XML.replace(LIM + "</joint>", torso + "</joint>", 1), tips=["ta", "tb"])
        assert robot.joint_names[0] == "t" and robot.chain("ta").lower[0] == -np.inf
        assert robot.lower[0] == -np.inf and robot.upper[0] == np.inf
        assert np.all(np.abs(robot.random_q(rng)) <= np.pi)
        q = robot.random_q(rng)
        q[0] = 2.0
        r = robot.solve(robot.fk(q), q0=robot.middle)
        assert r.success and robot.within_limits(r.q), r.reason


# the first arm's elbow mimics a joint on no chain (held at 1 x 0 + 0.7 on it), and a
# continuous wrist on the second arm, locked at 0.5
HELD = (
    XML.replace("</robot>", "")
    .replace('<link name="a2"/>', '<link name="a2"/><link name="am"/><link name="side"/>')
    .replace('<link name="tb"/>', '<link name="tb"/><link name="tc"/>')
    .replace('parent link="a2"', 'parent link="am"')
    + _joint("a_m", "a2", "am", "0.1 0 0", "0 0 1").replace(
        "</joint>", '<mimic joint="jx" multiplier="1" offset="0.7"/></joint>'
    )
    + _joint("jx", "base", "side", "0 0 -0.1", "1 0 0")
    + _joint("b_c", "tb", "tc", "0.1 0 0", "0 1 0").replace('type="revolute"', 'type="continuous"')
    + "</robot>"
)


def test_the_union_holds_the_joints_the_chains_hold_where_they_hold_them(rng):
    """A mimic joint fixed on a chain (its driver moves on none) and a continuous joint
    locked on one are held in the chains' one model where the chains hold them: it held
    them at 0, and solved (and verified) another robot, its targets missed."""
    robot = armik.load(HELD, tips=["ta", "tc"], locked={"b_c": 0.5})
    assert robot.shared == ("t",) and "a_m" not in robot.joint_names
    reader = yourdfpy.URDF.load(io.StringIO(HELD), load_meshes=False)
    for q in robot.random_q(rng, 3):
        cfg = {**dict(zip(robot.joint_names, q)), "jx": 0.0, "b_c": 0.5}
        reader.update_cfg({n: cfg[n] for n in reader.actuated_joint_names})
        targets = {t: pin.SE3(reader.get_transform(t, "base")) for t in robot.tips}
        r = robot.solve(targets, q0=robot.middle)
        assert r.success, r.reason
        cfg.update(zip(robot.joint_names, r.q))
        reader.update_cfg({n: cfg[n] for n in reader.actuated_joint_names})
        for t in robot.tips:
            reached = reader.get_transform(t, "base")[:3, 3]
            assert np.linalg.norm(reached - targets[t].translation) < TOL["solve"]


@pytest.mark.parametrize("offset", [None, (0.0, 0.0, 0.05)])
def test_a_tip_a_joint_shares_its_name_with(rng, offset):
    """The bundled SCARA's link and joint 'quill' share a name: its tip is the link's frame
    (its tool point with an offset) in the chains' one model too, where Pinocchio's lookup
    by name raised its own ValueError (several frames match)."""
    robot = armik.load("scara", tips=["quill", "tool"], tip_offset=offset)
    assert "quill" in robot.shared
    alone = armik.load("scara", tip="quill", tip_offset=offset)
    for q in robot.random_q(rng, 2):
        targets = robot.fk(q)
        mine = q[[robot.joint_names.index(n) for n in alone.joint_names]]
        assert targets["quill"].isApprox(alone.fk(mine), 1e-12)
        r = robot.solve(targets, q0=robot.middle)
        assert r.success, r.reason
        mine = r.q[[robot.joint_names.index(n) for n in alone.joint_names]]
        assert np.linalg.norm(alone.fk(mine).translation - targets["quill"].translation) < 1e-6
