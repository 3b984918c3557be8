"""A preference (``prefer=``) on a robot whose chains share no joint (``armik.Arms``).

A named score, or an ``armik.Posture`` over ``Arms.joint_names``, splits by chain: each
chain ranks its own answers by its part of it (``armik.arms_options``), and the best of
each chain is the best of the robot. The robot's score of an answer (``r.score``,
``BatchResult.score``) is the score of its whole configuration, from the chains' own: a
``Posture``'s is the sum of theirs, ``"nearest"``'s the distance from q0 over every
joint (the root of the sum of their squares), ``"limits"``'s the smallest margin of any
joint (the worst chain's), ``"manipulability"``'s minus the product of the chains'
measures (the measure of the tips' Jacobian, block-diagonal over chains that share no
joint); a ``Score`` of another class, the sum of the chains'.

A callable ``cost(q)`` takes the whole configuration, in ``Arms.joint_names``' order, as
over shared joints; it need not split by chain, so its best answer is searched in two
steps. Each chain in turn (the order of the targets) lists its answers (``Arm.solve_all``)
ranked by the cost of the whole configuration, its own joints varying and the other
chains' at their values so far: q0's part (mid-limits without q0), or the best answer of
a chain ranked before it. The combinations of those answers are then ranked by the cost
of the whole configuration, best first (at most ``MAX_RANKED``: each chain's best
answers kept). A cost that is a sum of chain terms gets the best answer of every
chain's; one that couples the chains the best of the combinations of the answers each
chain found (each chain's turns of 2 pi, and a redundant chain's self-motion, chosen with
the chains after it at q0's values).
"""

from __future__ import annotations

import dataclasses
import itertools
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from armik.arms_joined import joined
from armik.errors import OptionError
from armik.problem.scores import Cost, Limits, Manipulability, Nearest, Score, parse_score
from armik.result import IKResult

MAX_RANKED = 4096  # combinations of the chains' answers a callable cost is evaluated on


def is_cost(prefer: object) -> bool:
    """Whether ``prefer=`` is a callable cost of the whole configuration (a ``Score``,
    ``Posture`` among them, is callable too, but splits by chain)."""
    return prefer is not None and not isinstance(prefer, (str, Score)) and callable(prefer)


def combined(prefer: object, values: np.ndarray) -> np.ndarray:
    """The robot's score from its chains' (``values``: one row a chain) of the named score
    or ``Score`` ``prefer`` (module docstring); NaN where a chain's is."""
    score = parse_score(prefer)
    if isinstance(score, Nearest):
        out: np.ndarray = np.sqrt(np.sum(values**2, axis=0))
    elif isinstance(score, Limits):
        out = np.max(values, axis=0)
    elif isinstance(score, Manipulability):
        out = -np.prod(-values, axis=0)
    else:
        out = np.sum(values, axis=0)
    return out


def whole(prefer: object, results: Sequence[IKResult]) -> float | None:
    """The robot's score of the answer joined from ``results`` (a chain's each), or None
    where a chain's answer has none (a failure)."""
    scores = [r.score for r in results]
    if not scores or any(s is None for s in scores):
        return None
    return float(combined(prefer, np.array(scores, dtype=float)))


def scored(r: IKResult, prefer: object) -> IKResult:
    """``r``, a joined result (``armik.arms_joined``), with the robot's score in ``extra``
    when every chain's answer has one."""
    value = whole(prefer, list(r.extra["results"].values()))
    if value is not None:
        r.extra["score"] = value
    return r


