"""Each branch's admissible intervals of a 7R arm's self-motion parameter: the swivel angle
of the iiwa, joint 7 of the Panda. Inside an interval ``solve_all`` at that value verifies
an answer on the branch; just outside an edge it does not; the generating configuration's
branch holds at its own value."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.solvers.closed_form.srs import swivel_of

from ..conftest import arm

INWARD = 1e-6  # rad inside an edge: the branch verifies there
# rad past an edge: no longer verified there. Not 1e-6: where an edge is the edge of reach,
# the closed form's least-squares answer just past it misses by the square of the step,
# within the tolerance, and the verdict calls it a success
BEYOND = 1e-2


def _check(a, T, iv, option):
    """Every interval's middle, and each edge from just inside, verifies an answer on its
    branch; past each inner edge, none does."""

    def on_branch(value: float) -> set[str]:
        found = a.solve_all(T, **option(value))
        return {r.branch for r in found if r.success}

    for branch, spans in iv.branches.items():
        assert spans, branch
        for lo, hi in spans:
            assert lo <= hi
            assert branch in on_branch(0.5 * (lo + hi)), (branch, lo, hi)
            if hi - lo > 2 * INWARD:
                assert branch in on_branch(lo + INWARD) and branch in on_branch(hi - INWARD)
            for out in (lo - BEYOND, hi + BEYOND):
                past = not any(
                    a0 - BEYOND <= out <= b0 + BEYOND for a0, b0 in spans if b0 < lo or a0 > hi
                )
                if past and iv.low < out < iv.high:
                    assert branch not in on_branch(out), (branch, lo, hi, out)


def test_the_iiwa_swivel_intervals_hold_where_solve_all_says():
    a = arm("kuka_iiwa14")
    rng = np.random.default_rng(4)
    for _ in range(2):
        q = a.random_q(rng)
        T = a.fk(q)
        iv = a.intervals(T, "swivel")
        assert iv.over == "swivel" and iv.solver == "srs"
        psi = swivel_of(a.kinematics, q)
        mine = {
            r.branch
            for r in a.solve_all(T, swivel=psi)
            if r.success and np.allclose(r.q, q, atol=1e-6)
        }
        assert mine and mine <= set(iv.at(psi))  # the generating branch holds at its angle
        _check(a, T, iv, lambda v: {"swivel": v})


def test_the_panda_joint_7_intervals_hold_where_solve_all_says():
    a = arm("panda")
    q = a.middle + 0.2
    T = a.fk(q)
    iv = a.intervals(T, "panda_joint7")
    assert iv.over == "panda_joint7" and iv.solver == "swept"
    assert set(iv.at(q[6]))
    _check(a, T, iv, lambda v: {"hold": {"panda_joint7": v}})


def test_a_parameter_no_closed_form_answers_at_is_refused_with_the_choices():
    a = arm("panda")
    T = a.fk(a.middle)
    with pytest.raises(armik.OptionError, match="it can be swept over: 'panda_joint7'"):
        a.intervals(T, "swivel")
    with pytest.raises(armik.OptionError, match="panda_joint7"):
        a.intervals(T, "panda_joint1")


@pytest.mark.parametrize("over", [None, 6, ("swivel",)])
def test_a_parameter_that_is_no_name_is_refused(over):
    """``over`` names an option or a joint: None matched any declared option and gave the
    iiwa's swivel intervals labelled None; it is refused, naming the value."""
    a = arm("kuka_iiwa14")
    T = a.fk(np.array([0.3, -0.8, 0.5, 1.2, -0.4, 0.9, 0.2]))
    with pytest.raises(armik.OptionError, match="over must be the name") as got:
        a.intervals(T, over)
    assert repr(over) in str(got.value)
