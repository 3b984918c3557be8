"""An elbow stretched or folded at a joint limit: of the two roots rounding splits the
double root into (both exact), the closed forms keep, branch by branch, the row with fewer
joints outside the limits, then with the elbow nearer q0's (``elbow_pair.mirror_root``,
``elbow_pair.keep_nearer``), so that solve from q0 = q gives q back."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armik.solvers.closed_form import elbow_pair
from armik.solvers.closed_form.subproblems import elbow_extreme, mv, norm, rot, sub

from ...conftest import arm


def far_or_failed(a, configurations) -> list:
    """The configurations q whose target ``solve`` from q0 = q fails or answers more than
    1e-3 rad from q (the elbow's rounding at the fold moves it by about 1e-5)."""
    bad = []
    for q in configurations:
        r = a.solve(a.fk(q), q0=q)
        if not r.success or np.max(np.abs(r.q - q)) > 1e-3:
            bad.append((q.tolist(), r.success, r.q.tolist()))
    return bad


@pytest.mark.parametrize("name", ["ur5", "ur10"])
def test_folded_onto_its_limit_with_the_wrist_singular(name):
    # elbow_joint at pi (its limit), wrist_2 at 0: the merged elbow root was the one just
    # past -pi, whose turn near pi lies past the limit, and solve answered another branch
    a = arm(name)
    rng = np.random.default_rng(0)
    qs = []
    for _ in range(30):
        q = a.random_q(rng)
        q[2], q[4] = math.pi, 0.0
        qs.append(q)
    assert far_or_failed(a, qs) == []


@pytest.mark.parametrize("wrist", [None, 0.0])
def test_stretched_onto_a_one_sided_limit(wrist):
    # an elbow that bends one way only, stretched onto that limit: the root kept was just
    # below 0, so solve answered another branch or failed a reachable target
    a = arm("ur5").with_limits({"elbow_joint": (0.0, math.pi)})
    rng = np.random.default_rng(1)
    qs = []
    for _ in range(30):
        q = a.random_q(rng)
        q[2] = 0.0
        if wrist is not None:
            q[4] = wrist
        qs.append(q)
    assert far_or_failed(a, qs) == []


def test_kinova_stretched_with_a_joint_on_its_limit():
    # joint 3 at pi stretches the JACO 2's elbow; the root kept moved joint 2 or 5 on their
    # lower limits 1e-7 rad past them (joint_limits), and solve answered another branch
    a = arm("kinova")
    rng = np.random.default_rng(2)
    qs = []
    for k in range(30):
        q = a.random_q(rng)
        q[2] = math.pi
        q[1 if k % 2 else 4] = a.lower[1 if k % 2 else 4]
        qs.append(q)
    assert far_or_failed(a, qs) == []


def test_mirror_root_and_keep_nearer():
    p1, p2, k = (0.4, 0.1, 0.0), (-0.3, 0.2, 0.05), (0.0, 0.0, 1.0)
    e = elbow_extreme(p1, p2, k, 0.3)
    t = 1e-5

    def span(a):
        return norm(sub(mv(rot(k, a), p1), p2))

    assert elbow_pair.mirror_root(p1, p2, k, e + t) == pytest.approx(e - t, abs=1e-12)
    assert span(e + t) == pytest.approx(span(e - t), abs=1e-15)  # both roots of one span
    assert elbow_pair.mirror_root(p1, p2, k, e) == e
    q0 = np.array([0.0, 0.5, e, 0.0, 0.0, 0.0])
    lower, upper = np.full(6, -3.0), np.full(6, 3.0)
    W = np.zeros((2, 11))
    W[0, :6] = [0.0, 0.5 - 3e-7, e + t, 0.0, 0.0, 0.0]
    W[1, :6] = [0.0, 0.5 + 3e-7, e - t, 0.0, 0.0, 0.0]
    W[1, 6] = 7.0  # the row's other columns come with it
    # joint 2's lower limit at q0's value: the first row lies 3e-7 past it (beyond
    # sixr.SNAP), the second kept
    lower[1] = 0.5
    assert elbow_pair.keep_nearer(W, 0, 1, 2, q0, lower, upper) == 1
    assert W[0, 1] == 0.5 + 3e-7 and W[0, 6] == 7.0
    # both within the limits, as near q0 (to TIE): the first kept
    W[0, :7] = [0.0, 0.5 + 1e-7, e + t, 0.0, 0.0, 0.0, 0.0]
    W[1, :7] = [0.0, 0.5 + 1e-7, e - t, 0.0, 0.0, 0.0, 7.0]
    assert elbow_pair.keep_nearer(W, 0, 1, 2, q0, np.full(6, -3.0), upper) == 1
    assert W[0, 6] == 0.0
    # counts that differ: the first rows kept as they are
    assert elbow_pair.keep_nearer(W, 0, 1, 1, q0, lower, upper) == 1


def test_elbow_roots():
    p1, p2, k = (0.4, 0.1, 0.0), (-0.3, 0.2, 0.05), (0.0, 0.0, 1.0)
    e = elbow_extreme(p1, p2, k, 0.3)
    t = 1e-5

    def span(a):
        return norm(sub(mv(rot(k, a), p1), p2))

    # a span a hair short of the extreme: one root (subproblems.elbow merges them), its
    # mirror solved too
    c0, c1, n, ls, roots = elbow_pair.elbow_roots(p1, p2, k, span(e + t), 9.0)
    assert (n, ls, roots) == (1, False, 2)
    assert sorted([c0, c1]) == pytest.approx([e - t, e + t], abs=1e-9)
    # regular roots as they are; every turn spans it: one root, the free value's
    c0, c1, n, ls, roots = elbow_pair.elbow_roots(p1, p2, k, span(e + 0.5), 9.0)
    assert (n, roots) == (2, 2)
    c0, c1, n, ls, roots = elbow_pair.elbow_roots(p1, (0.0, 0.0, 0.0), k, norm(p1), 9.0)
    assert (c0, n, roots) == (9.0, -1, 1)
