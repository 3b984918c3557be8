"""Every solution of several tips at once: ``Arms.solve_all``, the word ``Arm.solve_all``
says on one arm.

Chains that share no joint each give every answer of their own ``solve_all`` (a closed
form: every branch); the robot's answers are their combinations, each joined as
``Arms.solve`` joins one (``armik.arms_joined``): successes first, nearest q0, or with
``prefer=`` best first by the robot's score of each, which each carries
(``armik.arms_prefer``). Where a tip has no verified answer, the one joined result of
each tip's best says which failed.

A tip placed relative to another (``armik.Relative``) on such chains is a pose in the base
once the reference chain's answer is chosen: each answer of the reference chain in turn
(``in_turn``), the relative tip's own ``solve_all`` at that answer's placement times the
relative pose, every combination listed. A reference tip given no target keeps q0's
values, one placement. A reference tip at a position (on more than 3 joints) has a
continuum of orientations: the chains are solved first (``Arms.solve``), then every
combination at the orientation that answer has is listed, each reason saying so; one
whose target leaves its placement free otherwise (a region, an aim, a weight of 0) at the
placements its own answers found, a sample of the continuum, each reason saying so too. Chains
that share joints, tips placed relative to each other in a cycle, and relative tips no
combination of the chains' own answers holds are solved together by the task solver,
which finds one answer: ``solve_all`` gives that one, its reason saying so
(``one_answer``).
"""

from __future__ import annotations

import dataclasses
import itertools
import time
from typing import Any

import numpy as np
import pinocchio as pin

from armik.arms_joined import held, joined, left_out
from armik.arms_options import held_apart
from armik.arms_prefer import is_cost, order, ranked
from armik.arms_request import read_request, score_of
from armik.arms_tasks import absolute, solve_order
from armik.problem.problem import as_problem
from armik.problem.tasks import Pose, Position, Relative
from armik.result import IKResult
from armik.targets.pose import Target

MAX_COMBINATIONS = 256  # answers at most: the nearest q0 (the best) of every chain's verified ones


def solve_all(arms: Any, request: Any, targets: dict, relative: dict, q0: object = None):
    """Every answer of ``arms`` (an ``armik.Arms``) for one target per tip (parsed, with
    their ``relative`` tasks: ``Arms._parsed``'s), as ``request`` (an ``ArmsRequest``)
    asks, best first; a tip left out holds its constraints at the values it keeps
    (``arms_joined.held``)."""
    found = _every(arms, request, targets, relative, q0)
    checks = left_out(arms, request.options, targets)
    return [held(arms, r, checks) for r in found] if checks else found


def _every(arms: Any, request: Any, targets: dict, relative: dict, q0: object):
    t0 = time.perf_counter()
    if arms._union is not None:
        one = arms._answer(request, targets, relative, q0, t0)
        return [one_answer(one, "share joints")]
    if relative:
        return in_turn(arms, request, targets, relative, q0, t0)
    seeds = arms._middle_seeds if q0 is None else arms.split(q0)
    held = request.chains_options(arms.tips)
    seeds = held_apart(seeds, held, arms._chains, targets)  # a tip left out: its holds
    prefer = request.prefer
    if is_cost(prefer):  # a cost of the whole configuration: ranked over the combinations
        reference = arms.middle if q0 is None else np.asarray(q0, dtype=float)
        return ranked(arms, targets, seeds, reference, prefer, held, MAX_COMBINATIONS, t0)
    own = _own(request, arms.tips)
    found = {
        tip: arms._chain_every(tip, target, seeds[tip], request.solver, own[tip])
        for tip, target in targets.items()
    }
    good = {tip: [r for r in rs if r.success] for tip, rs in found.items()}
    elapsed = time.perf_counter() - t0
    if not all(good.values()):  # a tip with no answer: the best of each, joined
        best = {tip: rs[0] for tip, rs in found.items() if rs}
        return [joined(arms.tips, best, seeds, elapsed)]
    tips = list(good)
    choices = itertools.product(*(good[tip] for tip in tips))
    if prefer is not None:
        return _scored(arms, prefer, tips, list(choices), seeds, elapsed)
    reference = np.concatenate([seeds[tip] for tip in arms.tips])
    results: list[IKResult] = [
        joined(arms.tips, dict(zip(tips, choice)), seeds, elapsed) for choice in choices
    ]
    results.sort(key=lambda r: float(np.linalg.norm(r.q - reference)))
    return results[:MAX_COMBINATIONS]


