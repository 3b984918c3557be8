"""The forward-kinematics check that every solver's answer passes through.

Errors are recomputed with Pinocchio from the returned joints, never taken from a solver.
Position error: |p_target - p_tip| (m). Orientation error: the geodesic angle
|log3(R_tip^T R_target)| (rad). Axes with zero weight (see ``Options.weights``) are not
measured; for a position-only target the orientation error is None.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .arm import Arm
from .options import Options
from .targets import Target


@dataclass(frozen=True)
class Check:
    position_error: float
    orientation_error: float | None
    violations: list[str]
    tol_position: float
    tol_orientation: float

    @property
    def pose_ok(self) -> bool:
        ori_ok = self.orientation_error is None or self.orientation_error <= self.tol_orientation
        return self.position_error <= self.tol_position and ori_ok

    @property
    def ok(self) -> bool:
        return self.pose_ok and not self.violations

    def describe(self) -> str:
        parts = [f"position error {self.position_error:.3g} m (tol {self.tol_position:g})"]
        if self.orientation_error is not None:
            parts.append(
                f"orientation error {self.orientation_error:.3g} rad (tol {self.tol_orientation:g})"
            )
        return ", ".join(parts)


def check(arm: Arm, q: np.ndarray, target: Target, opts: Options) -> Check:
    """Measure ``q`` against ``target`` with Pinocchio FK and the joint limits."""
    T = arm.fk_pin(arm.to_pin(q))
    d = target.position - T.translation
    ori = None
    if opts.weights is None:  # the common case, without masks
        pos = math.sqrt(d.dot(d))
        if target.rotation is not None and not opts.position_only:
            dw = pin.log3(T.rotation.T @ target.rotation)
            ori = math.sqrt(dw.dot(dw))
    else:
        w = opts.weight_vector(target.position_only)
        pos = float(np.linalg.norm((T.rotation.T @ d)[w[:3] > 0]))
        if target.rotation is not None and w[3:].any():
            dw = pin.log3(T.rotation.T @ target.rotation)
            ori = float(np.linalg.norm(dw[w[3:] > 0]))
    violations = arm.limit_violations(q)
    return Check(pos, ori, violations, opts.tol_position, opts.tol_orientation)
