"""Preferences (``prefer=``): each score against a hand computation, the closed forms'
choice equal to a brute-force scan of every branch and 2 pi variant, bad costs named."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import armik
from armik.problem.scores import Limits, Manipulability, Nearest, limit_margin, manipulability

from .. import conftest


def test_each_score_by_hand():
    J = np.array([[1.0, 2.0], [0.0, 3.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [1.0, 1.0]])
    # J^T J = [[2, 3], [3, 14]]: det 19 (fewer joints than rows: J^T J)
    assert manipulability(J) == pytest.approx(math.sqrt(19.0))
    arm = conftest.model("planar_2link")
    lo, hi = arm.lower, arm.upper
    q = lo + np.array([0.1, 0.5]) * (hi - lo)
    assert limit_margin(arm, q) == pytest.approx(0.1)
    assert Limits()(arm, q, q) == pytest.approx(-0.1)
    q0 = q + np.array([0.3, -0.4])
    assert Nearest()(arm, q, q0) == pytest.approx(0.5)
    posture = armik.Posture([0.0, 1.0], weights=[2.0, 3.0])
    assert posture(arm, np.array([1.0, 3.0]), q0) == pytest.approx(2.0 * 1.0 + 3.0 * 4.0)
    assert Manipulability()(arm, q, q0) == pytest.approx(-manipulability(arm.jacobian(q)))


@pytest.mark.parametrize("prefer", ["manipulability", "limits"])
def test_a_reason_names_the_measure_not_its_negated_cost(prefer):
    """A score ranks by a cost (lower is better), so manipulability and the limit margin are
    negated; the reason names the measure itself, positive, as the result's q has it."""
    arm = conftest.arm("ur5")
    T = arm.fk(arm.random_q(7))
    r = arm.solve(T, prefer=prefer)
    measure = manipulability(arm.jacobian(r.q)) if prefer == "manipulability" else None
    measure = limit_margin(arm, r.q) if measure is None else measure
    assert r.success and measure > 0.0 and r.score == pytest.approx(-measure, rel=1e-12)
    said = "manipulability" if prefer == "manipulability" else "joint-limit margin"
    assert f"{said} {measure:.6g}" in r.reason and f"{-measure:.6g}" not in r.reason


def _every_variant(arm, q):
    turns = []
    for qi, lo, hi in zip(q, arm.lower, arm.upper):
        ks = range(math.ceil((lo - qi) / (2 * math.pi)), math.floor((hi - qi) / (2 * math.pi)) + 1)
        turns.append([qi + 2 * math.pi * k for k in ks] or [qi])
    return [np.array(c) for c in itertools.product(*turns)]


@pytest.mark.parametrize("robot", ["ur5", "abb_irb120"])
@pytest.mark.parametrize("prefer", ["manipulability", "limits", "nearest", "cost"])
def test_the_closed_form_choice_is_the_best_of_every_branch(robot, prefer):
    """The chosen answer's score equals the best over every branch of solve_all and every
    2 pi variant within the limits (brute force)."""
    arm = conftest.arm(robot)
    rng = np.random.default_rng(34)
    weights = rng.uniform(0.5, 2.0, arm.dof)

    def cost(q):
        return float(weights @ np.cos(q) + 0.1 * q.sum())

    score = {
        "manipulability": Manipulability(),
        "limits": Limits(),
        "nearest": Nearest(),
        "cost": armik.problem.scores.Cost(cost),
    }[prefer]
    for _ in range(5):
        T = arm.fk(arm.random_q(rng))
        q0 = arm.random_q(rng)
        r = arm.solve(T, q0=q0, prefer=cost if prefer == "cost" else prefer)
        assert r.success
        branches = [b.q for b in arm.solve_all(T, q0=q0) if b.success]
        best = min(
            score(arm.kinematics, v, q0)
            for b in branches
            for v in _every_variant(arm, b)
            if arm.within_limits(v)
        )
        assert r.extra["score"] == pytest.approx(best, abs=1e-9)
        assert score(arm.kinematics, r.q, q0) == pytest.approx(best, abs=1e-9)
        assert np.allclose(arm.fk(r.q).homogeneous, T.homogeneous, atol=1e-6)


def test_solve_all_is_ordered_by_the_score():
    arm = conftest.arm("ur5")
    T = arm.fk(arm.random_q(2))
    ranked = arm.solve_all(T, prefer="manipulability")
    scores = [r.extra["score"] for r in ranked if r.success]
    assert len(scores) >= 2 and scores == sorted(scores)


def test_a_bad_cost_is_named():
    arm = conftest.arm("ur5")
    T = arm.fk(arm.random_q(3))

    def broken(q):
        raise RuntimeError("no model")

    with pytest.raises(armik.InputError, match="broken raised RuntimeError"):
        arm.solve(T, prefer=broken)
    with pytest.raises(armik.InputError, match="returned nan"):
        arm.solve(T, prefer=lambda q: math.nan)
    with pytest.raises(armik.InputError, match="prefer must be"):
        arm.solve(T, prefer="best")
    with pytest.raises(armik.InputError, match="one per joint"):
        arm.solve(T, prefer=armik.Posture([0.0, 0.0]))


