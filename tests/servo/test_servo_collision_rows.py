"""One chain's collision rows: on an arm of one joint, and with more pairs within reach
than rows, the nearest of them; each distance checked by coal on the URDF's boxes placed
here."""

from __future__ import annotations

import coal
import numpy as np

import armik

from ..conftest import write_urdf

DT = 0.002
# a plate 10 cm wide and 2 mm thick that a prismatic joint slides along x
URDF = """<?xml version="1.0"?>
<robot name="plate"><link name="base"/>
  <link name="plate"><collision><origin xyz="0 0 0.3"/>
    <geometry><box size="0.1 0.002 0.6"/></geometry></collision></link>
  <link name="tip"/>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="plate"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.3" effort="1" velocity="0.5"/></joint>
  <joint name="tip_fix" type="fixed"><parent link="plate"/><child link="tip"/>
    <origin xyz="0 0 0.6"/></joint>
</robot>"""
EDGE = (0.16, 0.0, 0.3)  # a box 10 cm beyond the plate's edge at slide 0


def _to_edge(Q: np.ndarray) -> float:
    """The nearest the plate comes to the box beyond its edge, by coal."""
    plate, box = coal.Box(0.1, 0.002, 0.6), coal.Box(0.02, 0.1, 0.1)
    at = coal.Transform3s(np.eye(3), np.array(EDGE))
    return min(
        coal.distance(
            plate,
            coal.Transform3s(np.eye(3), np.array([q[0], 0.0, 0.3])),
            box,
            at,
            coal.DistanceRequest(),
            coal.DistanceResult(),
        )
        for q in Q
    )


def _run(tmp_path, obstacles):
    arm = armik.load(write_urdf(tmp_path, URDF), tip="tip")
    target = arm.fk([0.0]).translation + np.array([0.2, 0.0, 0.0])  # through the box
    servo = arm.servo([0.0], dt=DT, obstacles=obstacles, margin=0.01)
    return arm, servo.track([target] * 800)


def test_an_arm_of_one_joint_keeps_an_obstacle_at_the_margin(tmp_path):
    # Pinocchio gives a one-joint model's joint Jacobian as a vector, not 6 x 1
    edge = armik.Box((0.02, 0.1, 0.1), EDGE)
    _, rec = _run(tmp_path, [edge])
    assert _to_edge(rec.q) >= 0.01 - 1e-6
    assert rec.status[-1] == "obstacle"
