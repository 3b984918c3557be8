"""Tips provably out of reach, for chains solved together (``Arms``): a target farther from
a chain's first joint than the chain can reach is refused before any descent, and the
other tips are solved without it, so that the failure names the tip that cannot reach
and the others' answer and errors are those of a solve, not of a compromise."""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Mapping
from typing import Any

import numpy as np
import pinocchio as pin

from armik import reasons
from armik.problem.problem import as_problem, as_target, lower
from armik.result import IKResult
from armik.status import Status
from armik.targets.pose import Target


def reaching(arms: Any, beyond: dict[str, str], targets, q0, request: Any, t0: float):
    """Tips sharing joints (``arms``, an ``Arms``), some provably beyond reach
    (``beyond_reach``): the others solved together as ``request`` (an ``ArmsRequest``)
    asks, the failure naming the tips that cannot reach; with none left, the start kept, as
    a solve that fails leaves it, a held value checked within its joint's limits."""
    union = arms._union
    rest = {t: v for t, v in targets.items() if t not in beyond}
    if rest:
        r = arms._solve_together(union, rest, {}, q0, request, t0)
    else:
        q = arms.middle if q0 is None else np.asarray(q0, dtype=float)
        if request.options:  # read with the request: its values checked here
            for c in request.together[1]:
                c.at(union, q)  # a held value within its joint's limits
        r = IKResult(
            q=q, success=False, status=Status.UNREACHABLE, reason="", solver="task",
            iterations=0, position_error=math.inf, orientation_error=None, time=0.0,
        )  # fmt: skip
    placements = {t: union.fk(r.q, t) for t in beyond}
    return with_unreachable(r, targets, beyond, placements, time.perf_counter() - t0)


def beyond_reach(chains: Mapping[str, object], targets: Mapping[str, object]) -> dict[str, str]:
    """Each tip whose target (a pose or a position, parsed by the facade: a ``Target``, or
    a task list that says one exactly, as ``Arm.solve`` reads it; regions are the task
    solver's to measure) lies beyond its chain's reach bound, with the reason that proves
    it."""
    out = {}
    for tip, given in targets.items():
        target = given if type(given) is Target else exact(given, tip)  # parsed: the usual
        if target is None:
            continue
        arm = chains[tip]
        distance = math.dist(target.position.tolist(), arm.first_joint_origin.tolist())  # type: ignore[attr-defined]
        if distance > arm.reach:  # type: ignore[attr-defined]
            out[tip] = reasons.beyond_reach(distance, arm.reach)  # type: ignore[attr-defined]
    return out


def with_unreachable(
    r: IKResult,
    targets: Mapping[str, object],
    beyond: dict[str, str],
    placements: Mapping[str, pin.SE3],
    elapsed: float,
) -> IKResult:
    """``r``, the other tips' solve (or the start where every tip is beyond reach), as the
    robot's failure: unreachable, the reason naming each tip out of reach first, every
    tip's errors at ``r.q`` (``placements``: each tip's pose there)."""
    errors = dict(r.extra.get("errors", {}))
    for tip in beyond:
        target = exact(targets[tip], tip)
        assert target is not None  # ``beyond_reach`` read it
        X = placements[tip]
        ori = None  # a position target has no orientation to miss
        if target.rotation is not None:
            ori = float(np.linalg.norm(pin.log3(target.rotation.T @ X.rotation)))
        errors[tip] = (float(np.linalg.norm(X.translation - target.position)), ori)
    others = [t for t in targets if t not in beyond]
    said = reasons.tips_beyond(beyond, others, r.status.value, r.reason)
    kept = {t: errors[t] for t in targets if t in errors}
    # a tip whose target holds no position or rotation (None: an Axis, a position) has
    # none to miss; a tip beyond reach holds a position
    positions = [p for p, _ in kept.values() if p is not None]
    oris = [o for _, o in kept.values() if o is not None]
    return dataclasses.replace(
        r,
        position_error=max(positions),
        orientation_error=max(oris) if oris else None,
        success=False,
        status=Status.UNREACHABLE,
        reason=said,
        time=elapsed,
        extra={**r.extra, "errors": kept},
    )


def exact(target: object, tip: str) -> Target | None:
    """``target`` as the pose or position it says: a ``Target`` (parsed by the facade), or
    a task list of one exact ``Pose`` or ``Position`` on ``tip`` (``problem.lower``'s,
    without options: the task's values, read when it was built, not parsed again); None
    for any other task list (a region, weights, several tasks)."""
    if type(target) is Target:
        return target
    problem = None if isinstance(target, np.ndarray) else as_problem(target)
    lowered = None if problem is None else lower(problem, tip)
    return None if lowered is None or lowered[1] else as_target(lowered[0])
