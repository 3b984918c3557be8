"""A body in a viser scene: one frame per part, posed for a configuration, drawn solid (the
meshes' own colours), red (a failed answer) or as a translucent ghost of one colour."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik.view.body import Body

if TYPE_CHECKING:
    import viser

FAILED = (230, 40, 40)


def wxyz_position(T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A 4x4 pose as viser's (w, x, y, z) quaternion and position (m)."""
    x, y, z, w = pin.Quaternion(np.ascontiguousarray(T[:3, :3])).coeffs()
    return np.array([w, x, y, z]), np.array(T[:3, 3])


def pose_of(wxyz, position) -> pin.SE3:
    """viser's (w, x, y, z) quaternion and position (m) as a pose (the gizmo's target)."""
    w, x, y, z = (float(v) for v in wxyz)
    R = pin.Quaternion(w, x, y, z).normalized().matrix()
    return pin.SE3(R, np.array(position, dtype=float))


class BodyNodes:
    """``body`` under the scene node ``prefix``. ``ghost``: an (r, g, b) colour drawn at
    ``opacity``, from each part's convex hull (a ghost's outline is what one compares, and
    hulls are a fraction of a mesh's size); None: the parts as they are."""

    def __init__(
        self,
        scene: viser.SceneApi,
        prefix: str,
        body: Body,
        *,
        ghost: tuple[int, int, int] | None = None,
        opacity: float = 0.3,
    ) -> None:
        self._scene = scene
        self._body = body
        self.prefix = prefix
        self._frames: list[viser.FrameHandle] = []
        self._solid: list[viser.SceneNodeHandle] = []
        self._failed: list[viser.MeshHandle] = []  # red copies, made at the first failure
        for i, part in enumerate(body.parts):
            frame = scene.add_frame(f"{prefix}/part{i}", show_axes=False)
            self._frames.append(frame)
            if ghost is None:
                node: viser.SceneNodeHandle = scene.add_mesh_trimesh(
                    f"{prefix}/part{i}/solid", part.mesh
                )
            else:
                hull = part.hull if body.kind == "meshes" else part.mesh
                node = scene.add_mesh_simple(
                    f"{prefix}/part{i}/ghost",
                    np.asarray(hull.vertices, np.float32),
                    np.asarray(hull.faces, np.uint32),
                    color=ghost,
                    opacity=opacity,
                    cast_shadow=False,
                    receive_shadow=False,
                )
            self._solid.append(node)
        self._visible = True

    def pose(self, poses: np.ndarray) -> None:
        """Place every part: ``poses`` (n, 4, 4) from ``Body.poses``."""
        for frame, T in zip(self._frames, poses):
            frame.wxyz, frame.position = wxyz_position(T)

    def tint(self, color: tuple[int, int, int]) -> None:
        """Recolour a ghost (the parts' solid colours stay as the meshes have them)."""
        for node in self._solid:
            if hasattr(node, "opacity"):  # a ghost's part, not a mesh in its own colours
                node.color = color  # type: ignore[attr-defined]

    def mark_failed(self, failed: bool) -> None:
        """Draw the body red (``failed``) or in its own colours."""
        if failed and not self._failed:
            for i, part in enumerate(self._body.parts):
                self._failed.append(
                    self._scene.add_mesh_simple(
                        f"{self.prefix}/part{i}/failed",
                        np.asarray(part.mesh.vertices, np.float32),
                        np.asarray(part.mesh.faces, np.uint32),
                        color=FAILED,
                        visible=False,
                    )
                )
        for solid, red in zip(self._solid, self._failed):
            solid.visible = not failed
            red.visible = failed

    @property
    def visible(self) -> bool:
        return self._visible

    @visible.setter
    def visible(self, value: bool) -> None:
        self._visible = bool(value)
        for frame in self._frames:
            frame.visible = self._visible

    def remove(self) -> None:
        for frame in self._frames:
            frame.remove()
        self._frames.clear()
