"""A frame's full pose, exactly or within per-axis bounds, with TRAC-IK's meaning.

The error twist of the reached placement ``T`` relative to the target ``T_t``, expressed in
the target frame: position ``R_t^T (p - p_t)``, rotation ``log3(R_t^T R)``. With bounds
``(bx, by, bz, brx, bry, brz)`` (m, rad) each component may lie within +- its bound;
``math.inf`` frees an axis, and so does a weight of 0.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from armik.errors import TargetError
from armik.problem.tasks.base import (
    KernelRow,
    Task,
    TaskError,
    check_bounds,
    check_frame,
    check_weights,
    dead_zone,
    replaced,
    scaled,
)
from armik.targets.pose import Target, parsed


class Pose(Task):
    """``T`` (any pose spelling ``Arm.solve`` takes) for ``frame`` (None: the tip)."""

    def __init__(
        self,
        T: object,
        bounds: object = None,
        weights: object = None,
        frame: str | None = None,
    ) -> None:
        target = parsed(T)
        if target.rotation is None:
            raise TargetError(
                f"Pose needs a full pose, got a position {target.position.tolist()}: use "
                "armik.Position for a position alone"
            )
        self.T = pin.SE3(target.rotation, target.position)
        self.frame = check_frame(frame)
        self.bounds = np.zeros(6) if bounds is None else check_bounds(bounds, 6, "Pose bounds")
        self.weights = np.ones(6) if weights is None else check_weights(weights, 6, "weights")
        # a weight of 0 frees its axis as an infinite bound does, not its distance
        self._free = np.where(self.weights == 0.0, math.inf, self.bounds)

    @classmethod
    def of(cls, target: Target, frame: str | None) -> Pose:
        """The exact pose ``Pose(target, frame=frame)`` of a full pose parsed already (a
        ``Target`` with a rotation), built without reading it again: one per tip of every
        solve over shared joints (``armik.Arms``)."""
        self = cls.__new__(cls)
        self.T = pin.SE3(target.rotation, target.position)
        self.frame = frame
        self.bounds, self.weights, self._free = np.zeros(6), np.ones(6), np.zeros(6)
        return self

    @property
    def rows(self) -> int:
        return 6

    def twist(self, T: pin.SE3) -> np.ndarray:
        """(6,): the error twist of ``T`` in the target frame (m, rad)."""
        R_t = self.T.rotation
        M = R_t.T @ T.rotation
        return np.concatenate([R_t.T @ (T.translation - self.T.translation), pin.log3(M)])

    def residual(self, T: pin.SE3) -> np.ndarray:
        out: np.ndarray = self.weights * dead_zone(self.twist(T), self._free)[0]
        return out

    def jacobian(self, T: pin.SE3, J: np.ndarray) -> np.ndarray:
        M = self.T.rotation.T @ T.rotation
        rows = np.vstack([M @ J[:3], pin.Jlog3(M) @ J[3:]])
        active = dead_zone(self.twist(T), self._free)[1]
        return np.where(active[:, None], self.weights[:, None] * rows, 0.0)

    def kernel_row(self) -> KernelRow:
        return KernelRow(self.T.rotation, self.T.translation, self._free, self.weights)

    def measure(self, T: pin.SE3, tol_position: float, tol_orientation: float) -> TaskError:
        outside = dead_zone(self.twist(T), self._free)[0]  # the distance from the region
        pos, ori = float(np.linalg.norm(outside[:3])), float(np.linalg.norm(outside[3:]))
        return TaskError(pos, ori, pos <= tol_position and ori <= tol_orientation)

    def centre(self) -> Task:
        """The exact pose, every weight 1: the frame's distance to the target's position and
        the angle to its rotation whatever the bounds (an infinite one included) and the
        weights, as ``Arm.solve`` reports them; itself where it is exact."""
        if not self.bounds.any() and self.weights.all():
            return self
        zero = np.zeros(6)
        return replaced(self, bounds=zero, weights=np.ones(6), _free=zero)

    def shrunk(self, factor: float) -> Task:
        if math.isfinite(factor) and not self.bounds.any():  # an exact pose: no region
            return self
        bounds = scaled(self.bounds, factor)
        if np.array_equal(bounds, self.bounds):  # no region: itself
            return self
        return replaced(self, bounds=bounds, _free=np.where(self.weights == 0.0, math.inf, bounds))
