"""A servo on several tips (``Arms.servo``): each chain its own servo, ticked side by side
(the joined q is each chain's own servo's, bit for bit), every limit on the joined
sequence, the status of the tip most held back, and what is not supported refused by
name."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import OptionError, TargetError
from armik.servo.streams import START as STARTS
from armik.servo.streams import circle, violations

from ..test_arms import dual_irb120

DT = 0.002
START = np.array([0.0, 0.2, 0.2, 0.0, 0.8, 0.0])  # each IRB 120 of the cell


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def _streams(cell, q0):
    TL, TR = cell.fk(q0, "l_tool0"), cell.fk(q0, "r_tool0")
    left = circle(TL, 600, DT, radius=0.05)
    right = [TR.translation + np.array([0.0, 0.0, -0.1])] * 600  # a position, 10 cm down
    return left, right


def test_each_chain_is_its_own_servo_and_every_limit_holds(cell):
    q0 = np.concatenate([START, START])
    left, right = _streams(cell, q0)
    servo = cell.servo(q0, dt=DT, acceleration_limits=15.0)
    rec = servo.track([{"l_tool0": a, "r_tool0": b} for a, b in zip(left, right)])
    alone_l = cell.chain("l_tool0").servo(START, dt=DT, acceleration_limits=15.0).track(left)
    alone_r = cell.chain("r_tool0").servo(START, dt=DT, acceleration_limits=15.0).track(right)
    assert rec.q.shape == (600, 12)
    assert np.array_equal(rec.q, np.hstack([alone_l.q, alone_r.q]))
    over = violations(
        q0, rec.q, cell.lower, cell.upper, servo.velocity_limits, servo.acceleration_limits, DT
    )
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}
    # the joined step's errors are the larger tip's; the tips' own FK says where they are
    assert np.array_equal(
        rec.position_error, np.maximum(alone_l.position_error, alone_r.position_error)
    )
    q = rec.q[-1]
    assert np.linalg.norm(cell.fk(q, "r_tool0").translation - right[-1]) < 1e-5
    assert np.linalg.norm(cell.fk(q, "l_tool0").translation - left[-1].translation) < 1e-3
    assert np.array_equal(servo.q, q) and servo.joint_names == cell.joint_names


def test_the_joined_status_is_the_tip_most_held_back(cell):
    q0 = np.concatenate([START, START])
    servo = cell.servo(q0, dt=DT)
    here = cell.fk(q0, "l_tool0")
    far = pin.SE3(np.eye(3), np.array([4.0, -0.5, 0.3]))
    for _ in range(3):
        s = servo.step({"l_tool0": here, "r_tool0": far})
    assert s.tips["l_tool0"].status == "on_target"
    assert s.tips["r_tool0"].status == "out_of_reach"
    assert s.status == "out_of_reach" and "out of reach" in s.reason
    assert s.position_error == s.tips["r_tool0"].position_error > 3.0
    assert np.allclose(s.q[:6], q0[:6], rtol=0.0, atol=1e-12)  # the other arm stays
    assert np.isfinite(s.q).all()


def test_bad_targets_are_refused_by_name(cell):
    servo = cell.servo(np.concatenate([START, START]))
    T = cell.fk(servo.q, "l_tool0")
    with pytest.raises(TargetError, match=r"no target for \['r_tool0'\]"):
        servo.step({"l_tool0": T})
    with pytest.raises(TargetError, match=r"unknown tips \['tool0'\]"):
        servo.step({"l_tool0": T, "r_tool0": T, "tool0": T})
    with pytest.raises(TargetError, match="one target per tip"):
        servo.step(T)
    with pytest.raises(OptionError, match="12 values"):
        cell.servo(START)


def test_what_is_not_supported_is_refused_with_the_way_round(cell):
    with pytest.raises(OptionError, match="self_collision is not supported"):
        cell.servo(np.concatenate([START, START]), self_collision=True)


@pytest.fixture(scope="module")
def elbow_and_hand() -> armik.Arms:
    """The Panda's elbow (``panda_link4``) and hand: chains that share joints 1 to 4."""
    return armik.load("panda", tips=["panda_link4", "panda_hand"])


