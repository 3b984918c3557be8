"""Bad input to several tips is an armik error naming it on every route: a tip's
constraints that are no constraint, a held torso joint outside its limits over shared
joints, and options given where every tip's target is beyond reach (read as where one tip
is solved)."""

from __future__ import annotations

import numpy as np
import pytest

import armik

from .test_arms_collision import dual
from .test_arms_parity import HANDS, TALOS


def test_a_tip_s_constraints_that_are_no_constraint_are_refused_by_name():
    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    T = robot.fk(robot.middle, "l_tool0")
    with pytest.raises(armik.OptionError, match=r"constraints\['l_tool0'\]"):
        robot.solve({"l_tool0": T}, constraints={"l_tool0": 3})


@pytest.fixture(scope="module")
def talos():
    return armik.load(TALOS, tips=HANDS)


def test_a_held_joint_outside_its_limits_over_shared_joints_is_named(talos):
    T = talos.fk(talos.middle, HANDS[0])
    for joint in ("torso_1_joint", "arm_left_1_joint"):
        with pytest.raises(armik.JointError, match=f"outside joint '{joint}'"):
            talos.solve({HANDS[0]: T}, hold={joint: 100.0})


@pytest.mark.parametrize(
    ("options", "error"),
    [
        ({"bogus": 1}, armik.OptionError),
        ({"solver": "bogus"}, armik.SolverError),
        ({"hold": {"nope": 1.0}}, armik.JointError),
        ({"hold": {"torso_1_joint": 100.0}}, armik.JointError),
        ({"margin": -1}, armik.OptionError),
    ],
)
def test_options_are_read_where_every_tip_is_beyond_reach(talos, options, error):
    far = np.array([5.0, 0.0, 0.0])
    near = talos.fk(talos.middle, HANDS[0]).translation
    for targets in ({HANDS[0]: near, HANDS[1]: far}, {HANDS[0]: far, HANDS[1]: far}):
        with pytest.raises(error):
            talos.solve(targets, **options)
    r = talos.solve({HANDS[0]: far, HANDS[1]: far})  # without them: the failure it was
    assert not r.success and r.status is armik.Status.UNREACHABLE


def test_a_target_built_by_hand_whose_rotation_is_no_rotation_is_refused_by_name(talos):
    q = talos.random_q(1)
    T = {tip: talos.fk(q, tip) for tip in talos.tips}
    left = talos.tips[0]
    good = armik.Target(T[left].translation.copy(), T[left].rotation.copy())
    assert talos.solve({**T, left: good}).success  # a Target by hand, a rotation: solved
    bad = armik.Target(T[left].translation.copy(), 2.0 * T[left].rotation)
    with pytest.raises(armik.TargetError, match=f"tip {left!r}.*not orthonormal"):
        talos.solve({**T, left: bad})


def test_a_tips_rows_of_position_and_quaternion_are_a_batch_and_a_path_as_on_one_arm():
    """``{tip: [(xyz, quat), ...]}`` is N poses per tip, as ``Arm.solve_batch`` reads a
    list of them (a ragged row crashed in numpy); one ``(xyz, quat)`` per tip is refused as
    one pose."""
    import pinocchio as pin

    robot = armik.load(dual("ur5"), tips=["l_tool0", "r_tool0"])
    rng = np.random.default_rng(3)
    qs = [robot.middle + rng.uniform(-0.2, 0.2, robot.dof) for _ in range(2)]
    rows = {
        t: [(robot.fk(q, t).translation, pin.Quaternion(robot.fk(q, t).rotation).coeffs())
            for q in qs]
        for t in robot.tips
    }  # fmt: skip
    batch = robot.solve_batch(rows, q0=qs[0])
    path = robot.solve_path(rows, qs[0])
    for rs in (list(batch), path):
        assert [r.success for r in rs] == [True, True]
        for r, q in zip(rs, qs):
            for t in robot.tips:
                assert np.allclose(
                    robot.fk(r.q, t).homogeneous, robot.fk(q, t).homogeneous, atol=1e-6
                )
    with pytest.raises(armik.TargetError, match=r"one \(position, quaternion\)"):
        robot.solve_batch({t: rows[t][0] for t in robot.tips})
