"""Several joints held in one solve: ``constraints=[armik.Hold(a), armik.Hold(b)]`` or
``hold={a: ..., b: ...}``. The compiled path holds one joint of a 7-joint arm (a 6R
chain); any other set of held joints is the task solver's, as box rows of its steps, a
plain pose or position given as its task. Every answer is checked on the arm's FK."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.options import Options
from tests import conftest

BUDGET = {"iteration_budget": 4000}  # deterministic: no test depends on timing


def test_several_holds_are_one_option():
    both = [armik.Hold("panda_joint2", 0.3), armik.Hold("panda_joint6", None)]
    opts = Options.from_kwargs({"constraints": both})
    assert opts.hold == (("panda_joint2", 0.3), ("panda_joint6", None))
    assert opts == Options.from_kwargs({"hold": {"panda_joint2": 0.3, "panda_joint6": None}})
    assert [c for c in opts.constraints if isinstance(c, armik.Hold)] == both


def test_a_joint_held_twice_is_refused():
    arm = conftest.arm("panda")
    T = arm.fk(arm.middle)
    with pytest.raises(armik.OptionError, match="panda_joint2 is held twice"):
        arm.solve(T, constraints=[armik.Hold("panda_joint2", 0.1), armik.Hold("panda_joint2", 0.2)])
    with pytest.raises(armik.OptionError, match="hold is given twice.*as an option"):
        arm.solve(T, constraints=[armik.Hold("panda_joint2")], hold={"panda_joint6": 0.2})


def test_two_joints_of_a_panda_held_for_a_pose():
    """Two joints held at an answer's values leave five for a pose: solved, both held
    exactly, the pose on the arm's FK."""
    arm = conftest.arm("panda")
    rng = np.random.default_rng(5)
    solved = 0
    for _ in range(5):
        q = arm.random_q(rng)
        T = arm.fk(q)
        held = [armik.Hold("panda_joint3", float(q[2])), armik.Hold("panda_joint7", float(q[6]))]
        r = arm.solve(T, q0=arm.random_q(rng), constraints=held, **BUDGET)
        if not r.success:  # five joints and a 6-D pose: a start may miss, never falsely
            assert r.status is not armik.Status.CONVERGED
            continue
        solved += 1
        assert r.q[2] == q[2] and r.q[6] == q[6]
        reached = arm.fk(r.q)
        assert np.linalg.norm(reached.translation - T.translation) <= 1e-6
        assert "held at" in r.reason
    assert solved >= 4


def test_two_joints_of_a_ur5_held_for_a_position():
    """A UR5's position with its wrist's last two joints held at the values of a
    configuration that reaches it (the other four then do), from another start; the same
    as the task list."""
    arm = conftest.arm("ur5")
    rng = np.random.default_rng(6)
    for _ in range(4):
        q = arm.random_q(rng)
        p = arm.fk(q).translation
        hold = {"wrist_2_joint": float(q[4]), "wrist_3_joint": float(q[5])}
        r = arm.solve(p, q0=arm.random_q(rng), hold=hold, **BUDGET)
        assert r.success and r.q[4] == q[4] and r.q[5] == q[5]
        assert np.linalg.norm(arm.fk(r.q).translation - p) <= 1e-6
        tasks = arm.solve([armik.Position(p)], q0=r.q, hold=hold, **BUDGET)
        assert tasks.success and np.array_equal(tasks.q, r.q)  # from an answer: stays


def test_one_joint_of_a_six_joint_arm_held_for_a_position():
    """What was refused before ("hold is for 7-joint arms"): a plain position with a held
    joint on a 6-joint arm is the task solver's."""
    arm = conftest.arm("ur5")
    p = arm.fk(arm.random_q(np.random.default_rng(7))).translation
    r = arm.solve(p, constraints=[armik.Hold("wrist_3_joint", 0.7)], **BUDGET)
    assert r.success and r.solver == "tasks" and r.q[5] == 0.7


