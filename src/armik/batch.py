"""Many targets at once: ``solve_batch`` and its result, ``BatchResult``.

``solve_batch`` reads the targets into one ``TargetBatch``, splits them into chunks and
solves the chunks on a pool of threads. A solver with a compiled batch entry
(``SolverSpec.run_batch``: ``dls`` and ``qp``) solves a whole chunk in the compiled kernel
with the GIL released, then the chunk is verified with ``verify.check_batch`` (Pinocchio FK
per row, the errors and limits compiled); only that verification holds the GIL (10 to 14 %
of the time on the Panda and the UR5). Any other solver is called target by target
through ``armik.solve``; the GIL then serialises the threads, so such a solver runs on one
thread unless ``workers`` says otherwise.

Every answer is verified by Pinocchio forward kinematics as ``Arm.solve`` verifies it, and
each target uses the options of a call of ``Arm.solve`` (``seed`` included): the same seeds
give the same answers as a loop of ``solve``. The budget is per target: ``timeout`` counts
the solving thread's CPU time, so other threads do not shorten it; ``iteration_budget``
makes the answers identical whatever the thread count, the chunking or the machine.

Results go into arrays allocated once for the whole batch; a chunk allocates only its own
scratch memory, so the memory used beyond the targets and results does not grow with N.
"""

from __future__ import annotations

import math
import os
import sys
import time
import warnings
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import npz
from .batch_targets import TargetBatch, parse_targets
from .errors import ArmikWarning, OptionError
from .ik import registry
from .options import Options
from .result import IKResult
from .status import Status

if TYPE_CHECKING:
    from .arm import Arm
    from .ik.registry import SolverSpec

DEFAULT_CHUNK = 256  # targets per chunk: small enough to balance threads, large enough
#                      that the per-chunk overhead (a few Python calls) does not show
_WORDS = np.array([s.value for s in Status])
_CONVERGED = Status.CONVERGED.code
FORMAT = "armik.BatchResult/1"

ProgressArg = bool | Callable[[int, int], None] | None


