"""A joint held on the chain of a tip given no target: the robot's answer has it at the
held value on every route (that chain keeps q0's values but for it), as over shared
joints; a held value outside its limits is refused by name."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint

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


class _Below(Constraint):
    """A joint of one chain at most ``value`` (rad): a check of the test's own."""

    def __init__(self, joint: str, value: float) -> None:
        self.joint, self.value = joint, value

    def check(self, arm, Q):
        k = arm.joint_names.index(self.joint)
        ok = np.asarray(Q)[:, k] <= self.value
        return Check(ok, armik.Status.UNREACHABLE, lambda i: "above")


def test_a_tip_left_out_holds_its_own_constraints_at_the_values_it_keeps():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    k = robot.joint_names.index("r_elbow_joint")
    T = robot.fk(robot.random_q(1), "l_tool0")
    given = {"constraints": {"r_tool0": [_Below("r_elbow_joint", 0.0)]}}
    for value in (1.0, -1.0):  # q0's right elbow breaks it, then keeps it
        q0 = robot.middle.copy()
        q0[k] = value
        results = [
            robot.solve({"l_tool0": T}, q0=q0, **given),
            *robot.solve_all({"l_tool0": T}, q0=q0, **given)[:3],
            robot.solve_batch({"l_tool0": [T, T]}, q0=q0, **given)[1],
            robot.solve_path({"l_tool0": [T]}, q0, max_joint_step=10.0, **given)[0],
        ]
        for r in results:
            assert r.q[k] == value and r.success == (value <= 0.0)
            if not r.success:
                assert "'r_tool0'" in r.reason and r.status is armik.Status.UNREACHABLE


def test_a_held_joint_of_the_urdf_on_no_chain_is_named_as_such():
    """TALOS's leg joint, on neither hand's chain, and a fixed joint: said as such, not as
    an unknown joint with a joint of a chain suggested for it."""
    from .test_arms import talos

    robot = talos()
    info = robot.chain(robot.tips[0]).kinematics.info
    fixed = next(name for name, kind in info.joint_types.items() if kind == "fixed")
    q = robot.middle
    T = {tip: robot.fk(q, tip) for tip in robot.tips}
    for joint, words in (
        ("leg_left_1_joint", "'leg_left_1_joint' is on none of the chains of tips"),
        (fixed, f"{fixed!r} is a fixed joint: it has no value to hold"),
    ):
        with pytest.raises(armik.JointError, match=words) as err:
            robot.solve(T, q0=q, hold={joint: 0.0})
        assert "unknown" not in str(err.value) and err.value.joint == joint


def test_a_shared_joint_locked_after_with_limits_is_checked_against_those_limits():
    """TALOS's torso, shared by both hands: locked within limits widened past its URDF's
    1.309 rad on both chains (and pickled so), refused outside limits narrowed."""
    import pickle

    from .test_arms import talos

    robot = talos()
    wide = robot.with_limits({"torso_1_joint": (-1.5, 1.5)}).with_locked({"torso_1_joint": 1.4})
    assert wide.dof == robot.dof - 1 and "torso_1_joint" not in wide.joint_names
    for tip in wide.tips:
        assert dict(wide.chain(tip).locked) == {"torso_1_joint": 1.4}
    copy = pickle.loads(pickle.dumps(wide))
    q = wide.random_q(5)
    for tip in wide.tips:
        assert copy.fk(q, tip).isApprox(wide.fk(q, tip), 1e-14)
    narrow = robot.with_limits({"torso_1_joint": (-0.5, 0.5)})
    with pytest.raises(armik.JointError, match=r"outside its limits \(given by with_limits\)"):
        narrow.with_locked({"torso_1_joint": 1.0})


@pytest.mark.parametrize("joint", ["arm_left_4_joint", "arm_right_4_joint"])
def test_a_joint_of_one_chain_locked_after_with_limits_is_checked_against_them(joint):
    """TALOS's elbow, on one hand's chain only, locked 0.2 rad past its URDF limit within
    limits widened past it: the other chain, which locks it off its chain, checked it
    against the URDF's and refused it. Narrowed limits still refuse a value outside them."""
    import pickle

    from .test_arms import talos

    robot = talos()
    k = robot.joint_names.index(joint)
    lo, hi = float(robot.lower[k]), float(robot.upper[k])
    wide = robot.with_limits({joint: (lo - 0.3, hi + 0.3)})
    locked = wide.with_locked({joint: hi + 0.2})
    assert joint not in locked.joint_names and locked.dof == robot.dof - 1
    for tip in locked.tips:
        assert dict(locked.chain(tip).locked)[joint] == hi + 0.2
    q = wide.middle.copy()
    q[k] = hi + 0.2
    free = [n for n in wide.joint_names if n != joint]
    q_locked = q[[wide.joint_names.index(n) for n in free]]
    copy = pickle.loads(pickle.dumps(locked))
    for tip in robot.tips:  # the other chain's placement does not move with the joint
        assert locked.fk(q_locked, tip).isApprox(wide.fk(q, tip), 1e-12)
        assert copy.fk(q_locked, tip).isApprox(wide.fk(q, tip), 1e-12)
    narrow = robot.with_limits({joint: (lo + 0.1, hi - 0.1)})
    for value in (hi - 0.05, hi + 0.2):
        with pytest.raises(armik.JointError, match=rf"'{joint}' is outside its limits \(given"):
            narrow.with_locked({joint: value})
    with pytest.raises(armik.JointError, match=rf"'{joint}' is outside its limits \(given"):
        wide.with_locked({joint: hi + 0.4})


def test_a_start_within_the_limits_says_no_clipping():
    """Over shared joints each chain's answer starts the next chain's solve: a chain's
    failed answer outside its limits is a start clipped into them, said by no warning (44
    "q0 outside the joint limits was clipped" warnings on a q0 within them)."""
    import warnings

    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    Q = robot.random_q(np.random.default_rng(5), n=4)
    T = {t: robot.fk(Q[3], t) for t in robot.tips}
    assert robot.within_limits(Q[0])
    with warnings.catch_warnings():
        warnings.simplefilter("error", armik.ArmikWarning)
        r = robot.solve(T, q0=Q[0], hold={"panda_joint5": float(Q[0, 4])}, iteration_budget=2000)
    assert robot.within_limits(r.q)
