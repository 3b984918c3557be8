"""The rank stage: a request with a score (``prefer=``), its answers ranked by it.

On a 7R arm the swept closed form applies to, the self-motion is searched for the score
(every solution has some value of joint 7) with the plain answer beside it; else the
answers ``solve_all`` finds, and where a numeric solver found them, those of starts near
q0 too (``prefer_near.near_answers``), the best moved along the self-motion on a redundant arm
(``_along_self_motion``). A task list without a compiled form is solved by the task
solver, its answer scored."""

from __future__ import annotations

import math
import time

import numpy as np
import pinocchio as pin

from armik import cpu_time, reasons
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.request import Request
from armik.result import IKResult
from armik.solve import prefer_near
from armik.solve.nullspace import descend
from armik.solve.prefer import ordered, rank, sweep_held
from armik.solve.stages import run
from armik.solve.task_solve import solve_problem
from armik.solve.turning import turning
from armik.solvers import registry
from armik.solvers.answers import Answers, one, stacked
from armik.status import Status
from armik.verify.verdict import finish


def preferred(arm: ArmModel, req: Request):
    """The best answer to ``req`` by its score (with ``req.every``, every answer found,
    best first); see the module."""
    target, q0, solver, _, _, _, every, t0, score, problem = req[:10]
    opts = req.settings
    # a full pose (read parsed the target): what the swept search and the descent hold
    pose = (
        problem is None
        and getattr(target, "rotation", None) is not None
        and getattr(target, "aim", None) is None  # a cone: a region
        and _plain_pose(opts)
    )
    seed = arm.seed(q0)  # read once: a q0 outside the limits is said once, clipped
    # every stage below reads the clipped seed (q0 None stays None: no start was given)
    plain = req.but(score=None, problem=None, **({} if q0 is None else {"q0": seed}))
    turn = turning(arm, req.opts, seed)  # the turns of an answer its constraints allow
    swept = None
    if pose and (solver == "auto" or registry.get(solver).sweep is not None):
        swept = sweep_held(arm, target, seed, opts, score, t0, turn, solver)
    if swept and any(r.success for r in swept):
        # every answer the plain request finds, ranked with the search's (one without every)
        first = run(arm, plain.but(every=every, t0=time.perf_counter()))
        ranked = rank(arm, [*(first if every else [first]), *swept], score, seed, t0, turn=turn)
        return ranked if every else ranked[0]
    budget = opts.iteration_budget
    if budget is None:
        share = plain.narrowed(timeout=opts.timeout * prefer_near.GATHER)
    else:
        share = plain.narrowed(iteration_budget=max(int(budget * prefer_near.GATHER_ITERATIONS), 1))
    if problem is None:  # what the search runs, loaded (or compiled) before its clock starts
        _load(arm, share.but(every=True))
        if pose:  # and the single descents from starts near q0
            _load(arm, plain.narrowed(max_restarts=0).but(every=False))
    # the shares' deadlines, in the budget's own time (the thread's CPU time), from here
    clock = cpu_time.thread_time()
    share = share.but(t0=time.perf_counter())
    if problem is None:  # solve_all's answers
        found = run(arm, share.but(every=True))
    else:  # the task solver's one answer, on the whole budget: nothing else is searched;
        # a secondary posture's move along the tasks' null space follows the preference
        whole = plain.but(problem=problem, every=False, t0=time.perf_counter())
        found = [solve_problem(arm, whole, score if opts.posture is not None else None)]
    # the task solver's one answer is no registered solver's: scored as it is
    searched = problem is None and bool(found) and registry.get(found[0].solver).kind == "numeric"
    if searched and pose:  # one descent from each start, by the solver that searched
        once = plain.narrowed(max_restarts=0).but(solver=found[0].solver, every=False)

        def solve_from(start: np.ndarray) -> IKResult:
            return run(arm, once.but(q0=start, t0=time.perf_counter()))  # type: ignore[no-any-return]

        middle = prefer_near.centre(arm, score, seed)
        found = [*found, *prefer_near.near_answers(arm, solve_from, middle, opts, clock)]
    known: dict = {}  # each answer's score, computed once
    if arm.dof > 6 and pose:
        best = [q for _, _, q in ordered(arm, found, score, seed, known, turn)]
        if best:
            solver_found = found[0].solver
            moved = _along_self_motion(
                arm, target, seed, opts, score, best, solver_found, t0, clock
            )
            found = [*moved, *found]
    count = (opts.max_solutions if searched else None) if every else 1
    ranked = rank(arm, found, score, seed, t0, known, count, turn)
    return ranked if every else ranked[0]


def _load(arm: ArmModel, req: Request) -> None:
    """``req`` run once per arm and options for one iteration: the kernels it loads (or
    compiles) on a process's first use, loaded outside the time the preference's stages
    share, so that a first call answers as every later one."""
    loaded = _LOADED(arm)
    if req.key is None or (req.key, req.every) in loaded:
        return
    if len(loaded) > 256:  # bounded, as the kept options are
        loaded.clear()
    loaded.add((req.key, req.every))
    run(arm, req.narrowed(iteration_budget=1).but(t0=time.perf_counter()))


_LOADED: Derived[set] = Derived("requests a preference ran once", lambda _: set())


def _plain_pose(opts) -> bool:
    """Whether the options ask for the plain pose: no bounds, weights, held joint or
    collisions (what the swept search and the self-motion descent assume; the target's
    aim is the caller's to check)."""
    return not (
        opts.bounds is not None
        or opts.weights
        or opts.position_only
        or opts.obstacles  # ``opts.collisions``, from its fields
        or opts.self_collision
        or opts.hold
        or opts.swivel is not None
    )


def _along_self_motion(
    arm, tgt, seed, opts, score, best: list, solver: str, t0: float, clock: float
) -> list[IKResult]:
    """A redundant arm's best answers (``prefer_near.DESCENTS`` distinct ones of ``best``, the
    configurations best first) each moved along its self-motion to a lower score
    (``armik.solve.nullspace``) until ``prefer_near.DESCENT_UNTIL`` of the budget has passed
    since ``clock`` (the thread's CPU time), verified
    again as ``solver``'s: the moved answers, to be ranked with the rest."""
    pose = pin.SE3(tgt.rotation, tgt.position)
    claims: list[Answers] = []
    for q in prefer_near.distinct(best, prefer_near.DESCENTS):
        left = prefer_near.DESCENT_UNTIL * opts.timeout - (cpu_time.thread_time() - clock)
        if opts.iteration_budget is not None:  # deterministic: the descent's own step cap
            left = math.inf
        elif left <= 0.0:
            break
        moved = descend(arm, q, pose, score, seed, left, ends=[c.q[0] for c in claims])
        claims.append(one(moved, Status.CONVERGED, reasons.SELF_MOTION))
    return (
        finish(arm, solver, stacked(claims, arm.dof), tgt, opts, seed, True, t0) if claims else []
    )
