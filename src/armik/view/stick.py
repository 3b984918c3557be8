"""The stick figure: the chain drawn from its kinematics alone (rods between joint origins,
a ball at every joint, a bar along every joint axis), for arms whose URDF has no meshes or
whose meshes cannot be found."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from armik.kernel.chain import PRISMATIC
from armik.model.arm_model import ArmModel
from armik.view.body import Body, Part, joint_poses

ROD = (175, 180, 190, 255)
BALL = (70, 75, 90, 255)
REVOLUTE_AXIS = (255, 140, 0, 255)  # orange: turns about this line
PRISMATIC_AXIS = (0, 150, 255, 255)  # blue: slides along this line


@dataclass(frozen=True, eq=False)
class Skeleton:
    """The chain for one configuration, in the base frame (m): ``points`` the base origin,
    every joint origin and the tip, in chain order; ``axes`` (N, 3) the unit joint axes;
    ``prismatic`` (N,) which joints slide (N: the joints of ``arm.model``, mimic joints
    included)."""

    points: np.ndarray
    axes: np.ndarray
    prismatic: np.ndarray


def size(arm: ArmModel) -> float:
    """A length (m) to scale drawings of ``arm`` by: its reach bound, or the sum of its
    links where an unlimited prismatic joint leaves the bound infinite."""
    if math.isfinite(arm.reach):
        return max(arm.reach, 1e-3)
    m = arm.model
    links = sum(
        float(np.linalg.norm(m.jointPlacements[j].translation)) for j in range(1, m.njoints)
    )
    return max(links + float(np.linalg.norm(m.frames[arm.tip_frame_id].placement.translation)), 0.1)


def local_axes(arm: ArmModel) -> np.ndarray:
    """(N, 3): each joint's unit axis in its own frame, for every joint of ``arm.model``
    (mimic joints included: the kernel chain's axes, Pinocchio's motion subspaces)."""
    return arm.kernel_chain.chain.axis


def slides(arm: ArmModel) -> np.ndarray:
    """(N,) bool: which joints of ``arm.model`` are prismatic (mimic joints included)."""
    return arm.kernel_chain.chain.joint_kind == PRISMATIC


def skeleton(arm: ArmModel, q: np.ndarray) -> Skeleton:
    """The stick figure's points and axes for joints ``q`` (rad, m)."""
    poses = joint_poses(arm, q)
    tip = arm.fk(q).translation
    points = np.vstack([np.zeros(3), poses[1:, :3, 3], tip])
    axes = np.einsum("nij,nj->ni", poses[1:, :3, :3], local_axes(arm))
    return Skeleton(points=points, axes=axes, prismatic=slides(arm).copy())


def stick_body(arm: ArmModel, note: str) -> Body:
    """The stick figure as parts, sized by the arm (``size``)."""
    import trimesh

    s = size(arm)
    m = arm.model
    rod, ball, bar = 0.012 * s, 0.03 * s, 0.09 * s
    parts: list[Part] = []

    def add(joint: int, mesh: trimesh.Trimesh, color, what: str, placement=None) -> None:
        mesh.visual.face_colors = color  # type: ignore[union-attr]  # a new mesh's: ColorVisuals
        parts.append(Part(joint, np.eye(4) if placement is None else placement, mesh, what))

    def rod_between(joint: int, a: np.ndarray, b: np.ndarray, what: str) -> None:
        if np.linalg.norm(b - a) > 1e-6 * s:
            add(joint, trimesh.creation.cylinder(rod, segment=[a, b], sections=16), ROD, what)

    base = arm.T_world_base
    add(0, trimesh.creation.cylinder(3 * ball, 0.4 * ball, sections=32), BALL, "base",
        base.homogeneous)  # fmt: skip
    rod_between(0, base.translation, m.jointPlacements[1].translation, "base link")
    tip_frame = m.frames[arm.tip_frame_id]
    for j in range(1, m.njoints):
        name = m.names[j]
        children = [c for c in range(j + 1, m.njoints) if m.parents[c] == j]
        for c in children:
            rod_between(j, np.zeros(3), m.jointPlacements[c].translation, f"link after {name}")
        if tip_frame.parentJoint == j:
            rod_between(j, np.zeros(3), tip_frame.placement.translation, "link to the tip")
        add(j, trimesh.creation.icosphere(subdivisions=2, radius=ball), BALL, name)
        axis = local_axes(arm)[j - 1]
        slide = bool(slides(arm)[j - 1])
        color = PRISMATIC_AXIS if slide else REVOLUTE_AXIS
        width = 0.5 * rod if slide else 0.7 * rod
        add(j, trimesh.creation.cylinder(width, segment=[-bar * axis, bar * axis]), color,
            f"axis of {name}")  # fmt: skip
    return Body(parts=tuple(parts), kind="stick", note=note)
