"""``swivel=`` fixes an SRS arm's elbow in its closed form; where the task solver solves
(several tips sharing joints, a list of tasks, joints it holds) it was taken and dropped,
the answer called a success at whatever swivel the descent left. It is refused by name,
with the way round, on every route; where the closed form solves, it applies."""

from __future__ import annotations

import numpy as np
import pytest

import armik


def _refused(call, where: str) -> None:
    with pytest.raises(armik.OptionError, match="is not taken by the task solver") as info:
        call()
    assert info.value.option == "swivel" and info.value.value == 0.3
    assert where in str(info.value)


def test_swivel_over_shared_joints_is_refused_on_every_route():
    robot = armik.load("kuka_iiwa14", tips=["iiwa_link_4", "iiwa_link_ee"])
    assert robot.shared
    q = robot.random_q(np.random.default_rng(1))
    T = {tip: robot.fk(q, tip) for tip in robot.tips}
    twice = {tip: [t, t] for tip, t in T.items()}
    where = "robot.chain(tip).solve(T, swivel=...)"
    _refused(lambda: robot.solve(T, swivel=0.3), where)
    _refused(lambda: robot.solve_all(T, swivel=0.3), where)
    _refused(lambda: robot.solve_batch(twice, swivel=0.3, progress=False), where)
    _refused(lambda: robot.solve_path(twice, q, swivel=0.3), where)
    # the chain alone, by its closed form, applies it
    arm = robot.chain("iiwa_link_ee")
    a, b = arm.solve(T["iiwa_link_ee"], swivel=0.3), arm.solve(T["iiwa_link_ee"], swivel=1.2)
    assert a.success and b.success and np.abs(a.q - b.q).max() > 0.1


def test_swivel_where_one_arm_is_solved_by_the_task_solver_is_refused():
    arm = armik.load("kuka_iiwa14")
    q = arm.random_q(np.random.default_rng(1))
    T = arm.fk(q)
    j = arm.joint_names
    held = {j[0]: float(q[0]), j[1]: float(q[1])}  # two joints: the task solver holds them
    _refused(lambda: arm.solve(T, hold=held, swivel=0.3), "hold one joint")
    _refused(lambda: arm.solve([armik.Pose(T)], hold=held, swivel=0.3), "a list of tasks")
    assert arm.solve([armik.Pose(T)], swivel=0.3).success  # lowered: the closed form's
