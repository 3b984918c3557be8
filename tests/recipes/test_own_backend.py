"""A batch backend of a test's own, added by CONTRIBUTING's recipe: a function
``run(jobs, workers)`` registered with ``armik.solve.backends.register_backend`` (or passed
as ``backend=`` itself) that decides where each chunk's job runs. Its answers equal the
default's on the same seeds, bit for bit, with a constraint of the test's own holding on
every answer."""

from __future__ import annotations

import multiprocessing
import operator
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint
from armik.solve.backends import backends, register_backend, unregister_backend
from tests.conftest import arm as bundled

# answers independent of time and threads; no restart, so that the constraint refuses some
# rows (a restart finds a Panda answer that holds it for every target here)
BUDGET = {"iteration_budget": 400, "seed": 3, "max_restarts": 0}


class BaseTurn(Constraint):
    """The Panda's joint 1 within +- 0.5 rad (a check alone: the constraint recipe's least)."""

    def check(self, arm, Q):
        return Check(np.abs(Q[:, 0]) < 0.5, armik.Status.JOINT_LIMITS, lambda i: "base turned")


def reversed_serial(jobs, workers):
    """Every job here, the last first, the results handed back in that order: the batch
    places each by the row it starts at (``backends.Rows``)."""
    return [job() for job in reversed(jobs)]


def process_pool(jobs, workers):
    """The jobs on a ``concurrent.futures`` pool of forked processes: each job pickles
    (the arm, its targets, seeds and request, the constraint with it) and comes back."""
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        return list(pool.map(operator.call, jobs))


@pytest.fixture
def own():
    register_backend("reversed", reversed_serial)
    register_backend("pool", process_pool)
    try:
        yield
    finally:
        unregister_backend("reversed")
        unregister_backend("pool")


def _batch(n: int = 12):
    """Panda poses and starts, joint 1 at about 0 or +-0.6: answers near the latter
    break ``BaseTurn``."""
    rng = np.random.default_rng(5)
    panda = bundled("panda")
    qs = panda.middle + rng.uniform(-0.3, 0.3, (n, 7))
    qs[:, 0] = rng.choice([-0.6, 0.0, 0.6], n) + rng.uniform(-0.05, 0.05, n)
    return panda, [panda.fk(q) for q in qs], qs


def _same(a, b) -> None:
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.success, b.success)
    np.testing.assert_array_equal(a.status, b.status)
    assert [a[i].reason for i in range(len(a))] == [b[i].reason for i in range(len(b))]
    assert a.solver == b.solver


@pytest.mark.parametrize("name", ["reversed", "pool", "serial", "threads", "processes"])
def test_equal_answers_to_the_default_with_a_constraint(own, name):
    panda, targets, qs = _batch()
    default = panda.solve_batch(targets, q0=qs, constraints=[BaseTurn()], workers=1, **BUDGET)
    assert default.success.any() and not default.success.all()
    assert (np.abs(default.q[default.success, 0]) < 0.5).all()
    assert any(default[i].reason == "base turned" for i in range(len(default)))
    got = panda.solve_batch(
        targets,
        q0=qs,
        constraints=[BaseTurn()],
        workers=2,
        chunk_size=5,
        backend=name,
        **BUDGET,
    )
    _same(got, default)


def test_a_callable_is_a_backend_and_a_closed_form_too():
    ur5 = bundled("ur5")
    rng = np.random.default_rng(1)
    targets = [ur5.fk(ur5.middle + rng.uniform(-0.5, 0.5, 6)) for _ in range(7)]
    calls = []

    def counted(jobs, workers):
        calls.append(len(jobs))
        return [job() for job in jobs]

    got = ur5.solve_batch(targets, chunk_size=3, backend=counted)
    _same(got, ur5.solve_batch(targets, chunk_size=3))
    assert calls == [3]  # 7 targets in chunks of 3


def test_bad_backends_are_named(own):
    panda, targets, qs = _batch(4)
    with pytest.raises(armik.OptionError, match="unknown batch backend 'gpu'.*'reversed'"):
        panda.solve_batch(targets, backend="gpu")
    with pytest.raises(armik.OptionError, match="is taken"):
        register_backend("reversed", reversed_serial)
    with pytest.raises(armik.OptionError, match="unknown batch backend 'nothing'"):
        unregister_backend("nothing")
    with pytest.raises(armik.ArmikError, match="gave 0 results for 2 jobs"):
        panda.solve_batch(targets, chunk_size=2, backend=lambda jobs, workers: [])
    with pytest.raises(armik.ArmikError, match="gave None for job 0"):
        panda.solve_batch(targets, chunk_size=2, backend=lambda jobs, workers: [None, None])
    assert "reversed" in backends()


@pytest.mark.parametrize("name", ["reversed", "pool"])
def test_a_batch_solved_row_by_row_runs_on_its_own_backend(own, name):
    """A batch the compiled batch has no form for (``prefer=``): its chunks of rows are the
    backend's jobs, each row solved from its own seed, with a constraint of the test's
    own holding on every success: the default's answers."""
    panda, targets, qs = _batch(5)
    asked = {"prefer": "manipulability", "constraints": [BaseTurn()], **BUDGET}
    got = panda.solve_batch(targets, q0=qs, chunk_size=2, backend=name, **asked)
    _same(got, panda.solve_batch(targets, q0=qs, **asked))
    assert got.success.any() and (np.abs(got.q[got.success, 0]) < 0.5).all()  # it holds
