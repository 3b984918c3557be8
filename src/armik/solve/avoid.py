"""Solves with collisions checked (options ``obstacles``, ``self_collision``, ``margin``)
or a user's own checks (``checks``): where the verdict refuses an answer the solver
claimed, the search goes on.

Every answer gets the verdict of any solve (FK, limits and the user's checks), then the
collision check (``armik.constraints.clear``): a success must keep every checked pair
``margin`` apart. A closed form's branches, from one run of its kernel, are checked nearest
the seed first, and the first collision-free verified one is the answer. A numeric solver
whose claimed answer the verdict refuses (it collides, or breaks a check) is run again from
a random configuration, within what is left of the budget (``timeout`` or
``iteration_budget``, and ``max_restarts``); when none holds, the result is the best
failure (``Status.COLLISION`` naming the closest pair, or the check's status and words).

On a path (``solve_path``), a numeric answer that reaches the pose but collides is first
slid out of contact (``solve.slide``: damped least squares on the pose with each close
pair a velocity damper on the step), near the previous waypoint's answer, then restarted
if that fails. Single solves and batches restart at once: sliding measured slower there
for no more successes (docs/collisions.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from armik import cpu_time, reasons
from armik.constraints.clear import Collisions, collision_check, distances
from armik.constraints.collision import checker
from armik.frozen import frozen
from armik.model.derived import Derived
from armik.solve import push
from armik.solve.slide import slide
from armik.solvers.answers import Answers, one
from armik.status import Status
from armik.verify.distances import with_distances
from armik.verify.measure import measure
from armik.verify.verdict import (
    decide_one,
    nearest_first,
    ranked,
    seed_distance,
    verdicts,
)
from armik.verify.verdicts import Verdicts, joined

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel
    from armik.problem.settings import SolverSettings
    from armik.solvers.registry import SolverSpec


@dataclass(frozen=True)
class First:
    """The plain solve ``solve`` tries first, done already: a numeric solver's first run,
    its verdict and the thread's CPU time when it started (the budget counts it)."""

    row: Verdicts  # one row
    started: float


def solve_avoiding(
    arm: ArmModel,
    spec: SolverSpec,
    target,
    seed: np.ndarray,
    opts: SolverSettings,
    clear: Collisions | None,
    every: bool,
    t0,
    first: First | None = None,
    slide_first: bool = False,
):
    """The verified results of ``spec`` for ``target`` (best first; the first only unless
    ``every``), each kept ``clear`` of collisions (None: only the verdict's checks); a
    numeric solver goes on from ``first`` when given, and with ``slide_first`` (the option
    ``slide``) slides its first colliding answer out of contact before it restarts."""
    check = None if clear is None else checker(arm, clear.obstacles, clear.self_collision)
    margin = math.inf if clear is None else clear.margin
    if not seed.flags.writeable:  # a read-only seed (a result's q) is another kernel type
        seed = seed.copy()
    if every:  # every answer's verdict, then the collision check of the N of them
        answers = spec.run(arm, target, seed, opts, True)
        found = verdicts(arm, answers, target, opts)
        if check is not None:
            found.judge(collision_check(check, answers.q, margin))
    elif spec.kind == "analytic":
        answers = spec.run(arm, target, seed, opts, True)
        found = _first_free(arm, answers, target, opts, check, margin, seed)
    else:
        if first is None:
            _load(arm, spec, target, seed, opts)
        runs = _restarting(arm, spec, target, seed, opts, check, margin, first, slide_first)
        if runs is None:
            return []
        found = runs
    results = ranked(found, spec.name, seed, every, t0)
    # measured apart (weights, a region: bounds or an aim): the true distances beside
    if opts.weights is not None or opts.bounds is not None or target.aim is not None:
        return with_distances(arm, results, target, opts)
    return results


def _checked(arm, answers, i: int, target, opts: SolverSettings, check, margin) -> Verdicts:
    """The verdict of answer ``i`` of ``answers`` with its collision check."""
    found = decide_one(arm, answers.take([i]), measure(arm, answers.q[i], target, opts), opts)
    return found if check is None else found.judge(collision_check(check, found.q, margin))


