"""The stages of one request whose target the compiled path takes (a pose, a position, a
parsed ``Target``; no preference, no task list): a held joint, the collision retry, a
target beyond reach before anything compiles, the prepared plan, the general path: choose
(``armik.solvers.registry``), run, verify (``armik.verify.verdict``).

``run(arm, request)`` is the one entry: what ``solve`` and ``solve_all`` end in, and what
batches, paths, their rungs, a region's centre and a preference call for each answer,
each with its own copy of the request (``Request.but``). The prepared plan is these stages
with the choice kept: it hands what it cannot take to the general path.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any, NamedTuple, cast

import numpy as np
import pinocchio as pin

from armik import cpu_time, reasons
from armik.constraints.clear import distances, of_options
from armik.constraints.collision import Checker, checker
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.request import Request, but_options, with_seed
from armik.result import IKResult
from armik.solve import far, parameter
from armik.solve.avoid import First, solve_avoiding
from armik.solve.held import Held, solve_held
from armik.solve.prepared import kind_of, plan_for
from armik.solvers import registry
from armik.solvers.registry import SolverSpec
from armik.targets.pose import Target, parsed
from armik.verify.verdict import finish
from armik.verify.verdicts import Verdicts

_SE3 = pin.SE3


def chosen(arm: ArmModel, solver: str, key: tuple | None, opts, position: bool | None, aim=None):
    """The solver ``registry.choose`` gives for ``opts`` (all but ``seed``; ``key``: their
    request's, which holds the shape of an aim) and a target of that kind (``position``;
    None: no target) with ``aim``, "auto"'s kept per arm under ``key`` as a plan is (None:
    chosen every time): a batch's or a path's."""
    kind = None if position is None else _KIND[position] if aim is None else kind_of(position, aim)
    if key is None or solver != "auto":  # a solver named: looked up by its name
        return registry.choose(solver, arm, kind, opts)
    kept = arm._derived.get(_CHOSEN)  # read as a dict, not through a call: every batch
    if kept is None or kept["generation"] != registry.generation:
        kept = arm._derived[_CHOSEN] = {"generation": registry.generation}
    spec = kept.get((key, position))
    if spec is None:
        spec = registry.choose(solver, arm, kind, opts)
        if len(kept) > 64:
            kept = arm._derived[_CHOSEN] = {"generation": registry.generation}
        kept[(key, position)] = spec
    return spec


_CHOSEN: Derived[dict] = Derived("auto's choices", lambda _: {})
# a target of each kind (True: a position) without an aim: what the registry's choice reads
_KIND = {True: kind_of(True), False: kind_of(False)}


def run(arm: ArmModel, req: Request):
    """The verified result of ``req`` (a list of every solution with ``req.every``)."""
    target: Any
    target, q0, solver, opts, key, seed, every, t0 = req[:8]
    if opts.swivel is not None:  # a parameter a solver declares (an SRS arm's swivel)
        return parameter.solve_at(arm, req, "swivel", opts.swivel)
    if opts.hold is not None:
        target = parsed(target, arm)  # once: the held arm's solve and its verdict read it
        if opts.obstacles or opts.self_collision:  # every branch at the value, kept clear
            return _held_clear(arm, req, target)
        return solve_held(arm, req, target, general)
    if not every and (opts.obstacles or opts.self_collision):  # ``opts.collisions``, inline
        return _avoiding(arm, req)
    if far.first_use and not every:  # a target beyond reach: answered before any compile
        got = far.beyond_reach(arm, req)
        if got is not None:
            return got
    kind = type(target)  # a position, for the plan
    vector = (kind is np.ndarray and target.ndim == 1) or (
        kind is Target and target.rotation is None
    )
    aim = target.aim if kind is Target else None  # its shape is in the key (``read``)
    # collisions and a user's checks are the general path's (one answer with collisions
    # went to ``_avoiding`` above)
    plan = (
        None
        if key is None
        or opts.checks
        or (every and (opts.obstacles or opts.self_collision))
        or req.sweep_from is not None  # a sweep's start the plans do not take
        else plan_for(arm, solver, key, opts, vector, every, aim)
    )
    if plan is not None and not every:
        got = plan.solve(target, q0, opts, seed, t0)
        if got is not None:
            return got
    elif plan is not None and plan.every:
        found = plan.solve_all(target, q0, opts, seed, t0)
        if found is not None:  # a complete solver's answers are all there are
            return found if plan.complete else _beyond_search(arm, req, found)
    opts = with_seed(opts, seed)
    if plan is not None and solver == "auto":
        # "auto"'s plan holds the general path's choice for its kind of target (the
        # registry's choice reads a target for its kind only)
        target = parsed(target, arm)
        if (target.rotation is None) == plan.position:
            results = _run(arm, plan.spec, target, q0, opts, every, t0)
        else:
            results = general(arm, target, q0, solver, opts, every, t0)
    else:
        results = general(arm, target, q0, solver, opts, every, t0, req.sweep_from)
    if every:
        return _beyond_search(arm, req, results)
    return results[0]


def _held_clear(arm: ArmModel, req: Request, target: Target):
    """A held joint's solve with collisions checked: its answers at the held value (a closed
    form's branches, the locked arm's every solution) searched as a closed form's are, the
    nearest verified one that keeps clear of the whole arm's collision model first."""
    opts = with_seed(req.opts, req.seed)
    clear = of_options(opts)
    held = Held(req, general)
    found = solve_avoiding(arm, held, target, arm.seed(req.q0), opts, clear, req.every, req.t0)  # type: ignore[arg-type]
    return found if req.every else found[0]


