"""A batch the compiled batch has no form for (task lists it cannot lower together,
``prefer=``, ``hold=``, ``swivel=``): each row's own request (``Request.rows``) solved as
``solve`` solves it, in chunks of rows (``RowsChunk``) that run here one after another, or
as a backend's jobs (``solve_batch(..., backend=...)``: ``armik.solve.backends``, the Dask
runner ``armik.solve.distributed``): the same answers either way, since each row is
solved alone from its own seed.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Callable, Iterable, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from armik.batch_result import PREFERRED, BatchResult
from armik.errors import ArmikError
from armik.frozen import frozen
from armik.request import Request
from armik.solve.backends import Rows, place
from armik.solve.progress import ProgressArg, make_progress
from armik.solve.single import routed
from armik.solve.tasks import SOLVER

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel
    from armik.options import Options


class RowsChunk(NamedTuple):
    """Rows ``start:start + len(targets)`` of a row-by-row batch as a backend's job:
    picklable, and called in any process that has armik it solves each row's request from
    its seed there (the solver looked up by name there, every constraint checked) and
    returns their ``Rows``, named by the one solver they share, else by ``label``."""

    arm: ArmModel
    targets: tuple[Request, ...]  # the rows' own requests
    seeds: np.ndarray  # (rows, dof)
    opts: Options  # the batch's, with its seed
    label: str  # the batch's solver where its rows name several
    start: int  # its first row in the batch

    def __call__(self, bar=None) -> Rows:
        n = len(self.targets)
        aim, along = _carried(self.targets)
        out = BatchResult.for_arm(
            self.arm, n, self.label, self.opts, "", self.opts.margin, aim, along=along
        )
        for i, row in enumerate(self.targets):
            try:
                r = routed(self.arm, row.but(q0=self.seeds[i], t0=time.perf_counter()))
            except ArmikError as exc:  # a user's cost or check refused at one row: named
                raise at_row(exc, self.start + i) from None
            out.put_result(i, r)
            out.solvers[i] = r.solver  # dropped by the batch where every row names one
            (out.said if r.success else out.reasons)[i] = r.reason  # its own words, a success's
            if bar is not None:
                bar(i + 1, n)
        named = _named(set(out.solvers.values()), self.label)
        return Rows(**{**vars(out), "solver": named}, start=self.start)


def at_row(exc: ArmikError, k: int) -> ArmikError:
    """``exc`` (of its class and fields) saying first that it was raised at target ``k``."""
    named = copy.copy(exc)
    named.args = (f"target {k}: {exc}", *exc.args[1:])
    return named


def _carried(rows: Sequence[Request]) -> tuple:
    """(aim, along): what the rows' targets share (a batch's ``cone=``, ``look_at=``: a
    region, as ``BatchResult.for_arm`` reads it; an ``armik.Axis`` lowered to poses), None
    for none; (None, None) where the rows' targets differ in them (a batch of task lists,
    an aim beside a pose): its words then name no axis."""
    carried = [(getattr(r.target, "aim", None), getattr(r.target, "along", None)) for r in rows]
    first = carried[0] if carried else (None, None)
    return first if all(c == first for c in carried) else (None, None)


def _named(names: set[str], label: str) -> str:
    """The batch's solver: the one its rows' results name (``label`` where they name
    several), with ``PREFERRED`` after it when ``label`` has it (a preference's batch), so
    that each row names the solver ``solve`` names (``BatchResult``'s rows)."""
    if len(names) != 1:
        return label
    (name,) = names
    return name + PREFERRED if label.endswith(PREFERRED) else name


def solve_rows(
    arm: ArmModel,
    request: Request,
    seeds: np.ndarray,
    progress: ProgressArg = None,
    run_jobs: Callable[..., Iterable[Any]] | None = None,  # a backend (``Backend``)
    chunk: int = 1,
    workers: int = 1,
) -> BatchResult:
    """The batch of ``request.rows``, each from its row of ``seeds``: here, one after
    another, or as ``run_jobs``' jobs of ``chunk`` rows each (on ``workers``, as the
    backend takes them); the batch's solver the one every row's result names, where they
    name one."""
    rows = request.rows or ()
    n = len(rows)
    opts = request.settings
    label = SOLVER if request.score is None else f"{request.solver}{PREFERRED}"
    bar = make_progress(progress, n, f"{arm.name}/{label}")
    if run_jobs is None:
        out: BatchResult = RowsChunk(arm, tuple(rows), seeds, opts, label, 0)(bar)
        named = out.solver
    else:
        jobs = [
            RowsChunk(arm, tuple(rows[s : s + chunk]), seeds[s : s + chunk], opts, label, s)
            for s in range(0, n, chunk)
        ]
        aim, along = _carried(rows)
        out = BatchResult.for_arm(arm, n, label, opts, "", opts.margin, aim, along=along)
        names = place(run_jobs, jobs, workers, out, bar)  # each part named by its rows' solver
        named = names.pop() if len(names) == 1 else label
    bar.close()
    fields = {k: v for k, v in vars(out).items() if k != "start"}
    if len(set(out.solvers.values())) <= 1:  # one solver: the batch's name says it
        fields["solvers"] = {}
    return frozen(
        BatchResult, **{**fields, "solver": named, "time": time.perf_counter() - request.t0}
    )
