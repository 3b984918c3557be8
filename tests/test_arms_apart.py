"""Obstacles on chains that share no joint: each chain's solve leaves out the links another
chain moves (``armik.arms_apart``), so an obstacle where a chain alone holds the other arm
is no link "that never moves"; every success keeps every link of the whole URDF the margin
clear of it, by coal on Pinocchio's placements computed here."""

from __future__ import annotations

import pickle

import coal
import numpy as np
import pinocchio as pin
import pytest

import armik
from armik import arms_apart
from armik.model.catalogue import erd_share

from .test_arms_collision import dual


def _whole(text: str):
    """The whole URDF's model and its collision geometry, meshes as convex hulls."""
    model = pin.buildModelFromXML(text)
    geom = pin.buildGeomFromUrdfString(model, text, pin.COLLISION, package_dirs=[erd_share()])
    for o in geom.geometryObjects:
        if isinstance(o.geometry, coal.BVHModelBase):
            o.geometry.buildConvexHull(True, "Qt")
            o.geometry = o.geometry.convex
    return model, geom


def _clearance(model, geom, robot, q, shape) -> float:
    """The smallest distance of any link of the whole URDF to ``shape`` at ``q``."""
    qf = pin.neutral(model)
    for name, v in zip(robot.joint_names, q):
        qf[model.joints[model.getJointId(name)].idx_q] = v
    data, gdata = model.createData(), pin.GeometryData(geom)
    pin.updateGeometryPlacements(model, data, geom, gdata, qf)
    P = shape.placement()
    return min(
        coal.distance(
            o.geometry,
            coal.Transform3s(gdata.oMg[i].rotation, gdata.oMg[i].translation),
            shape.geometry(),
            coal.Transform3s(P.rotation, P.translation),
            coal.DistanceRequest(),
            coal.DistanceResult(),
        )
        for i, o in enumerate(geom.geometryObjects)
    )


def test_an_obstacle_where_a_chain_holds_the_other_arm_is_solved_around():
    text = dual("ur5")
    robot = armik.load(text, tips=["l_tool0", "r_tool0"])
    left = robot.chain("l_tool0").kinematics
    full = left.chain.full
    data = full.createData()
    pin.framesForwardKinematics(full, data, left.chain.q_ref)
    # a ball about the right forearm as the left chain holds it (its cut): the right arm
    # moves, so the robot can clear it
    ball = armik.Sphere(0.05, data.oMf[full.getFrameId("r_forearm_link")].translation)
    with pytest.raises(armik.CollisionError, match="never moves"):  # the chain alone: as before
        robot.chain("l_tool0").solve(robot.fk(robot.middle, "l_tool0"), obstacles=[ball])
    model, geom = _whole(text)
    qs = robot.random_q(3, 6)
    goals = [{tip: robot.fk(q, tip) for tip in robot.tips} for q in qs]
    rows = {tip: [g[tip] for g in goals] for tip in robot.tips}
    margin = 0.02
    given = {"obstacles": [ball], "margin": margin}
    results = [robot.solve(g, **given) for g in goals]
    results += [robot.solve(goals[0], prefer=lambda x: float(x[0] ** 2), **given)]
    results += list(robot.solve_all(goals[1], **given))
    results += list(robot.solve_batch(rows, **given))
    results += list(robot.solve_path(rows, None, max_joint_step=10.0, **given))
    assert len(results) > 20 and all(r.success for r in results)
    for r in results:
        assert _clearance(model, geom, robot, r.q, ball) >= margin - 1e-9
    # the chain's model within the robot travels to worker processes as itself
    arm = arms_apart.facade(robot, "l_tool0", given)
    assert arm.kinematics is not left
    again = pickle.loads(pickle.dumps(arm))
    assert again.kinematics.left_out == arm.kinematics.left_out
    assert "r_forearm_link_0" in arm.kinematics.left_out
    assert arms_apart.facade(robot, "l_tool0", {}) is robot.chain("l_tool0")


