"""Collisions: the arm's collision geometry, its self-collision pairs, obstacles, and the
distance the verdict measures.

The geometry is the URDF's ``<collision>`` elements, read by Pinocchio's
``buildGeomFromUrdfString`` onto the whole URDF's model and cut like the chain
(``pin.buildReducedModel`` with the geometry), every mesh replaced by its convex hull.
Self-collision pairs are the pairs of geometry objects on bodies that move relative to one
another, minus adjacent bodies (the two sides of one moving joint, links joined by fixed
joints being one body, a link a passive mimic joint moves a body of its own) and minus the
pairs an SRDF disables. Links that never move relative
to the base are checked against the obstacles once, when a ``Checker`` is built.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from itertools import combinations
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin

from armik.constraints import carried
from armik.constraints.bounds import ordered_bounds, ordered_bounds_many
from armik.constraints.shapes import Shape, check_obstacles, convex_hull, flag, margin_of, solid
from armik.constraints.srdf import Pair
from armik.errors import CollisionError
from armik.model import mimic_frames
from armik.model.arm_model import ArmModel
from armik.model.catalogue import erd_share
from armik.model.derived import Derived
from armik.model.reduce import reduce_model
from armik.tolerances import FIXED_OVERLAP_TOL


@dataclass(frozen=True)
class ArmGeometry:
    """The collision geometry of one arm's chain (on ``arm.model``) and its pairs."""

    model: pin.GeometryModel  # convex hulls for meshes
    links: tuple[str, ...]  # the link of each geometry object
    moving: tuple[bool, ...]  # whether it moves relative to the base
    candidates: tuple[tuple[int, int], ...]  # pairs that can touch (not adjacent, not rigid)
    self_pairs: tuple[tuple[int, int], ...]  # candidates minus the SRDF's disabled pairs
    # objects a mimic joint off the chain moves with its driver on it, placed by the whole
    # model at each q (``model.mimic_frames.followed_objects``): the cut model holds them still
    followed: tuple = ()
    held: tuple = ()  # each object's held joints where the chain carries it (``carried``)


def arm_geometry(arm: ArmModel) -> ArmGeometry:
    """The arm's collision geometry, built once . Raises
    ``CollisionError`` when the URDF has none or a mesh cannot be found."""
    return _GEOMETRY(arm)


def _build_geometry(arm: ArmModel) -> ArmGeometry:
    chain = arm.chain
    full = chain.full
    dirs = list(arm.package_dirs)
    if Path(arm.source).is_file():
        dirs.append(str(Path(arm.source).resolve().parent))
    share = erd_share()
    if share is not None:
        dirs.append(share)
    try:
        geom = pin.buildGeomFromUrdfString(full, arm.info.text, pin.COLLISION, package_dirs=dirs)
    except (ValueError, RuntimeError, OSError) as exc:
        raise CollisionError(
            f"the collision geometry of arm {arm.name!r} could not be read ({exc}); give the "
            "folders that hold its meshes' packages with armik.load(..., package_dirs=[...])",
            option="package_dirs",
        ) from None
    for name in arm.left_out:  # links another chain of a robot moves (``armik.arms_apart``)
        geom.removeGeometryObject(name)
    if geom.ngeoms == 0:
        raise CollisionError(
            f"arm {arm.name!r} has no <collision> geometry in its URDF, so collisions cannot "
            "be checked: add <collision> elements to its links, or solve without obstacles= "
            "and self_collision=",
            option="obstacles",
        )
    links = tuple(full.frames[o.parentFrame].name for o in geom.geometryObjects)
    followed = mimic_frames.followed_objects(arm, geom)
    joints = [o.parentJoint for o in geom.geometryObjects]
    body, parent = _bodies(arm, joints)
    held = carried.held_joints(arm, joints, body)
    if chain.locked_joints:
        _, geom = reduce_model(full, list(chain.locked_joints), chain.q_ref, geom)
    for o, link in zip(geom.geometryObjects, links):
        if isinstance(o.geometry, coal.BVHModelBase):
            mesh = f"the collision mesh {o.meshPath!r} of link {link!r} of arm {arm.name!r}"
            fix = "give that <collision> a mesh of a solid, or a <box>, in the URDF"
            solid(o.geometry, mesh, fix)
            o.geometry = convex_hull(o.geometry)
    bodies = [o.parentJoint for o in geom.geometryObjects]
    touching = {tuple(sorted((j.parent, j.child))) for j in arm.info.joints.values()}
    candidates = []
    for a, b in combinations(range(geom.ngeoms), 2):
        ja, jb = body[a], body[b]
        if ja == jb or parent[ja] == jb or parent[jb] == ja:
            continue  # rigidly joined, or the two sides of one joint
        if tuple(sorted((links[a], links[b]))) in touching:
            continue
        candidates.append((a, b))
    disabled = arm.disabled_pairs
    self_pairs = tuple(
        (a, b) for a, b in candidates if tuple(sorted((links[a], links[b]))) not in disabled
    )
    return ArmGeometry(
        model=geom,
        links=links,
        moving=tuple(j != 0 or i in {k for k, _, _ in followed} for i, j in enumerate(bodies)),
        candidates=tuple(candidates),
        self_pairs=self_pairs,
        followed=followed,
        held=held,
    )


