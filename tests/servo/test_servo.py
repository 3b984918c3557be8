"""The servo: every limit on the commanded sequence (finite differences), convergence, the
targets it follows, and the errors it raises."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.problem.tasks import Axis, Pose, Position
from armik.servo.limits import DEFAULT_ACCELERATION
from armik.servo.streams import JUMP, START, circle, moved, violations
from tests.conftest import arm as load

DT = 0.002


def _check(arm, servo, q0, rec) -> None:
    """Every limit holds on the commanded sequence, and its reported dq, ddq are its
    finite differences; nothing is NaN."""
    assert np.isfinite(rec.q).all() and np.isfinite(rec.dq).all() and np.isfinite(rec.ddq).all()
    over = violations(
        q0, rec.q, arm.lower, arm.upper, servo.velocity_limits, servo.acceleration_limits, DT
    )
    assert over == {"position": 0.0, "velocity": 0.0, "acceleration": 0.0}
    P = np.vstack([q0, rec.q])
    np.testing.assert_allclose(rec.dq, np.diff(P, axis=0) / DT, rtol=0, atol=1e-9)


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_circle_tracked_within_limits(name):
    arm, q0 = load(name), START[name]
    servo = arm.servo(q0, dt=DT)
    rec = servo.track(circle(arm.fk(q0), 1500, DT))
    _check(arm, servo, q0, rec)
    # after the first tenth of a second (the arm accelerating from rest), on the circle
    assert rec.position_error[50:].max() < 1e-5
    assert rec.orientation_error[50:].max() < 1e-4


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_jump_settles_within_limits(name):
    arm, q0 = load(name), START[name]
    servo = arm.servo(q0, dt=DT)
    target = moved(arm.fk(q0), JUMP)
    rec = servo.track([target] * 1000)
    _check(arm, servo, q0, rec)
    assert rec.position_error[-1] < 1e-5
    assert rec.orientation_error[-1] < 1e-5
    assert rec.status[-1] == "on_target"
    # limited on the way: it did not get there in one tick
    assert {"velocity_limit", "acceleration_limit"} & set(rec.status[:200].tolist())
    T = arm.fk(rec.q[-1])  # measured by Pinocchio
    assert np.linalg.norm(T.translation - target.translation) < 1e-5


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_out_of_reach_never_nan_and_recovers(name):
    arm, q0 = load(name), START[name]
    servo = arm.servo(q0, dt=DT)
    T0 = arm.fk(q0)
    far = moved(T0, np.array([3.0, 0.0, 0.0]))
    rec = servo.track([far] * 500 + [T0] * 1500)
    _check(arm, servo, q0, rec)
    assert "out_of_reach" in set(rec.status[:500].tolist())
    assert rec.position_error[-1] < 1e-4


@pytest.mark.parametrize("name", ["panda", "xarm7"])
def test_settled_servo_commands_exactly_zero_motion(name):
    """On a held target a servo stops: no rounding chatter, no 1e-300 motions (an exact
    row's residual) that leave joints at 0 with denormal values."""
    arm, q0 = load(name), START[name]
    servo = arm.servo(q0, dt=DT)
    held = servo.track([arm.fk(q0)] * 20)
    assert (held.q == q0).all() and (held.dq == 0.0).all() and (held.ddq == 0.0).all()
    rec = servo.track([moved(arm.fk(q0), JUMP)] * 600)
    moving = np.flatnonzero(np.abs(rec.dq).max(axis=1) > 0.0)
    still = moving[-1] + 1
    assert still < 500  # settled, then held exactly
    assert (rec.q[still:] == rec.q[-1]).all() and (rec.dq[still:] == 0.0).all()
    assert rec.position_error[-1] < 1e-12 and rec.status[-1] == "on_target"
    values = np.abs(rec.q[rec.q != 0.0])
    assert values.min() > 1e-100


def test_braking_keeps_a_joint_off_its_limit_and_says_so():
    arm = load("ur5").with_limits({"elbow_joint": (1.3, 1.45)})
    q0 = START["ur5"]
    servo = arm.servo(q0, dt=DT)
    q_goal = q0 + np.array([0.4, 0.3, 0.6, -0.5, 0.2, 0.1])  # the elbow beyond its limit
    rec = servo.track([_fk_beyond(arm, q_goal)] * 1000)
    _check(arm, servo, q0, rec)
    assert "joint_limit" in set(rec.status.tolist())
    held = [r for r, j in zip(rec.reason, rec.joint) if j == "elbow_joint"]
    assert held and "elbow_joint" in held[0]
    assert rec.q[:, 2].max() <= 1.45


def _fk_beyond(arm, q):
    """The tip pose at q ignoring the joint limits (Pinocchio's FK)."""
    model = arm.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, arm.kinematics.to_pin(q))
    return data.oMf[arm.kinematics.tip_frame_id]


