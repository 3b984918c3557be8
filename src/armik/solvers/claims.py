"""A prepared solve's answer claimed converged (``Claim``): the one-row case of
``armik.solvers.answers.Answers`` kept on plain floats, its reason written only when read
(a solve makes one, and a solve's budget is counted in Python calls)."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import NamedTuple

import numpy as np

from armik.solvers.answers import Answers, one
from armik.status import Status


class Claim(NamedTuple):
    """A prepared solve's answer claimed converged (``SolverSpec.prepare_pose``'s runners):
    what the verdict needs, and the claim's reason as ``reason(*reason_args)``, written only
    when a result's reason is read. Build it with ``claim`` in a solver's inner path."""

    q: np.ndarray
    iterations: int
    restarts: int
    branch: str | None
    singular: bool
    reason: Callable[..., str]
    reason_args: tuple

    def answers(self) -> Answers:
        """This claim as one row, for the general verdict."""
        return one(
            self.q,
            Status.CONVERGED,
            self.reason(*self.reason_args),
            iterations=self.iterations,
            restarts=self.restarts,
            branch=self.branch,
            singular=self.singular,
        )


# ``claim((q, iterations, restarts, branch, singular, reason, reason_args))``: the Claim of
# that tuple, at a fifth of the cost of the generated ``Claim(...)`` (a solve makes one)
claim = partial(tuple.__new__, Claim)
