"""The one path from user input to verified results, shared by every solver."""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from armik import reasons
from armik.constraints.clear import distances
from armik.constraints.collision import checker
from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.options import Options, spelled, with_sight
from armik.problem.problem import Problem, as_problem, lower, rims, tightened
from armik.problem.scores import parse_score
from armik.problem.tasks import Pose, Position, Task
from armik.result import IKResult
from armik.solve import far, prefer
from armik.solve.avoid import First, solve_avoiding
from armik.solve.held import solve_held
from armik.solve.nullspace import descend
from armik.solve.prefer import rank, sweep_held
from armik.solve.prepared import plan_for
from armik.solve.swivel import solve_swivel
from armik.solve.tasks import CENTRE_RESTARTS, check_options, check_said_twice, solve_tasks
from armik.solvers import registry
from armik.solvers.answers import Answers, one, stacked
from armik.solvers.registry import SolverSpec
from armik.status import Status
from armik.targets.pose import Target, parsed
from armik.verify.verdict import finish
from armik.verify.verdicts import Verdicts


def solve(
    arm: ArmModel,
    target: object,
    *,
    q0: object = None,
    solver: str = "auto",
    all_solutions: bool = False,
    **options: object,
) -> list[IKResult]:
    """Parse, choose a solver, run it, verify every answer, rank: best first."""
    if not all_solutions:
        return [solve_one(arm, target, q0, solver, options)]
    return solve_one(arm, target, q0, solver, options, every=True)


def solve_one(
    arm: ArmModel, target: object, q0: object, solver: str, options: dict, every: bool = False
):
    """``solve(arm, target, q0=q0, solver=solver, **options)[0]`` (``Arm.solve``'s route),
    or with ``every`` the whole list of ``all_solutions=True``: the problem parsed (a
    preference taken out, a task list lowered to the compiled path's target and options
    where it has a form), then ranked by the preference, solved by the task solver, or
    solved as parsed (``solve_parsed``)."""
    t0 = time.perf_counter()
    score = None
    if "budget" in options:  # as its options, which the stages narrow (restarts, shares)
        options = spelled(options)
    if "prefer" in options:
        options = dict(options)
        score = parse_score(options.pop("prefer"))
    problem = None
    kind = type(target)  # the common poses first: ``Task``'s isinstance is an ABC's check
    if (
        kind is not _SE3
        and kind is not np.ndarray
        and (kind in (list, tuple) or isinstance(target, Task))
    ):
        problem = as_problem(target)
        if problem is not None:
            lowered = lower(problem, arm.tip)
            held = "hold" in options or "constraints" in options  # a call only then
            if lowered is not None and not (held and _held_apart(arm, options)):
                target, said = lowered
                check_said_twice(options, said, problem)
                options = {**options, **said}
                problem = None
    if problem is None and ("hold" in options or "constraints" in options):
        if _held_apart(arm, options):  # a plain pose or position: the task solver's task
            problem, options = _as_task(arm, target, options)
    if score is not None:
        return _preferred(arm, target, q0, solver, options, every, score, t0, problem)
    if problem is not None:
        one = _tasks(arm, problem, q0, solver, options, t0)
        return [one] if every else one
    opts, key, seed = _options(options)
    return _stages(arm, target, q0, solver, opts, key, seed, every, t0)


def _held_apart(arm: ArmModel, options: dict) -> bool:
    """Whether ``options`` hold joints the compiled path cannot (it holds one joint of a
    7-joint arm): the task solver holds them, as box rows of its steps."""
    count = _holds(options)[1]
    return count > 0 and (arm.dof != 7 or count != 1)


def _holds(options: dict) -> tuple[dict, int]:
    """(``options`` spelled out (``armik.options.spelled``) without their held joints, how
    many joints they hold); (``options``, 0) where they hold none."""
    if "hold" not in options and "constraints" not in options:
        return options, 0
    out = spelled(options) if "constraints" in options else dict(options)
    held = out.pop("hold", None)
    if held is None:
        return options, 0
    return out, len(held) if isinstance(held, Mapping) and held else 1


