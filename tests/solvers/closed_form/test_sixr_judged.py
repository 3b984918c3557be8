"""``sixr_judged.judged``: a 6R closed form's rows measured by the compiled FK (as
``fk_checks`` measures them), judged by the verdict's rule; ``finish`` (a decided
target's results' first access) measures the rows claimed outside the limits the same way,
orders the rows as ``solve_all`` ranks them and labels them; the rows the rule alone does
not decide go to the general verdict, labelled; a label met twice is numbered."""

from __future__ import annotations

from functools import partial
from importlib import import_module

import numpy as np
import pytest

from armik.kernel.measure import fk_check_frame, fk_checks
from armik.options import Options
from armik.solvers import registry
from armik.solvers.closed_form import sixr
from armik.solvers.closed_form.sixr import LS, NOT_FOUND, SHOULDER_OFFSET
from armik.solvers.closed_form.sixr_judged import (
    DECIDED,
    GENERAL,
    MEASURED,
    STATUS,
    WIDTH,
    context,
    finish,
    judge_array,
    judged,
)
from armik.status import Status
from armik.verify.judged import Judged
from armik.verify.verdict import numbered

from ...conftest import arm

TOL = 1e-6
TAG = 10  # a test row's own mark (the kernel's second reason value): which row it is
FAMILIES = {"ur5": "three_parallel", "abb_irb120": "spherical_wrist"}


def _chain(a):
    """The family's ``sixr.flat`` array of the bundled arm ``a``."""
    family = import_module(f"armik.solvers.closed_form.{FAMILIES[a.name]}")
    return sixr.flat(a.kinematics, family.FAMILY, family._classify)


class _Case:
    """A bundled arm, a target's configuration q, and ``judge`` / ``whole`` over rows."""

    def __init__(self, name: str = "ur5", seed: int = 0) -> None:
        self.arm = a = arm(name)
        m = a.kinematics
        self.q = a.random_q(np.random.default_rng(seed))
        self.H = a.fk(self.q).homogeneous
        self.frame = fk_check_frame(np.ones(6), 2, m.lower, m.upper)
        self.chain = _chain(a)
        self.ctx = context(self.chain, m.kernel_chain.flat, self.frame, judge_array(TOL, TOL))

    def judge(self, rows: np.ndarray, whole: bool = False):
        """``judged`` of ``rows`` (n, WIDTH) in an array of one row more, as the prepared
        solve passes them, then ``finish`` of the rows it kept with ``whole``; the rows
        written back."""
        buffer = np.vstack([rows, np.zeros((1, WIDTH))])
        m = self.arm.kinematics
        got = judged(
            len(rows), self.chain, *m.kernel_chain.flat, self.frame, judge_array(TOL, TOL),
            self.H, buffer,
        )  # fmt: skip
        if whole:
            finish(self.ctx, buffer, got[0])
        rows[:] = buffer[:-1]
        return got

    def judged_results(self) -> Judged:
        """The ``Judged`` of the arm's closed form, as ``armik.solve.prepared`` builds it."""
        m = self.arm.kinematics
        spec = registry.choose("auto", m, None, Options(), True)
        run_pose = spec.prepare_pose(m, Options(), False)
        return Judged(m, partial(finish, self.ctx), run_pose.words, spec.name, TOL, TOL, True)

    def results(self, rows: np.ndarray):
        """The results of ``rows`` judged (decided), as ``solve_all`` gives them."""
        buffer = np.vstack([rows, np.zeros((1, WIDTH))])
        m = self.arm.kinematics
        n, verdict = judged(
            len(rows), self.chain, *m.kernel_chain.flat, self.frame, judge_array(TOL, TOL),
            self.H, buffer,
        )  # fmt: skip
        assert verdict == DECIDED
        return self.judged_results().solutions(buffer, n, 0.0)


def _turned(a, q: np.ndarray) -> np.ndarray:
    """q with its last joint turned by 2 pi within the limits: the same pose and branch,
    another configuration (two rows of one q are one solution, listed once)."""
    other = q.copy()
    other[5] += 2 * np.pi if q[5] + 2 * np.pi <= a.upper[5] else -2 * np.pi
    assert a.within_limits(other)
    return other


def _row(q, flags: int = 0, tag: int = 0, code: int = 0) -> np.ndarray:
    row = np.zeros(WIDTH)
    row[:6], row[6], row[8], row[TAG] = q, flags, code, tag
    return row


def test_rows_are_measured_as_fk_checks_measures_them():
    case = _Case()
    a, q = case.arm, case.q
    rng = np.random.default_rng(1)
    outside = q.copy()
    outside[0] = a.upper[0] + 0.2  # claimed outside the limits: measured by finish
    rows = np.array(
        [_row(q), *[_row(a.random_q(rng), LS, b) for b in (1, 2, 3)], _row(outside, 0, 4)]
    )
    expected = np.empty((5, 3))
    fk_checks(*a.kinematics.kernel_chain.flat, case.frame, case.H, rows.copy(), expected)
    original, judged_only = rows.copy(), rows.copy()
    assert case.judge(judged_only) == (5, DECIDED)
    assert np.isnan(judged_only[4, MEASURED : MEASURED + 2]).all()  # waits for finish
    assert judged_only[4, STATUS] == Status.JOINT_LIMITS.code
    assert case.judge(rows, whole=True) == (5, DECIDED)
    got = {r[TAG]: tuple(r[MEASURED : MEASURED + 3]) for r in rows}
    assert all(got[r[TAG]] == tuple(e) for r, e in zip(original, expected))  # bit for bit
    ordered = {r[TAG]: r for r in rows}
    before = {r[TAG]: r for r in judged_only}
    assert all(  # the rows measured in the call are as finish leaves them
        np.array_equal(before[t][MEASURED : MEASURED + 3], ordered[t][MEASURED : MEASURED + 3])
        for t in (0, 1, 2, 3)
    )


