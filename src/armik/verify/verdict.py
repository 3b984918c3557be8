"""The verdict every answer gets: from a solver's claims and their measures to ranked,
verified results. Success only when the measure holds, whatever the solver claimed.

N answers and their measure become ``Verdicts`` (``decide``) by one ``RULE``, in the words
of ``armik.reasons``: single solves (``finish``), batches (``verdict_batch``) and the
prepared solves' answers the compiled measure does not decide alone. A prepared solve's
claimed answer is the one-row case on plain floats (``claimed_verdict``).
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING

import numpy as np

from armik import reasons
from armik.batch_result import BatchResult
from armik.constraints.base import satisfied
from armik.constraints.limits import on_limits
from armik.frozen import frozen
from armik.result import IKResult
from armik.solvers.answers import Answers
from armik.solvers.claims import Claim
from armik.status import Status
from armik.tolerances import LIMIT_TOL
from armik.verify.distances import batch_distances, with_distances
from armik.verify.measure import BatchMeasure, Measure, measure, measure_batch, measure_many
from armik.verify.verdicts import Verdicts, tied

if TYPE_CHECKING:
    from armik.constraints.base import Constraint
    from armik.model.arm_model import ArmModel
    from armik.problem.settings import SolverSettings
    from armik.targets.batch import TargetBatch

_CONVERGED = Status.CONVERGED.code
_NOT_CONVERGED = Status.NOT_CONVERGED.code
_JOINT_LIMITS = Status.JOINT_LIMITS.code
_UNREACHABLE = Status.UNREACHABLE.code

# The verdict's one rule, for one answer and for N, indexed [claimed converged, measure
# holds, within the limits]: a measure that holds is a success whatever the solver
# claimed; a claimed success the measure refutes is joint_limits outside the limits, else
# not_converged; any other claim stands (-1).
RULE = np.full((2, 2, 2), -1, dtype=np.int8)
RULE[:, 1, :] = _CONVERGED
RULE[1, 0, 0] = _JOINT_LIMITS
RULE[1, 0, 1] = _NOT_CONVERGED
_RULE = RULE.tolist()  # nested lists: the rule for a few answers, indexed without a call
_FEW = 32  # answers decided row by row (``decide``); more by array calls
# one answer: nested lists of statuses (None: the claim stands), indexed without a call
_SUCCESS, _OUTSIDE = Status.CONVERGED, Status.JOINT_LIMITS  # read per row
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
    opts: SolverSettings,
    seed: np.ndarray,
    all_solutions: bool,
    t0: float,
    counts: tuple[int, int] | None = None,
) -> list[IKResult]:
    """Verify ``answers`` (all of them, or nearest-first up to the first success), rank
    them best first and build the results; ``t0`` is the call's ``perf_counter`` start;
    ``counts``: the iterations and restarts of the whole search that ran them, where it
    ran more than these answers' run."""
    if all_solutions:
        found = verdicts(arm, answers, target, opts)
    else:
        found = first_verified(arm, answers, target, opts, seed)
    if counts is not None:
        found = found.recounted(*counts)
    results = ranked(found, solver, seed, all_solutions, t0)
    # measured apart (weights, a region: bounds or an aim): the distances beside
    if opts.weights is not None or opts.bounds is not None or target.aim is not None:
        return with_distances(arm, results, target, opts)
    return results


def decide(
    arm: ArmModel,
    answers: Answers,
    m: BatchMeasure,
    opts: SolverSettings,
    positions: np.ndarray | None = None,
) -> Verdicts:
    """The verdict of N answers from their measure ``m``, by the ``RULE``: a success only
    where the measure holds. A failure's words are the solver's where it gave some, else
    written from its claim (``positions``: the targets', naming an unreachable one's
    distance)."""
    claim = answers.claim
    n = len(claim)
    ok = m.ok
    if n <= _FEW:  # a solve's answers: the rule row by row costs less than array calls
        codes = []
        for c, o, w in zip(claim.tolist(), ok.tolist(), m.within_limits.tolist()):
            d = _RULE[c == _CONVERGED][o][w]
            codes.append(c if d < 0 else d)  # no rule: the claim stands
        status = np.array(codes, dtype=np.int8)
    else:
        status = status_codes(claim, ok, m.within_limits)
    out = Verdicts(
        answers=answers,
        status=status,
        position_error=m.position_error,
        orientation_error=m.orientation_error,
        rotation=m.rotation,
        words=[None] * n,
        tol_position=m.tol_position,
        tol_orientation=m.tol_orientation,
        region=m.region,
        cone=m.cone,
        free=m.free,
    )
    for i in np.flatnonzero(~ok).tolist():  # the rare failures get their words
        out.words[i] = _failure_words(arm, out, m, i, opts, positions)
    return out.checked(arm, opts.checks) if opts.checks else out


