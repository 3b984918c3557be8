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
