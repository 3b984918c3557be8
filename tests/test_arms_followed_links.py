"""A link hung from the base by a mimic joint of a joint the chains share (a rod turned with
the torso): ``Arms`` measures it against obstacles where the whole robot places it, on
``min_distance`` (as its servo does), although each chain's cut model hangs it on the base."""

from __future__ import annotations

import coal
import numpy as np

import armik

from .conftest import write_urdf
from .servo.test_servo_mimic_rows import URDF, Whole

TORSO = 0.5  # rad: the rod's end is in the ball with the torso here


def _ball() -> tuple[armik.Sphere, tuple]:
    centre = np.array([0.3 + 0.3 * np.sin(TORSO), 0.0, 0.3 * np.cos(TORSO)])
    return armik.Sphere(0.03, tuple(centre)), (
        coal.Sphere(0.03),
        coal.Transform3s(np.eye(3), centre),
    )


def _rod_distance(whole: Whole, names, q, shape) -> float:
    request = coal.DistanceRequest()
    return coal.distance(*whole.rod(names, q, "brod"), *shape, request, coal.DistanceResult())


def test_min_distance_measures_a_rod_the_shared_torso_turns(tmp_path):
    path = write_urdf(tmp_path, URDF)
    robot = armik.load(path, tips=["l_tool", "r_tool"])
    ball, shape = _ball()
    q = np.zeros(robot.dof)
    q[robot.joint_names.index("torso_j")] = TORSO
    d, pair = robot.min_distance(q, [ball])
    truth = _rod_distance(Whole(path), robot.joint_names, q, shape)
    assert truth < 0.0
    assert pair[0] == "brod"
    assert abs(d - truth) < 1e-9
