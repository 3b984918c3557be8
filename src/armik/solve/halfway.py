"""The solutions halfway along a planned or followed step (``armik.solve.ladder``'s check
of the steps a path takes): each halfway pose solved by the path's solver, the solution
nearest the step's middle kept (``_nearest``); a sweep's or a search's, which may pass by
the nearest, helped by numeric descents from the middle and the ends (``_descended``);
with a joint held, each pose solved as the path's rungs are (``_nearest_held``), a path
followed row by row as its rows are (``_row_at``)."""

from __future__ import annotations

import dataclasses
from typing import NamedTuple, cast

import numpy as np
import pinocchio as pin

from armik.errors import ArmikError
from armik.frozen import frozen
from armik.problem.settings import SolverSettings
from armik.problem.tasks.base import replaced
from armik.problem.tasks.pose import Pose
from armik.request import Request
from armik.solve.rungs import NUMERIC, every_answer, unwrapped
from armik.solve.single import routed
from armik.solve.turning import Turning
from armik.solvers import registry
from armik.solvers.registry import SolverSpec
from armik.status import Status
from armik.targets.aim import Aim
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target
from armik.verify.measure import measure_batch


class _Halfway(NamedTuple):
    """How a step's halfway poses are solved (``_nearest``): by ``spec`` with ``opts`` on
    ``targets``' aim, or where ``held`` (the path's request) holds a joint, as its rungs
    were, each answer turned as ``turn`` allows."""

    spec: SolverSpec
    opts: SolverSettings
    targets: TargetBatch
    held: Request | None
    turn: Turning


def within(Q: np.ndarray, Qa: np.ndarray, Qb: np.ndarray, step: np.ndarray) -> np.ndarray:
    """Whether each configuration of ``Q`` (a row, or rows) lies within ``step`` of both
    ends of its step, ``Qa`` and ``Qb``, on every joint (NaN: no solution, not within):
    the rule a step's solution halfway is held to."""
    return (np.abs(Q - Qa) <= step).all(axis=-1) & (np.abs(Q - Qb) <= step).all(axis=-1)


def searched(arm, half: _Halfway, P, R, q, near, middle, ends: tuple) -> None:
    """The solutions halfway not yet ``near`` both ends (``ends``: Qa, Qb, the bound)
    looked for again where the solver's nearest the middle may miss one: numeric descents
    from the middle, each end and about the middle (``_starts``, ``_descended``), and with
    a held joint the held problem solved from each end (``_from_ends``). ``q`` and
    ``near`` updated in place."""
    Qa, Qb, step = ends
    for seeds in _starts(arm, middle, Qa, Qb, step) if _may_miss(half) else ():
        if not near.all():  # descend too: the solution nearest the middle may be far
            near |= _descended(arm, half, P, R, seeds, q, ~near, ends)
    _from_ends(arm, half, P, R, q, near, ends)  # a held joint's: from each end


def _loose(arm, step: np.ndarray) -> bool:
    """Whether ``step`` lets every joint flip within one step (half a turn, a prismatic
    joint its whole travel): no jump can hide between two waypoints, and none is looked
    for (a sequence of point-to-point moves, ``max_joint_step=10``)."""
    flip = np.where(arm.prismatic, arm.upper - arm.lower, np.pi)
    return bool((np.asarray(step) >= flip).all())


def _may_miss(half: _Halfway) -> bool:
    """Whether the solution nearest a seed ``_nearest`` finds may miss one nearer: a sweep
    over a joint (the 7R arm's), a search, a numeric solver, a closed form at one value of
    a parameter read from the seed (an SRS arm's swivel); not a complete closed form, whose
    every branch is at hand, nor a held joint's rungs (solved as they were)."""
    spec = half.spec
    incomplete = spec.kind == "numeric" or not spec.complete or spec.sweep is not None
    incomplete = incomplete or spec.parameter is not None
    return half.held is None and incomplete


def _descended(arm, half: _Halfway, P, R, seeds, q, rows, ends) -> np.ndarray:
    """For ``rows`` of the halfway poses, one local descent of the numeric solver from
    ``seeds`` (the step's middle, or one of its ends), no restarts: where its answer is on
    the pose (Pinocchio's FK, ``_reached``), within the limits and within the step of both
    ends (``ends``: the ends and the step), it is the halfway solution (written into ``q``)
    and no jump hides there.
    Returns the rows so found. The sweep's branches at a few values of its joint may pass
    by a solution the self-motion holds next to the step (an arm along a joint limit)."""
    Qa, Qb, step = ends
    found = np.zeros(len(seeds), dtype=bool)
    opts = frozen(type(half.opts), **{**half.opts.__dict__, "max_restarts": 0})
    aim = half.targets.aim
    for k in np.flatnonzero(rows).tolist():
        target = Target(P[k].copy(), None if R is None else R[k].copy(), aim=aim)
        try:
            spec = registry.choose("auto", arm, target, opts)
            if spec.kind != "numeric":  # a closed form's arm (an SRS arm's): descend all the same
                spec = registry.choose(NUMERIC, arm, target, opts)
        except ArmikError:
            return found
        got = spec.run(arm, target, seeds[k].copy(), opts, False)
        for i in range(len(got)):
            c = arm.nearest_equivalent(got.q[i], seeds[k])
            inside = bool(((c >= arm.lower - 1e-9) & (c <= arm.upper + 1e-9)).all())
            close = bool(within(c, Qa[k], Qb[k], step))
            Pk, Rk = P[k : k + 1], None if R is None else R[k : k + 1]
            if inside and close and _reached(arm, c[None], Pk, Rk, half.opts, aim)[0]:
                q[k], found[k] = c, True
                break
    return found