def _first_free(arm, answers, target, opts: SolverSettings, check, margin, seed) -> Verdicts:
    """Check the branches nearest the seed first (``nearest_first``); stop at the first
    verified, collision-free one."""
    rows = []
    for i in nearest_first(arm, answers, seed):
        row = _checked(arm, answers, i, target, opts, check, margin)
        rows.append(row)
        if row.succeeded(0):
            return row
    return joined(rows, arm.dof) if rows else verdicts(arm, answers, target, opts)


def _restarting(
    arm,
    spec,
    target,
    seed: np.ndarray,
    opts: SolverSettings,
    check,
    margin: float,
    first: First | None,
    slide_first: bool,
) -> Verdicts | None:
    """Run the numeric solver, from the seed (or go on from its ``first`` run) then from
    random configurations, while the verdict refuses the answer it claims (it collides by
    ``check``, or breaks the verdict's checks) and the budget lasts; the rows of every run
    (None: the budget was spent before the first), or the verified run's row alone. A
    restart's answer that the solver claims and that collides gets its verdict only if no
    free answer follows (``_Deferred``): the search goes on at once."""
    start_cpu = cpu_time.thread_time() if first is None else first.started
    rng = np.random.default_rng(opts.seed)
    lo, hi = arm.sampling_box()  # ``arm.random_q(rng)``'s draws, the box found once:
    span, dof = hi - lo, arm.dof  # ``rng.uniform(lo, hi)``'s own arithmetic, 7x cheaper
    used_iterations = used_restarts = 0
    rows: list[Verdicts | _Deferred] = []
    q_start = seed
    for run in range(opts.max_restarts + 1):
        if run == 0 and first is not None:
            row = first.row
            if row.extra is None and check is not None:  # its distance measured here
                row.judge(collision_check(check, row.q, margin))
        else:
            left = _left(opts, start_cpu, used_iterations, used_restarts)
            if left is None:
                break
            answers = spec.run(arm, target, q_start, left, False)
            measured = None  # a claimed answer's (distance, pair), measured once
            claimed = len(answers) == 1 and answers.claim.item(0) == _CONVERGED
            if run > 0 and claimed and check is not None:
                distance, pair = measured = check.distance(answers.q[0])
                if distance < margin:  # claimed, colliding: on to the next start
                    used_iterations += int(answers.iterations[0])
                    used_restarts += int(answers.restarts[0]) + 1
                    rows.append(
                        _Deferred(answers, left, distance, pair, used_iterations, used_restarts)
                    )
                    q_start = lo + span * rng.random(dof)
                    continue
            found = verdicts(arm, answers, target, left)
            if len(found) > 1:
                best = min(
                    range(len(found)),
                    key=lambda i: (not found.succeeded(i), seed_distance(answers.q[i], seed)),
                )
                found = found.take([best])
            if measured is not None:
                row = found.judge(distances([measured], margin))
            elif check is not None:
                row = found.judge(collision_check(check, found.q, margin))
            else:
                row = found
        used_iterations += int(row.answers.iterations[0])
        used_restarts += int(row.answers.restarts[0]) + (run > 0)
        row = row.recounted(used_iterations, used_restarts)
        if row.succeeded(0):  # the first free answer: the one the rows rank first
            return row
        rows.append(row)
        colliding = int(row.status[0]) == _COLLISION  # (a result's row claims its status)
        if not colliding and row.answers.claim.item(0) != _CONVERGED:
            break  # the solver itself found nothing within what was left
        if run == 0 and slide_first and colliding:
            # the first answer only: it starts from the seed (a path's previous answer);
            # a restart's lands anywhere, where sliding buys no continuity
            slid = _slid(arm, target, row, opts, check, margin, start_cpu, used_iterations)
            if slid is not None:
                used_iterations = int(slid.answers.iterations[0])
                slid = slid.recounted(used_iterations, used_restarts)
                if slid.succeeded(0):
                    return slid
                rows.append(slid)
        elif run == 0 and PUSH and colliding:
            got = _pushed(arm, spec, target, row, opts, check, margin, start_cpu, used_iterations)
            used_iterations = got[1]
            rows.extend(p.recounted(used_iterations, used_restarts) for p in got[0])
            if got[0] and got[0][-1].succeeded(0):
                return rows[-1]  # type: ignore[return-value]
        q_start = lo + span * rng.random(dof)
    if not rows:
        return None
    built = [r.row(arm, target, margin) if type(r) is _Deferred else r for r in rows]
    return joined(built, arm.dof)  # type: ignore[arg-type]


