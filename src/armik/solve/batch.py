"""Many targets at once: ``solve_batch``.

``solve_batch`` reads the targets into one ``TargetBatch``, splits them into chunks and
solves the chunks on a pool of threads. A solver with a compiled batch entry
(``SolverSpec.run_batch``: ``dls`` and ``qp``) solves a whole chunk in the compiled kernel
with the GIL released, then the chunk is verified with ``verify.measure.measure_batch``
(Pinocchio FK per row, the errors and limits compiled); only that verification holds the
GIL (10 to 14 % of the time on the Panda and the UR5). Any other solver is called target by target
through ``armik.solve``, one worker unless ``workers`` says otherwise. With collisions
checked, a compiled chunk's verified answers are checked for collisions, and only the
targets whose answer fails are solved again through ``armik.solve``. Such work holds the
GIL (coal and Python) and two threads would run it no faster than one, so it goes to
forked processes instead where that is safe (``armik.solve.forked``).

Every answer is verified by Pinocchio forward kinematics as ``Arm.solve`` verifies it, and
each target uses the options of a call of ``Arm.solve`` (``seed`` included): the same seeds
give the same answers as a loop of ``solve``. The budget is per target: ``timeout`` counts
the solving thread's CPU time, so other threads do not shorten it; ``iteration_budget``
makes the answers identical whatever the thread count, the chunking or the machine.
With collisions checked, ``min_distance`` and ``pair_index`` hold each answer's closest
pair (its names in ``pair_names``, the checker's pairs in their order).

Results go into arrays allocated once for the whole batch; a chunk allocates only its own
scratch memory, so the memory used beyond the targets and results does not grow with N.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from armik import cpu_time, reasons
from armik.batch_result import BatchResult
from armik.constraints.clear import Collisions, of_options
from armik.constraints.collision import checker
from armik.errors import ArmikError, OptionError, warn
from armik.model.limit_units import degrees_note
from armik.request import Request, with_seed
from armik.solve import backends, batch_rows, forked
from armik.solve.backends import Rows, place
from armik.solve.progress import ProgressArg, make_progress, reporter
from armik.solve.stages import chosen, going_on, run
from armik.solvers import registry
from armik.solvers.closed_form import sixr
from armik.solvers.closed_form.family import Family
from armik.status import Status
from armik.targets.batch import TargetBatch, parse_targets
from armik.verify.verdict import verdict_batch
from armik.verify.verdicts import Verdicts

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel
    from armik.problem.settings import SolverSettings
    from armik.solvers.registry import SolverSpec

DEFAULT_CHUNK = 256  # targets per chunk: small enough to balance threads, large enough
#                      that the per-chunk overhead (a few Python calls) does not show
_CONVERGED = Status.CONVERGED.code
_COLLISION = Status.COLLISION.code


def solve_batch(
    arm: ArmModel,
    request: Request,
    workers: int | None = None,
    chunk_size: int | None = None,
    progress: ProgressArg = None,
    backend: object = None,
) -> BatchResult:
    """Solve IK for many targets; returns a ``BatchResult`` in the order of the targets.

    ``request``: the batch's, as ``armik.solve.read.read_batch`` reads ``Arm.solve_batch``'s
    arguments. Its targets: an (N, 4, 4) array, (N, 7) rows ``x y z qx qy qz qw``, (N, 3)
    positions, or a sequence of anything ``Arm.solve`` accepts (see
    ``armik.targets.batch``); its ``q0``: None (mid-limits), one configuration for all, or
    one per target (N, dof). ``workers``: threads, or processes for collision checks and
    solvers without a compiled batch entry (``armik.solve.forked``; default: the number of
    cores for a solver with a compiled batch entry, else 1; a batch solved row by row: 1,
    or what a backend runs its jobs on). ``chunk_size``: targets per
    task (default 256). ``progress``: a bar on stderr when True, or a callable ``(done,
    total)``; default: a bar when stderr is a terminal. ``backend``: where the chunks run
    (``armik.solve.backends``: a registered name such as ``"serial"``, ``"threads"``,
    ``"processes"``, or a function ``run(jobs, workers)``); default: as above.

    Raises ``TargetError`` naming the first bad target, ``OptionError`` for bad options;
    unreachable targets are results with ``success=False``.
    """
    t0 = request.t0
    targets, q0, solver = request.target, request.q0, request.solver
    run_jobs = None if backend is None else backends.backend(backend)
    if request.rows is not None:  # no compiled form: each row's own request
        seeds = batch_seeds(arm, q0, len(request.rows))
        if run_jobs is None:  # here, one after another
            return batch_rows.solve_rows(arm, request, seeds, progress)
        # the backend's jobs: chunks of rows (``batch_rows.RowsChunk``), each row as here
        chunk = _chunk_size(chunk_size)
        workers = 1 if workers is None else _workers(workers, None)
        return batch_rows.solve_rows(arm, request, seeds, progress, run_jobs, chunk, workers)
    opts = with_seed(request.opts, request.seed)  # seeded once: every chunk reads these
    batch = parse_targets(targets, arm)
    n = len(batch.positions)
    seeds = batch_seeds(arm, q0, n)
    spec = chosen(arm, solver, request.key, opts, batch.rotations is None if n else None, batch.aim)
    request = request.but(solver=spec.name)
    workers = _workers(workers, spec)
    chunk = _chunk_size(chunk_size)
    claim = reasons.CONVERGED if spec.kind == "numeric" else _closed_form(spec)  # as solve's
    branches = _branches(arm, spec)
    out = BatchResult.for_arm(
        arm, n, spec.name, opts, claim, opts.margin, batch.aim, branches, batch.along
    )
    clear = _clear(opts) if opts.obstacles or opts.self_collision else ()  # none asked: no call
    if clear:  # the pairs in the checker's order, whatever order rows finish in
        out.pair_names.extend(checker(arm, opts.obstacles, opts.self_collision).pair_names)
    # None: nothing reported (no progress asked, or by default stderr no terminal)
    quiet = progress is False or (progress is None and not sys.stderr.isatty())
    bar = None if quiet else reporter(progress, n, f"{arm.name}/{spec.name}")
    starts = range(0, n, chunk)

    def job(start: int, stop: int | None = None) -> int:
        stop = min(start + chunk, n) if stop is None else stop
        part = batch if start == 0 and stop == n else batch[start:stop]
        solve_chunk(arm, spec, part, seeds[start:stop], request, opts, clear, out, start)
        return stop - start

    done = 0
    if run_jobs is not None:
        # each job without the batch's targets and seeds (its rows' own are its fields):
        # a job pickled to a cluster carried every target, the batch's size each time
        bare = request.but(target=None, q0=None)
        jobs = [
            Chunk(arm, spec.name, batch[s : s + chunk], seeds[s : s + chunk], bare, s)
            for s in starts
        ]
        place(run_jobs, jobs, workers, out, _or_quiet(bar))
    elif workers == 1 or len(starts) <= 1:
        for start in starts:
            done += job(start)
            if bar is not None:
                bar(done, n)
    elif (clear or spec.run_batch is None) and forked.usable():  # most work holds the GIL
        bar = _or_quiet(bar)
        # the first few here, before any fork: what they compile or load is compiled or
        # loaded once, and their time says whether the rest is worth a fork
        first = min(_BEFORE_FORK, n)
        started = cpu_time.thread_time()
        done = job(0, first)
        bar(done, n)
        if (cpu_time.thread_time() - started) / first * (n - first) >= FORK_WORTH and _idle():
            if chunk_size is None:  # every process a share: a few chunks each, not one of 256
                chunk = min(chunk, max(1, -(-(n - first) // (_SHARES * workers))))
            _on_processes(job, out, n, first, chunk, workers, bar)
        else:
            _on_threads(job, range(first, n, chunk), workers, n, done, bar)
    else:
        _on_threads(job, starts, workers, n, done, _or_quiet(bar))
    if bar is not None:
        bar.close()
    object.__setattr__(out, "time", time.perf_counter() - t0)  # the result is ours until returned
    return out


def _or_quiet(bar):
    """``bar``, or a reporter that reports nothing for None (``progress.reporter``)."""
    return make_progress(False, 0, "") if bar is None else bar


class Chunk(NamedTuple):
    """One chunk of a batch as a backend's job (``armik.solve.backends``): picklable, and
    called in any process that has armik it solves and verifies its targets there, as the
    default path does (the solver ``solver`` looked up by name, every constraint of the
    request checked), and returns their rows (``Rows``: they name the row they start at)."""

    arm: ArmModel
    solver: str
    targets: TargetBatch
    seeds: np.ndarray
    request: Request
    start: int  # its first row in the batch

    def __call__(self) -> Rows:
        spec = registry.get(self.solver)
        opts = self.request.settings
        n = len(self.targets)
        aim = self.targets.aim
        branches = _branches(self.arm, spec)
        claim = reasons.CONVERGED if spec.kind == "numeric" else _closed_form(spec)
        along = self.targets.along
        out = BatchResult.for_arm(
            self.arm, n, spec.name, opts, claim, opts.margin, aim, branches, along
        )
        clear = _clear(opts) if opts.obstacles or opts.self_collision else ()
        solve_chunk(self.arm, spec, self.targets, self.seeds, self.request, opts, clear, out, 0)
        return Rows(**vars(out), start=self.start)


def _on_threads(job, starts, workers: int, n: int, done: int, bar) -> None:
    """The chunks at ``starts`` on ``workers`` threads, ``done`` of the ``n`` targets
    solved before."""
    pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="armik")
    try:
        pending = {pool.submit(job, s) for s in starts}
        while pending:
            finished, pending = wait(pending, return_when=FIRST_COMPLETED)
            for f in finished:  # each finished chunk is reported, however many woke us
                done += f.result()  # re-raises a chunk's exception here
                bar(done, n)
    finally:  # an error or Ctrl-C: drop the chunks not started, wait for the running
        pool.shutdown(wait=True, cancel_futures=True)


def _on_processes(job, out: BatchResult, n: int, first: int, chunk: int, workers: int, bar) -> None:
    """The chunks after the ``first`` targets (solved here already) on ``workers``
    processes (``armik.solve.forked``)."""
    done = first

    def rows(start: int) -> BatchResult:  # a chunk's rows, sent from a child
        job(start)
        return out[start : min(start + chunk, n)]

    def collect(start: int, part: BatchResult) -> None:
        nonlocal done
        out.put(start, part)
        done += len(part)
        bar(done, n)

    forked.run(rows, range(first, n, chunk), workers, collect)


_BEFORE_FORK = 16  # targets: enough to reach each compiled part a batch's chunk runs
# s of thread CPU time the rest of a batch would take here, as its first targets took, from
# which forking pays: a fork and a child's end cost about 10 ms
FORK_WORTH = 0.02


def _idle() -> bool:
    """Whether the machine has a core to spare for a child: the last minute's load average
    (this process included) below the cores this process may run on. Measured on the Panda
    shelf scene (benchmarks/collision_scenes.py --near, 2 workers, about 70 us of work a
    target): with a load average of 1.4 to 1.9 on two cores, 1000 targets ran at 19,000
    targets/s on two processes against 12,500-13,200 on two threads; with 2.3, at 10,100-
    10,600 against 12,500-13,100, and 400 targets at 7,500-7,800 against 11,000-11,700."""
    try:
        return os.getloadavg()[0] < cores()
    except OSError:  # no load average: as if idle
        return True


_SHARES = 4  # chunks per process by default: a chunk of 256 left one of two processes idle
# for most of a 400-target batch (measured: 2 processes slower than one)


def _clear(opts) -> tuple[Collisions]:
    """The collisions a batch's options check (``Options``' obstacles, self-collision and
    margin: some asked), as the constraint the verdict applies."""
    return (of_options(opts),)  # the options' own: validated where they were read


def solve_chunk(
    arm: ArmModel,
    spec: SolverSpec,
    targets: TargetBatch,
    seeds: np.ndarray,
    request: Request,
    opts: SolverSettings,
    clear: tuple[Collisions, ...],
    out: BatchResult,
    start: int,
) -> None:
    """Solve and verify one chunk, writing rows ``start:start + len(targets)`` of ``out``;
    ``request``: the batch's, the solver ``spec``'s, a row's solve its copy; ``opts``: its
    settings with its seed (``Request.settings``); ``clear``: the collisions they check
    (``_clear``)."""
    if spec.run_batch is None:
        for i in range(len(targets)):
            try:
                r = _row(arm, request, targets.target(i), seeds[i])
            except ArmikError as exc:  # a user's check refused at one row: named
                raise batch_rows.at_row(exc, start + i) from None
            _put(out, start + i, r)
        return
    collisions = bool(clear)
    # C-ordered and writable, as the compiled entries are compiled for (a broadcast or a
    # read-only seed would compile them again)
    if not (seeds.flags.c_contiguous and seeds.flags.writeable):
        seeds = np.array(seeds, order="C")
    answers = spec.run_batch(arm, targets, seeds, opts)
    success = verdict_batch(arm, answers, targets, opts, out, start, clear)
    if out.brancher is not None:  # each row's branch read from its answer when first read
        out.branches_unread(start, start + len(targets))  # a row solved again: its own
    if spec.kind == "analytic" and opts.checks:
        # a branch that passed a user's check only turned by 2 pi is not ``solve``'s
        # answer, which takes the nearest branch that passes as it is first
        stop = start + len(targets)
        success = success & (out.q[start:stop] == answers.q).all(axis=1)
    if collisions or spec.kind == "analytic" or opts.checks:
        # A success that keeps clear stands: it is the answer ``solve`` gives (its first
        # run, from the same seed, ends there). Every other target is solved again
        # (``_row``): a colliding one restarts (numeric) or tries the other
        # branches (closed forms); a closed form's rare failures get the specific reason
        # (too far, wrist orientation, ...) and the next verified branch that ``solve``
        # would fall back to; a numeric answer a user's check refuses restarts as in
        # ``solve``.
        numeric = collisions and spec.kind != "analytic"
        for i in np.flatnonzero(~success).tolist():
            if numeric and out.status_code[start + i] == _COLLISION:
                # verified, and colliding: its first run is this one, the search goes on
                # from its row (a failure of the solver's own is solved again: its words
                # are the single solve's)
                row = _first_row(out, start + i, opts)
                again = request.but(target=targets.target(i), q0=seeds[i], t0=time.perf_counter())
                r = going_on(arm, again, row)
            else:
                r = _row(arm, request, targets.target(i), seeds[i])
            _put(out, start + i, r)


@dataclass(frozen=True, eq=False)
class Branches:
    """A 6R closed form's branch codes (``sixr.LABELS``) of a batch's answers, read from
    each answer's geometry (``sixr.branch_bits``, as ``solve``'s kernel labels its answer)
    in one compiled call when a result is read (``BatchResult.brancher``): the batch
    itself computes none. ``h``, ``p``: the family's chain (``sixr.flat``)."""

    h: np.ndarray
    p: np.ndarray

    @property
    def labels(self) -> tuple[str, ...]:
        return sixr.LABELS

    def __call__(self, q: np.ndarray) -> np.ndarray:
        rows = np.zeros((len(q), 8))  # ``sixr.pack``'s columns: q, then the branch in 7
        rows[:, :6] = q
        sixr.hand_over(len(q), False, 0, self.h, self.p, rows)  # labels every row
        return rows[:, 7].astype(np.int16)


