"""A spin that is the last joint's (``spin_joint``): every branch from one closed-form
call, its last joint nearest q0's value; the answer nearest q0 over the whole range, no
farther than a dense brute-force sweep's best; auto takes it for one answer; an arm whose
tool is off that axis goes to the sweep."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers import registry
from armik.solvers.closed_form import spin_joint
from armik.status import Status

from ...conftest import arm, model
from .test_spin import FREE, brute_force, spin_options, turned


def spun_about_z(T_target: pin.SE3, T: pin.SE3) -> float:
    """The angle of ``T`` about the target's z; asserts nothing else moved."""
    M = T_target.actInv(T)
    w = pin.log3(M.rotation)
    assert np.abs(M.translation).max() <= 1e-6 and np.abs(w[:2]).max() <= 1e-6
    return float(w[2])


@pytest.mark.parametrize("robot", ["ur5", "abb_irb120", "ur10"])
def test_every_branch_nearest_q0_over_the_whole_spin(robot):
    a = arm(robot)
    rng = np.random.default_rng(23)
    for _ in range(3):
        T = turned(a.fk(a.random_q(rng)), rng.uniform(-3, 3))
        q0 = a.random_q(rng)
        r = a.solve(T, q0=q0, bounds=FREE)
        assert r.success and r.solver == "spin_joint", r.reason
        spun_about_z(T, a.fk(r.q))
        brute = brute_force(a.kinematics, T, q0, math.pi, n=721)
        assert float(np.linalg.norm(r.q - q0)) <= min(brute.values()) + 1e-9
        every = a.solve_all(T, q0=q0, bounds=FREE)
        assert {x.branch for x in every} == set(brute)
        for x in every:
            assert x.success and x.q[-1] == pytest.approx(np.clip(q0[-1], a.lower[-1], a.upper[-1]))
            assert float(np.linalg.norm(x.q - q0)) <= brute[x.branch] + 1e-9


def test_a_bounded_spin_and_the_limits():
    a = arm("ur5")
    rng = np.random.default_rng(3)
    T, q0 = a.fk(a.random_q(rng)), a.random_q(rng)
    r = a.solve(T, q0=q0, bounds=(0.0, 0.0, 0.0, 0.0, 0.0, 0.3))
    assert r.success and r.solver == "spin_joint"
    assert abs(spun_about_z(T, a.fk(r.q))) <= 0.3 + 1e-9
    narrow = a.with_limits({"wrist_3_joint": (0.0, 0.01)})
    T = turned(narrow.fk(np.array([0.3, -1.0, 1.2, -1.0, 1.2, 0.005])), 1.5)
    r = narrow.solve(T, bounds=(0.0, 0.0, 0.0, 0.0, 0.0, 0.2))
    assert not r.success and r.status is Status.JOINT_LIMITS, r.reason
    assert narrow.solve(T, bounds=(0.0, 0.0, 0.0, 0.0, 0.0, 1.6)).success


def test_a_tool_off_the_last_axis_goes_to_the_sweep():
    a = armik.load("ur5", tip_offset=(0.05, 0.0, 0.1))
    why = registry.why_not("spin_joint", a.kinematics, None, spin_options(FREE))
    assert why and "does not turn the tool" in why
    T = a.fk(a.random_q(np.random.default_rng(2)))
    assert a.solve(T, bounds=FREE).solver == "dls"
    assert a.solve_all(T, bounds=FREE)[0].solver == "spin"
    assert spin_joint.aligned(model("ur5"), 2) and not spin_joint.aligned(model("ur5"), 0)


@pytest.mark.parametrize("bounds", [FREE, (0.0, 0.0, 0.0, 0.0, 0.0, 0.3)])
def test_a_family_without_a_prepared_runner_goes_the_general_way(bounds):
    """The iiwa's spin: its family prepares no runner, so the prepared plan steps aside
    (it built one that called None) and solve, solve_batch and a followed path answer."""
    a = arm("kuka_iiwa14")
    T = a.fk(a.random_q(21))
    r = a.solve(T, bounds=bounds)
    assert r.success, r.reason
    assert abs(spun_about_z(T, a.fk(r.q))) <= bounds[5] + 1e-9
    batch = a.solve_batch(np.array([T.homogeneous] * 2), bounds=bounds, workers=1)
    assert batch.success.all()
    path = a.solve_path([T, T], r.q, bounds=bounds)
    assert path.success.all()


NEAR = 1e-4  # rad: the closed form at the stretched elbow, itself singular, to about 3e-5


def _reason_angle(reason: str) -> float:
    return float(reason.split("turned by the last joint (")[1].split(" rad")[0])


@pytest.mark.parametrize("robot", ["ur5", "abb_irb120"])
def test_a_whole_turn_from_a_singular_start_stays_on_its_branch(robot):
    """From the stretched wrist (joints 4 and 6 on one axis), a pose the tip already holds
    but turned about its z: the answer is q0 itself, on every route, where the closed form
    at the target's own spin gave another branch (wrist_1 moved by pi on the UR5)."""
    a = arm(robot)
    q0 = a.middle.copy()
    T = turned(a.fk(q0), 2.5)  # the same poses over a whole turn: q0 reaches one
    for r in (
        a.solve(T, q0=q0, bounds=FREE),
        a.solve((T.translation, T.rotation), q0=q0, bounds=FREE),  # the general path
        a.solve_all(T, q0=q0, bounds=FREE)[0],
    ):
        assert r.success and r.solver == "spin_joint", r.reason
        assert np.abs(r.q - q0).max() <= NEAR  # not pi away
    batch = a.solve_batch(np.array([T.homogeneous]), q0=q0, bounds=FREE)
    assert batch.success[0] and np.abs(batch.q[0] - q0).max() <= NEAR


@pytest.mark.parametrize("robot", ["ur5", "abb_irb120"])
def test_the_reason_s_spin_is_the_tips_turn_from_the_target(robot):
    """The reason's angle is the tip's turn about the target's z, as Pinocchio's FK gives it,
    whichever spin the closed form solved at."""
    a = arm(robot)
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(4):
        T = turned(a.fk(a.random_q(rng)), rng.uniform(-3, 3))
        q0 = a.random_q(rng)
        for r in [a.solve(T, q0=q0, bounds=FREE), *a.solve_all(T, q0=q0, bounds=FREE)]:
            if not r.success:
                continue
            turn = abs(spun_about_z(T, a.fk(r.q)))
            assert abs(_reason_angle(r.reason) - turn) <= 1e-5, r.reason
            checked += 1
    assert checked >= 4  # answers were compared, not all skipped