# options a plain target's tasks cannot say: with them the compiled path's error stands
_NOT_AS_TASK = ("weights", "bounds", "cone", "look_at", "toward")


def _as_task(arm: ArmModel, target: object, options: dict) -> tuple[Problem | None, dict]:
    """(problem, options): the problem of a plain pose or position (``armik.Pose``,
    ``armik.Position``; ``position_only`` said by the task), for the task solver to hold
    joints the compiled path cannot; (None, ``options``) where the options say more than
    such a task would (``_NOT_AS_TASK``): the compiled path's error then names the way."""
    if any(options.get(name) is not None for name in _NOT_AS_TASK):
        return None, options
    tgt = parsed(target, arm)
    if tgt.rotation is None or options.get("position_only"):
        rest = {k: v for k, v in options.items() if k != "position_only"}
        return as_problem(Position(tgt.position)), rest
    return as_problem(Pose(pin.SE3(tgt.rotation, tgt.position))), options


def solve_parsed(
    arm: ArmModel,
    target: object,
    q0: object,
    solver: str,
    options: dict,
    every: bool = False,
    t0: float | None = None,
):
    """The stages after parsing, for a target the compiled path takes (a pose, a position,
    a parsed ``Target``; no preference among ``options``): a held joint, the collision
    retry (``_clear_at_once``, then ``armik.solve.avoid``), the prepared plan, the general
    path. What paths, their rungs, a region's centre and a preference call for each answer
    (``solve_one`` without the parsing): the result, or with ``every`` the list."""
    t0 = time.perf_counter() if t0 is None else t0
    opts, key, seed = _options(options)
    return _stages(arm, target, q0, solver, opts, key, seed, every, t0)


def _stages(arm, target, q0, solver: str, opts: Options, key, seed, every: bool, t0: float):
    """``solve_parsed`` with the options validated (``_options``)."""
    if opts.swivel is not None:  # an SRS arm at one swivel angle
        return solve_swivel(arm, target, q0, solver, _with_seed(opts, seed), every, t0)
    if opts.hold is not None:
        target = parsed(target, arm)  # once: the held arm's solve and its verdict read it
        return solve_held(arm, target, q0, solver, _with_seed(opts, seed), every, t0, _general)
    if not every and (opts.obstacles or opts.self_collision):  # ``opts.collisions``, inline
        return _avoiding(arm, parsed(target, arm), q0, solver, opts, key, seed, t0)
    if far.first_use and not every:  # a target beyond reach: answered before any compile
        got = far.beyond_reach(arm, target, q0, solver, opts, t0)
        if got is not None:
            return got
    kind = type(target)  # a position, for the plan
    vector = (kind is np.ndarray and target.ndim == 1) or (
        kind is Target and target.rotation is None
    )
    plan = None if key is None else plan_for(arm, solver, key, opts, vector, every)
    if plan is not None and not every:
        got = plan.solve(target, q0, opts, seed, t0)
        if got is not None:
            return got
    elif plan is not None:
        found = plan.solve_all(target, q0, opts, seed, t0)
        if found is not None:
            return _beyond_search(arm, target, q0, solver, opts, seed, found, t0)
    results = _general(arm, target, q0, solver, _with_seed(opts, seed), every, t0)
    if every:
        return _beyond_search(arm, target, q0, solver, opts, seed, results, t0)
    return results[0]


