"""A joint held on the chain of a tip given no target: the robot's answer has it at the
held value on every route (that chain keeps q0's values but for it), as over shared
joints; a held value outside its limits is refused by name."""

from __future__ import annotations

import pytest

import armik

from .test_arms_collision import dual


def test_a_joint_held_on_a_chain_given_no_target_is_at_its_value():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    k = robot.joint_names.index("r_elbow_joint")
    q0 = robot.random_q(2)
    T = robot.fk(robot.random_q(1), "l_tool0")
    for given in (
        {"hold": {"r_elbow_joint": 0.3}},
        {"constraints": [armik.Hold("r_elbow_joint", 0.3)]},
    ):
        results = [
            robot.solve({"l_tool0": T}, q0=q0, **given),
            robot.solve({"l_tool0": T}, q0=q0, prefer=lambda x: float(x[0] ** 2), **given),
            *robot.solve_all({"l_tool0": T}, q0=q0, **given)[:3],
            robot.solve_batch({"l_tool0": [T, T]}, q0=q0, **given)[1],
            robot.solve_path({"l_tool0": [T]}, q0, max_joint_step=10.0, **given)[0],
        ]
        for r in results:
            assert r.success and r.q[k] == 0.3
            others = [i for i in range(6, 12) if i != k]
            assert (r.q[others] == q0[others]).all()  # the rest of the arm: q0's values
    held = robot.solve({"l_tool0": T}, q0=q0, hold={"r_elbow_joint": None})
    assert held.success and held.q[k] == q0[k]  # None: q0's value
    with pytest.raises(armik.JointError, match="r_elbow_joint"):
        robot.solve({"l_tool0": T}, hold={"r_elbow_joint": 100.0})
