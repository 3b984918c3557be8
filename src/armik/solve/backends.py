"""Batch backends: where ``solve_batch``'s chunks run, named (``solve_batch(...,
backend=...)``).

A backend is a function ``run(jobs, workers)`` of a list of chunk jobs and the workers
asked for, returning each job's result as the job returned it, in any order (a list, or an
iterable that yields them as they finish, ``concurrent.futures.as_completed``'s order
too). A job is a picklable callable of no arguments (``armik.solve.batch.Chunk``, or
``armik.solve.batch_rows.RowsChunk`` for a batch solved row by row): called
in any process that has armik, it solves and verifies its chunk there (the solver looked
up there by name, every constraint of the request checked) and returns its rows as a
``BatchResult`` that names the row of the batch they start at (``Rows``),
where the batch puts them.
So a backend only decides where and when the calls run: here one after another
(``"serial"``), on threads (``"threads"``), on forked processes (``"processes"``, threads
where forking is not safe: ``armik.solve.forked``), or anything of the user's own
(``register_backend``, or a callable passed as ``backend=``).

Without ``backend=`` a batch runs as it always has (``armik.solve.batch``): its chunks on
threads, or on forked processes for work that holds the GIL, written in place.
"""

from __future__ import annotations

import dataclasses
import operator
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

from armik.batch_result import BatchResult
from armik.errors import ArmikError, OptionError, listing
from armik.solve import forked

Job = Callable[[], Any]  # one chunk: solved and verified where it is called
Backend = Callable[[Sequence[Job], int], Iterable[Any]]  # (jobs, workers) -> their results

_BACKENDS: dict[str, Backend] = {}


def register_backend(name: str, run: Backend) -> None:
    """Name ``run`` as a batch backend (see the module); ``OptionError`` for a name that is
    not a str or is taken, or a ``run`` that is not callable."""
    if not isinstance(name, str) or not name:
        raise OptionError(f"a backend's name is a str, got {name!r}", option="backend", value=name)
    if name in _BACKENDS:
        raise OptionError(
            f"backend name {name!r} is taken: unregister_backend({name!r}) first",
            option="backend",
            value=name,
        )
    if not callable(run):
        raise OptionError(
            f"backend {name!r} must be a function run(jobs, workers), got {run!r}",
            option="backend",
            value=run,
        )
    _BACKENDS[name] = run


def unregister_backend(name: str) -> Backend:
    """Remove backend ``name`` and return it; ``OptionError`` for a name not registered."""
    run = backend(name)
    del _BACKENDS[name]
    return run


def backends() -> list[str]:
    """The registered backends' names."""
    return list(_BACKENDS)


def backend(given: object) -> Backend:
    """The backend ``given`` names, or ``given`` itself when it is callable; ``OptionError``
    listing the registered names otherwise."""
    if isinstance(given, str) and given in _BACKENDS:
        return _BACKENDS[given]
    if callable(given) and not isinstance(given, str):
        return given  # type: ignore[return-value]
    raise OptionError(
        f"unknown batch backend {given!r}: give one of {listing(backends())}, a function "
        "run(jobs, workers) or a name registered with armik.solve.backends.register_backend",
        option="backend",
        value=given,
    )


def serial(jobs: Sequence[Job], workers: int) -> Iterator[Any]:
    """Every job here, one after another (``workers`` ignored)."""
    for job in jobs:
        yield job()


def threads(jobs: Sequence[Job], workers: int) -> Iterator[Any]:
    """The jobs on ``workers`` threads, their results in order as they come."""
    pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="armik")
    try:
        yield from pool.map(operator.call, jobs)
    finally:  # an error or Ctrl-C: drop the jobs not started, wait for the running
        pool.shutdown(wait=True, cancel_futures=True)


def processes(jobs: Sequence[Job], workers: int) -> Iterable[Any]:
    """The jobs shared by this process and ``workers - 1`` forked children
    (``armik.solve.forked``; threads where forking is not safe), in order once all ran."""
    if workers == 1 or len(jobs) <= 1 or not forked.usable():
        return threads(jobs, workers)
    done: dict[int, Any] = {}
    forked.run(lambda k: jobs[k](), range(len(jobs)), workers, done.__setitem__)
    return [done[k] for k in range(len(jobs))]


@dataclasses.dataclass(frozen=True, eq=False)
class Rows(BatchResult):
    """A job's answers, with the row of the batch they start at: the batch puts them
    there, whatever order a backend gives them in."""

    start: int = -1


def place(run_jobs: Backend, jobs: Sequence[Any], workers: int, out: BatchResult, bar) -> set[str]:
    """Each job's rows from ``run_jobs(jobs, workers)``, put in place in ``out`` as they
    come, in any order: each at the row its job starts at (``Rows.start``; a job's
    ``targets``, its rows' count); an ``ArmikError`` naming the backend when it gives too
    few, too many, repeated or other results. Returns the solvers the parts name."""
    at = {job.start: job for job in jobs}
    n, done = len(out), 0
    parts = run_jobs(jobs, workers)
    if isinstance(parts, (str, bytes, BatchResult)) or not hasattr(parts, "__iter__"):
        raise ArmikError(
            f"batch backend {run_jobs!r} returned {parts!r}: a backend returns each job's "
            "result (job()), as a list or an iterable yielding them"
        )
    placed: set[int] = set()
    names: set[str] = set()
    for part in parts:
        job = at.get(part.start) if isinstance(part, Rows) else None
        if job is None or len(part) != len(job.targets) or part.arm != out.arm:
            raise ArmikError(
                f"batch backend {run_jobs!r} gave {part!r} for job {len(placed)}: "
                "a backend returns each job's result (job()) as the job returned it, "
                "in any order"
            )
        if part.start in placed:
            raise ArmikError(
                f"batch backend {run_jobs!r} gave the result of the job at row {part.start} "
                "twice: a backend returns each job's result once"
            )
        placed.add(part.start)
        names.add(part.solver)
        out.put(part.start, part)
        done += len(part)
        bar(done, n)
    if len(placed) != len(jobs):
        raise ArmikError(
            f"batch backend {run_jobs!r} gave {len(placed)} results for {len(jobs)} jobs: a "
            "backend returns each job's result (job()), in any order"
        )
    return names


register_backend("serial", serial)
register_backend("threads", threads)
register_backend("processes", processes)
