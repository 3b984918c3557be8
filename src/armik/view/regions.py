"""Tolerance regions drawn as the tasks state them, in the base frame (m, rad).

- ``Pose(T, bounds)``: a translucent box about ``T``'s origin along ``T``'s axes, edges
  twice the translation bounds; and per bounded rotation component a fan in the target
  frame: the bound about x swings the y axis (in the y-z plane), about y the z axis, about
  z the x axis, through +- the bound (a whole disc where it is free).
- ``Position(p, bounds)``: the box about ``p`` along the base axes.
- ``Axis(axis, direction, within)``: a cone of half-angle ``within`` about ``direction``,
  its apex at the frame as shown, and the frame's axis now (green inside, red outside).
- ``LookAt(point, axis, within)``: the cone of half-angle ``within`` from the frame as
  shown to ``point`` (marked), and the frame's axis now.

A free axis (``inf``, or a weight of 0) is drawn ``FREE`` times the robot's size long, a
zero bound as a thin plate; an exact task has no region (its target frame is the gizmo's).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from armik.problem.tasks import Axis, LookAt, Pose, Position, Task
from armik.problem.tasks import cone as cones
from armik.view.nodes import wxyz_position

REGION = (70, 130, 255)
AXIS_COLORS = ((230, 60, 60), (60, 190, 60), (60, 100, 240))  # rotation about x, y, z
INSIDE, OUTSIDE = (40, 170, 70), (220, 50, 50)
FREE = 4.0  # a free axis's length, in robot sizes
THIN = 0.004  # a zero bound's thickness beside bounded axes, in robot sizes
SIDES = 48  # segments of a cone's rim or a fan's arc


@dataclass(frozen=True, eq=False)
class BoxRegion:
    """Translation bounds: a box centred at ``T`` (4x4), edges ``size`` (m) along its axes."""

    name: str
    T: np.ndarray
    size: np.ndarray


@dataclass(frozen=True, eq=False)
class FanRegion:
    """A rotation bound: about axis ``about`` (0, 1, 2: x, y, z) of ``T`` (4x4), through
    +- ``half_angle`` rad (pi: free), drawn ``radius`` m wide."""

    name: str
    T: np.ndarray
    about: int
    half_angle: float
    radius: float


@dataclass(frozen=True, eq=False)
class ConeRegion:
    """Directions within ``half_angle`` rad of ``direction`` (unit, base frame), drawn
    from ``apex`` (m) ``length`` m long; ``now``: the frame's axis at the configuration
    shown, ``inside`` whether it lies in the cone."""

    name: str
    apex: np.ndarray
    direction: np.ndarray
    half_angle: float
    length: float
    now: np.ndarray
    inside: bool


@dataclass(frozen=True, eq=False)
class PointMark:
    """A point a ``LookAt`` aims at (m, base frame)."""

    name: str
    position: np.ndarray


Region = BoxRegion | FanRegion | ConeRegion | PointMark


def task_regions(task: Task, T_frame: pin.SE3, scale: float, name: str) -> list[Region]:
    """What to draw for ``task`` (named under ``name``), its frame at ``T_frame`` (base
    frame) and the robot ``scale`` m across; [] for an exact task or one without a region
    drawing (``Relative``)."""
    if isinstance(task, Pose):
        free = np.where(task.weights == 0.0, math.inf, task.bounds)
        out: list[Region] = []
        box = _box_size(free[:3], scale)
        if box is not None:
            out.append(BoxRegion(f"{name}/box", task.T.homogeneous.copy(), box))
        for k in range(3):
            if free[3 + k] > 0.0:
                angle = min(float(free[3 + k]), math.pi)
                out.append(FanRegion(f"{name}/fan_r{'xyz'[k]}", task.T.homogeneous.copy(), k,
                                     angle, 0.15 * scale))  # fmt: skip
        return out
    if isinstance(task, Position):
        box = _box_size(task.bounds, scale)
        if box is None:
            return []
        T = np.eye(4)
        T[:3, 3] = task.p
        return [BoxRegion(f"{name}/box", T, box)]
    if isinstance(task, (Axis, LookAt)):
        apex = T_frame.translation.copy()
        now = T_frame.rotation @ task.axis
        if isinstance(task, Axis):
            direction, length, out = task.direction, 0.3 * scale, []
        else:
            sight = task.point - apex
            length = float(np.linalg.norm(sight))
            out = [PointMark(f"{name}/point", task.point.copy())]
            if length < 1e-9:  # at the point: any direction looks at it
                return out
            direction = sight / length
        inside = cones.angle(now, direction) <= task.within + 1e-9
        return [*out, ConeRegion(f"{name}/cone", apex, direction.copy(), task.within, length,
                                 now, inside)]  # fmt: skip
    return []


def _box_size(bounds: np.ndarray, scale: float) -> np.ndarray | None:
    """Edge lengths for translation ``bounds`` (m), or None when all are 0 (exact)."""
    if not (bounds > 0.0).any():
        return None
    edges = np.where(np.isinf(bounds), FREE * scale, 2.0 * bounds)
    return np.maximum(edges, THIN * scale)


def cone_mesh(region: ConeRegion) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces): the cone's side from its apex to its rim."""
    d = region.direction
    u = np.cross(d, (1.0, 0.0, 0.0) if abs(d[0]) < 0.9 else (0.0, 1.0, 0.0))
    u /= np.linalg.norm(u)
    v = np.cross(d, u)
    t = np.linspace(0.0, 2.0 * math.pi, SIDES, endpoint=False)
    a = region.half_angle
    rim = np.cos(a) * d + np.sin(a) * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)
    vertices = np.vstack([region.apex, region.apex + region.length * rim])
    k = np.arange(SIDES)
    faces = np.stack([np.zeros(SIDES, int), 1 + k, 1 + (k + 1) % SIDES], axis=1)
    return vertices.astype(np.float32), faces.astype(np.uint32)


