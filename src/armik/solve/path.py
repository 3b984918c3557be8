"""Paths: waypoints solved in order, without silent jumps between branches.

``solve_path`` solves each waypoint from the previous answer (the first from ``q0``, the
configuration the arm is in, and held to ``max_joint_step`` from it; without ``q0`` the
first is solved from mid-limits as a seed and free: no start to jump from). Angles are
unwrapped onto the previous answer: a continuous joint, or a joint with limits wider than
2 pi, takes the equivalent value modulo 2 pi nearest the previous one that lies within its
limits, so a tool spun through 360 degrees turns on rather than snapping back.

An answer that would move any joint by more than ``max_joint_step`` from the previous
answer is not accepted as it is. The waypoint is re-solved near the previous configuration:

1. a local solve from the previous answer, without random restarts: the path's solver,
   and for a closed form a numeric descent (``dls``) from that answer too;
2. a continuation: the pose is moved from the previous one to the waypoint through 2, 4,
   ... up to ``MAX_SUBSTEPS`` intermediate poses, each solved locally from the last.

If neither reaches the waypoint within ``max_joint_step``, the waypoint is reported with
status ``discontinuous`` (``success=False``) and the reason names the joint and the size of
the jump, and whether the pose is reachable without it at all; ``q`` then holds the
answer with the smallest jump found, and the path goes on from it. A waypoint that cannot
be reached keeps its own status (``unreachable``, ...), and the next waypoint starts from
the last answer that was reached. Last, each step is judged as the global plan judges the
steps it takes (``ladder.hidden_steps``): a success whose step hides a jump between the
waypoints is ``discontinuous`` too.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from armik import path_reasons, reasons
from armik.batch_result import BatchResult
from armik.errors import OptionError
from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.problem.problem import lower
from armik.problem.tasks.pose import Pose
from armik.problem.tasks.position import Position
from armik.request import Request
from armik.result import IKResult
from armik.solve import ladder, rungs
from armik.solve.path_score import preferred
from armik.solve.rungs import NUMERIC, free_spin, spun, spun_batch, unwrapped
from armik.solve.single import routed
from armik.solve.stages import chosen, run
from armik.solve.turning import ANY, Turning, refuse_broken, turning
from armik.solvers import registry
from armik.status import Status
from armik.targets.batch import TargetBatch, parse_targets
from armik.targets.pose import Target
from armik.verify.distances import batch_distances

DEFAULT_MAX_JOINT_STEP = 0.5  # rad (or m for a prismatic joint) between two waypoints
MAX_SUBSTEPS = 64  # finest continuation between two waypoints (intermediate poses)


def solve_path(
    arm: ArmModel,
    request: Request,
    local: Request,
    max_joint_step: float | np.ndarray | None = None,
    plan: str = "follow",
) -> BatchResult:
    """Solve a path's poses in order from its start; returns a ``BatchResult`` (one row per
    pose). ``request``, ``local``: the path's, as ``armik.solve.read.read_path`` reads
    ``Arm.solve_path``'s arguments (``local``: a waypoint re-solved near the previous answer).

    ``request.target``: anything ``solve_batch`` accepts ((N, 4, 4), (N, 7), (N, 3), a list).
    ``request.q0``: the configuration the arm starts from (rad, m); the first pose is held to
    ``max_joint_step`` from it too. None: no start given, the first pose is free (solved
    from mid-limits as a seed, on any branch; the later ones follow it). ``max_joint_step``:
    the largest move of any joint between consecutive answers (rad for revolute joints, m
    for prismatic ones; one number or one per joint; default 0.5). ``plan``: ``"follow"``
    (each waypoint from the previous answer, below) or ``"global"`` (every branch at every
    waypoint, or a numeric arm's tracked answers, ``armik.solve.rungs``: the continuous
    path of least joint motion, or with a score (``prefer=``) of the best summed score,
    ``armik.solve.ladder``; with ``q0=None`` the path may start on any branch and turn).

    Every answer is verified by Pinocchio FK (``Arm.solve``). A waypoint reachable only by
    a larger move gets status ``discontinuous`` and a reason; never a silent jump: either
    plan's answers are checked against ``max_joint_step`` last (``ladder.held_to_step``).
    """
    t0 = request.t0
    if request.rows is not None:  # task lists without a compiled form: the task solver's
        return _followed_rows(arm, request, max_step(max_joint_step, arm.joint_names))
    poses, q0, solver, score = request.target, request.q0, request.solver, request.score
    opts = request.settings
    step = max_step(max_joint_step, arm.joint_names)
    q_prev = arm.seed(q0)
    # a spin the bounds free over a whole turn: each pose at the spin nearest the one before
    batch = given = parse_targets(poses, arm)
    if opts.bounds is not None:  # no call for a plain path
        batch = spun_batch(arm, batch, q_prev, free_spin(opts.bounds))
    n = len(batch)
    turn = turning(arm, request.opts, q_prev)  # the turns of an answer its constraints allow
    if solver == "auto":  # kept per arm: the choice reads the first target's kind only
        position = batch.rotations is None if n else None
        spec = chosen(arm, solver, request.key, opts, position, batch.aim)
    else:  # the solver named, which may read the target itself
        spec = registry.choose(solver, arm, batch.target(0) if n else None, opts)
    # a held joint with "auto": each waypoint's solver chosen as solve chooses it (the sweep
    # at the held value where one applies), else the path's choice for every waypoint
    held_auto = solver == "auto" and opts.hold is not None
    if not held_auto:
        request, local = request.but(solver=spec.name), local.but(solver=spec.name)
    out = BatchResult.for_arm(
        arm, n, spec.name, opts, margin=opts.margin, aim=batch.aim, along=batch.along
    )
    if plan == "global":
        # every solution: what solve_all would run (a search where one is not complete)
        every = ladder.every(arm, solver, batch, opts)
        # not every solution: a sweep's, a numeric solver's, a swivel's, a search's
        if every.kind == "numeric" or not every.complete or every.parameter is not None:
            followed = BatchResult.for_arm(
                arm, n, spec.name, opts, margin=opts.margin, aim=batch.aim, along=batch.along
            )
            # as plan="follow" solves it: a colliding answer slid clear near the previous one
            walked = request if opts.slide or not opts.collisions else request.narrowed(slide=True)
            used = _walk(arm, batch, q_prev, step, walked, local, followed, None, q0 is None, turn)
            if held_auto and used is not None:  # its rows by the solver each waypoint chose
                object.__setattr__(followed, "solver", used)
            # a 7R arm: joint 7 sampled, or the swivel at the start's and the followed
            # answers'; a search's answers and the followed ones; else answers tracked
            # from the start and the breaks
            if every.sweep is not None:
                found = rungs.held(arm, batch, q_prev, followed, request, every)
            elif every.kind != "numeric":
                found = rungs.beside(arm, batch, q_prev, followed, request, every)
            else:
                found = rungs.tracked(arm, batch, q_prev, every.name, followed, request)
        else:
            found = rungs.every_branch(arm, batch, q_prev, every.name, request, step)
        out = BatchResult.for_arm(
            arm, n, every.name, opts, margin=opts.margin, aim=batch.aim, along=batch.along
        )
        start = None if q0 is None else q_prev
        # with a preference, the continuous path of the best summed score (ladder.TIE)
        held = request if opts.hold is not None else None  # halfway poses solved held too
        made = ladder.plan(
            arm, every, batch, found, start, step, opts, out, score, q_prev, turn, held
        )
        refuse_broken(arm, out, turn)
        if batch is not given:
            _to_given(arm, out, given, opts)
        label = every.name
        if every.sweep is not None and _holds_other(arm, opts, every.sweep.joint):
            # no sweep ran: each rung was solved on the arm with the held joint locked
            # (``armik.solve.held``), the followed answers by the solver each waypoint chose
            label = "+".join(sorted(made)) or label
        return frozen(
            BatchResult, **{**vars(out), "solver": label, "time": time.perf_counter() - t0}
        )
    chooser = None if score is None else _chooser(arm, score, q_prev, request, turn)
    used = _walk(arm, batch, q_prev, step, request, local, out, chooser, q0 is None, turn)
    if batch is not given:  # before the words of a jump quote them
        _to_given(arm, out, given, opts)
    ladder.held_to_step(arm, out, None if q0 is None else q_prev, step)
    half = (solver, opts, request if opts.hold is not None else None, turn)
    ladder.hidden_steps(arm, out, batch, step, half)
    refuse_broken(arm, out, turn)
    label = used if held_auto and used is not None else out.solver
    out = frozen(BatchResult, **{**vars(out), "solver": label, "time": time.perf_counter() - t0})
    return out


def _to_given(arm: ArmModel, out: BatchResult, given: TargetBatch, opts) -> None:
    """The true distances of a path's answers to its poses as given (in ``out``), where
    it solved them turned about the spin its bounds free (``spun_batch``): a pose's
    rotation is its own, the turned one the path's choice."""
    rows = np.flatnonzero(np.isfinite(out.position_error))
    if len(rows):
        pos, ori = batch_distances(arm, out.q[rows], given[rows], opts)
        out.position_error[rows], out.orientation_error[rows] = pos, ori


