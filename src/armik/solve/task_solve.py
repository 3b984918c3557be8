"""A request whose target is a task list with no compiled form (``Request.problem``): the
task solver (``armik.solve.tasks``), started from the compiled answer to the problem's
centre where it has one (``centre``)."""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from armik.model.arm_model import ArmModel
from armik.problem.problem import as_target, lower, rims, tightened
from armik.problem.scores import Score
from armik.request import Request
from armik.result import IKResult
from armik.solve.stages import run
from armik.solve.tasks import CENTRE_RESTARTS, solve_tasks
from armik.solvers import registry


def solve_problem(arm: ArmModel, req: Request, score: Score | None = None) -> IKResult:
    """The task solver's verified result for ``req.problem``, from its centre's answer;
    with ``score``, moved along the tasks' null space while it falls (``solve_tasks``)."""
    opts = req.settings
    problem = dataclasses.replace(req.problem, constraints=opts.constraints, budget=opts.budget)
    start = centre(arm, problem, req)
    return solve_tasks(arm, problem, req.q0, opts, req.t0, start, score=score)


RIM_SAMPLES = 8  # points on a region's rim tried where a closed form misses its centre


def centre(arm: ArmModel, problem, req: Request) -> IKResult | None:
    """The compiled answer to the problem's centre (``tightened``), if it has a form: an
    answer to the problem itself, or a start for the task solver; else None. Where a
    closed form finds no answer at the centre, the nearest q0 of its answers on the
    region's rim (``rims``: a cone's axis tilted to its edge), if any reaches."""
    lowered = lower(tightened(problem), arm.tip)
    if lowered is None:
        return None
    target, said = lowered
    target = as_target(target) or target  # the tasks' values as they read them: not again
    base = req.but(solver="auto", every=False, t0=time.perf_counter(), score=None, problem=None)
    hold = req.opts.hold
    if hold is not None and (arm.dof != 7 or len(hold) != 1):  # held apart: the task
        base = base.narrowed(hold=None)  # solver's box holds them
    restarts = min(req.opts.max_restarts, CENTRE_RESTARTS)
    centre = run(arm, base.lowered(target, said, max_restarts=restarts))
    if centre.success or registry.get(centre.solver).kind != "analytic":
        return centre  # a numeric miss shows nothing: the task solver goes on from it
    found = []
    for rim in rims(problem, RIM_SAMPLES):
        lowered = lower(rim, arm.tip)
        if lowered is not None:
            r = run(arm, base.lowered(as_target(lowered[0]) or lowered[0], lowered[1]))
            found += [r] if r.success else []
    seed = arm.seed(req.q0)
    return min(found, key=lambda r: float(np.linalg.norm(r.q - seed)), default=centre)