def ranked(
    arms: Any,
    targets: Mapping[str, object],
    seeds: Mapping[str, np.ndarray],
    reference: np.ndarray,
    fn: Any,
    options: Mapping[str, dict],
    count: int,
    t0: float,
) -> list[IKResult]:
    """The robot's answers for the callable cost ``fn`` (module docstring), best first, at
    most ``count``, each with its cost as its score; where a tip has no verified answer,
    the one joined result of each tip's best. ``seeds``: each chain's q0; ``reference``:
    the whole q0; ``options``: each tip's (``ArmsRequest.chains_options``: the solver among
    them where one was given)."""
    cost = Cost(fn)
    current = np.array(reference, dtype=float)
    found: dict[str, list[IKResult]] = {}
    firsts: dict[str, IKResult] = {}
    for tip, target in targets.items():
        cols = arms._columns[tip]
        raised: list[OptionError] = []
        part = _part(cost, arms, current.copy(), cols, reference, raised)
        try:
            own = {**options[tip], "prefer": part}
            solver = own.pop("solver", "auto")
            rs = arms._chain_every(tip, target, seeds[tip], solver, own)
        except OptionError:
            if raised:  # the cost's own error, at the whole configuration
                raise raised[-1] from raised[-1].__cause__
            raise
        found[tip] = [r for r in rs if r.success]
        if rs:
            firsts[tip] = rs[0]
        if found[tip]:
            current[cols] = found[tip][0].q
    if not all(found.values()):  # a tip with no answer: the best of each, joined
        return [joined(arms.tips, firsts, seeds, time.perf_counter() - t0)]
    tips = list(found)
    lists = _capped([found[tip] for tip in tips], MAX_RANKED)
    values = []
    for k, choice in enumerate(itertools.product(*lists)):
        q = np.array(reference, dtype=float)
        for tip, r in zip(tips, choice):
            q[arms._columns[tip]] = r.q
        values.append((cost(arms, q, reference), k, choice))
    values.sort(key=lambda v: (v[0], v[1]))
    elapsed = time.perf_counter() - t0
    out = []
    for value, _, choice in values[:count]:
        # the cost is of the whole configuration: each chain's answer carries the robot's
        # score, not the one its chain's search ranked it by (the other chains elsewhere)
        own = {tip: _with_score(r, value) for tip, r in zip(tips, choice)}
        r = joined(arms.tips, own, seeds, elapsed)
        r.extra["score"] = value
        out.append(r)
    return out


def _with_score(r: IKResult, value: float) -> IKResult:
    """``r`` with ``value`` as its score."""
    return dataclasses.replace(r, extra={**r.extra, "score": value})


def _part(
    cost: Cost,
    arms: Any,
    base: np.ndarray,
    cols: np.ndarray,
    reference: np.ndarray,
    raised: list[OptionError],
) -> Callable[[np.ndarray], float]:
    """The cost of one chain's joints ``x``: of the whole configuration ``base`` with the
    chain's columns ``cols`` at ``x``; the cost's error kept in ``raised``."""

    def part(x: np.ndarray) -> float:
        q = base.copy()
        q[cols] = x
        try:
            return cost(arms, q, reference)
        except OptionError as e:
            raised.append(e)
            raise

    part.__name__ = cost.name
    return part


def _capped(lists: list[list[IKResult]], cap: int) -> list[list[IKResult]]:
    """Each list's first answers (its best), as many as keep the product within ``cap``:
    the longest list shortened first."""
    lists = [list(rs) for rs in lists]
    while np.prod([len(rs) for rs in lists]) > cap:
        longest = max(range(len(lists)), key=lambda i: len(lists[i]))
        lists[longest].pop()
    return lists


def order(prefer: object, choices: list[tuple[IKResult, ...]]) -> list:
    """(score, combination) of ``choices`` (one answer a tip, ranked by a named score or a
    ``Posture`` each), best first by the robot's score (ties: in the order given)."""
    values = np.array([[r.score for r in choice] for choice in choices], dtype=float)
    whole_scores = combined(prefer, values.T) if len(choices) else np.empty(0)
    keys = sorted(range(len(choices)), key=lambda k: (float(whole_scores[k]), k))
    return [(float(whole_scores[k]), choices[k]) for k in keys]