def test_chains_that_collide_together_are_said_to_be_checked_without_the_other_arm():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    down = pin.utils.rpyToMatrix(np.pi, 0.0, 0.0)
    close = {
        "l_tool0": pin.SE3(down, np.array([0.4, 0.04, 0.3])),
        "r_tool0": pin.SE3(down, np.array([0.4, -0.04, 0.3])),
    }
    rel = armik.Relative("r_tool0", "l_tool0", close["l_tool0"].actInv(close["r_tool0"]))
    r = robot.solve({"l_tool0": close["l_tool0"], "r_tool0": rel}, self_collision=True)
    b = robot.solve_path({tip: [T] for tip, T in close.items()}, None, self_collision=True)
    for reason in (r.reason, b.reasons[0]):
        assert "in collision" in reason and "against the obstacles and its own links" in reason
        assert "held where it was cut" not in reason  # each chain leaves the other arm out


def _apart(model, geom, robot, q) -> float:
    """The smallest distance between a link of the left arm and one of the right, by coal
    on the whole URDF at ``q``."""
    qf = pin.neutral(model)
    for name, v in zip(robot.joint_names, q):
        qf[model.joints[model.getJointId(name)].idx_q] = v
    data, gdata = model.createData(), pin.GeometryData(geom)
    pin.updateGeometryPlacements(model, data, geom, gdata, qf)
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    M = [coal.Transform3s(m.rotation, m.translation) for m in gdata.oMg]
    objects = geom.geometryObjects
    return min(
        coal.distance(
            objects[i].geometry, M[i], objects[j].geometry, M[j],
            coal.DistanceRequest(), coal.DistanceResult(),
        )
        for i in range(len(objects))
        for j in range(len(objects))
        if links[i].startswith("l_") and links[j].startswith("r_")
    )  # fmt: skip


def test_a_hand_placed_relative_to_the_other_takes_another_answer_clear_of_it():
    text = dual("ur5")
    robot = armik.load(text, tips=["l_tool0", "r_tool0"])
    model, geom = _whole(text)
    down = pin.utils.rpyToMatrix(np.pi, 0.0, 0.0)
    rng = np.random.default_rng(3)
    plain = placed = 0
    for _ in range(12):  # tools 8-30 cm apart between the arms, pointing down
        x, z, gap = rng.uniform(0.3, 0.5), rng.uniform(0.2, 0.45), rng.uniform(0.08, 0.3)
        T_l = pin.SE3(down, np.array([x, gap / 2, z]))
        T_r = pin.SE3(down, np.array([x, -gap / 2, z]))
        box = armik.Relative("r_tool0", "l_tool0", T_l.actInv(T_r))
        each = robot.solve({"l_tool0": T_l, "r_tool0": T_r}, self_collision=True)
        r = robot.solve({"l_tool0": T_l, "r_tool0": box}, self_collision=True)
        plain += each.success
        placed += r.success
        if r.success:
            assert _apart(model, geom, robot, r.q) >= 0.0
            qf = pin.neutral(model)
            for name, v in zip(robot.joint_names, r.q):
                qf[model.joints[model.getJointId(name)].idx_q] = v
            data = model.createData()
            pin.framesForwardKinematics(model, data, qf)
            for tip, T in (("l_tool0", T_l), ("r_tool0", T_r)):  # by the whole URDF's FK
                M = data.oMf[model.getFrameId(tip)]
                assert np.linalg.norm(pin.log6(M.actInv(T)).vector) < 1e-6
        else:
            assert r.status is armik.Status.COLLISION
    assert placed == plain >= 10  # as many as where each hand's pose is given apart


def test_a_tip_left_out_keeps_q0_and_its_arm_is_checked_against_the_obstacles():
    text = dual("ur5")
    robot = armik.load(text, tips=["l_tool0", "r_tool0"])
    model, geom = _whole(text)
    q0 = robot.middle.copy()
    ball = armik.Sphere(0.05, robot.fk(q0, "r_forearm_link").translation)  # at q0's right arm
    T = robot.fk(robot.random_q(1), "l_tool0")
    given = {"obstacles": [ball]}
    for q in (q0, robot.random_q(4)):  # the right arm in the ball, and (most likely) not
        results = [
            robot.solve({"l_tool0": T}, q0=q, **given),
            robot.solve_all({"l_tool0": T}, q0=q, **given)[0],
            robot.solve_batch({"l_tool0": [T]}, q0=q, **given)[0],
            robot.solve_path({"l_tool0": [T]}, q, max_joint_step=10.0, **given)[0],
        ]
        inside = _clearance(model, geom, robot, q, ball) < 0  # q0's right arm in the ball
        for r in results:
            assert np.allclose(r.q[6:], q[6:])  # the right arm kept at q0's values
            if r.success:
                assert _clearance(model, geom, robot, r.q, ball) >= 0
            if inside:
                assert r.status is armik.Status.COLLISION and "['r_tool0']" in r.reason
        assert inside == (q is q0)
        assert inside or all(r.success for r in results)


