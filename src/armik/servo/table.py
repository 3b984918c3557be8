"""A servo's target as the compiled tick's table: one row per task on the tip.

Anything ``Arm.solve`` takes for one tip: a pose or a position in any spelling
``armik.parse_target`` reads, an ``armik.Pose`` (with ``bounds=``, ``weights=``), a
``Position``, an ``Axis``, a ``LookAt``, or a list of them, each task's row its
``kernel_row`` (``kernel.region``'s six rows). Each target is parsed once, here.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping

import numpy as np
import pinocchio as pin

from armik.errors import OptionError, TargetError
from armik.kernel.problem import NO_CONE, NO_LOOK
from armik.kernel.single import plain_pose
from armik.model.arm_model import ArmModel
from armik.options import checked_weights
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
    PARTS,
    POS,
    ROT,
    SIGHT,
    WEIGHTS,
)
from armik.targets.pose import Target, parse_target
from armik.tolerances import MAX_WEIGHT

_POSE = np.full(COLUMNS, 0.0)  # a pose's row: exact, every axis weighted
_POSE[BOUNDS : BOUNDS + 6] = -EXACT
_POSE[WEIGHTS : WEIGHTS + 6] = 1.0
_POSE[CONE], _POSE[AXIS + 2], _POSE[LOOK] = NO_CONE, 1.0, NO_LOOK
_POSE[PARTS : PARTS + 2] = 1.0
_POSITION = _POSE.copy()  # a position's: the rotation free, and none to report
_POSITION[ROT : ROT + 9] = np.eye(3).ravel()
_POSITION[BOUNDS + 3 : BOUNDS + 6] = math.inf
_POSITION[PARTS + 1] = 0.0


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
    weights = _weights(row.weights)
    top = weights.max()
    out[WEIGHTS : WEIGHTS + 6] = weights / top if top > 0.0 else weights
    out[CONE] = row.cone
    out[AXIS : AXIS + 3] = row.axis
    out[LOOK] = row.look
    out[SIGHT : SIGHT + 3] = row.sight
    out[PARTS], out[PARTS + 1] = row.parts
    return out


def _weights(weights: object) -> np.ndarray:
    """A task's weights by the rule ``solve`` reads them with (``options.checked_weights``:
    none above ``MAX_WEIGHT`` nor more than ``MAX_WEIGHT`` times the smallest positive one,
    whose squared errors would drown in the others' rounding); a ``TargetError`` with its
    message otherwise."""
    w = np.asarray(weights, dtype=float)
    if w.shape == (6,) and 0.0 < w[0] <= MAX_WEIGHT and (w == w[0]).all():
        return w  # equal weights (a task's default): the rule holds, at a tenth of its cost
    try:
        return np.array(checked_weights(tuple(w.tolist())))
    except OptionError as error:
        raise TargetError(str(error)) from None


def plain_matrix(target: object) -> np.ndarray | None:
    """The 4x4 of a ``pin.SE3`` or of a writable float64 C-order 4x4 array (what the
    compiled tick may write itself, where ``plain_pose`` holds), else None."""
    if isinstance(target, pin.SE3):
        return target.homogeneous
    if (
        type(target) is np.ndarray
        and target.shape == (4, 4)
        and target.dtype == np.float64
        and target.flags.c_contiguous
        and target.flags.writeable
    ):
        return target
    return None


def read(target: object, arm: ArmModel) -> np.ndarray | None:
    """None for a pose the compiled tick writes itself (``plain_matrix``, ``plain_pose``),
    else ``target``'s table; raises ``TargetError`` for a target the servo cannot read."""
    H = plain_matrix(target)
    if H is not None and plain_pose(H):
        return None
    return table(target, arm)


def sequence(targets: object, mapping: bool = False) -> list:
    """``targets`` (``track``'s: one target a tick) as a list; raises ``OptionError`` for
    one target given alone (a pose, a position, a task, with ``mapping`` a mapping tip ->
    target) or none, naming the fix."""
    one = isinstance(targets, (pin.SE3, str, bytes, Mapping)) or not isinstance(targets, Iterable)
    if isinstance(targets, np.ndarray):
        one = targets.ndim < 2 or targets.shape == (4, 4)
    elif isinstance(targets, (list, tuple)) and targets:
        one = all(isinstance(x, (int, float, np.number)) for x in targets)
    if (
        targets is None
        or isinstance(targets, (str, bytes))
        or (one and mapping and not isinstance(targets, Mapping))
    ):  # no target at all, or no mapping: not "one given alone"
        each = " (each a mapping {tip: target})" if mapping else ""
        raise OptionError(
            f"track takes a sequence of targets, one a tick{each}, got "
            f"{type(targets).__name__} {targets!r:.60}: pass a list ([target] * ticks)",
            option="targets",
            value=targets,
        )
    if one:
        what = "a mapping {tip: target}" if mapping else "a target"
        raise OptionError(
            f"track takes a sequence of targets, one a tick, got {what} alone "
            f"({type(targets).__name__}): use step(...) for one tick, or pass a list "
            "([target] * ticks)",
            option="targets",
            value=targets,
        )
    items = list(targets)  # type: ignore[call-overload]
    if not items:
        raise OptionError("targets must hold at least one target", option="targets")
    return items


def at_tick(i: int, error: TargetError) -> TargetError:
    """``error`` of the target of tick i, said before any tick ran."""
    return TargetError(f"target {i}: {error} (no tick ran: the servo is where it was)")