def test_chains_that_share_joints_step_their_union_within_every_limit(elbow_and_hand):
    robot = elbow_and_hand
    assert robot.shared
    q0 = STARTS["panda"]
    # the hand's pose and the elbow's position along a joint-space sway: 9 rows over 7
    # joints, every tick's targets met by one configuration
    sway = np.array([0.5, -0.3, 0.4, 0.3, -0.5, 0.4, 0.2])
    path = [q0 + 0.2 * np.sin(2 * np.pi * 0.5 * k * DT) * sway for k in range(1, 601)]
    hand = [robot.fk(q, "panda_hand") for q in path]
    elbow = [robot.fk(q, "panda_link4").translation for q in path]
    servo = robot.servo(q0, dt=DT, acceleration_limits=15.0)
    rec = servo.track([{"panda_hand": T, "panda_link4": p} for T, p in zip(hand, elbow)])
    over = violations(q0, rec.q, robot.lower, robot.upper, servo.velocity_limits, 15.0, DT)
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}
    q = rec.q[-1]
    reached = robot.fk(q, "panda_hand")
    assert np.linalg.norm(reached.translation - hand[-1].translation) < 1e-5
    assert np.linalg.norm(pin.log3(hand[-1].rotation @ reached.rotation.T)) < 1e-4
    assert np.linalg.norm(robot.fk(q, "panda_link4").translation - elbow[-1]) < 1e-5
    assert np.max(rec.position_error[100:]) < 1e-5  # once up to speed (from rest)
    assert np.isclose(
        rec.position_error[-1],
        max(
            np.linalg.norm(reached.translation - hand[-1].translation),
            np.linalg.norm(robot.fk(q, "panda_link4").translation - elbow[-1]),
        ),
    )
    assert np.array_equal(servo.q, q) and servo.joint_names == robot.joint_names


def test_a_target_out_of_reach_over_shared_joints_is_said_and_left(elbow_and_hand):
    robot = elbow_and_hand
    q0 = STARTS["panda"]
    hand, elbow = robot.fk(q0, "panda_hand"), robot.fk(q0, "panda_link4").translation
    far = hand.translation + np.array([3.0, 0.0, 0.0])
    servo = robot.servo(q0, dt=DT)
    away = servo.track([{"panda_hand": far, "panda_link4": elbow}] * 300)
    assert away.status[-1] == "out_of_reach" and np.isfinite(away.q).all()
    back = servo.track([{"panda_hand": hand, "panda_link4": elbow}] * 2500)
    assert back.status[-1] == "on_target" and back.position_error[-1] < 1e-4
    Q = np.vstack([away.q, back.q])
    assert violations(q0, Q, robot.lower, robot.upper, servo.velocity_limits,
                      servo.acceleration_limits, DT) == {
        "position": 0.0, "velocity": 0.0, "acceleration": 0.0
    }  # fmt: skip


def test_what_a_servo_over_shared_joints_does_not_take_is_refused(elbow_and_hand):
    robot = elbow_and_hand
    q0 = STARTS["panda"]
    with pytest.raises(OptionError, match="self_collision is not supported"):
        robot.servo(q0, self_collision=True)
    with pytest.raises(OptionError, match=r"weights= is not supported.*panda_joint1"):
        robot.servo(q0, weights=[1.0] * 6)
    servo = robot.servo(q0)
    with pytest.raises(OptionError, match="share joints: one servo steps their union"):
        servo.servo("panda_hand")
    hand = robot.fk(q0, "panda_hand")
    elsewhere = armik.Pose(hand, frame="panda_link4")
    with pytest.raises(TargetError, match="tip 'panda_hand'.*the servo follows tasks on the tip"):
        servo.step({"panda_hand": elsewhere, "panda_link4": hand.translation})
    with pytest.raises(TargetError, match="the target of tip 'panda_link4'"):
        servo.step({"panda_hand": hand, "panda_link4": "up"})
    bent = hand.homogeneous.copy()
    bent[0, 0] = np.nan  # not a pose: read by the parser, refused naming the tip
    with pytest.raises(TargetError, match="the target of tip 'panda_hand'"):
        servo.step({"panda_hand": bent, "panda_link4": hand.translation})
    with pytest.raises(OptionError, match="q0 must hold 7"):
        robot.servo(q0[:5])
    with pytest.raises(OptionError, match="q0 must hold 7 finite"):
        robot.servo("up")
    with pytest.raises(OptionError, match="within the joint limits"):
        robot.servo(robot.upper + 0.1)


