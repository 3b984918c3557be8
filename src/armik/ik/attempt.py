"""What a solver hands back before verification."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..status import Status


@dataclass(frozen=True, kw_only=True)
class Attempt:
    """A candidate answer. ``claim`` is the solver's own status; verification decides."""

    q: np.ndarray
    claim: Status
    reason: str
    iterations: int = 0
    branch: str | None = None
    singular: bool = False
    restarts: int = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "claim", Status.parse(self.claim))


@dataclass(frozen=True, kw_only=True)
class AttemptBatch:
    """Candidate answers for N targets as arrays, one row per target, before verification.

    ``claim`` holds ``Status.code`` values. A solver that can run many targets without a
    Python call per target (the compiled numeric core) hands these back from
    ``SolverSpec.run_batch``.
    """

    q: np.ndarray  # (N, dof) joint values, rad or m
    claim: np.ndarray  # (N,) int8 Status codes
    iterations: np.ndarray  # (N,) int
    restarts: np.ndarray  # (N,) int