def in_turn(arms: Any, request: Any, targets, relative: dict, q0: object, t0: float):
    """Every answer of tips placed relative to each other (``relative``: each tip's
    ``Relative`` tasks) on chains that share no joint: each chain's ``solve_all`` in turn,
    the reference chains first, a relative tip's target placed by the answers of the
    chains before it (``arms_tasks.absolute``, as ``Arms.solve`` places it); the verified
    combinations, nearest q0 first or best first by ``prefer=``. A reference tip at a
    position: at one sampled orientation (``_sampled``); one whose target leaves its
    placement free otherwise: at its own answers' placements, a sample each reason names
    (``_said_free``). Where none is verified, the chains at once: ``Arms.solve``'s one
    answer, or its failure."""
    tips = solve_order(targets, relative)
    if tips is None:  # relative to each other in a cycle: the chains at once, one answer
        return [one_answer(arms._answer(request, targets, relative, q0, t0), "cycle")]
    if is_cost(request.prefer):  # refused as ``Arms.solve`` refuses it, by name
        score_of(arms, request.prefer)
    points = _positions(arms, targets, relative)
    if points:
        return _sampled(arms, request, targets, relative, points, q0, t0)
    listed = _combinations(arms, request, targets, relative, tips, q0, t0)
    if not listed:
        return [one_answer(arms._answer(request, targets, relative, q0, t0), "none")]
    return _said_free(listed, _placed_freely(arms, targets, relative, request.options))


def _own(request: Any, tips) -> dict[str, dict]:
    """Each tip's own options (``ArmsRequest.each``), the solver apart."""
    return request.each or {tip: {} for tip in tips}


def _combinations(arms: Any, request: Any, targets, relative: dict, tips, q0, t0: float):
    """``in_turn``'s combinations, the chains solved in the order ``tips``; [] where none
    is verified."""
    seeds = arms._middle_seeds if q0 is None else arms.split(q0)
    held = request.chains_options(arms.tips)
    seeds = held_apart(seeds, held, arms._chains, targets)
    combos: list[dict[str, IKResult]] = [{}]
    own = _own(request, arms.tips)
    for tip in tips:
        grown = []
        for done in combos:
            target = targets[tip]
            if tip in relative:
                target = absolute(target, arms._placements(done, seeds))
            found = arms._chain_every(tip, target, seeds[tip], request.solver, own[tip])
            grown += [{**done, tip: r} for r in found if r.success]
        if not grown:
            return []
        combos = _nearest(grown, seeds)[:MAX_COMBINATIONS]
    elapsed = time.perf_counter() - t0
    prefer = request.prefer
    if prefer is None:
        return [joined(arms.tips, done, seeds, elapsed) for done in combos]
    choices = [tuple(done[t] for t in targets) for done in combos]
    return _scored(arms, prefer, list(targets), choices, seeds, elapsed)


def _scored(arms: Any, prefer, tips: list, choices: list, seeds, elapsed: float) -> list:
    """The combinations ``choices`` (an answer per tip of ``tips``) joined, best first by
    ``prefer`` (each chain's answers scored: the robot's score of each), at most
    ``MAX_COMBINATIONS``."""
    listed = []
    for value, choice in order(prefer, choices)[:MAX_COMBINATIONS]:
        r = joined(arms.tips, dict(zip(tips, choice)), seeds, elapsed)
        r.extra["score"] = value
        listed.append(r)
    return listed


def _positions(arms: Any, targets, relative: dict) -> dict[str, np.ndarray]:
    """Each reference tip (another's ``Relative`` is relative to it) whose target is a
    position (any spelling, or one exact ``Position`` task on it) on a chain of more than 3
    joints, whose answers are a continuum of orientations: its point."""
    out = {}
    for tip in sorted({t.relative_to for rel in relative.values() for t in rel}):
        given, arm = targets.get(tip), arms._chains[tip]
        if arm.dof <= 3 or given is None:
            continue
        problem = as_problem(given)  # None: a ``Target`` (parsed in ``_every``)
        if type(given) is Target:
            if given.rotation is None and given.aim is None and not given.planar:
                out[tip] = given.position
        elif problem is not None and len(problem.tasks) == 1 and type(problem.tasks[0]) is Position:
            task = problem.tasks[0]
            if task.frame in (None, tip) and not task.bounds.any():
                out[tip] = task.p
    return out


