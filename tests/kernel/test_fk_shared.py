"""``fk_checks_beside`` on rows that share leading joint values (``fk_shared``: each row
continued from an earlier row's partial placement) measures them bit for bit as
``fk_checks`` does row by row, on every bundled arm (mimic joints and weights: row by row
there too), signed zeros told apart, the rows it is told to skip measured apart."""

from __future__ import annotations

import numpy as np
import pytest

from armik.kernel.measure import fk_check_frame, fk_checks, fk_checks_beside

from ..conftest import ALL_ROBOTS, arm


def _branches(a, rng) -> np.ndarray:
    """Rows in branches, as a closed form gives them: the first joint two ways, the
    next ones two ways each under it, the rest free; a row repeated, a signed zero."""
    n = a.dof
    Q = a.random_q(rng, n=12)
    for r in range(12):
        Q[r, 0] = Q[r % 2, 0]  # rows 0, 2, 4, ... share joint 1, as do 1, 3, 5, ...
        if n > 3:
            Q[r, 1:3] = Q[r % 4, 1:3]  # and joints 2, 3 four ways
    Q[11] = Q[5]  # a row met twice
    Q[10, :] = Q[9, :]
    Q[10, 0], Q[9, 0] = 0.0, -0.0  # the same number, not the same sine
    return Q


@pytest.mark.parametrize("name", ALL_ROBOTS)
@pytest.mark.parametrize("w, measure", [(np.ones(6), 2), (np.array([1.0, 0, 1, 1, 1, 0]), 3)])
def test_shared_rows_are_measured_as_row_by_row(name, w, measure):
    a = arm(name)
    m = a.kinematics
    rng = np.random.default_rng(5)
    Q = _branches(a, rng)
    H = a.fk(a.random_q(rng)).homogeneous
    frame = fk_check_frame(w, measure, m.lower, m.upper)
    want = np.empty((len(Q), 3))
    fk_checks(*m.kernel_chain.flat, frame, H, Q.copy(), want)
    rows = np.full((len(Q), a.dof + 4), 7.0)
    rows[:, : a.dof] = Q
    skip = np.int64(0b100100100)  # rows 2, 5, 8 left alone (measured apart, later)
    n, col = np.int64(len(Q)), np.int64(a.dof)
    fk_checks_beside(*m.kernel_chain.flat, frame, H, rows, n, col, skip)
    left = [2, 5, 8]
    assert np.all(rows[left, a.dof : a.dof + 4] == 7.0)
    fk_checks_beside(*m.kernel_chain.flat, frame, H, rows, n, col, ~skip)  # the others
    got = rows[:, a.dof : a.dof + 3]
    assert np.array_equal(got, want, equal_nan=True)  # bit for bit
    assert np.array_equal(rows[:, : a.dof], Q)
    assert np.all(rows[:, a.dof + 3] == 7.0)  # nothing written beyond


def test_a_row_sharing_five_joints_is_measured_by_its_sixth():
    """The target's configuration and the same with the last joint turned by 1 mrad: the
    second row, continued from the first's placement after five joints, misses the
    target's orientation by that turn exactly."""
    a = arm("abb_irb120")
    m = a.kinematics
    rng = np.random.default_rng(6)
    q = a.random_q(rng)
    H = a.fk(q).homogeneous
    frame = fk_check_frame(np.ones(6), 2, m.lower, m.upper)
    rows = np.zeros((2, 17))
    rows[0, :6], rows[1, :6] = q, q
    rows[1, 5] += 1e-3  # the wrist's last joint apart: the first five shared
    fk_checks_beside(*m.kernel_chain.flat, frame, H, rows, np.int64(2), np.int64(11), np.int64(0))
    assert rows[0, 11] < 1e-12 and rows[0, 12] < 1e-12  # the target's own configuration
    assert rows[1, 12] == pytest.approx(1e-3, rel=1e-6)  # turned by the last joint alone