def test_verified_rows_first_in_their_order_then_failures_by_rank_and_error():
    case = _Case("abb_irb120")
    a, q = case.arm, case.q
    outside = q.copy()
    outside[5] = a.upper[5] + 0.5  # claimed, outside the limits: joint_limits
    far = q + 0.3  # not reached: its claim stands (unreachable), ranked after joint_limits
    farther = q + 0.6
    rows = np.array(
        [
            _row(farther, LS, 1, SHOULDER_OFFSET),
            _row(q, 0, 2),
            _row(far, LS, 3, SHOULDER_OFFSET),
            _row(outside, 0, 4),
            _row(_turned(a, q), 0, 5),
        ]
    )
    before = rows.copy()
    n, verdict = case.judge(rows, whole=True)
    assert (n, verdict) == (5, DECIDED)
    assert rows[:, TAG].tolist() in ([2, 5, 4, 3, 1], [2, 5, 4, 1, 3])
    errors = rows[3:, MEASURED] + rows[3:, MEASURED + 1]
    assert errors[0] <= errors[1]  # the unreachable rows by their errors
    codes = [Status.CONVERGED, Status.CONVERGED, Status.JOINT_LIMITS, Status.UNREACHABLE,
             Status.UNREACHABLE]  # fmt: skip
    assert rows[:, STATUS].tolist() == [s.code for s in codes]
    kept = [c for c in range(11) if c != 7]  # column 7: each row's branch, written
    assert sorted(map(tuple, rows[:, kept])) == sorted(map(tuple, before[:, kept]))
    h, p = sixr.unflatten.py_func(case.chain)[:2]
    assert rows[:, 7].tolist() == [sixr.branch_bits(h, p, r[:6].copy()) for r in rows]


@pytest.mark.parametrize(
    "change",
    ["one row", "claimed, refuted within the limits", "unclaimed, verified", "a search's miss"],
)
def test_what_the_rule_alone_does_not_decide_goes_to_the_general_verdict(change):
    case = _Case()
    q = case.q
    rows = np.array([_row(q, 0, 0), _row(0.9 * q, LS, 1, SHOULDER_OFFSET)])  # within
    if change == "one row":
        rows = rows[:1]
    elif change == "claimed, refuted within the limits":
        rows[1, 6] = 0
    elif change == "unclaimed, verified":
        rows[0, 6] = LS
    else:
        rows[1, 8] = NOT_FOUND
    before = rows[:, :11].copy()
    n, verdict = case.judge(rows)
    assert (n, verdict) == (len(rows), GENERAL)
    kept = [c for c in range(11) if c != 7]  # column 7: each row's branch, written
    assert np.array_equal(rows[:, kept], before[:, kept])  # nothing reordered
    h, p = sixr.unflatten.py_func(case.chain)[:2]
    assert rows[:, 7].tolist() == [sixr.branch_bits(h, p, r[:6].copy()) for r in rows]


def test_a_verified_row_found_twice_is_kept_once():
    """Two verified rows within DUPLICATE_TOL in every joint (a double root the kernel found
    twice) are one solution: the first kept, the rows after it moved up, a failure as near
    kept; decided by the rule as before."""
    case = _Case()
    a, q = case.arm, case.q
    outside = q.copy()
    outside[0] = a.upper[0] + 0.2  # claimed outside the limits: measured by finish
    rows = np.array(
        [_row(q, 0, 1), _row(outside, 0, 2), _row(q + 1e-9, 0, 3), _row(_turned(a, q), 0, 4)]
    )
    n, verdict = case.judge(rows, whole=True)
    assert (n, verdict) == (3, DECIDED)
    assert rows[:3, TAG].tolist() == [1, 4, 2]
    assert rows[2, STATUS] == Status.JOINT_LIMITS.code and rows[2, MEASURED] > 0.0


def test_a_decided_targets_labels_are_read_with_its_results():
    case = _Case()
    q = case.q
    rows = np.array([_row(q), _row(0.9 * q, LS, 1, SHOULDER_OFFSET)])
    judged_only = rows.copy()
    assert case.judge(judged_only) == (2, DECIDED)
    assert judged_only[:, 7].tolist() == [0, 0]  # read with the results
    h, p = sixr.unflatten.py_func(case.chain)[:2]
    bits = [sixr.branch_bits(h, p, r[:6].copy()) for r in rows]
    results = case.results(rows)
    assert [r.branch for r in results] == numbered([sixr.LABELS[b] for b in bits])
    assert [r.success for r in results] == [True, False]
    assert not results[0].q.flags.writeable


def test_a_label_met_twice_is_numbered():
    case = _Case()
    q = case.q
    twice = [r.branch for r in case.results(np.array([_row(q), _row(_turned(case.arm, q))]))]
    once = [r.branch for r in case.results(np.array([_row(q), _row(0.9 * q, LS, 1, 1)]))]
    assert twice == [once[0], f"{once[0]}#2"]
