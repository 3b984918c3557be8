"""Every solution of several tips at once: ``Arms.solve_all``, the word ``Arm.solve_all``
says on one arm.

Chains that share no joint each give every answer of their own ``solve_all`` (a closed
form: every branch); the robot's answers are their combinations, each joined as
``Arms.solve`` joins one (``armik.arms_joined``): successes first, nearest q0, or with
``prefer=`` best first by the robot's score of each, which each carries
(``armik.arms_prefer``). Where a tip has no verified answer, the one joined result of
each tip's best says which failed. Chains that share joints, or tips placed relative to
each other, are solved together by the task solver, which finds one answer: ``solve_all``
gives that one.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Mapping
from typing import Any

import numpy as np

from armik.arms_apart import facade, viewed
from armik.arms_joined import held, joined, left_out
from armik.arms_options import held_apart
from armik.arms_prefer import is_cost, order, ranked
from armik.result import IKResult

MAX_COMBINATIONS = 256  # answers at most: the nearest q0 (the best) of every chain's verified ones


def solve_all(arms: Any, targets: Mapping[str, object], q0: object = None, **options: Any):
    """Every answer of ``arms`` (an ``armik.Arms``) for one target per tip, best first; a
    tip left out holds its constraints at the values it keeps (``arms_joined.held``)."""
    found = _every(arms, targets, q0, **options)
    checks = left_out(arms, options, targets)
    return [held(arms, r, checks) for r in found] if checks else found


def _every(arms: Any, targets: Mapping[str, object], q0: object = None, **options: Any):
    t0 = time.perf_counter()
    relative = arms._check_targets(targets)
    if arms._union is not None or relative:
        return [arms.solve(targets, q0=q0, **options)]
    seeds = arms._middle_seeds if q0 is None else arms.split(q0)
    held = arms._holds(options)
    seeds = held_apart(seeds, held, arms._chains, targets)  # a tip left out: its holds
    prefer = options.get("prefer")
    if is_cost(prefer):  # a cost of the whole configuration: ranked over the combinations
        reference = arms.middle if q0 is None else np.asarray(q0, dtype=float)
        return ranked(
            viewed(arms, held), targets, seeds, reference, prefer, held, MAX_COMBINATIONS, t0
        )
    found = {
        tip: facade(arms, tip, held[tip]).solve_all(target, q0=seeds[tip], **held[tip])
        for tip, target in targets.items()
    }
    good = {tip: [r for r in rs if r.success] for tip, rs in found.items()}
    elapsed = time.perf_counter() - t0
    if not all(good.values()):  # a tip with no answer: the best of each, joined
        best = {tip: rs[0] for tip, rs in found.items() if rs}
        return [joined(arms.tips, best, seeds, elapsed)]
    tips = list(good)
    choices = itertools.product(*(good[tip] for tip in tips))
    if prefer is not None:  # each chain's answers scored: the robot's score of each
        listed = []
        for value, choice in order(prefer, list(choices))[:MAX_COMBINATIONS]:
            r = joined(arms.tips, dict(zip(tips, choice)), seeds, elapsed)
            r.extra["score"] = value
            listed.append(r)
        return listed
    reference = np.concatenate([seeds[tip] for tip in arms.tips])
    results: list[IKResult] = [
        joined(arms.tips, dict(zip(tips, choice)), seeds, elapsed) for choice in choices
    ]
    results.sort(key=lambda r: float(np.linalg.norm(r.q - reference)))
    return results[:MAX_COMBINATIONS]