def test_prefer_with_bounds_and_collisions():
    """A free spin and an obstacle with a preference: every answer still verified."""
    arm = conftest.arm("ur5")
    T = arm.fk(arm.random_q(4))
    spin = (0.0, 0.0, 0.0, 0.0, 0.0, math.inf)
    r = arm.solve(T, bounds=spin, prefer="limits")
    assert r.success and "limits" in r.reason
    floor = armik.HalfSpace((0.0, 0.0, 1.0), -0.5)
    c = arm.solve(T, obstacles=[floor], prefer="manipulability")
    assert c.success and "manipulability" in c.reason


def test_the_panda_sweep_finds_the_self_motion_optimum():
    """prefer='manipulability' on the Panda searches joint 7 (grid, then golden section):
    its answer is within 1 % of a dense scan of joint 7 over its range."""
    from armik.solvers.closed_form import swept_7r
    from armik.targets.pose import parse_target

    arm = conftest.arm("panda")
    rng = np.random.default_rng(7)
    for _ in range(3):
        T = arm.fk(arm.random_q(rng))
        r = arm.solve(T, prefer="manipulability", timeout=0.005)
        assert r.success and r.solver == "swept"
        target = parse_target(T, arm.kinematics)
        lo, hi = swept_7r.sweep_range(arm.kinematics, float(arm.middle[6]))
        found = [
            swept_7r.at_value(arm.kinematics, target, arm.middle, float(theta))
            for theta in np.linspace(lo, hi, 721)
        ]
        dense = max(
            manipulability(arm.jacobian(got.q[i]))
            for got in found
            for i in range(len(got))
            if got.claimed(i) and arm.within_limits(got.q[i])
        )
        assert manipulability(arm.jacobian(r.q)) >= 0.99 * dense


def test_a_numeric_answer_moves_along_the_self_motion():
    """On the xArm7 (no closed form): the descent in the null space raises manipulability
    and keeps the pose."""
    import pinocchio as pin

    from armik.solve.nullspace import descend

    arm = conftest.arm("xarm7")
    q = arm.random_q(11)
    T = arm.fk(q)
    moved = descend(arm.kinematics, q, T, Manipulability(), arm.middle, budget=1.0)
    assert manipulability(arm.jacobian(moved)) > manipulability(arm.jacobian(q))
    assert np.abs(pin.log6(arm.fk(moved).inverse() * T).vector).max() <= 1e-9
    assert arm.within_limits(moved)
    r = arm.solve(T, prefer="manipulability", iteration_budget=2000)
    gathered = [a.q for a in arm.solve_all(T, iteration_budget=2000) if a.success]
    best_gathered = max(manipulability(arm.jacobian(q)) for q in gathered)
    assert r.success and manipulability(arm.jacobian(r.q)) >= best_gathered - 1e-12


def test_a_batch_takes_the_preferred_answer_of_each_target():
    arm = conftest.arm("ur5")
    rng = np.random.default_rng(12)
    poses = np.array([arm.fk(arm.random_q(rng)).homogeneous for _ in range(6)])
    b = arm.solve_batch(poses, prefer="limits", progress=False)
    assert b.success.all()
    for H, q in zip(poses, b.q):
        assert np.array_equal(q, arm.solve(H, prefer="limits").q)
    # A path takes the preference only as a tie-break after continuity: no step beyond
    # the path's limit is hidden by it, these far-apart targets are flagged as jumps.
    path = arm.solve_path(poses, arm.middle, prefer="limits", max_joint_step=0.3)
    steps = np.abs(np.diff(np.vstack([arm.middle, path.q]), axis=0)).max(axis=1)
    assert all(s <= 0.3 + 1e-9 or st == "discontinuous" for s, st in zip(steps, path.status))


@pytest.mark.parametrize("robot", ["xarm7", "ur5"])
def test_each_joint_turns_to_the_best_variant(robot):
    """The per-joint scores' turns (chosen at once, nearest each score's centre) score as
    the best of every combination of turns within the limits (brute force)."""
    from armik.solve.prefer import best_variant

    arm = conftest.model(robot)
    rng = np.random.default_rng(35)
    scores = [
        Nearest(),
        Limits(),
        armik.Posture(arm.random_q(rng), rng.uniform(0.0, 2.0, arm.dof)),
    ]
    for _ in range(40):
        q, q0 = arm.random_q(rng), arm.random_q(rng)
        for score in scores:
            chosen = best_variant(arm, q, score, q0)
            assert arm.within_limits(chosen)
            best = min(score(arm, v, q0) for v in _every_variant(arm, q) if arm.within_limits(v))
            assert score(arm, chosen, q0) == pytest.approx(best, abs=1e-12)
