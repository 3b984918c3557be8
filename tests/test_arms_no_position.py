"""Tips whose targets hold no position (``armik.Axis`` alone) on several tips: their words
say no metres, as one arm's say none for an ``Axis``; the joined rows of a batch or a path
held NaN for their position and said "nan m", and their verdicts' 0 m. A tip beyond reach
beside such a tip, over shared joints, is refused by name: the largest error over the
tips compared None with a float and raised ``TypeError``."""

from __future__ import annotations

import re

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.status import Status
from tests.test_arms import dual_irb120, talos

METRES = re.compile(r"(\d|nan) m\b")  # a distance or a verdict's measure in metres


def _aimed(robot, q) -> dict:
    """Each tip an ``armik.Axis`` its placement at ``q`` misses by about 0.29 rad, within a
    cone of 0.2 rad: a region, measured apart from the distances."""
    out = {}
    for tip in robot.tips:
        direction = robot.fk(q, tip).rotation @ np.array([0.0, 0.3, 1.0])
        out[tip] = armik.Axis((0.0, 0.0, 1.0), direction, within=0.2)
    return out


@pytest.mark.parametrize(
    "robot",
    [lambda: armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"]), talos],
    ids=["apart", "shared"],
)
def test_tips_with_no_position_say_no_metres_in_a_batch_or_a_path(robot):
    robot = robot()
    q = robot.random_q(np.random.default_rng(3))
    aims = _aimed(robot, q)
    rows = {tip: [axis, axis] for tip, axis in aims.items()}
    batch = robot.solve_batch(rows, q0=q, workers=1)
    path = robot.solve_path(rows, q)
    for out in (batch, path):
        assert out.success.all(), out.summary()
        assert np.isnan(out.position_error).all()
        for tip in robot.tips:
            assert np.isnan(out.errors[tip][:, 0]).all()
        words = [out.summary(), out.reason(0), out.reason(1), out[0].reason]
        for said in words:
            assert not METRES.search(said), said
        # the distances are still said: the largest tip axis' angle, in radians
        largest = float(np.nanmax(out.orientation_error))
        assert f"every tip is at most {largest:.3g} rad from its target" in out.reason(0)
        assert f"of the solved: {largest:.2g} rad" in out.summary()


def test_a_tip_beyond_reach_beside_an_axis_over_shared_joints_is_refused_by_name():
    robot = talos()
    left, right = robot.tips
    q = robot.random_q(np.random.default_rng(3))
    T = robot.fk(q, left)
    far = pin.SE3(T.rotation, T.translation + np.array([3.0, 0.0, 0.0]))
    axis = armik.Axis((0.0, 0.0, 1.0), robot.fk(q, right).rotation @ np.array([0.0, 0.0, 1.0]))
    for target in (far, far.translation):
        r = robot.solve({left: target, right: axis}, q0=q)
        assert not r.success and r.status is Status.UNREACHABLE
        assert r.reason.startswith(f"tip {left!r}: target is "), r.reason
        X = robot.fk(r.q, left)
        assert r.errors[right][0] is None
        assert r.position_error == pytest.approx(
            np.linalg.norm(X.translation - T.translation - [3.0, 0.0, 0.0]), abs=1e-12
        )