def general(
    arm, target, q0, solver: str, opts, every: bool, t0: float, sweep_from: float | None = None
) -> list[IKResult]:
    """The general path: the solver chosen for the parsed target (its sweep started at
    ``sweep_from`` where given), run, verified."""
    tgt = parsed(target, arm)
    spec = registry.choose(solver, arm, tgt, opts, every)
    if sweep_from is not None:
        spec = registry.swept_from(spec, sweep_from)
    return _run(arm, spec, tgt, q0, opts, every, t0)


def _beyond_search(arm: ArmModel, req: Request, results: list) -> list:
    """``solve_all``'s ``results``, or where "auto" chose a search that verified nothing
    (a search's miss shows nothing about the target), the answer "auto" gives for one
    answer, with the search's miss in its reason."""
    if req.solver != "auto" or any(r.success for r in results) or not results:
        return results
    if registry.get(results[0].solver).complete:
        return results
    one = general(arm, req.target, req.q0, "auto", req.settings, False, req.t0)[0]
    said = reasons.search_missed(results[0].solver, results[0].reason, one.solver, one.reason)
    return [dataclasses.replace(one, reason=said)]


_NO_COLLISIONS = {"obstacles": (), "self_collision": False, "margin": 0.0}


class _Avoiding(NamedTuple):
    """What a collision-checked solve of one arm, solver, options (all but ``seed``) and
    target kind reads before its target: kept under the request's key, as a plan is."""

    spec: SolverSpec  # chosen as without collisions (no solver reads them)
    # the first such request without collisions: its options and plan key are the plain
    # solve's, tried first (each call puts in its own target, start and seed)
    plain: Request
    check: Checker


def _kept(arm: ArmModel, req: Request, position: bool) -> _Avoiding:
    """The ``_Avoiding`` of the request's options (its key: not None), built once per arm
    (registrations apart)."""
    solver, key = req.solver, req.key
    kept = arm._derived.get(_AVOIDING)  # read as a dict, not through a call: every solve
    if kept is None or kept.get("generation") != registry.generation:
        kept = arm._derived[_AVOIDING] = {"generation": registry.generation}
    found = kept.get((solver, key, position))
    if found is None:
        plain = req.narrowed(**_NO_COLLISIONS)
        aim = req.target.aim if type(req.target) is Target else None  # its shape: in the key
        kind = Target(np.zeros(3), None if position else np.eye(3), aim=aim)
        spec = registry.choose(solver, arm, kind, plain.opts)  # reads only the target's kind
        check = checker(arm, req.opts.obstacles, req.opts.self_collision)
        found = _Avoiding(spec, plain, check)
        # what the search runs, loaded (or compiled) here, before its budget's clock starts:
        # a first call in a process then answers as every later one does
        if not plain.opts.checks:
            plan_for(arm, solver, cast(tuple, plain.key), plain.opts, position, False)
        if spec.kind == "numeric":  # its restarts' entry: one iteration, no restart
            once = plain.narrowed(max_restarts=0, iteration_budget=1).opts
            spec.run(arm, kind, arm.middle.copy(), once, False)
        check.distance(arm.middle)
        if len(kept) > 64:
            kept.clear()
            kept["generation"] = registry.generation
        kept[(solver, key, position)] = found
    return found


_AVOIDING: Derived[dict] = Derived("collision-checked solves", lambda _: {})


