"""A user's constraint's ``box`` is read on every route, as the task solver reads it: a
malformed one (its shape, lower above upper, a NaN) is an ``OptionError`` naming its class,
where the compiled routes, which never step within it, took it silently."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint
from tests.conftest import arm as bundled


def _boxed(box):
    class Boxed(Constraint):
        def box(self, arm):
            return box(arm)

        def check(self, arm, Q):
            return Check(np.ones(len(Q), bool), armik.Status.JOINT_LIMITS, lambda i: "no")

    return Boxed()


BAD = {
    "shape": lambda a: (np.zeros(3), np.ones(3)),
    "order": lambda a: (a.upper, a.lower),
    "nan": lambda a: (np.full(a.dof, np.nan), a.upper),
}


@pytest.mark.parametrize("bad", sorted(BAD))
def test_a_malformed_box_is_refused_by_name_on_every_route(bad):
    ur5 = bundled("ur5")
    q = ur5.random_q(3)
    T = ur5.fk(q)
    c = [_boxed(BAD[bad])]
    routes = {
        "pose": lambda: ur5.solve(T, q0=q, constraints=c),
        "one task": lambda: ur5.solve([armik.Pose(T)], q0=q, constraints=c),
        "dls": lambda: ur5.solve(T, q0=q, constraints=c, solver="dls"),
        "position": lambda: ur5.solve(T.translation, q0=q, constraints=c),
        "solve_all": lambda: ur5.solve_all(T, constraints=c),
        "batch": lambda: ur5.solve_batch([T, T], q0=q, constraints=c, workers=1),
        "path": lambda: ur5.solve_path([T, T], q, constraints=c),
        "tasks": lambda: ur5.solve(
            [armik.Pose(T), armik.Position(T.translation)], q0=q, constraints=c
        ),
    }
    for route, call in routes.items():
        with pytest.raises(armik.OptionError, match="constraint Boxed: its box must") as got:
            call()
        assert got.value.option == "constraints", route


def test_a_box_well_formed_is_taken():
    ur5 = bundled("ur5")
    q = ur5.random_q(3)
    T = ur5.fk(q)
    for box in (lambda a: (a.lower, a.upper), lambda a: (-np.inf, np.inf), lambda a: None):
        r = ur5.solve(T, q0=q, constraints=[_boxed(box)])
        assert r.success, r.reason
        F = ur5.fk(r.q)
        assert np.linalg.norm(F.translation - T.translation) < 1e-6


class PinnedFirst(Constraint):
    """The first joint held at 0.3 rad by its box alone; its check reads nothing."""

    def box(self, arm):
        lower, upper = arm.lower.copy(), arm.upper.copy()
        lower[0] = upper[0] = 0.3
        return lower, upper

    def check(self, arm, Q):
        return Check(np.ones(len(Q), bool), armik.Status.JOINT_LIMITS, lambda i: "no")


def test_no_route_calls_an_answer_outside_a_constraints_box_a_success():
    """The task solver steps within a user's box; the compiled routes never read it, and an
    answer they found outside it (a UR5 branch with its first joint elsewhere) was a success:
    the check refuses it now on every route, in the check's status, and the branch in the
    box wins where there is one."""
    ur5 = bundled("ur5")
    q = ur5.random_q(7)
    c = [PinnedFirst()]
    for first, reachable in ((0.3, True), (1.5, False)):
        q[0] = first
        T = ur5.fk(q)
        found = [ur5.solve(T, q0=ur5.middle, constraints=c)]
        found.append(ur5.solve([armik.Pose(T)], q0=ur5.middle, constraints=c))
        found += list(ur5.solve_all(T, constraints=c))
        batch = ur5.solve_batch([T, T], q0=ur5.middle, constraints=c, workers=1)
        found += [batch[i] for i in range(len(batch))]
        assert found[0].success is reachable, found[0].reason
        for r in found:
            F = ur5.fk(r.q)
            if r.success:
                assert abs(r.q[0] - 0.3) <= 1e-12
                assert np.linalg.norm(F.translation - T.translation) < 1e-6
        if not reachable:
            assert any("outside its box" in r.reason for r in found)
