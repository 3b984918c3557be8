"""A frame's axis pointing along a direction of the base frame, within a cone: "the suction
cup points down within 3 degrees"; with ``within=0``, a 5-joint arm's "this point, pointing
that way" together with a ``Position``."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from armik.kernel.problem import LOOK_TOWARD
from armik.problem.tasks import cone
from armik.problem.tasks.base import (
    KernelRow,
    Task,
    TaskError,
    check_angle,
    check_frame,
    cone_row,
    replaced,
    unit,
)
from armik.reasons import Cone

RIM = 0.9  # of the cone's angle: a rim direction's tilt, inside the cone by the rest


class Axis(Task):
    """``axis`` (in ``frame``'s own axes; None: the tip) within ``within`` rad of
    ``direction`` (in the base frame)."""

    def __init__(
        self, axis: object, direction: object, within: object = 0.0, frame: str | None = None
    ) -> None:
        self.axis = unit(axis, "Axis axis")
        self.direction = unit(direction, "Axis direction")
        self.within = check_angle(within, "Axis within")
        self.frame = check_frame(frame)

    @property
    def rows(self) -> int:
        return 3

    def residual(self, T: pin.SE3) -> np.ndarray:
        return cone.residual(self.axis, T.rotation.T @ self.direction, self.within)

    def jacobian(self, T: pin.SE3, J: np.ndarray) -> np.ndarray:
        w = T.rotation.T @ self.direction
        return cone.jacobian(self.axis, w, cone.skew(w) @ J[3:], self.within)

    def free(self) -> tuple[bool, bool]:
        return (True, False)  # a direction alone holds no position

    def cone_words(self) -> Cone:
        return Cone(self.within)

    def kernel_row(self) -> KernelRow:
        return cone_row(self.axis, self.within, LOOK_TOWARD, self.direction)

    def measure(self, T: pin.SE3, tol_position: float, tol_orientation: float) -> TaskError:
        w = T.rotation.T @ self.direction
        beyond = max(cone.angle(self.axis, w) - self.within, 0.0)
        return TaskError(None, beyond, beyond <= tol_orientation)

    def shrunk(self, factor: float) -> Task:
        within = self.within * factor
        return self if within == self.within else replaced(self, within=within)

    def rim(self, count: int) -> list[Task]:
        """The axis exactly along ``count`` directions tilted from ``direction`` by
        ``RIM`` of the cone's angle, evenly around it."""
        if self.within == 0.0:
            return []
        u = cone.across(self.direction)
        v = cone.cross(self.direction, u)
        tilt = RIM * self.within
        out: list[Task] = []
        for k in range(count):
            phi = 2.0 * math.pi * k / count
            d = math.cos(tilt) * self.direction + math.sin(tilt) * (
                math.cos(phi) * u + math.sin(phi) * v
            )
            out.append(replaced(self, direction=d, within=0.0))
        return out
