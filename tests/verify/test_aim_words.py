"""A success with an aim says what was measured in the aim's own terms, alike on every
route: a look-at's axis from the line to its point, an axis' from its direction. A look-at
or an axis alone has no region and no centre: it said "inside the region: the tip's axis
within its cone of 0 rad; the tip is 2.16e-09 rad from the region's centre, free
components apart" (``reasons.region``, ``reasons.measured_apart``)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import armik
from tests.conftest import arm
from tests.test_arms import dual_irb120

VERIFIED = "verified by forward kinematics: "


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """The angle (rad) between two vectors, by the atan2 of their cross and dot products."""
    return math.atan2(float(np.linalg.norm(np.cross(a, b))), float(a @ b))


def _aims(T):
    """(task, the tip's axis' angle from its sight at a placement, what the words call the
    sight) of a look-at and an axis alone, 0 wide and 0.1 wide."""
    z = T.rotation[:, 2]
    point = T.translation + 0.5 * z + np.array([0.0, 0.05, 0.0])
    for within in (0.0, 0.1):
        look = armik.LookAt(point, within=within)
        yield (
            look,
            lambda P, p=point: _angle(P.rotation[:, 2], p - P.translation),
            ("the line to the point"),
        )
        axis = armik.Axis((0, 0, 1), z + np.array([0.0, 0.05, 0.0]), within)
        yield axis, lambda P, d=axis.direction: _angle(P.rotation[:, 2], d), "its direction"


def _measured_words(reason: str) -> str:
    """A success's words past its solver's claim: what the verdict measured and the rest."""
    assert VERIFIED in reason, reason
    return reason.partition(VERIFIED)[2]


def _said(task, angle: float, sight: str) -> str:
    """What a success of ``task`` at ``angle`` says, in the aim's own terms."""
    if task.within == 0.0:
        return f"the tip's axis {angle:.3g} rad from {sight} (tol 1e-06)"
    return (
        f"the tip's axis within its cone of {task.within:g} rad around {sight}; the tip's "
        f"axis is {angle:.3g} rad from {sight}"
    )


def test_an_aim_alone_says_its_axis_in_its_own_terms_on_every_route():
    ur5 = arm("ur5")
    q = ur5.middle + 0.1
    T = ur5.fk(q)
    for task, angle_at, sight in _aims(T):
        q0 = q + 0.05
        one = ur5.solve(task, q0=q0)
        every = ur5.solve_all(task, q0=q0)
        batch = ur5.solve_batch([task, task], q0=q0, progress=False)
        path = ur5.solve_path([task, task], q0)
        held = ur5.solve(task, q0=q0, hold={"wrist_3_joint": float(q0[5])})  # the task solver
        results = [one, every[0], batch[0], path[1], held]
        assert all(r.success for r in results), [r.reason for r in results]
        for r in results:
            angle = angle_at(ur5.fk(r.q))  # by Pinocchio
            assert r.orientation_error == pytest.approx(angle, abs=1e-12), r.reason
            assert "region" not in r.reason and "centre" not in r.reason, r.reason
            untold = re.sub(r"\(tol [^)]*\)", "", r.reason)  # a tolerance's metres apart
            assert "position error" not in untold and not re.search(r"\d m\b", untold), r.reason
        for r in results[:4]:  # the compiled verdict's words, alike
            words = _measured_words(r.reason)
            assert words == _said(task, r.orientation_error, sight), r.reason
        assert batch.reason(0) == batch[0].reason == one.reason
        if task.within:  # the task solver's: the distance past its tasks' words
            assert held.reason.endswith(
                f"; the tip's axis is {held.orientation_error:.3g} rad from {sight}; joint "
                f"'wrist_3_joint' held at {q0[5]:.6g}"
            ), held.reason


def test_an_aim_beside_a_position_says_the_position_and_the_axis():
    """``[Position, Axis]`` in a cone: the position error, the axis within its cone, then
    the distances: the tip's to the target's position, its axis' from its direction."""
    ur5 = arm("ur5")
    q = ur5.middle + 0.1
    T = ur5.fk(q)
    axis = armik.Axis((0, 0, 1), T.rotation[:, 2] + np.array([0.0, 0.05, 0.0]), 0.1)
    tasks = [armik.Position(T.translation), axis]
    for r in (ur5.solve(tasks, q0=q), ur5.solve_batch([tasks], q0=q, progress=False)[0]):
        P = ur5.fk(r.q)
        angle = _angle(P.rotation[:, 2], axis.direction)
        far = float(np.linalg.norm(P.translation - T.translation))
        assert r.success and r.orientation_error == pytest.approx(angle, abs=1e-12)
        assert _measured_words(r.reason) == (
            f"inside the region: position error {r.measured[0]:.3g} m (tol 1e-06), the tip's "
            "axis within its cone of 0.1 rad around its direction; the tip is "
            f"{far:.3g} m from the target, its axis "
            f"{angle:.3g} rad from its direction"
        )


def test_a_tips_aim_on_several_tips_says_what_one_arm_says():
    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    q = cell.random_q(np.random.default_rng(3))
    T = cell.fk(q, "l_tool0")
    left = cell.chain("l_tool0")
    for task, _, _ in _aims(T):
        targets = {"l_tool0": task, "r_tool0": cell.fk(q, "r_tool0")}
        r = cell.solve(targets, q0=q + 0.05)
        alone = left.solve(task, q0=(q + 0.05)[:6])
        tip = r.extra["results"]["l_tool0"]
        assert r.success and tip.success, r.reason
        assert _measured_words(tip.reason) == _measured_words(alone.reason)
        assert "region" not in tip.reason, tip.reason


def test_a_batch_summary_of_an_aim_alone_says_the_axis_not_a_region():
    # it said "largest distance to the region's centre of the solved: 0 m, 2.2e-09 rad"
    ur5 = arm("ur5")
    q = ur5.middle + 0.1
    for task, angle_at, sight in _aims(ur5.fk(q)):
        batch = ur5.solve_batch([task, task], q0=q + 0.05, progress=False)
        assert batch.success.all()
        worst = max(angle_at(ur5.fk(row)) for row in batch.q)  # by Pinocchio
        said = batch.summary().partition("targets/s; ")[2]
        assert said.startswith(
            f"largest distance of the solved: the tip's axis {worst:.2g} rad from {sight}"
        ), batch.summary()
        assert "region" not in said and not re.search(r"\d m\b", said), batch.summary()
