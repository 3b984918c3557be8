"""A batch solved row by row whose user's cost or check raises at one row names that row."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint

from ..conftest import arm


class Refuses(Constraint):
    """A check that raises on one configuration (a user's bug at one row)."""

    def __init__(self, q: np.ndarray) -> None:
        self.q = q

    def check(self, arm, Q):
        if np.isclose(Q, self.q, atol=1e-6).all(axis=1).any():
            raise ValueError("not this one")
        return Check(np.ones(len(Q), bool), armik.Status.JOINT_LIMITS, lambda i: "")


@pytest.mark.parametrize("run", [{}, {"backend": "threads", "chunk_size": 2}])
def test_a_cost_that_raises_at_one_row_names_it(run):
    a = arm("ur5")
    qs = [a.random_q(k) for k in range(4)]

    def cost(q):
        if np.allclose(q, qs[2], atol=1e-6):  # one of target 2's answers
            raise ValueError("no such pose here")
        return float(q @ q)

    with pytest.raises(armik.OptionError, match=r"^target 2: prefer=cost raised ValueError") as e:
        a.solve_batch([a.fk(q) for q in qs], prefer=cost, **run)
    assert e.value.option == "prefer"  # its class and fields kept


def test_a_check_that_raises_at_one_row_names_it():
    a = arm("ur5")
    qs = [a.random_q(k) for k in range(4)]
    options = {"constraints": [Refuses(qs[3])], "hold": {"wrist_3_joint": None}}
    with pytest.raises(armik.OptionError, match=r"^target 3: constraint Refuses: its check"):
        a.solve_batch([a.fk(q) for q in qs], q0=np.array(qs), **options)


@pytest.mark.parametrize("run", [{"workers": 1}, {"backend": "processes", "workers": 2}])
def test_a_solver_without_a_compiled_batch_names_the_row_too(run):
    # swept solves target by target in every chunk
    a = arm("panda")
    qs = [a.random_q(k) for k in range(4)]
    targets = [a.fk(q) for q in qs]
    answer = a.solve(targets[1], solver="swept").q
    with pytest.raises(armik.OptionError, match=r"^target 1: constraint Refuses: its check"):
        a.solve_batch(targets, solver="swept", constraints=[Refuses(answer)], chunk_size=2, **run)
