"""The viewer's servo mode: a dragged target is followed by the servo, frame by frame,
within the limits, instead of solved; off again, drags solve."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.view.follow import Follower

from ..conftest import arm
from ..test_arms import dual_irb120

BENT = np.array([0.0, 0.0, 0.0, 0.0, 0.6, 0.0])  # rad: the IRB 120's wrist bent


def _frames(follower: Follower, most: int) -> list:
    """Frames until the follower comes to rest (at most ``most``)."""
    steps = []
    for _ in range(most):
        step = follower.frame()
        if step is None:
            break
        steps.append(step)
    return steps


def test_a_follower_comes_to_rest_on_its_target_within_the_limits():
    a = arm("abb_irb120")
    q0 = a.middle + BENT  # away from the wrist's singularity, where the servo damps
    T = a.fk(q0 + 0.3)
    f = Follower(a, q0, (a.tip,), dt=0.002)
    assert f.frame() is None  # no target: nothing to do
    f.aim({a.tip: T})
    steps = _frames(f, 300)
    assert steps and f.frame() is None  # at rest: no more frames until a new aim
    last = steps[-1]
    assert last.status == "on_target"
    assert np.abs(last.dq).max() < 1e-9
    error = pin.log6(a.fk(last.q).inverse() * T).vector
    assert np.linalg.norm(error) < 1e-5
    Q = np.array([s.q for s in steps])
    assert a.within_limits(Q.min(axis=0)) and a.within_limits(Q.max(axis=0))
    # a frame is FRAME s of servo time: the speed between frames within the limits
    speed = np.abs(np.diff(Q, axis=0)) / (f.steps_a_frame * f.servo.dt)
    assert (speed <= f.servo.velocity_limits * (1 + 1e-9)).all()
    f.aim({a.tip: a.fk(q0)})  # a new target: moving again
    assert f.frame() is not None


def test_a_follower_comes_to_rest_where_it_stalls():
    """A pose the 5-joint SO-101 cannot take: the follower stops ticking once the arm
    rests as near as it gets, as it does on a target."""
    a = arm("so101")
    q0 = a.middle + 0.2
    T = a.fk(q0)
    f = Follower(a, q0, (a.tip,), dt=0.004)
    f.aim({a.tip: pin.SE3(T.rotation @ pin.rpy.rpyToMatrix(0.7, 0.0, 0.0), T.translation)})
    steps = _frames(f, 400)
    assert steps and f.frame() is None
    assert steps[-1].status == "stalled" and np.abs(steps[-1].dq).max() < 1e-9


def test_a_follower_comes_to_rest_stretched_toward_a_target_beyond_reach():
    """A target 3 m away: the arm stretches toward it and stays; the follower stops
    ticking there, as where it stalls, and moves again at the next aim."""
    a = arm("ur5")
    q0 = np.array([0.3, -1.2, 1.4, -1.5, -1.5, 0.2])
    T = a.fk(q0)
    f = Follower(a, q0, (a.tip,), dt=0.002)
    f.aim({a.tip: pin.SE3(T.rotation, T.translation + np.array([3.0, 0.0, 0.0]))})
    steps = _frames(f, 300)
    assert steps and f.frame() is None
    assert steps[-1].status == "out_of_reach" and np.abs(steps[-1].dq).max() < 1e-9
    assert np.isfinite(steps[-1].q).all()
    f.aim({a.tip: T})  # back where it started
    steps = _frames(f, 300)
    assert steps[-1].status == "on_target" and f.frame() is None


def test_several_tips_follow_each_their_target():
    a = arm("abb_irb120")
    robot = armik.load("abb_irb120", tips=[a.tip])  # an Arms of one chain
    q0 = robot.middle + BENT
    T = robot.fk(q0 + 0.2, a.tip)
    f = Follower(robot, q0, tuple(robot.tips), dt=0.002)
    f.aim({a.tip: T})
    steps = _frames(f, 300)
    assert steps[-1].status == "on_target"


def test_on_several_tips_a_tip_not_aimed_holds_its_pose():
    """The viewer aims only the tips dragged so far: the others hold where they are, and
    the servo (one target per tip) follows the one dragged."""
    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    q0 = np.concatenate([BENT + [0.0, 0.2, 0.2, 0.0, 0.2, 0.0]] * 2)
    T = cell.fk(q0 + 0.1, "l_tool0")
    f = Follower(cell, q0, tuple(cell.tips), dt=0.002)
    f.aim({"l_tool0": T})
    steps = _frames(f, 300)
    assert steps and f.frame() is None and steps[-1].status == "on_target"
    assert np.linalg.norm(pin.log6(cell.fk(steps[-1].q, "l_tool0").inverse() * T)) < 1e-5
    assert np.allclose(steps[-1].q[6:], q0[6:], rtol=0.0, atol=1e-12)  # the other arm held


@pytest.fixture
def viewer():
    pytest.importorskip("viser")
    v = armik.view(arm("abb_irb120"), port=0, open_browser=False)
    yield v
    v.close()


def _drag(viewer, T: pin.SE3) -> None:
    x, y, z, w = pin.Quaternion(T.rotation).coeffs()
    viewer._dragged(SimpleNamespace(wxyz=(w, x, y, z), position=tuple(T.translation)))


def test_in_the_servo_mode_a_drag_aims_the_servo_and_solves_nothing(viewer):
    a = viewer.arm
    follower = viewer.follow(dt=0.004)
    assert viewer.panel.follow.value is True
    assert follower.servo.dt == 0.004
    T = a.fk(a.middle + 0.2)
    _drag(viewer, T)
    assert viewer.result is None  # no solve: the servo follows
    (aimed,) = follower.targets.values()
    assert np.allclose(aimed.homogeneous, T.homogeneous)
    assert viewer.follow(False) is None
    assert viewer.panel.follow.value is False
    _drag(viewer, T)
    assert viewer.result is not None  # off again: a drag solves


def test_in_the_servo_mode_the_servo_goes_on_from_the_arm_shown(viewer):
    """``show`` (the sliders) or ``set_target`` puts the arm elsewhere: the next drag is
    followed from there, not from where the servo had left the arm (a jump back)."""
    a = viewer.arm
    viewer.follow(dt=0.004)
    for k, move in enumerate(("show", "set_target")):
        q = a.middle + BENT + np.array([0.8, 0.3, -0.3, 0.5, 0.2, 0.2]) * (1 - 2 * k)
        if move == "show":
            viewer.show(q)
        else:
            assert viewer.set_target(a.fk(q), q0=q).success
            q = viewer.q
        _drag(viewer, a.fk(q + 0.01))  # a small drag near the arm shown
        follower = viewer._follower
        assert follower is not None
        # every frame so far (the mode's thread runs them too) heads from q to q + 0.01
        step = follower.frame() or follower.last
        at = follower.servo.q if step is None else step.q
        assert np.abs(at - q).max() < 0.05, move
    # show may put the arm outside its limits (FK): the servo goes on from within them
    q = a.middle.copy()
    q[0] = a.upper[0] + 0.5
    viewer.show(q)
    assert np.array_equal(viewer.q, q)
    assert np.array_equal(viewer._follower.servo.q, np.clip(q, a.lower, a.upper))
    viewer.follow(False)  # the servo box ticked with the arm shown outside its limits
    viewer._toggled_follow(True)
    assert viewer.panel.follow.value is True and viewer._follower is not None
    assert np.array_equal(viewer._follower.servo.q, np.clip(q, a.lower, a.upper))
