"""The geometry of a chain read from its Pinocchio model: joint axis lines and the classes
of arms that have a closed-form IK.

Every joint's axis is a line (point, unit direction) in the base frame at q = 0. From these
lines the chain is classified:

- ``planar``: every joint revolute, all axes parallel (the plane of motion, ``Plane``);
- ``spherical_wrist``: 6 revolute joints whose last three axes meet in one point, with
  axes 2 and 3 parallel or axes 1 and 2 meeting (the closed form of ``ik/spherical.py``);
- ``three_parallel``: 6 revolute joints with axes 2, 3, 4 parallel and axes 5, 6 meeting
  (the Universal Robots family, ``ik/three_parallel.py``).

Tolerances: two axes are parallel when the angle between them is below ``ANGLE_TOL``; lines
meet when they pass within ``DISTANCE_TOL`` of one point. An arm that misses by more is
refused with the measured angle or distance, so a near miss never gets a closed form that
is only approximately right.

Plane coordinates (planar chains): origin on the first joint's axis at the tip's
height, ``normal`` along the first joint's axis, ``x`` the projection of the base axis that
follows the normal's largest component (z -> x, x -> y, y -> z), ``y = normal x x``. For an
arm turning about the base z axis the plane's (x, y) are the base frame's (x, y).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

if TYPE_CHECKING:
    from .arm import Arm

PARALLEL_TOL = 1e-9  # planar chains
ANGLE_TOL = 1e-9  # rad: axes closer than this to parallel are parallel
DISTANCE_TOL = 1e-9  # m: lines closer than this to one point meet there


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
    J = J.reshape(6, arm.model.nv)  # Pinocchio returns shape (6,) for a 1-DOF model
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


def axis_lines(arm: Arm) -> Axes:
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


@dataclass(frozen=True)
class Chain6R:
    """A 6R chain in product-of-exponentials form for the subproblem solvers.

    With R_i = rot(h_i, q_i) and R_0i = R_1 ... R_i:
    p_tip = p[0] + R_01 p[1] + R_02 p[2] + ... + R_06 p[6],  R_tip = R_06 R_tip0.
    ``h``: (6, 3) unit axes at q = 0 in the base frame; ``p``: (7, 3) vectors between the
    chosen points on consecutive axes (the first from the base origin, the last to the tip).
    """

    kind: str  # "spherical_wrist" or "three_parallel"
    variant: str  # for the spherical wrist: "parallel_23" or "meeting_12"
    h: np.ndarray
    p: np.ndarray
    R_tip0: np.ndarray
    description: str


def _chain(kind: str, variant: str, ax: Axes, points: list[np.ndarray], text: str) -> Chain6R:
    p = np.empty((7, 3))
    p[0] = points[0]
    for i in range(1, 6):
        p[i] = points[i] - points[i - 1]
    p[6] = ax.tip_position - points[5]
    h = np.ascontiguousarray(ax.directions)
    return Chain6R(kind, variant, h, p, np.ascontiguousarray(ax.tip_rotation), text)


def _common_6r(arm: Arm) -> str | None:
    if arm.dof != 6:
        return f"the chain has {arm.dof} joints, this class needs 6"
    if np.any(arm.prismatic):
        names = [n for n, p in zip(arm.joint_names, arm.prismatic) if p]
        return f"joint {names[0]!r} is prismatic, this class needs 6 revolute joints"
    return None


def _fmt(x: float) -> str:
    return f"{x:.3g}"


def spherical_wrist(arm: Arm, ax: Axes | None = None) -> Chain6R | str:
    """The 6R spherical-wrist geometry of ``arm``, or the reason it is not one."""
    why = _common_6r(arm)
    if why:
        return why
    return spherical_wrist_axes(ax or axis_lines(arm))


def spherical_wrist_axes(ax: Axes) -> Chain6R | str:
    """The spherical-wrist geometry of six revolute axis lines (``spherical_wrist`` without
    the arm: for chains built from part of an arm), or the reason it is not one."""
    P, H = ax.points, ax.directions
    for i, j in ((3, 4), (4, 5)):
        ang = angle_between(H[i], H[j])
        if ang < ANGLE_TOL:
            return f"axes {i + 1} and {j + 1} are parallel, so the last three do not form a wrist"
    w, miss = meeting_point(P[3:], H[3:])
    if miss > DISTANCE_TOL:
        return (
            f"the last three axes do not meet in one point: they miss by {_fmt(miss)} m "
            f"(tolerance {DISTANCE_TOL:g} m)"
        )
    a23 = angle_between(H[1], H[2])
    a12 = angle_between(H[0], H[1])
    if a12 < ANGLE_TOL:
        return "axes 1 and 2 are parallel; the closed form needs them to cross"
    if a23 < ANGLE_TOL:
        text = f"spherical wrist at {np.round(w, 6).tolist()} m, axes 2 and 3 parallel"
        pts = [P[0], P[1], P[2], w, w, w]
        return _chain("spherical_wrist", "parallel_23", ax, pts, text)
    c12, d12 = meeting_point(P[:2], H[:2])
    if d12 <= DISTANCE_TOL:
        text = f"spherical wrist at {np.round(w, 6).tolist()} m, axes 1 and 2 meet"
        pts = [c12, c12, P[2], w, w, w]
        return _chain("spherical_wrist", "meeting_12", ax, pts, text)
    return (
        "the last three axes meet in a point, but axes 2 and 3 are not parallel (angle "
        f"{_fmt(a23)} rad) and axes 1 and 2 do not meet (they miss by {_fmt(d12)} m): "
        "no closed form here for that case"
    )


def three_parallel(arm: Arm, ax: Axes | None = None) -> Chain6R | str:
    """The geometry of a 6R arm with axes 2, 3, 4 parallel (the UR family), or the reason
    it is not one."""
    why = _common_6r(arm)
    if why:
        return why
    ax = ax or axis_lines(arm)
    P, H = ax.points, ax.directions
    for i, j in ((1, 2), (1, 3)):
        ang = angle_between(H[i], H[j])
        if ang > ANGLE_TOL:
            return (
                f"axes 2, 3, 4 are not parallel: axes {i + 1} and {j + 1} are "
                f"{_fmt(ang)} rad apart (tolerance {ANGLE_TOL:g} rad)"
            )
    if angle_between(H[0], H[1]) < ANGLE_TOL:
        return "axis 1 is parallel to axes 2, 3, 4"
    if angle_between(H[4], H[1]) < ANGLE_TOL:
        return "axis 5 is parallel to axes 2, 3, 4"
    if angle_between(H[4], H[5]) < ANGLE_TOL:
        return "axes 5 and 6 are parallel"
    c56, d56 = meeting_point(P[4:], H[4:])
    if d56 > DISTANCE_TOL:
        return (
            f"axes 5 and 6 do not meet: they miss by {_fmt(d56)} m (tolerance "
            f"{DISTANCE_TOL:g} m); the closed form needs them to"
        )
    text = f"axes 2, 3, 4 parallel along {np.round(H[1], 6).tolist()}, axes 5 and 6 meet"
    pts = [P[0], P[1], P[2], P[3], c56, c56]
    return _chain("three_parallel", "", ax, pts, text)


CLASSES = ("planar", "spherical_wrist", "three_parallel")


def _not_planar(arm: Arm, ax: Axes) -> str:
    """Why the chain is not planar, with the measured angle."""
    names = [n for n, p in zip(arm.joint_names, arm.prismatic) if p]
    if names:
        return f"joint {names[0]!r} is prismatic"
    angles = [angle_between(ax.directions[0], d) for d in ax.directions[1:]]
    i = int(np.argmax(angles))
    return f"axes 1 and {i + 2} are {_fmt(angles[i])} rad apart (tolerance {PARALLEL_TOL:g} rad)"


@dataclass(frozen=True)
class Swept:
    """A 7R arm read as joints 6 to 1 from the tip (a 6R chain) and joint 7's axis line in
    the tip frame at q = 0."""

    geo: Chain6R
    variant: int  # spherical.kernel's: 0 axes 2, 3 parallel, 1 axes 1, 2 meeting
    c: np.ndarray  # a point on joint 7's axis (tip frame at q = 0), m
    u: np.ndarray  # joint 7's unit axis (tip frame)

    @property
    def description(self) -> str:
        return f"joint 7 held, joints 6 to 1 read from the tip: {self.geo.description}"


def swept_7r(arm: Arm, ax: Axes | None = None) -> Swept | str:
    """The geometry ``ik.swept`` sweeps over (see there), or the reason this 7R arm is not
    in the class: joint 7 held, joints 6 to 1 read from the tip form a spherical wrist."""
    if arm.dof != 7:
        return f"the chain has {arm.dof} joints, this class needs 7"
    if np.any(arm.prismatic):
        return "the chain has a prismatic joint, this class needs 7 revolute joints"
    ax = ax or axis_lines(arm)
    Rt = ax.tip_rotation.T
    t = ax.tip_position
    order = (5, 4, 3, 2, 1, 0)  # joints 6 to 1
    reversed_axes = Axes(
        np.array([Rt @ (ax.points[j] - t) for j in order]),
        np.array([-(Rt @ ax.directions[j]) for j in order]),
        np.ones(6, dtype=bool),
        -(Rt @ t),
        Rt.copy(),
    )
    geo = spherical_wrist_axes(reversed_axes)
    if isinstance(geo, str):
        return f"with joint 7 held, joints 6 to 1 from the tip are not a spherical wrist: {geo}"
    variant = 0 if geo.variant == "parallel_23" else 1
    return Swept(geo, variant, Rt @ (ax.points[6] - t), Rt @ ax.directions[6])


def classify(arm: Arm) -> dict[str, object]:
    """Each class name -> its geometry (``Plane`` or ``Chain6R``) or the reason it does not
    apply (a string)."""
    out: dict[str, object] = {}
    ax = axis_lines(arm)
    out["planar"] = arm.plane if arm.plane is not None else _not_planar(arm, ax)
    if arm.dof != 6 or np.any(arm.prismatic):
        out["spherical_wrist"] = out["three_parallel"] = _common_6r(arm)
    else:
        out["spherical_wrist"] = spherical_wrist(arm, ax)
        out["three_parallel"] = three_parallel(arm, ax)
    out["swept_7r"] = swept_7r(arm, ax)
    return out
