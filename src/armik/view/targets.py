"""A tip's target and its gizmo: where the gizmo sits for a target (a pose, a position or a
task list), and what dragging it makes of the target.

A task list's gizmo is its anchor: the first ``Pose`` or ``Position`` on the tip. Dragging
moves the anchor and keeps every other task (an ``Axis`` cone, a ``LookAt`` point) and the
anchor's bounds; a list without an anchor gains a ``Position`` at the gizmo.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from armik.errors import FrameError, InputError
from armik.problem.problem import as_problem
from armik.problem.tasks import Pose, Position, Task
from armik.problem.tasks.base import replaced
from armik.targets.pose import parse_target
from armik.view.robot import Robot


def per_tip(T: object, robot: Robot) -> dict[str, object]:
    """``set_target``'s ``T`` as tip -> target: one arm's target as it is, or a mapping of
    tips; ``InputError`` for several tips not given one by one, ``FrameError`` for a tip
    the robot lacks."""
    tips = robot.tips
    if isinstance(T, Mapping):
        unknown = [t for t in T if t not in tips]
        if unknown:
            raise FrameError(
                f"unknown tips {unknown}; this robot's tips: {list(tips)}",
                frame=str(unknown[0]),
                candidates=tips,
            )
        if not T:
            raise InputError(f"no target given: give {{tip: target}} for tips {list(tips)}")
        return dict(T)
    if robot.several:
        raise InputError(
            f"this robot has several tips {list(tips)}: give set_target a target per tip, "
            f"{{{tips[0]!r}: T, ...}}, got a {type(T).__name__}"
        )
    return {tips[0]: T}


def tasks_of(target: object) -> tuple[Task, ...] | None:
    """The tasks of a task or task list; None for a pose or a position."""
    problem = as_problem(target)
    return None if problem is None else problem.tasks


def anchor(tasks: tuple[Task, ...], tip: str) -> int | None:
    """The index of the first ``Pose`` or ``Position`` on the tip, or None."""
    for i, task in enumerate(tasks):
        if type(task) in (Pose, Position) and task.frame in (None, tip):
            return i
    return None


def gizmo_pose(target: object, robot: Robot, q: np.ndarray, tip: str) -> np.ndarray:
    """4x4: where ``tip``'s gizmo sits for ``target`` (None: the tip at ``q``); a position
    keeps the tip's orientation at ``q``."""
    T_tip = robot.fk(q, tip).homogeneous
    if target is None:
        return T_tip
    tasks = tasks_of(target)
    if tasks is None:
        parsed = parse_target(target, robot.chains[tip])
        if parsed.rotation is None:
            return _at(T_tip, parsed.position)
        return parsed.se3().homogeneous
    i = anchor(tasks, tip)
    if i is None:
        return T_tip
    task = tasks[i]
    if isinstance(task, Pose):
        return task.T.homogeneous
    assert isinstance(task, Position)
    return _at(T_tip, task.p)


def dragged(target: object, T: pin.SE3, position_only: bool, tip: str) -> object:
    """The target after its gizmo was dragged to ``T`` (module docstring); a pose or a
    position target becomes ``T`` (its position alone with ``position_only``)."""
    tasks = tasks_of(target)
    if tasks is None:
        return T.translation.copy() if position_only else T
    i = anchor(tasks, tip)
    if i is None:
        return [Position(T.translation), *tasks]
    task = tasks[i]
    if isinstance(task, Pose):
        R = task.T.rotation if position_only else T.rotation
        moved = replaced(task, T=pin.SE3(R, T.translation.copy()))
    else:
        moved = replaced(task, p=T.translation.copy())
    return [*tasks[:i], moved, *tasks[i + 1 :]]


def _at(T: np.ndarray, p: np.ndarray) -> np.ndarray:
    out = T.copy()
    out[:3, 3] = p
    return out
