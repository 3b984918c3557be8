"""A servo's target as the compiled tick's table: one row per task on the tip.

Anything ``Arm.solve`` takes for one tip: a pose or a position in any spelling
``armik.parse_target`` reads, an ``armik.Pose`` (with ``bounds=``, ``weights=``), a
``Position``, an ``Axis``, a ``LookAt``, or a list of them, each task's row its
``kernel_row`` (``kernel.region``'s six rows). Each target is parsed once, here.
"""

from __future__ import annotations

import math

import numpy as np

from armik.errors import TargetError
from armik.kernel.problem import NO_CONE, NO_LOOK
from armik.model.arm_model import ArmModel
from armik.problem.problem import as_problem
from armik.problem.tasks.base import KernelRow
from armik.servo.layout import (
    AXIS,
    BOUNDS,
    COLUMNS,
    CONE,
    EXACT,
    LOOK,
    MAX_TASKS,
    POS,
    ROT,
    SIGHT,
    WEIGHTS,
)
from armik.targets.pose import Target, parse_target

_POSE = np.full(COLUMNS, 0.0)  # a pose's row: exact, every axis weighted
_POSE[BOUNDS : BOUNDS + 6] = -EXACT
_POSE[WEIGHTS : WEIGHTS + 6] = 1.0
_POSE[CONE], _POSE[AXIS + 2], _POSE[LOOK] = NO_CONE, 1.0, NO_LOOK
_POSITION = _POSE.copy()  # a position's: the rotation free
_POSITION[ROT : ROT + 9] = np.eye(3).ravel()
_POSITION[BOUNDS + 3 : BOUNDS + 6] = math.inf


def table(target: object, arm: ArmModel) -> np.ndarray:
    """The (tasks, COLUMNS) table of ``target``; raises ``TargetError`` naming what the
    servo cannot follow."""
    problem = as_problem(target)
    if problem is None:
        return _of_target(parse_target(target, arm))
    tasks = problem.tasks
    if len(tasks) > MAX_TASKS:
        raise TargetError(
            f"the servo follows at most {MAX_TASKS} tasks on the tip, got {len(tasks)}: "
            "give fewer tasks"
        )
    out = np.empty((len(tasks), COLUMNS))
    for t, task in enumerate(tasks):
        row = task.kernel_row() if len(task.frames) == 1 and task.frame is None else None
        if row is None:
            raise TargetError(
                f"the servo follows tasks on the tip (armik.Pose, Position, Axis, LookAt "
                f"without frame=), got {task!r}: give the target on the tip"
            )
        out[t] = _row(row)
    return out


def _of_target(target: Target) -> np.ndarray:
    if target.rotation is None:
        row = _POSITION.copy()
    else:
        row = _POSE.copy()
        row[ROT : ROT + 9] = target.rotation.ravel()
    row[POS : POS + 3] = target.position
    return row[None]


def _row(row: KernelRow) -> np.ndarray:
    out = np.empty(COLUMNS)
    out[ROT : ROT + 9] = np.ravel(row.R_t)
    out[POS : POS + 3] = row.p_t
    out[BOUNDS : BOUNDS + 6] = np.where(np.asarray(row.bounds) == 0.0, -EXACT, row.bounds)
    # only a task's weights' ratios matter: (100, 100, 100, 1, 1, 1) is (1, 1, 1, .01, ...)
    weights = np.asarray(row.weights, dtype=float)
    top = weights.max()
    out[WEIGHTS : WEIGHTS + 6] = weights / top if top > 0.0 else weights
    out[CONE] = row.cone
    out[AXIS : AXIS + 3] = row.axis
    out[LOOK] = row.look
    out[SIGHT : SIGHT + 3] = row.sight
    return out
