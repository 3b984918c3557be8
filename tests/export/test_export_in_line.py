"""The exported swept 7R solver (joint 7 held) where joints 3 and 5 lie in one line (joint
4 = 0: the Panda's limits widened to hold it, the iiwa's stretched elbow): every row
``solve_all(T, hold=)`` gives, each reaching the target by Pinocchio's FK. Only the pair's
sum turns the tip; both keep joint 5 at the middle of its limits, or the value nearest it
that keeps joint 3 within its own, where the closed form's split was its rounding's."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from tests.export.build import Solver
from tests.export.test_export_c import reached
from tests.export.test_export_held import same_as_held_solve_all
from tests.solvers.test_swept_in_line import CASES, panda_shifted, panda_wide

LOADS = {"wide": panda_wide, "shifted": panda_shifted, "iiwa": lambda: armik.load("kuka_iiwa14")}
# m and rad: at joint 4 = 0 the elbow of the chain solved from the tip is at a double root,
# which rounding moves by about 1e-8 rad (the square root of double precision)
REACHED = 1e-7


@pytest.fixture(scope="module", params=sorted(LOADS))
def built(request, tmp_path_factory):
    arm = LOADS[request.param]()
    return arm, Solver(arm, "in_line", tmp_path_factory.mktemp("in_line"))


def check(arm, solver, q: np.ndarray) -> np.ndarray:
    """The C's rows for the tip's pose at ``q``, joint 7 held at q's: solve_all's, each
    reaching the pose within ``REACHED``."""
    T = arm.fk(q).homogeneous
    Q = solver.ik(T, q[6])
    assert np.isfinite(Q).all() and np.all(Q[:, 6] == q[6])
    for row in Q:
        assert arm.within_limits(row)
        assert max(reached(arm, row, T)) < REACHED, (row.tolist(), q.tolist())
    same_as_held_solve_all(arm, Q, T, q[6])
    return Q


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_split_configuration_is_among_the_rows(case, tmp_path):
    load, q, split = CASES[case]
    arm, q = load(), np.array(q)
    Q = check(arm, Solver(arm, "in_line", tmp_path), q)
    assert len(Q) == 4  # both shoulders, each at joint 4 = 0 and at the elbow's other root
    kept = np.delete(Q, split, axis=1)
    assert np.abs(kept - np.delete(q, split)).max(axis=1).min() < 1e-6


def test_targets_on_the_line_give_solve_alls_rows(built):
    arm, solver = built
    rng = np.random.default_rng(11)
    on_line = 0
    for k in range(60):
        q = arm.random_q(rng)
        q[3] = (0.0, 1e-12, -1e-12)[k % 3]
        if abs(q[1]) < 1e-3 or not arm.within_limits(q):
            continue  # joint 2 at 0 too: joints 1, 3 and 5 in one line, another case
        Q = check(arm, solver, q)
        on_line += int(np.any(np.abs(Q[:, 3]) < 1e-9))
    assert on_line >= 20