def decide_one(arm: ArmModel, answers: Answers, m: Measure, opts: SolverSettings) -> Verdicts:
    """``decide`` for one answer and its ``Measure``, on plain floats (a solve's usual
    case: the verdicts of the answers a search verifies one by one); a failure's words
    are ``decide``'s."""
    if not m.ok or opts.checks:
        return decide(arm, answers, BatchMeasure.of([m]), opts)
    ori = m.orientation_error
    return frozen(
        Verdicts,
        answers=answers,
        status=np.array([_CONVERGED], dtype=np.int8),  # a measure that holds (``RULE``)
        position_error=np.array([m.position_error]),
        orientation_error=np.array([math.nan if ori is None else ori]),
        rotation=ori is not None,
        words=[None],
        tol_position=m.tol_position,
        tol_orientation=m.tol_orientation,
        region=m.region,
        extra=None,
        cone=m.cone,
        free=m.free,
    )


def _failure_words(
    arm, v: Verdicts, m: BatchMeasure, i: int, opts: SolverSettings, positions
) -> str:
    answers = v.answers
    code = int(answers.claim[i])
    if code == _CONVERGED:
        if not m.within_limits[i]:
            return limits_reason(arm, answers.q[i])
        return reasons.check_failed(v.measured(i))
    if code == _NOT_CONVERGED:  # where its best stopped, a limit may be what held it
        if answers.reasons is not None:
            said = answers.reasons[i]
        else:
            restarts = f"at most {opts.max_restarts} restarts"
            why = reasons.budget(opts.timeout, opts.iteration_budget, restarts)
            said = reasons.not_converged(why, v.measured(i))
        return reasons.resting_on_limits(said, on_limits(arm, answers.q[i]))
    if answers.reasons is not None:
        return answers.reasons[i]
    if code == _UNREACHABLE and positions is not None:
        distance = math.dist(positions[i].tolist(), arm.first_joint_origin.tolist())
        return reasons.unreachable(distance, arm.reach)
    return reasons.claimed(Status.from_code(code).value, v.measured(i))


def verdicts(arm: ArmModel, answers: Answers, target, opts: SolverSettings) -> Verdicts:
    """The verdict of every answer, measured together (``measure_many``)."""
    if not len(answers):
        none = np.empty(0)
        m = BatchMeasure(none, none, none.astype(bool), opts.tol_position, opts.tol_orientation)
        return decide(arm, answers, m, opts)
    if len(answers) == 1:
        return decide_one(arm, answers, measure(arm, answers.q[0], target, opts), opts)
    return decide(arm, answers, measure_many(arm, list(answers.q), target, opts), opts)


def ranked(found: Verdicts, solver: str, seed, all_solutions: bool, t0: float):
    """The results of verdicts, best first (the first only unless ``all_solutions``)."""
    n = len(found)
    if n < 2:
        return found.results(range(n), solver, time.perf_counter() - t0)
    order = found.order(seed)
    if not all_solutions:
        return found.results(order[:1], solver, time.perf_counter() - t0)
    order = found.once(order)
    branch = found.answers.branch
    labels = numbered([None] * n if branch is None else [branch[i] for i in order])
    return found.results(order, solver, time.perf_counter() - t0, labels)


def numbered(labels: list[str | None]) -> list[str | None]:
    """``solve_all``'s branch labels made distinct, in their order: a label met again gets
    "#2", "#3" (a search family has up to 16 solutions and 8 labels)."""
    if len(set(labels)) == len(labels):  # distinct already: the closed forms' usual case
        return labels
    seen: dict[str, int] = {}
    out = []
    for label in labels:
        if label is not None:
            count = seen.get(label, 0) + 1
            seen[label] = count
            label = f"{label}#{count}" if count > 1 else label
        out.append(label)
    return out


