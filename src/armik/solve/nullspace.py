"""A verified answer moved along the self-motion of a redundant arm towards a lower score
(``armik.problem.scores``): a projected gradient, the score's gradient projected into the
null space of the tip Jacobian, each step followed by Newton steps back onto the target,
kept only where the score falls and the pose still holds, run until the step stalls. The
numeric arms' local refinement for ``prefer=``; the result is verified again by Pinocchio
FK as every answer is.

For the squared-distance scores (``nearest``, ``Posture``) the first step tried is the
minimiser of the score on the tangent plane of the self-motion, ``-N (q - q0)`` for
``nearest``: the descent converges in a few steps where a fixed step length took tens.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np
import pinocchio as pin

from armik import cpu_time
from armik.model.arm_model import ArmModel
from armik.problem.scores import Nearest, Posture, Score

STEPS = 40  # gradient steps at most
NEWTON = 4  # Newton steps back onto the target after each
FD = 1e-6  # rad or m: the finite-difference step of the score's gradient
HOLD = 1e-9  # m and rad: the pose error a moved configuration must keep
FIRST = 0.1  # rad or m: the first step's length where the score has no quadratic model
SHORTEST = 1e-7  # rad or m: the shortest step tried
HALVINGS = 8  # a step that still does not help after this many halvings ends the descent
FLAT = 1e-12  # a step that lowers a score without a model by less (relative) ends it
MEET = 1e-3  # rad or m: a descent this near where an earlier one ended would end there too


def _row_solve(J: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``(J J^T)^-1 v`` (``J`` of full row rank), by least squares where it is singular."""
    try:
        return np.linalg.solve(J @ J.T, v)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(J @ J.T, v, rcond=None)[0]


class Held(Protocol):
    """What a moved configuration must keep: residual rows, zero where it holds, and their
    Jacobian (rows x dof)."""

    def residual(self, q: np.ndarray) -> np.ndarray: ...

    def jacobian(self, q: np.ndarray) -> np.ndarray: ...


class HeldPose:
    """The tip held at ``target``: the error twist of the tip to it, in the tip frame
    (LOCAL, as the Jacobian), with its sign for ``q - J^T (J J^T)^-1 r``."""

    def __init__(self, arm: ArmModel, target: pin.SE3) -> None:
        self.arm, self.target = arm, target

    def residual(self, q: np.ndarray) -> np.ndarray:
        return -pin.log6(self.arm.fk(q).inverse() * self.target).vector

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        return self.arm.jacobian(q)


def _onto(
    held: Held, q: np.ndarray, box: tuple[np.ndarray, np.ndarray]
) -> tuple[np.ndarray, float]:
    """``q`` taken back onto what is ``held`` by Newton steps within ``box`` (lower,
    upper), and its remaining residual."""
    for _ in range(NEWTON):
        r = held.residual(q)
        error = float(np.abs(r).max(initial=0.0))
        if error <= HOLD:
            return q, error
        J = held.jacobian(q)
        q = np.clip(q - J.T @ _row_solve(J, r), *box)
    return q, float(np.abs(held.residual(q)).max(initial=0.0))


def _gradient(arm: ArmModel, score: Score, q: np.ndarray, q0: np.ndarray) -> np.ndarray:
    exact = score.gradient(arm, q, q0)
    if exact is not None:
        return exact
    g = np.empty(q.size)
    for i in range(q.size):
        d = np.zeros(q.size)
        d[i] = FD
        g[i] = (score(arm, q + d, q0) - score(arm, q - d, q0)) / (2.0 * FD)
    return g


def _model_scale(score: Score, value: float) -> float | None:
    """``c`` such that ``-c N g`` (``g`` the score's gradient) is the minimiser of the score
    on the self-motion's tangent plane: the distance itself for ``nearest`` (its gradient
    is the unit vector ``(q - q0) / |q - q0|``), ``1 / (2 max w)`` for a ``Posture``
    (exact when its weights are equal, shorter otherwise); None for other scores."""
    if isinstance(score, Nearest):
        return value
    if isinstance(score, Posture) and score.weights.max() > 0.0:
        return 0.5 / float(score.weights.max())
    return None


def descend(
    arm: ArmModel,
    q: np.ndarray,
    target: pin.SE3 | Held,
    score: Score,
    q0: np.ndarray,
    budget: float,
    steps: int = STEPS,
    ends: Sequence[np.ndarray] = (),
    box: tuple[np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """``q`` moved along the self-motion while the score falls, within ``budget`` seconds
    of the thread's CPU time and ``steps`` gradient steps; ``q`` itself when no step helps.

    Each step: the projected gradient ``d = -N g`` (``N = I - J^T (J J^T)^-1 J``), a trial
    of length ``min(model, 2 * last accepted)`` along it (``model``: the tangent plane's
    minimiser where the score has one, else unbounded; the first ``last`` is ``FIRST``),
    halved until the score falls with the pose held; the descent ends where ``HALVINGS``
    halvings did not help, the model's step is shorter than ``SHORTEST``, or (no model)
    a step lowered the score by less than ``FLAT`` of it, or the step came within ``MEET``
    of one of ``ends`` (where earlier descents from other answers ended). ``target``: the
    tip's pose, or any residual rows to hold (``Held``: the tasks of a task list, several
    tips). ``box``: the (lower, upper) every configuration stays within (default: the
    joint limits; a path passes its step's box about the previous answer)."""
    box = (arm.lower, arm.upper) if box is None else box
    held = HeldPose(arm, target) if isinstance(target, pin.SE3) else target
    started = cpu_time.thread_time()
    best = score(arm, q, q0)
    length = FIRST
    for _ in range(steps):
        if cpu_time.thread_time() - started > budget:
            break
        J = held.jacobian(q)
        g = _gradient(arm, score, q, q0)
        d = J.T @ _row_solve(J, J @ g) - g  # -N g
        norm = float(np.linalg.norm(d))
        if norm < 1e-12:
            break
        scale = _model_scale(score, best)
        trial = min(2.0 * length, np.inf if scale is None else scale * norm)
        for _ in range(HALVINGS + 1):
            if trial < SHORTEST or cpu_time.thread_time() - started > budget:
                return q
            step = np.clip(q + (trial / norm) * d, *box)
            moved, error = _onto(held, step, box)
            value = score(arm, moved, q0)
            if error <= HOLD and value < best:
                flat = scale is None and best - value <= FLAT * max(abs(best), 1.0)
                q, best, length = moved, value, trial
                if flat or any(np.abs(q - e).max() <= MEET for e in ends):
                    return q  # flat (the steps shrink slowly), or where another descent ended
                break
            trial *= 0.5
        else:
            return q  # no step along d helps: a minimum along the self-motion, or near one
    return q
