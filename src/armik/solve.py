"""The one path from user input to verified results, shared by every solver."""

from __future__ import annotations

import time

import numpy as np

from .arm import Arm
from .ik import registry
from .ik.attempt import Attempt
from .options import Options
from .result import IKResult
from .status import FAILURE_RANK, Status
from .targets import parse_target
from .verify import Check, check, check_many


def solve(
    arm: Arm,
    target: object,
    *,
    q0: object = None,
    solver: str = "auto",
    all_solutions: bool = False,
    **options: object,
) -> list[IKResult]:
    """Parse, choose a solver, run it, verify every answer, rank: best first."""
    t0 = time.perf_counter()
    opts = _options(options)
    tgt = parse_target(target, arm)
    seed = arm.seed(q0)
    spec = registry.choose(solver, arm, tgt, opts)
    attempts = spec.run(arm, tgt, seed, opts, all_solutions)
    if all_solutions:
        checks = check_many(arm, [a.q for a in attempts], tgt, opts)
        rows = [_verdict(a, c) for a, c in zip(attempts, checks)]
    else:
        rows = _first_verified(arm, attempts, tgt, opts, seed)
    if len(rows) > 1:
        rows.sort(key=lambda r: _rank(r, seed))
    rows = rows if all_solutions else rows[:1]
    elapsed = time.perf_counter() - t0
    for row in rows:
        row["solver"] = spec.name
        row["time"] = elapsed
    return [IKResult._checked(row) for row in rows]


_OPTIONS: dict[tuple, Options] = {}


def _options(kwargs: dict) -> Options:
    """``Options.from_kwargs``, remembered for hashable option values other than ``seed``
    (validation costs a few us, and a loop of solves passes the same options, often with a
    new seed each time)."""
    if not kwargs:
        return Options.from_kwargs(kwargs)
    seed = kwargs.get("seed", 0)
    try:
        # with the types: 1 == True, but validation may accept one and refuse the other
        key = tuple((k, type(v), v) for k, v in kwargs.items() if k != "seed")
        opts = _OPTIONS.get(key)
    except TypeError:  # an unhashable value (a list of weights): validate every time
        return Options.from_kwargs(kwargs)
    if opts is None:
        opts = Options.from_kwargs(kwargs)
        if len(_OPTIONS) > 256:
            _OPTIONS.clear()
        _OPTIONS[key] = opts
    elif opts.seed != seed or type(opts.seed) is not type(seed):
        # the seed's own validation, as Options.from_kwargs does it; then a copy of the
        # remembered options with that seed (copy.copy and the frozen __init__ cost us)
        if type(seed) is int and seed >= 0:
            checked = seed  # what the validation returns for a plain int
        else:
            checked = None if seed is None else Options.from_kwargs({"seed": seed}).seed
        fields = opts.__dict__.copy()
        fields["seed"] = checked
        opts = object.__new__(Options)
        opts.__dict__.update(fields)
    return opts


def _first_verified(arm: Arm, attempts: list[Attempt], target, opts: Options, seed) -> list:
    """Verify candidates nearest-first (within limits, claimed converged, then distance to
    the seed) and stop at the first success: it is the nearest verified answer."""
    if len(attempts) == 1:
        return [_judge(arm, attempts[0], target, opts)]

    def order(a: Attempt) -> tuple:
        return (a.claim is not Status.CONVERGED, not arm.within_limits(a.q), _distance(a.q, seed))

    rows = []
    for attempt in sorted(attempts, key=order):
        rows.append(_judge(arm, attempt, target, opts))
        if rows[-1]["success"]:
            return rows[-1:]
    return rows


def _distance(q: np.ndarray, seed: np.ndarray) -> float:
    d = q - seed
    return float(np.sqrt(d.dot(d)))


def _judge(arm: Arm, attempt: Attempt, target, opts: Options) -> dict:
    return _verdict(attempt, check(arm, attempt.q, target, opts))


def _verdict(attempt: Attempt, c: Check) -> dict:
    """The row of an answer from its check: success only when the check holds."""
    if c.ok:
        status, success = Status.CONVERGED, True
        reason = f"verified by forward kinematics: {c.describe()}"
        if attempt.claim is Status.CONVERGED and attempt.reason:
            reason = f"{attempt.reason}; {reason}"
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
        return (0, _distance(row["q"], seed))
    ori = row["orientation_error"] or 0.0
    return (1, FAILURE_RANK[row["status"]], row["position_error"] + ori)