def first_verified(arm: ArmModel, answers: Answers, target, opts: SolverSettings, seed) -> Verdicts:
    """Verify answers nearest-first (``nearest_first``) and stop at the first success: it
    is the nearest verified answer. The verdicts of the answers verified."""
    if len(answers) == 1:
        return decide_one(arm, answers, measure(arm, answers.q[0], target, opts), opts)
    order, measures = [], []
    checks = opts.checks
    for i in nearest_first(arm, answers, seed):
        m = measure(arm, answers.q[i], target, opts)
        if m.ok and (not checks or satisfied(arm, checks, answers.q[i])):
            return decide_one(arm, answers.take([i]), m, opts)  # a success: the nearest one
        order.append(i)
        measures.append(m)
    if not order:
        return verdicts(arm, answers, target, opts)
    return decide(arm, answers.take(order), BatchMeasure.of(measures), opts)


def nearest_first(arm: ArmModel, answers: Answers, seed: np.ndarray) -> list[int]:
    """The rows in the order they are verified for one answer: claimed converged, within
    the limits, then by distance to the seed (ties to ``sixr.TIE``: the solver's order,
    ``verdicts.tied``), as ``solve_all`` lists them."""
    Q = answers.q
    # the keys in one pass over the rows (``within_limits``' bounds, as arrays)
    lo, hi = arm.lower - LIMIT_TOL, arm.upper + LIMIT_TOL
    inside = np.asarray(((Q >= lo) & (Q <= hi)).all(axis=1)).tolist()
    claimed = (answers.claim == _CONVERGED).tolist()
    keys = []
    for q, c, w in zip(Q, claimed, inside):
        d = q - seed
        keys.append((not c, not w, float(np.sqrt(d.dot(d)))))
    return tied(sorted(range(len(keys)), key=keys.__getitem__), keys, Q.shape[1])


def seed_distance(q: np.ndarray, seed: np.ndarray) -> float:
    d = q - seed
    return float(np.sqrt(d.dot(d)))


def success_reason(
    claim_reason, claim_args, pos, ori, tol_p, tol_r, region=False, cone=None, free=(False, False)
) -> str:
    """The reason of a success from its parts: the claim's reason is ``claim_reason``
    itself, or ``claim_reason(*claim_args)`` when it is a function (results of prepared
    solves write their reason on first read, see ``IKResult``); ``region``: the errors are
    the distances outside the target's region (``cone``: its aim's, in words); ``free``:
    (position, rotation) left free, not said (``SolverSettings.left_free``)."""
    if callable(claim_reason):
        claim_reason = claim_reason(*claim_args)
    pos, ori = None if free[0] else pos, None if free[1] else ori
    if region:
        return reasons.verified(claim_reason, reasons.region(pos, ori, tol_p, tol_r, cone))
    return reasons.verified(claim_reason, reasons.measured(pos, ori, tol_p, tol_r))


def limits_reason(arm: ArmModel, q: np.ndarray) -> str:
    """The reason of a claimed answer outside the joint limits."""
    return reasons.outside_limits(arm.limit_violations(q))


def claimed_verdict(
    arm: ArmModel,
    got: Claim,
    pos: float,
    ori: float | None,
    inside: bool,
    tol_p: float,
    tol_r: float,
    region: bool = False,
    cone: reasons.Cone | None = None,
    free: tuple = (False, False),
) -> dict | None:
    """``verdict`` of a prepared runner's claimed answer ``got`` from its measure (``ori``
    None where the orientation is not measured; ``inside``: within the limits; ``region``:
    the errors are the distances outside the target's region, ``cone``: its aim's),
    without building the ``Answers`` and ``Measure``: a success within the tolerances and
    the limits, ``joint_limits`` outside the limits, else None (the general ``verdict``
    decides: ``check_failed``'s reason needs the target's region). The fields of an
    ``IKResult`` but ``solver`` and ``time``; the reason written on first read."""
    q = got.q
    if q.flags.writeable:  # the runner's own array (solve_all's rows are read-only)
        q.setflags(write=False)
    its, rs, branch, singular = got.iterations, got.restarts, got.branch, got.singular
    why = (got.reason, got.reason_args)
    return _claimed(
        arm, q, its, rs, branch, singular, pos, ori, inside, tol_p, tol_r, why, region, cone, free
    )


