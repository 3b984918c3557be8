"""A row of several tips whose verdicts measured other than the distances (a tip's region,
weights) says what they measured, the worst tip's, and then how far every tip is from its
target, what ``position_error`` reports. It said "(on the weighted axes); the tip is
0.0148 m, 1.1e-07 rad from the target" of a box with no weights, as if one tip's weighted
target (``reasons.tips_apart``)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import armik
from armik.arms_steps import held
from tests.test_arms import dual_irb120

LEFT, RIGHT = "l_tool0", "r_tool0"
BOX = (0.01, 0.01, 0.01, 0.0, 0.0, 0.0)


def _far(cell, q, targets: dict) -> float:
    """The largest distance of a tip to its target's position (a box's centre), by
    Pinocchio."""
    return max(
        float(np.linalg.norm(cell.fk(q, tip).translation - pin.SE3(T).translation))
        for tip, T in targets.items()
    )


def _words(measured, far: float) -> str:
    return (
        f"position error {measured[0]:.3g} m (tol 1e-06), orientation error "
        f"{measured[1]:.3g} rad (tol 1e-06), the worst of what the tips' verdicts measured; "
        f"every tip is at most {far:.3g} m, "
    )


def test_a_batch_of_several_tips_with_a_region_says_each_tips_distance():
    cell = armik.load(dual_irb120(), tips=[LEFT, RIGHT])
    q = cell.random_q(np.random.default_rng(3))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    shifted = pin.SE3(T_l.rotation, T_l.translation + np.array([0.004, 0.0, 0.0]))
    rel = armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))
    for targets, plain in [
        ({LEFT: armik.Pose(shifted, bounds=BOX), RIGHT: T_r}, {LEFT: shifted, RIGHT: T_r}),
        ({LEFT: armik.Pose(shifted, bounds=BOX), RIGHT: rel}, None),  # row by row
    ]:
        rows = {tip: [t, t] for tip, t in targets.items()}
        for b in (
            cell.solve_batch(rows, q0=q, progress=False),
            cell.solve_path(rows, q, max_joint_step=10.0),
        ):
            assert b.success.all(), b.reason(0)
            for i in range(2):
                said = b.reason(i)
                assert "weighted" not in said and "from the target" not in said, said
                assert b[i].reason == said
                if plain is not None:  # each tip's distance to its target, the box's centre
                    far = _far(cell, b.q[i], plain)
                    assert b.position_error[i] == max(e[i, 0] for e in b.errors.values())
                    assert abs(b.position_error[i] - far) < 1e-12
                    assert _words(b.measured[i], far) in said, said
            assert "largest distance to their targets" in b.summary(), b.summary()


def test_a_jump_of_several_tips_says_what_their_verdicts_measured():
    """A path's row solved as ``Arms.solve`` solves it and moved further than its step
    (``arms_steps.held``): 'verified:' said the distances, 0.004 m of a box its verdict
    measured 0 outside; now what the verdicts measured, then the distances."""
    cell = armik.load(dual_irb120(), tips=[LEFT, RIGHT])
    q = cell.random_q(np.random.default_rng(3))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    shifted = pin.SE3(T_l.rotation, T_l.translation + np.array([0.004, 0.0, 0.0]))
    r = cell.solve({LEFT: armik.Pose(shifted, bounds=BOX), RIGHT: T_r}, q0=q)
    assert r.success and r.measured is not None
    jump = held(cell, r, r.q + 1.0, np.full(cell.dof, 0.1), first=False)
    assert jump.status == "discontinuous"
    far = _far(cell, r.q, {LEFT: shifted, RIGHT: T_r})
    said = jump.reason.partition(", verified: ")[2]
    assert said.startswith(
        f"position error {r.measured[0]:.3g} m, orientation error {r.measured[1]:.3g} rad, "
        f"the worst of what the tips' verdicts measured; every tip is at most {far:.3g} m"
    ), jump.reason
