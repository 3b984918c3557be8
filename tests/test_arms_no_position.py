"""Tips whose targets hold no position (``armik.Axis`` alone) on several tips: their words
say no metres, as one arm's say none for an ``Axis``; the joined rows of a batch or a path
held NaN for their position and said "nan m", and their verdicts' 0 m."""

from __future__ import annotations

import re

import numpy as np
import pytest

import armik
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
