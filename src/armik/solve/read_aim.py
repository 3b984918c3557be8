"""A target's aim as the facade reads it (``armik.solve.read``): the keywords ``cone=``,
``look_at=`` and ``toward=`` (``keyword_aim``), a lowered task list's aim
(``aimed_once``, ``tasks_aim``), a batch's (``aimed_batch``), and an aimed target as the
tasks it lowers from (``aimed_tasks``: the task solver's, where it holds joints the
compiled path cannot)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from armik.errors import OptionError
from armik.problem.problem import Problem, as_problem
from armik.problem.tasks import Axis, LookAt, Position, Task
from armik.targets.aim import Aim, aim_of, refuse_freed, refuse_without_direction
from armik.targets.batch import TargetBatch, parse_targets
from armik.targets.pose import Target


def task_aim(problem: Problem) -> Aim | None:
    """The aim of ``problem``'s ``Axis`` or ``LookAt`` task, or None: one lowered to a pose
    (an axis of the tip's own exactly along a direction, its spin freed by bounds) carries
    no aim, and what would free the axis it measures is refused all the same."""
    for task in problem.tasks:
        if type(task) is Axis or type(task) is LookAt:
            x, y, z = task.axis.tolist()
            return Aim((x, y, z), float(task.within))
    return None


def tasks_aim(problems: list[Problem]) -> Aim | None:
    """The first aim of ``problems``' tasks (``task_aim``), or None."""
    return next((a for a in map(task_aim, problems) if a is not None), None)


def aimed_tasks(tgt: Target, aim: Aim, options: dict) -> tuple[Problem | None, dict]:
    """(problem, options): an aimed target as the tasks it lowers from: its position (in
    the box ``bounds`` says, base frame) and an ``armik.LookAt`` of its point or an
    ``armik.Axis`` along its direction (``toward``, else where the target's rotation takes
    the axis); (None, ``options``) where they say more (weights, rotation bounds)."""
    refuse_without_direction(aim, tgt.rotation is not None)
    if options.get("position_only"):  # as the compiled path refuses it: the aim measured
        refuse_freed(aim, SimpleNamespace(position_only=True, weights=None))
    bounds = options.get("bounds")
    try:
        box = None if bounds is None else np.asarray(bounds, dtype=float)
    except (TypeError, ValueError):  # not numbers: the options' checks name it
        return None, options
    # the rotation's bounds 0 or +inf say nothing beside the cone (``refuse_freed``); any
    # other (a width, NaN, -inf, not six) goes on to the options' checks, which name it
    if options.get("weights") is not None or (
        box is not None and (box.shape != (6,) or not np.isin(box[3:], (0.0, np.inf)).all())
    ):
        return None, options
    rest = {k: v for k, v in options.items() if k not in ("bounds", "position_only")}
    at = Position(tgt.position, None if box is None else box[:3])
    if aim.point is not None:
        sight: Task = LookAt(aim.point, aim.axis, aim.within)
    else:
        rotation = np.eye(3) if tgt.rotation is None else tgt.rotation  # (toward: unread)
        direction = aim.toward if aim.toward is not None else rotation @ aim.axis
        sight = Axis(aim.axis, direction, aim.within)
    return as_problem([at, sight]), rest


AIM_NAMES = ("cone", "look_at", "toward")  # the keywords that spell a target's aim
AIM_OF_TASKS = (
    "cone does not apply to a list of tasks the compiled path has no form for: say it in "
    "the tasks (armik.Axis, armik.LookAt)"
)


def keyword_aim(options: dict) -> tuple[Aim | None, dict]:
    """(aim, the other options): the target's aim the keywords ``cone=``, ``look_at=`` and
    ``toward=`` spell (``armik.targets.aim.aim_of``), taken out of the options."""
    if "cone" not in options and "look_at" not in options and "toward" not in options:
        return None, options
    rest = {k: v for k, v in options.items() if k not in AIM_NAMES}
    return aim_of(options.get("cone"), options.get("look_at"), options.get("toward")), rest


def aimed_once(lowered: object, given: Aim | None) -> Aim | None:
    """The aim of a lowered task list (a ``Target``'s, or the first of a list's: they
    lower together with one aim), or ``given`` by keywords; an ``OptionError`` when both
    say one."""
    first = lowered[0] if type(lowered) is list and lowered else lowered
    aim = first.aim if type(first) is Target else None
    if aim is not None and given is not None:
        name = "cone" if given.point is None and given.toward is None else "look_at"
        raise OptionError(
            f"{name} is given both by the task and as an option: give it in the task "
            "(armik.Axis, armik.LookAt)",
            option=name,
            value=given,
        )
    return aim if aim is not None else given


def aimed_batch(targets: object, arm, aim: Aim | None) -> TargetBatch:
    """The targets of a batch or a path, with what every one carries: ``aim`` (the
    keywords' or the lowered tasks'), and the axis of the ``armik.Axis`` each was lowered
    from (``Target.along``: a task list lowered alike, ``lower_all``)."""
    batch = parse_targets(targets, arm)
    first = targets[0] if type(targets) is list and targets else None
    along = first.along if type(first) is Target else None
    if aim is None and along is None:
        return batch
    return TargetBatch(batch.positions, batch.rotations, aim, along)
