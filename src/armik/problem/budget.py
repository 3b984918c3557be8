"""A solve's budget: what it may spend before it answers with the best it has.

``armik.Budget(timeout=0.01)`` (CPU seconds of the solving thread),
``armik.Budget(iterations=500)`` (a count instead of a time: the same seeded call gives the
same answer on every machine), ``restarts`` (random restarts after the first attempt) and
``per_attempt`` (iterations of one attempt) is the option ``budget=``. The old keywords
spell the same budget (``timeout``, ``iteration_budget``, ``max_restarts``,
``max_iterations``), and ``Options.budget`` gives it back with every field filled.

A filled budget also keeps the accounts of a solve that spends it over several runs (the
collision retry, the task solver's descents): ``left`` is what remains for the next run,
``spent`` whether anything does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import cast

from armik import cpu_time
from armik.checked import integer, positive
from armik.frozen import frozen
from armik.tolerances import MAX_COUNT, MAX_TIMEOUT

# Budget's fields and the options that spell them
OPTION_OF = {
    "timeout": "timeout",
    "iterations": "iteration_budget",
    "restarts": "max_restarts",
    "per_attempt": "max_iterations",
}


@dataclass(frozen=True)
class Budget:
    """What a solve may spend; None: the default (0.05 s, no count, 1000 restarts, 100
    iterations an attempt). With ``iterations``, ``timeout`` is not used."""

    timeout: float | None = None
    iterations: int | None = None
    restarts: int | None = None
    per_attempt: int | None = None

    def __post_init__(self) -> None:
        if self.timeout is not None:
            timeout = positive("Budget timeout", self.timeout, MAX_TIMEOUT, "s")
            object.__setattr__(self, "timeout", timeout)
        for name, least in (("iterations", 1), ("restarts", 0), ("per_attempt", 1)):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, integer(f"Budget {name}", value, least, MAX_COUNT))

    def said(self) -> dict[str, object]:
        """The budget as the options that spell it (its fields that are given)."""
        return {OPTION_OF[k]: v for k, v in self.__dict__.items() if v is not None}

    # The accounts, on a filled budget (``Options.budget``).

    @property
    def counted(self) -> bool:
        """Whether the budget counts iterations rather than time."""
        return self.iterations is not None

    def time_left(self, started: float) -> float:
        """CPU seconds left of the timeout since ``started`` (``cpu_time.thread_time``); inf
        when the budget counts iterations."""
        if self.iterations is not None:
            return math.inf
        return self.timeout - (cpu_time.thread_time() - started)  # type: ignore[operator]

    def spent(self, started: float, used: int) -> bool:
        """Whether nothing is left after ``used`` iterations since ``started``."""
        if self.iterations is not None:
            return used >= self.iterations
        return self.time_left(started) <= 0.0

    def attempt(self, used: int) -> int:
        """The iterations the next attempt may take after ``used`` of them."""
        per_attempt = cast(int, self.per_attempt)
        return per_attempt if self.iterations is None else min(per_attempt, self.iterations - used)

    def may_restart(self, restarts: int) -> bool:
        """Whether another restart is left after ``restarts`` of them."""
        return restarts < cast(int, self.restarts)

    def left(self, started: float, used: int, restarts: int) -> Budget | None:
        """The budget of the next run after ``used`` iterations and ``restarts`` restarts
        since ``started``; None when nothing is left."""
        if self.spent(started, used):
            return None
        if self.iterations is not None:
            timeout, iterations = self.timeout, self.iterations - used
        else:
            timeout, iterations = self.time_left(started), None
        return frozen(
            Budget,
            timeout=timeout,
            iterations=iterations,
            restarts=max(cast(int, self.restarts) - restarts, 0),
            per_attempt=self.per_attempt,
        )


#: The budget of a solve that says none (``Options``' defaults).
DEFAULT = Budget(timeout=0.05, restarts=1000, per_attempt=100)
