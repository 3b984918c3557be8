"""The verdict every answer gets: from a solver's claims and their measures to ranked,
verified results. Success only when the measure holds, whatever the solver claimed.

Single solves (``finish``), prepared solves (``armik.solve.prepared``, through
``claimed_verdict``, ``verdict`` and ``failure_rank``) and batches (``verdict_batch``) all
decide here by one ``RULE`` (``status_of`` one answer, ``status_codes`` N), in the words of
``armik.reasons``.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING

import numpy as np

from armik import reasons
from armik.batch_result import BatchResult
from armik.result import IKResult
from armik.solvers.answers import Answers
from armik.solvers.claims import Claim
from armik.status import FAILURE_RANK, Status
from armik.verify.measure import Measure, measure, measure_batch, measure_many

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel
    from armik.options import Options
    from armik.targets.batch import TargetBatch

_CONVERGED = Status.CONVERGED.code
_NOT_CONVERGED = Status.NOT_CONVERGED.code
_JOINT_LIMITS = Status.JOINT_LIMITS.code

# The verdict's one rule, for one answer and for N, indexed [claimed converged, measure
# holds, within the limits]: a measure that holds is a success whatever the solver
# claimed; a claimed success the measure refutes is joint_limits outside the limits, else
# not_converged; any other claim stands (-1).
RULE = np.full((2, 2, 2), -1, dtype=np.int8)
RULE[:, 1, :] = _CONVERGED
RULE[1, 0, 0] = _JOINT_LIMITS
RULE[1, 0, 1] = _NOT_CONVERGED
# one answer: nested lists of statuses (None: the claim stands), indexed without a call
_DECIDED = [[[None if c < 0 else Status.from_code(c) for c in w] for w in o] for o in RULE.tolist()]


def status_of(claim: Status, ok: bool, within: bool) -> Status:
    """The status ``RULE`` gives one answer."""
    decided = _DECIDED[claim is Status.CONVERGED][1 if ok else 0][1 if within else 0]
    return claim if decided is None else decided


def status_codes(claim: np.ndarray, ok: np.ndarray, within: np.ndarray) -> np.ndarray:
    """The status codes ``RULE`` gives N answers (int8 claims, bool measures)."""
    claim = np.asarray(claim, dtype=np.int8)
    code = RULE[_index(claim == _CONVERGED), _index(ok), _index(within)]
    return np.where(code < 0, claim, code).astype(np.int8)


def _index(flags: np.ndarray) -> np.ndarray:
    """Booleans as 0/1 indices (a view where they are booleans already)."""
    return np.asarray(flags, dtype=np.bool_).view(np.int8)


def finish(
    arm: ArmModel,
    solver: str,
    answers: Answers,
    target,
    opts: Options,
    seed: np.ndarray,
    all_solutions: bool,
    t0: float,
) -> list[IKResult]:
    """Verify ``answers`` (all of them, or nearest-first up to the first success), rank
    them best first and build the results; ``t0`` is the call's ``perf_counter`` start."""
    if all_solutions:
        rows = verdicts(arm, answers, target, opts)
    else:
        rows = _first_verified(arm, answers, target, opts, seed)
    return ranked(rows, solver, seed, all_solutions, t0)


def verdicts(arm: ArmModel, answers: Answers, target, opts: Options) -> list[dict]:
    """The verdict row of every answer, measured together (``measure_many``)."""
    measures = measure_many(arm, list(answers.q), target, opts)
    return [verdict(answers, i, m) for i, m in enumerate(measures)]


def ranked(rows: list[dict], solver: str, seed, all_solutions: bool, t0: float):
    """The results of verdict rows, best first (the first only unless ``all_solutions``)."""
    if len(rows) > 1:
        rows.sort(key=lambda r: _rank(r, seed))
    rows = rows if all_solutions else rows[:1]
    if all_solutions:
        number_repeated_branches(rows)
    elapsed = time.perf_counter() - t0
    for row in rows:
        row["solver"] = solver
        row["time"] = elapsed
    return [IKResult._checked(row) for row in rows]


