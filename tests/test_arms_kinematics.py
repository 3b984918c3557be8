"""Several tips answer in ``Arm``'s words (``armik.arms_kinematics``): every tip's placement,
Jacobian and poses of many configurations, the limits, random configurations; an empty
target mapping refused by name."""

from __future__ import annotations

import numpy as np
import pytest

import armik

TIPS = ["panda_hand", "panda_link5"]


@pytest.fixture(scope="module")
def robot():
    return armik.load("panda", tips=TIPS)


def test_fk_and_jacobian_without_a_frame_give_every_tip(robot):
    q = robot.random_q(1)
    every = robot.fk(q)
    assert list(every) == TIPS
    for tip in TIPS:
        assert every[tip].isApprox(robot.fk(q, frame=tip), 1e-14)
        single = robot.chain(tip)
        assert every[tip].isApprox(single.fk(robot.split(q)[tip]), 1e-14)
    for reference in ("local", "base"):
        J = robot.jacobian(q, reference=reference)
        assert list(J) == TIPS
        for tip in TIPS:
            np.testing.assert_array_equal(J[tip], robot.jacobian(q, tip, reference))
    np.testing.assert_array_equal(robot.jacobian(q, "base")["panda_hand"], J["panda_hand"])


def test_fk_batch_gives_every_tips_poses(robot):
    Q = robot.random_q(2, n=5)
    poses = robot.fk_batch(Q)
    assert list(poses) == TIPS
    for tip in TIPS:
        assert poses[tip].shape == (5, 4, 4)
        for i, q in enumerate(Q):
            np.testing.assert_allclose(poses[tip][i], robot.fk(q, tip).homogeneous, atol=1e-12)
    with pytest.raises(armik.OptionError, match=r"Q must have shape \(N, 7\).*got \(2, 3\)"):
        robot.fk_batch(np.zeros((2, 3)))
    with pytest.raises(armik.OptionError, match="Q must be an .*'abc'"):
        robot.fk_batch("abc")
    Q[3, 6] = np.nan  # the robot's row and joint named, not one chain's part of the row
    with pytest.raises(armik.OptionError, match="row 3 of Q is not finite at 'panda_joint7'"):
        robot.fk_batch(Q)


def test_random_q_takes_n_as_arm_does(robot):
    Q = robot.random_q(9, n=10)
    assert Q.shape == (10, robot.dof)
    assert all(robot.within_limits(q) for q in Q)
    np.testing.assert_array_equal(robot.random_q(9), robot.random_q(np.random.default_rng(9)))
    with pytest.raises(armik.OptionError, match="n must be an integer >= 0, got 'x'"):
        robot.random_q(9, n="x")
    with pytest.raises(armik.OptionError, match="rng must be .*got 'x'"):
        robot.random_q("x")


def test_within_limits_reads_one_configuration(robot):
    assert robot.within_limits(robot.middle)
    assert not robot.within_limits(robot.upper + 0.1)
    assert not robot.within_limits([np.nan] * robot.dof)
    with pytest.raises(armik.OptionError, match=r"q must have 7 values .*shape \(3,\)"):
        robot.within_limits([0.0] * 3)
    with pytest.raises(armik.OptionError, match="q must be 7 numbers.*'abc'"):
        robot.within_limits("abc")
    with pytest.raises(armik.OptionError, match="q must hold 7 values.*'abc'"):
        robot.fk("abc")


def test_an_empty_target_mapping_is_refused_by_name(robot):
    for solve in (robot.solve, robot.solve_all):
        with pytest.raises(armik.TargetError, match=r"empty mapping \{\}.*'panda_hand'"):
            solve({})


def test_an_empty_target_mapping_to_a_batch_or_a_path_is_refused_by_name(robot):
    with pytest.raises(armik.TargetError, match=r"no targets.*'panda_hand'"):
        robot.solve_batch({})
    with pytest.raises(armik.TargetError, match=r"no targets.*'panda_hand'"):
        robot.solve_path({}, None)


def test_a_plan_that_is_none_is_refused_as_on_one_arm(robot):
    with pytest.raises(armik.OptionError, match="plan must be 'follow'.*'bogus'"):
        robot.solve_path(robot.fk_batch(robot.random_q(0, n=3)), robot.middle, plan="bogus")
