"""The joint limits, the constraint every problem has: each step stays within them, and an
answer outside them (by more than ``LIMIT_TOL``) is ``joint_limits``, not a success."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from armik import reasons
from armik.constraints.base import Check, Constraint
from armik.status import Status
from armik.tolerances import LIMIT_TOL

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


@dataclass(frozen=True)
class JointLimits(Constraint):
    """The arm's joint limits (its URDF's, or those ``Arm.with_limits`` gives)."""

    def said(self) -> dict[str, object]:
        return {}  # always on: no option spells it

    def box(self, arm: ArmModel) -> tuple[np.ndarray, np.ndarray]:
        return arm.lower, arm.upper

    def check(self, arm: ArmModel, Q: np.ndarray) -> Check:
        Q = np.asarray(Q, dtype=float)
        # ``ArmModel.within_limits`` over N rows at once (a NaN is outside)
        ok = np.asarray(((Q >= arm.lower - LIMIT_TOL) & (Q <= arm.upper + LIMIT_TOL)).all(axis=1))
        return Check(
            ok, Status.JOINT_LIMITS, lambda i: reasons.outside_limits(arm.limit_violations(Q[i]))
        )


def on_limits(arm: ArmModel, q: np.ndarray, tol: float = 1e-9) -> list[str]:
    """The joints of ``q`` that rest on a limit (within ``tol``, rad or m), in words: where
    a descent that found no answer stopped, a limit is often what held it."""
    values = np.asarray(q, dtype=float).tolist()
    lower, upper = arm.lower.tolist(), arm.upper.tolist()
    units = ["m" if p else "rad" for p in arm.prismatic.tolist()]
    said = []
    for name, v, lo, hi, unit in zip(arm.joint_names, values, lower, upper, units):
        if abs(v - lo) <= tol:
            said.append(f"{name} at its lower limit ({lo:.6g} {unit})")
        elif abs(v - hi) <= tol:
            said.append(f"{name} at its upper limit ({hi:.6g} {unit})")
    return said
