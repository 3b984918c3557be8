"""What a solver hands back before verification: an ``Attempt`` (one candidate and the
solver's own status), an ``AttemptBatch`` (N of them as arrays) and a ``Claim`` (a prepared
solve's answer claimed converged, its reason written only when read)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING, dataclass, fields
from functools import partial
from typing import Any, NamedTuple

import numpy as np

from armik.frozen import frozen
from armik.status import Status


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

    def attempt(self) -> Attempt:
        """The ``Attempt`` of this claim, for the general verdict."""
        return Attempt(
            q=self.q,
            claim=Status.CONVERGED,
            reason=self.reason(*self.reason_args),
            iterations=self.iterations,
            branch=self.branch,
            singular=self.singular,
            restarts=self.restarts,
        )


# ``claim((q, iterations, restarts, branch, singular, reason, reason_args))``: the Claim of
# that tuple, at a fifth of the cost of the generated ``Claim(...)`` (a solve makes one)
claim = partial(tuple.__new__, Claim)


_ATTEMPT_DEFAULTS = {
    f.name: f.default for f in fields(Attempt) if f.default is not MISSING and f.init
}
_ATTEMPT_NAMES = frozenset(f.name for f in fields(Attempt))


def attempt(**row: Any) -> Attempt:
    """``Attempt(**row)``, built without the generated frozen ``__init__`` (a setattr per
    field, a microsecond per solve) when ``claim`` is a ``Status`` and every field without
    a default is given: the object that ``Attempt(**row)`` builds."""
    d = {**_ATTEMPT_DEFAULTS, **row}
    if type(row.get("claim")) is not Status or d.keys() != _ATTEMPT_NAMES:
        return Attempt(**row)  # a field unknown or missing: the dataclass says which
    return frozen(Attempt, **d)


_BRANCH, _SINGULAR = _ATTEMPT_DEFAULTS["branch"], _ATTEMPT_DEFAULTS["singular"]


def converged_attempt(q: np.ndarray, iterations: int, restarts: int, reason: str) -> Attempt:
    """``attempt(q=q, claim=Status.CONVERGED, iterations=iterations, restarts=restarts,
    reason=reason)``, its fields written directly (the success path of every solve)."""
    return frozen(
        Attempt,
        q=q,
        claim=_STATUS_CONVERGED,
        reason=reason,
        iterations=iterations,
        branch=_BRANCH,
        singular=_SINGULAR,
        restarts=restarts,
    )


_STATUS_CONVERGED = Status.CONVERGED