def test_region_target_stops_inside_the_region():
    arm, q0 = load("ur5"), START["ur5"]
    servo = arm.servo(q0, dt=DT)
    bounds = (0.02, 0.02, 0.02, math.inf, math.inf, math.inf)
    task = Pose(moved(arm.fk(q0), JUMP), bounds=bounds)
    rec = servo.track([task] * 1000)
    _check(arm, servo, q0, rec)
    assert rec.status[-1] == "on_target"
    m = task.measure(arm.fk(rec.q[-1]), 1e-6, 1e-6)
    assert m.within and m.position < 1e-12
    # stopped on the region's edge, not at its centre: the true distance is reported
    assert 0.02 < rec.position_error[-1] <= 0.02 * math.sqrt(3) + 1e-9
    assert np.abs(rec.dq[-1]).max() < 1e-9


def test_position_and_axis_tasks():
    arm, q0 = load("panda"), START["panda"]
    servo = arm.servo(q0, dt=DT)
    p = arm.fk(q0).translation + JUMP
    rec = servo.track([[Position(p), Axis((0, 0, 1), (0, 0, -1))]] * 1500)
    _check(arm, servo, q0, rec)
    T = arm.fk(rec.q[-1])
    assert np.linalg.norm(T.translation - p) < 1e-5
    assert T.rotation[:, 2] @ np.array([0.0, 0.0, -1.0]) > math.cos(1e-4)
    only = servo.step(p)  # a position alone: no orientation to report
    assert only.orientation_error is None and only.position_error < 1e-5


def test_an_axis_within_a_cone_stops_on_its_edge_on_target():
    """The cone's edge is one row (the angle beyond it), not three of rank one: no
    singularity there, the axis on the edge and the position exact."""
    arm, q0 = load("panda"), START["panda"]
    T0 = arm.fk(q0)
    z0 = T0.rotation[:, 2]
    turn = np.cross(z0, [1.0, 0.0, 0.0])
    z = pin.exp3(0.3 * turn / np.linalg.norm(turn)) @ z0
    rec = arm.servo(q0, dt=DT).track([[Position(T0.translation), Axis((0, 0, 1), z, 0.1)]] * 800)
    _check(arm, arm.servo(q0, dt=DT), q0, rec)
    assert rec.status[-1] == "on_target" and "singularity" not in set(rec.status.tolist())
    T = arm.fk(rec.q[-1])
    assert abs(math.acos(np.clip(T.rotation[:, 2] @ z, -1.0, 1.0)) - 0.1) < 1e-9
    assert np.linalg.norm(T.translation - T0.translation) < 1e-9


def test_singular_stretched_arm_steps_without_nan():
    arm = load("ur5")
    q0 = np.array([0.0, -math.pi / 2, 0.0, -math.pi / 2, 0.0, 0.0])  # elbow straight
    servo = arm.servo(q0, dt=DT)
    T0 = arm.fk(q0)
    first = servo.step(T0)
    assert first.sigma < 1e-6  # the stretched elbow has lost a direction
    rec = servo.track([moved(T0, np.array([0.0, -0.1, -0.2]))] * 1500)
    _check(arm, servo, q0, rec)
    assert rec.position_error[-1] < rec.position_error[0]


def test_five_joint_arm_tracks_what_it_can_of_a_full_pose():
    arm = load("so101")
    q0 = np.array([0.2, 0.3, 0.2, 0.5, 0.1])
    servo = arm.servo(q0, dt=DT)
    T0 = arm.fk(q0)
    q1 = q0 + np.array([0.3, -0.2, 0.2, -0.3, 0.4])
    T1 = arm.fk(q1)  # reachable: it follows the pose exactly
    rec = servo.track([T1] * 1500)
    _check(arm, servo, q0, rec)
    assert rec.position_error[-1] < 1e-5 and rec.orientation_error[-1] < 1e-5
    # a pose off its five-dimensional set: no NaN, and as near as it gets
    R = pin.exp3(np.array([0.3, 0.2, 0.0])) @ T0.rotation
    rec = servo.track([pin.SE3(R, T0.translation)] * 1000)
    _check(arm, servo, rec.q[0] - rec.dq[0] * DT, rec)
    assert rec.orientation_error[-1] < rec.orientation_error[0]


def test_steps_and_track_agree():
    arm, q0 = load("ur5"), START["ur5"]
    targets = circle(arm.fk(q0), 50, DT)
    a, b = arm.servo(q0), arm.servo(q0)
    rec = a.track(targets)
    steps = [b.step(t) for t in targets]
    np.testing.assert_array_equal(rec.q, np.array([s.q for s in steps]))
    assert rec.status.tolist() == [s.status.value for s in steps]
    assert steps[-1].q.flags.writeable is False
    assert len(rec) == 50


