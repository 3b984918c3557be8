"""A flat list of tasks for several tips, each naming its frame (Pink's and mink's habit:
``robot.solve([armik.Pose(T_l, frame=left), armik.Relative(right, left, T)])``), read as
the mapping ``Arms.solve`` takes: each task under the tip whose chain holds its frame, the
tips in the robot's order (a batch's rows each so, ``rows_by_tip``); and each tip's target
as tasks on it (``as_tasks``), for the task solver."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, cast

import numpy as np
import pinocchio as pin

from armik.errors import TargetError
from armik.model.arm_model import ArmModel
from armik.model.frames import moves, named, owner
from armik.problem.problem import as_problem
from armik.problem.tasks import Pose, Position, Relative, Task
from armik.problem.tasks.base import replaced
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target, parsed


def by_tip(chains: Mapping[str, ArmModel], targets: object) -> Any:
    """``targets`` as tip -> its tasks where it is a list of tasks, a mapping over the tips
    in the order of ``chains`` (the robot's tips: the order a mapping or a list gives them
    in is no part of the request), else as given; a ``TargetError`` for a task that names
    no frame or a frame on no chain."""
    if isinstance(targets, Mapping):
        return in_order(chains, targets)
    if not isinstance(targets, (list, tuple)) or not targets:
        return targets
    if not all(isinstance(t, Task) for t in targets):
        return targets  # the mapping check names what is wrong
    out: dict[str, list[Task]] = {}
    for task in targets:
        if task.frame is None:
            raise TargetError(
                f"{type(task).__name__} in a list of tasks for several tips names no frame: "
                f"give frame= (one of the tips {list(chains)}, or a frame of their chains)"
            )
        tip = placing(chains, task.frame)
        if tip not in chains:
            raise TargetError(
                f"{type(task).__name__} names frame {task.frame!r}, which no chain of tips "
                f"{list(chains)} has"
            )
        out.setdefault(tip, []).append(task)
    return in_order(chains, out)


def placing(chains: Mapping[str, ArmModel], frame: str) -> str:
    """The tip whose chain places ``frame`` as the robot does (``frames.owner``'s, or
    ``frame`` where no chain has it): where several chains move it (it hangs below joints
    they share: a torso carries the other arm, which the chain holds still), the one that
    hangs it on the deepest joint of the URDF's tree."""
    tip = owner(chains, frame)
    if tip not in chains or tip == frame:
        return tip
    movers = [t for t, arm in chains.items() if arm.model.existFrame(frame) and moves(arm, frame)]
    return max(movers, key=lambda t: _depth(chains[t], frame)) if len(movers) > 1 else tip


def _depth(arm: ArmModel, frame: str) -> int:
    """How many joints of the URDF's tree lie above the joint ``arm`` hangs ``frame`` on."""
    model, full = arm.model, arm.chain.full
    j = full.getJointId(model.names[model.frames[named(model, frame)].parentJoint])
    depth = 0
    while j:
        j, depth = full.parents[j], depth + 1
    return depth


def in_order(chains: Mapping[str, ArmModel], targets: Mapping) -> Mapping:
    """``targets`` (tip -> target) over the tips in the order of ``chains``; as given where
    they are in it already, or name a tip no chain has (the caller's check names it)."""
    keys = list(targets)
    order = [t for t in chains if t in targets]
    if keys == order or len(order) != len(keys):
        return targets
    return {t: targets[t] for t in order}


def rows_by_tip(chains: Mapping[str, ArmModel], rows: object, options: Mapping) -> Any:
    """A batch's or a path's rows, each a flat list of tasks naming their frames (``by_tip``'s
    list), as the mapping tip -> its N rows of tasks (a tip's exact poses as poses, read
    already, where no option reads a pose otherwise than a task: ``position_only``,
    ``weights``, ``bounds``); any other spelling as given. A ``TargetError`` names a row
    whose tips are not the first row's."""
    if not isinstance(rows, (list, tuple)) or not rows:
        return rows
    if not all(isinstance(r, Task) or _tasks(r) for r in rows):
        return rows  # the mapping check names what is wrong
    out: dict[str, list[list[Task]]] = {}
    for i, row in enumerate(rows):
        each = by_tip(chains, [row] if isinstance(row, Task) else list(row))
        if i and each.keys() != out.keys():
            raise TargetError(
                f"row {i} of the tasks gives tips {list(each)}, row 0 {list(out)}: every row "
                "names the same tips, as each tip needs its N targets"
            )
        for tip, tasks in each.items():
            out.setdefault(tip, []).append(tasks)
    if any(options.get(k) is not None for k in ("weights", "bounds")) or options.get(
        "position_only"
    ):
        return out  # read against the tasks (a Pose's rotation not dropped unseen)
    return {tip: _plain(tip, tasks) for tip, tasks in out.items()}


