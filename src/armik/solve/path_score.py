"""A followed path's preference (``solve_path(..., prefer=)``): continuity first, then the
score. At each waypoint the followed answer stands unless another verified answer within
``max_joint_step`` of the previous one scores better: another branch or turn of a closed
form (``solve_all`` from the previous answer), or, on a redundant arm, the followed answer
moved a few steps along its self-motion (``armik.solve.nullspace``). A few steps a
waypoint: the path drifts toward the score as it goes instead of jumping to the best
configuration of each pose, which would break it."""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
import pinocchio as pin

from armik import path_reasons, reasons
from armik.model.arm_model import ArmModel
from armik.problem.scores import Score
from armik.problem.settings import SolverSettings
from armik.request import Request
from armik.result import IKResult
from armik.solve.nullspace import descend
from armik.solve.prefer import best_variant
from armik.solve.rungs import unwrapped
from armik.solve.stages import run
from armik.solve.turning import ANY, Turning
from armik.solvers import registry
from armik.solvers.answers import one
from armik.status import Status
from armik.targets.pose import Target
from armik.verify.verdict import finish

STEPS = 3  # self-motion steps at a waypoint at most (deterministic: no time budget)


def preferred(
    arm: ArmModel,
    target: Target,
    r: IKResult,
    q_prev: np.ndarray,
    step: np.ndarray,
    score: Score,
    reference: np.ndarray,
    request: Request,
    turn: Turning = ANY,
) -> IKResult:
    """The best-scored verified answer at ``target`` within ``step`` of ``q_prev``, the
    followed answer ``r`` among them (``reference``: the score's q0, the path's start;
    ``turn``: the turns and the self-motion the request allows: no held joint moves)."""
    if not r.success:
        return r
    candidates = [r]
    opts = request.settings
    if registry.get(r.solver).kind != "numeric":  # every branch and turn, nearest first
        now = time.perf_counter()
        found = run(arm, request.but(target=target, q0=q_prev, solver=r.solver, every=True, t0=now))
        candidates += [unwrapped(arm, c, q_prev, turn) for c in found if c.success]
    elif arm.dof > 6 and _plain_pose(target, opts, opts.collisions):
        pose = pin.SE3(target.rotation, target.position)
        box = (np.maximum(arm.lower, q_prev - step), np.minimum(arm.upper, q_prev + step))
        fixed = list(turn.fixed)  # a held joint stays where the followed answer holds it
        box[0][fixed] = box[1][fixed] = np.asarray(r.q)[fixed]
        moved = descend(arm, r.q, pose, score, reference, math.inf, steps=STEPS, box=box)
        if not np.array_equal(moved, r.q):
            claim = one(moved, Status.CONVERGED, reasons.SELF_MOTION)
            candidates += finish(arm, r.solver, claim, target, opts, q_prev, False, 0.0)
    if np.isposinf(step).all():  # a free first answer: each at the turn the score ranks first
        candidates = [_best_turn(arm, c, score, reference, turn) for c in candidates]
    within = [
        c for c in candidates if c.success and bool((np.abs(c.q - q_prev) <= step + 1e-12).all())
    ]
    if len(within) < 2:  # the followed answer, its score reported all the same
        return dataclasses.replace(r, extra={**r.extra, "score": score(arm, r.q, reference)})
    values = [score(arm, c.q, reference) for c in within]
    k = int(np.argmin(values))  # ties: the followed answer, first
    best = within[k]
    return IKResult(
        **{
            **{f: getattr(best, f) for f in _FIELDS},
            "reason": path_reasons.best_within_step(
                best.reason, score.name, score.words(values[k]), len(within)
            ),
            "time": r.time,
            "extra": {**best.extra, "score": values[k]},
        }
    )


def _best_turn(
    arm: ArmModel, r: IKResult, score: Score, reference: np.ndarray, turn: Turning
) -> IKResult:
    """``r`` at its best 2 pi variant for ``score`` (``prefer.best_variant``): the same pose."""
    q = best_variant(arm, np.asarray(r.q), score, reference, turn)
    if q is r.q or np.array_equal(q, r.q):
        return r
    q = np.array(q, dtype=float)
    q.flags.writeable = False
    return dataclasses.replace(r, q=q)


_FIELDS = tuple(f for f in IKResult.__dataclass_fields__ if f not in ("reason", "time", "extra"))


def _plain_pose(target: Target, opts: SolverSettings, collisions: bool) -> bool:
    """A full pose without a region, weights or collisions: what the self-motion descent
    holds."""
    region = opts.bounds is not None or target.aim is not None
    return target.rotation is not None and not (region or opts.weights or collisions)
