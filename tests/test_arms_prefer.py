"""Options on two IRB 120s that share no joint: held values checked against the robot
before any chain's batch runs."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.errors import JointError, TargetError

from .test_arms import dual_irb120


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def test_a_batch_checks_held_values_against_the_robot_before_any_chain_runs(cell, monkeypatch):
    def ran(*args, **kwargs):
        raise AssertionError("a chain's batch ran before the held values were checked")

    monkeypatch.setattr(type(cell.chain("l_tool0")), "solve_batch", ran)
    rows = {tip: np.zeros((2, 3)) for tip in cell.tips}
    with pytest.raises(JointError, match="outside joint 'r_joint_1'"):
        cell.solve_batch(rows, hold={"r_joint_1": 100.0})
    q0 = np.tile(cell.middle, (2, 1))
    q0[1, cell.joint_names.index("r_joint_2")] = 10.0  # held at q0's value: outside
    with pytest.raises(JointError, match="outside joint 'r_joint_2'"):
        cell.solve_batch(rows, q0=q0, hold={"r_joint_2": None})
    with pytest.raises(TargetError, match=r"shape \(2, 5\)"):  # the second tip's rows
        cell.solve_batch({"l_tool0": rows["l_tool0"], "r_tool0": np.zeros((2, 5))})