def test_a_pose_is_followed_alike_however_it_is_spelled():
    """A pin.SE3 and a float 4x4 have their table written by the compiled tick; the same
    pose as (position, rotation) goes through the parser: the same commands, bit for bit.
    A 4x4 the tick does not keep as given (a rotation orthonormal to 1e-10 only) is
    handed to the parser, which snaps it; one with NaN is refused by the parser."""
    arm, q0 = load("ur5"), START["ur5"]
    targets = circle(arm.fk(q0), 200, DT) + [moved(arm.fk(q0), JUMP)] * 100
    spellings = [
        targets,
        [T.homogeneous for T in targets],
        [(T.translation, T.rotation) for T in targets],
    ]
    runs = [arm.servo(q0).track(seq) for seq in spellings]
    for rec in runs[1:]:
        np.testing.assert_array_equal(rec.q, runs[0].q)
        assert rec.status.tolist() == runs[0].status.tolist()
    servo = arm.servo(q0)
    M = arm.fk(q0).homogeneous
    M[:3, :3] *= 1.0 + 1e-10
    s = servo.step(M)
    assert s.status == "on_target" and np.isfinite(s.q).all()
    M[0, 3] = float("nan")
    with pytest.raises(armik.TargetError):
        servo.step(M)


def test_limits_given_are_kept():
    arm, q0 = load("panda"), START["panda"]
    servo = arm.servo(q0, velocity_limits=0.5, acceleration_limits={"panda_joint1": 5.0})
    assert (servo.velocity_limits == 0.5).all()
    assert servo.acceleration_limits[0] == 5.0
    assert (servo.acceleration_limits[1:] == DEFAULT_ACCELERATION).all()
    rec = servo.track([moved(arm.fk(q0), JUMP)] * 300)
    _check(arm, servo, q0, rec)
    assert np.abs(rec.dq).max() > 0.4  # the limit was reached, and held


def test_obstacle_kept_at_the_margin_within_limits():
    arm, q0 = load("panda"), START["panda"]
    T0 = arm.fk(q0)
    sphere = armik.Sphere(0.05, tuple(T0.translation + np.array([0.0, 0.16, -0.16])))
    targets = circle(T0, 3000, DT)  # two turns
    free = arm.servo(q0).track(targets)  # without the sphere the hand passes through it
    assert min(arm.min_distance(q, [sphere])[0] for q in free.q[::10]) < 0.0
    servo = arm.servo(q0, dt=DT, obstacles=[sphere], margin=0.01)
    rec = servo.track(targets)
    _check(arm, servo, q0, rec)
    assert min(arm.min_distance(q, [sphere])[0] for q in rec.q) >= 0.01 - 1e-4
    assert "obstacle" in set(rec.status.tolist())
    assert rec.position_error[-1] < 1e-5  # back on the circle past the sphere
    assert rec.status[-1] == "tracking"


@pytest.mark.parametrize(
    ("options", "named"),
    [
        ({"dt": 0.0}, "dt"),
        ({"dt": "fast"}, "dt"),
        ({"velocity_limits": -1.0}, "velocity_limits"),
        ({"velocity_limits": [1.0, 2.0]}, "velocity_limits"),
        ({"acceleration_limits": math.inf}, "acceleration_limits"),
        ({"acceleration_limits": {"nope": 1.0}}, "nope"),
        ({"gain": 2.0}, "gain"),
        ({"obstacles": [(0.5, 0, 0.3)]}, "obstacles"),
        ({"obstacles": [armik.Sphere(0.05, (0.9, 0, 0.3))], "margin": -0.1}, "margin"),
        ({"self_collision": "yes"}, "self_collision"),
        ({"collision": True}, "collision"),
    ],
)
def test_bad_options_raise_naming_them(options, named):
    arm = load("panda")
    with pytest.raises(armik.InputError, match=named):
        arm.servo(START["panda"], **options)


def test_bad_start_and_targets_raise():
    arm = load("panda")
    q = START["panda"].copy()
    q[3] = 0.5  # beyond joint 4's upper limit
    with pytest.raises(armik.OptionError, match="q0"):
        arm.servo(q)
    with pytest.raises(armik.OptionError, match="q0"):
        arm.servo(q[:3])
    servo = arm.servo(START["panda"])
    with pytest.raises(armik.TargetError):
        servo.step([1.0, float("nan"), 0.0])
    with pytest.raises(armik.TargetError, match="tip"):
        servo.step(Position((0.3, 0, 0.5), frame="panda_link4"))
    assert np.isfinite(servo.q).all()


@pytest.mark.parametrize(
    "options",
    [
        {"tol_position": float("nan")},
        {"tol_position": -1e-6},
        {"tol_orientation": "a"},
        {"dt": True},
        {"gain": None},
    ],
)
def test_a_bad_servo_setting_is_refused_by_name(options):
    """A NaN tolerance would never be on target, a bool is no period: refused by name."""
    a = armik.load("ur5")
    ((name, value),) = options.items()
    with pytest.raises(armik.OptionError, match=name) as caught:
        a.servo(a.middle, **options)
    assert caught.value.option == name


def test_numpy_numbers_are_numbers_to_a_servo():
    a = armik.load("ur5")
    s = a.servo(a.middle, dt=np.float32(0.002), gain=np.float32(0.5), tol_position=np.float64(1e-6))
    assert s.dt == pytest.approx(0.002)
