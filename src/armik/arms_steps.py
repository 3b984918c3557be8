"""How a path of several tips (``Arms.solve_path``) judges its steps: a move larger than
``max_joint_step`` (``held``) and a jump hidden between two waypoints (``hidden_steps``),
as one arm's path judges them (``armik.solve.ladder``).

A hidden jump is looked for tip by tip, on each tip's chain (its columns of the rows), by
the rule one arm's path is judged by (``ladder.hidden_steps``): a step whose chain has no
solution at the halfway pose within the step of both ends has none for the robot either,
since the robot's configuration there would hold one for that chain. A tip whose rows are
no poses of its chain (a ``Relative``, a ``Position`` within bounds, several tasks) is
judged by the same rule on the whole robot, every tip's target moved halfway
(``armik.arms_halfway``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from pinocchio import SE3

from armik import arms_halfway, path_reasons, reasons
from armik.batch_result import BatchResult
from armik.problem.problem import as_problem, as_target, lower
from armik.problem.tasks import Task
from armik.request import but_options
from armik.result import IKResult
from armik.solve import ladder
from armik.solve.read import options as read_options
from armik.solve.rungs import free_spin, spun_batch
from armik.solve.turning import ANY
from armik.status import Status
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target


def held(arms: Any, r: IKResult, q_prev: np.ndarray, step: np.ndarray, first: bool):
    """``r``, or ``r`` reported ``discontinuous`` when a joint moves by more than its step."""
    moved = np.abs(np.asarray(r.q) - q_prev)
    j = int(np.argmax(moved / step))
    if moved[j] <= step[j]:
        return r
    start = "q0 (the start)" if first else "the previous waypoint's answer"
    unit = "m" if arms.prismatic[j] else "rad"
    move = path_reasons.moved(arms.joint_names[j], moved[j], unit, start, step[j])
    # what the verdicts measured (the worst tip's), the distances beside where they differ
    apart = r.measured
    said = reasons.best_errors(*(apart or (r.position_error, r.orientation_error)))
    if apart is not None:
        said = reasons.tips_apart(said, r.position_error, r.orientation_error)
    return dataclasses.replace(
        r,
        success=False,
        status=Status.DISCONTINUOUS,
        reason=path_reasons.jump(path_reasons.jump_found(move), "that answer", said),
    )


def hidden_steps(
    arms: Any,
    out: BatchResult,
    waypoints: Mapping[str, TargetBatch | Sequence],
    step: np.ndarray,
    opts,
    went: np.ndarray | None = None,
) -> None:
    """Each success of ``out`` whose step from the row the path went on from (``went``:
    the rows it went on from; None: each success or jump, as one arm's path goes on) hides
    a jump for some tip's chain made ``discontinuous``, in place, the reason naming the
    tip. ``waypoints``: each tip's rows read once, its poses or positions a ``TargetBatch``
    (``stacked``), its rows of tasks as given. Tips given poses or positions, or a pose as
    a task (``_poses``), on their chains:
    the halfway poses solved with ``opts``' tolerances and the task's loosening
    (``position_only``, ``weights``, ``bounds``: measured as one arm's path measures them, a
    spin the bounds free turned as its path turns it), the chain free (a held joint is
    looser there: a jump may pass, none is made up). Tips given other tasks (a
    ``Relative``, a ``Position`` within bounds, several tasks): the steps still successes
    judged on the robot (``arms_halfway.hidden_steps``), the reason naming those tips."""
    task = {
        "tol_position": opts.tol_position,
        "tol_orientation": opts.tol_orientation,
        "position_only": opts.position_only,
        "weights": opts.weights,
        "bounds": opts.bounds,
    }
    if went is None:  # read before any step is judged: a jump found here is gone on from
        went = out.success | (out.status_code == Status.DISCONTINUOUS.code)
    unread = []  # tips whose rows are no poses of their chains: judged on the robot
    for tip, rows in waypoints.items():
        chain, cols = arms._chains[tip], arms._columns[tip]
        read = _poses(tip, rows)
        if read is None:
            unread.append(tip)
            continue
        targets, said = read
        plain = but_options(read_options({}), **{**task, **said})
        spin = None if plain.bounds is None else free_spin(plain.bounds)
        targets = spun_batch(chain, targets, out.q[0, cols], spin)  # as its own path's
        part = BatchResult.for_arm(chain, len(out), out.solver, plain)
        part.q[:] = out.q[:, cols]
        part.success[:] = out.success
        part.status_code[:] = out.status_code
        errors = out.errors.get(tip)
        part.position_error[:] = out.position_error if errors is None else errors[:, 0]
        part.orientation_error[:] = out.orientation_error if errors is None else errors[:, 1]
        ladder.hidden_steps(chain, part, targets, step[cols], ("auto", plain, None, ANY), went)
        for k in np.flatnonzero(out.success & ~part.success).tolist():
            out.success[k] = False
            out.status_code[k] = Status.DISCONTINUOUS.code
            out.reasons[k] = f"{tip}: {part.reasons[k]}"
    if unread:
        arms_halfway.hidden_steps(arms, out, waypoints, step, opts, unread, went)


def _posed(target: object) -> bool:
    """Whether a lowered target is a pose or a position (an ``armik.Axis`` exactly along a
    direction too: a pose whose spin is free), not an aim's."""
    return isinstance(target, (SE3, np.ndarray)) or (type(target) is Target and target.aim is None)


def _poses(tip: str, rows: TargetBatch | Sequence) -> tuple[TargetBatch, dict] | None:
    """(poses, what the tasks say beside them) of a tip's rows: its poses or positions as
    read (a ``TargetBatch``); a task of each row's lowered as one arm's ``solve`` lowers it
    (``lower``: a ``Pose`` with bounds or weights, the bounds and weights said) where every
    row says the same beside a pose, or a position, the tasks' values as they read them;
    None for other tasks (a ``Relative``, several)."""
    if isinstance(rows, TargetBatch):
        return rows, {}
    problems = [as_problem(row) if isinstance(row, (Task, list, tuple)) else None for row in rows]
    lowered = [None if p is None else lower(p, tip) for p in problems]
    if not lowered or any(x is None or not _posed(x[0]) for x in lowered):
        return None
    said = lowered[0][1]  # type: ignore[index]
    if any(x[1] != said for x in lowered):  # type: ignore[index]
        return None
    batch = stacked([as_target(x[0]) for x in lowered])  # type: ignore[index]
    return None if type(batch) is not TargetBatch else (batch, said)


def stacked(rows: Sequence) -> TargetBatch | Sequence:
    """A tip's rows, each read once (a parsed ``Target``, or tasks), as its path is judged:
    its poses, or its positions, as one ``TargetBatch`` (their values as read, not read
    again); ``rows`` as given where they are tasks, or poses and positions together."""
    if not rows or any(type(t) is not Target for t in rows):
        return rows
    kinds = {t.rotation is None for t in rows}
    if len(kinds) != 1:  # some with a rotation, some without: no batch has both
        return rows
    positions = np.array([t.position for t in rows], dtype=float)
    if kinds == {True}:
        return TargetBatch(positions)
    return TargetBatch(positions, np.array([t.rotation for t in rows], dtype=float))
