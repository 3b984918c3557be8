"""What a batch or a path of several tips (``Arms.solve_batch``, ``Arms.solve_path``:
``armik.arms_many``) is given, read once: N rows per tip (``count_rows``; one pose where a
tip needs its N refused by name), the tips in the robot's order, q0 as each row's seed
(``row_seeds``: one configuration or one per row, checked and clipped as ``Arm``'s seed), and
each target parsed once: each tip's rows where its chain's own batch or path takes them
(``read_rows``), else each row as ``Arms.solve`` parses it (``parsed_rows``), a row of
either as ``Arms._solve_row`` takes it (``row_of``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from armik.arms_rows import at, row_named
from armik.errors import OptionError, TargetError
from armik.solve.task_lists import task_problems
from armik.targets.batch import TargetBatch, parse_targets
from armik.tolerances import LIMIT_TOL


def read_rows(arms: Any, targets: Mapping[str, Any]) -> dict[str, Any]:
    """Each tip's rows (``targets``: tip -> N rows) parsed once, as its chain's own batch or
    path parses them: its poses or positions as a ``TargetBatch``, its rows of tasks as
    given (each chain's solve reads them)."""
    read = {}
    for tip, rows in targets.items():
        tasks = type(rows) in (list, tuple) and task_problems(rows) is not None
        read[tip] = rows if tasks else parse_targets(rows, arms._chains[tip])
    return read


def row_of(arms: Any, read: Mapping[str, Any], i: int) -> tuple[dict, dict]:
    """(targets, relative): row ``i`` of each tip's rows read once (``read_rows``', or
    each row parsed: ``parsed_rows``), as ``Arms._solve_row`` takes it."""
    row = {tip: at(rows, i) for tip, rows in read.items()}
    return row, arms._check_targets(row)


def parsed_rows(arms: Any, targets: Mapping[str, Any], n: int) -> list[tuple[dict, dict]]:
    """Every row of ``targets`` (tip -> N rows) parsed once, as ``Arms.solve`` parses its
    targets (a bad one named by its row and its tip)."""
    out = []
    read = frozenset(tip for tip, rows in targets.items() if isinstance(rows, TargetBatch))
    for i in range(n):
        with row_named(i):
            out.append(arms._parsed({tip: at(rows, i) for tip, rows in targets.items()}, read))
    return out


def count_rows(arms: Any, targets: object, call: str) -> int:
    """N, the rows of ``targets`` (tip -> N targets); a ``TargetError`` naming the tip given
    one pose (the dict ``Arms.solve`` takes) where ``call`` (the method) needs its rows."""
    if isinstance(targets, Mapping) and not targets:
        raise TargetError(
            f"no targets: give each tip's targets, {{tip: targets}} over {list(arms.tips)}"
        )
    if not isinstance(targets, Mapping):
        raise OptionError(
            f"targets must map tip names {list(arms.tips)} to each tip's targets, or be N "
            "rows, each a list of tasks naming their frames (armik.Pose(T, frame=tip)), got "
            f"{type(targets).__name__}",
            option="targets",
            value=targets,
        )
    arms._check_targets({tip: None for tip in targets})
    for tip, rows in targets.items():
        one = _one_pose(rows)
        if one:
            raise TargetError(
                f"Arms.{call}: tip {tip!r} needs a sequence of poses, one per row (N rows), "
                f"got {one}: give every tip its N poses, {{tip: [pose, ...]}}; Arms.solve "
                "takes one pose per tip"
            )
    sizes = {tip: len(rows) for tip, rows in targets.items()}
    if len(set(sizes.values())) != 1:
        raise TargetError(f"every tip needs as many targets as the others, got {sizes}")
    return next(iter(sizes.values()))


def in_tips_order(arms: Any, targets: Mapping[str, Any]) -> dict[str, Any]:
    """``targets`` in the order of ``arms.tips``, as ``Arms.solve`` reads them: the first
    failing tip's status and the order of the reason's tips are the robot's, not the
    dict's."""
    return {tip: targets[tip] for tip in arms.tips if tip in targets}


def _one_pose(rows: object) -> str:
    """What ``rows`` is when it is one pose (a ``pinocchio.SE3``, a 4x4 matrix, a (7,) row
    or a (3,) position, ``(position, quaternion)``, a task) rather than a tip's N rows;
    "" otherwise."""
    if isinstance(rows, (str, bytes)) or not hasattr(rows, "__len__"):
        many = hasattr(rows, "__iter__") and not isinstance(rows, (str, bytes))
        return (
            f"a {type(rows).__name__}, which has no length"
            if many
            else f"one {type(rows).__name__}"
        )
    if isinstance(rows, np.ndarray):
        return f"an array of shape {rows.shape}" if rows.shape in _ONE_POSE else ""
    if not isinstance(rows, (list, tuple)) or not rows:
        return ""
    if isinstance(rows[0], (int, float, np.number)) and len(rows) in (3, 7):
        return f"one {type(rows).__name__} of {len(rows)} numbers"
    shapes = [_shape(row) for row in rows[:4]]
    if len(rows) == 4 and shapes == [(4,)] * 4:
        return "one 4x4 matrix"
    if len(rows) == 2 and shapes == [(3,), (4,)]:
        return "one (position, quaternion)"
    return ""


_ONE_POSE = ((4, 4), (7,), (3,))  # an array of one of these shapes is one target


def _shape(row: object) -> tuple[int, ...]:
    """``row``'s shape as an array's; () for a ragged one (a row's ``(position,
    quaternion)``: a pose of a tip's rows, not one pose's row)."""
    if not isinstance(row, (list, tuple, np.ndarray)):
        return ()
    try:
        return np.shape(row)
    except ValueError:  # numpy refuses ragged nesting
        return ()


def row_seeds(arms: Any, q0: object, n: int) -> np.ndarray:
    """(n, dof) seeds from None, one configuration or one per row."""
    if q0 is None:
        return np.tile(arms.middle, (n, 1))
    try:  # numbers only: a string or a complex value is no configuration
        if isinstance(q0, (str, bytes)) or np.iscomplexobj(q0):  # type: ignore[arg-type]
            raise TypeError
        q = np.asarray(q0, dtype=float)
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        q = None
    if q is None or q.shape not in ((arms.dof,), (n, arms.dof)):
        got = f"shape {q.shape}" if q is not None else f"{q0!r:.80}"
        raise OptionError(
            f"q0 must be None, one configuration ({arms.dof} values, one per joint of "
            f"{list(arms.joint_names)}) or one per target ({n}, {arms.dof}), got {got}",
            option="q0",
            value=q0,
        )
    if q.shape == (arms.dof,):
        return np.tile(arms._seed(q), (n, 1))  # clipped into the limits, as Arm's seed
    if not np.isfinite(q).all():  # the row and the robot's joint, not a chain's part
        i, j = np.argwhere(~np.isfinite(q))[0]
        raise OptionError(
            f"q0 must be finite: row {i} is {q[i].tolist()}, not finite at {arms.joint_names[j]!r}",
            option="q0",
            value=q0,
        )
    out = q.copy()
    outside = (q < arms.lower - LIMIT_TOL) | (q > arms.upper + LIMIT_TOL)
    for i in np.flatnonzero(outside.any(axis=1)).tolist():  # clipped, as Arm's seed
        out[i] = arms._seed(q[i], i)
    return out