def _branches(arm: ArmModel, spec: SolverSpec) -> Branches | None:
    """What reads the branches of ``spec``'s compiled batch rows: a 6R family's
    ``Branches``, None for any other solver (its rows solved by ``solve`` carry theirs)."""
    family = getattr(spec.run_batch, "__self__", None)
    if not isinstance(family, Family):
        return None
    h, p = sixr.unflatten.py_func(sixr.flat(arm, family.family, family.classify))[:2]
    return Branches(h, p)


def _put(out: BatchResult, i: int, r) -> None:
    """Row ``i`` of ``out`` as ``solve``'s result ``r``; a success's words kept where its
    row's numbers do not give them (a spin's angle, a search's words)."""
    out.put_result(i, r)
    if r.success and out.reason(i) != r.reason:
        out.said[i] = r.reason


def _closed_form(spec: SolverSpec) -> str:
    """The words a success of ``spec``'s compiled batch rows begins with, as ``solve``'s
    reason does: a 6R family's ("closed form (spherical wrist)"), else none."""
    family = getattr(spec.run_batch, "__self__", None)
    return family.closed_form if isinstance(family, Family) else ""


def _first_row(part: BatchResult, i: int, opts: SolverSettings) -> Verdicts:
    """Row ``i`` of the batch's verdict as ``solve``'s own first run leaves it for the
    search (``armik.solve.avoid``): its status, words and counts, and its collision check's
    distance and pair where it was checked."""
    r = part[i]
    kept: dict[str, Any] = {k: r.extra[k] for k in ("min_distance", "closest_pair") if k in r.extra}
    r = dataclasses.replace(r, extra=kept)
    return Verdicts.of_result(r, opts.tol_position, opts.tol_orientation)


