"""The task solver's compiled descent (``armik.kernel.task_rows``, ``armik.solve.task_table``):
each frame's compiled chain against Pinocchio's FK and LOCAL Jacobian to 1e-12, on trees
(two hands over a shared torso, a prismatic lift, continuous joints) and on an elbow; each
task's compiled rows equal to its Python residual and Jacobian; the descent's answers
verified on Pinocchio's FK; the lists without a compiled form keep the Python descent."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.kernel.chain import Flat
from armik.kernel.fk import forward, jacobian_local
from armik.kernel.task_rows import stacked
from armik.model.union import Union
from armik.options import Options
from armik.problem.problem import Problem
from armik.solve import task_table as table_module
from armik.solve.task_table import task_table
from armik.solve.tasks import _placed, _stack, frame_ids, solve_tasks

from .. import conftest

ROBOTS = Path(armik.load("panda").source).parents[2]
TREES = {  # URDF in example-robot-data, the tips, another frame on a chain
    "talos": (
        "talos_data/robots/talos_reduced.urdf",
        ("gripper_left_base_link", "gripper_right_base_link"),
        "arm_left_4_link",
    ),
    "pr2": (
        "pr2_description/urdf/pr2.urdf",
        ("l_gripper_tool_frame", "r_gripper_tool_frame"),
        "r_elbow_flex_link",
    ),
}


def union(name: str) -> tuple[Union, tuple[str, ...]]:
    path, tips, other = TREES[name]
    robot = armik.load(str(ROBOTS / path), tips=list(tips))
    return Union(list(robot._chains.values())), (*tips, other)


def _pin_frame(arm, q, name):
    model, data = arm.model, arm.model.createData()
    pin.computeJointJacobians(model, data, arm.to_pin(q))
    fid = model.getFrameId(name)
    T = arm.T_base_world * pin.updateFramePlacement(model, data, fid)
    return T, pin.getFrameJacobian(model, data, fid, pin.LOCAL)


def _compiled_frame(chains, c, q):
    ch = table_module.FrameChains(*chains)
    flat = Flat(
        ch.packed[ch.offsets[c] : ch.offsets[c + 1]],
        ch.kinds[ch.kind_offsets[c] : ch.kind_offsets[c + 1]],
        ch.halton,
    )
    N = (len(flat.kind) - len(q)) // 2
    R, p, geo = np.empty((3, 3)), np.empty(3), np.empty((2, N, 3))
    forward(flat, q, R, p, geo[0], geo[1])
    J = np.empty((6, len(q)))
    jacobian_local(flat, R, p, geo[0], geo[1], J)
    return R, p, J


@pytest.mark.parametrize("name", sorted(TREES))
def test_each_frame_of_a_tree_is_pinocchios_to_1e_12(name):
    arm, frames = union(name)
    ids = tuple(arm.model.getFrameId(f) for f in frames)
    chains = table_module._CHAINS(arm, ids)
    assert chains is not None
    rng = np.random.default_rng(7)
    for _ in range(20):
        q = arm.random_q(rng)
        for c, frame in enumerate(frames):
            R, p, J = _compiled_frame(chains, c, q)
            T, J_pin = _pin_frame(arm, q, frame)
            assert np.abs(R - T.rotation).max() <= 1e-12
            assert np.abs(p - T.translation).max() <= 1e-12
            assert np.abs(J - J_pin).max() <= 1e-12


def test_an_elbow_of_an_arm_is_pinocchios_to_1e_12():
    km = conftest.model("panda")
    ids = (km.model.getFrameId("panda_link4"), km.tip_frame_id)
    chains = table_module._CHAINS(km, ids)
    rng = np.random.default_rng(3)
    for _ in range(20):
        q = km.random_q(rng)
        for c, frame in enumerate(("panda_link4", km.tip)):
            R, p, J = _compiled_frame(chains, c, q)
            T, J_pin = _pin_frame(km, q, frame)
            assert np.abs(R - T.rotation).max() <= 1e-12
            assert np.abs(p - T.translation).max() <= 1e-12
            assert np.abs(J - J_pin).max() <= 1e-12
            if c == 0:  # the elbow: the joints past it do not move it
                assert not J[:, 4:].any() and J[:, :4].any()


def _tasks(arm, a, b, q):
    Ta, Tb = arm.fk(q, a), arm.fk(q, b)
    return (
        armik.Pose(Ta, frame=a, bounds=(0.01, 0.0, 0.02, 0.0, 0.1, 0.0)),
        armik.Position(Tb.translation, frame=b, bounds=(0.005, 0.0, math.inf)),
        armik.Axis((0, 0, 1), (0.0, 0.3, -1.0), 0.05, frame=b),
        armik.LookAt((0.5, 0.1, 0.2), (1, 0, 0), 0.02, frame=a),
        armik.Pose(Tb, weights=(1, 1, 1, 0, 0, 2), frame=b),
        armik.Axis((1, 0, 0), Ta.rotation[:, 0], 0.0, frame=a),
    )


def test_each_tasks_compiled_rows_are_its_python_rows():
    """Six rows a task in the table (its unused ones zero), the Python task's rows in them:
    a pose within bounds and weighted, a position in a box, an axis in a cone and exact, a
    look-at; at configurations near the targets and far from them (rows inside and outside
    their regions)."""
    arm, (a, b, _) = union("talos")
    rng = np.random.default_rng(11)
    for k in range(20):
        q = arm.random_q(rng)
        tasks = _tasks(arm, a, b, q)
        ids = frame_ids(arm, tasks)
        table = task_table(arm, tasks, ids)
        ch = table.chains
        at = q + (0.02 if k % 2 else 0.5) * rng.standard_normal(len(q))
        e, A = stacked(*ch, table.R_t, table.p_t, table.params, table.ints, at)
        r, A_py = _stack(tasks, ids, _placed(arm, at, ids))
        row = 0
        for t, task in enumerate(tasks):
            # a pose's six rows; a position's first three; a direction's last three
            rows = slice(6 * t, 6 * t + 6) if task.rows == 6 else None
            if rows is None:
                first = type(task) is armik.Position
                rows = slice(6 * t, 6 * t + 3) if first else slice(6 * t + 3, 6 * t + 6)
                unused = slice(6 * t + 3, 6 * t + 6) if first else slice(6 * t, 6 * t + 3)
                assert not e[unused].any() and not A[unused].any()
            mine = slice(row, row + task.rows)
            assert np.abs(-e[rows] - r[mine]).max() <= 1e-12, type(task).__name__
            assert np.abs(A[rows] - A_py[mine]).max() <= 1e-12, type(task).__name__
            row += task.rows


@pytest.mark.parametrize("name", sorted(TREES))
def test_both_hands_and_an_elbow_are_solved_and_verified(name):
    """Three frames of a tree at once, from FK of random configurations: every answer holds
    every task on Pinocchio's FK of the model, within the limits."""
    arm, (a, b, elbow) = union(name)
    rng = np.random.default_rng(21)
    solved = 0
    for _ in range(15):
        q = arm.random_q(rng)
        tasks = (
            armik.Pose(arm.fk(q, a), frame=a),
            armik.Position(arm.fk(q, b).translation, frame=b),
            armik.Position(arm.fk(q, elbow).translation, bounds=(0.05,) * 3, frame=elbow),
        )
        r = _solve(arm, tasks)
        assert r.solver == "tasks"
        if not r.success:
            continue
        solved += 1
        for task in tasks:
            assert task.measure(arm.fk(r.q, task.frame), 1e-6, 1e-6).within
        assert arm.within_limits(r.q)
    assert solved >= 14


