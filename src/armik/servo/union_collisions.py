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
from armik.constraints.collision import obstacle_name
from armik.constraints.shapes import check_obstacles
from armik.model import mimic_frames
from armik.model.arm_model import ArmModel
from armik.servo.collisions import ACTIVE, INSIDE, RATE, asked, margin_of, still, urgency
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
        self._levers()
        self.rows = np.zeros((MAX_ROWS, 2 * n + 1))  # C, b, then the levers
        self.request = coal.DistanceRequest()
        # witness points to 1e-9: at coal's default (1e-6) a face's normal turned the row
        # 3e-5 off the distance's derivative, the hands side by side
        self.request.gjk_tolerance = 1e-9
        self.nearest = math.inf  # m: the nearest pair's distance at the last ``at``
        self.pairs: list[tuple[int, int]] = []  # each row's pair (an obstacle's: -1 - it)
        self.said: set[tuple[str, str]] = set()  # pairs inside the margin no joint moves

    def at(
        self,
        q: np.ndarray,
        ahead: float = 0.0,
        v: np.ndarray | None = None,
        amax: np.ndarray | None = None,
        levers: bool = False,
    ) -> np.ndarray:
        """The rows at the union's joint values q (rad, m), most urgent first, at most
        ``MAX_ROWS``: (K, n + 1), C then b for ``C dq >= b`` (with ``levers``, (K, 2 n + 1):
        then each joint's lever, ``armik.servo.rows``); ``ahead`` m farther than
        ``ACTIVE`` beyond the margin (``collisions.ahead``). A pair's urgency is its gap to
        the margin less its braking distance at the velocities v (rad/s, m/s) and the
        acceleration limits ``amax`` (``collisions.urgency``; none given: at rest)."""
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
        # the pairs the broad phase leaves, most urgent bound first (the distance's less
        # the braking distance's, ``_reach``), measured until no bound is below the
        # ``MAX_ROWS``-th nearest distance (an urgency is at most the distance); the rows
        # are the ``MAX_ROWS`` most urgent of those measured. By distance
        # alone, TALOS's hands sent at each other at once filled the rows with the torso's
        # and the arms' near pairs, slow ones, and the fingertips, closing at 3 m/s, came
        # among them 0.17 m apart, too late to stop: they passed 0.2 mm into each other
        slow = urgency(v, amax)
        share = np.zeros(len(self.objects)) if slow is None else self._reach(centre, slow)
        for f in self.follower:  # (on the whole model: the joints' own bound)
            share[f] = max(share[f], ahead)
        order = sorted((g - share[a] - (share[b] if b >= 0 else 0.0), a, b) for g, a, b in near)
        found: list[tuple[float, int, int, coal.DistanceResult]] = []
        kept: list[float] = []  # the ``MAX_ROWS`` nearest distances, a max-heap, negated
        request = self.request
        transforms: dict[int, coal.Transform3s] = {}
        self.nearest = math.inf
        for first, a, b in order:  # (a pair's urgency is at most its distance)
            if len(kept) == MAX_ROWS and first >= -kept[0]:
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
            self.nearest = min(self.nearest, d)
            if d >= reach:
                continue
            found.append((d, a, b, result))
            if len(kept) < MAX_ROWS:
                heapq.heappush(kept, -d)
            elif d < -kept[0]:
                heapq.heapreplace(kept, -d)
        found.sort(key=lambda f: f[0])
        if len(found) > MAX_ROWS:  # those that may be among the most urgent
            last = found[MAX_ROWS - 1][0]
            found = [
                f for f in found if f[0] - share[f[1]] - (f[2] >= 0) * share[max(f[2], 0)] <= last
            ]
        C, L = self._closing(found)
        # the most urgent, each pair inside the margin before any outside it; a pair no
        # joint moves takes no row (said once where it is inside the margin)
        d = np.array([f[0] for f in found])
        urgent = d - INSIDE * (d < self.margin)
        if slow is not None:
            urgent -= np.abs(C) @ slow
        moved = C.any(axis=1)
        if not moved.all():
            for i in np.flatnonzero(~moved & (d < self.margin)).tolist():
                a, b = found[i][1:3]
                other = self.names[b] if b >= 0 else obstacle_name(-1 - b, self.shapes[-1 - b])
                still(self.said, self.names[a], other, found[i][0])
            urgent[~moved] = math.inf
        pick = np.argsort(urgent, kind="stable")[: min(MAX_ROWS, int(moved.sum()))]
        self.pairs = [found[i][1:3] for i in pick.tolist()]
        K = len(pick)
        n = self.n
        self.rows[:K, :n] = C[pick]
        self.rows[:K, n] = [-self.gain * (found[i][0] - self.margin) for i in pick.tolist()]
        self.rows[:K, n + 1 :] = L[pick]
        return self.rows[:K] if levers else self.rows[:K, : n + 1]

    def _closing(self, found: list) -> tuple[np.ndarray, np.ndarray]:
        """(len(found), n): each pair's row, n . (J_p2 - J_p1), its witness points'
        Jacobians from their chains', the union's columns, all pairs at once."""
        P = len(found)
        J = np.zeros((2, P, 6, self.n))  # each side's joint Jacobian, then at its point
        r = np.zeros((2, P, 3))  # each point from its joint's origin
        normal = np.zeros((P, 3))
        joints: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray] | None] = {}
        for i, (_, a, b, result) in enumerate(found):
            normal[i] = result.normal
            for side, k, p in (
                (0, a, result.getNearestPoint1()),
                (1, b, result.getNearestPoint2()),
            ):
                if k < 0:
                    continue
                if k not in joints:
                    joints[k] = self._joint(k)
                held = joints[k]
                if held is not None:
                    Jk, cols, origin = held
                    J[side, i][:, cols] = Jk
                    r[side, i] = np.asarray(p) - origin
        w, lin = J[:, :, 3:], J[:, :, :3]  # v + w x r, each point
        point = lin + np.cross(w, r[:, :, :, None], axisa=2, axisb=2, axisc=2)
        apart = point[1] - point[0]  # (each joint's lever: how fast it parts the points)
        return np.einsum("pi,pin->pn", normal, apart), np.linalg.norm(apart, axis=1)

    def _joint(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """Object k's joint Jacobian (6 x its chain's joints, at the joint's origin, in
        Pinocchio's ``LOCAL_WORLD_ALIGNED``), its union columns and the origin; None
        where no joint moves it."""
        c, _ = self.objects[k]
        if k in self.follower:  # moved by a mimic joint off its chain
            joint, full = self.follower[k], self.full[c]
            Jf = mimic_frames.followed_jacobian(self.arms[c], full, joint)
            return Jf, self.cols[c], full.oMi[joint].translation  # type: ignore[union-attr]
        joint = self.joints[k]
        if joint == 0:
            return None
        data = self.data[c]
        J = pin.getJointJacobian(self.arms[c].model, data, joint, pin.LOCAL_WORLD_ALIGNED)
        J = J.reshape(6, len(self.cols[c]))  # one joint: Pinocchio gives (6,)
        return J, self.cols[c], data.oMi[joint].translation

    def _levers(self) -> None:
        """What bounds each object's braking distance: ``moves`` (objects x n), 1 where
        the union's joint moves it (every joint of its chain where a mimic joint off the
        chain turns it, or one of them has no single velocity), ``slide`` (n) 1 on a
        prismatic joint, and ``origin``, each union joint's (chain, Pinocchio joint)."""
        self.moves = np.zeros((len(self.objects), self.n))
        self.slide = np.zeros(self.n)
        origin: dict[int, tuple[int, int]] = {}
        for k, (c, _) in enumerate(self.objects):
            model, cols = self.arms[c].model, self.cols[c]
            j, chain = self.joints[k], []
            while j > 0:
                chain.append(j)
                j = model.parents[j]
            if k in self.follower or any(model.joints[j].nv != 1 for j in chain):
                self.moves[k, cols] = 1.0
            for j in chain:
                joint = model.joints[j]
                if joint.nv == 1:
                    col = int(cols[joint.idx_v])
                    self.moves[k, col] = 1.0
                    origin.setdefault(col, (c, j))
                    self.slide[col] = 1.0 if joint.shortname().startswith("JointModelP") else 0.0
        self.origin = [origin.get(col, (-1, 0)) for col in range(self.n)]

    def _reach(self, centre: np.ndarray, slow: np.ndarray) -> np.ndarray:
        """m: a bound on each object's share of any pair's braking distance, each joint's
        braking turn ``slow`` times the most it moves the object's points a radian (or a
        m): its bounding sphere's farthest point from the joint's origin (1 on a prismatic
        joint); a pair's braking distance is at most its objects' sum."""
        origins = np.zeros((self.n, 3))
        for col, (c, j) in enumerate(self.origin):
            if c >= 0:
                origins[col] = self.data[c].oMi[j].translation
        far = np.linalg.norm(centre[:, None, :] - origins[None], axis=2) + self.radius[:, None]
        return (self.moves * (far + self.slide)) @ slow


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
