"""Many targets for several tips: ``Arms.solve_batch`` and ``Arms.solve_path``.

Targets are a mapping tip -> that tip's N targets (anything ``Arm.solve_batch`` takes for
one tip: (N, 4, 4), (N, 7), (N, 3), a list of targets or of task lists). Chains that share
no joint, with no ``Relative`` task coupling them, are each solved by their own batch (the
compiled path, on every core) or path, and the rows joined: a row succeeds when every
tip's does, its status is the first failing tip's, its errors the worst tip's, its reason
names each tip that failed. Other robots (a shared torso, relative tasks) are solved row by
row as ``Arms.solve`` solves one (``Arms._solve_row``, from the call's options read once:
``armik.arms_request``); a path then seeds each waypoint with the previous answer and
reports a larger move than ``max_joint_step`` as ``discontinuous``, naming the joint, and
a jump hidden between two waypoints too, naming the tip (``armik.arms_steps``). A
cost of the whole configuration (a callable ``prefer=``, ``armik.arms_prefer``) is a
batch's row by row too, and refused on a path of chains that share no joint. Every target
is parsed once: each tip's rows where its chain's own batch or path takes them, else each
row as ``Arms.solve`` parses it; a row solved again, and a path's steps judged, read those.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from typing import Any, Protocol

import numpy as np

from armik.arms_apart import facade
from armik.arms_collision import between, clear_rows
from armik.arms_joined import held_rows, left_out
from armik.arms_many_read import (
    count_rows,
    in_tips_order,
    parsed_rows,
    read_rows,
    row_of,
    row_seeds,
)
from armik.arms_options import check_held, held_apart
from armik.arms_prefer import combined, is_cost
from armik.arms_request import ArmsRequest, read_request
from armik.arms_rows import empty, row_named, solve_rows
from armik.arms_steps import held, hidden_steps, stacked
from armik.batch_result import BatchResult
from armik.constraints.base import own
from armik.errors import OptionError
from armik.problem.problem import relative_tasks
from armik.problem.settings import SolverSettings
from armik.solve import backends
from armik.solve.batch import DEFAULT_CHUNK
from armik.solve.ladder import STEP_EDGE
from armik.solve.path import max_step
from armik.solve.progress import ProgressArg
from armik.solve.read import check_plan
from armik.solve.read import options as read_options
from armik.status import Status


class Arms(Protocol):
    """What these functions read of ``armik.arms.Arms`` (which calls them: named here, not
    imported, so that neither module imports the other)."""

    _chains: dict[str, Any]
    _columns: dict[str, np.ndarray]
    _union: Any
    shared: tuple[str, ...]

    @property
    def tips(self) -> tuple[str, ...]: ...
    @property
    def dof(self) -> int: ...
    @property
    def joint_names(self) -> Sequence[str]: ...
    @property
    def middle(self) -> np.ndarray: ...

    lower: np.ndarray
    upper: np.ndarray

    @property
    def prismatic(self) -> np.ndarray: ...
    def chain(self, tip: str) -> Any: ...
    def _parsed(self, targets: Mapping[str, object], read: Any = ()) -> tuple[dict, dict]: ...
    def _solve_row(self, request: ArmsRequest, targets: dict, relative: dict, q0: Any) -> Any: ...
    def _check_targets(self, targets: object) -> dict: ...
    def _seed(self, q0: object, row: int | None = None) -> np.ndarray: ...
    def _one_start(self, options: dict, q0: object) -> None: ...


_CONVERGED = Status.CONVERGED.code
_JUMP = Status.DISCONTINUOUS.code


def solve_batch(
    arms: Arms,
    targets: Mapping[str, Any],
    q0: object = None,
    *,
    workers: int | None = None,
    chunk_size: int | None = None,
    progress: ProgressArg = None,
    backend: object = None,
    **options: Any,
) -> BatchResult:
    """Every row of ``targets`` (tip -> N targets) from ``q0`` (None: mid-limits, one
    configuration, or one per row (N, dof)); one ``BatchResult`` over every joint.
    ``workers``, ``chunk_size``, ``progress`` and ``backend`` as ``Arm.solve_batch``'s: on
    independent chains each chain's batch takes them (a progress callable hears each
    chain's batch in turn); row by row (module docstring) rows go in chunks of
    ``chunk_size`` (default 256) on ``workers`` threads (default 1), and ``backend`` raises
    ``OptionError``."""
    t0 = time.perf_counter()
    n = count_rows(arms, targets, "solve_batch")
    targets = in_tips_order(arms, targets)
    seeds = row_seeds(arms, q0, n)  # its shape first: a constraint's words were said before
    arms._one_start(options, q0)  # for a constraint resolved from it, as Arm's batch
    opts = _read(options)
    request = read_request(arms, options)  # what every row reads of the options
    prefer = request.prefer
    if _independent(arms, targets) and not is_cost(prefer):
        batch = {"workers": workers, "chunk_size": chunk_size, "progress": progress}
        each = request.chains_options(arms.tips)  # each chain's part, as Arms.solve's
        check_held(arms._chains, each, seeds, arms._columns)  # before any chain's batch
        read = read_rows(arms, targets)  # before any chain's batch runs: their errors first
        parts = {
            tip: facade(arms, tip, each[tip]).solve_batch(
                rows, q0=seeds[:, arms._columns[tip]], backend=backend, **batch, **each[tip]
            )
            for tip, rows in read.items()
        }
        seeds = _held_apart(arms, seeds, each, parts)
        out = _joined(arms, parts, seeds, opts, time.perf_counter() - t0, prefer)
        held_rows(arms, out, left_out(arms, options, targets))  # a tip left out: its checks
        # the chains' answers together; a row whose arms collide solved again as
        # ``Arms.solve`` solves it, which tries the other combinations of their answers
        for i in clear_rows(arms, out, between(arms, options, targets)):
            out.put_result(i, _solved(arms, request, row_of(arms, read, i), i, seeds[i]))
        return _timed(out, t0)
    run_jobs = None if backend is None else backends.backend(backend)
    threads, size = _whole(workers, "workers", 1), _whole(chunk_size, "chunk_size", DEFAULT_CHUNK)
    out = solve_rows(arms, targets, seeds, request, opts, size, threads, progress, run_jobs)
    return _timed(out, t0)


def _held_apart(arms: Arms, seeds: np.ndarray, each: dict, parts: Mapping) -> np.ndarray:
    """``seeds`` (rows over the robot's joints) with the held joints of the tips given no
    rows (not in ``parts``) at their values (``arms_options.held_apart``)."""
    each_seed = {tip: seeds[:, cols] for tip, cols in arms._columns.items()}
    held = held_apart(each_seed, each, arms._chains, parts)
    out = seeds.copy()
    for tip, cols in arms._columns.items():
        out[:, cols] = held[tip]
    return out


def _whole(value: object, name: str, default: int) -> int:
    """``workers`` or ``chunk_size`` as a whole number >= 1 (None: ``default``)."""
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        what = "threads, or a backend's workers" if name == "workers" else "targets per task"
        raise OptionError(
            f"{name} must be a whole number >= 1 ({what}), got {value!r}",
            option=name,
            value=value,
        )
    return int(value)


def solve_path(
    arms: Arms,
    waypoints: Mapping[str, Any],
    q0: object,
    max_joint_step: float | np.ndarray | None = None,
    plan: str = "follow",
    **options: Any,
) -> BatchResult:
    """The waypoints (tip -> N waypoints) in order from ``q0`` (None: the first free,
    solved from mid-limits), never with a silent jump larger than ``max_joint_step`` (one
    number or one per joint of ``joint_names``)."""
    t0 = time.perf_counter()
    check_plan(plan)  # a plan that is none: refused as Arm.solve_path refuses it
    n = count_rows(arms, waypoints, "solve_path")
    waypoints = in_tips_order(arms, waypoints)
    start = arms.middle if q0 is None else row_seeds(arms, q0, 1)[0]
    step = _step(arms, max_joint_step)
    opts = _read(options)
    _refuse_resolved(options.get("constraints"))
    request = read_request(arms, options)  # what every row reads of the options
    prefer = request.prefer
    if _independent(arms, waypoints):
        if is_cost(prefer):
            raise OptionError(
                f"prefer={prefer!r}: a cost of the robot's whole configuration on a path of "
                "chains that share no joint, where each chain's path ranks its own answers; "
                "give 'nearest', 'limits', 'manipulability' or armik.Posture over "
                "robot.joint_names (split by chain), or solve each waypoint with "
                "Arms.solve(..., prefer=cost)",
                option="prefer",
                value=prefer,
            )
        each = request.chains_options(arms.tips)  # each chain's part, as Arms.solve's
        check_held(arms._chains, each, start[None, :], arms._columns)
        read = read_rows(arms, waypoints)  # once: each chain's path, the rows again, the judge
        parts = {
            tip: facade(arms, tip, each[tip]).solve_path(
                rows,
                None if q0 is None else start[arms._columns[tip]],  # None: a free start
                max_joint_step=step[arms._columns[tip]],
                plan=plan,
                **each[tip],
            )
            for tip, rows in read.items()
        }
        out = _joined(
            arms, parts, _held_apart(arms, np.tile(start, (n, 1)), each, parts), opts, 0.0, prefer
        )
        held_rows(arms, out, left_out(arms, options, waypoints))  # a tip left out: its checks
        found = clear_rows(arms, out, between(arms, options, waypoints))  # the answers together
        if not out.success.all():  # the rows after a failed one: from the success before it
            rows = [row_of(arms, read, i) for i in range(n)]
            _follow(arms, out, rows, start, step, request, q0 is None, set(found))
            hidden_steps(arms, out, read, step, opts)  # the rows solved again too
        return _timed(out, t0)
    if plan != "follow":
        raise OptionError(
            f"plan={plan!r} over several tips needs chains that share no joint and no "
            "Relative task between them; here use plan='follow'",
            option="plan",
            value=plan,
        )
    rows = parsed_rows(arms, waypoints, n)  # before any row is solved: their errors first
    out = empty(arms, n, "arms, path", opts)
    _follow(arms, out, rows, start, step, request, q0 is None)
    read = {tip: stacked([targets[tip] for targets, _ in rows]) for tip in waypoints}
    hidden_steps(arms, out, read, step, opts, out.success.copy())  # on from successes
    return _timed(out, t0)


def _solved(arms: Arms, request: ArmsRequest, row: tuple[dict, dict], i: int, q0) -> Any:
    """Row ``i`` (``row``: its parsed targets and their relative tasks) as ``Arms.solve``
    solves it from ``q0`` (checked, as its seed is): where the chains' first answers
    collide, the nearest clear combination of their answers."""
    with row_named(i):
        return arms._solve_row(request, row[0], row[1], arms._seed(q0))


def _follow(arms, out, rows, start, step, request, free: bool, again=None) -> None:
    """A path's rows (``out``; ``rows``: each row's parsed targets, as ``_solved`` takes
    them) each solved from the last success before it (``start`` before
    any; ``free``: no q0, the first row from anywhere), a larger move than ``step``
    ``discontinuous``. With ``again`` (each chain's path run from its own answers, the rows
    a check between the chains then failed): those rows, and after a failed row each success
    that moves more than ``step`` from the row the path went on from, the last success or
    jump (as one arm's path, ``ladder.held_to_step``), solved again from there."""
    q_prev = start
    after = len(out.q) if again is None else int(np.argmin(out.success))  # the first failed
    for i in range(len(out.q)):
        redo = again is None or i in again
        if not redo and i > after and out.success[i] and not free:
            redo = bool((np.abs(out.q[i] - q_prev) > step + STEP_EDGE).any())
        if redo:
            r = _solved(arms, request, rows[i], i, q_prev)
            if r.success and not (free and i == 0):  # without q0 the first is free
                r = held(arms, r, q_prev, step, first=i == 0)
            out.put_result(i, r)
        jump = again is not None and out.status_code[i] == _JUMP
        if out.success[i] or jump:
            q_prev, free = np.array(out.q[i]), False


def _step(arms: Arms, max_joint_step: object) -> np.ndarray:
    """``max_joint_step`` over every joint of the robot: one number, or one per joint."""
    return max_step(max_joint_step, list(arms.joint_names))


def _independent(arms: Arms, targets: Mapping[str, Any]) -> bool:
    """Whether every tip's rows can go to its own chain's batch: no shared joint and no
    ``Relative`` task in any row."""
    if arms._union is not None:
        return False
    return not any(
        isinstance(rows, (list, tuple)) and any(relative_tasks(row) for row in rows)
        for rows in targets.values()
    )


def _read(options: Mapping[str, Any]) -> SolverSettings:
    """The options every chain's solve reads, checked before any runs: an unknown one, or a
    bad value, refused before the work, not after it. ``prefer=`` and ``solver=`` are each
    chain's own solve's to read (``Arms.solve`` takes them), and so are constraints given by
    tip (``arms_options.chain_constraints``)."""
    by_tip = isinstance(options.get("constraints"), Mapping)
    own: tuple[str, ...] = ("prefer", "solver", "constraints") if by_tip else ("prefer", "solver")
    return read_options({k: v for k, v in options.items() if k not in own})


def _measured(out: BatchResult, parts) -> None:
    """Each row's ``measured`` where some tip's verdict measured other than its distances
    (a region, weights): the worst tip's, each other tip's distances standing for it."""
    rows = np.zeros(len(out.q), dtype=bool)
    worst = np.zeros((len(out.q), 2))
    worst[:, 1] = math.nan
    for b in parts:
        apart = ~np.isnan(b._measured[:, 0])
        rows |= apart
        pos = np.where(apart, b._measured[:, 0], b.position_error)
        ori = np.where(apart, b._measured[:, 1], b.orientation_error)
        worst[:, 0] = np.fmax(worst[:, 0], pos)
        worst[:, 1] = np.fmax(worst[:, 1], ori)
    out._measured[rows] = worst[rows]


def _nearest(out: BatchResult, parts) -> None:
    """Each row's closest pair where the chains checked collisions: the nearest of the
    chains' (each checked its own links), with the margin their successes kept."""
    for b in parts:
        if np.isnan(b._distances).all():
            continue
        object.__setattr__(out, "margin", max(out.margin, b.margin))
        rows = ~(b._distances >= out._distances) & ~np.isnan(b._distances)  # NaN: unchecked
        ours = np.array([out._pair(p) for p in b.pair_names] + [-1], dtype=np.int32)
        out._distances[rows] = b._distances[rows]
        out._pairs[rows] = ours[b._pairs[rows]]  # -1 stays -1


def _timed(out: BatchResult, t0: float) -> BatchResult:
    object.__setattr__(out, "time", time.perf_counter() - t0)
    return out


def _joined(
    arms: Arms,
    parts: dict[str, BatchResult],
    seeds: np.ndarray,
    opts: SolverSettings,
    elapsed: float,
    prefer: object = None,
) -> BatchResult:
    """One row per target over every joint from each tip's rows (module docstring), with
    ``prefer``, each row's score the robot's from the tips' (``armik.arms_prefer``)."""
    n = len(seeds)
    solvers = "+".join(dict.fromkeys(b.solver for b in parts.values()))
    out = empty(arms, n, solvers, opts)
    out.q[:] = seeds
    out.success[:] = True
    out.status_code[:] = _CONVERGED
    out.position_error[:] = math.nan  # (NaN where no tip's target holds a position)
    out.iterations[:] = 0
    out.restarts[:] = 0
    for tip in reversed(list(parts)):  # the first failing tip's status wins
        b = parts[tip]
        out.q[:, arms._columns[tip]] = b.q
        out.status_code[:] = np.where(b.success, out.status_code, b.status_code)
    orientation = np.full(n, math.nan)
    for b in parts.values():
        np.logical_and(out.success, b.success, out=out.success)
        out.position_error[:] = np.fmax(out.position_error, b.position_error)
        orientation = np.fmax(orientation, b.orientation_error)
        out.iterations[:] += b.iterations
        out.restarts[:] += b.restarts
    out.orientation_error[:] = orientation
    for tip in [t for t in arms.tips if t in parts]:  # each tip's distances, in tips' order
        out.errors[tip] = np.column_stack([parts[tip].position_error, parts[tip].orientation_error])
    _measured(out, parts.values())
    _nearest(out, parts.values())
    if prefer is not None:
        out._scores[:] = combined(prefer, np.array([b._scores for b in parts.values()]))
    for i in np.flatnonzero(~out.success):
        out.reasons[int(i)] = "; ".join(
            f"{tip}: {b.status[i]}: {b.reason(int(i))}"
            for tip, b in parts.items()
            if not b.success[i]
        )
    object.__setattr__(out, "time", elapsed)
    return out


def _refuse_resolved(given: object) -> None:
    """An ``OptionError`` for a user's constraint resolved from the start (its own
    ``at(arm, seed)``) on a path of several tips, whose rows are solved again from the
    waypoint before, where it would be resolved again (not from the path's q0)."""
    items = given.values() if isinstance(given, Mapping) else [given]
    for c in [c for x in items for c in (x if isinstance(x, (list, tuple)) else [x])]:
        if own(c):
            raise OptionError(
                f"constraint {type(c).__name__} is resolved from the start (its at(arm, "
                "seed)), and a path of several tips solves rows again from the waypoint "
                "before: not yet taken here; solve each chain's path, "
                "robot.chain(tip).solve_path(..., constraints=[...])",
                option="constraints",
                value=c,
            )
