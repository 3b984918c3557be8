"""A frame's origin at a point of the base frame, exactly or within per-axis bounds."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from armik.problem.tasks.base import (
    KernelRow,
    Task,
    TaskError,
    check_bounds,
    check_frame,
    dead_zone,
    replaced,
    scaled,
)
from armik.targets.pose import _vector

_EYE, _ONES, _FREE = np.eye(3), np.ones(6), np.full(3, np.inf)


class Position(Task):
    """``p`` (m, base frame) for ``frame``'s origin (None: the tip), each base axis within
    +- its bound (``bounds``: 3 numbers, m; ``math.inf`` frees an axis)."""

    def __init__(self, p: object, bounds: object = None, frame: str | None = None) -> None:
        self.p = _vector(p, 3, "Position")
        self.frame = check_frame(frame)
        self.bounds = np.zeros(3) if bounds is None else check_bounds(bounds, 3, "Position bounds")

    @property
    def rows(self) -> int:
        return 3

    def residual(self, T: pin.SE3) -> np.ndarray:
        return dead_zone(T.translation - self.p, self.bounds)[0]

    def jacobian(self, T: pin.SE3, J: np.ndarray) -> np.ndarray:
        active = dead_zone(T.translation - self.p, self.bounds)[1]
        return np.where(active[:, None], T.rotation @ J[:3], 0.0)

    def kernel_row(self) -> KernelRow:
        # the target's rotation the identity: the box in the base frame; the rotation free
        return KernelRow(
            _EYE, self.p, np.concatenate([self.bounds, _FREE]), _ONES, parts=(True, False)
        )

    def measure(self, T: pin.SE3, tol_position: float, tol_orientation: float) -> TaskError:
        pos = float(np.linalg.norm(self.residual(T)))
        return TaskError(pos, None, pos <= tol_position)

    def centre(self) -> Task:
        """The exact point: the frame's distance to it whatever the bounds (an infinite one
        included), as ``Arm.solve`` reports it; itself where it is exact."""
        return replaced(self, bounds=np.zeros(3)) if self.bounds.any() else self

    def shrunk(self, factor: float) -> Task:
        if math.isfinite(factor) and not self.bounds.any():  # an exact point: no region
            return self
        bounds = scaled(self.bounds, factor)
        return self if np.array_equal(bounds, self.bounds) else replaced(self, bounds=bounds)