def _placed_freely(arms: Any, targets, relative: dict, options: dict) -> list[str]:
    """The reference tips (another's ``Relative`` is relative to them) whose target leaves
    their placement free within a continuum: a region (bounds), an aim (a cone, an axis, a
    look-at), a weight of 0, a position (``_positions``: on more than 3 joints), in the
    target or the call's options. A full pose held exactly, or no target (q0's values),
    fixes it."""
    weights, bounds = options.get("weights"), options.get("bounds")
    freed = (
        bool(options.get("position_only"))
        or any(k in options for k in ("cone", "look_at", "toward"))
        or (weights is not None and 0 in tuple(weights))
        or (bounds is not None and any(b != 0 for b in tuple(bounds)))
    )
    out = []
    for tip in sorted({t.relative_to for rel in relative.values() for t in rel}):
        given = targets.get(tip)
        if given is None:
            continue
        if freed or not _exact(given, tip, arms._chains[tip].dof):
            out.append(tip)
    return out


def _exact(given: object, tip: str, dof: int) -> bool:
    """Whether ``given`` (a tip's target: parsed, or a task list) fixes the tip's
    placement: a full pose, exactly (a position on 3 joints or fewer: its few answers)."""
    if type(given) is Target:
        return given.aim is None and (given.rotation is not None or dof <= 3)
    problem = as_problem(given)
    on = [t for t in problem.tasks if t.frame in (None, tip)] if problem is not None else []
    if len(on) != 1:
        return False
    (task,) = on
    if type(task) is Position:
        return dof <= 3 and not task.bounds.any()
    if isinstance(task, Relative):  # its placement its reference's, held as this pose is
        task = task.pose
    if isinstance(task, Pose):
        return not task.bounds.any() and bool(task.weights.all())
    return False


def _sampled(arms: Any, request: Any, targets, relative: dict, points: dict, q0, t0: float):
    """Reference tips at positions (``points``): ``Arms.solve``'s answer, then every
    combination with those tips at its orientations (a pose each: that position, the
    answer's orientation), each result's reason saying the orientation is one sample of a
    continuum; that one answer where none is verified, its failure where it fails."""
    one = arms._answer(request, targets, relative, q0, time.perf_counter())
    if not one.success and request.prefer is not None:  # the sample needs an answer, any:
        # the preference ranks the combinations below (its own best may be out of reach)
        unranked = {k: v for k, v in request.options.items() if k != "prefer"}
        one = arms._answer(read_request(arms, unranked), targets, relative, q0, time.perf_counter())
    if not one.success:
        return [one]
    pinned = {**targets}
    for tip, point in points.items():
        pinned[tip] = pin.SE3(arms.fk(one.q, tip).rotation, point)
    tips = solve_order(pinned, relative)
    listed = _combinations(arms, request, pinned, relative, tips, q0, t0)
    if not listed:
        return [one_answer(one, "none")]
    said = f"; {SAMPLED.format(tips=list(points))}"
    listed = [dataclasses.replace(r, reason=r.reason + said) for r in listed]
    free = _placed_freely(arms, targets, relative, request.options)
    return _said_free(listed, [tip for tip in free if tip not in points])


def _said_free(listed: list[IKResult], free: list[str]) -> list[IKResult]:
    """``listed`` (every combination at the placements its reference tips' answers found),
    each reason saying so of the tips ``free`` whose target leaves that placement free."""
    if not free:
        return listed
    said = f"; {FREED.format(tips=free)}"
    return [dataclasses.replace(r, reason=r.reason + said) for r in listed]


SAMPLED = (
    "the position target of {tips} held at one orientation, that of the chains' answer "
    "solved first: the answers of a position are a continuum, these are every combination "
    "of the chains' own answers at that orientation"
)
FREED = (
    "the target of {tips} leaves its placement free within a continuum (a region, an aim, a "
    "weight of 0): these are every combination of the chains' own answers at the placements "
    "its own answers found, a sample of that continuum"
)


def _nearest(combos: list[dict[str, IKResult]], seeds) -> list[dict[str, IKResult]]:
    """``combos`` (tip -> its answer) nearest their tips' seeds first (ties: as given)."""

    def distance(done: dict[str, IKResult]) -> float:
        return float(np.sqrt(sum(np.sum((r.q - seeds[t]) ** 2) for t, r in done.items())))

    return sorted(combos, key=distance)


_ONE = {
    "share joints": "chains that share joints are solved together by the task solver",
    "cycle": "tips placed relative to each other in a cycle are solved together by the task solver",
    "none": "no combination of the chains' own answers held every tip; the chains at once "
    "(the task solver)",
}


def one_answer(r: IKResult, why: str) -> IKResult:
    """``r``, the one answer of the chains solved at once, its reason saying that
    ``solve_all`` lists one answer there, not every solution (``why``: a key of ``_ONE``)."""
    if not r.success:
        return r
    said = f"{r.reason}; solve_all lists this one answer: {_ONE[why]}, which finds one"
    return dataclasses.replace(r, reason=said)