_GEOMETRY = Derived("collision geometry", _build_geometry)


def _bodies(arm: ArmModel, joints: list[int]) -> tuple[list[int], dict[int, int]]:
    """The body of each object whose whole-model joint is in ``joints``: the joint that
    moves it there (its own, or the nearest above it that moves: one of the chain's, or a
    mimic joint off the chain that follows its driver, ``mimic_frames.followers``), 0 for
    the base's; and each body's parent body. A followed link is a body of its own, as it
    moves relative to the link it hangs from: welded to that link, a parallelogram's rod
    was paired as that link, its pairs with the links beside it never checked."""
    full = arm.chain.full
    held = set(arm.chain.locked_joints) - set(mimic_frames.followers(arm))

    def body(j: int) -> int:
        while j != 0 and j in held:
            j = full.parents[j]
        return j

    out = [body(j) for j in joints]
    return out, {b: body(full.parents[b]) if b else 0 for b in out}


def _unmoved(what: str, links) -> CollisionError:
    """The error for ``what`` (an arm, a robot) whose ``links`` with geometry never move."""
    return CollisionError(
        f"{what} has <collision> geometry only on links that never move relative to its base "
        f"({', '.join(dict.fromkeys(links))}), so collisions cannot be checked: add "
        "<collision> elements to the links its joints move, or solve without obstacles= "
        "and self_collision=",
        option="obstacles",
    )


def obstacle_name(i: int, shape: Shape) -> str:
    return f"obstacles[{i}] ({type(shape).__name__})"


