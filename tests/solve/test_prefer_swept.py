"""``prefer=`` with ``solver="swept"`` asked for by name searches joint 7 as "auto" does
(``armik.solve.prefer.sweep_held``): the answer is the swept closed form's, at the value
of joint 7 the search chose, and scores as "auto"'s."""

from __future__ import annotations

import numpy as np
import pytest

from armik.problem.scores import parse_score

from .. import conftest


@pytest.mark.parametrize("case", [4, 7])
def test_swept_by_name_searches_joint_7_for_the_score(case):
    arm = conftest.arm("panda")
    T = arm.fk(arm.random_q(1000 + case))
    q0 = arm.random_q(6000 + case)
    auto = arm.solve(T, q0=q0, prefer="manipulability")
    swept = arm.solve(T, q0=q0, prefer="manipulability", solver="swept")
    assert auto.success and swept.success and swept.solver == "swept"
    assert "closed form with joint 7 held" in swept.reason  # not moved off its value
    own = parse_score("manipulability")(arm.kinematics, swept.q, np.asarray(q0, dtype=float))
    assert swept.score == pytest.approx(own, abs=1e-12)
    assert swept.score <= auto.score + 1e-12