def _solve(arm, tasks):
    opts = Options(iteration_budget=3000, seed=0)  # deterministic: no clock
    return solve_tasks(arm, Problem(tasks, budget=opts.budget), None, opts, 0.0)


def test_a_panda_tip_and_its_elbow_go_through_the_table(monkeypatch):
    """Position and axis of the tip with the elbow in a box: the compiled descent runs (a
    table is built) and every answer holds on Pinocchio's FK."""
    arm = conftest.arm("panda")
    km = arm.kinematics
    built = []
    real = table_module.task_table

    def counted(*args):
        built.append(real(*args))
        return built[-1]

    monkeypatch.setattr("armik.solve.tasks.task_table", counted)
    rng = np.random.default_rng(4)
    for _ in range(20):
        q = arm.random_q(rng)
        T = arm.fk(q)
        elbow = conftest.frame_position(arm, q, "panda_link4")
        tasks = [
            armik.Position(T.translation),
            armik.Axis((0, 0, 1), T.rotation[:, 2], 0.05),
            armik.Position(elbow, bounds=(0.03,) * 3, frame="panda_link4"),
        ]
        r = arm.solve(tasks, iteration_budget=3000, seed=1)
        assert r.success, r.reason
        for task in tasks:
            T_frame = _pin_frame(km, r.q, task.frame or km.tip)[0]
            assert task.measure(T_frame, 1e-6, 1e-6).within
    assert built and all(t is not None for t in built)


