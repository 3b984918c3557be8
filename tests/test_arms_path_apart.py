"""A path of chains that share no joint: each chain's own path, the rows joined; where the
joined rows then fail (the chains' answers collide, one tip out of reach), the path goes on
from the row it went on from, as one arm's does: a colliding row solved again as
``Arms.solve`` solves it (the chains' other answers, as a batch does), and no success
further than ``max_joint_step`` from the last success or jump. Every success checked by
Pinocchio's FK of the whole URDF and by coal between the arms."""

from __future__ import annotations

import itertools

import coal
import numpy as np
import pinocchio as pin
import pytest

import armik

from .test_arms_apart import _whole
from .test_arms_collision import dual


@pytest.fixture(scope="module")
def two():
    text = dual("ur5")
    return text, armik.load(text, tips=["l_tool0", "r_tool0"])


def _placed(model, geom, robot, q):
    """The whole URDF at the robot's ``q``: its data and geometry data."""
    qf = pin.neutral(model)
    for name, v in zip(robot.joint_names, q):
        qf[model.joints[model.getJointId(name)].idx_q] = v
    data, gd = model.createData(), pin.GeometryData(geom)
    pin.framesForwardKinematics(model, data, qf)
    pin.updateGeometryPlacements(model, data, geom, gd, qf)
    return data, gd


def _between(model, geom, gd) -> float:
    """The smallest distance of a left arm's link to a right arm's."""
    side = [model.frames[o.parentFrame].name[:2] for o in geom.geometryObjects]
    objects = list(enumerate(geom.geometryObjects))
    return min(
        coal.distance(
            a.geometry,
            coal.Transform3s(gd.oMg[i].rotation, gd.oMg[i].translation),
            b.geometry,
            coal.Transform3s(gd.oMg[k].rotation, gd.oMg[k].translation),
            coal.DistanceRequest(),
            coal.DistanceResult(),
        )
        for (i, a), (k, b) in itertools.product(objects, objects)
        if side[i] == "l_" and side[k] == "r_"
    )


def test_a_path_tries_the_chains_other_answers_where_their_first_collide(two):
    text, robot = two
    model, geom = _whole(text)
    down = pin.utils.rpyToMatrix(np.pi, 0.0, 0.0)
    rng = np.random.default_rng(3)
    goals = []
    for _ in range(12):  # both tools pointing down, 8-30 cm apart between the arms
        x, z, gap = rng.uniform(0.3, 0.5), rng.uniform(0.2, 0.45), rng.uniform(0.08, 0.3)
        goals.append(
            {
                "l_tool0": pin.SE3(down, np.array([x, gap / 2, z])),
                "r_tool0": pin.SE3(down, np.array([x, -gap / 2, z])),
            }
        )
    rows = {tip: [g[tip] for g in goals] for tip in robot.tips}
    b = robot.solve_batch(rows, self_collision=True)
    p = robot.solve_path(rows, None, max_joint_step=10.0, self_collision=True)
    alone = {t: robot.chain(t).solve_path(rows[t], None, max_joint_step=10.0) for t in robot.tips}
    first = np.hstack([alone[t].q for t in robot.tips])  # each chain's own answers, joined
    collided = [i for i in range(12) if robot.in_collision(first[i], self_collision=True)]
    assert collided and any(p.success[i] for i in collided)
    assert all(p.success[i] for i in range(12) if b.success[i])  # every row a batch solves
    for i in np.flatnonzero(p.success):
        data, gd = _placed(model, geom, robot, p.q[i])
        assert _between(model, geom, gd) >= 0.0
        for tip in robot.tips:
            err = pin.log6(data.oMf[model.getFrameId(tip)].actInv(goals[i][tip])).vector
            assert np.linalg.norm(err) < 1e-5


def test_a_path_never_jumps_over_a_row_another_tip_fails(two):
    text, robot = two
    model, geom = _whole(text)
    left, right = robot.tips
    q = np.tile(robot.middle, (5, 1))
    # 0.2 rad a waypoint, each joint, from 1.2 off the middle: nearer the middle (elbow and
    # wrist singular) the tool's straight line between some waypoints leaves the reach
    q[:, robot._columns[left]] += 1.2 + 0.2 * np.arange(5)[:, None]
    rows = {tip: [robot.fk(x, tip) for x in q] for tip in robot.tips}
    rows[right][2] = pin.SE3(np.eye(3), np.array([3.0, -0.5, 0.3]))  # out of reach
    step = 0.3
    p = robot.solve_path(rows, q[0], max_joint_step=step)
    assert str(p.status[2]) == "unreachable"
    # row 3 is 0.4 rad from row 1 for the left arm: a jump, said so, not a success
    assert str(p.status[3]) == "discontinuous" and "max_joint_step 0.3" in p.reason(3)
    went_on = q[0]  # the last success or jump, as one arm's path goes on from it
    for i in range(5):
        if p.success[i]:
            assert np.abs(p.q[i] - went_on).max() <= step + 1e-9, i
            data, _ = _placed(model, geom, robot, p.q[i])
            for tip in robot.tips:
                err = pin.log6(data.oMf[model.getFrameId(tip)].actInv(rows[tip][i])).vector
                assert np.linalg.norm(err) < 1e-5
        if p.success[i] or str(p.status[i]) == "discontinuous":
            went_on = p.q[i]
    assert p.success[[0, 1, 4]].all()
