"""Every solution of several tips at once: ``Arms.solve_all``, the word ``Arm.solve_all``
says on one arm.

Chains that share no joint each give every answer of their own ``solve_all`` (a closed
form: every branch); the robot's answers are their combinations, each joined as
``Arms.solve`` joins one (``armik.arms_joined``): successes first, nearest q0. Where a tip
has no verified answer, the one joined result of each tip's best says which failed.
Chains that share joints, or tips placed relative to each other, are solved together by
the task solver, which finds one answer: ``solve_all`` gives that one.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Mapping
from typing import Any

import numpy as np

from armik.arms_joined import joined
from armik.result import IKResult

MAX_COMBINATIONS = 256  # answers at most: the nearest q0 of every chain's verified ones


def solve_all(arms: Any, targets: Mapping[str, object], q0: object = None, **options: Any):
    """Every answer of ``arms`` (an ``armik.Arms``) for one target per tip, best first."""
    t0 = time.perf_counter()
    relative = arms._check_targets(targets)
    if arms._union is not None or relative:
        return [arms.solve(targets, q0=q0, **options)]
    seeds = arms._middle_seeds if q0 is None else arms.split(q0)
    held = arms._holds(options)
    found = {
        tip: arms.chain(tip).solve_all(target, q0=seeds[tip], **held[tip])
        for tip, target in targets.items()
    }
    good = {tip: [r for r in rs if r.success] for tip, rs in found.items()}
    elapsed = time.perf_counter() - t0
    if not all(good.values()):  # a tip with no answer: the best of each, joined
        best = {tip: rs[0] for tip, rs in found.items() if rs}
        return [joined(arms.tips, best, seeds, elapsed)]
    reference = np.concatenate([seeds[tip] for tip in arms.tips])
    tips = list(good)
    results: list[IKResult] = [
        joined(arms.tips, dict(zip(tips, choice)), seeds, elapsed)
        for choice in itertools.product(*(good[tip] for tip in tips))
    ]
    results.sort(key=lambda r: float(np.linalg.norm(r.q - reference)))
    return results[:MAX_COMBINATIONS]
