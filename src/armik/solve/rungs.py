"""Where a global plan's rungs come from (``armik.solve.ladder``): the answers at each
waypoint that a path may pass through.

- A closed form: every branch of ``solve_all`` at every waypoint (``every_branch``); at a
  singular waypoint, its singular rows solved again so that their free angle continues
  the waypoints beside it (``armik.solve.singular_rungs``).
- A 7R arm whose joint 7 the swept closed form holds: every branch at joint 7 values about
  the followed path's and on a grid over its range, and the followed answers (``held``);
  with a joint held (``hold=``), every branch at its value.
- An arm whose closed form answers at one value of a parameter read from the seed (an SRS
  arm's swivel, the iiwa): every branch at the start's value and at each followed
  answer's, and the followed answers (``beside``); a closed form that may miss answers (a
  search, a spin's sweep): its answers and the followed ones. Beside both, a numeric
  descent's answers from the start, each waypoint from the one before.
- Any other arm, by its numeric solver: answers tracked along the path (``tracked``): the
  followed path's own, and from distinct answers of ``solve_all`` at the first waypoint and
  where following breaks, each waypoint solved from the track's answer at the one before,
  forward and backward. Not every solution: the plan is the least motion over what was
  tracked, and a break it reports is one no tracked answer passes.

A spin the bounds free over a whole turn (``free_spin``; ``Axis(..., within=0)`` with a
``Position`` lowers to one) makes every rotation of a pose about that axis the same set of
poses, the one a target carries arbitrary; but a closed form solves it at that spin, and at
a singular configuration (a wrist's two parallel axes sharing the spin as they please) the
branches at another spin need not pass near the arm's. A path turns each pose to the spin
nearest the one before, the first to the tip's at the start (``spun_batch``, ``spun``):
no verdict changes, and the start's branch is found as at the tip's own rotation.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.problem.settings import spin_of
from armik.request import Request
from armik.result import IKResult
from armik.solve.singular_rungs import continued
from armik.solve.stages import run
from armik.solve.turning import ANY, Turning, turning
from armik.solvers.closed_form.spin import nearest_spin
from armik.status import Status
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target

HELD_OFFSETS = 0.1 * np.arange(-2, 3)  # rad: joint 7's values about the followed path's
HELD_GRID = 6  # values across joint 7's range beside them: other branches, missed waypoints
TRACKS = 8  # answers of solve_all tracked from a waypoint (the first, each break)
BREAKS = 8  # breaks of the followed path reseeded at most (the first ones)
SAME = 1e-6  # rad or m: a track this near another's answer has merged with it
NUMERIC = "dls"  # a descent where a closed form misses the continuation (paths, rungs, halfway)


def every_branch(
    arm: ArmModel, batch, q_prev: np.ndarray, solver: str, request, step: np.ndarray
) -> list:
    """Each waypoint's ``solve_all`` results by ``solver`` from ``q_prev`` (a pose as a 4x4
    array takes the prepared path); at a singular waypoint, with its singular rows solved
    again so that their free angle continues the waypoints beside it
    (``singular_rungs.continued``; ``step``: the path's ``max_joint_step`` per joint)."""
    targets = [batch.target(i) for i in range(len(batch))]
    found = [every_answer(arm, request, target, q_prev, solver) for target in targets]

    def solve(i: int, seed: np.ndarray) -> list:
        return every_answer(arm, request, targets[i], seed, solver)

    return continued(arm, found, q_prev, step, solve)


def every_answer(arm: ArmModel, request: Request, target, q: np.ndarray, solver: str) -> list:
    """``target``'s ``solve_all`` results by ``solver`` from ``q``, as ``request`` asks (its
    held joints held, its constraints checked): a rung's, and a global plan's halfway pose
    where the request holds a joint (``ladder``)."""
    now = time.perf_counter()
    return run(arm, request.but(target=target, q0=q, solver=solver, every=True, t0=now))  # type: ignore[no-any-return]


def held(arm: ArmModel, batch, q_start: np.ndarray, followed, request, spec) -> list:
    """A 7R arm's rungs: at each waypoint, every branch of ``spec``'s closed form (a
    solver with a ``Sweep``: the swept one) with its joint at values about the followed
    path's (the last value it reached where it missed) and on a grid over its range, and
    the followed path's own answers: so the plan moves no more than it (unless a hidden
    jump rules a step out), and may change branch where it breaks."""
    j = spec.sweep.joint
    lo, hi = float(arm.lower[j]), float(arm.upper[j])
    grid = np.linspace(lo, hi, HELD_GRID + 2)[1:-1]
    theta, seed = float(q_start[j]), np.array(q_start, dtype=float)  # read only
    # a held joint (``hold=``, None: at the start's value) is solved at its value whatever
    # the sweep's start: one value gives every branch there
    held_joint = request.opts.hold is not None
    rungs = []
    for i in range(len(batch)):
        own = reached(followed, i)
        # where nothing reaches the waypoint, its failure is the followed path's (as solve
        # and plan="follow" say it: a collision, not the limits one sweep value breaks)
        found: list = [followed[i] if own is None else own]
        if own is not None:
            theta = float(own.q[j])  # where joint 7 admits no closed form exactly there
        target = batch.target(i)
        values = (
            [theta] if held_joint else np.concatenate((np.clip(theta + HELD_OFFSETS, lo, hi), grid))
        )
        for value in values:
            swept = request.but(sweep_from=float(value))  # where its sweep starts
            found += every_answer(arm, swept, target, seed, spec.name)
        rungs.append(found)
    return rungs


def beside(arm: ArmModel, batch, q_start: np.ndarray, followed, request, spec) -> list:
    """The rungs of a closed form that gives not every solution, beside the followed
    path's: at each waypoint ``spec``'s answers from the start and the followed path's
    answer, so that the plan passes wherever following does (unless a hidden jump rules a
    step out); where ``spec`` answers at one value of a parameter it reads from the seed
    (``Parameter``: an SRS arm's swivel), every branch at the followed answer's value too
    (the last one reached where following missed), not only at the start's."""
    reseed = spec.parameter is not None
    rungs = []
    seed = np.array(q_start, dtype=float)
    for i in range(len(batch)):
        target = batch.target(i)
        found = every_answer(arm, request, target, q_start, spec.name)
        own = reached(followed, i)
        if own is not None:
            found.append(own)
            seed = np.array(own.q, dtype=float)
        if reseed and not np.array_equal(seed, q_start):
            found += every_answer(arm, request, target, seed, spec.name)
        rungs.append(found)
    if request.opts.swivel is None:  # a swivel fixed (``swivel=``): no descent keeps it
        _descended(arm, batch, q_start, request, rungs)
    return rungs


def _descended(arm: ArmModel, batch, q_start: np.ndarray, request, rungs: list) -> None:
    """Add a numeric descent's answers to ``rungs``, each waypoint solved from the one
    before from the start on: where the closed form's parameter changes along the path
    (an SRS arm's swivel near a singular shoulder), the answers at the followed one's may
    drive a joint to its limit where the descent moves on continuously."""
    local = request.narrowed(max_restarts=0).but(solver=NUMERIC)
    turn = turning(arm, request.opts, q_start)
    prev = np.asarray(q_start, dtype=float)
    for i in range(len(batch)):
        r = run(arm, local.but(target=batch.target(i), q0=prev, t0=time.perf_counter()))
        if not r.success:
            continue  # out of its reach here: it goes on from its last answer
        r = unwrapped(arm, r, prev, turn)
        _add(rungs[i], r)
        prev = np.asarray(r.q)


def reached(followed, i: int) -> IKResult | None:
    """The followed path's verified answer at waypoint ``i`` as a rung: its success, or the
    answer of a jump (``discontinuous``: verified, reported for the move to it, which a
    plan may make elsewhere); None where it reached nothing."""
    if followed.success[i]:
        return followed[i]  # type: ignore[no-any-return]
    if followed.status_code[i] != Status.DISCONTINUOUS.code:
        return None
    return dataclasses.replace(followed[i], success=True, status=Status.CONVERGED)


def tracked(arm: ArmModel, batch, q_start: np.ndarray, solver: str, followed, request) -> list:
    """A numeric arm's rungs (see the module): each waypoint's followed result (its own
    failure where nothing reaches it) and every distinct answer a track reached there."""
    n = len(batch)
    targets = [batch.target(i) for i in range(n)]
    local = request.narrowed(max_restarts=0).but(solver=solver)
    turn = turning(arm, request.opts, q_start)
    rungs: list[list[IKResult]] = [[reached(followed, i) or followed[i]] for i in range(n)]
    ok = np.asarray(followed.success, dtype=bool)
    breaks = [i for i in range(1, n) if not ok[i] and ok[i - 1]][:BREAKS]
    for s in [0, *breaks]:
        seed = q_start if s == 0 else np.asarray(followed.q[s - 1])
        found = every_answer(arm, request, targets[s], seed, solver)
        for start in [r for r in found if r.success][:TRACKS]:
            if not _add(rungs[s], unwrapped(arm, start, seed, turn)):
                continue  # an answer already there: its track is run
            for indices in (range(s + 1, n), range(s - 1, -1, -1)):
                _track(arm, targets, np.asarray(rungs[s][-1].q), indices, local, rungs, turn)
    return rungs


def _track(arm, targets, start: np.ndarray, indices, local: Request, rungs, turn) -> None:
    """Solve the waypoints ``indices`` in turn, each from the track's last answer, adding
    each answer to its waypoint's rungs; a track that reaches an answer already there has
    merged with another, and stops."""
    prev = start
    for i in indices:
        r = run(arm, local.but(target=targets[i], q0=prev, t0=time.perf_counter()))
        if not r.success:
            continue  # out of reach here: the track goes on from its last answer
        r = unwrapped(arm, r, prev, turn)
        if not _add(rungs[i], r):
            return
        prev = np.asarray(r.q)


def _add(found: list[IKResult], r: IKResult) -> bool:
    """Add ``r`` to a waypoint's rungs unless an answer within ``SAME`` is there."""
    if any(x.success and np.abs(np.asarray(x.q) - r.q).max() <= SAME for x in found):
        return False
    found.append(r)
    return True


def unwrapped(arm: ArmModel, r: IKResult, q_prev: np.ndarray, turn: Turning = ANY) -> IKResult:
    """``r`` with its angles moved by multiples of 2 pi next to ``q_prev`` (within limits;
    only the turns ``turn`` allows); the pose, hence the verification, is unchanged."""
    q = arm.nearest_equivalent(r.q, q_prev)
    if turn is not ANY and not np.array_equal(q, r.q):
        fixed = list(turn.fixed)
        q[fixed] = np.asarray(r.q)[fixed]
        q = turn.kept(arm, q, np.asarray(r.q))
    return r if np.array_equal(q, r.q) else dataclasses.replace(r, q=q)


def free_spin(bounds: tuple[float, ...] | None) -> int | None:
    """The rotation component of the target frame that ``bounds`` free over a whole turn
    (the position and the other components exact), else None."""
    spin = spin_of(bounds)
    return spin[0] if spin is not None and spin[1] >= math.pi else None


def spun(arm: ArmModel, target: Target, q: np.ndarray, k: int | None) -> Target:
    """``target`` turned about its own axis ``k`` (a spin free over a whole turn: the same
    poses) to the rotation nearest the tip's at ``q``; unchanged where ``k`` is None, for a
    position or an aim."""
    if k is None or target.rotation is None or target.aim is not None:
        return target
    rotation = nearest_spin(target.rotation, arm.fk(q).rotation, k)[0]
    return frozen(Target, **{**target.__dict__, "rotation": rotation})


def spun_batch(arm: ArmModel, batch: TargetBatch, q: np.ndarray, k: int | None) -> TargetBatch:
    """``batch`` with each rotation turned about its axis ``k`` to the one nearest the
    rotation before it (the first: the tip's at ``q``); unchanged where ``k`` is None, for
    positions or an aim."""
    if k is None or batch.rotations is None or batch.aim is not None or not len(batch):
        return batch
    rotations = np.array(batch.rotations, dtype=float)
    previous = arm.fk(q).rotation
    for i in range(len(rotations)):
        rotations[i] = previous = nearest_spin(rotations[i], previous, k)[0]
    return frozen(TargetBatch, **{**batch.__dict__, "rotations": rotations})
