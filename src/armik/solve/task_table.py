"""A list of tasks as the compiled descent's table (``armik.kernel.task_rows``): each task's
rows (``Task.kernel_row``) on its frame's chain (``armik.model.frame_chains``), for any
number of tasks on any frames of one model: both hands and the torso between them, an
elbow and the tip, three tasks on one tip, one hand's pose in the other's (a task with
a second frame, ``armik.Relative``, is placed in that frame's).

A new task the compiled step can take says so in its ``kernel_row``; the table and the
descent do not change. A list with a task that has no row (one of the user's own) has no
table, and the task solver's Python descent takes it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from armik.kernel.task_rows import PARAMS, descend
from armik.model.derived import DerivedBy
from armik.model.frame_chains import FrameChains, frame_chains
from armik.problem.tasks import Task
from armik.problem.tasks.base import KernelRow

# an arm's (or a union's) chains of a tuple of frames, or None where they have no form
_CHAINS: DerivedBy[FrameChains | None] = DerivedBy("frame chains", frame_chains)


class TaskTable(NamedTuple):
    """The arrays ``task_rows.descend`` takes besides q and the box."""

    chains: FrameChains
    R_t: np.ndarray  # (T, 3, 3)
    p_t: np.ndarray  # (T, 3)
    params: np.ndarray  # (T, PARAMS)
    ints: np.ndarray  # (T, 3): chain, look, reference chain (-1: the base)


def task_table(arm, tasks: tuple[Task, ...], ids) -> TaskTable | None:
    """The table of ``tasks`` on their frames (``ids``: each task's frame ids in
    ``arm.model``, ``tasks.frame_ids``), or None where a task or a frame has no compiled
    form."""
    rows: list[KernelRow] = []
    found: dict[int, None] = {}  # the frames, in order, once each
    for task, f in zip(tasks, ids):  # one pass: every solve of the task solver builds one
        row = task.kernel_row()
        if row is None or len(f) not in (1, 2):
            return None
        rows.append(row)
        found.update(dict.fromkeys(f))
    frames = tuple(found)
    chains = _CHAINS(arm, frames)
    if chains is None:
        return None
    T = len(rows)
    R_t, p_t = np.empty((T, 3, 3)), np.empty((T, 3))
    params, ints = np.empty((T, PARAMS)), np.empty((T, 3), dtype=np.int64)
    for t, row in enumerate(rows):
        R_t[t], p_t[t] = row.R_t, row.p_t
        params[t] = [*row.bounds, *row.weights, row.cone, *row.axis, *row.sight]
        # a second frame is the one the first's pose is in (``Relative``)
        reference = frames.index(ids[t][1]) if len(ids[t]) == 2 else -1
        ints[t] = frames.index(ids[t][0]), row.look, reference
    table = TaskTable(chains, R_t, p_t, params, ints)
    if not descend.signatures:  # loaded (or compiled) now, before a budget's clock starts
        q = np.zeros(arm.dof)
        descend_table(table, q, (q - 1.0, q + 1.0), 0, 1.0, 1.0, 1.0)
    return table


def descend_table(
    table: TaskTable,
    q: np.ndarray,
    box: tuple[np.ndarray, np.ndarray],
    iterations: int,
    tol_position: float,
    tol_orientation: float,
    lam0: float,
) -> tuple[np.ndarray, int]:
    """(q, iterations used): the compiled descent from ``q`` within ``box``."""
    ch = table.chains
    q = np.array(q, dtype=float)
    lo, hi = np.array(box[0], dtype=float), np.array(box[1], dtype=float)  # writable: one signature
    used, _ = descend(
        ch.packed,
        ch.offsets,
        ch.kinds,
        ch.kind_offsets,
        ch.halton,
        table.R_t,
        table.p_t,
        table.params,
        table.ints,
        q,
        lo,
        hi,
        int(iterations),
        float(tol_position),
        float(tol_orientation),
        float(lam0),
    )
    return q, int(used)