@dataclass(frozen=True, eq=False)
class BatchResult:
    """The answers for N targets, as arrays with the field names of ``IKResult``.

    - ``q`` (N, dof): joint values (rad, m); for a failure, the best configuration found.
    - ``success`` (N,) bool: verified by Pinocchio FK within the tolerances and the limits.
    - ``status`` (N,) words (``converged``, ``unreachable``, ...), as in ``IKResult``;
      stored as the small integer codes ``status_code`` (``Status.code``).
    - ``position_error`` (N,) m and ``orientation_error`` (N,) rad, measured on ``q``;
      ``orientation_error`` is NaN where it is not measured (position-only targets).
    - ``iterations``, ``restarts`` (N,) per target; ``solver``; ``time`` (s) for the whole
      batch, verification included.
    - ``reasons``: index -> reason for every target that failed (successes are explained
      by their errors; see ``reason(i)``).

    ``len(r)``, ``r[i]`` (an ``IKResult``), ``r[mask]`` or ``r[a:b]`` (a ``BatchResult``),
    iteration over ``IKResult``s, ``save``/``load`` (.npz) and ``summary()``.
    """

    q: np.ndarray
    success: np.ndarray
    status_code: np.ndarray
    position_error: np.ndarray
    orientation_error: np.ndarray
    iterations: np.ndarray
    restarts: np.ndarray
    solver: str
    time: float
    joint_names: tuple[str, ...] = ()
    arm: str = ""
    tol_position: float = Options.tol_position
    tol_orientation: float = Options.tol_orientation
    reasons: dict[int, str] = field(default_factory=dict)

    # -- container --------------------------------------------------------------------

    def __len__(self) -> int:
        return len(self.success)

    @property
    def status(self) -> np.ndarray:
        """(N,) status words; ``r.status == "converged"`` compares element-wise."""
        return _WORDS[self.status_code]

    @property
    def success_rate(self) -> float:
        """Fraction of targets solved, in [0, 1] (NaN for an empty batch)."""
        return float(self.success.mean()) if len(self) else math.nan

    def counts(self) -> dict[str, int]:
        """How many targets ended in each status, statuses that occur only."""
        found = np.bincount(self.status_code.astype(np.intp), minlength=len(_WORDS))
        return {str(_WORDS[i]): int(c) for i, c in enumerate(found) if c}

    def reason(self, i: int) -> str:
        """Why target ``i`` ended as it did."""
        i = self._index(i)
        if i in self.reasons:
            return self.reasons[i]
        parts = [f"position error {self.position_error[i]:.3g} m (tol {self.tol_position:g})"]
        if not math.isnan(self.orientation_error[i]):
            parts.append(
                f"orientation error {self.orientation_error[i]:.3g} rad "
                f"(tol {self.tol_orientation:g})"
            )
        return "verified by forward kinematics: " + ", ".join(parts)

    def _index(self, i: int) -> int:
        n = len(self)
        i = int(i)
        if not -n <= i < n:
            raise IndexError(f"target index {i} out of range for a batch of {n}")
        return i + n if i < 0 else i

    def __getitem__(self, index):
        if isinstance(index, (int, np.integer)):
            i = self._index(index)
            ori = float(self.orientation_error[i])
            return IKResult(
                q=self.q[i],
                success=bool(self.success[i]),
                status=Status.from_code(self.status_code[i]),
                reason=self.reason(i),
                solver=self.solver,
                iterations=int(self.iterations[i]),
                position_error=float(self.position_error[i]),
                orientation_error=None if math.isnan(ori) else ori,
                time=self.time / max(len(self), 1),
                restarts=int(self.restarts[i]),
                extra={"index": i, "batch_time": self.time},
            )
        picked = np.arange(len(self))[index]
        if picked.ndim != 1:
            raise IndexError("index a BatchResult with an int, a slice, a mask or an index list")
        reasons = {}
        if self.reasons:
            keys = np.fromiter(self.reasons, dtype=np.int64, count=len(self.reasons))
            for j in np.flatnonzero(np.isin(picked, keys)).tolist():
                reasons[j] = self.reasons[int(picked[j])]
        return BatchResult(
            q=self.q[picked],
            success=self.success[picked],
            status_code=self.status_code[picked],
            position_error=self.position_error[picked],
            orientation_error=self.orientation_error[picked],
            iterations=self.iterations[picked],
            restarts=self.restarts[picked],
            solver=self.solver,
            time=self.time * len(picked) / max(len(self), 1),  # its share of the batch's time
            joint_names=self.joint_names,
            arm=self.arm,
            tol_position=self.tol_position,
            tol_orientation=self.tol_orientation,
            reasons=reasons,
        )

    def __iter__(self) -> Iterator[IKResult]:
        for i in range(len(self)):
            yield self[i]

    def __repr__(self) -> str:
        return f"BatchResult({self.summary()})"

    def summary(self) -> str:
        """One line: how many were solved, by status, the time and the throughput."""
        n = len(self)
        name = f"{self.arm}/{self.solver}" if self.arm else self.solver
        if n == 0:
            return f"{name}: 0 targets"
        solved = int(self.success.sum())
        counts = ", ".join(f"{k} {v}" for k, v in self.counts().items())
        rate = n / self.time if self.time > 0 else math.inf
        line = (
            f"{name}: {solved}/{n} solved ({100.0 * solved / n:.2f} %; {counts}) in "
            f"{self.time:.3g} s, {rate:,.0f} targets/s"
        )
        if solved:
            worst = self.position_error[self.success].max()
            line += f"; largest error of the solved: {worst:.2g} m"
            ori = self.orientation_error[self.success]
            if not np.isnan(ori).all():
                line += f", {np.nanmax(ori):.2g} rad"
        return line

    # -- files ------------------------------------------------------------------------

    def save(self, path: str | Path) -> Path:
        """Write the arrays and the metadata to an ``.npz`` file (no pickles)."""
        keys = np.array(sorted(self.reasons), dtype=np.int64)
        meta = {
            "format": FORMAT,
            "solver": self.solver,
            "time": self.time,
            "arm": self.arm,
            "joint_names": list(self.joint_names),
            "tol_position": self.tol_position,
            "tol_orientation": self.tol_orientation,
            "statuses": _WORDS.tolist(),
        }
        arrays = dict(
            q=self.q,
            success=self.success,
            status_code=self.status_code,
            status=self.status,
            position_error=self.position_error,
            orientation_error=self.orientation_error,
            iterations=self.iterations,
            restarts=self.restarts,
            reason_index=keys,
            reason_text=np.array([self.reasons[int(k)] for k in keys], dtype=str),
        )
        return npz.save(path, meta, arrays)

    @classmethod
    def load(cls, path: str | Path) -> BatchResult:
        """Read a file written by ``save``; raises ``InputError`` if it is not one."""
        meta, arrays = npz.load(path, FORMAT, "a batch result written by BatchResult.save")
        words = meta["statuses"]
        codes = np.array([Status(w).code for w in words], dtype=np.int8)
        return cls(
            q=arrays["q"],
            success=arrays["success"],
            status_code=codes[arrays["status_code"]],  # through the words: codes may move
            position_error=arrays["position_error"],
            orientation_error=arrays["orientation_error"],
            iterations=arrays["iterations"],
            restarts=arrays["restarts"],
            solver=meta["solver"],
            time=float(meta["time"]),
            joint_names=tuple(meta["joint_names"]),
            arm=meta["arm"],
            tol_position=float(meta["tol_position"]),
            tol_orientation=float(meta["tol_orientation"]),
            reasons={
                int(k): str(t)
                for k, t in zip(arrays["reason_index"].tolist(), arrays["reason_text"])
            },
        )

    # -- building ---------------------------------------------------------------------

    @classmethod
    def empty(cls, n: int, dof: int, **meta) -> BatchResult:
        """Arrays for n answers, to be filled in place (the solvers' failure state)."""
        return cls(
            q=np.zeros((n, dof)),
            success=np.zeros(n, dtype=bool),
            status_code=np.full(n, Status.NOT_CONVERGED.code, dtype=np.int8),
            position_error=np.full(n, np.nan),
            orientation_error=np.full(n, np.nan),
            iterations=np.zeros(n, dtype=np.int32),
            restarts=np.zeros(n, dtype=np.int32),
            **meta,
        )

    @classmethod
    def for_arm(cls, arm: Arm, n: int, solver: str, opts: Options) -> BatchResult:
        """``empty`` rows for n targets of ``arm``, labelled with its joints and tolerances."""
        return cls.empty(
            n,
            arm.dof,
            solver=solver,
            time=0.0,
            joint_names=tuple(arm.joint_names),
            arm=arm.name,
            tol_position=opts.tol_position,
            tol_orientation=opts.tol_orientation,
        )

    def put(self, start: int, part: BatchResult) -> None:
        """Copy ``part`` into rows ``start:start + len(part)`` (used while assembling)."""
        stop = start + len(part)
        for name in _ARRAYS:
            getattr(self, name)[start:stop] = getattr(part, name)
        self.reasons.update({start + i: r for i, r in part.reasons.items()})

    def put_result(self, i: int, r: IKResult) -> None:
        """Copy one ``IKResult`` into row ``i``."""
        self.q[i] = r.q
        self.success[i] = r.success
        self.status_code[i] = r.status.code
        self.position_error[i] = r.position_error
        self.orientation_error[i] = math.nan if r.orientation_error is None else r.orientation_error
        self.iterations[i] = r.iterations
        self.restarts[i] = r.restarts
        if not r.success:
            self.reasons[i] = r.reason


