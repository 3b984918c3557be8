"""One frame's pose in another's: "the right hand 30 cm in front of the left, facing it"
(two hands holding a box), "the tool in front of the camera".

The placement measured is ``T_rel = T_ref^-1 T_frame`` (``frame`` in ``relative_to``), held
to ``T`` exactly or within ``bounds`` as ``Pose`` holds a frame in the base; its LOCAL
Jacobian is ``J_frame - Ad(T_rel^-1) J_ref``: the frame's motion less what the reference's
motion carries along.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from armik.errors import TargetError
from armik.problem.tasks.base import KernelRow, Placed, Task, TaskError, check_frame, replaced
from armik.problem.tasks.pose import Pose


class Relative(Task):
    """``frame``'s pose in ``relative_to``'s at ``T`` (any pose spelling), within
    ``bounds`` (m and rad in ``T``'s frame, as ``Pose``'s); ``weights`` as ``Pose``'s."""

    def __init__(
        self,
        frame: str,
        relative_to: str,
        T: object,
        bounds: object = None,
        weights: object = None,
    ) -> None:
        self.frame = check_frame(frame)
        self.relative_to = check_frame(relative_to)
        if self.frame is None or self.relative_to is None:
            raise TargetError(
                f"Relative needs two frame names, got frame={frame!r} and "
                f"relative_to={relative_to!r}: armik.Relative('right_tool', 'left_tool', T)"
            )
        if self.frame == self.relative_to:
            raise TargetError(
                f"Relative holds a frame in another frame, but both are {frame!r}: for a "
                "frame in the base use armik.Pose(T, frame=...)"
            )
        self.pose = Pose(T, bounds=bounds, weights=weights)

    @property
    def frames(self) -> tuple[str | None, ...]:
        return (self.frame, self.relative_to)

    def placement(self, placed: list[Placed]) -> Placed:
        (T_f, J_f), (T_r, J_r) = placed
        T = T_r.actInv(T_f)
        if J_f is None:
            return T, None
        return T, J_f - T.inverse().toActionMatrix() @ J_r

    @property
    def rows(self) -> int:
        return 6

    def residual(self, T: pin.SE3) -> np.ndarray:
        return self.pose.residual(T)

    def jacobian(self, T: pin.SE3, J: np.ndarray) -> np.ndarray:
        return self.pose.jacobian(T, J)

    def kernel_row(self) -> KernelRow:
        """The pose's rows, on the placement of ``frame`` in ``relative_to`` (the table
        reads the second frame as the reference)."""
        return self.pose.kernel_row()

    def free(self) -> tuple[bool, bool]:
        return self.pose.free()  # its bounds and weights are its pose's

    def measure(self, T: pin.SE3, tol_position: float, tol_orientation: float) -> TaskError:
        return self.pose.measure(T, tol_position, tol_orientation)

    def shrunk(self, factor: float) -> Task:
        pose = self.pose.shrunk(factor)
        return self if pose is self.pose else replaced(self, pose=pose)

    def centre(self) -> Task:
        pose = self.pose.centre()
        return self if pose is self.pose else replaced(self, pose=pose)

    def __repr__(self) -> str:
        return f"Relative({self.frame!r}, relative_to={self.relative_to!r})"
