"""Every link of a robot of several tips (``armik.Arms``) once, each from a chain that places
it where the robot does, and the pairs its collision checks measure (``armik.arms_collision``).

Each chain's collision geometry (``armik.constraints.collision.arm_geometry``) holds every
link of the URDF, those off the chain frozen where the chain was cut. A link is placed by
its nearest joint above it that some chain moves; every chain that holds that joint places
it as the robot does, the others where they froze it. So each link is taken from the chain
whose model hangs it on the deepest joint (the first such chain; a link below a mimic joint
that a chain moves by its driver, ``followed``, from that chain). Two links are a pair where
some chain places both as the robot does and counts them a self-collision pair (not rigidly
joined, not adjacent, not disabled by its SRDF); two links that no one chain places both
(each on a joint of its own chain: two arms) are a pair unless an SRDF disables it. Every
link a joint moves is paired with every obstacle.
"""

from __future__ import annotations

import math
from typing import Any

import coal
import numpy as np
import pinocchio as pin

from armik.constraints.collision import (
    UNBOUNDED,
    ArmGeometry,
    arm_geometry,
    check_fixed,
    obstacle_name,
)
from armik.constraints.shapes import Shape
from armik.model.arm_model import ArmModel


class Links:
    """The objects of ``chains`` (each an ``ArmModel`` of one URDF) once each and their
    pairs (the module's rule); ``obstacles`` as shapes in the base frame."""

    def __init__(
        self, chains: list[ArmModel], obstacles: tuple[Shape, ...], self_collision: bool
    ) -> None:
        self.geometry: list[ArmGeometry] = [arm_geometry(arm) for arm in chains]
        placed, followed, right = _placing(chains, self.geometry)
        owner = {name: followed.get(name, int(np.argmax(deeps))) for name, deeps in placed.items()}
        self.objects: list[tuple[int, int]] = []  # (chain, its object)
        key: dict[str, int] = {}
        for c, g in enumerate(self.geometry):
            for i, o in enumerate(g.model.geometryObjects):
                if owner[o.name] == c and o.name not in key:
                    key[o.name] = len(self.objects)
                    self.objects.append((c, i))
        pairs: set[tuple[int, int]] = set()
        if self_collision:
            for c, g in enumerate(self.geometry):
                names = [o.name for o in g.model.geometryObjects]
                for a, b in g.self_pairs:
                    if c in right[names[a]] and c in right[names[b]]:
                        pairs.add(tuple(sorted((key[names[a]], key[names[b]]))))  # type: ignore[arg-type]
            disabled = frozenset().union(*(arm.disabled_pairs for arm in chains))
            objects = [self._object(k) for k in range(len(self.objects))]
            for ka in range(len(self.objects)):
                for kb in range(ka + 1, len(self.objects)):
                    na, nb = objects[ka].name, objects[kb].name
                    if right[na] & right[nb]:
                        continue  # one chain places both (a link fixed to the base, every
                        # chain): that chain's own pairs said
                    la, lb = self.link(ka), self.link(kb)
                    if tuple(sorted((la, lb))) not in disabled:
                        pairs.add((ka, kb))
        self.names = [self.link(k) for k in range(len(self.objects))]
        self.self_pairs = sorted(pairs)
        self.pair_a = np.array([a for a, _ in self.self_pairs], dtype=np.intp)
        self.pair_b = np.array([b for _, b in self.self_pairs], dtype=np.intp)
        self.joints = [int(self._object(k).parentJoint) for k in range(len(self.objects))]
        # moving: on a joint of its chain, or turned by a mimic joint that chain moves by its
        # driver (placed on the whole model) even where the cut model hangs it on the base
        turned = {key[name] for name in followed}
        self.moving = np.array(
            [k for k, j in enumerate(self.joints) if j != 0 or k in turned], dtype=np.intp
        )
        self.geoms = [self._object(k).geometry for k in range(len(self.objects))]
        self.radius = np.array([_radius(g) for g in self.geoms])
        self.centre = np.array([g.aabb_center for g in self.geoms]).reshape(-1, 3)
        self.shapes = obstacles
        world = chains[0].T_world_base
        self.obstacles = [
            (s.geometry(), coal.Transform3s(world * s.placement())) for s in obstacles
        ]
        self.obstacle_radius = np.array([_radius(g) for g, _ in self.obstacles])
        centres = [
            T.transform(g.aabb_center) if _radius(g) < UNBOUNDED else np.zeros(3)
            for g, T in self.obstacles
        ]
        self.obstacle_centre = np.array(centres).reshape(-1, 3)
        for k in np.setdiff1d(np.arange(len(self.objects)), self.moving).tolist():
            c, i = self.objects[k]  # no joint moves it: an obstacle it sinks into is refused
            for s, shape in enumerate(obstacles):
                world = chains[c].T_world_base * shape.placement()
                obj = pin.GeometryObject(obstacle_name(s, shape), 0, 0, world, shape.geometry())
                check_fixed(chains[c], self.geometry[c], i, obj, shape, s)

    def _object(self, k: int) -> Any:
        c, i = self.objects[k]
        return self.geometry[c].model.geometryObjects[i]

    def link(self, k: int) -> str:
        """The link of object ``k``."""
        c, i = self.objects[k]
        return self.geometry[c].links[i]


def _placing(chains: list[ArmModel], geometry: list[ArmGeometry]) -> tuple[dict, dict, dict]:
    """(placed, followed, right) of the objects of ``chains`` (their ``geometry``), by
    object name: the depth in the URDF's tree of the joint each chain hangs it on (-1: not
    in that chain's geometry), the chain that moves it below a mimic joint by its driver,
    and the chains that place it as the robot does (the deepest, or that one)."""
    full = chains[0].chain.full  # the URDF's model, every chain cut from it
    depth = [0] * full.njoints
    for j in range(1, full.njoints):
        depth[j] = depth[full.parents[j]] + 1
    placed: dict[str, list[int]] = {}
    followed: dict[str, int] = {}
    for c, (arm, g) in enumerate(zip(chains, geometry)):
        moved = {i for i, _, _ in g.followed}
        for i, o in enumerate(g.model.geometryObjects):
            joint = arm.model.names[o.parentJoint]
            deep = depth[full.getJointId(joint)] if o.parentJoint else 0
            placed.setdefault(o.name, [-1] * len(chains))[c] = deep
            if i in moved:
                followed.setdefault(o.name, c)
    right = {name: {c for c, d in enumerate(ds) if d == max(ds)} for name, ds in placed.items()}
    for name, c in followed.items():
        right[name] = {c}
    return placed, followed, right


def moved_elsewhere(chains: list[ArmModel]) -> list[frozenset[str]]:
    """For each of ``chains`` (each an ``ArmModel`` of one URDF, sharing no joint), the
    names of its collision objects that another chain places as the robot does and it
    does not (its cut holds them still, or carries them on its own joints, where the
    robot moves them with another chain's)."""
    geometry = [arm_geometry(arm) for arm in chains]
    right = _placing(chains, geometry)[2]
    return [
        frozenset(o.name for o in g.model.geometryObjects if c not in right[o.name])
        for c, g in enumerate(geometry)
    ]


def _radius(geometry: coal.CollisionGeometry) -> float:
    """The radius of a sphere about ``aabb_center`` holding the shape (``UNBOUNDED``
    without one)."""
    geometry.computeLocalAABB()
    r = float(geometry.aabb_radius)
    return r if math.isfinite(r) else UNBOUNDED
