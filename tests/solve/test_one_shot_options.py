"""Options given as one-shot iterators (a generator, ``iter([...])``) are the same request as
the list: a request's options are read more than once (spelled, checked, per chain), and an
iterator read once was empty the next time, its constraints, held joints or obstacles
dropped without a word and a violating answer called a success."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint
from tests.conftest import arm as bundled

Q_BENT = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])  # the Panda's joint 4 at -2


class ElbowUp(Constraint):
    def check(self, arm, Q):
        return Check(Q[:, 3] > -1.0, armik.Status.JOINT_LIMITS, lambda i: "elbow below -1")


def _gen(items):
    return (item for item in items)


ROUTES = {
    "solve": lambda a, T, **kw: [a.solve(T, q0=Q_BENT, **kw)],
    "solve dls": lambda a, T, **kw: [a.solve(T, q0=Q_BENT, solver="dls", **kw)],
    "solve prefer": lambda a, T, **kw: [a.solve(T, q0=Q_BENT, prefer="manipulability", **kw)],
    "solve_all": lambda a, T, **kw: list(a.solve_all(T, q0=Q_BENT, **kw)),
    "solve_batch": lambda a, T, **kw: list(a.solve_batch([T, T], q0=Q_BENT, workers=1, **kw)),
    "solve_path": lambda a, T, **kw: list(a.solve_path([T, T], Q_BENT, **kw)),
}


@pytest.mark.parametrize("route", list(ROUTES))
@pytest.mark.parametrize("spell", [iter, _gen], ids=["iter", "generator"])
def test_a_constraint_given_as_an_iterator_holds_as_the_list_does(route, spell):
    panda = bundled("panda")
    T = panda.fk(Q_BENT)
    results = ROUTES[route](panda, T, constraints=spell([ElbowUp()]))
    assert results
    for r in results:
        assert not r.success or r.q[3] > -1.0, (route, r.q, r.reason)
    listed = ROUTES[route](panda, T, constraints=[ElbowUp()])
    assert [r.success for r in results] == [r.success for r in listed]


def test_held_joints_and_obstacles_given_as_iterators_hold():
    panda = bundled("panda")
    T = panda.fk(Q_BENT)
    r = panda.solve(T, q0=Q_BENT, constraints=iter([armik.Hold("panda_joint7", 0.0)]))
    assert not r.success or abs(r.q[6]) < 1e-9, r.q
    ball = armik.Sphere(0.1, panda.fk(Q_BENT, "panda_link4").translation)
    for r in [
        panda.solve(T, q0=Q_BENT, constraints=iter([armik.Collisions([ball])])),
        panda.solve(T, q0=Q_BENT, obstacles=iter([ball])),
        *panda.solve_path([T, T], Q_BENT, obstacles=iter([ball])),
    ]:
        assert not (r.success and panda.in_collision(r.q, [ball])), r.reason