def _holds_other(arm: ArmModel, opts, joint: int) -> bool:
    """Whether ``opts`` hold a joint other than ``joint`` (a sweep's)."""
    return opts.hold is not None and any(n != arm.joint_names[joint] for n, _ in opts.hold)


def _followed_rows(arm: ArmModel, request: Request, step: np.ndarray) -> BatchResult:
    """A followed path of task lists without a compiled form (``request.rows``, each read
    as ``solve`` reads it): each waypoint's answer from the previous one, then held to
    ``step`` (``ladder.held_to_step``: a larger move is ``discontinuous``, never silent);
    a score ranks each waypoint's answers as ``solve``'s does."""
    rows = request.rows or ()
    seed = arm.seed(request.q0)  # read once: a q0 outside the limits is said once
    q_prev = seed.copy()
    opts = request.settings
    out = BatchResult.for_arm(arm, len(rows), "tasks", opts, margin=opts.margin)
    names = set()
    for i, row in enumerate(rows):
        r = routed(arm, row.but(q0=q_prev, t0=time.perf_counter(), score=request.score))
        out.put_result(i, r)
        out.reasons[i] = r.reason  # its own words, a success's too (a task list's)
        names.add(r.solver)
        if r.success:
            q_prev = np.array(r.q)
    ladder.held_to_step(arm, out, None if request.q0 is None else seed, step)
    targets = _row_poses(arm, rows)
    if targets is not None:  # each step judged as the other paths' (halfway._row_at)
        turn = turning(arm, request.opts, seed)
        held: Request | None = request  # the held rows' halfway solved held
        judged, solver = opts, request.solver
        if not _reached_held(arm, rows):  # halfway off the poses it reaches: the arm free
            judged = dataclasses.replace(opts, hold=None, **_said(arm, rows[0]))
            targets = spun_batch(arm, targets, seed, free_spin(judged.bounds))
            held, solver = None, "auto"
        half = (solver, judged, held, turn)
        ladder.hidden_steps(arm, out, targets, step, half)
    label = names.pop() if len(names) == 1 else out.solver
    return frozen(
        BatchResult, **{**vars(out), "solver": label, "time": time.perf_counter() - request.t0}
    )