def test_a_relative_tasks_compiled_rows_are_its_python_rows():
    """One hand's pose in the other's (exact, and within bounds with a weight): the
    compiled placement in the reference frame and its Jacobian, ``J_frame - Ad(T^-1)
    J_ref``, give the Python task's rows."""
    arm, (a, b, _) = union("talos")
    rng = np.random.default_rng(12)
    for k in range(20):
        q = arm.random_q(rng)
        T_rel = arm.fk(q, a).actInv(arm.fk(q, b))
        tasks = (
            armik.Relative(b, a, T_rel),
            armik.Relative(
                a, b, T_rel.inverse(), bounds=(0.01, 0, 0, 0, 0.2, 0), weights=(1,) * 5 + (3,)
            ),
        )
        ids = frame_ids(arm, tasks)
        table = task_table(arm, tasks, ids)
        at = q + (0.02 if k % 2 else 0.5) * rng.standard_normal(len(q))
        e, A = stacked(*table.chains, table.R_t, table.p_t, table.params, table.ints, at)
        r, A_py = _stack(tasks, ids, _placed(arm, at, ids))
        assert np.abs(-e - r).max() <= 1e-12
        assert np.abs(A - A_py).max() <= 1e-12


def test_a_list_with_a_task_of_its_own_keeps_the_python_descent():
    """A task the user wrote, with no compiled rows: no table, the Python descent."""

    class Height(armik.Position):
        def kernel_row(self):
            return None

    arm, (a, _, _) = union("talos")
    tasks = (armik.Pose(arm.fk(arm.middle, a), frame=a), Height((0, 0, 1), frame=a))
    assert task_table(arm, tasks, frame_ids(arm, tasks)) is None


def test_a_tips_target_may_hold_a_task_on_another_frame_of_its_chain():
    """TALOS's hands over the shared torso with the left elbow in a box: the left tip's
    list holds the elbow's task; a task on the other tip is still that tip's to give."""
    path, tips, elbow = TREES["talos"]
    robot = armik.load(str(ROBOTS / path), tips=list(tips))
    arm, _ = union("talos")
    rng = np.random.default_rng(8)
    solved = 0
    for _ in range(10):
        q = robot.random_q(rng)
        T_a, T_b = robot.fk(q, tips[0]), robot.fk(q, tips[1])
        box = armik.Position(
            arm.fk(_in_union(robot, arm, q), elbow).translation, (0.05,) * 3, elbow
        )
        r = robot.solve({tips[0]: [armik.Pose(T_a), box], tips[1]: T_b}, iteration_budget=3000)
        if not r.success:
            continue
        solved += 1
        at = _in_union(robot, arm, r.q)
        assert box.measure(arm.fk(at, elbow), 1e-6, 1e-6).within
        assert armik.Pose(T_b).measure(arm.fk(at, tips[1]), 1e-6, 1e-6).within
    assert solved >= 9
    with pytest.raises(armik.errors.TargetError, match="its own tasks"):
        robot.solve({tips[0]: [armik.Pose(T_a), armik.Position(T_b.translation, frame=tips[1])]})


def _in_union(robot, arm, q):
    """The union's joint values from the robot's q (ordered by ``robot.joint_names``)."""
    return np.array([q[robot.joint_names.index(n)] for n in arm.joint_names])


def test_an_arm_with_mimic_joints_has_its_frames_compiled():
    """A frame past a mimic joint and the tip (tests/model/test_mimic.py's arm: a revolute
    and a prismatic joint mimicking drivers): the compiled rows are the Python task's on
    Pinocchio's mimic model, and a list on both frames is solved and verified."""
    from ..model.test_mimic import five_joint_urdf

    arm = armik.load_string(five_joint_urdf(), base="base", tip="tip")
    km = arm.kinematics
    assert km.mimics
    rng = np.random.default_rng(9)
    for k in range(10):
        q = km.random_q(rng)
        T, p = km.fk(q), _pin_frame(km, q, "l3")[0].translation
        tasks = (armik.Pose(T, weights=(1, 1, 1, 0, 0, 0)), armik.Position(p, frame="l3"))
        ids = frame_ids(km, tasks)
        table = task_table(km, tasks, ids)
        at = q + 0.3 * rng.standard_normal(len(q))
        e, A = stacked(*table.chains, table.R_t, table.p_t, table.params, table.ints, at)
        r, A_py = _stack(tasks, ids, _placed(km, at, ids))
        assert np.abs(-e[:6] - r[:6]).max() <= 1e-12 and np.abs(-e[6:9] - r[6:9]).max() <= 1e-12
        assert np.abs(A[:9] - A_py[:9]).max() <= 1e-12
        got = arm.solve(list(tasks), iteration_budget=3000, seed=k)
        assert got.success, got.reason
        assert np.linalg.norm(_pin_frame(km, got.q, "l3")[0].translation - p) <= 1e-6
