"""A path of several tips whose rows hold tasks no chain's own path reads as poses
(``armik.arms_steps``: a ``Relative``, one tip's pose in another's frame; a ``Position``
within bounds; several tasks of a tip): each step judged halfway on the whole robot, by the
rule one arm's path is judged by (``armik.solve.ladder``).

A small, straight step passes: no joint moves by more than ``BEND`` of the bound, and the
joints moved straight keep every task's placement (a ``Relative``'s in its reference frame)
within ``CHORD`` of its motion of the placement halfway (``ladder.straight``). Any other is
judged on the row halfway: every tip's target moved halfway (a pose's translation halved
and its rotation halved along its geodesic, ``ladder.poses_halfway``, a spin its bounds
free over a whole turn taken nearest the row before; a ``Relative``'s pose of its frame in
the other's; a ``Position``'s point), its bounds and weights kept. ``Arms.solve``, one
descent from the step's middle, then from each end and from points spread over the
configurations within the step of both ends (``_seeds``), verifies its answer in each
task's own measure (within a region: the distance outside its bounds); one within
``max_joint_step`` of both ends (``halfway.within``) passes the step. Where it bends from
the middle by more than ``BEND`` of the bound, both halves are judged the same way,
``DEPTH`` rounds at most. The robot is free there (no joint held, no constraint or
collision checked): any configuration that keeps them is one of the free robot's, so no
jump is made up, while one that they alone force is not seen.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import Any, NamedTuple, cast

import numpy as np
import pinocchio as pin

from armik import path_reasons
from armik.arms_request import ArmsRequest, read_request
from armik.batch_result import BatchResult
from armik.problem.problem import as_problem
from armik.problem.settings import SolverSettings
from armik.problem.tasks import Pose, Position, Relative, Task
from armik.problem.tasks.base import replaced
from armik.solve.halfway import _loose, within
from armik.solve.ladder import BEND, DEPTH, STEP_EDGE, judged_from, poses_halfway, straight
from armik.solve.rungs import free_spin
from armik.solvers.closed_form.spin import nearest_spin
from armik.status import Status
from armik.targets.batch import TargetBatch

AROUND = 12  # descents from about the step, beside those from its middle and its ends
# iterations of each descent halfway: one onto a bounded Relative (a region) closes in
# slowly (two IRB 120s: the default 100 stop outside it from every start; from the
# step's middle 1000 close in where 300 stop 2 mm and 0.13 rad off); a descent that runs
# them all costs only where no answer is near: a jump
DESCENT = 1000
Row = dict[str, Any]  # tip -> a pose (pin.SE3), a position ((3,) array) or a tuple of tasks


class _Judge(NamedTuple):
    """What every step of one path is judged with: the robot, ``max_joint_step`` per joint,
    the request of the solves halfway (``armik.arms_request``: its options read once), and
    the spin the path's bounds free (plain poses)."""

    arms: Any
    step: np.ndarray
    request: ArmsRequest
    spin: int | None


def hidden_steps(
    arms: Any,
    out: BatchResult,
    waypoints: Mapping[str, Any],
    step: np.ndarray,
    opts: SolverSettings,
    tips: Sequence[str],
    went: np.ndarray,
) -> None:
    """Each success of ``out`` whose step from the row the path went on from (``went``)
    hides a jump on the robot (module docstring) made ``discontinuous``, in place, the
    reason naming ``tips`` (those judged here). Rows holding a task none moves halfway (an
    ``Axis``, a ``LookAt``, an aim), or rows not alike but for where, are not judged; nor
    is a step over the bound (``arms_steps.held``'s to say)."""
    rows = _rows(arms, waypoints)
    if rows is None or _loose(arms, step):  # every flip within the bound: none hides
        return
    options = {"tol_position": opts.tol_position, "tol_orientation": opts.tol_orientation}
    for name in ("position_only", "weights", "bounds"):  # as the rows were solved
        if getattr(opts, name) not in (None, False):
            options[name] = getattr(opts, name)
    spin = None if opts.bounds is None else free_spin(opts.bounds)
    descent = {"max_restarts": 0, "max_iterations": DESCENT}
    judge = _Judge(arms, step, read_request(arms, {**options, **descent}), spin)
    for k, j in zip(*(x.tolist() for x in judged_from(out, went))):
        Qa, Qb = out.q[j], out.q[k]
        if not (np.abs(Qb - Qa) <= step + STEP_EDGE).all():  # no within of both ends
            continue
        if not _hides(judge, rows[j], rows[k], Qa, Qb, DEPTH):
            continue
        measured = path_reasons.row_verified(out, k)
        out.success[k] = False
        out.status_code[k] = Status.DISCONTINUOUS.code
        hidden = path_reasons.hidden_step("the previous waypoint's answer")
        jump = path_reasons.jump(hidden, "the followed answer", measured)
        out.reasons[k] = f"{', '.join(tips)}: {jump}"