def _row_poses(arm: ArmModel, rows: Sequence[Request]) -> TargetBatch | None:
    """The tip's poses (or positions) of a path by rows where each row asks for one, alike
    but for where (the same task, bounds and weights): the poses its steps are judged
    halfway along; None for other task lists."""
    tasks = [row.problem.tasks[0] for row in rows if row.problem and len(row.problem.tasks) == 1]
    if not tasks or len(tasks) != len(rows):
        return None
    first = tasks[0]
    alike = (
        type(t) is type(first)
        and isinstance(t, (Pose, Position))
        and t.frame in (None, arm.tip)
        and np.array_equal(t.bounds, first.bounds)
        and np.array_equal(getattr(t, "weights", ()), getattr(first, "weights", ()))
        for t in tasks
    )
    if not all(alike):
        return None
    if not _reached_held(arm, rows) and lower(rows[0].problem, arm.tip) is None:
        return None  # judged on the arm free as its compiled form: none for this task
    if isinstance(first, Position):
        return TargetBatch(np.array([t.p for t in tasks]), None)
    P = np.array([t.T.translation for t in tasks])
    return TargetBatch(P, np.array([t.T.rotation for t in tasks]))


def _reached_held(arm: ArmModel, rows: Sequence[Request]) -> bool:
    """Whether the held arm of a path by rows (``hold=``) reaches the poses near its rows':
    its free joints as many as the components each row's task pins. Else (a UR5 held at a
    joint, full poses) the pose halfway along a step is off the poses it reaches, and the
    step is judged on the arm free: any configuration of the held arm is one of the free
    arm's, so where none of these lies within the step of both ends, no held one does."""
    held = len(rows[0].settings.hold or ())
    return _pinned(rows[0].problem.tasks[0]) <= arm.dof - held


