"""A failure's words give the errors of its best attempt only where the task measures
them: a part not asked was said to be "0", as if reached."""

from __future__ import annotations

import numpy as np
import pytest

from ...conftest import arm


@pytest.mark.parametrize("solver", ["clik", "dls", "qp"])
def test_a_failure_words_only_what_was_asked(solver):
    a = arm("ur5")
    T = a.fk(a.random_q(5))
    few = dict(q0=np.zeros(6), solver=solver, max_iterations=2, max_restarts=0)
    for target, weights, said, unsaid in (
        (T.translation, None, "position error", "orientation error"),
        (T, (1, 1, 1, 0, 0, 0), "position error", "orientation error"),
        (T, (0, 0, 0, 1, 1, 1), "orientation error", "position error"),
        (T, None, "orientation error", "no such words"),
    ):
        r = a.solve(target, weights=weights, **few)
        assert not r.success
        assert said in r.reason and unsaid not in r.reason, (weights, r.reason)
