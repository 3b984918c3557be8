"""A spherical wrist with axes 4 and 6 in line (joint 5 = 0): only joint 4 + joint 6 turns
the tool, so joint 4 is free. Where joint 6's limits are narrower than a turn, joint 4 at
the middle of its limits can leave joint 6 outside them on some branches and not others:
each such branch keeps joint 4 at the value nearest the middle that keeps joint 6 within
its limits, in ``solve_all`` and in the exported C alike, so that every branch the target
has is among the rows, each reaching it by Pinocchio's FK."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from tests.export.build import Solver
from tests.export.test_export_c import check_solutions, same_as_solve_all


def irb120_narrow_wrist() -> armik.Arm:
    return armik.load("abb_irb120").with_limits({"joint_6": (-1.0, 1.0)})


def _branch_found(Q: np.ndarray, q: np.ndarray) -> bool:
    """Whether a row of ``Q`` is ``q`` but for the split of joints 4 and 6 (modulo 2 pi)."""
    keep = [0, 1, 2, 4]
    for row in Q:
        same = np.abs(np.angle(np.exp(1j * (row[keep] - q[keep])))).max() < 1e-6
        total = np.angle(np.exp(1j * ((row[3] + row[5]) - (q[3] + q[5]))))
        if same and abs(total) < 1e-6:
            return True
    return False


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    arm = irb120_narrow_wrist()
    return arm, Solver(arm, "wrist", tmp_path_factory.mktemp("free_wrist"))


def test_every_branch_at_the_wrist_singularity(built):
    arm, solver = built
    rng = np.random.default_rng(1)
    moved = 0
    for _ in range(60):
        q = arm.random_q(rng)
        q[4] = 0.0
        T = arm.fk(q).homogeneous
        good = np.array([r.q for r in arm.solve_all(T) if r.success])
        assert _branch_found(good, q), q.tolist()  # the target's own branch
        Q = solver.ik(T)
        check_solutions(arm, Q, T)
        same_as_solve_all(arm, Q, T)
        moved += int(np.any(np.abs(Q[:, 3] - arm.middle[3]) > 1e-9))
    assert moved  # joint 4 at the middle left joint 6 outside its limits on some branch