_ARRAYS = (
    "q",
    "success",
    "status_code",
    "position_error",
    "orientation_error",
    "iterations",
    "restarts",
)


def solve_batch(
    arm: Arm,
    targets: object,
    q0: object = None,
    solver: str = "auto",
    workers: int | None = None,
    chunk_size: int | None = None,
    progress: ProgressArg = None,
    **options: object,
) -> BatchResult:
    """Solve IK for many targets; returns a ``BatchResult`` in the order of the targets.

    ``targets``: an (N, 4, 4) array, (N, 7) rows ``x y z qx qy qz qw``, (N, 3) positions,
    or a sequence of anything ``Arm.solve`` accepts (see ``armik.batch_targets``).
    ``q0``: None (mid-limits), one configuration for all, or one per target (N, dof).
    ``workers``: threads (default: the number of cores for a solver with a compiled batch
    entry, else 1). ``chunk_size``: targets per task (default 256). ``progress``: a bar on
    stderr when True, or a callable ``(done, total)``; default: a bar when stderr is a
    terminal. ``options``: as for ``Arm.solve`` and applied to every target.

    Raises ``TargetError`` naming the first bad target, ``OptionError`` for bad options;
    unreachable targets are results with ``success=False``.
    """
    t0 = time.perf_counter()
    opts = Options.from_kwargs(options)
    batch = parse_targets(targets, arm)
    n = len(batch)
    seeds = batch_seeds(arm, q0, n)
    spec = registry.choose(solver, arm, batch.target(0) if n else None, opts)
    workers = _workers(workers, spec)
    chunk = _chunk_size(chunk_size)
    out = BatchResult.for_arm(arm, n, spec.name, opts)
    bar = make_progress(progress, n, f"{arm.name}/{spec.name}")
    starts = range(0, n, chunk)

    def job(start: int) -> int:
        stop = min(start + chunk, n)
        solve_chunk(arm, spec, batch[start:stop], seeds[start:stop], opts, options, out, start)
        return stop - start

    done = 0
    if workers == 1 or len(starts) <= 1:
        for start in starts:
            done += job(start)
            bar(done, n)
    else:
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
    bar.close()
    object.__setattr__(out, "time", time.perf_counter() - t0)
    return out


