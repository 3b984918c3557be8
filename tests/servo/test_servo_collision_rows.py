"""One chain's collision rows: on an arm of one joint, and with more pairs within reach
than rows, the nearest of them; each distance checked by coal on the URDF's boxes placed
here."""

from __future__ import annotations

import coal
import numpy as np
import pytest

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


def test_the_rows_are_the_nearest_pairs_where_more_are_within_reach(tmp_path):
    """Sixteen bars 3 cm from the plate's broad faces, their lower bounds (the plate's
    bounding capsule) below zero, fill as many rows; the box beyond its edge, its bound
    tight, is nearer than any bar once the plate slides toward it: it gets a row and the
    plate stops at the margin (it took the first pairs by bound, and went 2.5 cm in)."""
    bars = [
        armik.Box((0.6, 0.02, 0.02), (0.1, side * 0.041, z))
        for side in (1, -1)
        for z in np.linspace(0.05, 0.55, 8)
    ]
    edge = armik.Box((0.02, 0.1, 0.1), EDGE)
    arm, rec = _run(tmp_path, [*bars, edge])
    assert len(bars) == 16
    assert _to_edge(rec.q) >= 0.01 - 1e-6
    assert min(arm.min_distance(q, bars)[0] for q in rec.q[::20]) > 0.029
    rows = arm.servo([0.0], obstacles=[*bars, edge], margin=0.01)._collisions
    C = rows.at(np.array([0.095]))  # the edge 5 mm away, every bar 3 cm
    distances = np.sort(rows.margin - C[:, -1] / rows.gain)
    assert len(C) == 16 and distances[0] == pytest.approx(0.005, abs=1e-9)
