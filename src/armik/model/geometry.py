"""The geometry of a chain read from its Pinocchio model: joint axis lines, the plane of a
planar chain, and the measures the closed forms' classifiers use (angles between axes,
where lines meet).

Every joint's axis is a line (point, unit direction) in the base frame at q = 0. Each
closed-form family classifies these lines in its own file (``armik.solvers.closed_form``);
``armik.tolerances`` holds the angle and distance within which axes are parallel or meet.

Plane coordinates (planar chains): from the plane's point nearest the base's origin, ``x``
and ``y`` the base's two axes other than the one nearest the normal, in their order,
projected onto the plane (``y`` then made square to ``x``), ``normal = x cross y``. On a
plane along two base axes (x-y, x-z, y-z) they are those base axes. A 2-vector target gives
the base coordinates along those two axes (``Plane.from_base``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik.tolerances import PARALLEL_TOL

if TYPE_CHECKING:
    from armik.model.arm_view import ArmView


@dataclass(frozen=True)
class Plane:
    """Plane of motion, in the arm's base frame (m): ``x`` and ``y`` the base axes across it
    in their order, from ``origin``, the plane's point nearest the base's origin."""

    origin: np.ndarray
    x: np.ndarray
    y: np.ndarray
    normal: np.ndarray
    signs: np.ndarray  # +1 where a joint axis is along the normal, -1 where opposite
    joint_origins: np.ndarray  # (dof, 2): each joint's axis, in plane coordinates

    def to_3d(self, xy: np.ndarray) -> np.ndarray:
        return self.origin + xy[0] * self.x + xy[1] * self.y

    def from_base(self, xy) -> tuple[np.ndarray, np.ndarray]:
        """(the plane's point, its plane coordinates) whose base coordinates across the
        plane are ``xy``: the base's two axes other than the one nearest the normal, in
        their order (x, y on a plane along the base's x-y), the third read off the plane.
        On a plane along two base axes these are the plane coordinates themselves."""
        k = int(np.argmax(np.abs(self.normal)))
        i, j = (m for m in range(3) if m != k)
        n = self.normal
        if n[i] == 0.0 and n[j] == 0.0:  # along two base axes: (x, y) are its own coordinates
            return self.to_3d(xy), xy
        p = np.zeros(3)
        p[i], p[j] = xy[0], xy[1]
        p[k] = (n @ self.origin - n[i] * p[i] - n[j] * p[j]) / n[k]
        return p, self.to_2d(p)

    def axes_words(self, names: list[str] | None = None) -> str:
        """The joints' axis as the URDF turns them (the first joint's direction, not the
        normal the plane's coordinates chose), naming any joint that turns the other way."""
        axis = [round(float(v), 6) + 0.0 for v in self.normal * self.signs[0]]
        other = [k for k, s in enumerate(self.signs) if s != self.signs[0]]
        if not other:
            return f"all axes along {axis}"
        which = [names[k] if names else f"joint {k + 1}" for k in other]
        return f"axes along {axis} ({', '.join(which)} about the opposite direction)"

    def to_2d(self, p: np.ndarray) -> np.ndarray:
        d = p - self.origin
        return np.array([d @ self.x, d @ self.y])

    def height(self, p: np.ndarray) -> float:
        """Distance of ``p`` from the plane along the normal (m)."""
        return float((p - self.origin) @ self.normal)


def find_plane(arm: ArmView) -> Plane | None:
    if np.any(arm.prismatic) or arm.mimics:
        return None
    q = arm.to_pin(arm.middle)
    J = pin.computeFrameJacobian(arm.model, arm.data, q, arm.tip_frame_id, pin.LOCAL_WORLD_ALIGNED)
    J = J.reshape(6, arm.model.nv)  # Pinocchio returns shape (6,) for a 1-DOF model
    R = arm.T_base_world.rotation
    axes = (R @ J[3:]).T
    normal = axes[0] / np.linalg.norm(axes[0])
    for a in axes[1:]:
        revolute = abs(np.linalg.norm(a) - 1.0) <= 1e-9
        if not revolute or np.linalg.norm(np.cross(a, normal)) > PARALLEL_TOL:
            return None
    # the plane's coordinates are the base frame's two axes across the normal, in their
    # order ((x, y) for a plane along the base's x-y, (x, z), (y, z)), from the point of
    # the plane nearest the base's origin: a 2-vector target is in the base frame
    k = int(np.argmax(np.abs(normal)))
    i, j = (m for m in range(3) if m != k)
    x = np.eye(3)[i] - normal[i] * normal
    x /= np.linalg.norm(x)
    y = np.eye(3)[j] - normal[j] * normal - (np.eye(3)[j] @ x) * x
    y /= np.linalg.norm(y)
    normal = np.cross(x, y)  # (x, y, normal) right-handed, whichever way the axes point
    signs = np.sign(axes @ normal)
    tip = arm.fk_pin(q).translation  # also leaves the joint placements in arm.data
    data = arm.data
    joints = [arm.T_base_world.act(data.oMi[j].translation) for j in range(1, arm.model.njoints)]
    origin = (tip @ normal) * normal
    plane = Plane(origin, x, y, normal, signs, np.zeros((arm.dof, 2)))
    object.__setattr__(plane, "joint_origins", np.array([plane.to_2d(p) for p in joints]))
    return plane


# -- axis lines and the 6R classes ------------------------------------------------------


@dataclass(frozen=True)
class Axes:
    """Each joint's axis line at q = 0, in the base frame, and the tip pose at q = 0.

    ``points[i]`` is joint i's origin (a point on its axis), ``directions[i]`` its unit
    axis (signed as the joint turns; zero for a prismatic joint, whose line is its origin).
    """

    points: np.ndarray  # (dof, 3) m
    directions: np.ndarray  # (dof, 3)
    revolute: np.ndarray  # (dof,) bool
    tip_position: np.ndarray  # (3,) m
    tip_rotation: np.ndarray  # (3, 3)


def axis_lines(arm: ArmView) -> Axes:
    """The joint axis lines of ``arm`` at q = 0, read from the Pinocchio model."""
    q = arm.to_pin(np.zeros(arm.dof))
    T_tip = arm.fk_pin(q)  # leaves the joint placements in arm.data
    J = pin.computeJointJacobians(arm.model, arm.data, q)  # WORLD: columns are world axes
    J = J.reshape(6, arm.model.nv)  # Pinocchio returns shape (6,) for a 1-DOF model
    R = arm.T_base_world.rotation
    points, dirs = [], []
    for j in range(1, arm.model.njoints):
        points.append(arm.T_base_world.act(arm.data.oMi[j].translation))
        col = arm.model.joints[j].idx_v
        w = R @ J[3:, col]
        dirs.append(w / np.linalg.norm(w) if np.linalg.norm(w) > 0.5 else np.zeros(3))
    revolute = np.array([np.linalg.norm(d) > 0.5 for d in dirs]) & ~np.asarray(arm.prismatic)
    return Axes(
        np.array(points), np.array(dirs), revolute, T_tip.translation.copy(), T_tip.rotation.copy()
    )


def angle_between(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two axis lines' directions (rad, 0 for parallel or anti-parallel)."""
    return math.atan2(float(np.linalg.norm(np.cross(a, b))), abs(float(a @ b)))


def meeting_point(points: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, float]:
    """The point nearest (least squares) to a set of non-parallel lines, and the largest
    distance from it to one of them (m)."""
    A = np.zeros((3, 3))
    b = np.zeros(3)
    for p, d in zip(points, directions):
        P = np.eye(3) - np.outer(d, d)
        A += P
        b += P @ p
    x = np.linalg.lstsq(A, b, rcond=None)[0]
    miss = max(
        float(np.linalg.norm((np.eye(3) - np.outer(d, d)) @ (x - p)))
        for p, d in zip(points, directions)
    )
    return x, miss


def line_distance(p1, d1, p2, d2) -> float:
    """Distance between two lines (m)."""
    n = np.cross(d1, d2)
    if np.linalg.norm(n) < 1e-12:
        return float(np.linalg.norm(np.cross(p2 - p1, d1)))
    return abs(float((p2 - p1) @ n)) / float(np.linalg.norm(n))


def fmt(x: float) -> str:
    """A measured number for a reason text."""
    return f"{x:.3g}"
