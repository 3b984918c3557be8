"""The one answer type before verification (``armik.solvers.answers.Answers``): rows built
from per-row values, one row, stacked and taken rows keep every column; every solver hands
its answers back in it, and the verdict reads each row as the results say."""

from __future__ import annotations

import numpy as np
import pytest

from armik.options import Options
from armik.solvers import registry
from armik.solvers.answers import Answers, one, stacked
from armik.solvers.claims import claim
from armik.status import Status
from armik.targets.pose import parse_target
from tests import conftest


def _three() -> Answers:
    return Answers.of(
        np.arange(9.0).reshape(3, 3),
        [Status.CONVERGED, Status.UNREACHABLE, Status.NOT_CONVERGED],
        ["a", "b", "c"],
        3,
        iterations=[1, 2, 3],
        restarts=[0, 1, 2],
        branch=["x", None, "z"],
        singular=[False, True, False],
    )


def test_rows_keep_every_column():
    a = _three()
    assert len(a) == 3 and a.q.shape == (3, 3) and a.claim.dtype == np.int8
    assert [a.status(i) for i in range(3)] == [
        Status.CONVERGED,
        Status.UNREACHABLE,
        Status.NOT_CONVERGED,
    ]
    assert [a.claimed(i) for i in range(3)] == [True, False, False]
    assert [a.label(i) for i in range(3)] == ["x", None, "z"]
    assert [a.is_singular(i) for i in range(3)] == [False, True, False]
    taken = a.take([2, 0])
    assert taken.q.tolist() == [[6.0, 7.0, 8.0], [0.0, 1.0, 2.0]]
    assert taken.reasons == ("c", "a") and taken.branch == ("z", "x")
    assert taken.iterations.tolist() == [3, 1] and taken.restarts.tolist() == [2, 0]
    assert taken.singular is not None and taken.singular.tolist() == [False, False]
    both = stacked([a.take((1,)), one(np.ones(3), Status.CONVERGED, "d", iterations=7)], 3)
    assert both.reasons == ("b", "d") and both.branch == (None, None)
    assert both.iterations.tolist() == [2, 7] and [both.is_singular(i) for i in (0, 1)] == [
        True,
        False,
    ]
    empty = stacked([], 3)
    assert len(empty) == 0 and empty.q.shape == (0, 3)
    assert a.reworded(["p", "q", "r"]).reason(2) == "r"


def test_a_claim_is_the_one_row_case():
    c = claim((np.zeros(6), 4, 1, "elbow-up", True, str, ("closed form",)))
    row = c.answers()
    assert len(row) == 1 and row.claimed(0) and row.reason(0) == "closed form"
    assert row.label(0) == "elbow-up" and row.is_singular(0)
    assert row.iterations.tolist() == [4] and row.restarts.tolist() == [1]


@pytest.mark.parametrize(
    ("name", "solver", "every"),
    [
        ("ur5", "dls", False),
        ("ur5", "qp", False),
        ("ur5", "clik", False),
        ("ur5", "auto", True),
        ("panda", "swept", True),
        ("abb_irb120", "general_6r", True),
        ("planar_2link", "planar2r", True),
    ],
)
def test_every_solver_hands_back_answers_the_results_keep(name, solver, every):
    """Each solver's ``run`` gives ``Answers``; the results of ``solve_all`` carry their
    rows' claims' words, labels and flags, each row verified on its own FK."""
    arm = conftest.arm(name)
    q = arm.random_q(np.random.default_rng(2))
    T = arm.fk(q)
    target = T.translation[:2] if name == "planar_2link" else T
    model = arm.kinematics
    parsed = parse_target(target, model)
    budget = {"iteration_budget": 2000, "max_iterations": 1000}  # clik: one long descent
    opts = Options(**budget)
    spec = registry.choose(solver, model, parsed, opts, every)
    near = q + 0.05  # a start clik (a baseline without restarts) converges from
    got = spec.run(model, parsed, near, opts, every)
    assert isinstance(got, Answers) and len(got) >= 1
    assert got.q.shape == (len(got), arm.dof)
    assert got.reasons is not None and all(got.reasons)
    results = arm.solve_all(target, q0=near, solver=spec.name, **budget)
    assert any(r.success for r in results)
    for r in results:
        if r.success:
            assert np.linalg.norm(arm.fk(r.q).translation - T.translation) <= 1e-6