def _preferred(
    arm, target, q0, solver: str, options: dict, every: bool, score, t0: float, problem=None
):
    """The rank stage with a score: on a 7R arm the swept closed form applies to, the
    self-motion searched for the score (every solution has some value of joint 7) with
    the plain answer beside it; else the answers solve_all finds, and where a numeric
    solver found them, those of starts near q0 too (``prefer.near_answers``), the best
    moved along the self-motion on a redundant arm (``_along_self_motion``). ``problem``:
    a task list without a compiled form (``target`` then), whose solve the task solver's."""
    opts = _validated(options)
    if problem is None:  # parsed once here: every answer ranked below is to this target
        target = parsed(target, arm)
    pose = problem is None and _plain_pose(opts)
    seed = arm.seed(q0)
    swept = None
    if pose and solver == "auto":
        swept = sweep_held(arm, target, seed, opts, score, t0)
    if swept and any(r.success for r in swept):
        plain = solve_parsed(arm, target, q0, solver, options)
        ranked = rank(arm, [plain, *swept], score, seed, t0)
        return ranked if every else ranked[0]
    budget = opts.iteration_budget
    share: dict = {"timeout": opts.timeout * prefer.GATHER}
    if budget is not None:
        share = {"iteration_budget": max(int(budget * prefer.GATHER_ITERATIONS), 1)}
    found = _found(arm, target, q0, solver, {**options, **share}, problem)
    searched = bool(found) and registry.get(found[0].solver).kind == "numeric"
    if searched and pose:  # one descent from each start, by the solver that searched

        def solve_from(start: np.ndarray) -> IKResult:
            once = {**options, "max_restarts": 0}
            return solve_parsed(arm, target, start, found[0].solver, once)  # type: ignore

        middle = prefer.centre(arm, score, seed)
        found = [*found, *prefer.near_answers(arm, solve_from, middle, opts, t0)]
    known: dict = {}  # each answer's score, computed once
    if arm.dof > 6 and pose:
        best = [q for _, _, q in prefer.ordered(arm, found, score, seed, known)]
        if best:
            moved = _along_self_motion(arm, target, seed, opts, score, best, found[0].solver, t0)
            found = [*moved, *found]
    count = (opts.max_solutions if searched else None) if every else 1
    ranked = rank(arm, found, score, seed, t0, known, count)
    return ranked if every else ranked[0]


def _found(arm, target, q0, solver: str, options: dict, problem) -> list[IKResult]:
    """The answers a preference ranks: ``solve_all``'s, or the task solver's one."""
    if problem is None:
        return solve_parsed(arm, target, q0, solver, options, True)  # type: ignore[no-any-return]
    return [_tasks(arm, problem, q0, solver, options, time.perf_counter())]


def _tasks(arm, problem, q0, solver: str, options: dict, t0: float) -> IKResult:
    """A task list without a compiled form: the task solver, from its centre's answer."""
    opts = _validated(options)
    check_options(opts, solver)
    problem = dataclasses.replace(problem, constraints=opts.constraints, budget=opts.budget)
    return solve_tasks(arm, problem, q0, opts, t0, _centre(arm, problem, q0, options))


def _validated(options: dict) -> Options:
    """``options`` as ``Options``, this call's seed in them."""
    opts, _, seed = _options(options)
    return _with_seed(opts, seed)


def _plain_pose(opts: Options) -> bool:
    """Whether the options ask for the plain pose: no region, weights, held joint or
    collisions (what the swept search and the self-motion descent assume)."""
    return not (
        opts.region
        or opts.weights
        or opts.position_only
        or opts.collisions
        or opts.hold
        or opts.swivel is not None
    )


def _along_self_motion(
    arm, target, seed, opts: Options, score, best: list, solver: str, t0: float
) -> list[IKResult]:
    """A redundant arm's best answers (``prefer.DESCENTS`` distinct ones of ``best``, the
    configurations best first) each moved along its self-motion to a lower score
    (``armik.solve.nullspace``) until ``prefer.DESCENT_UNTIL`` of the budget, verified
    again as ``solver``'s: the moved answers, to be ranked with the rest."""
    tgt = parsed(target, arm)
    pose = pin.SE3(tgt.rotation, tgt.position)
    claims: list[Answers] = []
    for q in prefer.distinct(best, prefer.DESCENTS):
        left = prefer.DESCENT_UNTIL * opts.timeout - (time.perf_counter() - t0)
        if opts.iteration_budget is not None:  # deterministic: the descent's own step cap
            left = math.inf
        elif left <= 0.0:
            break
        moved = descend(arm, q, pose, score, seed, left, ends=[c.q[0] for c in claims])
        claims.append(one(moved, Status.CONVERGED, reasons.SELF_MOTION))
    return (
        finish(arm, solver, stacked(claims, arm.dof), tgt, opts, seed, True, t0) if claims else []
    )


