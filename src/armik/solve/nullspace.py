"""A verified answer moved along the self-motion of a redundant arm towards a lower score
(``armik.problem.scores``): the score's gradient projected into the null space of the tip
Jacobian, each step followed by Newton steps back onto the target, kept only where the
score falls and the pose still holds. The numeric arms' local refinement for ``prefer=``;
the result is verified again by Pinocchio FK as every answer is.
"""

from __future__ import annotations

import time

import numpy as np
import pinocchio as pin

from armik.model.arm_model import ArmModel
from armik.problem.scores import Score

STEPS = 40  # gradient steps at most
NEWTON = 4  # Newton steps back onto the target after each
FD = 1e-6  # rad or m: the finite-difference step of the score's gradient
HOLD = 1e-9  # m and rad: the pose error a moved configuration must keep


def _pose_error(arm: ArmModel, q: np.ndarray, target: pin.SE3) -> np.ndarray:
    """The tip's error twist to ``target`` in the tip frame (LOCAL, as the Jacobian)."""
    return pin.log6(arm.fk(q).inverse() * target).vector


def _onto(arm: ArmModel, q: np.ndarray, target: pin.SE3) -> tuple[np.ndarray, float]:
    """``q`` taken back onto ``target`` by Newton steps, and its remaining pose error."""
    for _ in range(NEWTON):
        e = _pose_error(arm, q, target)
        if np.abs(e).max() <= HOLD:
            return q, float(np.abs(e).max())
        q = np.clip(q + np.linalg.pinv(arm.jacobian(q)) @ e, arm.lower, arm.upper)
    return q, float(np.abs(_pose_error(arm, q, target)).max())


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


def descend(
    arm: ArmModel, q: np.ndarray, target: pin.SE3, score: Score, q0: np.ndarray, budget: float
) -> np.ndarray:
    """``q`` moved along the self-motion while the score falls, within ``budget`` seconds
    of the thread's CPU time; ``q`` itself when no step helps."""
    started = time.thread_time()
    best = score(arm, q, q0)
    step = 0.1
    for _ in range(STEPS):
        if time.thread_time() - started > budget or step < 1e-4:
            break
        J = arm.jacobian(q)
        N = np.eye(q.size) - np.linalg.pinv(J) @ J
        d = N @ _gradient(arm, score, q, q0)
        norm = float(np.linalg.norm(d))
        if norm < 1e-12:
            break
        trial, error = _onto(arm, np.clip(q - step * d / norm, arm.lower, arm.upper), target)
        value = score(arm, trial, q0)
        if error <= HOLD and value < best:
            q, best, step = trial, value, step * 1.5
        else:
            step *= 0.5
    return q