def number_repeated_branches(rows: list[dict]) -> None:
    """Make the branch labels of ``solve_all``'s rows distinct, in their order: a label
    met again gets "#2", "#3" (a search family has up to 16 solutions and 8 labels)."""
    labels = [row.get("branch") for row in rows]
    if len(set(labels)) == len(labels):  # distinct already: the closed forms' usual case
        return
    seen: dict[str, int] = {}
    for row, label in zip(rows, labels):
        if label is None:
            continue
        count = seen.get(label, 0) + 1
        seen[label] = count
        if count > 1:
            row["branch"] = f"{label}#{count}"


def _first_verified(arm: ArmModel, answers: Answers, target, opts: Options, seed) -> list:
    """Verify answers nearest-first (``nearest_first``) and stop at the first success: it
    is the nearest verified answer."""
    if len(answers) == 1:
        return [verdict(answers, 0, measure(arm, answers.q[0], target, opts))]
    rows = []
    for i in nearest_first(arm, answers, seed):
        rows.append(verdict(answers, i, measure(arm, answers.q[i], target, opts)))
        if rows[-1]["success"]:
            return rows[-1:]
    return rows


def nearest_first(arm: ArmModel, answers: Answers, seed: np.ndarray) -> list[int]:
    """The rows in the order they are verified for one answer: claimed converged, within
    the limits, then by distance to the seed (ties: the solver's order)."""
    q = answers.q
    return sorted(
        range(len(answers)),
        key=lambda i: (
            not answers.claimed(i),
            not arm.within_limits(q[i]),
            seed_distance(q[i], seed),
        ),
    )


def seed_distance(q: np.ndarray, seed: np.ndarray) -> float:
    d = q - seed
    return float(np.sqrt(d.dot(d)))


def success_reason(claim_reason, claim_args, pos, ori, tol_p, tol_r, region=False) -> str:
    """The reason of a success from its parts: the claim's reason is ``claim_reason``
    itself, or ``claim_reason(*claim_args)`` when it is a function (results of prepared
    solves write their reason on first read, see ``IKResult``); ``region``: the errors are
    the distances outside the target's region."""
    if callable(claim_reason):
        claim_reason = claim_reason(*claim_args)
    text = reasons.measured(pos, ori, tol_p, tol_r)
    return reasons.verified(claim_reason, reasons.outside_region(text) if region else text)


def limits_reason(arm: ArmModel, q: np.ndarray) -> str:
    """The reason of a claimed answer outside the joint limits."""
    return reasons.outside_limits(arm.limit_violations(q))


def verdict(answers: Answers, i: int, m: Measure) -> dict:
    """The row of answer ``i`` from its measure: success only when the measure holds."""
    claim = answers.status(i)
    claimed = claim is Status.CONVERGED
    status = status_of(claim, m.ok, not m.violations)
    success = status is Status.CONVERGED
    if success:
        reason = reasons.verified(answers.reason(i) if claimed else None, m.describe())
    elif not claimed:
        reason = answers.reason(i)
    elif status is Status.JOINT_LIMITS:
        reason = reasons.outside_limits(m.violations)
    else:
        reason = reasons.check_failed(m.describe())
    return dict(
        q=answers.q[i],
        success=success,
        status=status,
        reason=reason,
        iterations=int(answers.iterations[i]),
        position_error=m.position_error,
        orientation_error=m.orientation_error,
        branch=answers.label(i),
        singular=answers.is_singular(i),
        restarts=int(answers.restarts[i]),
    )