def _hides(judge: _Judge, a: Row, b: Row, Qa: np.ndarray, Qb: np.ndarray, depth: int) -> bool:
    """Whether the step from ``Qa`` (on row ``a``) to ``Qb`` (on row ``b``) hides a jump:
    not small and straight, and no solution of the row halfway within the step of both
    ends; where the one found bends from the middle, either half hiding one."""
    if _straight(judge, a, Qa, Qb):
        return False
    half = {tip: _between(a[tip], b[tip], judge.spin) for tip in a}
    q = _solution(judge, half, Qa, Qb)
    if q is None:
        return True
    bend = float(np.max(np.abs(q - 0.5 * (Qa + Qb)) / judge.step))
    if depth > 1 and bend > BEND:
        return _hides(judge, a, half, Qa, q, depth - 1) or _hides(judge, half, b, q, Qb, depth - 1)
    return False


def _solution(judge: _Judge, row: Row, Qa: np.ndarray, Qb: np.ndarray) -> np.ndarray | None:
    """A verified answer for ``row`` within the step of both ends, each angle turned nearest
    its seed: one descent from each of ``_seeds`` in turn; None where none is."""
    arms = judge.arms
    spelled = {tip: list(t) if isinstance(t, tuple) else t for tip, t in row.items()}
    targets, relative = arms._parsed(spelled)  # the row halfway read once, as solve reads it
    for seed in _seeds(arms, Qa, Qb, judge.step):
        r = arms._solve_row(judge.request, targets, relative, arms._seed(seed))
        if not r.success:
            continue
        q = np.array(r.q, dtype=float)
        for tip, cols in arms._columns.items():  # a turn of a wide joint: nearest the seed
            q[cols] = arms._chains[tip].nearest_equivalent(q[cols], seed[cols])
        if within(q, Qa, Qb, judge.step):
            return q
    return None


def _seeds(arms: Any, Qa: np.ndarray, Qb: np.ndarray, step: np.ndarray) -> Iterator[np.ndarray]:
    """Where the descents halfway start, in turn: the step's middle, each end, then
    ``AROUND`` points spread over the configurations within the step of both ends and the
    limits (fixed: the same every call). A descent from the middle stalls on a joint limit
    where the self-motion holds a solution within the step further along (TALOS's torso
    and an elbow at their limits: one 0.37 rad off the middle)."""
    yield from (0.5 * (Qa + Qb), Qa, Qb)
    lo = np.maximum(np.maximum(Qa, Qb) - step, arms.lower)
    hi = np.minimum(np.minimum(Qa, Qb) + step, arms.upper)
    for u in np.random.default_rng(0).uniform(0.0, 1.0, (AROUND, len(step))):
        yield lo + u * (hi - lo)


def _straight(judge: _Judge, row: Row, Qa: np.ndarray, Qb: np.ndarray) -> bool:
    """Whether the step is small and straight: no joint moves by more than ``BEND`` of the
    bound, and every task's placement keeps on its way (``ladder.straight``; a rotation
    weighed at its tip's chain's reach)."""
    arms = judge.arms
    if not (np.abs(Qb - Qa) <= BEND * judge.step).all():
        return False
    Q = (Qa, Qb, 0.5 * (Qa + Qb))
    for tip, target in row.items():
        reach = arms._chains[tip].reach
        reach = reach if np.isfinite(reach) else 1.0
        for frame, reference, rotations in _placed(tip, target):
            H = np.array([_placement(arms, q, frame, reference).homogeneous for q in Q])
            if not straight(H, reach if rotations else None)[0]:
                return False
    return True


def _placed(tip: str, target: object) -> list[tuple[str, str | None, bool]]:
    """What each task of ``target`` (one tip's, as ``_targets`` reads it) places: (frame,
    the frame it is placed in or None for the base, whether its rotation counts)."""
    if isinstance(target, pin.SE3):
        return [(tip, None, True)]
    if isinstance(target, np.ndarray):
        return [(tip, None, False)]
    out: list[tuple[str, str | None, bool]] = []
    for task in cast(tuple, target):
        if isinstance(task, Relative):
            out.append((cast(str, task.frame), task.relative_to, True))
        else:
            out.append((task.frame or tip, None, isinstance(task, Pose)))
    return out


