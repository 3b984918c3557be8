"""``sixr_judged.judged``: a 6R closed form's rows measured by the compiled FK (as
``fk_checks`` measures them), judged by the verdict's rule and ordered as ``solve_all``
ranks them; the rows the rule alone does not decide go to the general verdict, labelled;
a decided target's labels read with its results, numbered when one is met twice."""

from __future__ import annotations

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
    judge_array,
    judged,
)
from armik.status import Status
from armik.verify.judged import Judged
from armik.verify.verdict import numbered

from ...conftest import arm

TOL = 1e-6


FAMILIES = {"ur5": "three_parallel", "abb_irb120": "spherical_wrist"}


def _chain(a):
    """The family's ``sixr.flat`` array of the bundled arm ``a``."""
    family = import_module(f"armik.solvers.closed_form.{FAMILIES[a.name]}")
    return sixr.flat(a.kinematics, family.FAMILY, family._classify)


def _case(name: str = "ur5", seed: int = 0):
    """(judge(rows) -> (n, verdict), the target's configuration q, the arm)."""
    a = arm(name)
    m = a.kinematics
    q = a.random_q(np.random.default_rng(seed))
    H = a.fk(q).homogeneous
    frame = fk_check_frame(np.ones(6), 2, m.lower, m.upper)
    chain = _chain(a)

    def judge(rows: np.ndarray):
        flat = m.kernel_chain.flat
        return judged(len(rows), chain, *flat, frame, judge_array(TOL, TOL), H, rows)

    return judge, q, a


def _row(q, flags: int = 0, bits: int = 0, code: int = 0) -> np.ndarray:
    row = np.zeros(WIDTH)
    row[:6], row[6], row[7], row[8] = q, flags, bits, code
    return row


def test_rows_are_measured_as_fk_checks_measures_them():
    judge, q, a = _case()
    rng = np.random.default_rng(1)
    rows = np.array([_row(q, bits=0)] + [_row(a.random_q(rng), LS, b) for b in (1, 2, 3)])
    expected = np.empty((4, 3))
    m = a.kinematics
    H = a.fk(q).homogeneous
    frame = fk_check_frame(np.ones(6), 2, m.lower, m.upper)
    fk_checks(*m.kernel_chain.flat, frame, H, rows.copy(), expected)
    n, verdict = judge(rows)
    assert (n, verdict) == (4, DECIDED)
    assert np.array_equal(rows[0, MEASURED : MEASURED + 3], expected[0])  # bit for bit
    got = {tuple(r[:6]): tuple(r[MEASURED : MEASURED + 3]) for r in rows}
    assert all(got[tuple(r[:6])] == tuple(e) for r, e in zip(rows, expected))


def test_verified_rows_first_in_their_order_then_failures_by_rank_and_error():
    judge, q, a = _case("abb_irb120")
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
            _row(q, 0, 5),
        ]
    )
    before = rows.copy()
    n, verdict = judge(rows)
    assert (n, verdict) == (5, DECIDED)
    assert rows[:, 7].tolist() == [2, 5, 4, 3, 1] or rows[:, 7].tolist() == [2, 5, 4, 1, 3]
    errors = rows[3:, MEASURED] + rows[3:, MEASURED + 1]
    assert errors[0] <= errors[1]  # the unreachable rows by their errors
    codes = [Status.CONVERGED, Status.CONVERGED, Status.JOINT_LIMITS, Status.UNREACHABLE,
             Status.UNREACHABLE]  # fmt: skip
    assert rows[:, STATUS].tolist() == [s.code for s in codes]
    assert sorted(map(tuple, rows[:, :11])) == sorted(map(tuple, before[:, :11]))


@pytest.mark.parametrize(
    "change",
    ["one row", "claimed, refuted within the limits", "unclaimed, verified", "a search's miss"],
)
def test_what_the_rule_alone_does_not_decide_goes_to_the_general_verdict(change):
    judge, q, a = _case()
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
    n, verdict = judge(rows)
    assert (n, verdict) == (len(rows), GENERAL)
    kept = [c for c in range(11) if c != 7]  # column 7: each row's branch, written
    assert np.array_equal(rows[:, kept], before[:, kept])  # nothing reordered


def test_the_general_verdicts_rows_are_labelled_the_decided_ones_with_their_results():
    judge, q, a = _case()
    h, p = sixr.unflatten.py_func(_chain(a))[:2]
    rows = np.array([_row(q), _row(0.9 * q, LS, 0, SHOULDER_OFFSET)])
    rows[0, 6] = LS  # unclaimed, verified: the general verdict's
    assert judge(rows) == (2, GENERAL)
    assert rows[:, 7].tolist() == [sixr.branch_bits(h, p, r[:6].copy()) for r in rows]
    rows = np.array([_row(q), _row(0.9 * q, LS, 0, SHOULDER_OFFSET)])
    assert judge(rows) == (2, DECIDED)
    assert rows[:, 7].tolist() == [0, 0]  # read with the results
    bits = [sixr.branch_bits(h, p, r[:6].copy()) for r in rows]
    results = _judged_of(a).solutions(rows, 0.0)
    assert [r.branch for r in results] == numbered([sixr.LABELS[b] for b in bits])
    assert [r.success for r in results] == [True, False]


def _judged_of(a) -> Judged:
    """The ``Judged`` of ``a``'s closed form, as ``armik.solve.prepared`` builds it."""
    m = a.kinematics
    spec = registry.choose("auto", m, None, Options(), True)
    run_pose = spec.prepare_pose(m, Options(), False)
    return Judged(m, run_pose.labels, run_pose.words, spec.name, TOL, TOL, True)


def test_a_label_met_twice_is_numbered():
    judge, q, a = _case()
    rows = np.array([_row(q), _row(q)])
    assert judge(rows) == (2, DECIDED)
    twice = [r.branch for r in _judged_of(a).solutions(rows, 0.0)]
    once = [r.branch for r in _judged_of(a).solutions(rows[:1].copy(), 0.0)]
    assert len(set(twice)) == 2 and all(b.startswith(once[0]) for b in twice)
    assert twice != [once[0], once[0]]
