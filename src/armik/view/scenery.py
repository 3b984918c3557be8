"""What the viewer draws beside the arm: obstacles and reach maps, in the base frame (m)."""

from __future__ import annotations

import numpy as np
import trimesh

from armik.constraints.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Shape, Sphere
from armik.view.nodes import wxyz_position

OBSTACLE = (255, 150, 60)
REACHED, UNREACHED = (40, 170, 70), (220, 50, 50)


def reach_colors(fraction: np.ndarray) -> np.ndarray:
    """(n, 3) uint8: red at 0 through yellow to green at 1; grey where nothing was reached."""
    f = np.clip(np.asarray(fraction, float), 0, 1)[:, None]
    low, mid, high = np.array(UNREACHED), np.array([230, 200, 40]), np.array(REACHED)
    rgb = np.where(f < 0.5, low + (mid - low) * 2 * f, mid + (high - mid) * (2 * f - 1))
    rgb[f[:, 0] == 0] = (160, 160, 160)
    return rgb.round().astype(np.uint8)


def draw_reach(scene, reach_map, unreached: bool) -> int:
    """A reach map's voxels as one point cloud at ``/reach``; returns the points drawn."""
    X, Y, Z = np.meshgrid(reach_map.xs, reach_map.ys, reach_map.zs, indexing="ij")
    f = reach_map.fraction
    keep = np.isfinite(f) & ((f > 0) | unreached)
    points = np.stack([X[keep], Y[keep], Z[keep]], axis=1).astype(np.float32)
    scene.add_point_cloud(
        "/reach", points, reach_colors(f[keep]), point_size=0.2 * reach_map.resolution,
        point_shape="circle",
    )  # fmt: skip
    return len(points)


def draw_obstacle(scene, name: str, shape: Shape) -> None:
    """One obstacle in the scene, translucent, at its placement in the base frame."""
    wxyz, position = wxyz_position(shape.T)
    if isinstance(shape, Box):
        scene.add_box(name, color=OBSTACLE, dimensions=shape.size, opacity=0.6,
                      wxyz=wxyz, position=position)  # fmt: skip
    elif isinstance(shape, Sphere):
        scene.add_icosphere(name, radius=shape.radius, color=OBSTACLE, opacity=0.6,
                            position=shape.center)  # fmt: skip
    else:
        if isinstance(shape, Cylinder):
            mesh = trimesh.creation.cylinder(radius=shape.radius, height=shape.length)
        elif isinstance(shape, Capsule):
            mesh = trimesh.creation.capsule(radius=shape.radius, height=shape.length)
        elif isinstance(shape, HalfSpace):  # a wide slab under its surface
            n = np.asarray(shape.normal, dtype=float)
            mesh = trimesh.creation.box((4.0, 4.0, 0.02))
            z = np.array([0.0, 0.0, 1.0])
            T = trimesh.geometry.align_vectors(z, n)
            T[:3, 3] = n * (shape.offset - 0.01)
            wxyz, position = wxyz_position(T)
        else:
            assert isinstance(shape, Mesh)
            # the hull of the vertices kept when it was made: what its collisions measure
            mesh = trimesh.convex.convex_hull(np.array(shape.vertices))
        scene.add_mesh_simple(name, mesh.vertices, mesh.faces, color=OBSTACLE, opacity=0.6,
                              wxyz=wxyz, position=position)  # fmt: skip
