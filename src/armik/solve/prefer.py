"""The rank stage with a score: every verified answer found, each 2 pi variant of it that
the limits allow, scored (``armik.problem.scores``); the best first.

Closed forms give every branch, so their best is the best over the finite set of
solutions within the limits; numeric solvers give the distinct answers their budget finds
(``solve_all`` spends the whole budget), so theirs is the best found.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import time
from collections.abc import Callable
from typing import cast

import numpy as np

from armik.model.arm_model import ArmModel
from armik.problem.scores import Score
from armik.result import IKResult
from armik.status import Status

TWO_PI = 2.0 * math.pi
MAX_VARIANTS = 256  # per answer: 2 pi shifts of every joint that allows them, combined


def turns(arm: ArmModel, q: np.ndarray) -> list[list[float]]:
    """Per joint: its value and the values 2 pi turns away within its limits, on the
    revolute joints whose limits span more than one turn."""
    lower, upper, no_period = arm._limit_lists  # no period: prismatic, or a mimic's driver
    choices = []
    for qi, lo, hi, linear in zip(q.tolist(), lower, upper, no_period):
        values = [qi]
        if not linear and math.isfinite(lo) and math.isfinite(hi) and hi - lo > TWO_PI:
            k_lo, k_hi = math.ceil((lo - qi) / TWO_PI), math.floor((hi - qi) / TWO_PI)
            values += [qi + k * TWO_PI for k in range(k_lo, k_hi + 1) if k != 0]
        choices.append(values)
    return choices


def best_variant(arm: ArmModel, q: np.ndarray, score: Score, q0: np.ndarray) -> np.ndarray:
    """The 2 pi variant of ``q`` within the limits that ``score`` ranks first: ``q`` when
    turns do not change the score, each joint's best turn when it splits by joints, else
    the best of every combination (at most ``MAX_VARIANTS``, ``q``'s own first)."""
    if not score.turns_matter:
        return q
    choices = turns(arm, q)
    if all(len(c) == 1 for c in choices):
        return q
    if score.per_joint(arm, 0, float(q[0]), q0) is not None:  # then a float for each joint

        def by_joint(i: int) -> Callable[[float], float]:
            return lambda v: cast(float, score.per_joint(arm, i, v, q0))

        return np.array([min(c, key=by_joint(i)) for i, c in enumerate(choices)])
    combos = itertools.islice(itertools.product(*choices), MAX_VARIANTS)
    return min((np.array(c) for c in combos), key=lambda x: score(arm, x, q0))


def rank(
    arm: ArmModel, results: list[IKResult], score: Score, q0: np.ndarray, t0: float
) -> list[IKResult]:
    """The successes of ``results``, each as its best 2 pi variant, best ``score`` first
    (ties: in the order found), then the failures as they were; each success carries its
    score in ``extra["score"]`` and the score's name in its reason."""
    scored: list[tuple[float, int, IKResult, np.ndarray]] = []
    seen: set[tuple[float, ...]] = set()
    for r in results:
        if r.success:
            q = best_variant(arm, np.asarray(r.q), score, q0)
            key = tuple(np.round(q, 9).tolist())  # one answer found twice counts once
            if key not in seen:
                seen.add(key)
                scored.append((score(arm, q, q0), len(scored), r, q))
    scored.sort(key=lambda item: (item[0], item[1]))
    elapsed = time.perf_counter() - t0
    ranked = [
        dataclasses.replace(
            r,
            q=q,
            reason=f"{r.reason}; {score.name} {value:.6g}, ranked among {len(scored)} verified"
            + ("" if np.array_equal(q, r.q) else " (a 2 pi variant within the limits)"),
            time=elapsed,
            extra={**r.extra, "score": value},
        )
        for value, _, r, q in scored
    ]
    return ranked + [r for r in results if not r.success]


SWEEP_GRID = 32  # values of the held joint over its range, before the refinement
REFINE_STEPS = 16  # golden-section steps between the best grid value's neighbours
GOLDEN = 0.6180339887498949


def sweep_held(arm: ArmModel, target, q0: np.ndarray, opts, score: Score, t0: float):
    """On a 7R arm the ``swept`` closed form applies to: the self-motion searched for the
    score, joint 7 on a grid over its range and then refined by golden section around the
    best value (every branch in closed form at each value, scored at its best 2 pi
    variant); the best configurations verified (``finish``). None where it does not apply."""
    from armik.solvers import registry
    from armik.solvers.closed_form import swept_7r
    from armik.verify.verdict import finish

    if arm.dof != 7 or registry.why_not("swept", arm, target, opts) is not None:
        return None
    lo, hi = (float(x) for x in swept_7r.sweep_range(arm, float(q0[6])))

    def best_at(theta: float) -> float:
        """The best score over the branches at joint 7 = ``theta`` (inf: none reached)."""
        scores = [
            score(arm, best_variant(arm, a.q, score, q0), q0)
            for a in swept_7r.at_value(arm, target, q0, theta)
            if a.claim is Status.CONVERGED and arm.within_limits(a.q)
        ]
        return min(scores, default=math.inf)

    grid = np.linspace(lo, hi, SWEEP_GRID)
    values = [best_at(float(t)) for t in grid]
    k = int(np.argmin(values))
    if not math.isfinite(values[k]):
        return []
    a, b = float(grid[max(k - 1, 0)]), float(grid[min(k + 1, len(grid) - 1)])
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = best_at(c), best_at(d)
    for _ in range(REFINE_STEPS):
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = best_at(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = best_at(d)
    theta = min((float(grid[k]), values[k]), (c, fc), (d, fd), key=lambda x: x[1])[0]
    attempts = swept_7r.at_value(arm, target, q0, theta)
    return finish(arm, "swept", attempts, target, opts, q0, True, t0)