@pytest.fixture(scope="module")
def pr2() -> armik.Arms:
    """PR2's two grippers: their chains share the torso's lift, a prismatic joint; the
    forearm and wrist rolls are continuous."""
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "pr2_description" / "urdf" / "pr2.urdf"
    return armik.load(urdf, tips=["l_gripper_tool_frame", "r_gripper_tool_frame"])


def test_a_shared_lift_and_continuous_joints_step_within_their_limits(pr2):
    q0 = pr2.middle
    assert pr2.shared == ("torso_lift_joint",)
    up = {tip: pr2.fk(q0, tip).translation + np.array([0.0, 0.0, 0.1]) for tip in pr2.tips}
    servo = pr2.servo(q0, dt=DT)
    rec = servo.track([up] * 1500)
    assert rec.status[-1] == "on_target" and rec.position_error[-1] < 1e-6
    over = violations(
        q0, rec.q, pr2.lower, pr2.upper, servo.velocity_limits, servo.acceleration_limits, DT
    )
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}
    for tip in pr2.tips:
        assert np.linalg.norm(pr2.fk(rec.q[-1], tip).translation - up[tip]) < 1e-6


@pytest.mark.parametrize("which", ["panda", "pr2"])
def test_the_rows_over_shared_joints_are_pinocchio_s(which, elbow_and_hand, pr2):
    """The compiled rows of the servo over shared joints (each chain's kernel FK and its
    servo's rows, scattered into the union's columns) against Pinocchio's FK and frame
    Jacobians of the union's model, to 1e-12: a pose's six rows ``-(R_t^T (p - p_t),
    log3(R_t^T R))`` and their Jacobian ``(R_t^T R J_v, Jlog3(R_t^T R) J_w)`` (LOCAL),
    a position's three; revolute joints (the Panda), a prismatic lift and continuous
    joints (PR2)."""
    robot = elbow_and_hand if which == "panda" else pr2
    servo = robot.servo(robot.middle)._union
    union = robot._joint()
    model, data = union.model, union.model.createData()
    rng = np.random.default_rng(7)
    first, second = robot.tips
    for trial in range(20):
        q = robot.random_q(rng)
        near = np.clip(q + rng.uniform(-0.5, 0.5, robot.dof), robot.lower, robot.upper)
        goals = {t: robot.fk(near, t) for t in robot.tips}  # (log3 is ill-conditioned at pi)
        if trial % 2:  # the first tip's position alone
            goals[first] = goals[first].translation
        E, A = servo.rows_at(goals, q)
        assert E.shape == (12,) and A.shape == (12, robot.dof)
        pin.computeJointJacobians(model, data, union.to_pin(q))
        for k, tip in enumerate(robot.tips):
            fid = model.getFrameId(tip)
            T = union.T_base_world * pin.updateFramePlacement(model, data, fid)
            J = pin.getFrameJacobian(model, data, fid, pin.LOCAL)
            goal = goals[tip]
            if not isinstance(goal, pin.SE3):
                goal = pin.SE3(np.eye(3), goal)
            M = goal.rotation.T @ T.rotation
            rows = slice(6 * k, 6 * k + 6)
            assert np.allclose(E[rows][:3], -goal.rotation.T @ (T.translation - goal.translation),
                               rtol=0.0, atol=1e-12)  # fmt: skip
            assert np.allclose(A[rows][:3], M @ J[:3], rtol=0.0, atol=1e-12)
            if tip == first and trial % 2:
                assert not E[rows][3:].any() and not A[rows][3:].any()  # rotation free
                continue
            assert np.allclose(E[rows][3:], -pin.log3(M), rtol=0.0, atol=1e-12)
            assert np.allclose(A[rows][3:], pin.Jlog3(M) @ J[3:], rtol=0.0, atol=1e-12)
