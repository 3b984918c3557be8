"""The closed form over a spin: the nearest admissible answer over the whole swept range,
equal to a dense brute-force sweep's best; every branch's best for solve_all; auto takes it
for every solution only."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.model.arm_model import ArmModel
from armik.options import Options
from armik.solvers import registry
from armik.solvers.closed_form import spin
from armik.status import Status
from armik.targets.pose import parse_target

from ...conftest import arm, model
from .random_arms import load_arm

FREE = (0.0, 0.0, 0.0, 0.0, 0.0, math.inf)


def turned(T: pin.SE3, theta: float) -> pin.SE3:
    return T * pin.SE3(pin.exp3(np.array([0.0, 0.0, theta])), np.zeros(3))


def brute_force(a: ArmModel, T, q0, half: float, n: int = 3601) -> dict:
    """Each branch's smallest distance to q0 over n spins in [-half, half] (on the arm
    model ``a``)."""
    family = spin.family(a, parse_target(T, a))
    best: dict = {}
    for t in np.linspace(-half, half, n):
        got = family.run(a, parse_target(turned(T, t), a), q0, None, True)
        for i in range(len(got)):
            if got.status(i) is Status.CONVERGED and a.within_limits(got.q[i]):
                d = float(np.linalg.norm(got.q[i] - q0))
                best[got.label(i)] = min(best.get(got.label(i), math.inf), d)
    return best


def offset(robot: str):
    """The arm with its tool off the last joint's axis: the spin is not that joint's."""
    return armik.load(robot, tip_offset=(0.05, 0.0, 0.1))


@pytest.mark.parametrize("robot", ["ur5", "abb_irb120"])
def test_the_sweep_finds_the_nearest_answer_over_the_range(robot):
    a = offset(robot)
    rng = np.random.default_rng(17)
    for _ in range(3):
        T = turned(a.fk(a.random_q(rng)), rng.uniform(-3, 3))
        q0 = a.random_q(rng)
        r = a.solve(T, q0=q0, bounds=FREE, solver="spin")
        assert r.success and r.solver == "spin", r.reason
        brute = brute_force(a.kinematics, T, q0, math.pi)
        d = float(np.linalg.norm(r.q - q0))
        assert d <= min(brute.values()) + 1e-9
        assert d >= min(brute.values()) - 2e-3  # the grid of 3601 is 1.7 mrad apart
        every = a.solve_all(T, q0=q0, bounds=FREE)
        assert every[0].solver == "spin" and all(x.success for x in every)
        assert {x.branch for x in every} == set(brute)
        for x in every:
            assert float(np.linalg.norm(x.q - q0)) <= brute[x.branch] + 1e-9


def test_a_bounded_spin_stays_within_its_bound():
    a = offset("ur5")
    rng = np.random.default_rng(3)
    T, q0 = a.fk(a.random_q(rng)), a.random_q(rng)
    bounds = (0.0, 0.0, 0.0, 0.0, 0.0, 0.3)
    r = a.solve(T, q0=q0, bounds=bounds, solver="spin")
    assert r.success
    spin_angle = pin.log3(T.rotation.T @ a.fk(r.q).rotation)
    assert abs(spin_angle[2]) <= 0.3 + 1e-9 and np.abs(spin_angle[:2]).max() < 1e-9
    brute = brute_force(a.kinematics, T, q0, 0.3, n=601)
    assert float(np.linalg.norm(r.q - q0)) <= min(brute.values()) + 1e-9


def test_auto_takes_the_sweep_for_every_solution_only():
    a = offset("ur5")
    T = a.fk(a.random_q(np.random.default_rng(5)))
    assert a.solve(T, bounds=FREE).solver == "dls"
    assert a.solve_all(T, bounds=FREE)[0].solver == "spin"
    assert registry.get("spin").complete is False


def test_the_sweep_says_when_it_does_not_apply():
    a = model("ur5")
    box = (0.005, 0.005, 0.005, 0.05, 0.05, 0.05)
    why = registry.why_not("spin", a, None, spin_options(box))
    assert why and "free one rotation component" in why
    assert "no complete closed form" in registry.why_not(
        "spin", model("panda"), None, spin_options(FREE)
    )


def test_a_spin_window_the_limits_exclude_is_not_converged():
    a = arm("ur5").with_limits({"wrist_3_joint": (0.0, 0.01)})
    T = a.fk(np.array([0.3, -1.0, 1.2, -1.0, 1.2, 0.005]))
    T = turned(T, 1.5)  # the spin that puts wrist 3 back is 1.5 rad away; the bound is 0.2
    r = a.solve(T, bounds=(0.0, 0.0, 0.0, 0.0, 0.0, 0.2), solver="spin")
    assert not r.success and r.status is Status.NOT_CONVERGED and "spins about" in r.reason


def spin_options(bounds) -> Options:
    return Options.from_kwargs({"bounds": bounds})


@pytest.mark.parametrize("kind, seed", [("spherical", 0), ("three_parallel_free", 2)])
def test_every_solution_of_a_label_given_twice_is_kept(kind, seed):
    # the 16-solution families name two answers by one label: each is its own branch
    a = load_arm(kind, np.random.default_rng(seed))
    rng = np.random.default_rng(7)
    twice = 0
    for _ in range(3):
        T = a.fk(a.random_q(rng))
        plain = [r for r in a.solve_all(T) if r.success]
        every = a.solve_all(T, bounds=FREE)
        assert every[0].solver == "spin" and all(r.success for r in every)
        twice += any("#" in r.branch for r in plain)
        assert len(every) >= len(plain)  # the target's own spin is in the range
        for r in every:
            err = pin.log3(T.rotation.T @ a.fk(r.q).rotation)
            assert np.abs(err[:2]).max() < 1e-6
    assert twice  # the case: a label the closed form gives twice
