"""Collision rows of a servo over chains that share joints: obstacles and self-collision,
between the chains too, as velocity dampers on the union's step.

Each chain's collision geometry (``armik.constraints.collision.arm_geometry``) holds every
link of the robot, those off the chain frozen where the chain was cut. Here each link is
taken once, as ``Arms.min_distance`` takes it (``armik.arms_links``): from a chain that
places it where the robot does (the one that hangs it on the deepest joint, never one that
froze it, three tips with two on a torso too), and the pairs are those the robot's checks
measure: every moving link against every obstacle (a half space too: it has no bounding
sphere, so the broad phase keeps it), and with self-collision each chain's own pairs among
the links it places and every pair of links no one chain places both (two arms), an
SRDF's disabled pairs left out. A pair whose bounding spheres are farther than ``margin +
ACTIVE`` apart costs nothing (the broad phase); for the others coal gives the distance d,
the witness points and the normal n, and the row is ``armik.servo.collisions``'s:
``n . (J_p2 - J_p1) dq >= -RATE dt (d - margin)``, each point's Jacobian from its chain's
Pinocchio Jacobian, its columns the union's.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence

import coal
import numpy as np
import pinocchio as pin

from armik.arms_links import Links
from armik.constraints.shapes import check_obstacles
from armik.model import mimic_frames
from armik.model.arm_model import ArmModel
from armik.servo.collisions import ACTIVE, RATE, asked, margin_of
from armik.servo.layout import MAX_ROWS


class UnionCollisions:
    """The collision rows of ``arms`` (the chains, each with its joints' union columns
    ``cols``, n union joints) at the union's joint values (``at``)."""

    def __init__(
        self,
        arms: Sequence[ArmModel],
        cols: Sequence[np.ndarray],
        n: int,
        obstacles: object,
        self_collision: bool,
        margin: float,
        gain: float,
    ) -> None:
        self.arms, self.cols, self.n = list(arms), list(cols), n
        self.margin, self.gain = margin, gain
        self.data = [arm.model.createData() for arm in arms]
        self.shapes = check_obstacles(obstacles)
        # each link once, from a chain that places it where the robot does, and the pairs
        # the robot's own checks measure (``Arms.min_distance``'s)
        links = Links(self.arms, self.shapes, self_collision)
        self.geometry = links.geometry
        self.gdata = [pin.GeometryData(g.model) for g in self.geometry]
        self.objects, self.names, self.self_pairs = links.objects, links.names, links.self_pairs
        self.obstacles = links.obstacles
        self.obstacle_radius, self.obstacle_centre = links.obstacle_radius, links.obstacle_centre
        self.moving, self.geoms, self.joints = links.moving, links.geoms, links.joints
        self.radius, self.centre = links.radius, links.centre
        self.pair_a, self.pair_b = links.pair_a, links.pair_b
        # a link below a mimic joint off its chain that follows its driver on it: placed,
        # and its points' Jacobians read, on the whole model (the cut one holds it still)
        self.full = [
            arm.chain.full.createData() if g.followed else None
            for arm, g in zip(arms, self.geometry)
        ]
        follower = {
            (c, i): joint for c, g in enumerate(self.geometry) for i, joint, _ in g.followed
        }
        self.follower = {k: follower[o] for k, o in enumerate(self.objects) if o in follower}
        self.rows = np.zeros((MAX_ROWS, n + 1))
        self.request = coal.DistanceRequest()
        # witness points to 1e-9: at coal's default (1e-6) a face's normal turned the row
        # 3e-5 off the distance's derivative, the hands side by side
        self.request.gjk_tolerance = 1e-9
        self.nearest = math.inf  # m: the nearest pair's distance at the last ``at``
        self.pairs: list[tuple[int, int]] = []  # each row's pair (an obstacle's: -1 - it)

    def at(self, q: np.ndarray, ahead: float = 0.0) -> np.ndarray:
        """The rows at the union's joint values q (rad, m), nearest pairs first, at most
        ``MAX_ROWS``: (K, n + 1), C then b for ``C dq >= b``; ``ahead`` m farther than
        ``ACTIVE`` beyond the margin (``collisions.ahead``)."""
        for arm, data, g, gd, cols, full in zip(
            self.arms, self.data, self.geometry, self.gdata, self.cols, self.full
        ):
            qp = arm.to_pin(q[cols])
            pin.computeJointJacobians(arm.model, data, qp)
            pin.updateGeometryPlacements(arm.model, data, g.model, gd)
            if full is not None:  # below a mimic joint off the chain: the whole model's
                mimic_frames.place_followed_moving(arm, q[cols], gd, g.followed, full)
        placed = [self.gdata[c].oMg[i] for c, i in self.objects]
        R = np.array([M.rotation for M in placed])
        centre = np.array([M.translation for M in placed]) + np.einsum("kij,kj->ki", R, self.centre)
        reach = self.margin + ACTIVE + ahead
        pa, pb = self.pair_a, self.pair_b
        gap = np.linalg.norm(centre[pa] - centre[pb], axis=1) - self.radius[pa] - self.radius[pb]
        close = np.flatnonzero(gap < reach)
        near = list(zip(gap[close].tolist(), pa[close].tolist(), pb[close].tolist()))
        if self.obstacles:  # (other: -1 - the obstacle)
            m = self.moving
            d = np.linalg.norm(centre[m][:, None, :] - self.obstacle_centre[None], axis=2)
            gap = d - self.radius[m][:, None] - self.obstacle_radius[None]
            for i, s in zip(*np.nonzero(gap < reach)):
                near.append((float(gap[i, s]), int(m[i]), -1 - int(s)))
        # the pairs the broad phase leaves, nearest bound first, measured until the
        # ``MAX_ROWS`` nearest distances are known (no bound left below the farthest of them)
        found: list[tuple[float, int, int, coal.DistanceResult]] = []
        kept: list[float] = []  # the distances found, as a max-heap of the nearest, negated
        request = self.request
        transforms: dict[int, coal.Transform3s] = {}
        for bound, a, b in sorted(near):
            if len(kept) == MAX_ROWS and bound >= -kept[0]:
                break
            for k in (a, b) if b >= 0 else (a,):
                if k not in transforms:
                    transforms[k] = _transform(placed[k])
            Ta = transforms[a]
            if b >= 0:
                gb, Tb = self.geoms[b], transforms[b]
            else:
                gb, Tb = self.obstacles[-1 - b]
            result = coal.DistanceResult()
            d = coal.distance(self.geoms[a], Ta, gb, Tb, request, result)
            if d < reach:
                found.append((d, a, b, result))
                if len(kept) < MAX_ROWS:
                    heapq.heappush(kept, -d)
                elif d < -kept[0]:
                    heapq.heapreplace(kept, -d)
        found.sort(key=lambda f: f[0])
        self.nearest = found[0][0] if found else math.inf
        K = 0
        jacobians: dict = {}
        self.pairs = [(a, b) for _, a, b, _ in found[:MAX_ROWS]]
        for d, a, b, result in found[:MAX_ROWS]:
            Jd = -self._point(a, np.array(result.getNearestPoint1()), jacobians)
            if b >= 0:
                Jd += self._point(b, np.array(result.getNearestPoint2()), jacobians)
            self.rows[K, :-1] = np.array(result.normal) @ Jd
            self.rows[K, -1] = -self.gain * (d - self.margin)
            K += 1
        return self.rows[:K]

    def _point(self, k: int, p: np.ndarray, jacobians: dict) -> np.ndarray:
        """The 3 x n Jacobian (the union's columns) of the world point p fixed to object
        k; ``jacobians``: this tick's joint Jacobians, by (chain, joint)."""
        c, _ = self.objects[k]
        out = np.zeros((3, self.n))
        if k in self.follower:  # moved by a mimic joint off its chain
            joint, full = self.follower[k], self.full[c]
            Jf = mimic_frames.followed_jacobian(self.arms[c], full, joint)
            r = p - full.oMi[joint].translation  # type: ignore[union-attr]
            out[:, self.cols[c]] = Jf[:3] + np.cross(Jf[3:].T, r).T
            return out
        joint = self.joints[k]
        if joint == 0:
            return out
        data = self.data[c]
        J = jacobians.get((c, joint))
        if J is None:
            J = pin.getJointJacobian(self.arms[c].model, data, joint, pin.LOCAL_WORLD_ALIGNED)
            J = J.reshape(6, len(self.cols[c]))  # one joint: Pinocchio gives (6,)
            jacobians[c, joint] = J
        r = p - data.oMi[joint].translation
        out[:, self.cols[c]] = J[:3] + np.cross(J[3:].T, r).T  # v + w x r
        return out


def _transform(M: pin.SE3) -> coal.Transform3s:
    return coal.Transform3s(M.rotation, M.translation)


def union_rows(
    arms: Sequence[ArmModel],
    cols: Sequence[np.ndarray],
    n: int,
    obstacles: object,
    self_collision: object,
    margin: object,
    dt: float,
) -> UnionCollisions | None:
    """The collision rows asked for, or None (no obstacle, no self-collision); a
    ``CollisionError`` naming a bad option."""
    if not asked(obstacles, self_collision):
        return None
    m = margin_of(margin)
    return UnionCollisions(arms, cols, n, obstacles, bool(self_collision), m, RATE * dt)