class Checker:
    """The distances of one arm to one set of obstacles (and itself, with
    ``self_collision``): ``distance(q)`` is the smallest over every checked pair.

    Each of the arm's geometry objects has a bounding sphere and each obstacle a bounding
    box (a half space's reaches 2 ``FAR`` below its plane, and ``FAR`` past the base's
    origin where that is inside), so each pair has a lower bound on
    its signed distance (sphere to sphere, sphere to box); ``distance`` asks coal for the
    pairs in the order of their bounds and stops at the first bound beyond the smallest
    distance found: the same answer as asking for every pair, for a few of coal's calls
    (docs/collisions.md)."""

    def __init__(self, arm: ArmModel, obstacles: tuple[Shape, ...], self_collision: bool) -> None:
        g = arm_geometry(arm)
        if not any(g.moving):  # nothing a joint moves could be measured: every answer clear
            raise _unmoved(f"arm {arm.name!r}", g.links)
        model = g.model.copy()
        names = list(g.links)
        pairs = list(g.self_pairs) if self_collision else []
        n_self = len(pairs)
        boxes: list[tuple] = []  # per obstacle pair: the obstacle's bounding box
        for k, shape in enumerate(obstacles):
            placement = arm.T_world_base * shape.placement()
            obj = pin.GeometryObject(obstacle_name(k, shape), 0, 0, placement, shape.geometry())
            index = model.addGeometryObject(obj)
            names.append(obstacle_name(k, shape))
            first = len(pairs)
            for i, moving in enumerate(g.moving):
                if moving:
                    pairs.append((i, index))
                else:
                    check_fixed(arm, g, i, obj, shape, k)
            box = _box_of(obj.geometry, arm.T_base_world * placement)
            boxes.extend([box] * (len(pairs) - first))
        for a, b in pairs:
            model.addCollisionPair(pin.CollisionPair(a, b))
        self.arm = arm
        self.model = model
        self.pair_names = carried.named(names, g.held, pairs, arm.tip)
        self._local = threading.local()
        # bounds: each link object's sphere (its centre in its joint's frame) and capsule,
        # each obstacle's box (a half space: a box reaching far below its plane), in the base
        # frame, where the chain's FK places the joints (``bounds.ordered_bounds``)
        centre, self._radius = _spheres(g.model)
        self._capsule = _capsules(g.model)
        self._followed = g.followed
        for i, _, _ in g.followed:  # placed apart: bounded by nothing, every pair asked
            self._radius[i] = self._capsule[i, 6] = UNBOUNDED
        self._joint_of = np.array([o.parentJoint for o in g.model.geometryObjects], dtype=np.intp)
        self._frames = arm.model.njoints
        self._centre = np.array(
            [o.placement.act(c) for o, c in zip(g.model.geometryObjects, centre)]
        ).reshape(-1, 3)
        self._self = (
            np.array([a for a, _ in pairs[:n_self]], dtype=np.intp),
            np.array([b for _, b in pairs[:n_self]], dtype=np.intp),
        )
        self._link = np.array([a for a, _ in pairs[n_self:]], dtype=np.intp)
        self._box_R = np.array([R for R, _, _ in boxes]).reshape(-1, 3, 3)
        self._box_t = np.array([t for _, t, _ in boxes]).reshape(-1, 3)
        self._box_half = np.array([h for _, _, h in boxes]).reshape(-1, 3)
        # what ``ordered_bounds`` reads besides q and the scratch, gathered once
        self._flat = tuple(arm.kernel_chain.flat)
        self._shapes = (
            self._joint_of, self._centre, self._radius, self._capsule, *self._self,
            self._link, self._box_R, self._box_t, self._box_half,
        )  # fmt: skip

    def distance(self, q: np.ndarray) -> tuple[float, Pair | None]:
        """(distance m, (name_a, name_b)) of the closest checked pair at joint values ``q``
        (rad, m); negative when they overlap (the depth); (inf, None) with no pair."""
        if not self.pair_names:
            return float("inf"), None
        gd = getattr(self._local, "data", None)  # read as an attribute: every check
        if gd is None:
            gd = self.geometry_data()
        arm = self.arm
        pin.updateGeometryPlacements(arm.model, arm.data, self.model, gd, arm.to_pin(q))
        if self._followed:
            mimic_frames.place_followed(arm, q, gd, self._followed, self._full_data())
        bound, order, ranked = self._ordered(q)
        return self._closest(gd, bound, order, ranked)

    def distances(self, Q: np.ndarray) -> list[tuple[float, Pair | None]]:
        """``distance`` at each row of ``Q`` (N, dof), the bounds of every row from one
        call of the compiled kernel."""
        Q = np.array(Q, dtype=float, order="C").reshape(len(Q), self.arm.dof)
        n = len(Q)
        if not self.pair_names or n < 2:
            return [self.distance(q) for q in Q]
        gd = self.geometry_data()
        arm = self.arm
        model, data, geometry = arm.model, arm.data, self.model
        m = len(self.pair_names)
        bound, order = np.empty((n, m)), np.empty((n, m), dtype=np.intp)
        ranked = np.empty(n, dtype=np.intp)
        packed, kind, halton = self._flat
        H = np.empty((self._frames, 4, 4))
        ordered_bounds_many(packed, kind, halton, Q, H, *self._shapes, bound, order, ranked)
        update, to_pin, closest = pin.updateGeometryPlacements, arm.to_pin, self._closest
        out = []
        for i, k in enumerate(ranked.tolist()):
            update(model, data, geometry, gd, to_pin(Q[i]))
            if self._followed:
                mimic_frames.place_followed(arm, Q[i], gd, self._followed, self._full_data())
            out.append(closest(gd, bound[i], order[i], k))
        return out

    def _closest(self, gd, bound: np.ndarray, order: np.ndarray, ranked: int):
        """(distance, pair) of the closest pair, the geometry placed in ``gd``: coal asked
        for the pairs in the order of their bounds, until a bound is beyond the smallest
        distance found."""
        model = self.model
        best, k_best = math.inf, 0
        compute = pin.computeDistance
        for k in order[:ranked].tolist():  # in increasing order of their bounds
            if bound[k] - BOUND_SLACK >= best:
                break  # every later bound is at least this one
            d = compute(model, gd, k).min_distance
            if d < best:
                best, k_best = d, k
        else:  # the others, in no order: each whose bound is below the best so far
            for k in order[ranked:].tolist():
                if bound[k] - BOUND_SLACK < best:
                    d = compute(model, gd, k).min_distance
                    if d < best:
                        best, k_best = d, k
        return float(best), self.pair_names[k_best]

    def _full_data(self) -> pin.Data:
        """This thread's data of the URDF's whole model (``_followed``'s placements)."""
        data = getattr(self._local, "full", None)
        if data is None:
            data = self._local.full = self.arm.chain.full.createData()
        return data

    def geometry_data(self) -> pin.GeometryData:
        """This thread's ``GeometryData`` of the checker's model."""
        gd = getattr(self._local, "data", None)
        if gd is None:
            gd = self._local.data = pin.GeometryData(self.model)
        return gd

    def bounds(self, q: np.ndarray) -> np.ndarray:
        """A lower bound (m) on the distance of every pair at joint values ``q`` (rad, m):
        the larger of sphere to sphere and capsule to capsule for the arm's pairs, sphere to
        box (signed) for the obstacles' (``bounds.pair_bounds``). A view of this thread's
        scratch: copy it to keep it."""
        return self._ordered(q)[0]

    def _ordered(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
        """(bounds, pairs, m) at ``q`` in this thread's scratch: the first m pairs in
        increasing order of their bounds, then the others, none of whose bounds is smaller
        (``bounds.ordered_bounds``)."""
        scratch = getattr(self._local, "scratch", None)
        if scratch is None:
            n = len(self.pair_names)
            scratch = self._local.scratch = (
                np.empty(self.arm.dof),
                np.empty((self._frames, 4, 4)),
                np.empty(n),
                np.empty(n, dtype=np.intp),
            )
        qs, H, out, order = scratch
        qs[:] = q  # a read-only or strided q would be another compiled type
        packed, kind, halton = self._flat
        ranked = ordered_bounds(packed, kind, halton, qs, H, *self._shapes, out, order)
        return out, order, ranked


BOUND_SLACK = 1e-6  # m: coal's distances may fall this far below an exact lower bound
UNBOUNDED = 1e9  # m: the bounding radius of an object placed apart (no bound prunes it)


def _spheres(model: pin.GeometryModel) -> tuple[np.ndarray, np.ndarray]:
    """The bounding sphere of each object of ``model``, in its own frame: (centres,
    radii), from a hull's points, else from coal's bounding box."""
    centres = np.empty((model.ngeoms, 3))
    radii = np.empty(model.ngeoms)
    for i, o in enumerate(model.geometryObjects):
        centres[i], radii[i] = _sphere(o.geometry)
    return centres, radii


def _capsules(model: pin.GeometryModel) -> np.ndarray:
    """(n, 7): for each object of ``model`` a capsule holding it, in its joint's frame: the
    segment's two ends and the radius. Its axis is the hull's principal one, its radius
    the hull's farthest point from that axis, its ends drawn in as far as every point stays
    within the radius; a capsule holding every point holds their hull (it is convex). For a
    long link it bounds the distance far closer than a sphere (docs/collisions.md)."""
    out = np.empty((model.ngeoms, 7))
    for i, o in enumerate(model.geometryObjects):
        points = _points(o.geometry)
        placed = points @ o.placement.rotation.T + o.placement.translation
        out[i] = _capsule(placed)
    return out


def _points(geom) -> np.ndarray:
    """Points whose hull holds ``geom``: a hull's own, else coal's bounding box corners."""
    if isinstance(geom, coal.ConvexBase):
        return np.asarray(geom.points(), dtype=float)
    geom.computeLocalAABB()
    lo, hi = np.array(geom.aabb_local.min_), np.array(geom.aabb_local.max_)
    corners = [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    return np.array(corners)


def _capsule(points: np.ndarray) -> np.ndarray:
    centre = points.mean(axis=0)
    rel = points - centre
    axis = np.linalg.svd(rel, full_matrices=False)[2][0]
    t = rel @ axis
    r = np.linalg.norm(rel - np.outer(t, axis), axis=1)
    reach = np.sqrt(np.maximum(r.max() ** 2 - r**2, 0.0))
    t1, t2 = float(np.min(t + reach)), float(np.max(t - reach))
    if t1 > t2:  # round enough for one point: a sphere about the middle
        t1 = t2 = (t1 + t2) / 2
    # the radius measured to the segment as drawn, with a margin for rounding
    s = np.clip(t, t1, t2)
    radius = float(np.linalg.norm(rel - np.outer(s, axis), axis=1).max()) * (1 + 1e-9) + 1e-12
    return np.concatenate([centre + t1 * axis, centre + t2 * axis, [radius]])


def _sphere(geom) -> tuple[np.ndarray, float]:
    if isinstance(geom, coal.Sphere):
        return np.zeros(3), float(geom.radius)
    if isinstance(geom, coal.ConvexBase):
        points = np.asarray(geom.points())
        centre = (points.min(axis=0) + points.max(axis=0)) / 2
        return centre, float(np.linalg.norm(points - centre, axis=1).max())
    geom.computeLocalAABB()
    return np.array(geom.aabb_center), float(geom.aabb_radius)


FAR = 100.0  # m: beyond any arm's reach from its base's origin


def _box_of(geom, M: pin.SE3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rotation, centre, half sides) of a box holding the obstacle ``geom`` placed at
    ``M`` in the base frame."""
    if isinstance(geom, coal.Halfspace):  # the solid side: normal . x <= d
        normal = M.rotation @ np.array(geom.n)
        offset = float(geom.d + normal @ M.translation)
        R = _frame_of(normal)
        # 2 FAR below the plane, and at least FAR past the base's origin (an arm deep inside)
        depth = max(FAR, (offset + FAR) / 2)
        return R, (offset - depth) * normal, np.array([depth, FAR, FAR])
    if isinstance(geom, coal.Box):
        return M.rotation.copy(), M.translation.copy(), np.array(geom.halfSide)
    geom.computeLocalAABB()
    box = geom.aabb_local
    centre = (np.array(box.min_) + np.array(box.max_)) / 2
    return M.rotation.copy(), M.act(centre), (np.array(box.max_) - np.array(box.min_)) / 2


def _frame_of(normal: np.ndarray) -> np.ndarray:
    """A rotation whose first axis is ``normal`` (a unit vector)."""
    other = np.array([0.0, 0.0, 1.0]) if abs(normal[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    y = np.cross(normal, other)
    y /= np.linalg.norm(y)
    return np.column_stack([normal, y, np.cross(normal, y)])


def check_fixed(arm, g: ArmGeometry, i: int, obj, shape: Shape, k: int) -> None:
    """Refuse an obstacle that a link fixed to the base sinks into (beyond a base resting
    on its table: ``FIXED_OVERLAP_TOL``)."""
    data = arm.model.createData()
    pin.forwardKinematics(arm.model, data, arm.to_pin(arm.middle))
    link = g.model.geometryObjects[i]
    T_link = data.oMi[link.parentJoint] * link.placement
    d = coal.distance(
        link.geometry,
        coal.Transform3s(T_link.rotation, T_link.translation),
        obj.geometry,
        coal.Transform3s(obj.placement.rotation, obj.placement.translation),
        coal.DistanceRequest(),
        coal.DistanceResult(),
    )
    if d < -FIXED_OVERLAP_TOL:
        raise CollisionError(
            f"{obstacle_name(k, shape)} overlaps link {g.links[i]!r}, which never moves "
            f"relative to the base, by {-d:.3g} m: move or shrink the obstacle (a link "
            f"may sink at most {FIXED_OVERLAP_TOL:g} m into one, as a base into its table)",
            value=shape,
        )


_CHECKERS: Derived[dict] = Derived("collision checkers", lambda _: {})  # per obstacles


def checker(arm: ArmModel, obstacles: tuple[Shape, ...], self_collision: bool) -> Checker:
    """The ``Checker`` of these obstacles, built once per arm."""
    checkers = _CHECKERS(arm)
    key = (obstacles, bool(self_collision))
    found = checkers.get(key)
    if found is None:
        if len(checkers) > 32:
            checkers.clear()
        found = checkers[key] = Checker(arm, obstacles, bool(self_collision))
    return found


def min_distance(
    arm: ArmModel, q: object, obstacles: object = (), self_collision: bool = False
) -> tuple[float, Pair | None]:
    """(distance m, (name_a, name_b)): the closest checked pair at ``q`` (rad, m)."""
    from_obstacles = check_obstacles(obstacles)
    self_collision = flag(self_collision)
    if not from_obstacles and not self_collision:
        raise CollisionError(
            "nothing to measure: give obstacles=[...] or self_collision=True",
            option="obstacles",
        )
    return checker(arm, from_obstacles, self_collision).distance(arm.check_q(q))


def in_collision(
    arm: ArmModel,
    q: object,
    obstacles: object = (),
    self_collision: bool = False,
    margin: float = 0.0,
) -> bool:
    """Whether some checked pair at ``q`` is closer than ``margin`` (m)."""
    return min_distance(arm, q, obstacles, self_collision)[0] < margin_of(margin)
