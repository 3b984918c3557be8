"""One verdict over N answers (``armik.verify.verdicts.Verdicts``): N answers decided at
once equal each decided alone, a result is a row of the verdicts, and a check applies to
the rows it was given only."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.constraints.clear import distances
from armik.kernel.descent import DUPLICATE_TOL
from armik.options import Options
from armik.solvers.answers import Answers
from armik.solvers.closed_form.sixr import TIE
from armik.status import Status
from armik.targets.pose import parse_target
from armik.verify.measure import measure, measure_many
from armik.verify.verdict import decide, decide_one, nearest_first
from armik.verify.verdicts import Verdicts
from tests import conftest

CLAIMS = [Status.CONVERGED, Status.NOT_CONVERGED, Status.UNREACHABLE, Status.CONVERGED]


def _answers(arm, rng, n: int) -> tuple[Answers, object]:
    """n answers for one reachable target: the answer itself, others near and far, one
    outside the limits, with each kind of claim."""
    q_goal = arm.random_q(rng)
    Q = [q_goal, q_goal + 1e-9, arm.random_q(rng)]
    Q.append(np.where(np.isfinite(arm.upper), arm.upper + 0.3, 0.0))  # outside the limits
    Q += [arm.random_q(rng) for _ in range(n - len(Q))]
    claims = [CLAIMS[i % len(CLAIMS)] for i in range(n)]
    words = [f"the solver's words {i}" for i in range(n)]
    answers = Answers.of(Q, claims, words, arm.dof, iterations=range(n), restarts=[1] * n)
    return answers, parse_target(arm.fk(q_goal), arm)


@pytest.mark.parametrize("name", ["panda", "ur5"])
@pytest.mark.parametrize("n", [12, 40])  # a few decided row by row, more by array calls
def test_n_answers_decided_at_once_equal_each_alone(name, n):
    arm = conftest.model(name)
    rng = np.random.default_rng(4)
    for opts in (Options(), Options(position_only=True), Options(tol_position=1e-3)):
        answers, target = _answers(arm, rng, n)
        many = decide(arm, answers, measure_many(arm, list(answers.q), target, opts), opts)
        assert many.success.any() and not many.success.all()
        for i in range(len(answers)):
            one = decide_one(arm, answers.take([i]), measure(arm, answers.q[i], target, opts), opts)
            assert _same(many.fields(i), one.fields(0))
            # the same words but the measured numbers (the compiled FK's and Pinocchio's)
            said, alone = many.reason(i), one.reason(0)
            assert said.split("position error")[0] == alone.split("position error")[0]
            assert many.succeeded(i) == one.succeeded(0)


MEASURED = ("position_error", "orientation_error", "reason")


def _same(a: dict, b: dict) -> bool:
    """The same fields, bit for bit (an unmeasured orientation None in both), but the
    errors: several answers are placed by the compiled FK (``measure_many``), one by
    Pinocchio's (``measure``), the same to 1e-12."""
    if a.keys() != b.keys():
        return False
    for k in a:
        if k == "q":
            if not np.array_equal(a[k], b[k]):
                return False
        elif k in MEASURED[:2] and a[k] is not None:
            if b[k] is None or abs(a[k] - b[k]) > 1e-12:
                return False
        elif k not in MEASURED and a[k] != b[k]:
            return False
    return True


def _ur5_verdicts():
    """Six UR5 answers and their verdicts (rows 0 and 1 successes, 3 outside the limits)."""
    arm = conftest.model("ur5")
    answers, target = _answers(arm, np.random.default_rng(8), 6)
    opts = Options()
    return answers, decide(arm, answers, measure_many(arm, list(answers.q), target, opts), opts)


def test_a_result_is_a_row_of_the_verdicts():
    answers, found = _ur5_verdicts()
    results = found.results([3, 0, 5], "dls", 0.25)
    for r, i in zip(results, [3, 0, 5]):
        assert r.solver == "dls" and r.time == 0.25
        assert np.array_equal(r.q, answers.q[i]) and not r.q.flags.writeable
        assert r.q.base is None or r.q.base is not answers.q  # a copy, not a view
        assert r.status.code == found.status[i] and r.success == bool(found.success[i])
        assert r.reason == found.reason(i)
        assert r.position_error == found.position_error[i]
        assert r.iterations == i and r.restarts == 1
        assert r.as_dict() == found.result(i, "dls", 0.25).as_dict()
    assert results[1].success  # the target's own answer
    assert results[1].reason.startswith("the solver's words 0; verified by forward kinematics")
    assert results[0].status is Status.JOINT_LIMITS  # claimed, outside the limits
    assert "outside the joint limits" in results[0].reason


