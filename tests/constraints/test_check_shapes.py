"""A user's ``Check`` of another shape than the verdict reads (``ok`` one bool for many
answers, a column, too short; ``status`` a str), a check that raises, or a result that is no
``Check``: an ``OptionError`` naming the constraint's class and what is wrong, on every
route, where numpy's and Python's own errors came out of the verdict. One bool (or a
(1, 1) array) for one answer is that answer's."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint
from armik.constraints.hold import Hold
from armik.constraints.limits import JointLimits
from tests.conftest import arm as bundled


class BoolOk(Constraint):
    def check(self, arm, Q):
        return Check(bool(Q[0, 2] > -5), armik.Status.JOINT_LIMITS, lambda i: "j3")


class ColumnOk(Constraint):
    def check(self, arm, Q):
        return Check((Q[:, 2] > -5)[:, None], armik.Status.JOINT_LIMITS, lambda i: "j3")


class ShortOk(Constraint):
    def check(self, arm, Q):
        return Check(np.ones(1, bool), armik.Status.JOINT_LIMITS, lambda i: "j3")


class WordStatus(Constraint):
    def check(self, arm, Q):
        return Check(Q[:, 2] > 5.0, "joint_limits", lambda i: "never")


class Raising(Constraint):
    def check(self, arm, Q):
        return Check(Q[:, 2] > float(Q[0, 2]) / 0.0, armik.Status.JOINT_LIMITS, str)


class Plain(Constraint):
    def check(self, arm, Q):
        return (Q[:, 2] > -5, armik.Status.JOINT_LIMITS, lambda i: "j3")


class WhyRaises(Constraint):
    def check(self, arm, Q):
        return Check(Q[:, 2] > 5.0, armik.Status.JOINT_LIMITS, lambda i: f"j3 {Q[i + 99, 2]}")


class WhyNumber(Constraint):
    def check(self, arm, Q):
        return Check(Q[:, 2] > 5.0, armik.Status.JOINT_LIMITS, lambda i: Q[i, 2])


@pytest.fixture(scope="module")
def panda():
    return bundled("panda")


def _solves(panda):
    T = panda.fk(panda.middle + 0.1)
    targets = [T, panda.fk(panda.middle - 0.1)]
    return {
        "solve": lambda c: panda.solve(T, constraints=[c]),
        "solve_all": lambda c: panda.solve_all(T, constraints=[c]),
        "solve_batch": lambda c: panda.solve_batch(targets, constraints=[c], workers=1),
    }


@pytest.mark.parametrize("route", ["solve", "solve_all", "solve_batch"])
@pytest.mark.parametrize(
    ("cls", "said"),
    [
        (WordStatus, r"Check.status must be .* got 'joint_limits' \(a str\): give "
         r"armik.Status.JOINT_LIMITS"),
        (Raising, "its check raised ZeroDivisionError: float division by zero"),
        (Plain, "its check returned tuple, not a Check"),
        (WhyRaises, r"its Check.why of answer 0 raised IndexError: index 99 is out of bounds"),
        (WhyNumber, r"its Check.why of answer 0 must return a str, got np.float64"),
    ],
)  # fmt: skip
def test_a_bad_check_on_any_answers_is_named(panda, route, cls, said):
    with pytest.raises(armik.OptionError, match=f"constraint {cls.__name__}: {said}") as e:
        _solves(panda)[route](cls())
    assert e.value.option == "constraints"


@pytest.mark.parametrize("route", ["solve_all", "solve_batch"])
@pytest.mark.parametrize(
    ("cls", "said"),
    [
        (BoolOk, r"one bool per answer checked, shape \(\d+,\) here, got True"),
        (ColumnOk, r"shape \((\d+),\) here, got shape \(\1, 1\), dtype bool \(a column"),
        (ShortOk, r"shape \(\d+,\) here, got shape \(1,\), dtype bool"),
    ],
)
def test_ok_of_another_shape_than_the_answers_is_named(panda, route, cls, said):
    with pytest.raises(armik.OptionError, match=f"constraint {cls.__name__}: .*{said}"):
        _solves(panda)[route](cls())


@pytest.mark.parametrize("cls", [BoolOk, ColumnOk, ShortOk])
def test_one_bool_for_one_answer_is_that_answer_s(panda, cls):
    r = _solves(panda)["solve"](cls())
    assert r.success


def test_only_a_user_s_check_is_read_through():
    """armik's own constraints' checks are called as written: no call added."""
    assert not hasattr(Hold.check, "_armik_checked")
    assert not hasattr(JointLimits.check, "_armik_checked")
    assert BoolOk.check._armik_checked and BoolOk.check.__wrapped__.__name__ == "check"


class Boxed(Constraint):
    """A constraint whose ``box`` (the task solver's step rows) gives ``rows``."""

    def __init__(self, rows):
        self.rows = rows

    def box(self, arm):
        if isinstance(self.rows, str):
            raise KeyError("joint_9")
        return self.rows

    def check(self, arm, Q):
        return Check(np.ones(len(Q), bool), armik.Status.JOINT_LIMITS, lambda i: "never")


@pytest.mark.parametrize(
    ("rows", "said"),
    [
        ((np.zeros(3), np.ones(3)), r"7 numbers each .* got shapes \(3,\) and \(3,\)"),
        (np.zeros(7), r"must return None or \(lower, upper\)"),
        (("a", "b"), r"must return None or \(lower, upper\)"),
        ((-(10**400), 10**400), r"must return None or \(lower, upper\)"),  # beyond a float
        ((np.full(7, np.nan), np.ones(7)), r"lower <= upper.* joint 0 \(panda_joint1\)"),
        ((np.ones(7), -np.ones(7)), r"lower <= upper.* gave \[1.0, -1.0\]"),
        ("raise", "its box raised KeyError: 'joint_9'"),
    ],
)
def test_a_bad_box_is_named(panda, rows, said):
    """A user's ``box`` of another shape than one number per joint, below its lower row,
    or raising: numpy's broadcast and ufunc errors came out of the task solver's step (a
    single array was read as its first two numbers for every joint)."""
    T = panda.fk(panda.middle + 0.1)
    elbow = panda.fk(panda.middle + 0.1, "panda_link4").translation
    tasks = [armik.Pose(T), armik.Position(elbow, bounds=(0.05,) * 3, frame="panda_link4")]
    with pytest.raises(armik.OptionError, match=f"constraint Boxed: .*{said}") as e:
        panda.solve(tasks, constraints=[Boxed(rows)], iteration_budget=100)
    assert e.value.option == "constraints"


def test_a_box_of_one_number_a_side_holds_every_joint():
    """``(lower, upper)`` as two numbers: every joint within them, the answer's too."""
    arm = bundled("ur5")
    q = np.array([0.2, -1.0, 1.4, -0.6, 1.1, 0.3])
    elbow = arm.fk(q, "forearm_link").translation
    tasks = [armik.Position(arm.fk(q).translation), armik.Position(elbow, frame="forearm_link")]
    r = arm.solve(tasks, q0=q + 0.05, constraints=[Boxed((-1.5, 1.5))], iteration_budget=2000)
    assert r.success, r.reason
    assert np.all(np.abs(r.q) <= 1.5)


class AtNone(Boxed):
    def at(self, arm, seed):
        return None  # meant: "nothing to resolve"


class AtRaises(Boxed):
    def at(self, arm, seed):
        return {"wrist": 1}["elbow"]


@pytest.mark.parametrize(
    ("cls", "said"),
    [
        (AtNone, r"its at\(arm, seed\) must return the constraint resolved .* got None"),
        (AtRaises, "its at raised KeyError: 'elbow'"),
    ],
)
def test_a_bad_at_is_named(panda, cls, said):
    """A user's ``at`` (the constraint resolved for one solve) returning no constraint, or
    raising: a bare AttributeError ('NoneType' has no 'box') or KeyError
    came out of the task solver."""
    T = panda.fk(panda.middle + 0.1)
    elbow = panda.fk(panda.middle + 0.1, "panda_link4").translation
    tasks = [armik.Pose(T), armik.Position(elbow, bounds=(0.05,) * 3, frame="panda_link4")]
    with pytest.raises(armik.OptionError, match=f"constraint {cls.__name__}: {said}") as e:
        panda.solve(tasks, constraints=[cls(None)], iteration_budget=100)
    assert e.value.option == "constraints"
