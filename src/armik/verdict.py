"""From a solver's attempts to ranked, verified results: the verdict every answer gets.

The check (``verify.py``) measures an answer; the verdict turns the measure and the
solver's claim into a status and a reason: success only when the check holds, whatever the
solver claimed. ``solve.py`` (the general path) and ``plan.py`` (prepared solves of plain
poses) both end here.
"""

from __future__ import annotations

import time

import numpy as np

from .arm import Arm
from .ik.attempt import Attempt
from .options import Options
from .result import IKResult
from .status import FAILURE_RANK, Status
from .verify import Check, check, check_many, describe


def finish(
    arm: Arm,
    solver: str,
    attempts: list[Attempt],
    target,
    opts: Options,
    seed: np.ndarray,
    all_solutions: bool,
    t0: float,
) -> list[IKResult]:
    """Verify ``attempts`` (all of them, or nearest-first up to the first success), rank
    them best first and build the results; ``t0`` is the call's ``perf_counter`` start."""
    if all_solutions:
        checks = check_many(arm, [a.q for a in attempts], target, opts)
        rows = [verdict(a, c) for a, c in zip(attempts, checks)]
    else:
        rows = _first_verified(arm, attempts, target, opts, seed)
    return ranked(rows, solver, seed, all_solutions, t0)


def ranked(rows: list[dict], solver: str, seed, all_solutions: bool, t0: float):
    """The results of verdict rows, best first (the first only unless ``all_solutions``)."""
    if len(rows) > 1:
        rows.sort(key=lambda r: _rank(r, seed))
    rows = rows if all_solutions else rows[:1]
    elapsed = time.perf_counter() - t0
    for row in rows:
        row["solver"] = solver
        row["time"] = elapsed
    return [IKResult._checked(row) for row in rows]


def _first_verified(arm: Arm, attempts: list[Attempt], target, opts: Options, seed) -> list:
    """Verify candidates nearest-first (within limits, claimed converged, then distance to
    the seed) and stop at the first success: it is the nearest verified answer."""
    if len(attempts) == 1:
        return [verdict(attempts[0], check(arm, attempts[0].q, target, opts))]

    def order(a: Attempt) -> tuple:
        return (
            a.claim is not Status.CONVERGED,
            not arm.within_limits(a.q),
            seed_distance(a.q, seed),
        )

    rows = []
    for attempt in sorted(attempts, key=order):
        rows.append(verdict(attempt, check(arm, attempt.q, target, opts)))
        if rows[-1]["success"]:
            return rows[-1:]
    return rows


def seed_distance(q: np.ndarray, seed: np.ndarray) -> float:
    d = q - seed
    return float(np.sqrt(d.dot(d)))


def verified_reason(claim_reason: str | None, check_text: str) -> str:
    """The reason of a success: the solver's own words, then the check's measure."""
    reason = f"verified by forward kinematics: {check_text}"
    return f"{claim_reason}; {reason}" if claim_reason else reason


def success_reason(claim_reason, claim_args, pos, ori, tol_p, tol_r) -> str:
    """``verified_reason`` from its parts: the claim's reason is ``claim_reason`` itself,
    or ``claim_reason(*claim_args)`` when it is a function (results built by ``plan.py``
    write their reason on first read, see ``IKResult``)."""
    if callable(claim_reason):
        claim_reason = claim_reason(*claim_args)
    return verified_reason(claim_reason, describe(pos, ori, tol_p, tol_r))


def verdict(attempt: Attempt, c: Check) -> dict:
    """The row of an answer from its check: success only when the check holds."""
    if c.ok:
        status, success = Status.CONVERGED, True
        claim = attempt.reason if attempt.claim is Status.CONVERGED else None
        reason = verified_reason(claim, c.describe())
    elif attempt.claim is Status.CONVERGED:
        success = False
        if c.violations:
            status = Status.JOINT_LIMITS
            reason = "outside the joint limits: " + "; ".join(c.violations)
        else:
            status = Status.NOT_CONVERGED
            reason = f"forward-kinematics check failed: {c.describe()}"
    else:
        status, success, reason = attempt.claim, False, attempt.reason
    return dict(
        q=attempt.q,
        success=success,
        status=status,
        reason=reason,
        iterations=attempt.iterations,
        position_error=c.position_error,
        orientation_error=c.orientation_error,
        branch=attempt.branch,
        singular=attempt.singular,
        restarts=attempt.restarts,
    )


def _rank(row: dict, seed: np.ndarray) -> tuple:
    if row["success"]:
        return (0, seed_distance(row["q"], seed))
    ori = row["orientation_error"] or 0.0
    return (1, FAILURE_RANK[row["status"]], row["position_error"] + ori)