def _centre(arm, problem, q0, options: dict):
    """The compiled answer to the problem's centre (``tightened``), if it has a form: an
    answer to the problem itself, or a start for the task solver; else None. Where a
    closed form finds no answer at the centre, the nearest q0 of its answers on the
    region's rim (``rims``: a cone's axis tilted to its edge), if any reaches."""
    lowered = lower(tightened(problem), arm.tip)
    if lowered is None:
        return None
    target, said = lowered
    if _held_apart(arm, options):  # held joints the compiled path cannot hold: the task
        options = _holds(options)[0]  # solver's box
    restarts = min(options.get("max_restarts", CENTRE_RESTARTS), CENTRE_RESTARTS)
    centre = solve_parsed(arm, target, q0, "auto", {**options, **said, "max_restarts": restarts})
    if centre.success or registry.get(centre.solver).kind != "analytic":
        return centre  # a numeric miss shows nothing: the task solver goes on from it
    found = []
    for rim in rims(problem, RIM_SAMPLES):
        lowered = lower(rim, arm.tip)
        if lowered is not None:
            r = solve_parsed(arm, lowered[0], q0, "auto", {**options, **lowered[1]})
            found += [r] if r.success else []
    seed = arm.seed(q0)
    return min(found, key=lambda r: float(np.linalg.norm(r.q - seed)), default=centre)


def _beyond_search(arm, target, q0, solver: str, opts: Options, seed, results: list, t0: float):
    """``solve_all``'s ``results``, or where "auto" chose a search that verified nothing
    (a search's miss shows nothing about the target), the answer "auto" gives for one
    answer, with the search's miss in its reason."""
    if solver != "auto" or any(r.success for r in results) or not results:
        return results
    if registry.get(results[0].solver).complete:
        return results
    one = _general(arm, target, q0, solver, _with_seed(opts, seed), False, t0)[0]
    said = reasons.search_missed(results[0].solver, results[0].reason, one.solver, one.reason)
    return [dataclasses.replace(one, reason=said)]


RIM_SAMPLES = 8  # points on a region's rim tried where a closed form misses its centre
_NO_COLLISIONS = {"obstacles": (), "self_collision": False, "margin": 0.0}


def _avoiding(arm, target, q0, solver, opts: Options, key, seed, t0: float) -> IKResult:
    """A collision-checked solve: a closed form's branches from one run of its kernel,
    checked nearest first; a numeric solver's plain solve first (most answers are clear at
    once), then its restarts go on from that run."""
    plain = frozen(Options, **{**opts.__dict__, **_NO_COLLISIONS})
    tgt = parsed(target, arm)
    # chosen as without collisions (no solver reads them): remembered for these options
    spec = registry.choose(solver, arm, tgt, plain)
    first = None
    if spec.kind != "analytic":
        started, now = time.thread_time(), time.perf_counter()
        if key is None:  # options no plan is kept for (obstacles): the general path
            r = _run(arm, spec, tgt, q0, _with_seed(plain, seed), False, now)[0]
        else:  # the plan's key apart from the options' with collisions
            r = _stages(arm, target, q0, solver, plain, (key, "plain"), seed, False, now)
        clear, first = _clear_at_once(arm, r, opts, started, t0)
        if clear is not None:
            return clear
    return _run(arm, spec, tgt, q0, _with_seed(opts, seed), False, t0, first)[0]


def _clear_at_once(arm, r: IKResult, opts: Options, started: float, t0: float):
    """(result, first): a numeric solver's plain solve ``r`` (begun at thread CPU time
    ``started``) when its answer is a success and collision-free, with its distance and
    pair (the answer the collision-checked search starts with, as ``solve_batch``'s
    chunks), and None; else None and ``First``, that run for the search
    (``armik.solve.avoid``) to go on from."""
    if not r.success:
        return None, First(Verdicts.of_result(r, opts.tol_position, opts.tol_orientation), started)
    distance, pair = checker(arm, opts.obstacles, opts.self_collision).distance(r.q)
    if distance < opts.margin:
        row = Verdicts.of_result(r, opts.tol_position, opts.tol_orientation)
        return None, First(row.judge(distances([(distance, pair)], opts.margin)), started)
    clear = dataclasses.replace(
        r,
        reason=reasons.and_clear(r.reason, pair, distance, opts.margin),
        time=time.perf_counter() - t0,
        extra={"min_distance": distance, "closest_pair": pair},
    )
    return clear, None