def solve_chunk(
    arm: Arm,
    spec: SolverSpec,
    targets: TargetBatch,
    seeds: np.ndarray,
    opts: Options,
    options: dict,
    out: BatchResult,
    start: int,
) -> None:
    """Solve and verify one chunk, writing rows ``start:start + len(targets)`` of ``out``."""
    if spec.run_batch is None:
        from .solve import solve

        for i in range(len(targets)):
            r = solve(arm, targets.target(i), q0=seeds[i], solver=spec.name, **options)[0]
            out.put_result(start + i, r)
        return
    attempts = spec.run_batch(arm, targets, np.ascontiguousarray(seeds), opts)
    part = judge(arm, attempts, targets, opts)
    out.put(start, part)
    if spec.kind == "analytic":
        # A closed form is deterministic: its rare failures are solved again one by one, so
        # they carry the specific reason (too far, wrist orientation, ...) and the next
        # verified branch that ``solve`` would fall back to.
        from .solve import solve

        for i in np.flatnonzero(~part.success).tolist():
            r = solve(arm, targets.target(i), q0=seeds[i], solver=spec.name, **options)[0]
            out.put_result(start + i, r)


def judge(arm: Arm, attempts, targets: TargetBatch, opts: Options) -> BatchResult:
    """Verify a chunk of attempts with the FK check and decide each status, as ``solve``
    judges one attempt: a verified answer is a success whatever the solver claimed; a
    claimed success that fails the check is ``joint_limits`` (outside the limits) or
    ``not_converged``; any other claim stands."""
    from .verify import check_batch

    n = len(targets)
    part = BatchResult.empty(n, arm.dof, solver="", time=0.0)
    part.q[:] = attempts.q
    part.iterations[:] = attempts.iterations
    part.restarts[:] = attempts.restarts
    claim = np.asarray(attempts.claim, dtype=np.int8)
    c = check_batch(arm, part.q, targets, opts)
    part.position_error[:] = c.position_error
    part.orientation_error[:] = c.orientation_error
    ok = c.ok
    claimed = claim == _CONVERGED
    part.success[:] = ok
    part.status_code[:] = np.where(
        ok,
        _CONVERGED,
        np.where(
            claimed,
            np.where(c.within_limits, Status.NOT_CONVERGED.code, Status.JOINT_LIMITS.code),
            claim,
        ),
    )
    for i in np.flatnonzero(~ok).tolist():  # the rare failures get their reasons
        errors = _errors(part, i, opts)
        if claimed[i] and not c.within_limits[i]:
            part.reasons[i] = "outside the joint limits: " + "; ".join(
                arm.limit_violations(part.q[i])
            )
        elif claimed[i]:
            part.reasons[i] = f"forward-kinematics check failed: {errors}"
        elif claim[i] == Status.UNREACHABLE.code:
            distance = math.dist(targets.positions[i].tolist(), arm.first_joint_origin.tolist())
            part.reasons[i] = (
                f"target is {distance:.4g} m from the first joint, beyond the arm's reach of "
                f"at most {arm.reach:.4g} m; q is the seed, unchanged"
            )
        elif claim[i] == Status.NOT_CONVERGED.code:
            budget = (
                f"{opts.iteration_budget} iterations"
                if getattr(opts, "iteration_budget", None) is not None
                else f"{opts.timeout:g} s of CPU time"
            )
            part.reasons[i] = (
                f"no solution within the budget ({budget}, at most {opts.max_restarts} "
                f"restarts); best found: {errors}; the target may be out of reach"
            )
        else:
            part.reasons[i] = f"{Status.from_code(claim[i]).value}: {errors}"
    return part


