"""A tick's status is the command's: ``on_target`` only where Pinocchio's FK of the
returned q is within the tolerances of the target, and a step refused on several tips
moves no chain."""

from __future__ import annotations

import re

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import TargetError
from armik.servo.streams import START

from ..test_arms import dual_irb120

DT = 0.002
TOL = 1e-6  # the servo's default tolerances (m, rad)


def _off(T: pin.SE3, target: pin.SE3) -> tuple[float, float]:
    """Pinocchio's distances of T from target (m, rad)."""
    err = pin.log6(target.actInv(T)).vector
    return float(np.linalg.norm(T.translation - target.translation)), float(np.linalg.norm(err[3:]))


def _moving(servo, T0: pin.SE3) -> None:
    """``servo`` sent 25 cm along y for 60 ticks: moving at speed."""
    far = pin.SE3(T0.rotation, T0.translation + np.array([0.0, 0.25, 0.0]))
    for _ in range(60):
        servo.step(far)
    assert np.abs(servo.dq).max() > 1.0


class _Hand:
    """A servo over shared joints stepped by the hand's target, the elbow's held."""

    def __init__(self, servo, elbow: str, hand: str, at: np.ndarray) -> None:
        self.servo, self.elbow, self.hand, self.at = servo, elbow, hand, at

    def step(self, target: pin.SE3):
        return self.servo.step({self.elbow: self.at, self.hand: target})

    @property
    def dq(self) -> np.ndarray:
        return self.servo.dq


def test_a_moving_arm_told_to_stop_where_it_is_is_not_on_target_until_it_is():
    arm = armik.load("panda")
    q0 = START["panda"]
    servo = arm.servo(q0, dt=DT)
    _moving(servo, arm.fk(q0))
    here = arm.fk(servo.q)  # stop here: the arm cannot within one tick
    first = servo.step(here)
    assert first.status != "on_target"
    assert _off(arm.fk(first.q), here)[0] > 1e-3  # the arm has passed it, as said
    statuses = [first.status]
    for _ in range(1000):
        s = servo.step(here)
        statuses.append(s.status)
        if s.status == "on_target":  # the command's own FK, by Pinocchio
            pos, rot = _off(arm.fk(s.q), here)
            assert pos <= TOL and rot <= TOL
            assert s.position_error <= TOL and s.orientation_error <= TOL
    assert statuses[-1] == "on_target"


def test_over_shared_joints_too_a_moving_arm_told_to_stop_is_not_on_target():
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    assert robot.shared
    elbow, hand = robot.tips
    q0 = START["panda"]
    servo = robot.servo(q0, dt=DT)
    _moving(_Hand(servo, elbow, hand, robot.fk(q0, elbow).translation), robot.fk(q0, hand))
    here = {elbow: robot.fk(servo.q, elbow).translation, hand: robot.fk(servo.q, hand)}
    s = servo.step(here)
    assert s.status != "on_target"
    assert _off(robot.fk(s.q, hand), here[hand])[0] > 1e-3


def test_a_target_one_tip_cannot_read_moves_no_chain_and_names_the_tip():
    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    q = np.array([0.0, 0.2, 0.2, 0.0, 0.8, 0.0])
    q0 = np.concatenate([q, q])
    servo = cell.servo(q0, dt=DT)
    up = cell.fk(q0, "l_tool0").translation + np.array([0.0, 0.0, 0.05])
    with pytest.raises(TargetError, match=r"the target of tip 'r_tool0': .*NaN"):
        servo.step({"l_tool0": up, "r_tool0": np.array([np.nan, 0.0, 0.0])})
    assert np.array_equal(servo.q, q0) and not servo.dq.any()  # neither chain ticked
    # the same step with the right target ticks both, as a chain's own servo does
    right = cell.fk(q0, "r_tool0")
    s = servo.step({"l_tool0": up, "r_tool0": right})
    alone = cell.chain("l_tool0").servo(q, dt=DT).step(up)
    assert np.array_equal(s.q[:6], alone.q)


@pytest.mark.parametrize("margin", [-0.1, float("nan"), "1 cm", 2.0])
def test_a_bad_margin_is_refused_with_or_without_obstacles(margin):
    """Unread without obstacles, a bad margin was taken whatever it was."""
    arm = armik.load("panda")
    with pytest.raises(armik.CollisionError, match="margin") as caught:
        arm.servo(START["panda"], margin=margin)
    assert caught.value.option == "margin"
    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    q = np.array([0.0, 0.2, 0.2, 0.0, 0.8, 0.0])
    with pytest.raises(armik.CollisionError, match="margin"):
        cell.servo(np.concatenate([q, q]), margin=margin)
    shared = armik.load("panda", tips=["panda_link4", "panda_hand"])
    with pytest.raises(armik.CollisionError, match="margin"):
        shared.servo(START["panda"], margin=margin)
    ball = [armik.Sphere(0.05, (1.0, 1.0, 1.0))]
    arm.servo(START["panda"], obstacles=ball, margin=0.02)  # a distance: taken, as before
    arm.servo(START["panda"], margin=0.0)  # none: nothing asked of the collision checks