def test_held_joints_that_leave_the_pose_out_of_reach_fail_honestly():
    """Every joint but one held away from any answer: not a success, with a reason."""
    arm = conftest.arm("ur5")
    T = arm.fk(np.array([0.3, -1.0, 1.2, -0.5, 1.0, 0.2]))
    names = arm.joint_names[:5]
    r = arm.solve(T, hold={n: 0.0 for n in names}, iteration_budget=300)
    assert not r.success and r.reason
    assert np.all(r.q[:5] == 0.0)


def test_a_followed_path_of_task_lists_holds_a_joint_of_a_six_joint_arm():
    """A UR5 path of task lists the compiled path takes (a position, the tool's z within
    0.1 rad of a direction) with a joint held: each waypoint's list read as ``solve`` reads
    it, the joint held by the task solver. It was refused as needing a 7-joint arm's closed
    form, where ``solve``, ``solve_batch`` and a path of plain poses all held it; a global
    plan is refused by name (the task solver gives one answer a waypoint)."""
    arm = conftest.arm("ur5")
    q = np.array([0.2, 0.3, 1.0, -0.5, 0.8, 0.1])
    T = arm.fk(q)
    z = T.rotation[:, 2]
    rows = [
        [armik.Position(T.translation + [0.0, 0.0, dz]), armik.Axis((0, 0, 1), z, 0.1)]
        for dz in (0.0, 0.005, 0.01)
    ]
    hold = {"shoulder_lift_joint": 0.3}
    path = arm.solve_path(rows, q, hold=hold, **BUDGET)
    for i, tasks in enumerate(rows):
        r = path[i]
        assert r.success, r.reason
        assert abs(r.q[1] - 0.3) <= 1e-9
        F = arm.fk(r.q)
        assert np.linalg.norm(F.translation - tasks[0].p) <= 1e-6
        assert float(F.rotation[:, 2] @ z) >= np.cos(0.1 + 1e-6)
    with pytest.raises(armik.OptionError, match="plan='global' .* held here") as e:
        arm.solve_path(rows, q, plan="global", hold=hold, **BUDGET)
    assert e.value.option == "hold"


def test_tip_frame_weights_the_task_solver_would_read_in_the_target_frame_are_refused():
    """``weights=`` weigh the tip frame's error; a pose whose held joints the task solver
    holds became ``armik.Pose(T, weights=w)``, weighed in the target frame. With x and the
    spin free the two free other poses: a UR5 answer 2 cm off in the tip frame's weighted y
    was a success. Refused by name; weights that free x alone are taken, the pose's
    weighted tip-frame error within the tolerance on an FK computed here."""
    arm = conftest.arm("ur5")
    q = np.array([0.2, -1.0, 1.4, -0.6, 1.1, 0.3])
    T = arm.fk(q)
    turn = T.rotation @ pin.exp3(np.array([0.0, 0.0, 0.5]))
    target = pin.SE3(turn, T.translation + 0.05 * T.rotation[:, 0])
    hold = {"wrist_3_joint": float(q[5])}
    for call in (
        lambda: arm.solve(target, q0=q, weights=(0, 1, 1, 1, 1, 0), hold=hold, **BUDGET),
        lambda: arm.solve_batch([target] * 2, q0=q, weights=(0, 1, 1, 0, 0, 0), hold=hold),
    ):
        with pytest.raises(armik.OptionError, match="weigh the tip frame's error") as e:
            call()
        assert e.value.option == "weights"
    w = np.array([0, 1, 1, 1, 1, 1.0])
    reach = pin.SE3(T.rotation, T.translation + 0.05 * T.rotation[:, 0])
    r = arm.solve(reach, q0=q, weights=tuple(w), hold=hold, **BUDGET)
    assert r.success, r.reason
    F = arm.fk(r.q)
    tip = np.concatenate(
        [
            F.rotation.T @ (F.translation - reach.translation),
            pin.log3(F.rotation.T @ reach.rotation),
        ]
    )
    assert np.linalg.norm(w * tip) <= 1e-6 and abs(r.q[5] - q[5]) <= 1e-9
