"""What the user passed, read once into a ``Request`` (``armik.request``).

The only reader of keyword options: ``read`` takes a call of ``solve`` or ``solve_all``
as the user spelled it (a target, ``q0``, ``solver``, keyword options) and returns the
request every stage reads. A preference (``prefer=``) is taken out as the request's
score; a budget or constraints as objects are spelled as the options they stand for; a
task list is lowered to the compiled path's target and options where it has a form, else
kept as the request's problem for the task solver, as is a plain target with joints held
that the compiled path cannot hold. ``settings`` validates the options alone, remembered
per arm: a loop of solves passes the same options, often with a new seed each time.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Iterator, Mapping

import numpy as np
import pinocchio as pin

from armik.errors import OptionError
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.options import Options, spelled
from armik.problem.problem import (
    Problem,
    as_problem,
    as_target,
    check_said_twice,
    lower,
    refuse_beside_tasks,
    refuse_looking_from_target,
    refuse_tip_frame_weights,
)
from armik.problem.scores import fit_reference, parse_score
from armik.problem.tasks import Pose, Position, Task
from armik.request import Request, but_options, resolved
from armik.solve.read_aim import (
    AIM_NAMES,
    AIM_OF_TASKS,
    aimed_batch,
    aimed_once,
    aimed_tasks,
    keyword_aim,
    task_aim,
    tasks_aim,
)
from armik.solve.refused import check_options
from armik.solve.task_lists import lower_all, not_lowered_globally, task_problems
from armik.targets.aim import refuse_freed, refuse_without_direction
from armik.targets.batch import parse_targets
from armik.targets.pose import MAX_POSITION, Target, checked, is_rotation, parsed


def read(
    arm: ArmModel,
    target: object,
    q0: object,
    solver: str,
    options: dict,
    every: bool = False,
    parsed_already: bool = False,
) -> Request:
    """The request of ``solve(arm, target, q0, solver, **options)`` (``every``: solve_all;
    ``parsed_already``: ``target`` is the parser's ``Target``, its parts checked)."""
    if not options:  # the common call: nothing to read but a plain pose or position
        kind = type(target)
        if kind is _SE3 or kind is np.ndarray:
            t0 = time.perf_counter()
            return _new(
                Request, (target, q0, solver, _DEFAULT, (), 0, every, t0, None, None, None, None)
            )
    t0 = time.perf_counter()
    if not _OBJECTS.isdisjoint(options):
        options = replayable(options)
    score = None
    if "budget" in options:  # as its options, which the stages narrow (restarts, shares)
        options = spelled(options)
    if "prefer" in options:
        options = dict(options)
        score = parse_score(options.pop("prefer"), arm)
    aim = None
    if "cone" in options or "look_at" in options or "toward" in options:
        aim, options = keyword_aim(options)
    problem = beside = None  # beside: (tasks, options) beside a lowered list, checked once read
    freed = None  # an aim task lowered to a pose (``task_aim``): refused what frees it
    kind = type(target)  # the common poses first: ``Task``'s isinstance is an ABC's check
    if (
        kind is not _SE3
        and kind is not np.ndarray
        and kind is not Target
        and (kind in (list, tuple) or isinstance(target, Task))
    ):
        problem = as_problem(target)
        if problem is not None:
            lowered = lower(problem, arm.tip, options.get("weights"))
            held = "hold" in options or "constraints" in options  # a call only then
            if lowered is not None and not (held and _held_apart(arm, options)):
                target, said = lowered
                check_said_twice(options, said)
                if "position_only" in options or "bounds" in options:  # once read, below
                    beside = (problem, options)
                # an Axis exactly along a direction: a pose, its spin free (no aim)
                if aim is None and (type(target) is not Target or target.aim is None):
                    freed = task_aim(problem)
                if aim is not None:  # a call only then: the lowered target's aim is read below
                    aim = aimed_once(target, aim)
                options = {**options, **said}
                problem, target = None, as_target(target) or target  # its values: not again
            elif aim is not None:
                raise OptionError(AIM_OF_TASKS, option=AIM_NAMES[0], value=aim)
    held = False  # a plain target whose held joints only the task solver holds
    if problem is None and ("hold" in options or "constraints" in options):
        if _held_apart(arm, options):  # a plain pose or position: the task solver's task
            given = target if aim is None else parsed(target, arm).aimed(aim)
            problem, options = _as_task(arm, given, options)
            held = problem is not None
            aim = aim if problem is None else None
    opts, key, seed = settings(arm, options) if options else (_DEFAULT, (), 0)
    if beside is not None:  # after ``settings``, which names a value that is not one
        refuse_beside_tasks(*beside)
    if problem is not None:
        check_options(opts, solver, held=held)
    if freed is not None:
        refuse_freed(freed, opts, aimed=False)
    if score is not None and problem is None:  # every answer ranked is to this target
        target = parsed(target, arm)
    if type(target) is Target and not parsed_already:  # built by hand: checked, not plain
        p, R = target.position, target.rotation  # plain: finite float arrays, 3 and 3 x 3
        ok = type(p) is np.ndarray and p.shape == _POINT and p.dtype == _FLOAT
        if R is not None:
            ok = ok and type(R) is np.ndarray and R.shape == _MATRIX and R.dtype == _FLOAT
            ok = ok and is_rotation(R)
        if not (ok and p.dot(p) <= _FAR and math.isfinite(0.0 if R is None else R.sum())):
            target = checked(target)  # (the parser's rule: each coordinate within 1e6 m)
    if aim is None and type(target) is Target:  # a row of an aimed batch or path
        aim = target.aim
    if aim is not None:  # the target carries it; its plans are kept apart by its shape
        if type(target) is not Target or target.aim is not aim:
            target = parsed(target, arm).aimed(aim)
        refuse_without_direction(aim, target.rotation is not None)
        refuse_freed(aim, opts)
        key = None if key is None else (key, aim[0], aim[1], aim[2] is None, aim[3] is None)
        if aim.point is not None:  # [Position(p), LookAt(p)]'s refusal
            refuse_looking_from_target(target.position, aim, opts)
    opts = resolved(opts, arm, q0) if opts.checks else opts  # a user's own: at q0
    # built as the tuple it is (``Request``'s own ``__new__`` is a Python call: every solve)
    return _new(
        Request, (target, q0, solver, opts, key, seed, every, t0, score, problem, None, None)
    )


def read_batch(arm: ArmModel, targets: object, q0: object, solver: str, options: dict) -> Request:
    """The request of ``solve_batch(arm, targets, q0=q0, solver=solver, **options)``: the
    targets as given, or task lists lowered together to the compiled batch's targets and
    options; where the compiled batch has no form for them (task lists that do not lower
    together, a preference, a held joint, a swivel angle), each row's own request in
    ``rows``, read as ``solve`` reads it."""
    t0 = time.perf_counter()
    if not _OBJECTS.isdisjoint(options):
        options = replayable(options)
    if "budget" in options:  # as its options, which a row's solve may narrow
        options = spelled(options)
    given = options  # a row solved as ``solve`` solves it reads its task list with these
    aim = None
    if "cone" in options or "look_at" in options or "toward" in options:
        aim, options = keyword_aim(options)
    rows: list | None = None
    freed = None  # an aim task lowered to a pose (``task_aim``): refused what frees it
    ranked = False  # each row's answers ranked by a preference
    # an array holds poses or positions: tasks come as a list or a tuple
    problems = task_problems(targets) if type(targets) in (list, tuple) else None
    lowered = None
    if problems is not None:
        settings(arm, {k: v for k, v in options.items() if k != "prefer"})  # before the tasks
        lowered = lower_all(problems, options, arm.tip)
        if lowered is None:  # no compiled form: the task solver, target by target
            if aim is not None:
                raise OptionError(AIM_OF_TASKS, option=AIM_NAMES[0], value=aim)
            rows = [list(p.tasks) for p in problems]
        else:
            targets, options = lowered
            aim = aimed_once(targets, aim)
            freed = None if aim is not None else tasks_aim(problems)
    if aim is not None or lowered is not None:  # every target's: the batch carries it
        targets = batch = aimed_batch(targets, arm, aim)
        if aim is not None:
            refuse_without_direction(aim, batch.rotations is not None)
    if rows is None and options.get("prefer") is not None:  # each target's answers ranked
        batch = parse_targets(targets, arm)
        rows, ranked = [batch.target(i) for i in range(len(batch))], True
    plain = options
    if "prefer" in options:  # the rows' score, not a setting
        plain = dict(options)
        del plain["prefer"]
    opts, key, seed = settings(arm, plain) if plain else (_DEFAULT, (), 0)
    if rows is None and (opts.hold is not None or opts.swivel is not None):
        # held joints, an SRS arm's swivel angle: each target solved as solve does
        batch = parse_targets(targets, arm)
        rows = [batch.target(i) for i in range(len(batch))]
    if rows is not None and lowered is not None and problems is not None:
        # lowered task lists solved row by row: each row its own task list, read as
        # ``solve`` reads it (a lowered target made a held joint's task would lose its aim)
        rows, options = [list(p.tasks) for p in problems], given
    if freed is not None:
        refuse_freed(freed, opts, aimed=False)
    if aim is not None:
        refuse_freed(aim, opts)
        key = None if key is None else (key, aim.shape)
        if aim.point is not None:  # [Position(p), LookAt(p)]'s refusal
            refuse_looking_from_target(targets.positions, aim, opts)  # type: ignore[attr-defined]
    opts = resolved(opts, arm, q0, True) if opts.checks else opts  # a user's own: the one q0's
    if rows is None:
        return Request(targets, q0, solver, opts, key, seed, False, t0)
    each = tuple(read(arm, row, None, solver, options) for row in rows)
    if opts.checks:  # each row's own: resolved from the batch's start, not the middle
        each = tuple([r.but(opts=but_options(r.opts, checks=opts.checks)) for r in each])
    score = parse_score(options["prefer"]) if ranked else None  # each row said it
    return Request(None, q0, solver, opts, key, seed, False, t0, score, rows=each)


def read_path(
    arm: ArmModel, poses: object, q0: object, solver: str, plan: str, options: dict
) -> tuple[Request, Request]:
    """(request, local): the request of ``solve_path(arm, poses, q0, solver=solver,
    plan=plan, **options)``, the poses as given (task lists lowered together to the
    compiled path's targets and options), a preference as its score; a followed path
    slides a colliding answer out of contact near the previous one (``Options.slide``)
    unless told otherwise. ``local``: the same options without restarts, not sliding
    unless told to (a waypoint re-solved near the previous answer)."""
    t0 = time.perf_counter()
    check_plan(plan)
    if not _OBJECTS.isdisjoint(options):
        options = replayable(options)
    score = None
    if "prefer" in options:  # the path's score, not a setting
        score = parse_score(options["prefer"], arm)
        options = {k: v for k, v in options.items() if k != "prefer"}
    if "budget" in options:  # as its options, which each rung's solve narrows
        options = spelled(options)
    aim = None
    if "cone" in options or "look_at" in options or "toward" in options:
        aim, options = keyword_aim(options)
    problems = task_problems(poses)
    if problems is not None:
        settings(arm, options)  # its values named before the tasks read them
        lowered = lower_all(problems, options, arm.tip)
        if lowered is None and aim is not None:
            raise OptionError(AIM_OF_TASKS, option=AIM_NAMES[0], value=aim)
        # no compiled form, or joints only the task solver holds: each list as solve reads it
        if lowered is None or _held_apart(arm, options):
            if plan == "global":
                if lowered is not None:
                    raise _held_global(options)
                raise not_lowered_globally()
            rows = tuple(read(arm, list(p.tasks), q0, solver, options) for p in problems)
            return _by_rows(arm, rows, q0, solver, options, t0, score)
        poses, options = lowered
        aim = aimed_once(poses, aim)
        if aim is None and (freed := tasks_aim(problems)) is not None:
            refuse_freed(freed, settings(arm, options)[0], aimed=False)
    elif "hold" in options or "constraints" in options:
        if _held_apart(arm, options):  # joints only the task solver holds: as solve does
            if plan == "global":
                raise _held_global(options)
            batch = parse_targets(poses, arm)
            each = [batch.target(i) for i in range(len(batch))]
            if aim is not None:  # every waypoint's, as the compiled path's batch carries it
                each = [t.aimed(aim) for t in each]
            rows = tuple(read(arm, t, q0, solver, options) for t in each)
            return _by_rows(arm, rows, q0, solver, options, t0, score)
    opts, key, seed = settings(arm, {**options, "max_restarts": 0})
    if aim is not None or problems is not None:  # every waypoint's: the path carries it
        poses = batch = aimed_batch(poses, arm, aim)
        if aim is not None:
            refuse_without_direction(aim, batch.rotations is not None)
            refuse_freed(aim, opts)
            key = None if key is None else (key, aim.shape)
            if aim.point is not None:  # [Position(p), LookAt(p)]'s refusal, at every waypoint
                refuse_looking_from_target(batch.positions, aim, opts)
    opts = resolved(opts, arm, q0) if opts.checks else opts  # a user's own: at the path's q0
    local = Request(poses, q0, solver, opts, key, seed, False, t0)
    if plan == "follow" and "slide" not in options:
        options = {"slide": True, **options}
    opts, key, seed = settings(arm, options)
    opts = resolved(opts, arm, q0) if opts.checks else opts
    if aim is not None and key is not None:
        key = (key, aim.shape)
    return Request(poses, q0, solver, opts, key, seed, False, t0, score), local


def _held_global(options: dict) -> OptionError:
    """The refusal of a global plan whose held joints only the task solver holds."""
    return OptionError(
        "plan='global' plans over every solution at each waypoint, and the joints held here "
        "are held by the task solver, which gives one answer each: give plan='follow', or "
        "lock them: arm.with_locked({name: value})",
        option="hold",
        value=options.get("hold"),
    )


def _by_rows(arm, rows: tuple, q0, solver: str, options: dict, t0: float, score):
    """(request, local) of a path followed waypoint by waypoint, each ``rows``' own."""
    opts, key, seed = settings(arm, options)
    path = Request(None, q0, solver, opts, key, seed, False, t0, score, rows=rows)
    return path, path


def check_plan(plan: object) -> None:
    """An ``OptionError`` for a plan that is neither "follow" nor "global"."""
    if plan not in ("follow", "global"):
        raise OptionError(
            f"plan must be 'follow' (each waypoint from the previous answer) or 'global' "
            f"(every branch at every waypoint, the least motion), got {plan!r}",
            option="plan",
            value=plan,
        )


# the options that take several objects, as any iterable (a one-shot iterator: ``replayable``)
_OBJECTS = frozenset(("constraints", "obstacles", "secondary"))


def replayable(options: dict) -> dict:
    """``options`` with each one-shot iterator (a generator, ``iter([...])``), alone or a
    tip's in a mapping, read into a tuple: options are read more than once (spelled, then
    checked, then per chain), and an iterator read once is empty the next time (its
    constraints or obstacles dropped without a word)."""
    out = dict(options)
    for name, value in options.items():
        if isinstance(value, Iterator):
            out[name] = tuple(value)
        elif isinstance(value, Mapping) and any(isinstance(v, Iterator) for v in value.values()):
            out[name] = {k: tuple(v) if isinstance(v, Iterator) else v for k, v in value.items()}
    return out


def _held_apart(arm: ArmModel, options: dict) -> bool:
    """Whether ``options`` hold joints only the task solver holds (the compiled path: one
    joint of a 7-joint arm)."""
    if "hold" not in options and "constraints" not in options:
        return False
    held = (spelled(options) if "constraints" in options else options).get("hold")
    count = 0 if held is None else len(held) if isinstance(held, Mapping) and held else 1
    return count > 0 and (arm.dof != 7 or count != 1)


_SAID_BY_POSE = ("weights", "bounds")  # said by a full pose's task (``armik.Pose``)


def _as_task(arm: ArmModel, target: object, options: dict) -> tuple[Problem | None, dict]:
    """(problem, options): the problem of a plain pose or position (``armik.Pose``, with
    the pose's ``weights`` and ``bounds``; ``armik.Position``, ``position_only`` said by
    the task), for the task solver to hold joints the compiled path cannot; (None,
    ``options``) where the options say more than such a task would: the compiled path's
    error then names the way. An aimed target is the tasks it lowers from (``aimed_tasks``)."""
    tgt = parsed(target, arm)
    said = {name: options[name] for name in _SAID_BY_POSE if options.get(name) is not None}
    if tgt.aim is not None:  # the tasks it lowers from (``armik.problem.problem.lower``)
        return aimed_tasks(tgt, tgt.aim, options)
    if said and (tgt.rotation is None or options.get("position_only")):
        return None, options
    if tgt.rotation is None or options.get("position_only"):
        rest = {k: v for k, v in options.items() if k != "position_only"}
        return as_problem(Position(tgt.position)), rest
    if not said:  # parsed already: not read again
        return as_problem(Pose.of(tgt, None)), options
    refuse_tip_frame_weights(said)
    rest = {k: v for k, v in options.items() if k not in said}
    return as_problem(Pose(pin.SE3(tgt.rotation, tgt.position), **said)), rest


def options(kwargs: Mapping[str, object]) -> Options:
    """The validated options of ``kwargs`` (not remembered), a target's aim checked and
    left out: what the viewer, the C export, the CLI and ``Arms`` check options by."""
    return Options.from_kwargs(keyword_aim(dict(kwargs))[1])


def settings(arm: ArmModel, kwargs: dict) -> tuple[Options, tuple | None, int | None]:
    """(options, key, seed): ``Options.from_kwargs(kwargs)``, remembered for ``arm`` under
    ``key`` (None: not remembered) when the values other than ``seed`` are hashable, and
    this call's validated ``seed``. A loop of solves passes the same options, often with a
    new seed each time: the remembered options keep the seed they were first built with
    (``Request.settings`` gives them this call's). A target's aim is taken out before."""
    if not kwargs:
        return _DEFAULT, (), 0
    seed = kwargs.get("seed", 0)
    if "seed" in kwargs:
        kwargs = dict(kwargs)
        del kwargs["seed"]
    try:
        # with the types (1 == True, but a held value of True is refused, 1 is not); a held
        # joint's dict as its items, a list or tuple of obstacles as its scene's number
        hold = kwargs["hold"] if "hold" in kwargs else None
        if type(hold) is dict:
            items = (tuple(hold.items()), tuple(map(type, hold.values())))
            given = {**kwargs, "hold": items}
        else:
            given = kwargs
        if "obstacles" in kwargs and type(kwargs["obstacles"]) in (list, tuple):
            given = {**given, "obstacles": _scene(arm, kwargs["obstacles"])}
        key = (tuple(given.items()), tuple(map(type, kwargs.values())))
        kept = arm._derived.get(_KEPT)  # read as a dict, not through a call: every solve
        if kept is None:
            kept = _KEPT(arm)
        opts = kept.get(key)
    except TypeError:  # an unhashable value (a list of weights): validate every time
        opts = _fitted(arm, Options.from_kwargs({**kwargs, "seed": seed}))
        return opts, None, _seed(seed)
    if type(seed) is not int or not 0 <= seed < 2**63:  # a plain seed needs no call
        seed = _seed(seed)
    if opts is None:
        opts = _fitted(arm, Options.from_kwargs({**kwargs, "seed": seed}))  # seed checked too
        if len(kept) > 256:
            kept.clear()
        kept[key] = opts
    return opts, key, seed


_KEPT: Derived[dict] = Derived("validated options", lambda _: {})


def _fitted(arm: ArmModel, opts: Options) -> Options:
    """``opts`` once what they say of the joints fits ``arm`` (a secondary posture: one
    value per joint), whichever solver then runs."""
    if opts.posture is not None:
        fit_reference(opts.posture[0], arm, "secondary")
    return opts


def _scene(arm: ArmModel, obstacles: list | tuple) -> int:
    """A number for these shapes, the same for equal shapes: what the key holds in their
    place, so that each of the stages' lookups under the key does not hash every shape
    again (2 us for four)."""
    scenes = arm._derived.get(_SCENES)
    if scenes is None:
        scenes = _SCENES(arm)
    shapes = tuple(obstacles)
    number = scenes.get(shapes)
    if number is None:
        if len(scenes) > 256:
            scenes.clear()
        number = scenes[shapes] = next(_NUMBERS)  # never one a kept key held before
    return number


_SCENES: Derived[dict] = Derived("obstacle scenes", lambda _: {})
_NUMBERS = itertools.count()


def _seed(seed: object) -> int | None:
    """``seed`` as ``Options.from_kwargs`` validates it."""
    if type(seed) is int and 0 <= seed < 2**63:
        return seed  # what the validation returns for a plain int
    return None if seed is None else Options.from_kwargs({"seed": seed}).seed


_SE3, _new = pin.SE3, tuple.__new__
# a Target's plain parts: float arrays of 3 and a rotation, the position within MAX_POSITION
_POINT, _MATRIX, _FLOAT, _FAR = (3,), (3, 3), np.dtype(float), MAX_POSITION**2
_DEFAULT = Options()  # frozen: shared by every call without options
