"""IK where each step is a QP with the joint limits as constraints (qpsolvers).

    minimise 1/2 dq^T (A^T A + lambda I) dq - (A^T e)^T dq
    subject to max(lower - q, -s) <= dq <= min(upper - q, s)

with s = ``numeric.MAX_STEP``. When the unconstrained minimiser (the DLS step) already lies
in the box it is the QP's solution, so the QP backend is called only when a bound is active.
"""

from __future__ import annotations

import numpy as np
import qpsolvers

from ..arm import Arm
from ..options import Options
from ..targets import Target
from .base import Attempt
from .numeric import LAMBDA_MIN, Problem, State, dls_step, limit_box, run_numeric
from .registry import SolverSpec, register

BACKEND_OPTIONS = {
    "osqp": {"eps_abs": 1e-9, "eps_rel": 1e-9, "polish": True, "verbose": False},
}


def build_problem(pb: Problem, s: State) -> qpsolvers.Problem:
    """The QP of one step, as a ``qpsolvers.Problem`` (dense P, box bounds)."""
    lam = 0.5 * float(s.e @ s.e) + LAMBDA_MIN
    P = s.A.T @ s.A + lam * np.eye(s.A.shape[1])
    lb, ub = limit_box(pb, s)
    return qpsolvers.Problem(P, -(s.A.T @ s.e), lb=lb, ub=ub)


def make_step(backend: str):
    options = BACKEND_OPTIONS.get(backend, {})

    def step(pb: Problem, s: State) -> np.ndarray:
        dq = dls_step(pb, s)
        lb, ub = limit_box(pb, s)
        if np.all(dq >= lb) and np.all(dq <= ub):
            return dq
        sol = qpsolvers.solve_problem(build_problem(pb, s), solver=backend, **options)
        if not sol.found or sol.x is None:
            return np.clip(dq, lb, ub)
        return np.clip(sol.x, lb, ub)

    return step


def applies(arm: Arm, target: Target | None = None, opts: Options | None = None) -> str | None:
    backend = "osqp" if opts is None else opts.qp_solver
    if backend not in qpsolvers.available_solvers:
        return (f"QP backend {backend!r} is not installed; installed: "
                f"{', '.join(qpsolvers.available_solvers) or 'none'}")
    return None


def run(arm: Arm, target: Target, q0: np.ndarray, opts: Options, all_solutions: bool
        ) -> list[Attempt]:
    return run_numeric(arm, target, q0, opts, all_solutions, make_step(opts.qp_solver))


SPEC = register(SolverSpec(
    name="qp", kind="numeric", enforces_limits=True, priority=40, check=applies, run=run,
    summary="QP per step with joint limits as constraints (qpsolvers, osqp by default)"))
