"""The swept-joint solver for 7R arms (ik/swept.py): joint 7 held, joints 6 to 1 in closed
form; every answer exact for its joint 7 and verified by Pinocchio FK."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.closed_form import families
from armik.solvers.closed_form import swept_7r as swept

from ...conftest import arm, model


def test_which_arms_it_applies_to():
    assert swept.applies(model("panda")) is None  # spherical shoulder, joints 5 and 6 meet
    assert "needs 7" in swept.applies(model("ur5"))
    why = swept.applies(model("xarm7"))  # its shoulder misses by a rounding of its URDF
    assert "do not meet" in why and "m" in why
    T = arm("panda").fk(arm("panda").middle)
    assert arm("panda").solve(T).solver == "dls"  # not chosen by auto
    classes = families.classify(model("panda"))  # what armik info prints
    assert isinstance(classes["swept_7r"], swept.Swept)
    assert "joints 6 to 1" in classes["swept_7r"].description


@pytest.mark.parametrize("load_kw", [{}, {"tip_offset": (0.02, -0.01, 0.1)}])
def test_the_configuration_of_the_target_comes_back(load_kw):
    a = armik.load("panda", **load_kw)
    rng = np.random.default_rng(20)
    for _ in range(30):
        q = a.random_q(rng)
        r = a.solve(a.fk(q), q0=q, solver="swept")
        assert r.success and r.solver == "swept"
        assert np.allclose(r.q, q, atol=1e-8)
        assert r.position_error < 1e-12 and r.orientation_error < 1e-12


def test_solve_all_holds_joint_7_and_contains_the_generating_configuration():
    a = arm("panda")
    rng = np.random.default_rng(21)
    for _ in range(30):
        q = a.random_q(rng)
        results = a.solve_all(a.fk(q), q0=q, solver="swept")
        good = [r for r in results if r.success]
        assert any(np.allclose(r.q, q, atol=1e-8) for r in good)
        assert all(r.q[6] == q[6] for r in good)  # the branches of q0's joint 7
        assert all(a.within_limits(r.q) for r in good)


def test_from_the_middle_the_sweep_finds_an_answer():
    a = arm("panda")
    rng = np.random.default_rng(22)
    results = [a.solve(a.fk(a.random_q(rng)), solver="swept") for _ in range(40)]
    assert sum(r.success for r in results) >= 38
    for r in results:
        if r.success:
            assert a.within_limits(r.q) and r.position_error < 1e-9


def test_an_unreachable_target_fails_with_the_reason():
    a = arm("panda")
    r = a.solve(pin.SE3(np.eye(3), np.array([2.0, 0.0, 0.3])), solver="swept")
    assert not r.success and r.status == "unreachable"
    assert "too far" in r.reason
    assert np.all(np.isfinite(r.q))


def test_a_held_joint_7_the_pose_is_out_of_reach_from_says_it_is_held():
    # the pose is reachable (q made it); with joint 7 2.5 rad away it is not: the reason
    # says so, not that the target is beyond the arm
    a = arm("panda")
    q = a.random_q(np.random.default_rng(3))
    T = a.fk(q)
    assert any(r.success for r in a.solve_all(T, hold={"panda_joint7": float(q[6])}))
    value = float(q[6]) + 2.5 if q[6] < 0 else float(q[6]) - 2.5
    results = a.solve_all(T, hold={"panda_joint7": value})
    assert results and not any(r.success for r in results)
    for r in results:
        assert r.solver == "swept" and r.q[6] == value
        assert r.reason.startswith(f"with joint 7 held at {value:.6g} rad: "), r.reason


@pytest.mark.parametrize("q7", [-2.8973, -1.0, 0.0, 0.3, 2.8973])
def test_the_sweep_tries_every_cell_once_nearest_first(q7):
    lo, hi = -2.8973, 2.8973
    values = swept.sweep_values(q7, lo, hi).tolist()
    assert values[0] == q7
    width = (hi - lo) / swept.SWEEP
    centres = sorted(lo + (i + 0.5) * width for i in range(swept.SWEEP))
    assert sorted(values[1:]) == pytest.approx(centres, abs=1e-12)
    distances = [abs(v - q7) for v in values[1:]]
    assert all(a <= b + 1e-12 for a, b in zip(distances, distances[1:]))


def test_every_held_answer_is_labelled_by_its_branch():
    # The closed form's labels of joints 6 to 1, named after the arm's own parts: distinct
    # for the distinct answers of one held joint 7, the same for solve and solve_all.
    a = arm("panda")
    rng = np.random.default_rng(12)
    for _ in range(5):
        q = a.random_q(rng)
        T = a.fk(q)
        every = a.solve_all(T, q0=q, solver="swept")
        labels = [r.branch for r in every]
        assert all(isinstance(b, str) and b.count("/") == 2 for b in labels)
        assert len(set(labels)) == len(labels)
        one = a.solve(T, q0=q, solver="swept")
        same = [r for r in every if np.allclose(r.q, one.q, atol=1e-12)]
        assert same and same[0].branch == one.branch