def claimed_verdict(
    arm: ArmModel,
    got: Claim,
    pos: float,
    ori: float | None,
    inside: bool,
    tol_p: float,
    tol_r: float,
    region: bool = False,
) -> dict | None:
    """``verdict`` of a prepared runner's claimed answer ``got`` from its measure (``ori``
    None where the orientation is not measured; ``inside``: within the limits; ``region``:
    the errors are the distances outside the target's region),
    without building the ``Answers`` and ``Measure``: a success within the tolerances and
    the limits, ``joint_limits`` outside the limits, else None (the general ``verdict``
    decides: ``check_failed``'s reason needs the target's region). The fields of an
    ``IKResult`` but ``solver`` and ``time``; the reason written on first read."""
    ok = inside and pos <= tol_p and (ori is None or ori <= tol_r)
    status = _DECIDED[1][1 if ok else 0][1 if inside else 0]  # status_of a claimed answer
    if status is Status.JOINT_LIMITS:
        return _claimed(got, False, status, pos, ori, limits_reason, (arm, got.q))
    if status is Status.CONVERGED:
        why = (got.reason, got.reason_args, pos, ori, tol_p, tol_r, region)
        return _claimed(got, True, status, pos, ori, success_reason, why)
    return None


def _claimed(got: Claim, success: bool, status: Status, pos, ori, reason, args) -> dict:
    q = got.q
    if q.flags.writeable:  # the runner's own array (solve_all's rows are read-only)
        q.setflags(write=False)
    return dict(
        q=q,
        success=success,
        status=status,
        iterations=got.iterations,
        position_error=pos,
        orientation_error=ori,
        branch=got.branch,
        singular=got.singular,
        restarts=got.restarts,
        _reason=(reason, args),
    )


def failure_rank(status: Status, position_error: float, orientation_error) -> tuple:
    """How failed results are ranked among themselves: by status, then by their errors."""
    return (FAILURE_RANK[status], position_error + (orientation_error or 0.0))


def _rank(row: dict, seed: np.ndarray) -> tuple:
    if row["success"]:
        return (0, seed_distance(row["q"], seed))
    return (1, *failure_rank(row["status"], row["position_error"], row["orientation_error"]))


def verdict_batch(
    arm: ArmModel, answers: Answers, targets: TargetBatch, opts: Options
) -> BatchResult:
    """The verdict of a chunk of answers (one a target), by the ``RULE`` that decides one
    (``verdict``); the rare failures get their reasons row by row."""
    n = len(targets)
    part = BatchResult.empty(n, arm.dof, solver="", time=0.0)
    part.q[:] = answers.q
    part.iterations[:] = answers.iterations
    part.restarts[:] = answers.restarts
    claim = np.asarray(answers.claim, dtype=np.int8)
    m = measure_batch(arm, part.q, targets, opts)
    part.position_error[:] = m.position_error
    part.orientation_error[:] = m.orientation_error
    ok = m.ok
    claimed = claim == _CONVERGED
    part.success[:] = ok
    part.status_code[:] = status_codes(claim, ok, m.within_limits)
    for i in np.flatnonzero(~ok).tolist():  # the rare failures get their reasons
        errors = reasons.measured(
            part.position_error[i],
            part.orientation_error[i],
            opts.tol_position,
            opts.tol_orientation,
        )
        if claimed[i] and not m.within_limits[i]:
            part.reasons[i] = limits_reason(arm, part.q[i])
        elif claimed[i]:
            part.reasons[i] = reasons.check_failed(errors)
        elif claim[i] == Status.UNREACHABLE.code:
            distance = math.dist(targets.positions[i].tolist(), arm.first_joint_origin.tolist())
            part.reasons[i] = reasons.unreachable(distance, arm.reach)
        elif claim[i] == Status.NOT_CONVERGED.code:
            restarts = f"at most {opts.max_restarts} restarts"
            why = reasons.budget(opts.timeout, opts.iteration_budget, restarts)
            part.reasons[i] = reasons.not_converged(why, errors)
        else:
            part.reasons[i] = reasons.claimed(Status.from_code(claim[i]).value, errors)
    return part