def test_a_check_applies_to_the_rows_it_was_given():
    answers, found = _ur5_verdicts()
    assert found.succeeded(0) and found.succeeded(1)
    pair = ("a", "b")
    found.judge(distances([(0.5, pair), (-0.01, pair)], 0.0), rows=[1, 0])
    assert found.succeeded(1) and not found.succeeded(0)  # row 0 was the check's answer 1
    assert found.status[0] == Status.COLLISION.code
    assert found.reason(0).startswith("in collision: a and b")
    assert found.reason(1).endswith("a and b 0.5 m apart (margin 0 m)")
    assert found.extra[1]["min_distance"] == 0.5 and found.extra[2] == {}


def test_a_batch_of_answers_is_decided_as_one_solve_decides():
    arm = armik.load("panda")
    rng = np.random.default_rng(2)
    T = arm.fk_batch(np.stack([arm.random_q(rng) for _ in range(20)]))
    T[3, :3, 3] = (3.0, 0.0, 0.5)  # out of reach: a failure's words
    opts = dict(solver="dls", iteration_budget=2000)
    res = arm.solve_batch(T, q0=arm.kinematics.middle, progress=False, **opts)
    for i in range(len(T)):
        r = arm.solve(T[i], q0=arm.kinematics.middle, **opts)
        assert res.status[i] == r.status.value
        np.testing.assert_array_equal(res.q[i], r.q)
        assert res.position_error[i] == r.position_error
        if not r.success:  # in the same words, though a batch's solver gives none
            assert res.reason(i) == r.reason
    assert not res.success[3] and "beyond the arm's reach" in res.reason(3)


def test_rows_as_near_the_seed_to_the_tie_keep_the_solvers_order():
    """Successes by distance to the seed, but distances within sixr.TIE of each other (a
    sum's rounding) in the solver's order, as a closed form and the exported C list them;
    nearest_first (one answer's order) alike; the failures after them."""
    arm = conftest.model("ur5")
    seed = np.zeros(6)
    e = np.eye(6)
    Q = [
        e[0] * (1.0 + 1e-13),  # as near as rows 2 and 4: first, the solver's first
        e[1] * 3.0,  # a failure
        e[2],
        e[3] * 0.5,  # nearer by more than TIE
        e[4] * (1.0 - 1e-13),
        e[5] * (1.0 + 3 * TIE),  # farther by more than TIE
    ]
    claims = [Status.CONVERGED] * 6
    claims[1] = Status.UNREACHABLE
    answers = Answers.of(Q, claims, ["w"] * 6, 6)
    status = np.array([Status.CONVERGED.code] * 6, dtype=np.int8)
    status[1] = Status.UNREACHABLE.code
    found = Verdicts(answers, status, np.zeros(6), np.zeros(6), True, [None] * 6, 1e-6, 1e-6)
    assert found.order(seed) == [3, 0, 2, 4, 5, 1]
    assert nearest_first(arm, answers, seed) == [3, 0, 2, 4, 5, 1]


def test_a_success_listed_twice_is_listed_once():
    """Verdicts.once: a success within DUPLICATE_TOL of an earlier one in every joint (a
    double root found twice) is left out; one as near that is a failure, or farther in one
    joint, stays."""
    e = np.eye(6)
    Q = [e[0], e[0] + 1e-8, e[0] + 1e-8 * e[1], e[0] + 2 * DUPLICATE_TOL * e[5], e[2]]
    answers = Answers.of(Q, [Status.CONVERGED] * 5, ["w"] * 5, 6)
    status = np.array([Status.CONVERGED.code] * 5, dtype=np.int8)
    status[2] = Status.NOT_CONVERGED.code
    found = Verdicts(answers, status, np.zeros(5), np.zeros(5), True, [None] * 5, 1e-6, 1e-6)
    assert found.once([4, 1, 0, 3, 2]) == [4, 1, 3, 2]
    assert found.once([0, 4]) == [0, 4]