def _placement(arms: Any, q: np.ndarray, frame: str, reference: str | None) -> pin.SE3:
    """``frame``'s placement at ``q`` (Pinocchio's FK), in ``reference``'s where given."""
    T = arms.fk(q, frame)
    return T if reference is None else arms.fk(q, reference).actInv(T)


def _rows(arms: Any, waypoints: Mapping[str, Any]) -> list[Row] | None:
    """Each row of the path as tip -> its target (``_targets``; ``waypoints``: each tip's
    rows read once, ``arms_steps.hidden_steps``'); None where a tip's rows are not all
    moved halfway."""
    each = {}
    for tip, rows in waypoints.items():
        read = _targets(rows)
        if read is None:
            return None
        each[tip] = read
    n = len(next(iter(each.values()), []))
    return [{tip: targets[i] for tip, targets in each.items()} for i in range(n)]


def _targets(rows: Any) -> list | None:
    """A tip's rows as its poses (``pin.SE3``) or positions where they are those (a
    ``TargetBatch``, read once), else its rows of tasks, each a ``Pose``, a ``Position`` or
    a ``Relative``, alike in every row but for where they hold their frames; None otherwise
    (another task, an aim, poses and positions together)."""
    batch = rows if type(rows) is TargetBatch else None
    if batch is not None:
        if batch.aim is not None:
            return None
        if batch.rotations is None:
            return list(np.array(batch.positions, dtype=float))
        return [pin.SE3(R, p) for R, p in zip(batch.rotations, batch.positions)]
    tasks = []
    for row in rows:
        problem = as_problem(row) if isinstance(row, (Task, list, tuple)) else None
        if problem is None:
            return None
        tasks.append(tuple(problem.tasks))
    first = tasks[0] if tasks else ()
    alike = all(len(t) == len(first) and all(map(_alike, t, first)) for t in tasks)
    return tasks if alike else None


def _alike(a: Task, b: Task) -> bool:
    """Whether tasks ``a`` and ``b`` differ only in where they hold their frames: a
    ``Pose``, ``Position`` or ``Relative`` each, on the same frames, bounds and weights."""
    if type(a) is not type(b) or type(a) not in (Pose, Position, Relative) or a.frame != b.frame:
        return False
    if isinstance(a, Relative) and isinstance(b, Relative):
        if a.relative_to != b.relative_to:
            return False
        a, b = a.pose, b.pose
    same = np.array_equal(getattr(a, "weights", ()), getattr(b, "weights", ()))
    return same and np.array_equal(getattr(a, "bounds", ()), getattr(b, "bounds", ()))


def _between(a: object, b: object, spin: int | None) -> object:
    """A tip's target halfway from ``a`` to ``b`` (``_targets``'): a pose's or a position's,
    or each task's (``_task_between``); ``spin``: the axis a plain pose's bounds free."""
    if isinstance(a, pin.SE3) and isinstance(b, pin.SE3):
        return _pose_between(a, b, spin)
    if isinstance(a, np.ndarray) and isinstance(b, np.ndarray):
        return 0.5 * (a + b)
    return tuple(map(_task_between, a, b))  # type: ignore[call-overload]


def _task_between(a: Task, b: Task) -> Task:
    """Task ``a`` held halfway to where ``b`` holds its frame, its bounds and weights kept."""
    if isinstance(a, Position) and isinstance(b, Position):
        return replaced(a, p=0.5 * (a.p + b.p))
    if isinstance(a, Relative) and isinstance(b, Relative):
        return replaced(a, pose=_task_between(a.pose, b.pose))
    assert isinstance(a, Pose) and isinstance(b, Pose)
    return replaced(a, T=_pose_between(a.T, b.T, free_spin(tuple(a.bounds.tolist()))))


def _pose_between(Ta: pin.SE3, Tb: pin.SE3, spin: int | None) -> pin.SE3:
    """The pose halfway from ``Ta`` to ``Tb`` (``poses_halfway``), ``Tb`` first turned about
    its axis ``spin`` (free over a whole turn: the same poses) nearest ``Ta``."""
    Rb = Tb.rotation if spin is None else nearest_spin(Tb.rotation, Ta.rotation, spin)[0]
    P, R = poses_halfway(Ta.translation[None], Ta.rotation[None], Tb.translation[None], Rb[None])
    return pin.SE3(R[0], P[0])