def _row(arm: ArmModel, request: Request, target, seed: np.ndarray):
    """One row solved by the stages, as ``Arm.solve`` solves it."""
    return run(arm, request.but(target=target, q0=seed, t0=time.perf_counter()))


def batch_seeds(arm: ArmModel, q0: object, n: int) -> np.ndarray:
    """(n, dof) seeds: mid-limits, one configuration for every target, or one per target.
    Seeds outside the limits are clipped into them with one ``ArmikWarning``, said at the
    user's line."""
    if q0 is None:
        return np.broadcast_to(arm.middle, (n, arm.dof))
    try:
        if isinstance(q0, (str, bytes)) or np.iscomplexobj(q0):  # type: ignore[arg-type]  # any object: numpy reads it
            raise TypeError  # never drop an imaginary part silently
        q = np.asarray(q0, dtype=float)
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        raise OptionError(
            f"q0 must be {arm.dof} finite real numbers or an (N, {arm.dof}) array, got {q0!r}",
            option="q0",
        ) from None
    if q.shape == (arm.dof,):
        return np.broadcast_to(arm.seed(q), (n, arm.dof))
    if q.shape != (n, arm.dof):
        raise OptionError(
            f"q0 must have shape ({arm.dof},) (one seed for every target) or ({n}, {arm.dof}) "
            f"(one per target), got {q.shape}",
            option="q0",
        )
    bad = ~np.isfinite(q).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise OptionError(f"q0 of target {i} must be finite, got {q[i].tolist()}", option="q0")
    outside = ((q < arm.lower) | (q > arm.upper)).any(axis=1)
    if outside.any():
        i = int(np.flatnonzero(outside)[0])
        warn(
            f"q0 outside the joint limits was clipped into them for {int(outside.sum())} "
            f"target(s); the first, target {i}: "
            + "; ".join(arm.limit_violations(q[i]))
            + degrees_note(q[i], arm)
        )
        q = np.clip(q, arm.lower, arm.upper)
    return q


def cores() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _workers(workers: object, spec: SolverSpec | None) -> int:
    if workers is None:
        return cores() if spec is not None and spec.run_batch is not None else 1
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise OptionError(
            f"workers must be a whole number >= 1 (threads or processes), got {workers!r}",
            option="workers",
            value=workers,
        )
    return int(workers)


def _chunk_size(chunk: object) -> int:
    if chunk is None:
        return DEFAULT_CHUNK
    if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1:
        raise OptionError(
            f"chunk_size must be a whole number >= 1 (targets per task), got {chunk!r}",
            option="chunk_size",
            value=chunk,
        )
    return int(chunk)
