"""A tick's errors are what ``solve`` reports at the same joint values: the true distances
to the target, its position and its rotation, whatever the bounds and weights
(docs/tolerances.md): a spin a region frees turned 1 rad reports 1 rad, a position it
frees the tip's distance from it; on one tip and on several, apart and over shared
joints. Checked against Pinocchio's FK."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.servo.streams import START

from ..test_arms import dual_irb120

INF = math.inf
# (name, bounds, weights, the target's offset from the tip: rotation vector, translation,
# in the target frame), each offset in what the bounds free or inside the box: the tip at
# q lies in every region, so that neither the servo nor the descent moves it
CASES = [
    ("spin", (0, 0, 0, 0, 0, INF), None, (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)),
    ("free x", (INF, 0, 0, 0, 0, 0), None, (0.0, 0.0, 0.0), (0.1, 0.0, 0.0)),
    ("free roll", (0, 0, 0, INF, 0, 0), None, (1.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
    (
        "rotation free",
        (0.02, 0.02, 0.02, INF, INF, INF),
        None,
        (0.3, -0.5, 1.0),
        (0.01, -0.015, 0.012),
    ),
    ("position free", (INF, INF, INF, 0, 0, 0), None, (0.0, 0.0, 0.0), (0.1, 0.05, -0.05)),
    ("box", (0.01, 0.02, 0.03, 0.05, 0.05, 0.05), None, (0.02, -0.03, 0.04), (0.005, -0.01, 0.02)),
    ("rotation weighted 0", None, (1, 1, 1, 0, 0, 0), (0.3, -0.5, 1.0), (0.0, 0.0, 0.0)),
]
IDS = [c[0] for c in CASES]


def _target(T: pin.SE3, case) -> armik.Pose:
    _, bounds, weights, rotation, translation = case
    offset = pin.SE3(pin.exp3(np.array(rotation)), np.array(translation))
    return armik.Pose(T * offset, bounds=bounds, weights=weights)


def _truth(T: pin.SE3, target: armik.Pose) -> tuple[float, float]:
    """Pinocchio's distances of T to the target: |p - p_t| and |log3(R_t^T R)|, whatever
    the target's bounds and weights."""
    Tt = target.T
    return (
        float(np.linalg.norm(T.translation - Tt.translation)),
        float(np.linalg.norm(pin.log3(Tt.rotation.T @ T.rotation))),
    )


def _close(a: float | None, b: float | None) -> bool:
    return a is not None and b is not None and abs(a - b) <= 1e-12


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_a_tick_reports_what_solve_reports_at_the_same_q(case):
    ur5 = armik.load("ur5")
    q = START["ur5"]
    target = _target(ur5.fk(q), case)
    step = ur5.servo(q).step(target)
    solved = ur5.solve(target, q0=q, solver="dls")
    assert step.status == "on_target" and solved.success
    assert np.array_equal(step.q, q) and np.array_equal(solved.q, q)  # both where they began
    pos, ori = _truth(pin.SE3(ur5.fk(q)), target)
    assert _close(step.position_error, pos) and _close(solved.position_error, pos)
    assert _close(step.orientation_error, ori) and _close(solved.orientation_error, ori)
    record = ur5.servo(q).track([target] * 3)
    assert np.allclose(record.position_error, pos, rtol=0, atol=1e-12)
    assert np.allclose(record.orientation_error, ori, rtol=0, atol=1e-12)


def test_a_box_of_a_position_counts_every_axis_and_has_no_orientation():
    """The box frees z: the tip 0.3 m above the point is inside it, 0.3 m from the point."""
    ur5 = armik.load("ur5")
    q = START["ur5"]
    p = ur5.fk(q).translation
    target = armik.Position(p - (0.005, 0.0, 0.3), bounds=(0.01, 0.01, INF))
    step = ur5.servo(q).step(target)
    solved = ur5.solve(target, q0=q)  # a task list: the task solver
    assert step.status == "on_target" and np.array_equal(solved.q, q)
    truth = float(np.linalg.norm(ur5.fk(q).translation - target.p))
    assert truth > 0.3
    assert _close(step.position_error, truth) and _close(solved.position_error, truth)
    assert step.orientation_error is None and solved.orientation_error is None
    assert np.isnan(ur5.servo(q).track([target]).orientation_error).all()


def _worse(a: float | None, b: float | None) -> float | None:
    return b if a is None else a if b is None else max(a, b)


@pytest.mark.parametrize("robot", ["apart", "shared"])
@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_several_tips_report_what_arms_solve_reports(robot, case):
    """Each tip's errors as ``Arms.solve``'s ``errors`` say them, the step's the largest:
    two IRB 120s (a servo a chain) and the Panda's elbow and hand (one over the union)."""
    if robot == "apart":
        arms = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
        q = np.concatenate([START["abb_irb120"], START["abb_irb120"]])
    else:
        arms = armik.load("panda", tips=["panda_link4", "panda_hand"])
        q = START["panda"]
    first, hand = arms.tips
    target = _target(arms.fk(q, hand), case)
    targets = {first: arms.fk(q, first), hand: target}
    step = arms.servo(q).step(targets)
    solved = arms.solve(targets, q0=q)
    assert step.status == "on_target" and solved.success
    assert np.array_equal(step.q, q) and np.abs(solved.q - q).max() < 1e-9
    pos, ori = _truth(arms.fk(q, hand), target)
    assert _close(solved.errors[hand][0], pos) and _close(solved.errors[hand][1], ori)
    if step.tips is not None:  # each chain's own servo
        assert _close(step.tips[hand].position_error, pos)
        assert _close(step.tips[hand].orientation_error, ori)
    largest = [_worse(*[e[k] for e in solved.errors.values()]) for k in range(2)]
    assert _close(step.position_error, largest[0]) and _close(step.orientation_error, largest[1])


def test_off_target_and_near_a_half_turn_the_distances_are_pinocchio_s():
    """Partly freed rotations, the arm moving, some targets a hair short of a half turn off
    (where the angle comes from the trace and the skew part)."""
    ur5 = armik.load("ur5")
    q = START["ur5"]
    rng = np.random.default_rng(7)
    patterns = [(0, 0, 0, 0, 0, INF), (0, 0, 0, INF, 0, 0), (0, 0, 0, 0, INF, INF)]
    for k in range(24):
        axis = rng.normal(size=3)
        angle = math.pi - 10.0 ** rng.uniform(-9, -1) if k % 2 else rng.uniform(0.1, 3.0)
        offset = pin.SE3(pin.exp3(axis / np.linalg.norm(axis) * angle), rng.normal(size=3) * 0.05)
        target = armik.Pose(ur5.fk(q) * offset, bounds=patterns[k % 3])
        step = ur5.servo(q).step(target)
        assert step.status != "on_target" and not np.array_equal(step.q, q)
        pos, ori = _truth(ur5.fk(step.q), target)
        assert abs(step.position_error - pos) < 1e-9 and abs(step.orientation_error - ori) < 1e-9
