"""A user's constraint resolved from the call's start (its ``at(arm, seed)``, CONTRIBUTING's
recipe) is resolved on every route, not only the task solver's: unresolved, its check
would run on nothing (here it raises; a check that passed unresolved would let any answer
through)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.base import Check, Constraint
from tests.conftest import arm as bundled

REACH = 0.3  # joint 1 within this of the start's value (rad)


class NearStart(Constraint):
    """Joint 1 within ``REACH`` of the start's value; unresolved it has nothing to hold."""

    def __init__(self, ref=None):
        self.ref = ref

    def at(self, arm, seed):
        return NearStart(float(seed[0]))

    def check(self, arm, Q):
        if self.ref is None:
            raise ValueError("NearStart: resolve with at(arm, seed) first")
        return Check(
            np.abs(Q[:, 0] - self.ref) < REACH, armik.Status.JOINT_LIMITS, lambda i: "moved"
        )


Q = np.array([0.4, -0.6, 1.2, 0.3, 1.1, -0.5])


def _ur5():
    arm = bundled("ur5")
    return arm, arm.fk(Q)


def _start(shift: float) -> np.ndarray:
    q0 = Q.copy()
    q0[0] += shift
    return q0


@pytest.mark.parametrize(
    "how",
    [{}, {"solver": "dls"}, {"prefer": "nearest"}, {"obstacles": [armik.Sphere(0.05, (2, 2, 2))]}],
)
def test_solve_resolves_it_from_q0(how):
    arm, T = _ur5()
    near = arm.solve(T, q0=_start(0.1), constraints=[NearStart()], **how)
    assert near.success and abs(near.q[0] - Q[0]) < 1e-6, near.reason
    far = arm.solve(T, q0=_start(1.0), constraints=[NearStart()], **how)
    assert not far.success and far.reason == "moved"


def test_solve_all_resolves_it_from_q0():
    arm, T = _ur5()
    every = arm.solve_all(T, q0=_start(0.1), constraints=[NearStart()])
    held = [r for r in every if r.success]
    assert held and all(abs(r.q[0] - Q[0] - 0.1) < REACH for r in held)
    assert len(held) < len(every)  # the branches with joint 1 elsewhere are refused


def test_a_batch_resolves_it_from_its_one_start_and_refuses_a_start_per_row():
    arm, T = _ur5()
    rows = arm.solve_batch([T, T], q0=_start(0.1), constraints=[NearStart()], workers=1)
    assert all(r.success and abs(r.q[0] - Q[0]) < 1e-6 for r in rows)
    rows = arm.solve_batch([T, T], q0=_start(1.0), constraints=[NearStart()], workers=1)
    assert not any(r.success for r in rows)
    with pytest.raises(armik.OptionError, match="NearStart.*q0 per row"):
        arm.solve_batch([T, T], q0=np.stack([_start(0.1), _start(0.2)]), constraints=[NearStart()])


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_a_path_resolves_it_from_its_start(plan):
    arm, T = _ur5()
    path = arm.solve_path([T, T], _start(0.1), constraints=[NearStart()], plan=plan)
    assert path.success.all() and np.all(np.abs(path.q[:, 0] - Q[0]) < 1e-6)
    path = arm.solve_path([T, T], _start(1.0), constraints=[NearStart()], plan=plan)
    assert not path.success.any()


def test_several_tips_over_a_shared_torso_resolve_it_from_q0_not_a_chains_start():
    """TALOS's hands over a shared torso: the descent starts from each chain's answer, and
    the constraint is the call's, resolved from its q0 (it was resolved from that start:
    a success with the torso 0.5 rad from q0's value)."""
    from tests.test_arms import talos

    robot = talos()
    left = robot.tips[0]
    j = robot.joint_names.index(robot.chain(left).joint_names[0])  # the torso's first joint
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(4):
        q = robot.random_q(rng)
        T = {tip: robot.fk(q, tip) for tip in robot.tips}
        q0 = np.clip(q + 0.6, robot.lower, robot.upper)
        r = robot.solve(T, q0=q0, constraints={left: [NearStart()]})
        if r.success:
            assert abs(r.q[j] - q0[j]) < REACH, (r.q[j], q0[j])
            checked += 1
        else:
            assert r.status is armik.Status.JOINT_LIMITS or r.status is armik.Status.NOT_CONVERGED
    assert checked


def _dual():
    from tests.test_arms import dual_irb120

    robot = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    q = robot.random_q(np.random.default_rng(2))
    q[1] = 0.8
    return robot, q