_CONVERGED, _COLLISION = Status.CONVERGED.code, Status.COLLISION.code


def _load(arm: ArmModel, spec: SolverSpec, target, seed: np.ndarray, opts: SolverSettings):
    """Load (or compile) a numeric solver's kernel before the budget's clock starts: one
    iteration, once per arm and kind of target, as the collision search's first plain solve
    does (a first call in a process then searches as later ones)."""
    loaded = _LOADED(arm)
    kind = (spec.name, target.rotation is None, opts.bounds is not None or target.aim is not None)
    if kind not in loaded:
        once = frozen(type(opts), **{**opts.__dict__, "max_restarts": 0, "iteration_budget": 1})
        spec.run(arm, target, seed.copy(), once, False)
        loaded.add(kind)


_LOADED: Derived[set] = Derived("numeric solvers run once before a search", lambda _: set())


@dataclass(frozen=True)
class _Deferred:
    """A restart's claimed answer that collides, its verdict built only when the search
    ends without a free answer (its failure is then ranked among the others)."""

    answers: Answers  # one row
    left: SolverSettings  # the options it ran with
    distance: float
    pair: object
    iterations: int  # the search's counts after it
    restarts: int

    def row(self, arm, target, margin: float) -> Verdicts:
        found = verdicts(arm, self.answers, target, self.left)
        found.judge(distances([(self.distance, self.pair)], margin))
        return found.recounted(self.iterations, self.restarts)


# Push a numeric solve's colliding first answer clear with the servo's collision rows
# before restarting (``solve.push``). Off: on the Panda shelf scene a push and its descent
# cost more than the restarts they save (benchmarks/collision_near.py, docs/collisions.md).
PUSH = False


def _pushed(arm, spec, target, row: Verdicts, opts, check, margin, start_cpu: float, used: int):
    """([verdict, ...], iterations used): ``row``'s colliding answer pushed clear with the
    servo's rows (``solve.push``) and descended on from there without restarts, up to
    ``push.PUSHES`` times while the answer still collides and the budget lasts."""
    found: list[Verdicts] = []
    q = row.q[0]
    for _ in range(push.PUSHES):
        start = push.pushed(arm, check, q, margin)
        left = None if start is None else _left(opts, start_cpu, used, 0)
        if left is None:
            break
        left = frozen(type(left), **{**left.__dict__, "max_restarts": 0})
        answers = spec.run(arm, target, start, left, False)
        got = verdicts(arm, answers, target, left).judge(
            collision_check(check, answers.q[:1], margin)
        )
        used += int(answers.iterations[0])
        found.append(got)
        if got.succeeded(0) or int(got.status[0]) != Status.COLLISION.code:
            break
        q = got.q[0]
    return found, used


SLIDE_STEPS = 30  # steps of one slide, at most


def _slid(arm, target, row: Verdicts, opts, check, margin, start_cpu: float, used: int):
    """The verdict of ``row``'s answer slid out of contact, within what is left of the
    budget; None when nothing is left."""
    steps = SLIDE_STEPS
    if opts.iteration_budget is not None:
        steps = min(steps, opts.iteration_budget - used)
    if steps <= 0:
        return None
    deadline = math.inf if opts.iteration_budget is not None else start_cpu + opts.timeout
    tol = min(opts.tol_position, opts.tol_orientation) * 0.1
    q, taken = slide(arm, target, row.q[0], check, margin, steps, deadline, tol, opts)
    slid = one(q, Status.CONVERGED, reasons.SLID, iterations=used + taken)
    return _checked(arm, slid, 0, target, opts, check, margin)


def _left(
    opts: SolverSettings, start_cpu: float, iterations: int, restarts: int
) -> SolverSettings | None:
    """The options of the next run: what is left of the budget, or None when spent."""
    left = opts.budget.left(start_cpu, iterations, restarts)
    if left is None:
        return None
    seed = None if opts.seed is None else (opts.seed + restarts) % 2**63
    return frozen(type(opts), **{**opts.__dict__, "seed": seed, **left.said()})