def _said(arm: ArmModel, row: Request) -> dict:
    """The options a row's task says beside its pose (``lower``: a ``Pose``'s bounds and
    weights), which the arm free is judged under halfway."""
    lowered = lower(row.problem, arm.tip) if row.problem is not None else None
    return {} if lowered is None else lowered[1]


def _pinned(task: Pose | Position) -> int:
    """How many components of its pose (or position) ``task`` pins (neither free by an
    infinite bound nor weighted 0)."""
    free = task._free if isinstance(task, Pose) else task.bounds
    return int(np.isfinite(free).sum())


def _walk(
    arm, batch, q_prev, step, request, local, out, chooser=None, free=False, turn=ANY
) -> str | None:
    """Solve the waypoints in order, each from the previous answer, into ``out``
    (``request``: the path's; ``local``: the same without restarts);
    ``chooser(target, r, q_prev, within)``: the answer kept among those within ``within`` (a
    preference), else ``r``; ``free``: no start given, the first answer (from ``q_prev``,
    a seed) is held to no step, a preference choosing among every answer there; ``turn``:
    the turns the request allows an answer (``armik.solve.turning``). Returns the solver
    of the first verified answer, else of the first answer (None: no waypoint)."""
    used = None
    bounds = request.settings.bounds
    spin = None if bounds is None else free_spin(bounds)  # no call for a plain path
    for i in range(len(batch)):
        target = batch.target(i) if spin is None else spun(arm, batch.target(i), q_prev, spin)
        r = _at(arm, request, target, q_prev)
        if not (free and i == 0 and chooser is not None):  # a free first answer: as preferred
            r = unwrapped(arm, r, q_prev, turn)
        within = np.full(arm.dof, np.inf) if free and i == 0 else step
        if r.success and _jump(r.q, q_prev, within) > 1.0:
            r = _near(arm, target, q_prev, step, local, r, i == 0, turn)
        elif chooser is not None:
            r = chooser(target, r, q_prev, within)
        out.put_result(i, r)
        if r.success or r.status is Status.DISCONTINUOUS:
            q_prev = np.array(r.q)
        if used is None or (r.success and not out.success[:i].any()):
            used = r.solver
    return used


def _at(arm: ArmModel, request: Request, target: object, q: np.ndarray) -> IKResult:
    """``target`` solved from ``q`` by the stages, as ``request`` asks."""
    return run(arm, request.but(target=target, q0=q, t0=time.perf_counter()))  # type: ignore[no-any-return]


def _chooser(arm, score, start: np.ndarray, request: Request, turn: Turning):
    """A preference's choice at each waypoint (``path_score.preferred``) among the answers
    within a step of the one before, scored against the path's start, turned only as
    ``turn`` allows."""
    reference = np.array(start, dtype=float)

    def choose(target: Target, r: IKResult, q_prev: np.ndarray, within: np.ndarray) -> IKResult:
        return preferred(arm, target, r, q_prev, within, score, reference, request, turn)

    return choose


def max_step(value: object, joints: Sequence[str]) -> np.ndarray:
    """``max_joint_step`` (None: the default) as one positive, finite float per joint of
    ``joints`` (rad or m): one number for all, or one each; not bools or strings (``Arm``'s
    paths and ``Arms``')."""
    n = len(joints)
    if value is None:
        return np.full(n, DEFAULT_MAX_JOINT_STEP)
    try:
        if isinstance(value, (str, bytes)) or any(
            isinstance(v, (bool, np.bool_)) for v in np.ravel(np.asarray(value, dtype=object))
        ):
            raise TypeError
        step = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()
    except (TypeError, ValueError, OverflowError):
        raise OptionError(
            f"max_joint_step must be one number or {n} numbers (rad or m), one per joint of "
            f"{list(joints)}, got {value!r}",
            option="max_joint_step",
            value=value,
        ) from None
    if not (np.isfinite(step).all() and (step > 0).all()):
        raise OptionError(
            f"max_joint_step must be positive and finite, got {value!r}",
            option="max_joint_step",
            value=value,
        )
    return step