def test_several_tips_take_constraints_none_as_one_arm_does():
    robot, q = _dual()
    T = {t: robot.fk(q, t) for t in robot.tips}
    assert robot.solve(T, constraints=None).success


def _relative_tasks(robot, q, left_task):
    left, right = robot.tips
    T = {t: robot.fk(q, t) for t in robot.tips}
    return T, [left_task(T[left], left), armik.Relative(right, left, T[left].inverse() * T[right])]


def test_a_relative_task_solved_together_again_starts_from_the_chains_answer_quietly():
    """Chains apart with a relative task whose chains' answers fail a constraint are solved
    together again from those answers (clipped into the limits): a q0 within the limits
    gives no warning that it was clipped (it warned, the failing answer taken for q0). No
    answer within the limits holds this constraint: the call fails, and says so (the
    together solve checks it: unchecked, it returned q0's branch as a success)."""
    import warnings

    class Below(Constraint):
        def check(self, arm, Q):
            return Check(Q[:, 1] < 0.2, armik.Status.JOINT_LIMITS, lambda i: "joint 2 above")

    robot, q = _dual()
    assert robot.within_limits(q)
    _, tasks = _relative_tasks(robot, q, lambda T, tip: armik.Pose(T, frame=tip))
    with warnings.catch_warnings():
        warnings.simplefilter("error", armik.ArmikWarning)
        r = robot.solve(tasks, q0=q, constraints={robot.tips[0]: [Below()]}, iteration_budget=1000)
    assert not r.success and r.status is armik.Status.JOINT_LIMITS, r.reason


def test_a_relative_task_solved_together_again_holds_the_constraint():
    """The left tip given a position only: its chain's answer from q0 is q0 itself, joint 2
    at 0.8 rad, which the constraint refuses, and the right tip cannot reach its relative
    pose from the chain's answer that holds it; solved together, the answer holds the
    constraint and both tasks, by Pinocchio."""

    class Above(Constraint):
        def check(self, arm, Q):
            return Check(Q[:, 1] > 1.0, armik.Status.JOINT_LIMITS, lambda i: "joint 2 below")

    robot, q = _dual()
    assert q[1] < 1.0  # q0 fails the constraint
    left, right = robot.tips
    T, tasks = _relative_tasks(robot, q, lambda T, tip: armik.Position(T.translation, frame=tip))
    r = robot.solve(tasks, q0=q, constraints={left: [Above()]}, iteration_budget=1000)
    assert r.success and r.reason.startswith("every task holds"), r.reason  # together
    assert r.q[1] > 1.0
    reached = {t: _pinocchio_tip(r.q, t) for t in robot.tips}
    assert np.linalg.norm(reached[left].translation - T[left].translation) < 1e-6
    relative = T[left].inverse() * T[right]
    apart = pin.log6(reached[left].actInv(reached[right]).actInv(relative)).vector
    assert np.linalg.norm(apart) < 2e-6


def _pinocchio_tip(q, tip: str) -> pin.SE3:
    """``tip``'s pose at the dual IRB 120's joints ``q`` by Pinocchio, on the URDF's whole model
    (its root, the base, is the world)."""
    from tests.test_arms import dual_irb120

    model = pin.buildModelFromXML(dual_irb120())
    data = model.createData()
    full = pin.neutral(model)
    names = [f"{side}joint_{i}" for side in ("l_", "r_") for i in range(1, 7)]
    for name, value in zip(names, q):
        full[model.joints[model.getJointId(name)].idx_q] = value
    pin.framesForwardKinematics(model, data, full)
    return data.oMf[model.getFrameId(tip)].copy()


@pytest.mark.parametrize("q0", [[[0.1] * 6, [0.2] * 5], "middle", [[0.1] * 6, [0.2] * 6]])
def test_a_q0_that_is_no_configuration_is_named_as_without_the_constraint(q0):
    """Ragged, text or a batch's rows given to ``solve``: ``q0``'s own words (a raw numpy
    ``ValueError`` before), never a batch's on a single solve."""
    arm, T = _ur5()
    with pytest.raises(armik.OptionError, match="q0 must") as info:
        arm.solve(T, q0=q0, constraints=[NearStart()])
    assert "per row" not in str(info.value)


