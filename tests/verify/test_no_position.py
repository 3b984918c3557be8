"""An ``armik.Axis`` or an ``armik.LookAt`` alone holds no position: its ``position_error``
is None (NaN in a batch) on every route, one arm's as a servo's ticks and the task
solver's; ``Arm.solve`` said 0.0, a distance to nothing (``verify.distances``). Its
``orientation_error`` is the tip's axis' angle from its direction, Pinocchio's to 1e-12."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armik
from tests.conftest import arm
from tests.test_arms import dual_irb120


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    return math.atan2(float(np.linalg.norm(np.cross(a, b))), float(a @ b))


def _aims(T):
    """(task, the tip's axis' angle from its sight at a placement) of a look-at and an axis
    alone, 0 wide and 0.1 wide."""
    z = T.rotation[:, 2] + np.array([0.0, 0.05, 0.0])
    point = T.translation + 0.5 * z
    for within in (0.0, 0.1):
        yield (
            armik.LookAt(point, within=within),
            lambda P, p=point: _angle(P.rotation[:, 2], p - P.translation),
        )
        axis = armik.Axis((0, 0, 1), z, within)
        yield axis, lambda P, d=axis.direction: _angle(P.rotation[:, 2], d)


def test_an_aim_alone_has_no_position_error_on_every_route_of_one_arm():
    ur5 = arm("ur5")
    q = ur5.middle + 0.1
    for task, angle_at in _aims(ur5.fk(q)):
        q0 = q + 0.05
        batch = ur5.solve_batch([task, task], q0=q0, progress=False)
        path = ur5.solve_path([task, task], q0)
        results = [
            ur5.solve(task, q0=q0),
            ur5.solve(task, q0=q0, solver="qp"),  # the prepared path's numeric runner
            *ur5.solve_all(task, q0=q0),
            batch[0],
            path[1],
            ur5.solve(task, q0=q0, hold={"wrist_3_joint": float(q0[5])}),  # the task solver
        ]
        for r in results:
            assert r.success and r.position_error is None, (r.solver, r.position_error)
            assert r.orientation_error == pytest.approx(angle_at(ur5.fk(r.q)), abs=1e-12)
            assert "n/a" in repr(r)
        for rows in (batch, path):
            assert np.isnan(rows.position_error).all()
            for i, row in enumerate(rows.q):
                assert rows.orientation_error[i] == pytest.approx(angle_at(ur5.fk(row)), abs=1e-12)
        servo = ur5.servo(q0)
        for _ in range(300):
            tick = servo.step(task)
        assert tick.position_error is None  # as the servo says
        assert tick.orientation_error == pytest.approx(angle_at(ur5.fk(tick.q)), abs=1e-12)


def test_an_aim_keeps_its_distance_where_its_target_holds_a_position():
    """Beside a position, or the keyword aim on a pose, or a pose whose bounds free its
    position: the distance to that position, by Pinocchio; an aim beside bounds freeing
    the position holds none."""
    ur5 = arm("ur5")
    q = ur5.middle + 0.1
    T = ur5.fk(q)
    z = T.rotation[:, 2] + np.array([0.0, 0.05, 0.0])
    z = z / np.linalg.norm(z)
    free = (math.inf,) * 3 + (0.0,) * 3
    for given, options, kept in [
        ([armik.Position(T.translation), armik.Axis((0, 0, 1), z, 0.1)], {}, True),
        (T, {"cone": (0, 0, 1, 0.1)}, True),
        (T, {"bounds": free}, True),
        (T.translation, {"cone": (0, 0, 1, 0.1), "toward": tuple(z), "bounds": free}, None),
    ]:
        r = ur5.solve(given, q0=q + 0.05, **options)
        assert r.success, r.reason
        if kept is True:
            far = float(np.linalg.norm(ur5.fk(r.q).translation - T.translation))
            assert r.position_error == pytest.approx(far, abs=1e-12)
        else:
            assert r.position_error == kept


def test_several_tips_say_no_position_of_an_aim_alone():
    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    q = cell.random_q(np.random.default_rng(3))
    T_r = cell.fk(q, "r_tool0")
    for task, angle_at in _aims(cell.fk(q, "l_tool0")):
        targets = {"l_tool0": task, "r_tool0": T_r}
        for r in (cell.solve(targets, q0=q + 0.05), cell.solve_all(targets, q0=q + 0.05)[0]):
            assert r.success, r.reason
            pos, ori = r.errors["l_tool0"]
            assert pos is None
            assert ori == pytest.approx(angle_at(cell.fk(r.q, "l_tool0")), abs=1e-12)
            far = float(np.linalg.norm(cell.fk(r.q, "r_tool0").translation - T_r.translation))
            assert r.position_error == pytest.approx(far, abs=1e-12)  # the right tip's
        rows = cell.solve_batch({t: [v, v] for t, v in targets.items()}, q0=q, progress=False)
        assert rows.success.all() and np.isnan(rows.errors["l_tool0"][:, 0]).all()
        both = {"l_tool0": task, "r_tool0": armik.Axis((0, 0, 1), T_r.rotation[:, 2])}
        r = cell.solve(both, q0=q + 0.05)  # no tip holds a position: the robot neither
        assert r.success and r.position_error is None, r.position_error
        rows = cell.solve_batch({t: [v, v] for t, v in both.items()}, q0=q, progress=False)
        assert rows.success.all() and np.isnan(rows.position_error).all()
