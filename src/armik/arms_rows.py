"""A several-tip batch solved row by row (chains that share joints, ``Relative`` tasks, a
cost of the whole configuration: ``armik.arms_many``) as chunks of rows, each a batch
backend's job (``ArmsRows``): picklable, the robot travelling as its chains' recipes and
the options as the call's request (``armik.arms_request``), read once on the caller's
side; called in any process that has armik it parses each row's targets and solves the
row from the request as ``Arms.solve`` solves one (``Arms._solve_row``), every tip
verified and every constraint checked. The rows run here one chunk after
another, on threads, or on a backend (``armik.solve.backends``: threads, forked processes,
a Dask cluster's ``OnDask``), with the same answers: each row is solved alone from its own
seed.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from typing import Any, NamedTuple

import numpy as np

from armik.arms_request import ArmsRequest
from armik.batch_result import BatchResult
from armik.errors import TargetError
from armik.problem.settings import SolverSettings
from armik.solve import backends
from armik.solve.backends import Backend, Rows, place
from armik.solve.progress import ProgressArg, make_progress
from armik.targets.batch import TargetBatch

LABEL = "arms"  # the batch's solver: each row names its chains' own in its result


class ArmsRows(NamedTuple):
    """Rows ``start:start + len(targets)`` of the batch as a backend's job."""

    arm: Any  # the ``armik.arms.Arms`` (``arm`` as every job's: a Dask runner sends it once)
    targets: tuple[dict[str, object], ...]  # each row's target per tip, as given
    seeds: np.ndarray  # (rows, dof), each checked
    request: ArmsRequest  # the call's options, read once on the caller's side
    opts: SolverSettings  # the batch's tolerances, read once on the caller's side
    start: int  # its first row in the batch
    read: frozenset[str] = frozenset()  # tips whose targets are parsed (a ``TargetBatch``'s)

    def __call__(self) -> Rows:
        arms = self.arm
        out = empty(arms, len(self.targets), LABEL, self.opts)
        for i, row in enumerate(self.targets):
            with row_named(self.start + i):
                targets, relative = arms._parsed(row, self.read)
                out.put_result(i, arms._solve_row(self.request, targets, relative, self.seeds[i]))
        return Rows(**vars(out), start=self.start)


@contextmanager
def row_named(i: int) -> Iterator[None]:
    """A ``TargetError`` of row ``i`` of a batch or a path says the row, as one arm's batch
    says it ("target 3: ...")."""
    try:
        yield
    except TargetError as e:
        if e.args and isinstance(e.args[0], str) and not e.args[0].startswith("target "):
            e.args = (f"target {i}: {e.args[0]}", *e.args[1:])
        raise


def solve_rows(
    arms: Any,
    targets: Mapping[str, Any],
    seeds: np.ndarray,
    request: ArmsRequest,
    opts: SolverSettings,
    chunk: int,
    workers: int,
    progress: ProgressArg = None,
    run_jobs: Backend | None = None,
) -> BatchResult:
    """Every row of ``targets`` (tip -> N targets) from its row of ``seeds`` as ``request``
    asks, in jobs of
    ``chunk`` rows: on ``run_jobs`` (a backend) with ``workers``, or without one here on
    ``workers`` threads (1: one after another)."""
    n = len(seeds)
    read = frozenset(tip for tip, each in targets.items() if isinstance(each, TargetBatch))
    rows = [{tip: at(each, i) for tip, each in targets.items()} for i in range(n)]
    jobs = [
        ArmsRows(arms, tuple(rows[s : s + chunk]), seeds[s : s + chunk], request, opts, s, read)
        for s in range(0, n, chunk)
    ]
    if run_jobs is None:
        run_jobs = backends.serial if workers == 1 or len(jobs) <= 1 else backends.threads
    out = empty(arms, n, LABEL, opts)
    bar = make_progress(progress, n, "+".join(arms.tips))
    place(run_jobs, jobs, workers, out, bar)  # a row's error raises here, as in a loop
    bar.close()
    return out


def at(rows: Any, i: int) -> Any:
    """Row ``i`` of a tip's rows: a ``TargetBatch``'s ``Target``, any other's item."""
    return rows.target(i) if isinstance(rows, TargetBatch) else rows[i]


def empty(arms: Any, n: int, solver: str, opts: SolverSettings) -> BatchResult:
    """A batch of ``n`` rows over every joint of ``arms``, to be filled in place."""
    return BatchResult.empty(
        n,
        arms.dof,
        solver=solver,
        time=0.0,
        joint_names=arms.joint_names,
        arm="+".join(arms.tips),
        tol_position=opts.tol_position,
        tol_orientation=opts.tol_orientation,
    )