def _avoiding(arm: ArmModel, req: Request) -> IKResult:
    """A collision-checked solve: a closed form's branches from one run of its kernel,
    checked nearest first; a numeric solver's plain solve first (most answers are clear at
    once), then its restarts go on from that run."""
    target, q0, solver, opts, key, seed, _, t0 = req[:8]
    kind = type(target)  # a pose the plan takes as given: parsed only if it is needed
    shape = cast(np.ndarray, target).shape if kind is np.ndarray else None
    plain_key: tuple | None
    if key is not None and (kind is _SE3 or shape == (4, 4) or shape == (3,)):
        spec, kept, check = _kept(arm, req, shape == (3,))
        plain, plain_key = kept.opts, kept.key
    else:
        plain = but_options(opts, **_NO_COLLISIONS)
        target = parsed(target, arm)
        # chosen as without collisions (no solver reads them): remembered for these options
        spec = registry.choose(solver, arm, target, plain)
        check = checker(arm, opts.obstacles, opts.self_collision)
        plain_key = None if key is None else (key, "plain")
    first = None
    if spec.kind != "analytic":
        started, now = cpu_time.thread_time(), time.perf_counter()
        if plain_key is None:  # options no plan is kept for (obstacles): the general path
            r = _run(arm, spec, parsed(target, arm), q0, with_seed(plain, seed), False, now)[0]
        else:  # the plan's key apart from the options' with collisions
            r = run(arm, req.but(target=target, opts=plain, key=plain_key, t0=now))
        clear, first = _clear_at_once(check, r, opts, started, t0)
        if clear is not None:
            return clear
    target = parsed(target, arm)
    return _run(arm, spec, target, q0, with_seed(opts, seed), False, t0, first)[0]  # type: ignore[no-any-return]


def going_on(arm: ArmModel, req: Request, row: Verdicts) -> IKResult:
    """``run``'s result of a collision-checked request for a numeric solver whose plain
    solve from the request's seed is done already, with its verdict and collision check:
    ``row`` (a batch's chunk's), the search going on from it as ``_avoiding`` goes on
    from its own."""
    target, q0, solver, opts, _, seed, _, t0 = req[:8]
    tgt = parsed(target, arm)
    spec = registry.choose(solver, arm, tgt, but_options(opts, **_NO_COLLISIONS))
    first = First(row, cpu_time.thread_time())
    return _run(arm, spec, tgt, q0, with_seed(opts, seed), False, t0, first)[0]  # type: ignore[no-any-return]


def _clear_at_once(check: Checker, r: IKResult, opts, started: float, t0: float):
    """(result, first): a numeric solver's plain solve ``r`` (begun at thread CPU time
    ``started``) when its answer is a success and collision-free by ``check``, with its
    distance and pair (the answer the collision-checked search starts with, as
    ``solve_batch``'s chunks), and None; else None and ``First``, that run for the search
    (``armik.solve.avoid``) to go on from."""
    if not r.success:
        return None, First(Verdicts.of_result(r, opts.tol_position, opts.tol_orientation), started)
    distance, pair = check.distance(r.q)
    if distance < opts.margin:
        row = Verdicts.of_result(r, opts.tol_position, opts.tol_orientation)
        return None, First(row.judge(distances([(distance, pair)], opts.margin)), started)
    fields = dict(r.__dict__)  # the plain result's, as ``IKResult._from_fields`` takes them
    said = fields.pop("_reason", None)  # a prepared result's reason, written on first read
    if said is None:
        fields["reason"] = reasons.and_clear(fields["reason"], pair, distance, opts.margin)
    else:
        fields.pop("reason", None)
        fields["_reason"] = (_said_clear, (said, pair, distance, opts.margin))
    fields["time"] = time.perf_counter() - t0
    kept = fields.pop("extra")  # what the verdict measured apart (weights, a region)
    clear = IKResult._from_fields(fields)
    clear.extra.update(kept)
    clear.extra["min_distance"], clear.extra["closest_pair"] = distance, pair
    return clear, None


def _said_clear(said: tuple, pair, distance: float, margin: float) -> str:
    """The reason of a prepared success kept clear: its own words, then the clearance."""
    return reasons.and_clear(said[0](*said[1]), pair, distance, margin)


def _run(arm, spec: SolverSpec, tgt: Target, q0, opts, every: bool, t0: float, first=None):
    """The verified results of ``spec`` for the parsed target ``tgt`` (collisions checked
    where the options ask, a numeric solver going on from ``first`` when given)."""
    seed = arm.seed(q0)
    if opts.obstacles or opts.self_collision:  # ``opts.collisions``, inline
        clear = of_options(opts)  # the options' own: validated where they were read
        return solve_avoiding(arm, spec, tgt, seed, opts, clear, every, t0, first, opts.slide)
    if opts.checks and not every:
        if spec.kind != "analytic":  # restarted while a check refuses its answer
            return solve_avoiding(arm, spec, tgt, seed, opts, None, False, t0)
        answers = spec.run(arm, tgt, seed, opts, False)
        found = finish(arm, spec.name, answers, tgt, opts, seed, False, t0)
        if found[0].success or len(answers) > 1:
            return found
        # a closed form's one answer that a user's check refuses: the nearest of every
        # branch that holds it, as the collision-checked solve takes its branches
        answers = spec.run(arm, tgt, seed, opts, True)
        again = finish(arm, spec.name, answers, tgt, opts, seed, False, t0)
        return again if again[0].success else found
    answers = spec.run(arm, tgt, seed, opts, every)
    return finish(arm, spec.name, answers, tgt, opts, seed, every, t0)
