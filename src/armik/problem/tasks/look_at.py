"""A frame's axis pointing at a point of the base frame, within a cone: a camera or a
nozzle aimed at a spot."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from armik.errors import TargetError
from armik.kernel.problem import LOOK_POINT
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
from armik.targets.pose import _vector
from armik.tolerances import MAX_POSITION, SIGHT


class LookAt(Task):
    """``axis`` (in ``frame``'s own axes; None: the tip) within ``within`` rad of the line
    from the frame's origin to ``point`` (m, base frame)."""

    def __init__(
        self,
        point: object,
        axis: object = (0.0, 0.0, 1.0),
        within: object = 0.0,
        frame: str | None = None,
    ) -> None:
        self.point = _vector(point, 3, "LookAt point")
        if not np.abs(self.point).max() <= MAX_POSITION:  # its sight from the tip overflows
            raise TargetError(
                f"LookAt point {self.point.tolist()} is beyond {MAX_POSITION:g} m from the "
                "base: give it in metres; a point that far away is a direction: say it with "
                "armik.Axis(axis, direction)"
            )
        self.axis = unit(axis, "LookAt axis")
        self.within = check_angle(within, "LookAt within")
        self.frame = check_frame(frame)

    @property
    def rows(self) -> int:
        return 3

    def _sight(self, T: pin.SE3) -> tuple[np.ndarray, float]:
        """The unit line of sight in the base frame and the distance to the point."""
        v = self.point - T.translation
        distance = float(np.linalg.norm(v))
        return (v / distance if distance > SIGHT else v), distance

    def residual(self, T: pin.SE3) -> np.ndarray:
        # no rows on the point (within SIGHT, as the compiled rows): a restart leaves it
        d, distance = self._sight(T)
        if distance <= SIGHT:
            return np.zeros(3)
        return cone.residual(self.axis, T.rotation.T @ d, self.within)

    def jacobian(self, T: pin.SE3, J: np.ndarray) -> np.ndarray:
        d, distance = self._sight(T)
        if distance <= SIGHT:
            return np.zeros((3, J.shape[1]))
        R = T.rotation
        w = R.T @ d
        # d moves with the origin (dp = R v dq) and w with the frame's rotation too
        dd = (np.eye(3) - np.outer(d, d)) / distance @ (-R @ J[:3])
        return cone.jacobian(self.axis, w, cone.skew(w) @ J[3:] + R.T @ dd, self.within)

    def free(self) -> tuple[bool, bool]:
        return (True, False)  # a direction alone holds no position

    def cone_words(self) -> Cone:
        return Cone(self.within, at_point=True)

    def kernel_row(self) -> KernelRow:
        return cone_row(self.axis, self.within, LOOK_POINT, self.point)

    def measure(self, T: pin.SE3, tol_position: float, tol_orientation: float) -> TaskError:
        d, distance = self._sight(T)
        # standing on the point, to within SIGHT: no line of sight (a move of the frame by
        # a micrometre turns it any way), nothing aimed
        if distance <= SIGHT:
            return TaskError(None, math.pi, False)
        beyond = max(cone.angle(self.axis, T.rotation.T @ d) - self.within, 0.0)
        return TaskError(None, beyond, beyond <= tol_orientation)

    def shrunk(self, factor: float) -> Task:
        within = self.within * factor
        return self if within == self.within else replaced(self, within=within)
