"""A region's rim (``Task.rim``): exact tasks just inside its edge, tried in closed form where
a closed form shows the region's centre out of reach (``armik.solve.task_solve.centre``)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

import armik
from armik import Axis, Position
from armik.problem.problem import as_problem, lower, rims, tightened
from armik.problem.tasks.axis import RIM
from armik.solve import task_solve
from armik.solve.read import read
from tests import conftest


def test_a_cone_rim_is_directions_tilted_evenly_around_it():
    cone = Axis((0, 0, 1), (0.3, -0.2, 0.9), 0.1)
    rim = cone.rim(8)
    assert len(rim) == 8 and Axis((0, 0, 1), (0, 0, 1)).rim(8) == []
    d = cone.direction
    tilts = [math.acos(min(1.0, float(t.direction @ d))) for t in rim]
    assert np.allclose(tilts, RIM * 0.1, atol=1e-12)
    assert all(t.within == 0.0 and abs(np.linalg.norm(t.direction) - 1.0) < 1e-12 for t in rim)
    # evenly around: consecutive directions equally far apart, none repeated
    gaps = [float(np.linalg.norm(rim[k].direction - rim[k - 1].direction)) for k in range(8)]
    assert np.allclose(gaps, gaps[0], rtol=1e-9) and gaps[0] > 1e-3
    problems = rims(as_problem([Position((0.3, 0.1, 0.4)), cone]), 8)
    assert len(problems) == 8 and all(lower(p) is not None for p in problems)


def test_a_cone_whose_centre_is_out_of_reach_is_solved_on_its_rim_in_closed_form():
    """A UR5 target (found by search over seeded random targets) whose cone's centre
    direction no configuration reaches with the tool at the point: the closed form on the
    rim answers (``centre``, the task solver's start), the point exact and the tool's axis
    within the cone by Pinocchio's FK; the cone itself is the compiled step's."""
    arm = conftest.arm("ur5")
    rng = np.random.default_rng(0)
    for _ in range(64):  # the 64th of these targets: its centre is out of reach
        T = arm.fk(arm.random_q(rng))
        tilt = pin.exp3(rng.uniform(-1.0, 1.0, 3) * 0.8 * 0.05 / math.sqrt(3.0))
        tasks = [Position(T.translation), Axis((0, 0, 1), tilt @ T.rotation[:, 2], 0.05)]
    target, said = lower(tightened(as_problem(tasks)), arm.tip)
    centre = arm.solve(target, q0=arm.middle, **said)
    assert not centre.success and centre.status is armik.Status.UNREACHABLE
    request = read(arm.kinematics, T, arm.middle, "auto", {})  # its options and start
    on_rim = task_solve.centre(arm.kinematics, as_problem(tasks), request)
    cone = arm.solve(tasks, q0=arm.middle)
    assert cone.success and cone.solver == "dls", cone.reason
    for r in (on_rim, cone):
        assert r.success, r.reason
        X = arm.fk(r.q)
        assert np.linalg.norm(X.translation - T.translation) <= 1e-6
        angle = math.acos(min(1.0, float(X.rotation[:, 2] @ tasks[1].direction)))
        assert angle <= 0.05 + 1e-6 and arm.within_limits(r.q)
    assert on_rim.solver == "spin_joint"