def claimed_rows(
    arm: ArmModel, got: Answers, measured: list, tol_p: float, tol_r: float, rot: bool
) -> list[dict | None]:
    """``claimed_verdict`` of each of a runner's rows ``got`` (read-only q) from
    ``measured``, each row's (position error, orientation error, > 0 within the limits) in
    plain floats; None for a row not claimed converged or one the general verdict decides.
    One loop over columns read once: a ``solve_all``'s cost is per row."""
    Q, converged = got.q, _CONVERGED
    claims, its, rss = got.claim.tolist(), got.iterations.tolist(), got.restarts.tolist()
    labels = got.branch or (None,) * len(claims)
    flags = (False,) * len(claims) if got.singular is None else got.singular.tolist()
    words = got.reason
    out: list[dict | None] = []
    for i, (pos, ori, inside) in enumerate(measured):
        if claims[i] != converged:
            out.append(None)
            continue
        ori = ori if rot else None
        why = (words, (i,))
        row = _claimed(arm, Q[i], its[i], rss[i], labels[i], flags[i], pos, ori, inside > 0.0,
                       tol_p, tol_r, why, False)  # fmt: skip
        out.append(row)
    return out


def _claimed(
    arm,
    q,
    its,
    rs,
    branch,
    singular,
    pos,
    ori,
    inside,
    tol_p,
    tol_r,
    why,
    region,
    cone=None,
    free=(False, False),
):
    """The fields of a claimed answer's result but ``solver`` and ``time``, by the rule
    (``status_of`` a claim): a success within the tolerances and the limits,
    ``joint_limits`` outside the limits, else None (the general verdict decides). ``why``:
    the claim's reason as (function, arguments)."""
    ok = inside and pos <= tol_p and (ori is None or ori <= tol_r)
    status = _DECIDED[1][1 if ok else 0][1 if inside else 0]
    if status is _SUCCESS:
        said = (why[0], why[1], pos, ori, tol_p, tol_r, region, cone, free)
        reason: tuple = (success_reason, said)
    elif status is _OUTSIDE:
        reason = (limits_reason, (arm, q))
    else:
        return None
    return dict(
        q=q,
        success=status is _SUCCESS,
        status=status,
        iterations=its,
        position_error=pos,
        orientation_error=ori,
        branch=branch,
        singular=singular,
        restarts=rs,
        _reason=reason,
    )


def verdict_batch(
    arm: ArmModel,
    answers: Answers,
    targets: TargetBatch,
    opts: SolverSettings,
    out: BatchResult,
    start: int = 0,
    constraints: tuple[Constraint, ...] = (),
) -> np.ndarray:
    """The verdict of a chunk of answers (one a target), as every verdict (``decide``),
    with each of ``constraints`` checked over the verified answers (a collision check's
    distance and pair kept), written into rows ``start:start + len(targets)`` of ``out``
    (a success's words are written when read); returns the chunk's successes."""
    stop = start + len(answers.q)
    q = out.q[start:stop]
    q[:] = answers.q
    m = measure_batch(arm, q, targets, opts)
    found = decide(arm, answers, m, opts, targets.positions)
    if found.answers.q is not answers.q:  # a row turned by 2 pi to pass a check
        q[:] = found.answers.q
    for c in constraints:
        rows = np.flatnonzero(found.success)
        found.judge(c.check(arm, q[rows]), rows.tolist())
    out.iterations[start:stop] = answers.iterations
    out.restarts[start:stop] = answers.restarts
    if opts.weights is not None or m.region:  # measured apart: the distances beside
        measured = out._measured[start:stop]
        measured[:, 0], measured[:, 1] = found.position_error, found.orientation_error
        position, orientation = batch_distances(arm, q, targets, opts)
    else:
        position, orientation = found.position_error, found.orientation_error
    out.position_error[start:stop] = position
    out.orientation_error[start:stop] = orientation
    out.status_code[start:stop] = found.status
    success = found.success
    out.success[start:stop] = success
    for i in np.flatnonzero(~success).tolist():
        out.reasons[start + i] = found.reason(i)
    for i, kept in enumerate(found.extra or ()):
        if "min_distance" in kept:
            out.put_distance(start + i, kept["min_distance"], kept["closest_pair"])
    return success
