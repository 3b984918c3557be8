"""Solve a problem of tasks (``armik.problem``) that the compiled path has no form for: a
task on another frame, more than two tasks, a look-at of the point the tip stands on.

Damped least squares (Levenberg-Marquardt) on the stacked task residuals, each step
clipped into the joint limits; random restarts within the budget (``timeout`` in CPU time
of the solving thread, or the deterministic ``iteration_budget``); the answer nearest
meeting every task is kept. Every answer is measured by each task on Pinocchio's FK
(``Task.measure``) with the call's tolerances, and by the limits, before it is called a
success. A miss is ``not_converged``: a numeric search does not show a target out of reach.

With a score (``prefer=`` over several tips' shared joints: ``nearest``, ``limits``, an
``armik.Posture``, a cost; or a secondary ``armik.Posture``), the answer found is moved
along what the tasks leave free (their null space: the self-motion, a region's slack)
while the score falls (``armik.solve.nullspace``), and kept only where every task still
holds on Pinocchio's FK: a posture task for the joints no task fixes. A local descent
from the answer found.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable

import numpy as np
import pinocchio as pin

from armik import cpu_time, reasons
from armik.constraints.base import Constraint, satisfied
from armik.constraints.hold import Hold
from armik.constraints.limits import JointLimits
from armik.errors import TargetError
from armik.model import mimic_frames
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.model.frames import named
from armik.problem.problem import Problem
from armik.problem.scores import Posture, Score
from armik.problem.settings import SolverSettings
from armik.problem.tasks import Pose, Task, TaskError
from armik.result import IKResult
from armik.solve.nullspace import descend
from armik.solve.task_table import descend_table, task_table
from armik.solvers.answers import one
from armik.status import Status
from armik.verify.verdict import status_of
from armik.verify.verdicts import Verdicts

SOLVER = "tasks"
LAMBDA0 = 1e-3  # the damping's start, relative to the largest diagonal of J^T J
NEAR = 1e-3  # m + rad: a descent ending this close goes on (``solve_tasks``) ...
CLOSING = 0.5  # ... while each run of iterations at least halves its error
AIM = 0.9  # the descent aims at the regions scaled by this (``Task.shrunk``)
SCORE_STEPS = 40  # null-space steps for a score at most (each a few Newton steps)
CENTRE_RESTARTS = 20  # the centre's compiled attempt: out of reach where the region may not be


def frame_ids(arm: ArmModel, tasks: tuple[Task, ...]) -> tuple[tuple[int, ...], ...]:
    """Each task's frames (``Task.frames``) as indices of the arm's Pinocchio model (None:
    the tip); an ``armik`` error naming a frame the model does not have. Looked up once
    per arm for the same frames (a loop of solves asks for the same ones)."""
    names = tuple([tuple(t.frames) for t in tasks])
    known = arm._derived.get(_IDS)  # read as a dict, not through a call: every solve
    if known is None:
        known = _IDS(arm)
    found = known.get(names)
    if found is None:
        found = tuple([tuple([_frame_id(arm, t, f) for f in t.frames]) for t in tasks])
        if len(known) > 256:
            known.clear()
        known[names] = found
    return found


_IDS: Derived[dict] = Derived("frame ids of task frames", lambda _: {})
_FOLLOWED: Derived[dict] = Derived("task frames a mimic joint off the chain moves", lambda _: {})


def _frame_id(arm: ArmModel, task: Task, frame: str | None) -> int:
    if frame is None or frame == arm.tip:
        return arm.tip_frame_id
    if arm.model.existFrame(frame):
        i = named(arm.model, frame)  # a name a joint and a link share: the link's
        if not isinstance(arm, ArmModel):  # a union of chains holds such a frame still
            arm.refuse_followed(frame)
        elif (whole := mimic_frames.full_frame(arm, frame)) is not None:  # a mimic joint the
            _FOLLOWED(arm)[i] = whole  # chain's model holds moves it: placed on the whole model
        return i
    names = sorted(f.name for f in arm.model.frames)
    raise TargetError(
        f"{type(task).__name__} asks for frame {frame!r}, which this arm's model does not "
        f"have; its frames: {names}"
    )


def _placed(arm: ArmModel, q: np.ndarray, ids) -> dict:
    """Each frame's (T_base_frame, LOCAL Jacobian) at ``q`` from one pass of Pinocchio's
    kinematics; a frame the chain does not move keeps a zero Jacobian."""
    model, data = arm.model, arm.data
    pin.computeJointJacobians(model, data, arm.to_pin(q))
    placed, followed = {}, arm._derived.get(_FOLLOWED)
    for i in {i for frames in ids for i in frames}:
        if followed and i in followed:  # one pass of the whole model's kinematics
            placed[i] = mimic_frames.placed(arm, q, followed[i], pin.LOCAL)
            continue
        T = arm.T_base_world * pin.updateFramePlacement(model, data, i)
        placed[i] = (T, pin.getFrameJacobian(model, data, i, pin.LOCAL).reshape(6, arm.dof))
    return placed


def _on(tasks, ids, placed: dict) -> list:
    """Each task's (placement, Jacobian) from its frames' (``Task.placement``)."""
    return [t.placement([placed[i] for i in frames]) for t, frames in zip(tasks, ids)]


def _stack(tasks: tuple[Task, ...], ids, placed: dict):
    on = _on(tasks, ids, placed)
    r = np.concatenate([t.residual(T) for t, (T, _) in zip(tasks, on)])
    A = np.vstack([t.jacobian(T, J) for t, (T, J) in zip(tasks, on)])
    return r, A


class HeldTasks:
    """The tasks' residual rows (``nullspace.Held``), the rows no task constrains at ``q``
    (a region's slack: zero residual, zero Jacobian) dropped, so that they are left free."""

    def __init__(self, arm: ArmModel, tasks: tuple[Task, ...], ids) -> None:
        self.arm, self.tasks, self.ids = arm, tasks, ids
        self._at: tuple[bytes, np.ndarray, np.ndarray] | None = None

    def _rows(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = q.tobytes()
        if self._at is None or self._at[0] != key:
            r, A = _stack(self.tasks, self.ids, _placed(self.arm, q, self.ids))
            active = (r != 0.0) | np.any(A != 0.0, axis=1)
            self._at = (key, r[active], A[active])
        return self._at[1], self._at[2]

    def residual(self, q: np.ndarray) -> np.ndarray:
        return self._rows(q)[0]

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        return self._rows(q)[1]


def _measure(
    arm: ArmModel, tasks, ids, q: np.ndarray, opts: SolverSettings, placed=None
) -> list[TaskError]:
    """Each task on its frames' placements by Pinocchio's FK (the verdict's)."""
    if placed is None:
        model, data, T_base = arm.model, arm.data, arm.T_base_world
        pin.forwardKinematics(model, data, arm.to_pin(q))
        placed = {
            i: (T_base * pin.updateFramePlacement(model, data, i), None)
            for i in {i for frames in ids for i in frames}
        }
        if followed := arm._derived.get(_FOLLOWED):  # placed on the whole model (_frame_id)
            for i in placed.keys() & followed.keys():
                placed[i] = (mimic_frames.placement(arm, q, followed[i]), None)
    tol_p, tol_o, get = opts.tol_position, opts.tol_orientation, placed.__getitem__
    return [t.measure(t.placement(list(map(get, f)))[0], tol_p, tol_o) for t, f in zip(tasks, ids)]


def measure_tasks(
    arm: ArmModel, problem: Problem, q: np.ndarray, opts: SolverSettings
) -> list[TaskError]:
    """Each of ``problem``'s tasks measured at ``q`` on Pinocchio's FK, with the tolerances
    of ``opts``: what ``extra["task_errors"]`` holds where the task solver answered."""
    return _measure(arm, problem.tasks, frame_ids(arm, problem.tasks), q, opts)


def _descend(
    arm: ArmModel, tasks, ids, q: np.ndarray, opts: SolverSettings, iterations: int, box, table=None
):
    """(q, iterations used): Levenberg-Marquardt from ``q`` until every task holds (on
    Pinocchio's placements) or the iterations run out, each step clipped into ``box``
    (lower, upper: the constraints' rows, ``box_of``). With ``table`` (the tasks' compiled
    rows aimed inside their regions, ``task_table``), the same descent compiled."""
    if table is not None:
        tol_p, tol_r = opts.tol_position, opts.tol_orientation
        return descend_table(table, q, box, iterations, tol_p, tol_r, LAMBDA0)
    lo, hi = box
    aims = tuple([t.shrunk(AIM) for t in tasks])
    eye = np.eye(len(q))
    placed = _placed(arm, q, ids)
    if all([e.within for e in _measure(arm, tasks, ids, q, opts, placed)]):
        return q, 0
    r, A = _stack(aims, ids, placed)
    cost = float(r @ r)
    lam = None
    for k in range(iterations):
        H = A.T @ A
        g = A.T @ r
        if lam is None:
            lam = LAMBDA0 * max(float(np.max(np.diag(H))), 1e-12)
        dq = np.linalg.solve(H + lam * eye, -g)
        # joints a step would push through their limits are held for it (an active set):
        # clipping them alone leaves a step that no longer lowers the cost next to a limit
        pushing = ((q <= lo) & (dq < 0.0)) | ((q >= hi) & (dq > 0.0))
        if pushing.any():
            Af = A * ~pushing
            dq = np.linalg.solve(Af.T @ Af + lam * eye, -(Af.T @ r))
        trial = np.clip(q + dq, lo, hi)
        placed2 = _placed(arm, trial, ids)
        r2, A2 = _stack(aims, ids, placed2)
        cost2 = float(r2 @ r2)
        if cost2 < cost:  # measured only where q moved: a rejected step leaves it as it was
            q, placed, r, A, cost = trial, placed2, r2, A2, cost2
            lam = max(lam / 3.0, 1e-12)
            if all([e.within for e in _measure(arm, tasks, ids, q, opts, placed)]):
                return q, k + 1
        else:
            lam *= 4.0
            if lam > 1e12:
                return q, k + 1
    return q, iterations


def _total(errors: list[TaskError]) -> float:
    return sum([(e.position or 0.0) + (e.orientation or 0.0) for e in errors])


def _describe(tasks, errors: list[TaskError]) -> str:
    parts = []
    for t, e in zip(tasks, errors):
        words, free = [], t.free()  # a part wholly free: its 0 not said
        if e.position is not None and not free[0]:
            words.append(f"{e.position:.3g} m")
        if e.orientation is not None and not free[1]:
            words.append(f"{e.orientation:.3g} rad")
        parts.append(
            f"{type(t).__name__} {' and '.join(words)} {'held' if e.within else 'outside'}"
        )
    return ", ".join(parts)


def _unmoved(arm: ArmModel, tasks, ids, q: np.ndarray, opts, t0: float) -> IKResult | None:
    """Where a task is on frames no joint moves (the base's, a link fixed to it) and does not
    hold: no configuration meets it, and the result says so at once (``unreachable``, the
    frame named) rather than spend the budget; None otherwise."""
    frames = arm.model.frames
    still = [k for k, fs in enumerate(ids) if all(frames[f].parentJoint == 0 for f in fs)]
    if not still:
        return None
    errors = _measure(arm, tasks, ids, q, opts)
    missed = [k for k in still if not errors[k].within]
    if not missed:
        return None
    k = missed[0]
    r = _result(arm, tasks, q, errors, opts, 0, 0, t0, ())
    why = reasons.unmoved(
        type(tasks[k]).__name__,
        frames[ids[k][0]].name,
        _describe(tasks[k : k + 1], errors[k : k + 1]),
    )
    return dataclasses.replace(r, success=False, status=Status.UNREACHABLE, reason=why)


def solve_tasks(
    arm: ArmModel,
    problem: Problem,
    q0: object,
    opts: SolverSettings,
    t0: float,
    centre: IKResult | None = None,
    reseed: Callable[[np.random.Generator], np.ndarray] | None = None,
    score: Score | None = None,
    reference: np.ndarray | None = None,
) -> IKResult:
    """The verified answer to ``problem`` from ``q0`` (see the module docstring). ``centre``:
    the compiled answer to the problem with its regions shrunk to their centres: taken as
    it is when every task holds on it, else the descent starts from it. ``reseed``: where
    a restart starts (default: a random configuration within the limits). ``score``: the
    answer moved along the tasks' null space while it falls, ``reference`` its q0
    (default: q0); without one, a secondary posture (``SolverSettings.posture``) is that score."""
    tasks = problem.tasks
    ids = frame_ids(arm, tasks)
    q = arm.seed(q0)
    frames = arm.model.frames
    if 0 in [frames[fs[0]].parentJoint for fs in ids]:  # a task on a frame no joint moves
        unmoved = _unmoved(arm, tasks, ids, q, opts, t0)
        if unmoved is not None:
            return unmoved
    reference = q.copy() if reference is None else reference
    # at the call's start (a user's own ``at`` where the call was read: ``base.own``, inline)
    given, read = problem.constraints, "_armik_checked"
    constraints = tuple([c if hasattr(type(c).at, read) else c.at(arm, reference) for c in given])
    box = box_of(arm, constraints)
    checked = tuple([c for c in constraints if type(c) is not JointLimits])
    if centre is not None:
        errors = _measure(arm, tasks, ids, centre.q, opts)
        if (
            centre.success
            and all([e.within for e in errors])
            and satisfied(arm, _unsaid(checked, centre), centre.q)
        ):
            return dataclasses.replace(
                centre,
                reason=reasons.on_centre(centre.reason),
                time=time.perf_counter() - t0,
                extra={**centre.extra, "task_errors": errors},
            )
        q = np.array(centre.q)
    q = np.clip(q, *box)
    rng = np.random.default_rng(opts.seed)
    budget = problem.budget
    aims = tuple([t.shrunk(AIM) for t in tasks])
    followed = arm._derived.get(_FOLLOWED)  # the compiled table places the chain's frames
    on_chain = not followed or not any([i in followed for fs in ids for i in fs])
    table = task_table(arm, aims, ids) if on_chain else None
    started = cpu_time.thread_time()
    used = restarts = 0
    # the start is measured only where the first descent ends short of every task: a
    # descent that closes in leaves nothing to compare it with
    best, best_done = q, False
    best_errors: list[TaskError] | None = None
    before = math.inf  # the last descent's end error: one still closing in goes on
    while True:
        left = budget.attempt(used)
        q, k = _descend(arm, tasks, ids, q, opts, left, box, table)
        used += k
        errors = _measure(arm, tasks, ids, q, opts)
        # done: every task holds and every constraint (a collision check only then)
        done = all([e.within for e in errors]) and satisfied(arm, checked, q)
        if not done and best_errors is None:
            best_errors = _measure(arm, tasks, ids, best, opts)  # the start's
        if done or (
            not best_done and best_errors is not None and _total(errors) < _total(best_errors)
        ):
            best, best_errors, best_done = q, errors, done
        if done or budget.spent(started, used) or not budget.may_restart(restarts):
            break
        # a descent that ran its iterations out near an answer and still closing in (its
        # error down by a good part since the last) goes on from where it is: a restart
        # would throw away what many joints and an active limit make slow to reach
        end = _total(errors)
        if k == left and end < NEAR and end < CLOSING * before:
            before = end
            continue
        before = math.inf
        q = np.clip(arm.random_q(rng) if reseed is None else reseed(rng), *box)
        restarts += 1
    assert best_errors is not None  # the first pass measured the start or took its end
    moved, secondary = False, score is None and opts.posture is not None
    if secondary:  # the posture followed in the tasks' null space once they hold
        score = Posture(*opts.posture)  # type: ignore[misc]
    if score is not None and best_done:
        q, best_errors = _scored(
            arm, tasks, ids, best, best_errors, score, reference, opts, started, checked
        )
        moved, best = q is not best, q
    r = _result(arm, tasks, best, best_errors, opts, used, restarts, t0, checked)
    if score is None or not r.success:
        return r
    value = score(arm, r.q, reference)
    return dataclasses.replace(
        r,
        reason=reasons.preferred(r.reason, score.name, score.words(value), moved, secondary),
        extra={**r.extra, "score": value},
    )


def _unsaid(checked: tuple[Constraint, ...], centre: IKResult) -> tuple[Constraint, ...]:
    """The constraints a centre's success has not checked: a held joint the compiled path
    did not hold (``armik.solve.task_solve.centre``); collisions it checked (``min_distance``
    in its ``extra``)."""
    return tuple(c for c in checked if type(c) is Hold or "min_distance" not in centre.extra)


def _scored(
    arm: ArmModel,
    tasks,
    ids,
    q,
    errors,
    score: Score,
    reference,
    opts: SolverSettings,
    started,
    checked,
):
    """(q, errors) moved along the tasks' null space while ``score`` falls, within what is
    left of the budget; as they were where a moved answer does not hold every task on
    Pinocchio's FK, leaves the limits or breaks a constraint of ``checked``."""
    left = opts.budget.time_left(started)  # inf with an iteration budget: the step cap alone
    if left <= 0.0:
        return q, errors
    aims = tuple([t.shrunk(AIM) for t in tasks])
    moved = descend(arm, q, HeldTasks(arm, aims, ids), score, reference, left, SCORE_STEPS)
    if moved is q:
        return q, errors
    moved_errors = _measure(arm, tasks, ids, moved, opts)
    if (
        all([e.within for e in moved_errors])
        and arm.within_limits(moved)
        and satisfied(arm, checked, moved)
    ):
        return moved, moved_errors
    return q, errors


def _result(
    arm, tasks, q, errors, opts: SolverSettings, iterations, restarts, t0, checked
) -> IKResult:
    # the descent claims nothing: the verdict's rule on its measure alone, then the constraints'
    # checks; the errors are the frames' distances to their targets (``Task.centre``)
    within = arm.within_limits(q)
    status = status_of(Status.NOT_CONVERGED, all([e.within for e in errors]) and within, within)
    positions = [e.position for e in errors if e.position is not None]
    orientations = [e.orientation for e in errors if e.orientation is not None]
    if status is Status.CONVERGED:
        reason = reasons.tasks_hold(opts.tol_position, opts.tol_orientation, restarts)
    else:
        reason = reasons.tasks_missed(restarts, iterations, _describe(tasks, errors))
    extra: dict = {"task_errors": errors}
    centres = tuple([t.centre() for t in tasks])
    if any([c is not t for c, t in zip(centres, tasks)]):  # their centres' distances
        apart = _measure(arm, centres, frame_ids(arm, centres), q, opts)
        extra["measured"] = (max(positions, default=0.0), max(orientations, default=None))
        positions = [e.position for e in apart if e.position is not None]
        orientations = [e.orientation for e in apart if e.orientation is not None]
        if status is Status.CONVERGED:  # several tasks: the largest of their frames'
            ori, pos = max(orientations) if orientations else None, max(positions, default=None)
            weighted = type(tasks[0]) is Pose and not tasks[0].weights.all()  # said alone
            frames = tasks[0].frames if len(tasks) == 1 else ()
            if frames in ((None,), (arm.tip,)):  # the tip's
                reason = reasons.tip_apart(reason, tasks[0], pos, ori, weighted)
            elif len(frames) == 1:  # one task on another frame: that frame's
                reason = reasons.frame_apart(reason, tasks[0], pos, ori, weighted)
            else:
                reason = reasons.tasks_apart(reason, pos, ori)
    found = Verdicts(
        answers=one(q, Status.NOT_CONVERGED, reason, iterations=iterations, restarts=restarts),
        status=np.array([status.code], dtype=np.int8),
        position_error=np.array([max(positions, default=math.nan)]),
        orientation_error=np.array([max(orientations) if orientations else math.nan]),
        rotation=bool(orientations),
        words=[reason],
        tol_position=opts.tol_position,
        tol_orientation=opts.tol_orientation,
        extra=[extra],
    )
    r = found.checked(arm, checked).result(0, SOLVER, time.perf_counter() - t0)
    if not positions:  # no task holds a position (an axis, a look-at): no distance to one
        r.__dict__["position_error"] = None
    return r


def box_of(arm: ArmModel, constraints: tuple[Constraint, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The box of every step: the intersection of the constraints' boxes and the limits."""
    lo, hi = arm.lower.copy(), arm.upper.copy()
    for c in constraints:
        b = c.box(arm)
        if b is not None:
            np.maximum(lo, b[0], out=lo)
            np.minimum(hi, b[1], out=hi)
    return lo, hi
