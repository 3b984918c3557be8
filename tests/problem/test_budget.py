"""A solve's budget as an object (armik.Budget): the old keywords spell the same budget,
bad values get armik errors naming them, and its accounts say what is left."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armik
from armik import cpu_time
from armik.errors import OptionError
from armik.options import Options
from armik.problem.budget import DEFAULT
from tests import conftest


def test_the_old_keywords_spell_the_same_budget():
    new = Options.from_kwargs({"budget": armik.Budget(timeout=0.01, restarts=3, per_attempt=40)})
    old = Options.from_kwargs({"timeout": 0.01, "max_restarts": 3, "max_iterations": 40})
    assert new == old
    assert new.budget == armik.Budget(timeout=0.01, iterations=None, restarts=3, per_attempt=40)
    counted = Options.from_kwargs({"budget": armik.Budget(iterations=500)})
    assert counted.iteration_budget == 500 and counted.budget.counted
    assert Options().budget == DEFAULT and not DEFAULT.counted


@pytest.mark.parametrize(
    ("given", "named"),
    [
        ({"timeout": 0.0}, "Budget timeout must be > 0, got 0.0"),
        ({"timeout": math.nan}, "Budget timeout must be finite"),
        ({"timeout": "fast"}, "Budget timeout must be a number, got 'fast'"),
        ({"iterations": 0}, "Budget iterations must be >= 1, got 0"),
        ({"iterations": 2.5}, "Budget iterations must be an integer"),
        ({"restarts": -1}, "Budget restarts must be >= 0, got -1"),
        ({"per_attempt": True}, "Budget per_attempt must be an integer"),
    ],
)
def test_bad_budgets_are_named(given, named):
    with pytest.raises(OptionError, match=named.replace("(", r"\(")):
        armik.Budget(**given)


def test_a_budget_given_twice_or_not_a_budget_is_refused():
    with pytest.raises(OptionError, match="timeout is given twice .by the budget and as an"):
        Options.from_kwargs({"budget": armik.Budget(timeout=0.01), "timeout": 0.02})
    with pytest.raises(OptionError, match="budget must be an armik.Budget"):
        Options.from_kwargs({"budget": {"timeout": 0.01}})


def test_the_accounts_of_a_counted_budget():
    budget = Options.from_kwargs({"iteration_budget": 100, "max_restarts": 5}).budget
    started = cpu_time.thread_time()
    left = budget.left(started, used=30, restarts=2)
    assert left is not None
    assert (left.iterations, left.restarts, left.per_attempt) == (70, 3, 100)
    assert budget.attempt(30) == 70 and budget.attempt(95) == 5
    assert budget.spent(started, 100) and budget.left(started, 100, 0) is None
    assert budget.time_left(started) == math.inf


def test_the_accounts_of_a_timed_budget():
    budget = Options.from_kwargs({"timeout": 1.0, "max_iterations": 40}).budget
    now = cpu_time.thread_time()  # as budgets count it (less earlier Python runs)
    left = budget.left(now, used=10_000, restarts=0)  # iterations do not count here
    assert left is not None and left.iterations is None and 0.0 < left.timeout <= 1.0
    assert budget.attempt(10_000) == 40
    assert budget.spent(now - 2.0, 0) and budget.left(now - 2.0, 0, 0) is None


def test_solves_with_a_budget_equal_the_old_keywords():
    """One target each way on the Panda: a solve, a solve with collisions (whose retry
    spends what is left), a batch, a path and a list of tasks the task solver takes."""
    arm = conftest.arm("panda")
    rng = np.random.default_rng(11)
    q_true = arm.random_q(rng)
    T = arm.fk(q_true)
    q0 = arm.random_q(rng)
    budget, said = (
        armik.Budget(iterations=3000, restarts=20),
        {
            "iteration_budget": 3000,
            "max_restarts": 20,
        },
    )
    wall = armik.Box((0.05, 0.6, 0.6), (0.3, 0.0, 0.5))
    cases = [
        (arm.solve, T, {}),
        (arm.solve, T, {"obstacles": [wall], "self_collision": True}),
        (arm.solve_all, T, {}),
    ]
    for solve, target, more in cases:
        new = solve(target, q0=q0, budget=budget, **more)
        old = solve(target, q0=q0, **said, **more)
        new, old = ([new], [old]) if isinstance(new, armik.IKResult) else (new, old)
        assert [r.q.tolist() for r in new] == [r.q.tolist() for r in old]
        assert [r.reason for r in new] == [r.reason for r in old]
    poses = [arm.fk(arm.random_q(rng)) for _ in range(3)]
    new_b = arm.solve_batch(poses, q0=q0, budget=budget)
    old_b = arm.solve_batch(poses, q0=q0, **said)
    assert np.array_equal(new_b.q, old_b.q)
    new_p = arm.solve_path(poses, q0=q0, budget=budget)
    old_p = arm.solve_path(poses, q0=q0, **said)
    assert np.array_equal(new_p.q, old_p.q)
    tasks = [
        armik.Position(T.translation),
        armik.Axis((0, 0, 1), T.rotation[:, 2], 0.05),
        armik.Position(
            conftest.frame_position(arm, q_true, "panda_link4"),
            bounds=[0.02] * 3,
            frame="panda_link4",
        ),
    ]
    new_t = arm.solve(tasks, q0=q0, budget=budget)
    old_t = arm.solve(tasks, q0=q0, **said)
    assert new_t.q.tolist() == old_t.q.tolist() and new_t.iterations == old_t.iterations


def test_a_counted_budget_bounds_the_iterations():
    """An unreachable pose with a small counted budget: the solver stops within it."""
    arm = conftest.arm("panda")
    far = np.array([2.0, 0.0, 0.5])
    r = arm.solve(far, budget=armik.Budget(iterations=50, restarts=3))
    assert not r.success and r.iterations <= 50
