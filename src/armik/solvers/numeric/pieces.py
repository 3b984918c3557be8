"""Pieces of the numeric solvers' kernel for tests, readers and ``clik``: ``Problem`` (one
target's settings, chain and scratch), ``evaluate``, ``descend`` and ``RestartSeeds``. They
call the compiled functions (``armik.kernel``), they do not copy them; the solvers' own
call of the kernel is ``driver.py``'s.
"""

from __future__ import annotations

import math
import secrets
import time
from dataclasses import dataclass

import numpy as np

from armik.kernel import descent as _descent
from armik.kernel import error as _error
from armik.kernel import restarts as _restarts
from armik.kernel.chain import Flat
from armik.kernel.clock import thread_cpu_ns
from armik.kernel.problem import NO_LIMIT, SHIFT, STEP_DLS, Settings, Workspace, workspace
from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings
from armik.solvers.numeric.driver import DLS_STEP, Step, settings
from armik.targets.pose import Target


@dataclass
class Problem:
    """One target's settings, chain and scratch, for calling kernel pieces from Python."""

    arm: ArmModel
    chain: Flat
    settings: Settings
    R_t: np.ndarray
    p_t: np.ndarray
    q0: np.ndarray  # joint values (rad, m)
    ws: Workspace

    @classmethod
    def build(cls, arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings) -> Problem:
        R = np.eye(3) if target.rotation is None else target.rotation
        return cls(
            arm,
            arm.kernel_chain.flat,
            settings(opts, target.position_only, arm.dof, 1, DLS_STEP, target.aim),
            np.ascontiguousarray(R, dtype=float),
            np.ascontiguousarray(target.position, dtype=float),
            np.asarray(q0, dtype=float).copy(),
            workspace(arm.dof, 64, arm.kernel_chain.chain.joint_kind.shape[0]),
        )

    @property
    def q0_pin(self) -> np.ndarray:
        return self.arm.to_pin(self.q0)

    def with_step(self, step: Step) -> Problem:
        st = self.settings._replace(step=step.kind, backend=step.backend)
        return Problem(self.arm, self.chain, st, self.R_t, self.p_t, self.q0, self.ws)


@dataclass(slots=True)
class State:
    """The pose error at one configuration (``qp``: Pinocchio coordinates)."""

    qp: np.ndarray
    e: np.ndarray  # weighted error twist
    A: np.ndarray  # weighted error Jacobian
    pos: float
    rot: float
    sq: float  # the least-squares objective |e|^2 (weighted)


def _state(pb: Problem, slot: int) -> State:
    ws = pb.ws
    pos, rot, sq = ws.val[slot].tolist()
    return State(pb.arm.to_pin(ws.q[slot]), ws.e[slot].copy(), ws.A[slot].copy(), pos, rot, sq)


def converged(pb: Problem, s: State) -> bool:
    """Within the iteration's tolerances (half the verification's)."""
    return s.pos <= pb.settings.tol_pos and s.rot <= pb.settings.tol_rot


def evaluate(pb: Problem, qp: np.ndarray) -> State:
    """Pose error and its Jacobian at ``qp`` (Pinocchio coordinates), by the kernel."""
    pb.ws.q[0] = pb.arm.from_pin(qp)
    _error.evaluate(pb.chain, pb.settings, pb.R_t, pb.p_t, pb.ws, 0)
    return _state(pb, 0)


def descend(
    pb: Problem,
    qp: np.ndarray,
    step: Step,
    max_iterations: int,
    deadline: float,
    minima: np.ndarray | None = None,
) -> tuple[State, int, bool]:
    """One attempt of the kernel from ``qp``, until ``max_iterations`` or ``deadline``
    (a ``time.perf_counter()`` value, inf for none); ``minima`` (rows in Pinocchio
    coordinates) are where earlier attempts got stuck. Returns the last state, the
    iterations used, and convergence."""
    pb = pb.with_step(step)
    ws = pb.ws
    count = 0 if minima is None else len(minima)
    if count > ws.minima.shape[0]:
        raise ValueError(f"at most {ws.minima.shape[0]} known minima")
    for k, row in enumerate(() if minima is None else minima):
        ws.minima[k] = pb.arm.from_pin(row)
    ws.q[0] = pb.arm.from_pin(qp)
    deadline_ns = NO_LIMIT
    if math.isfinite(deadline):
        deadline_ns = thread_cpu_ns() + int(max(deadline - time.perf_counter(), 0.0) * 1e9)
    entry = _descent.descend_dls if step.kind == STEP_DLS else _descent.descend_qp
    its, ok, slot = entry(
        pb.chain, pb.settings, pb.R_t, pb.p_t, pb.q0, ws, max_iterations, deadline_ns, count
    )
    return _state(pb, slot), its, ok


class RestartSeeds:
    """The restart configurations of a solve with seed ``seed`` (see ``kernel.restarts``)."""

    def __init__(self, arm: ArmModel, seed: int | None) -> None:
        self.arm = arm
        self.chain = arm.kernel_chain.flat
        self.shift = np.empty(arm.dof)
        _restarts.seed_shift(secrets.randbits(63) if seed is None else int(seed), self.shift)
        self.k = 0

    def next(self) -> np.ndarray:
        out = np.empty(self.arm.dof)
        _restarts.restart_point(self.chain, self.shift, self.k, out)
        self.k += 1
        return out

    def pick(self, pb: Problem) -> np.ndarray:
        """The next candidates' configuration (Pinocchio coordinates) whose tip lands
        nearest the target."""
        out = np.empty(self.arm.dof)
        pb.ws.vec[SHIFT] = self.shift
        self.k = _restarts.pick(pb.chain, pb.settings, pb.R_t, pb.p_t, pb.ws, self.k, out)
        return self.arm.to_pin(out)
