"""The rank stage with a score: every verified answer found, each 2 pi variant of it that
the limits allow, scored (``armik.problem.scores``); the best first.

Closed forms give every branch, so their best is the best over the finite set of
solutions within the limits; numeric solvers give the distinct answers their budget finds,
so theirs is the best found: ``solve_all``'s answers from q0 and its restarts, then
answers from starts near the score's centre (``prefer_near``: q0, or a ``Posture``'s
reference), in boxes around it that grow to the whole range.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Iterator
from functools import partial
from operator import itemgetter
from typing import cast

import numpy as np

from armik import reasons
from armik.kernel.descent import DUPLICATE_TOL
from armik.model.arm_model import ArmModel
from armik.model.turns import UNLIMITED_TURNS
from armik.model.turns import turns as model_turns
from armik.problem.scores import Limits, Nearest, Posture, Score
from armik.result import IKResult
from armik.solve.turning import ANY, Turning, best_kept
from armik.solvers import registry
from armik.solvers.closed_form.swept_7r import DIP_STEPS, golden_search
from armik.tolerances import LIMIT_TOL
from armik.verify.verdict import finish

TWO_PI = 2.0 * math.pi


def turns(
    arm: ArmModel, q: np.ndarray, turn: Turning = ANY, unlimited: int = 0
) -> list[list[float]]:
    """Per joint: its value and the values 2 pi turns away within its limits
    (``armik.model.turns``), on the joints ``turn`` lets move; a joint without limits
    turned by up to ``unlimited`` turns each way."""
    return model_turns(arm, q, turn.free(arm.dof), unlimited)


def best_variant(
    arm: ArmModel, q: np.ndarray, score: Score, q0: np.ndarray, turn: Turning = ANY
) -> np.ndarray:
    """The 2 pi variant of ``q`` within the limits that ``score`` ranks first: ``q`` when
    turns do not change the score, each joint's best turn when it splits by joints, else
    the best of every combination (at most ``MAX_TURNS``, ``q``'s own first); only turns
    ``turn`` allows (``turning.best_kept``: the best that pass its checks)."""
    if not score.turns_matter:
        return q
    centre = _turn_centre(arm, score, q0)
    if centre is not None:
        k = _turns_towards(arm, q, centre, turn)
        return best_kept(arm, q, score, q0, turn, q + TWO_PI * k) if k.any() else q
    choices = turns(arm, q, turn, UNLIMITED_TURNS)
    if all(len(c) == 1 for c in choices):
        return q
    if score.per_joint(arm, 0, float(q[0]), q0) is not None:  # then a float for each joint

        def by_joint(i: int) -> Callable[[float], float]:
            return lambda v: cast(float, score.per_joint(arm, i, v, q0))

        best = np.array([min(c, key=by_joint(i)) for i, c in enumerate(choices)])
        return best_kept(arm, q, score, q0, turn, best)
    return best_kept(arm, q, score, q0, turn)


def continuous_turned(
    arm: ArmModel, Q: np.ndarray, score: Score, q0: np.ndarray, turn: Turning = ANY
) -> np.ndarray:
    """(N, dof): the rows of ``Q`` with their continuous joints (no limits) turned as
    ``score`` ranks best (``best_variant`` on those joints alone; the others as given),
    ``Q`` itself when nothing turns. A path's plan turns a limited joint through rungs of
    their own, but scores a continuous one as the solver gave it."""
    unlimited = np.isneginf(arm.lower) & np.isposinf(arm.upper) & turn.free(arm.dof)
    if not score.turns_matter or not unlimited.any() or not len(Q):
        return Q
    only = dataclasses.replace(turn, fixed=tuple(np.flatnonzero(~unlimited).tolist()))
    centre = _turn_centre(arm, score, q0)
    if centre is None:
        return np.array([best_variant(arm, q, score, q0, only) for q in Q])
    K = _turns_towards(arm, Q, centre, only)
    failed = np.any(K, axis=1) & ~only.keeps(arm, Q + TWO_PI * K) if only.checks else None
    if failed is None or not failed.any():
        return Q + TWO_PI * K if K.any() else Q
    out = Q + TWO_PI * K  # a turn that fails a check: the best of the row's turns that pass
    for i in np.flatnonzero(failed).tolist():
        out[i] = best_kept(arm, Q[i], score, q0, only)
    return out


def _turn_centre(arm: ArmModel, score: Score, q0: np.ndarray) -> np.ndarray | None:
    """Per joint, the value the named per-joint scores want each joint's turn nearest:
    q0 (``nearest``), the reference (``Posture``), the middle of the range (``limits``);
    each joint's term grows with the distance from it, so the best turn is the nearest
    one. None for other scores."""
    if isinstance(score, Nearest):
        return q0
    if isinstance(score, Posture) and score.q_ref.size == arm.dof:
        return score.q_ref
    if isinstance(score, Limits):  # an unlimited joint has no middle: NaN, as no centre
        middle = np.full(arm.dof, np.nan)
        bounded = np.isfinite(arm.lower) & np.isfinite(arm.upper)
        middle[bounded] = (arm.lower[bounded] + arm.upper[bounded]) / 2.0
        return middle
    return None


def _turns_towards(
    arm: ArmModel, Q: np.ndarray, centre: np.ndarray, turn: Turning = ANY
) -> np.ndarray:
    """For configurations ``Q`` (rows, or one), the whole turns of 2 pi that bring each
    joint ``turns`` lets turn nearest ``centre`` within its limits (0 for the others)."""
    bounded = np.isfinite(arm.lower) & np.isfinite(arm.upper)
    unlimited = np.isneginf(arm.lower) & np.isposinf(arm.upper)  # continuous: any turn
    free = (bounded & (arm.upper - arm.lower > TWO_PI)) | (unlimited & np.isfinite(centre))
    free &= ~np.array(arm._limit_lists[2], bool) & turn.free(arm.dof)
    if not free.any():
        return np.zeros_like(Q)
    with np.errstate(invalid="ignore"):  # the unlimited joints' bounds: masked below
        k = np.round((centre - Q) / TWO_PI)
        k = np.clip(k, np.ceil((arm.lower - Q) / TWO_PI), np.floor((arm.upper - Q) / TWO_PI))
    return np.where(free, k, 0.0)


def rank(
    arm: ArmModel,
    results: list[IKResult],
    score: Score,
    q0: np.ndarray,
    t0: float,
    known: dict | None = None,
    count: int | None = None,
    turn: Turning = ANY,
) -> list[IKResult]:
    """The successes of ``results``, each as its best 2 pi variant, best ``score`` first
    (ties: in the order found), then the failures as they were; each success carries its
    score in ``extra["score"]`` and the score's name in its reason. ``known``: as for
    ``ordered``; ``count``: the first ``count`` results only (all ranked all the same);
    ``turn``: the turns the request allows."""
    scored = ordered(arm, results, score, q0, known, turn)
    elapsed = time.perf_counter() - t0
    n = len(scored)
    ranked = [  # each one's words written on first read, as its own are
        IKResult._from_fields(
            {
                **{k: v for k, v in r.__dict__.items() if k not in _WORDS},
                "q": q,
                "_reason": (_ranked_words, (r, score, value, n, q is not r.q)),
                "time": elapsed,
            }
        )
        for value, r, q in scored[:count]
    ]
    for one, (value, r, _) in zip(ranked, scored):
        one.extra.update(r.extra, score=value)
    return (ranked + [r for r in results if not r.success])[:count]


_WORDS = ("reason", "_reason", "extra")


def _ranked_words(r: IKResult, score: Score, value: float, n: int, turned: bool) -> str:
    return reasons.ranked_first(r.reason, score.name, score.words(value), n, turned)


def ordered(
    arm: ArmModel,
    results: list[IKResult],
    score: Score,
    q0: np.ndarray,
    known: dict | None = None,
    turn: Turning = ANY,
) -> list[tuple[float, IKResult, np.ndarray]]:
    """(score, result, its best 2 pi variant) for each distinct success of ``results``,
    best first (ties: in the order found). ``known``: scores by answer, read and filled in
    (a search that ranks its answers again with the ones it moved scores each once)."""
    known = {} if known is None else known
    found = [r for r in results if r.success]
    variants = _variants(arm, found, score, q0, turn)
    scored: list[tuple[float, int, IKResult, np.ndarray]] = []
    seen: set[tuple[float, ...]] = set()
    for r, q, row in zip(found, variants, np.round(variants, 9).tolist()):
        key = tuple(row)
        if key not in seen:
            seen.add(key)
            value = known.get(key)
            if value is None:
                value = known[key] = score(arm, q, q0)
            scored.append((value, len(scored), r, q))
    scored.sort(key=lambda item: (item[0], item[1]))
    kept: list[np.ndarray] = []  # one solution found twice (a copy moved a little) counts once
    out = []
    for value, _, r, q in scored:
        if all(np.abs(q - other).max() >= DUPLICATE_TOL for other in kept):
            kept.append(q)
            out.append((value, r, q))
    return out


def _variants(
    arm: ArmModel, found: list[IKResult], score: Score, q0: np.ndarray, turn: Turning
) -> list:
    """Each answer's best 2 pi variant (``best_variant``, of the turns ``turn`` allows):
    its own read-only ``q`` where no joint turns, else a new read-only array; for the named
    per-joint scores at once."""
    qs = [r.q for r in found]
    centre = _turn_centre(arm, score, q0) if score.turns_matter and qs else None
    if centre is None:
        out = []
        for q in qs:
            v = best_variant(arm, q, score, q0, turn)
            if v is not q and np.array_equal(v, q):
                v = q
            elif v is not q:
                v = np.array(v, dtype=float)
                v.flags.writeable = False
            out.append(v)
        return out
    Q = np.array(qs)
    K = _turns_towards(arm, Q, centre, turn)
    failed = np.zeros(len(Q), dtype=bool)
    if turn.checks:  # turns that fail a check: the best of the answer's that pass
        failed = np.any(K, axis=1) & ~turn.keeps(arm, Q + TWO_PI * K)
        K[failed] = 0.0
    turned: list = np.any(K, axis=1).tolist()
    if not any(turned) and not failed.any():
        return qs
    moved = Q + TWO_PI * K
    for i in np.flatnonzero(failed).tolist():
        moved[i] = best_kept(arm, qs[i], score, q0, turn)
        turned[i] = not np.array_equal(moved[i], qs[i])
    moved.flags.writeable = False
    return [moved[i] if turned[i] else q for i, q in enumerate(qs)]


SWEEP_GRID = 32  # values of the held joint over its range, before the refinement
REFINE_STEPS = 12  # golden-section steps between a grid value's neighbours
REFINED = 3  # the grid's least values (of any branch) refined, best first
PROBED = 2  # the grid's dips of the limit violation searched for a narrow interval
EDGES = 2  # the cells where a branch's reach ends, outside the limits, searched as dips
RESCORED = 4  # the best values of joint 7 tried, scored again by every branch there
EDGE_STEPS = 6  # bisection steps to each edge of a narrow interval found


def sweep_held(
    arm: ArmModel,
    target,
    q0: np.ndarray,
    opts,
    score: Score,
    t0: float,
    turn: Turning = ANY,
    solver: str = "auto",
):
    """On a 7R arm the ``swept`` closed form applies to: the self-motion searched for the
    score, joint 7 on a grid over its range, then refined by golden section around the
    grid's best local minima (a minimum at the edge of a reachable interval among them),
    and narrow reachable intervals the grid steps over sought where the branches' limit
    violation dips between grid values, or in a cell where a branch's reach ends
    (``_reach_edges``: it may fall to 0 there, though it falls on toward the next value);
    every branch in closed form at each value, scored at its best 2 pi variant; the
    ``RESCORED`` best values tried scored again by every branch there, the best one's
    configurations verified (``finish``). None where it does not apply (or ``solver``,
    where not "auto", sweeps no joint)."""
    spec = next(
        (
            s
            for s in registry.sweeps()
            if solver in ("auto", s.name)
            and (s.declines(opts, target=target) or s.why_not(arm, target, opts)) is None
        ),
        None,
    )
    if spec is None or spec.sweep is None:
        return None
    sweep = spec.sweep
    lo, hi = (float(x) for x in sweep.range(arm, float(q0[sweep.joint])))

    exact = sweep.exact(arm, target, q0)
    # each row's branch where the sweep tells it (each followed alone), else one for all
    branches = getattr(exact, "branches", None) or partial(_one_branch, exact)
    lower, upper = arm.lower - LIMIT_TOL, arm.upper + LIMIT_TOL  # ``within_limits``' bounds
    # a turn of 2 pi changes the score only on a joint whose range holds one (the Panda's do not)
    span = np.where(
        np.isfinite(arm.lower) & np.isfinite(arm.upper), arm.upper - arm.lower, math.inf
    )
    turns_matter = score.turns_matter and bool(((span > TWO_PI) & turn.free(arm.dof)).any())

    def at(theta: float, only: frozenset | None = None) -> dict[int, tuple[float, float]]:
        """Per branch at joint 7 = ``theta`` (those of ``only`` where given): (its best
        score within the limits, inf where it is outside them; its smallest limit
        violation, 0 within them). A branch not reached there is absent. (Loops, not
        comprehensions: the search calls it about a hundred times.)"""
        Q, labels = branches(theta)
        if only is not None:
            keep, kept = [], []
            for i, b in enumerate(labels):
                if b in only:
                    keep.append(i)
                    kept.append(b)
            Q, labels = Q[keep], kept
        if not len(Q):
            return {}
        over = np.maximum(np.maximum(lower - Q, Q - upper).max(axis=1), 0.0)
        if turn.checks:  # a row a constraint of the request refuses: none to search for
            over[~turn.keeps(arm, Q)] = math.inf
        inside = over <= 0.0
        values = np.full(len(Q), math.inf)
        if inside.any() and not turns_matter:  # every row as it is: the score's array form
            values[inside] = score.many(arm, Q[inside], q0)
        elif inside.any():
            for i in np.flatnonzero(inside).tolist():
                values[i] = score(arm, best_variant(arm, Q[i], score, q0, turn), q0)
        out: dict[int, tuple[float, float]] = {}
        for b, v, o in zip(labels, values.tolist(), over.tolist()):
            old = out.get(b)
            out[b] = (v, o) if old is None else (min(old[0], v), min(old[1], o))
        return out

    def on(group: frozenset, part: int) -> Callable[[float], float]:
        """The best score (``part`` 0) or the least violation (1) of ``group``'s branches."""
        return lambda theta: min([x[part] for x in at(theta, group).values()], default=math.inf)

    grid = [float(t) for t in np.linspace(lo, hi, SWEEP_GRID)]
    found = [at(t) for t in grid]
    seen = [(v, t) for got, t in zip(found, grid) for v, _ in got.values()]  # (score, value)
    n = len(grid)

    def around(k: int) -> tuple[float, float]:
        return grid[max(k - 1, 0)], grid[min(k + 1, n - 1)]

    lows = _turning_points(found, 0)  # of each branch's score: its least values
    dips = _turning_points(found, 1)  # of its limit violation, where it is outside them
    for _, k, group in lows[:REFINED]:
        seen += golden(on(group, 0), *around(k), REFINE_STEPS)
    for _, k, group in dips[:PROBED]:
        seen += _narrow(on(group, 1), on(group, 0), *around(k))
    for _, k, j, group in _reach_edges(found)[:EDGES]:
        seen += _narrow(on(group, 1), on(group, 0), grid[min(j, k)], grid[max(j, k)])
    # a group's search scored its group alone: the best values tried, by every branch there
    top = sorted(seen, key=itemgetter(0))[:RESCORED]
    seen = [(min([v for v, _ in at(t).values()], default=math.inf), t) for _, t in top]
    value, theta = min(seen, key=itemgetter(0), default=(math.inf, 0.0))  # ties: first tried
    if not math.isfinite(value):
        return []
    answers = sweep.at_value(arm, target, q0, theta)
    return finish(arm, spec.name, answers, target, opts, q0, True, t0)


def _one_branch(exact: Callable[[float], np.ndarray], theta: float) -> tuple:
    """``exact``'s configurations at ``theta``, all of one branch (a sweep without any)."""
    Q = exact(theta)
    return Q, [0] * len(Q)


def _turning_points(found: list[dict], part: int) -> list[tuple]:
    """(value, k, group) where the grid's values ``found`` (per branch, its score and its
    limit violation: ``part`` 0 or 1) have a least value at the k-th: of the group's best
    score where it is within the limits (0), or of its violation where it is not (1);
    smallest first."""
    out = []
    for group, score, over in _groups(found, part):
        f = over if part else score  # a violation's neighbours within the limits: 0
        padded = np.concatenate(([math.inf], f, [math.inf]))
        least = np.isfinite(f) & (f <= padded[:-2]) & (f <= padded[2:])
        if part:  # out of the limits there, reached
            least &= (score == math.inf) & (f > 0.0)
        out += [(float(f[k]), k, group) for k in np.flatnonzero(least).tolist()]
    out.sort(key=itemgetter(0, 1))
    return out


def _reach_edges(found: list[dict]) -> list[tuple]:
    """(violation, k, j, group) where the grid's k-th value reaches the group's branches
    outside the limits and its neighbour, the j-th, does not reach them: the cell holds
    the edge of their reachable interval, where the joints move fast (two branches meet
    there), and may hold a narrow interval within the limits that no dip shows; least
    violation first."""
    out = []
    for group, score, over in _groups(found, 1):
        outside = np.isfinite(over) & (over > 0.0) & (score == math.inf)
        for k in np.flatnonzero(outside).tolist():
            out += [
                (float(over[k]), k, j, group)
                for j in (k - 1, k + 1)
                if 0 <= j < len(over) and over[j] == math.inf
            ]
    out.sort(key=itemgetter(0, 1, 2))
    return out


def _groups(found: list[dict], part: int) -> Iterator[tuple]:
    """(group, score, violation) over the grid's values ``found``: branches of the same
    values (``part`` 0: scores, 1: violations) on the whole grid (a wrist's flip, which a
    score or the limits may not tell apart) form one group, each value their best."""
    labels = sorted(set().union(*found))
    values = np.full((2, len(found), len(labels)), math.inf)  # score, violation
    for k, got in enumerate(found):
        for j, b in enumerate(labels):
            if b in got:
                values[:, k, j] = got[b]
    groups: dict[bytes, list[int]] = {}
    for j, column in enumerate(np.round(values[part], 12).T):
        groups.setdefault(column.tobytes(), []).append(j)
    for members in groups.values():
        score, over = values[:, :, members].min(axis=2)
        yield frozenset(labels[j] for j in members), score, over


def golden(fn, a: float, b: float, steps: int, until: float = -math.inf) -> list:
    """(fn(x), x) at each value ``swept_7r.golden_search`` tries: driven here, where
    ``fn`` is (no call against the imports)."""
    out: list[tuple[float, float]] = []
    for x in golden_search(a, b, steps, out, until):
        out.append((fn(x), x))
    return out


def dip_within(violation, a: float, b: float) -> float | None:
    """``swept_7r.dip_within`` of a violation this module measures."""
    least, x = min(golden(violation, a, b, DIP_STEPS, until=0.0), key=itemgetter(0))
    return x if least <= 0.0 else None


def _narrow(
    violation: Callable[[float], float], best_at: Callable[[float], float], a: float, b: float
) -> list:
    """(score, x) of values tried in a narrow interval within [a, b] where a branch is
    within the limits, where its limit violation dips between grid values: a value with
    none (``swept_7r.dip_within``), then each edge of its interval by bisection and the
    score's golden section between them; [] where the violation stays above 0."""
    inside = dip_within(violation, a, b)
    if inside is None:
        return []
    edges = []
    for out in (a, b):  # from the value inside toward each end (out of reach or limits)
        x_in, x_out = inside, out
        for _ in range(EDGE_STEPS):
            mid = (x_in + x_out) / 2.0
            if math.isfinite(best_at(mid)):
                x_in = mid
            else:
                x_out = mid
        edges.append(x_in)
    return [(best_at(inside), inside), *golden(best_at, edges[0], edges[1], REFINE_STEPS)]