def test_a_servo_on_chains_apart_streams_around_an_obstacle_where_a_chain_holds_the_other_arm():
    text = dual("ur5")
    robot = armik.load(text, tips=["l_tool0", "r_tool0"])
    left = robot.chain("l_tool0").kinematics
    data = left.chain.full.createData()
    pin.framesForwardKinematics(left.chain.full, data, left.chain.q_ref)
    ball = armik.Sphere(0.05, data.oMf[left.chain.full.getFrameId("r_forearm_link")].translation)
    model, geom = _whole(text)
    q0 = robot.random_q(2)
    assert _clearance(model, geom, robot, q0, ball) > 0.05
    servo = robot.servo(q0, obstacles=[ball], margin=0.02)  # refused as "never moves" before
    goal = {tip: robot.fk(robot.random_q(4), tip) for tip in robot.tips}
    nearest = min(_clearance(model, geom, robot, servo.step(goal).q, ball) for _ in range(300))
    assert nearest >= 0.02 - 1e-4
    assert not np.allclose(servo.q, q0)  # it moved


def test_a_chain_within_the_robot_locks_and_limits_as_itself():
    robot = armik.load(dual("panda"), tips=["l_panda_hand", "r_panda_hand"])
    down, c = pin.utils.rpyToMatrix(np.pi, 0.0, 0.0), np.array([0.5, 0.0, 0.4])
    T = {
        "l_panda_hand": pin.SE3(down, c + [0, 0.2, 0]),
        "r_panda_hand": pin.SE3(down, c - [0, 0.2, 0]),
    }
    far = armik.Sphere(0.05, (3.0, 3.0, 3.0))
    # joint 3 held: the held solve locks the chain's model (a raw AttributeError before)
    r = robot.solve(T, hold={"l_panda_joint3": 0.3}, obstacles=[far])
    assert r.success
    assert r.q[robot.joint_names.index("l_panda_joint3")] == 0.3
    arm = arms_apart.facade(robot, "l_panda_hand", {"obstacles": [far]}).kinematics
    left_out = arm.left_out
    assert left_out and all(n.startswith("r_") for n in left_out)
    narrowed = arm.with_limits({"l_panda_joint1": (-1.0, 1.0)})
    locked = arm.with_locked({"l_panda_joint3": 0.3})
    for model in (narrowed, locked, pickle.loads(pickle.dumps(narrowed))):
        assert model.left_out == left_out
    assert pickle.loads(pickle.dumps(narrowed)).upper[0] == 1.0
    assert "l_panda_joint3" not in locked.joint_names


def test_the_chains_within_the_robot_are_its_own_attribute_and_a_new_robot_builds_its_own():
    from armik.arms_kinematics import ArmsKinematics

    assert "_apart" in ArmsKinematics.__annotations__  # declared, with its type and when kept
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    assert robot._apart is None  # nothing built before a solve asks for collisions
    far = armik.Sphere(0.05, (3.0, 3.0, 3.0))
    goal = {tip: robot.fk(robot.middle, tip) for tip in robot.tips}
    assert robot.solve(goal).success and robot._apart is None  # no collisions: the chains'
    assert robot.solve(goal, obstacles=[far]).success
    built = robot._apart
    assert built is not None and list(built) == list(robot.tips)
    assert arms_apart.facade(robot, "l_tool0", {"obstacles": [far]}).kinematics is built["l_tool0"]
    assert robot.solve(goal, obstacles=[far]).success and robot._apart is built  # kept
    narrowed = robot.with_limits({"l_shoulder_pan_joint": (-1.0, 1.0)})
    assert narrowed._apart is None  # a new robot: its chains' limits, not this one's
    assert narrowed.solve(goal, obstacles=[far]).success
    within = narrowed._apart
    assert within is not None and within["l_tool0"].upper[0] == 1.0
    assert within["l_tool0"].left_out == built["l_tool0"].left_out
    assert pickle.loads(pickle.dumps(narrowed))._apart is None
