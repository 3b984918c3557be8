"""6R arms with a spherical shoulder (solvers/closed_form/spherical_shoulder.py): the Panda
and the KUKA iiwa with joint 7 locked are solved in closed form, with every solution that
``hold=`` on joint 7 gives (the swept closed form at that value), each verified by
Pinocchio FK."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.closed_form import families
from armik.solvers.closed_form import spherical_shoulder as shoulder
from armik.solvers.closed_form.sixr import Chain6R, forward

from .random_arms import wrapped_distance

JOINT_7 = {"panda": "panda_joint7", "kuka_iiwa14": "iiwa_joint_7"}
TARGETS = 40


def _reached(a: armik.Arm, q: np.ndarray, T) -> tuple[float, float]:
    """Pinocchio's distance of fk(q) to T: (m, rad)."""
    M = pin.SE3(a.fk(q).homogeneous)
    W = pin.SE3(T.homogeneous)
    return float(np.linalg.norm(M.translation - W.translation)), float(
        np.linalg.norm(pin.log3(M.rotation.T @ W.rotation))
    )


@pytest.mark.parametrize("robot", sorted(JOINT_7))
def test_a_locked_joint_7_is_a_spherical_shoulder(robot):
    a = armik.load(robot, locked={JOINT_7[robot]: 0.3})
    geo = shoulder.classify(a.kinematics)
    assert isinstance(geo, Chain6R) and "spherical shoulder" in geo.description
    assert isinstance(families.classify(a.kinematics)["spherical_shoulder"], Chain6R)
    assert "spherical_shoulder solves" in families.classify(a.kinematics)["elimination_6r"]
    T = a.fk(a.middle)
    assert a.solve(T).solver == "spherical_shoulder"  # exact and complete: solve's too
    assert {r.solver for r in a.solve_all(T)} == {"spherical_shoulder"}
    # the chain kept is the arm's own, and read from the tip it is its own inverse
    rng = np.random.default_rng(3)
    back = shoulder.reversed_chain(geo)
    again = shoulder.reversed_chain(back)
    for _ in range(5):
        q = a.random_q(rng)
        R, p = forward(geo.h, geo.p, geo.R_tip0, q)
        H = a.fk(q).homogeneous
        assert np.allclose(np.reshape(R, (3, 3)), H[:3, :3], atol=1e-12)
        assert np.allclose(p, H[:3, 3], atol=1e-12)
        Rb, pb = forward(back.h, back.p, back.R_tip0, q[::-1].copy())
        Hb = np.eye(4)
        Hb[:3, :3], Hb[:3, 3] = np.reshape(Rb, (3, 3)), pb
        assert np.allclose(Hb, np.linalg.inv(H), atol=1e-12)
    assert np.allclose(again.h, geo.h) and np.allclose(again.p, geo.p)


def test_arms_without_a_spherical_shoulder_say_why():
    assert "axes 2 and 3 are parallel" in shoulder.classify(armik.load("ur5").kinematics)
    assert "needs 6" in shoulder.classify(armik.load("panda").kinematics)
    a = armik.load("panda", locked={"panda_joint1": 0.2})  # joints 2, 3, 4: an elbow between
    assert "do not meet" in shoulder.classify(a.kinematics)


@pytest.mark.parametrize("robot", sorted(JOINT_7))
def test_every_solution_of_hold_and_no_other(robot):
    """On random targets and locked values: the locked arm's solve_all has the solutions
    of solve_all(T, hold={joint 7: value}), no more, each within 1e-9 rad of one of them
    and reaching the target within 1e-9 by Pinocchio; solve's answer is one of them."""
    full = armik.load(robot)
    rng = np.random.default_rng(11)
    name = JOINT_7[robot]
    found = 0
    for _ in range(TARGETS):
        value = float(rng.uniform(full.lower[6], full.upper[6]))
        locked = full.with_locked({name: value})
        q = full.random_q(rng)
        q[6] = value
        T = full.fk(q)
        held = [np.delete(r.q, 6) for r in full.solve_all(T, hold={name: value}) if r.success]
        got = [r for r in locked.solve_all(T, q0=q[:6]) if r.success]
        assert len(got) == len(held) >= 1
        for r in got:
            assert r.solver == "spherical_shoulder"
            assert min(wrapped_distance(r.q, h) for h in held) < 1e-9
            position, orientation = _reached(locked, r.q, T)
            assert position < 1e-9 and orientation < 1e-9
        assert any(wrapped_distance(r.q, q[:6]) < 1e-8 for r in got)  # the target's own
        one = locked.solve(T, q0=q[:6])
        assert one.success and one.solver == "spherical_shoulder"
        assert wrapped_distance(one.q, q[:6]) < 1e-8  # nearest q0: the target's own
        found += len(got)
    assert found > TARGETS


def test_batch_and_unreachable():
    a = armik.load("panda", locked={"panda_joint7": -0.4})
    rng = np.random.default_rng(5)
    Q = np.array([a.random_q(rng) for _ in range(6)])
    poses = np.array([a.fk(q).homogeneous for q in Q])
    b = a.solve_batch(poses, q0=Q, workers=1, progress=False)
    assert b.success.all()
    assert np.abs(b.q - Q).max() < 1e-8
    far = a.fk(a.middle).homogeneous.copy()
    far[:3, 3] = (3.0, 0.0, 0.5)
    r = a.solve(far)
    assert not r.success and r.status == "unreachable"


@pytest.mark.parametrize("value", [3e-4, 1e-3, 6e-3, 0.012, 0.03])
def test_nearly_parallel_axes_6_and_5_keep_every_digit(value):
    """The Panda with joint 6 held near 0: read from the tip, joints 7 and 5 meet metres
    away and the closed form lost digits with the cube of that distance (rows 3e-7 m off at
    1e-3 rad, the target's own configuration missed by 2e-6 rad). Every success reaches
    the target within 1e-9 by Pinocchio and the target's configuration is among them."""
    full = armik.load("panda")
    rng = np.random.default_rng(7)
    for _ in range(8):
        q = full.random_q(rng)
        q[5] = value
        T = full.fk(q)
        got = [r for r in full.solve_all(T, hold={"panda_joint6": value}) if r.success]
        assert got
        for r in got:
            position, orientation = _reached(full, r.q, T)
            assert position < 1e-9 and orientation < 1e-9
        assert min(wrapped_distance(r.q, q) for r in got) < 1e-9


def test_axes_6_and_5_meeting_far_away_are_refused_with_the_distance():
    near = armik.load("panda", locked={"panda_joint6": 1e-3})
    why = shoulder.classify(near.kinematics)
    assert isinstance(why, str) and "axes 6 and 5 meet 88.7 m from the shoulder" in why
    assert not isinstance(families.classify(near.kinematics)["elimination_6r"], str)
    apart = armik.load("panda", locked={"panda_joint6": 0.3})
    assert isinstance(shoulder.classify(apart.kinematics), Chain6R)