def test_a_held_joints_route_resolves_it_from_q0():
    """``hold=`` on a 6-joint arm (the task solver, started from the compiled centre's
    answer): the centre's verdict checked it unresolved (an ``OptionError``)."""
    arm, T = _ur5()
    r = arm.solve(T, q0=_start(0.1), hold={"wrist_3_joint": float(Q[5])}, constraints=[NearStart()])
    assert r.success and abs(r.q[0] - Q[0]) < 1e-6, r.reason


def test_a_path_followed_by_the_task_solver_keeps_it_resolved_from_q0():
    """``hold=`` on a 6-joint arm: each waypoint solved as ``solve`` solves it, from the
    answer before; the task solver resolved the constraint again there, and waypoints with
    joint 1 0.6 and 0.8 rad from q0's were successes."""
    arm, _ = _ur5()
    poses = []
    for i in range(5):
        q = Q.copy()
        q[0] += 0.2 * i
        poses.append(arm.fk(q))
    p = arm.solve_path(poses, Q, constraints=[NearStart()], hold={"wrist_3_joint": float(Q[5])})
    assert p.success[:2].all()
    for i in range(5):
        assert not p.success[i] or abs(p.q[i, 0] - Q[0]) < REACH, (i, p.q[i, 0])


def test_a_path_of_several_tips_refuses_it_by_name():
    """A path of several tips solves rows again from the waypoint before, where it would be
    resolved again: refused by name, not resolved from each waypoint."""
    robot, q = _dual()
    rows = {t: [robot.fk(q, t)] * 2 for t in robot.tips}
    with pytest.raises(armik.OptionError, match="NearStart is resolved from the start"):
        robot.solve_path(rows, q, constraints={robot.tips[0]: [NearStart()]})


@pytest.mark.parametrize("q0", [np.full((2, 6), np.nan), np.zeros((0, 6)), [[10**400] * 6] * 2])
def test_a_batch_q0_that_is_no_configuration_is_named_as_such(q0):
    arm, T = _ur5()
    with pytest.raises(armik.OptionError, match="q0") as info:
        arm.solve_batch([T, T], q0=q0, constraints=[NearStart()])
    assert "different q0 per row" not in str(info.value)


def test_several_tips_over_a_shared_torso_refuse_a_start_per_row_as_one_arm_does():
    """TALOS's hands over a shared torso solve a batch row by row, where the constraint was
    resolved from each row's q0 (chains apart and one arm refuse it): refused by name. One
    start given on every row resolves it from that start; rows that differ only on another
    chain's joints leave the constrained chain one start."""
    from tests.test_arms import talos

    robot = talos()
    left, right = robot.tips
    q = robot.random_q(np.random.default_rng(3))
    T = {tip: [robot.fk(q, tip)] * 2 for tip in robot.tips}
    far = np.clip(q + 0.6, robot.lower, robot.upper)
    with pytest.raises(armik.OptionError, match=r"NearStart \(constraints\[.*q0 per row"):
        robot.solve_batch(T, q0=np.stack([q, far]), constraints={left: [NearStart()]})
    j = robot.joint_names.index(robot.chain(left).joint_names[0])  # the torso's first joint
    same = robot.solve_batch(T, q0=np.stack([q, q]), constraints={left: [NearStart()]})
    assert same.success.all() and (np.abs(same.q[:, j] - q[j]) < REACH).all()
    other = q.copy()
    only_right = [robot.joint_names.index(n) for n in robot.chain(right).joint_names[2:]]
    assert not {robot.joint_names[i] for i in only_right} & set(robot.shared)
    other[only_right] = far[only_right]
    rows = robot.solve_batch(T, q0=np.stack([q, other]), constraints={left: [NearStart()]})
    assert rows.success.all() and (np.abs(rows.q[:, j] - q[j]) < REACH).all()


@pytest.mark.parametrize("shared", [False, True])
def test_several_tips_name_a_q0_of_the_wrong_row_count_as_a_q0(shared):
    """Two rows of q0 that differ, for three targets: the shape error, where the rows were
    read first and the constraint resolved from the start said they differ."""
    from tests.test_arms import talos

    robot, q = (talos(), None) if shared else _dual()
    q = robot.random_q(np.random.default_rng(3)) if q is None else q
    far = np.clip(q + 0.6, robot.lower, robot.upper)
    T = {tip: [robot.fk(q, tip)] * 3 for tip in robot.tips}
    with pytest.raises(armik.OptionError, match=r"q0 must be None.*\(3, \d+\), got shape \(2,"):
        robot.solve_batch(T, q0=np.stack([q, far]), constraints={robot.tips[0]: [NearStart()]})
