"""The numeric search's share of ``prefer=`` (``armik.solve.preferred``): how the budget
splits between ``solve_all``'s answers, the starts near the score's centre
(``near_answers``: q0, or a ``Posture``'s reference, in boxes around it that grow to the
whole range) and the self-motion descents of the best distinct answers (``distinct``)."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator

import numpy as np

from armik import cpu_time
from armik.model.arm_model import ArmModel
from armik.problem.scores import Posture, Score
from armik.result import IKResult

# The numeric search's shares of the budget (``timeout``, or ``iteration_budget``): solve_all
# from q0 and its restarts; the starts near the centre until NEAR_UNTIL of the timeout has
# passed (or the other half of the iterations is spent); the self-motion descents of the
# best answers until DESCENT_UNTIL (``armik.solve.nullspace``).
GATHER = 0.25  # of the timeout (CPU time of the kernel)
GATHER_ITERATIONS = 0.5  # of the iteration budget
NEAR_UNTIL = 0.35
DESCENT_UNTIL = 0.7
NEAR_STARTS = 32  # starts near the centre at most, one descent each (and max_restarts)
NEAR_FIRST = 0.1  # the first box's half-width, a fraction of each joint's half-range
NEAR_GROWTH = 1.1  # each next box this much wider, until it holds the whole range
DESCENTS = 4  # distinct answers moved along the self-motion, best first


def centre(arm: ArmModel, score: Score, q0: np.ndarray) -> np.ndarray:
    """Where the best answer is likely near: a ``Posture``'s reference, else q0."""
    if isinstance(score, Posture) and score.q_ref.size == arm.dof:
        return np.clip(score.q_ref, arm.lower, arm.upper)
    return q0


def near_starts(arm: ArmModel, middle: np.ndarray, rng: np.random.Generator) -> Iterator:
    """Starts drawn uniformly in boxes around ``middle`` (within the limits), the k-th of
    half-width ``NEAR_FIRST * NEAR_GROWTH**k`` times each joint's half-range (pi at most,
    unlimited joints pi): perturbations of growing size, the last ones over the whole
    range (the solver's own restarts cover the range evenly; these search near q0 first,
    where the nearest answer lies)."""
    half = np.minimum((arm.upper - arm.lower) / 2.0, math.pi)
    size = NEAR_FIRST
    while True:
        lo = np.maximum(arm.lower, middle - size * half)
        hi = np.minimum(arm.upper, middle + size * half)
        yield lo + rng.random(arm.dof) * (hi - lo)
        size = min(size * NEAR_GROWTH, 2.0)


def near_answers(
    arm: ArmModel,
    solve_from: Callable[[np.ndarray], IKResult],
    middle: np.ndarray,
    opts,
    clock: float,
) -> list[IKResult]:
    """The verified answers of one descent from each of ``near_starts`` (``solve_from``
    runs it), at most ``NEAR_STARTS`` and ``opts.max_restarts`` of them, until
    ``NEAR_UNTIL`` of the timeout has passed since ``clock`` (the thread's CPU time,
    ``cpu_time.thread_time``, as the budget is), or with an iteration budget
    until the starts have run ``1 - GATHER_ITERATIONS`` of it (deterministic: the starts
    come from ``opts.seed``)."""
    rng = np.random.default_rng(opts.seed)
    budget = opts.iteration_budget
    left = math.inf if budget is None else (1.0 - GATHER_ITERATIONS) * budget
    deadline = clock + NEAR_UNTIL * opts.timeout
    found = []
    starts = near_starts(arm, middle, rng)
    for _ in range(min(NEAR_STARTS, opts.max_restarts)):
        if left <= 0 or (budget is None and cpu_time.thread_time() > deadline):
            break
        r = solve_from(next(starts))
        left -= r.iterations
        if r.success:
            found.append(r)
    return found


def distinct(qs: list[np.ndarray], count: int, tol: float = 1e-3) -> list[np.ndarray]:
    """The first ``count`` of ``qs`` that differ from every earlier one kept by more than
    ``tol`` on some joint (answers a few solver tolerances apart move to the same place)."""
    kept: list[np.ndarray] = []
    for q in qs:
        if len(kept) == count:
            break
        if all(np.abs(q - k).max() > tol for k in kept):
            kept.append(q)
    return kept