def fan_mesh(region: FanRegion) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) in the base frame: the sector the swung axis sweeps."""
    R, centre = region.T[:3, :3], region.T[:3, 3]
    swung, towards = R[:, (region.about + 1) % 3], R[:, (region.about + 2) % 3]
    t = np.linspace(-region.half_angle, region.half_angle, SIDES + 1)
    arc = np.cos(t)[:, None] * swung + np.sin(t)[:, None] * towards
    vertices = np.vstack([centre, centre + region.radius * arc])
    k = np.arange(SIDES)
    faces = np.stack([np.zeros(SIDES, int), 1 + k, 2 + k], axis=1)
    return vertices.astype(np.float32), faces.astype(np.uint32)


def draw(scene, regions: list[Region], scale: float) -> list:
    """Add ``regions`` to ``scene``; returns the handles (``remove()`` each to clear)."""
    handles = []
    see_through = dict(opacity=0.25, side="double", cast_shadow=False, receive_shadow=False)
    add_mesh, add_line = scene.add_mesh_simple, scene.add_line_segments
    for r in regions:
        if isinstance(r, BoxRegion):
            wxyz, position = wxyz_position(r.T)
            box = scene.add_box(
                r.name, REGION, tuple(r.size), wxyz=wxyz, position=position, **see_through
            )
            handles.append(box)
        elif isinstance(r, FanRegion):
            handles.append(
                add_mesh(r.name, *fan_mesh(r), color=AXIS_COLORS[r.about], **see_through)
            )
        elif isinstance(r, PointMark):
            ball = scene.add_icosphere(r.name, 0.015 * scale, REGION, position=r.position)
            handles.append(ball)
        elif r.half_angle > 0.0:
            handles.append(add_mesh(r.name, *cone_mesh(r), color=REGION, **see_through))
        else:  # within 0: one direction, a line
            ray = np.array([[r.apex, r.apex + r.length * r.direction]], np.float32)
            handles.append(add_line(r.name, ray, REGION, thickness=0.004 * scale))
        if isinstance(r, ConeRegion):
            now = np.array([[r.apex, r.apex + r.length * r.now]], np.float32)
            color = INSIDE if r.inside else OUTSIDE
            handles.append(add_line(f"{r.name}_now", now, color, thickness=0.006 * scale))
    return handles