def test_a_margin_with_nothing_to_keep_from_is_refused_as_solve_refuses_it():
    """A margin and no obstacles, self_collision off: it checks nothing (a forgotten
    obstacles=), as ``solve`` says; on one arm and on several tips alike."""
    arm = armik.load("panda")
    with pytest.raises(armik.CollisionError, match="checks nothing") as caught:
        arm.servo(START["panda"], margin=0.02)
    assert caught.value.option == "margin"
    with pytest.raises(armik.OptionError, match="checks nothing"):
        arm.solve(arm.fk(START["panda"]), margin=0.02)  # the same rule
    shared = armik.load("panda", tips=["panda_link4", "panda_hand"])
    with pytest.raises(armik.CollisionError, match="checks nothing"):
        shared.servo(START["panda"], margin=0.02)
    assert shared.servo(START["panda"], self_collision=True, margin=0.02) is not None


def test_self_collision_is_numpy_s_bool_too_and_never_none():
    """``solve``'s rule: True or False, numpy's too (a mask's, a config's); None refused."""
    arm = armik.load("panda")
    q0 = START["panda"]
    T0 = arm.fk(q0)
    targets = [pin.SE3(T0.rotation, T0.translation + np.array([0.0, 0.1, -0.1]))] * 50
    plain = arm.servo(q0, self_collision=True).track(targets)
    numpy = arm.servo(q0, self_collision=np.True_).track(targets)
    assert np.array_equal(plain.q, numpy.q)
    arm.servo(q0, self_collision=np.False_)
    with pytest.raises(armik.CollisionError, match="self_collision") as caught:
        arm.servo(q0, self_collision=None)
    assert caught.value.option == "self_collision"
    shared = armik.load("panda", tips=["panda_link4", "panda_hand"])
    shared.servo(q0, self_collision=np.True_)
    with pytest.raises(armik.CollisionError, match="self_collision"):
        shared.servo(q0, self_collision=None)


def test_a_pose_a_five_joint_arm_cannot_take_ends_stalled_not_tracking():
    """The SO-101 (5 joints) told to roll its tool 0.7 rad about x where it stands: it
    settles at the nearest it gets, and says so, where it said ``tracking`` forever."""
    arm = armik.load("so101")
    q = arm.middle + 0.2
    T = arm.fk(q)
    rolled = pin.SE3(T.rotation @ pin.rpy.rpyToMatrix(0.7, 0.0, 0.0), T.translation)
    servo = arm.servo(q0=q, dt=0.004)
    steps = [servo.step(rolled) for _ in range(1500)]
    last = steps[-1]
    assert last.status == "stalled" and "stalled" in last.reason
    assert last.position_error > 1e-3  # off target: the arm cannot take that pose
    assert np.abs(last.dq).max() < 1e-9  # and holds still there
    assert "tracking" not in {s.status.value for s in steps[-100:]}


@pytest.mark.parametrize("name", ["ur5", "so101", "planar_2link"])
def test_a_reachable_target_is_never_called_stalled(name):
    """Targets the arm reaches (the FK of a configuration halfway to a random one) get
    no ``stalled`` tick, whatever else holds them back on the way (a limit, a
    singularity). Two of the UR5's four are reached by no path the servo takes: its
    joints rest at a limit 0.31 and 0.39 m off (joint_limit for good before the stall
    test read the gradient projected on the limits); there every tick from the first
    stalled one on holds still."""
    arm = armik.load(name)
    reached = 0
    for k in range(4):
        q0, q1 = arm.random_q(2 * k), arm.random_q(2 * k + 1)
        target = arm.fk(q0 + 0.5 * (q1 - q0))
        servo = arm.servo(q0=q0, dt=0.004)
        steps = [servo.step(target) for _ in range(1500)]
        statuses = [s.status.value for s in steps]
        if "stalled" in statuses:
            first = statuses.index("stalled")
            assert statuses[-1] == "stalled" and steps[-1].position_error > 0.1
            assert max(np.abs(s.dq).max() for s in steps[first + 1 :]) < 1e-9
        else:
            reached += statuses[-1] == "on_target"
    assert reached >= 1


@pytest.mark.parametrize("name", ["bounds", "weights", "position_only", "look_at", "hold"])
def test_solve_options_given_to_a_servo_are_refused_with_the_way_to_say_them(name):
    """``bounds=``, ``weights=``, ``position_only=`` ... belong to each tick's target; the
    refusal says so (one arm and several tips alike), and ``hold=`` that no joint is held."""
    arm = armik.load("ur5")
    hint = "holds no joint" if name == "hold" else "armik.Pose(T, bounds=...)"
    with pytest.raises(armik.OptionError, match=re.escape(hint)):
        arm.servo(arm.middle, **{name: None})
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])  # a shared union
    with pytest.raises(armik.OptionError, match=re.escape(hint)):
        robot.servo(robot.middle, **{name: None})


def test_a_limit_that_is_not_positive_is_refused_in_its_own_unit():
    """``velocity_limits=0`` names a velocity's unit and ``acceleration_limits=-1`` an
    acceleration's; both said "rad/s or rad/s^2"."""
    ur5 = armik.load("ur5")
    with pytest.raises(armik.OptionError, match=r"velocity_limits must be positive \(rad/s or m/s"):
        ur5.servo(ur5.middle, velocity_limits=0)
    with pytest.raises(armik.OptionError, match=r"acceleration_limits .*\(rad/s\^2 or m/s\^2"):
        ur5.servo(ur5.middle, acceleration_limits=-1)