def _jump(q: np.ndarray, q_prev: np.ndarray, step: np.ndarray) -> float:
    """The largest joint move as a multiple of its allowed step (> 1: too large)."""
    return float((np.abs(np.asarray(q) - q_prev) / step).max())


def _near(
    arm: ArmModel,
    target: Target,
    q_prev: np.ndarray,
    step: np.ndarray,
    local: Request,
    jumped: IKResult,
    first: bool,
    turn=ANY,
) -> IKResult:
    """Re-solve ``target`` near ``q_prev``; the answer if within ``step``, else the smallest
    jump found, reported as discontinuous."""
    candidates = [jumped]
    for near in _local(local):
        r = unwrapped(arm, _at(arm, near, target, q_prev), q_prev, turn)
        if r.success:
            if _jump(r.q, q_prev, step) <= 1.0:
                return r
            candidates.append(r)
    continuous = None  # the continuation's answer, reached in small moves
    T_from = arm.fk(q_prev)
    k = 2
    while k <= MAX_SUBSTEPS:
        q, ok = q_prev, True
        for pose in _between(T_from, target, k):
            s = unwrapped(arm, _at(arm, local, pose, q), q, turn)
            if not s.success or _jump(s.q, q, step) > 1.0:
                ok = False
                break
            q = np.array(s.q)
        if ok:
            if _jump(s.q, q_prev, step) <= 1.0:
                return dataclasses.replace(s, reason=path_reasons.through(s.reason, k - 1))
            continuous = s
            break
        k *= 2
    best = continuous or min(candidates, key=lambda c: _jump(c.q, q_prev, step))
    moved = np.abs(np.asarray(best.q) - q_prev)
    j = int(np.argmax(moved / step))
    unit = "m" if arm.prismatic[j] else "rad"
    start = "q0 (the start)" if first else "the previous waypoint's answer"
    move = path_reasons.moved(arm.joint_names[j], moved[j], unit, start, step[j])
    if continuous is not None:
        why = path_reasons.continuous_but(move)
    else:
        why = path_reasons.not_continuous(move, MAX_SUBSTEPS - 1)
    measured = path_reasons.verified(
        best.reason, reasons.best_errors(best.position_error, best.orientation_error)
    )
    return dataclasses.replace(
        best,
        success=False,
        status=Status.DISCONTINUOUS,
        reason=path_reasons.jump(why, "that answer", measured),
    )


def _local(local: Request) -> tuple[Request, ...]:
    """The re-solves near the previous answer: ``local`` itself, and for a closed form a
    numeric descent from that answer too. A closed form's answer nearest it can lie on
    another branch where the waypoints pass a singularity (an SRS arm's stretched elbow
    leaves its swivel angle undefined); the descent moves continuously off it. Not where
    the request fixes the closed form's parameter (``swivel=``): no descent keeps it."""
    if local.solver == "auto" or registry.get(local.solver).kind != "analytic":
        return (local,)
    if local.opts.swivel is not None:
        return (local,)
    return local, local.but(solver=NUMERIC)


def _between(T_from: pin.SE3, target: Target, k: int) -> list[Target]:
    """k poses from ``T_from`` (excluded) to ``target`` (included), evenly spaced along the
    screw motion between them (positions only for a position target)."""
    if target.rotation is None:
        return [
            Target(
                T_from.translation + (target.position - T_from.translation) * (j / k),
                aim=target.aim,
            )
            for j in range(1, k + 1)
        ]
    twist = pin.log6(T_from.actInv(target.se3()))
    poses = [T_from * pin.exp6(twist * (j / k)) for j in range(1, k)]
    between = [Target(T.translation.copy(), T.rotation.copy(), aim=target.aim) for T in poses]
    return between + [target]
