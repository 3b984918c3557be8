"""The classic Pinocchio CLIK loop, kept as a baseline for the benchmark.

As in Pinocchio's inverse-kinematics example: e = log6(T_tip^-1 T_target),
v = -J^T (J J^T + damp I)^-1 e with J = -Jlog6(...) J_local, q <- integrate(q, v dt) with a
fixed dt = 0.1, joints clipped into their limits, no restarts. Not chosen by "auto".

Options: ``max_iterations`` caps the loop (Pinocchio's example uses 1000: the benchmark
passes that), ``iteration_budget`` caps it too, and ``timeout`` counts the solving thread's
CPU time as for dls and qp. ``max_restarts``, ``seed`` and ``nullspace_gain`` have no effect:
the loop has no restarts and no null-space term.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from armik import cpu_time, reasons
from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings
from armik.solvers.answers import Answers, one
from armik.solvers.numeric.pieces import Problem, converged, evaluate
from armik.solvers.registry import SolverSpec, register
from armik.status import Status
from armik.targets.pose import Target

DT = 0.1
DAMP = 1e-12


def applies(arm: ArmModel, target: Target | None = None, _opts: object = None) -> str | None:
    return None


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings, all_solutions: bool
) -> Answers:
    pb = Problem.build(arm, target, q0, opts)
    s = evaluate(pb, pb.q0_pin.copy())
    # after the first evaluation, which compiles the kernel's error in a fresh process
    # (seconds): as for dls and qp, compiling is not the solve's time
    deadline = cpu_time.thread_time() + opts.timeout
    limit = opts.max_iterations
    if opts.iteration_budget is not None:
        limit, deadline = min(limit, opts.iteration_budget), math.inf
    # the damping relative to the weighted rows: at a singular pose 1e-12 beside rows
    # weighted 1e3 was below rounding and the system singular (LinAlgError)
    damp = DAMP * float(pb.settings.w.max()) ** 2 * np.eye(6)
    it = 0
    for it in range(limit + 1):
        if converged(pb, s):
            q = arm.nearest_equivalent(arm.from_pin(s.qp), q0)
            return one(q, Status.CONVERGED, "CLIK converged", iterations=it)
        if it == limit or cpu_time.thread_time() > deadline:
            break
        A, e = s.A, s.e
        v = A.T @ np.linalg.solve(A @ A.T + damp, e)
        qn = pin.integrate(arm.model, s.qp, v * DT)
        arm.clip_pin(qn)
        s = evaluate(pb, qn)
    w = pb.settings.w
    best = reasons.best_errors(s.pos if w[:3].any() else None, s.rot if w[3:].any() else None)
    why = f"CLIK did not converge: {best}"
    q = arm.nearest_equivalent(arm.from_pin(s.qp), q0)
    return one(q, Status.NOT_CONVERGED, why, iterations=it)


SPEC = register(
    SolverSpec(
        name="clik",
        kind="numeric",
        enforces_limits=True,  # every step clipped into the limits (``clip_pin``)
        priority=0,
        why_not=applies,
        solves=frozenset({"position_only", "weights"}),
        run=run,
        summary="baseline: Pinocchio's example CLIK loop (fixed step, clipping)",
        auto=False,
    )
)
