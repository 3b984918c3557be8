"""One target: the route of a request (``routed``), as the facades (``Arm``, and ``Arms``
for each chain) take it once they have read the keyword options into one
(``armik.solve.read``): the rank stage for a score (``armik.solve.preferred``), the task
solver for a task list without a compiled form (``armik.solve.task_solve``), or the stages
of the compiled path (``armik.solve.stages``)."""

from __future__ import annotations

from armik.model.arm_model import ArmModel
from armik.request import Request
from armik.solve.preferred import preferred
from armik.solve.stages import run
from armik.solve.task_solve import solve_problem


def routed(arm: ArmModel, req: Request):
    """The result of a request (with ``req.every``, the list): ranked by its score, solved
    by the task solver, or by the compiled path's stages."""
    if req.score is not None:
        return preferred(arm, req)
    if req.problem is not None:
        one = solve_problem(arm, req)
        return [one] if req.every else one
    return run(arm, req)
