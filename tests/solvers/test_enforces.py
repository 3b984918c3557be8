"""A solver declares the constraint classes its own steps keep (``SolverSpec.enforces``):
"auto" takes one that keeps a request's constraints before a solver of higher priority
that does not, and the verdict checks every constraint whatever a solver declares (the
registry's rule): a solver declaring nothing, or one declaring a constraint it then
breaks, has the user's constraint refused."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint
from armik.solvers import registry
from tests.conftest import arm as bundled

BENT = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])  # panda_joint4 at -2 rad


class ElbowUp(Constraint):
    """panda_joint4 above -1 rad."""

    def check(self, arm, Q):
        return Check(Q[:, 3] > -1.0, armik.Status.JOINT_LIMITS, lambda i: "elbow below -1 rad")


@pytest.fixture
def keeper():
    """dls registered again as "elbow_keeper", below every bundled solver, declaring that it
    keeps ``ElbowUp`` (which it does not: the verdict is what refuses)."""
    spec = dataclasses.replace(
        registry.get("dls"),
        name="elbow_keeper",
        priority=1,
        enforces=frozenset({ElbowUp}),
        prepare_pose=None,
        run_batch=None,
    )
    registry.register(spec)
    yield spec
    registry.unregister("elbow_keeper")


def test_a_solver_declaring_nothing_has_a_users_constraint_refused_by_the_verdict():
    a = bundled("panda")
    assert registry.get("dls").enforces == frozenset()
    T = a.fk(BENT)
    r = a.solve(T, q0=BENT, solver="dls", max_restarts=0, constraints=[ElbowUp()])
    assert not r.success and r.status is armik.Status.JOINT_LIMITS
    assert "elbow below -1 rad" in r.reason
    b = a.solve_batch([T], q0=BENT, solver="dls", max_restarts=0, constraints=[ElbowUp()])
    assert not b.success[0] and "elbow below -1 rad" in b.reason(0)


def test_auto_takes_a_solver_keeping_the_constraints_before_a_higher_one(keeper):
    a = bundled("panda")
    q = a.middle + 0.1
    q[3] = -0.8  # the elbow up
    assert a.solve(a.fk(q), q0=q).solver == "dls"  # no constraint: priority decides
    r = a.solve(a.fk(q), q0=q, constraints=[ElbowUp()])
    assert r.solver == "elbow_keeper" and r.success


def test_a_declaration_never_makes_a_broken_answer_a_success(keeper):
    a = bundled("panda")
    r = a.solve(a.fk(BENT), q0=BENT, max_restarts=0, constraints=[ElbowUp()])
    assert r.solver == "elbow_keeper"
    assert not r.success and r.status is armik.Status.JOINT_LIMITS
    assert "elbow below -1 rad" in r.reason