def _general(arm, target, q0, solver: str, opts: Options, all_solutions: bool, t0: float):
    tgt = parsed(target, arm)
    spec = registry.choose(solver, arm, tgt, opts, all_solutions)
    return _run(arm, spec, tgt, q0, opts, all_solutions, t0)


def _run(arm, spec: SolverSpec, tgt: Target, q0, opts: Options, every: bool, t0: float, first=None):
    """The verified results of ``spec`` for the parsed target ``tgt`` (collisions checked
    where the options ask, a numeric solver going on from ``first`` when given)."""
    seed = arm.seed(q0)
    if opts.collisions:
        return solve_avoiding(arm, spec, tgt, seed, opts, every, t0, first)
    answers = spec.run(arm, tgt, seed, opts, every)
    return finish(arm, spec.name, answers, tgt, opts, seed, every, t0)


_OPTIONS: dict[tuple, Options] = {}


def _options(kwargs: dict) -> tuple[Options, tuple | None, int | None]:
    """(options, key, seed): ``Options.from_kwargs(kwargs)``, remembered under ``key``
    (None: not remembered) when the values other than ``seed`` are hashable, and this
    call's validated ``seed``. Validation costs a few us, and a loop of solves passes the
    same options, often with a new seed each time: the remembered options keep the seed
    they were first built with (``_with_seed`` gives them this call's). A look-at's point
    or an axis' direction (``look_at``, ``toward``), new in each of a loop of targets, is
    kept out of the key too, and written into this call's copy."""
    if not kwargs:
        return _DEFAULT, (), 0
    seed = kwargs.get("seed", 0)
    look = kwargs["look_at"] if "look_at" in kwargs else None  # lookups, not calls
    toward = kwargs["toward"] if "toward" in kwargs else None
    sight = look is not None or toward is not None
    if "seed" in kwargs or "look_at" in kwargs or "toward" in kwargs:
        kwargs = dict(kwargs)
        if "seed" in kwargs:
            del kwargs["seed"]
        if "look_at" in kwargs:
            del kwargs["look_at"]
        if "toward" in kwargs:
            del kwargs["toward"]
    try:
        # with the types: 1 == True, but validation may accept one and refuse the other
        key = (tuple(kwargs.items()), tuple(map(type, kwargs.values())), look is None, sight)
        opts = _OPTIONS.get(key)
    except TypeError:  # an unhashable value (a list of weights): validate every time
        opts = Options.from_kwargs({**kwargs, "seed": seed})
        return (with_sight(opts, look, toward) if sight else opts), None, _seed(seed)
    if opts is None:
        opts = Options.from_kwargs({**kwargs, "seed": seed})  # the seed checked with them
        if len(_OPTIONS) > 256:
            _OPTIONS.clear()
        _OPTIONS[key] = opts
    return (with_sight(opts, look, toward) if sight else opts), key, _seed(seed)


def _seed(seed: object) -> int | None:
    """``seed`` as ``Options.from_kwargs`` validates it."""
    if type(seed) is int and 0 <= seed < 2**63:
        return seed  # what the validation returns for a plain int
    return None if seed is None else Options.from_kwargs({"seed": seed}).seed


def _with_seed(opts: Options, seed: int | None) -> Options:
    """``opts`` with this seed (a copy, built without the frozen ``__init__``)."""
    if opts.seed == seed and type(opts.seed) is type(seed):
        return opts
    return frozen(Options, **{**opts.__dict__, "seed": seed})


_SE3 = pin.SE3
_DEFAULT = Options()  # frozen: shared by every call without options
