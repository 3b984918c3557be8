"""An elbow stretched or folded onto a joint limit: of the two roots rounding splits the
double root into (both exact), the closed forms keep the one within the limits nearest q0
(``sixr.elbow_side``), so that solve from q0 = q gives q back."""

from __future__ import annotations

import math

import numpy as np
import pytest

from armik.solvers.closed_form import sixr
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


def test_elbow_side_takes_the_mirror_only_for_the_limits_or_q0():
    p1, p2, k = (0.4, 0.1, 0.0), (-0.3, 0.2, 0.05), (0.0, 0.0, 1.0)
    e = elbow_extreme(p1, p2, k, 0.3)
    t = 1e-5

    def span(a):
        return norm(sub(mv(rot(k, a), p1), p2))

    assert span(e + t) == pytest.approx(span(e - t), abs=1e-15)  # both roots of one span
    # the limit at the extreme, on the mirror's side: the mirror
    assert sixr.elbow_side(p1, p2, k, e + t, e, e - 1.0, e) == pytest.approx(e - t, abs=1e-12)
    # no limit in the way, q0 on the extreme: a tie keeps the root given
    assert sixr.elbow_side(p1, p2, k, e + t, e, -10.0, 10.0) == e + t
    # q0 on the mirror's side: the mirror
    assert sixr.elbow_side(p1, p2, k, e + t, e - 0.5, -10.0, 10.0) == pytest.approx(e - t)