def _plain(tip: str, rows: list[list[Task]]) -> TargetBatch | list:
    """A tip's rows as the mapping spells them where each is one exact pose, or each one
    exact position, of the tip (no bounds, no weights): its poses or positions, the same
    request as ``{tip: poses}`` (solved, and its steps judged halfway, alike), as the
    ``TargetBatch`` of the tasks' values (read when they were built: not again); else its
    rows of tasks."""
    if all(len(r) == 1 and _exact(r[0], tip, Pose) for r in rows):
        T = [cast(Pose, r[0]).T for r in rows]
        return TargetBatch(np.array([X.translation for X in T]), np.array([X.rotation for X in T]))
    if all(len(r) == 1 and _exact(r[0], tip, Position) for r in rows):
        return TargetBatch(np.array([cast(Position, r[0]).p for r in rows], dtype=float))
    return rows


def _exact(task: Task, tip: str, kind: type) -> bool:
    """Whether ``task`` is of exactly ``kind``, on ``tip``, with no bounds and no weights."""
    weights = getattr(task, "weights", None)
    plain = weights is None or bool((weights == 1.0).all())
    bounds = getattr(task, "bounds", None)
    loose = bounds is not None and bool(bounds.any())
    return type(task) is kind and task.frame == tip and not loose and plain


def _tasks(row: object) -> bool:
    """Whether ``row`` is a non-empty list of tasks."""
    return isinstance(row, (list, tuple)) and bool(row) and all(isinstance(t, Task) for t in row)


def placed(chains: Mapping[str, ArmModel], tip: str, tasks: Sequence[Task]) -> None:
    """A ``TargetError`` for a task in ``tip``'s target on a frame that another chain's
    joints move and ``tip``'s do not (a link of the other arm): ``tip``'s chain holds it
    still, so its failure there would prove nothing of the robot."""
    mine, tips = chains[tip], list(chains)
    for task in tasks:
        on(task, tip, tips)  # another tip's frame or its Relative: that tip's to give
        frame = task.frame
        if frame is None or frame == tip:
            continue
        other = owner(chains, frame)
        if other != tip and other in chains and moves(chains[other], frame):
            if not moves(mine, frame):
                raise TargetError(
                    f"the target of tip {tip!r} holds a {type(task).__name__} on frame "
                    f"{frame!r}, which the chain of tip {other!r} moves and that of {tip!r} "
                    f"does not: give it in the target of {other!r}"
                )


def as_tasks(target: object, tip: str, tips: Sequence[str]) -> list[Task]:
    """A tip's target as tasks on ``tip``: its tasks as given (``on``), or a ``Position``
    or ``Pose`` of that tip."""
    if type(target) is not Target:  # a parsed target holds no task
        problem = as_problem(target)
        if problem is not None:
            return [on(t, tip, tips) for t in problem.tasks]
        target = parsed(target)
    if target.rotation is None:
        return [Position(target.position, frame=tip)]
    return [Pose(target, frame=tip)]


def on(task: Task, tip: str, tips: Sequence[str]) -> Task:
    """``task`` on ``tip``, or on the frame it names that is no tip (an elbow, a camera
    link of that chain); a task on another tip, or another tip's ``Relative``, is that
    tip's to give."""
    if task.frame is None:
        return replaced(task, frame=tip)
    if task.frame != tip and (task.frame in tips or isinstance(task, Relative)):
        raise TargetError(
            f"the target of tip {tip!r} holds a task on frame {task.frame!r}: give each tip "
            "its own tasks"
        )
    return task


def absolute(target: object, placements: Mapping[str, pin.SE3]) -> object:
    """``target`` with each ``Relative`` task a ``Pose`` in the base, its reference frame
    at ``placements`` (its bounds and weights kept, the pose not read again); any other
    target as it is."""
    problem = as_problem(target)
    if problem is None or not any(isinstance(t, Relative) for t in problem.tasks):
        return target
    tasks: list[Task] = []
    for t in problem.tasks:
        if isinstance(t, Relative):
            ref = cast(str, t.relative_to)
            t = replaced(t.pose, T=placements[ref] * t.pose.T)
        tasks.append(t)
    return tasks


def solve_order(targets: Mapping[str, object], relative: dict) -> list[str] | None:
    """The tips, each after the tips their ``Relative`` tasks (``relative``) are relative
    to; None when they are relative to each other in a cycle."""
    after = {tip: {t.relative_to for t in rel} for tip, rel in relative.items()}
    order: list[str] = []
    pending = list(targets)
    while pending:
        ready = [t for t in pending if not (after.get(t, set()) & set(pending) - {t})]
        if not ready:
            return None
        order += ready
        pending = [t for t in pending if t not in ready]
    return order
