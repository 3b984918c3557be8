"""What the arm is drawn with: parts (a mesh fixed to one joint of the chain) and their poses
for a configuration, in the arm's base frame."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

if TYPE_CHECKING:
    import trimesh

    from armik.model.arm_model import ArmModel


@dataclass(frozen=True, eq=False)
class Part:
    """One rigid piece: ``mesh`` (m, in its own frame) placed by ``placement`` (4x4) in the
    frame of joint ``joint`` of the arm's Pinocchio model (0: the model's world)."""

    joint: int
    placement: np.ndarray
    mesh: trimesh.Trimesh
    link: str  # the URDF link it belongs to, or what the stick figure draws

    @cached_property
    def hull(self) -> trimesh.Trimesh:
        """The mesh's convex hull: a ghost's outline at a fraction of the mesh's size."""
        return self.mesh.convex_hull


@dataclass(frozen=True, eq=False)
class Body:
    """The parts of an arm. ``kind``: ``"meshes"`` (the URDF's visuals) or ``"stick"`` (links
    as rods, joints as balls, joint axes as coloured bars); ``note`` says why it is a stick
    figure ("" for meshes)."""

    parts: tuple[Part, ...]
    kind: str
    note: str = ""

    def poses(self, arm: ArmModel, q: np.ndarray) -> np.ndarray:
        """(len(parts), 4, 4): each part's pose in the base frame for joints ``q`` (rad, m)."""
        return joint_poses(arm, q)[[p.joint for p in self.parts]] @ self._placements

    @property
    def _placements(self) -> np.ndarray:
        cached = self.__dict__.get("_stack")
        if cached is None:
            cached = np.array([p.placement for p in self.parts]).reshape(-1, 4, 4)
            object.__setattr__(self, "_stack", cached)
        return cached


def joint_poses(arm: ArmModel, q: np.ndarray) -> np.ndarray:
    """(njoints, 4, 4): the frame of every joint of ``arm.model`` in the base frame for ``q``
    (rad, m); index 0 is the model's world."""
    d = arm.data
    pin.forwardKinematics(arm.model, d, arm.to_pin(arm.check_q(q)))
    T_base_world = arm.T_base_world.homogeneous
    return np.array([T_base_world @ d.oMi[j].homogeneous for j in range(arm.model.njoints)])