SPREAD = 6  # descents from about the middle beside those from it and from both ends


def _starts(arm, middle: np.ndarray, Qa: np.ndarray, Qb: np.ndarray, step: np.ndarray):
    """Where ``_descended`` starts, in turn: the step's middle, each end, then ``SPREAD``
    points about the middle (within half the step, fixed: the same every call) inside
    the limits: a descent from the middle may stall on a joint limit, where the
    self-motion holds a solution near both ends further along."""
    yield from (middle, Qa, Qb)
    offsets = np.random.default_rng(0).uniform(-0.5, 0.5, (SPREAD, arm.dof))
    for d in offsets:
        yield np.clip(middle + d * step, arm.lower, arm.upper)


def _nearest(arm, half: _Halfway, P, R, seeds) -> np.ndarray:
    """Per pose (with the path's aim), the solution nearest its seed, each angle turned
    nearest it within the limits; a row of NaN where there is none. An answer not claimed
    exact counts where its FK is within the tolerances (a least-squares answer on the edge
    of the workspace). With a held joint, the verified answers of the held problem."""
    spec, opts, aim = half.spec, half.opts, half.targets.aim
    if half.held is not None:
        return _nearest_held(arm, half, P, R, seeds)
    if spec.run_batch is not None and R is not None:  # the compiled batch: one call
        got = spec.run_batch(arm, TargetBatch(P, R, aim), seeds, opts)
        q = np.array(got.q, dtype=float)
        ok = got.claim == Status.CONVERGED.code
        ok[~ok] = _reached(arm, q[~ok], P[~ok], R[~ok], opts, aim)
    else:
        q = np.full_like(seeds, np.nan)
        for k, seed in enumerate(seeds):
            Pk, Rk = P[k : k + 1], None if R is None else R[k : k + 1]
            target = Target(Pk[0].copy(), None if Rk is None else Rk[0].copy(), aim=aim)
            got = spec.run(arm, target, seed.copy(), opts, True)
            for i in range(len(got)):
                c = arm.nearest_equivalent(got.q[i], seed)
                nearer = not np.abs(q[k] - seed).max() <= np.abs(c - seed).max()  # NaN: none yet
                if nearer and (got.claimed(i) or _reached(arm, c[None], Pk, Rk, opts, aim)[0]):
                    q[k] = c
        ok = ~np.isnan(q).any(axis=1)
    ok &= ((q >= arm.lower - 1e-9) & (q <= arm.upper + 1e-9)).all(axis=1)
    q[~ok] = np.nan
    return q


def _from_ends(arm, half: _Halfway, P, R, q, near, ends: tuple) -> None:
    """With a held joint, each pose not yet ``near`` solved again from each end of its step
    (``ends``: Qa, Qb, the bound), as the held problem is solved: the answer nearest the
    middle can be off the step's route where one nearest an end is on it (a Panda held at
    joints 1 and 7, positions). ``q`` and ``near`` updated in place."""
    Qa, Qb, step = ends
    for seeds in (Qa, Qb) if half.held is not None else ():
        redo = np.flatnonzero(~near)
        if not len(redo):
            return
        got = _nearest(arm, half, P[redo], None if R is None else R[redo], seeds[redo])
        ok = within(got, Qa[redo], Qb[redo], step)
        q[redo[ok]] = got[ok]
        near[redo[ok]] = True


def _nearest_held(arm, half: _Halfway, P, R, seeds) -> np.ndarray:
    """``_nearest`` where the path holds a joint: each pose's verified answers as the
    rungs are found (``rungs.every_answer``: the held joint at its value, a 6R chain), the
    nearest its seed among them turned as the path turns its rungs."""
    held = cast(Request, half.held)
    q = np.full_like(seeds, np.nan)
    for k, seed in enumerate(seeds):
        target = Target(P[k].copy(), None if R is None else R[k].copy(), aim=half.targets.aim)
        if held.rows is not None:  # a path by rows: as its rows are solved
            answers = [routed(arm, _row_at(held.rows[0], target, seed))]
        else:
            answers = every_answer(arm, held, target, seed, half.spec.name)
        for r in answers:
            if not r.success:
                continue
            c = np.asarray(unwrapped(arm, r, seed, half.turn).q)
            if not np.abs(q[k] - seed).max() <= np.abs(c - seed).max():  # NaN: none yet
                q[k] = c
    return q


def _row_at(row: Request, target: Target, seed: np.ndarray) -> Request:
    """A path by rows' request (``row``: one whose task is the tip's pose or position,
    ``armik.solve.path``) with that task moved onto ``target``, from ``seed``."""
    problem = row.problem
    task = problem.tasks[0]
    if isinstance(task, Pose):
        moved = replaced(task, T=pin.SE3(target.rotation, target.position))
    else:
        moved = replaced(task, p=np.array(target.position, dtype=float))
    return row.but(problem=dataclasses.replace(problem, tasks=(moved,)), q0=seed, score=None)


def _reached(arm, Q, P, R, opts: SolverSettings, aim: Aim | None = None) -> np.ndarray:
    """Whether the FK of each row of ``Q`` is on its pose within the tolerances, as the
    verdict measures it (``verify.measure.measure_batch``): with ``aim``, the position and
    the tip's axis within its cone, not the rotation beside it."""
    if not len(Q):
        return np.zeros(0, dtype=bool)
    return measure_batch(arm, Q, TargetBatch(P, R, aim), opts).pose_ok
