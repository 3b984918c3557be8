"""The verdict's one rule: one answer (``status_of``) and N (``status_codes``) decide alike,
as the library promises: a measure that holds is a success whatever was claimed, a refuted
claim is ``joint_limits`` or ``not_converged``, any other claim stands."""

import itertools

import numpy as np

from armik.status import Status
from armik.verify.verdict import status_codes, status_of


def expected(claim: Status, ok: bool, within: bool) -> Status:
    if ok:
        return Status.CONVERGED
    if claim is Status.CONVERGED:
        return Status.NOT_CONVERGED if within else Status.JOINT_LIMITS
    return claim


def test_one_and_n_answers_follow_the_same_rule():
    cases = list(itertools.product(list(Status), (False, True), (False, True)))
    claims = np.array([c.code for c, _, _ in cases], dtype=np.int8)
    ok = np.array([o for _, o, _ in cases])
    within = np.array([w for _, _, w in cases])
    many = status_codes(claims, ok, within)
    assert many.dtype == np.int8
    for (claim, o, w), code in zip(cases, many.tolist()):
        assert status_of(claim, o, w) is expected(claim, o, w)
        assert code == expected(claim, o, w).code
    # numpy booleans, as a measure of numpy floats gives them, decide as Python's do
    assert status_of(Status.CONVERGED, np.False_, np.True_) is Status.NOT_CONVERGED


def test_n_answers_take_any_array_of_flags():
    claims = np.array([Status.CONVERGED.code] * 3 + [Status.UNREACHABLE.code], dtype=np.int8)
    ok = np.array([1.0, 0.0, 0.0, 0.0])  # flags as numbers: read as booleans, not bytes
    within = [True, True, False, True]
    codes = status_codes(claims, ok, within).tolist()
    expect = [Status.CONVERGED, Status.NOT_CONVERGED, Status.JOINT_LIMITS, Status.UNREACHABLE]
    assert codes == [s.code for s in expect]