def _errors(part: BatchResult, i: int, opts: Options) -> str:
    """The check's errors of row i, worded as ``verify.Check.describe``."""
    text = f"position error {part.position_error[i]:.3g} m (tol {opts.tol_position:g})"
    if not math.isnan(part.orientation_error[i]):
        text += (
            f", orientation error {part.orientation_error[i]:.3g} rad "
            f"(tol {opts.tol_orientation:g})"
        )
    return text


def batch_seeds(arm: Arm, q0: object, n: int) -> np.ndarray:
    """(n, dof) seeds: mid-limits, one configuration for every target, or one per target.
    Seeds outside the limits are clipped into them with one ``ArmikWarning``."""
    if q0 is None:
        return np.broadcast_to(arm.middle, (n, arm.dof))
    try:
        if isinstance(q0, (str, bytes)) or np.iscomplexobj(q0):
            raise TypeError  # never drop an imaginary part silently
        q = np.asarray(q0, dtype=float)
    except (TypeError, ValueError):
        raise OptionError(
            f"q0 must be {arm.dof} real numbers or an (N, {arm.dof}) array, got {q0!r}",
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
        warnings.warn(
            f"q0 outside the joint limits was clipped into them for {int(outside.sum())} "
            f"target(s); the first, target {i}: " + "; ".join(arm.limit_violations(q[i])),
            ArmikWarning,
            stacklevel=3,
        )
        q = np.clip(q, arm.lower, arm.upper)
    return q


def cores() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _workers(workers: object, spec: SolverSpec) -> int:
    if workers is None:
        return cores() if spec.run_batch is not None else 1
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise OptionError(
            f"workers must be a whole number >= 1 (threads), got {workers!r}",
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


# -- progress ---------------------------------------------------------------------------


class Progress:
    """A one-line progress bar on stderr, redrawn at most every 0.1 s."""

    def __init__(self, label: str, total: int, stream=None) -> None:
        self.label, self.total = label, total
        self.stream = stream if stream is not None else sys.stderr
        self.t0 = time.perf_counter()
        self.last = -math.inf

    def __call__(self, done: int, total: int) -> None:
        now = time.perf_counter()
        if now - self.last < 0.1 and done < total:
            return
        self.last = now
        frac = done / total if total else 1.0
        filled = int(30 * frac)
        rate = done / (now - self.t0) if now > self.t0 else 0.0
        self.stream.write(
            f"\r{self.label:<20} [{'#' * filled}{'.' * (30 - filled)}] {done}/{total} "
            f"({rate:,.0f}/s)"
        )
        self.stream.flush()

    def close(self) -> None:
        self.stream.write("\n")
        self.stream.flush()


class _Callback:
    def __init__(self, fn: Callable[[int, int], None] | None) -> None:
        self.fn = fn

    def __call__(self, done: int, total: int) -> None:
        if self.fn is not None:
            self.fn(done, total)

    def close(self) -> None:
        pass


def make_progress(progress: ProgressArg, total: int, label: str):
    """A progress reporter ``(done, total)`` with ``close()``: a bar (True, or None with
    stderr on a terminal), the caller's callable, or nothing."""
    if progress is None:
        progress = sys.stderr.isatty()
    if progress is True:
        return Progress(label, total)
    if progress is False:
        return _Callback(None)
    if callable(progress):
        return _Callback(progress)
    raise OptionError(
        f"progress must be True, False, None or a callable (done, total), got {progress!r}",
        option="progress",
        value=progress,
    )
