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
