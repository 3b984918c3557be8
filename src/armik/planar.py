"""The plane of motion of a planar chain (every joint revolute, all axes parallel).

Plane coordinates: origin on the first joint's axis at the tip's height, ``normal`` along
the first joint's axis, ``x`` the projection of the base axis that follows the normal's
largest component (z -> x, x -> y, y -> z), ``y = normal x x``. For an arm turning about
the base z axis the plane's (x, y) are the base frame's (x, y).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

if TYPE_CHECKING:
    from .arm import Arm

PARALLEL_TOL = 1e-9


@dataclass(frozen=True)
class Plane:
    """Plane of motion, in the arm's base frame (m)."""

    origin: np.ndarray
    x: np.ndarray
    y: np.ndarray
    normal: np.ndarray
    signs: np.ndarray  # +1 where a joint axis is along the normal, -1 where opposite
    joint_origins: np.ndarray  # (dof, 2): each joint's axis, in plane coordinates

    def to_3d(self, xy: np.ndarray) -> np.ndarray:
        return self.origin + xy[0] * self.x + xy[1] * self.y

    def to_2d(self, p: np.ndarray) -> np.ndarray:
        d = p - self.origin
        return np.array([d @ self.x, d @ self.y])

    def height(self, p: np.ndarray) -> float:
        """Distance of ``p`` from the plane along the normal (m)."""
        return float((p - self.origin) @ self.normal)


def find_plane(arm: Arm) -> Plane | None:
    if np.any(arm.prismatic):
        return None
    q = arm.to_pin(arm.middle)
    J = pin.computeFrameJacobian(arm.model, arm.data, q, arm.tip_frame_id, pin.LOCAL_WORLD_ALIGNED)
    R = arm.T_base_world.rotation
    axes = (R @ J[3:]).T
    normal = axes[0] / np.linalg.norm(axes[0])
    for a in axes[1:]:
        revolute = abs(np.linalg.norm(a) - 1.0) <= 1e-9
        if not revolute or np.linalg.norm(np.cross(a, normal)) > PARALLEL_TOL:
            return None
    signs = np.sign(axes @ normal)
    k = int(np.argmax(np.abs(normal)))
    e = np.eye(3)[(k + 1) % 3]
    x = e - (e @ normal) * normal
    x /= np.linalg.norm(x)
    y = np.cross(normal, x)
    tip = arm.fk_pin(q).translation  # also leaves the joint placements in arm.data
    data = arm.data
    joints = [arm.T_base_world.act(data.oMi[j].translation) for j in range(1, arm.model.njoints)]
    first = joints[0]
    origin = first + ((tip - first) @ normal) * normal
    plane = Plane(origin, x, y, normal, signs, np.zeros((arm.dof, 2)))
    object.__setattr__(plane, "joint_origins", np.array([plane.to_2d(p) for p in joints]))
    return plane
