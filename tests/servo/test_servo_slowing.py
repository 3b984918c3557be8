"""A tick "slowing to stop on the target" (``acceleration_limit``, no joint named) reads
what the task measures where the command is, as the on-target decision does
(``servo.step.status_code``): a rotation weighted 0, or a region's centre beyond its box,
is no distance the arm still has to go. It read the true distances, so a tick 5e-6 m from
a position whose rotation was weighted 0 and 0.28 rad off said it was slowing to stop on
a target more than 10 tolerances away. Measured by Pinocchio's FK here."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import armik
from armik.servo.step import BRAKED
from armik.servo.streams import START

TOL = 1e-6  # the servo's on-target tolerance (m, rad)


def _slowing(arm, target, measured, acceleration: float) -> list[float]:
    """What ``measured`` (a placement -> (m, rad)) gives at every tick said to slow to stop
    on ``target``, tracked from rest at the UR5's start until on target."""
    servo = arm.servo(START["ur5"], dt=0.002, acceleration_limits=acceleration)
    said = []
    for _ in range(3000):
        tick = servo.step(target)
        if tick.status == "on_target":
            return said
        if tick.status == "acceleration_limit" and tick.joint is None:
            said.append(max(measured(arm.fk(tick.q))))
    raise AssertionError("never on target")


def test_a_rotation_weighted_0_is_not_the_distance_a_slowing_tick_still_has_to_go():
    ur5 = armik.load("ur5")
    T0 = ur5.fk(START["ur5"])
    T = pin.SE3(T0.rotation @ pin.exp3(np.array([0.3, 0.0, 0.0])), T0.translation + [0, 0.05, 0])
    target = armik.Pose(T, weights=(1, 1, 1, 0, 0, 0))

    def measured(P):  # every position axis weighted alike, the rotation not at all
        return (float(np.linalg.norm(P.translation - T.translation)), 0.0)

    said = _slowing(ur5, target, measured, 0.5)
    assert said and min(said) > BRAKED * TOL, said


def test_a_regions_centre_is_not_the_distance_a_slowing_tick_still_has_to_go():
    ur5 = armik.load("ur5")
    T0 = ur5.fk(START["ur5"])
    T = pin.SE3(T0.rotation, T0.translation + np.array([0.0, 0.05, 0.0]))
    box = 0.02
    target = armik.Pose(T, bounds=(box, box, box, 0, 0, 0))

    def measured(P):  # the distance outside the box, in the target frame; the angle
        e = T.rotation.T @ (P.translation - T.translation)
        outside = np.maximum(np.abs(e) - box, 0.0)
        return (
            float(np.linalg.norm(outside)),
            float(np.linalg.norm(pin.log3(T.rotation.T @ P.rotation))),
        )

    for acceleration in (0.5, 2.0):
        said = _slowing(ur5, target, measured, acceleration)
        assert said and min(said) > BRAKED * TOL, said


def test_tips_over_shared_joints_slow_on_what_their_tasks_measure():
    """The union's tick (``servo.union_tick``): the hand's rotation weighted 0 and the
    elbow inside its box, whose centre lies mm away, are no distance still to go."""
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    q0 = robot.middle
    elbow, hand = robot.fk(q0, "panda_link4"), robot.fk(q0, "panda_hand")
    turned = hand.rotation @ pin.exp3(np.array([0.3, 0.0, 0.0]))
    T = pin.SE3(turned, hand.translation + np.array([0.0, 0.05, 0.0]))
    box = 0.2
    targets = {
        "panda_link4": armik.Position(elbow.translation, bounds=(box,) * 3),
        "panda_hand": armik.Pose(T, weights=(1, 1, 1, 0, 0, 0)),
    }
    servo = robot.servo(q0, acceleration_limits=0.5)
    said = []
    for _ in range(3000):
        tick = servo.step(targets)
        if tick.status == "on_target":
            break
        if tick.status == "acceleration_limit" and tick.joint is None:
            e = np.abs(robot.fk(tick.q, "panda_link4").translation - elbow.translation)
            outside = float(np.linalg.norm(np.maximum(e - box, 0.0)))  # by Pinocchio
            far = float(np.linalg.norm(robot.fk(tick.q, "panda_hand").translation - T.translation))
            said.append(max(outside, far))
    assert tick.status == "on_target"
    assert all(d > BRAKED * TOL for d in said), said  # it said so 5.8e-6 m from the target
