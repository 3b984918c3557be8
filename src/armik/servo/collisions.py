"""A servo's collision rows: obstacles and self-collision as velocity dampers on the step.

For each checked pair (``armik.constraints.collision.Checker``: the arm's links against the
obstacles and, with ``self_collision``, against each other) whose lower bound on its
distance is below ``margin + ACTIVE`` (the broad phase: far pairs cost nothing), coal gives
the distance d, the witness points p1, p2 and the normal n from p1 to p2; the row

    n . (J_p2 - J_p1) dq >= -RATE dt (d - margin)

lets the pair close by at most a share ``RATE dt`` of its gap to the margin a tick, and
pushes a pair inside the margin apart (Pink's and mink's collision avoidance; the
velocity damper of Faverjon and Tournassoud). The rows are ``(K, n + 1)``: C, then b; the
compiled step (``armik.servo.rows``) keeps each pair its braking distance off and adds its
braking row. Pairs are taken as far out as the joints need to stop (``ahead``). A
link below a mimic joint off the chain that follows its driver on it is placed, and its
points' Jacobians read, on the URDF's whole model (``armik.model.mimic_frames``).
"""

from __future__ import annotations

import heapq

import numpy as np
import pinocchio as pin

from armik.constraints import collision
from armik.constraints.shapes import check_obstacles
from armik.errors import CollisionError, warn
from armik.model import mimic_frames
from armik.model.arm_model import ArmModel
from armik.servo.box import SAFE
from armik.servo.layout import AMAX, MAX_ROWS, RATE, V

ACTIVE = 0.05  # m beyond the margin: pairs nearer than this give a row
INSIDE = 1e6  # m off the urgency of a pair inside the margin (more than any braking distance)


class CollisionRows:
    """The rows of one checker's pairs at joint values q (``at``): each pair nearer than
    ``margin + active`` may close by at most ``gain`` of its gap to ``margin`` (m) a step."""

    def __init__(
        self, check: collision.Checker, margin: float, gain: float, active: float = ACTIVE
    ) -> None:
        arm = check.arm
        self.arm, self.margin, self.gain, self.active = arm, margin, gain, active
        self.check = check
        self.data = arm.model.createData()
        self.rows = np.zeros((MAX_ROWS, 2 * arm.dof + 1))  # C, b, then the levers
        self.nearest = float("inf")  # m: the nearest pair's distance at the last ``at``
        # objects below a mimic joint off the chain that follows its driver on it: placed,
        # and their points' Jacobians read, on the whole model (the cut one holds them still)
        self.followed = collision.arm_geometry(arm).followed
        self.follower = {i: joint for i, joint, _ in self.followed}
        self.full = arm.chain.full.createData() if self.followed else None
        self.said: set[tuple[str, str]] = set()  # pairs inside the margin no joint moves

    def at(
        self,
        q: np.ndarray,
        ahead: float = 0.0,
        v: np.ndarray | None = None,
        amax: np.ndarray | None = None,
        levers: bool = False,
    ) -> np.ndarray:
        """The rows at q (rad, m) of the ``MAX_ROWS`` most urgent pairs within reach
        (``ahead`` m farther: ``ahead``'s) at most, most urgent first: a pair's urgency is
        its distance less its braking distance at the velocities v (rad/s, m/s) and the
        acceleration limits ``amax`` (``urgency``; none given: its distance)."""
        arm, check, data = self.arm, self.check, self.data
        reach = self.margin + self.active + ahead
        bound = check.bounds(q)
        near = np.flatnonzero(bound < reach)
        self.nearest = float("inf")
        if near.size == 0:
            return self.rows[:0] if levers else self.rows[:0, : arm.dof + 1]
        model, gm = arm.model, check.model
        gd = check.geometry_data()
        qp = arm.to_pin(q)
        pin.computeJointJacobians(model, data, qp)
        pin.updateGeometryPlacements(model, data, gm, gd)
        if self.followed:
            mimic_frames.place_followed_moving(arm, q, gd, self.followed, self.full)
        # measured in the order of their bounds until the ``MAX_ROWS`` most urgent are
        # known: no bound left below the least urgent of them by more than ``ahead`` (a
        # bound on any pair's braking distance)
        slow = urgency(v, amax)
        kept: list[tuple[float, int, float, np.ndarray, np.ndarray]] = []  # (-urgency, k, ...)
        for k in near[np.argsort(bound[near])].tolist():
            full = len(kept) == MAX_ROWS  # (a pair inside the margin is measured)
            if full and bound[k] >= self.margin and bound[k] - ahead >= -kept[0][0]:
                break
            r = pin.computeDistance(gm, gd, k)
            d = r.min_distance
            self.nearest = min(self.nearest, d)
            if d >= reach or (full and d >= self.margin and d - ahead >= -kept[0][0]):
                continue
            pair = gm.collisionPairs[k]
            Jd = self._point(pair.second, np.array(r.getNearestPoint2()))
            Jd -= self._point(pair.first, np.array(r.getNearestPoint1()))
            C = np.array(r.normal) @ Jd
            if not C.any():  # no joint moves the pair: no row (said once inside the margin)
                if d < self.margin:
                    objects = gm.geometryObjects
                    still(self.said, objects[pair.first].name, objects[pair.second].name, d)
                continue
            lever = np.sqrt(np.sum(Jd * Jd, axis=0))  # (how fast each joint parts them)
            u = d if slow is None else d - float(np.abs(C) @ slow)
            if d < self.margin:  # inside the margin: its row before any pair outside it
                u -= INSIDE
            if len(kept) < MAX_ROWS:
                heapq.heappush(kept, (-u, k, d, C, lever))
            elif u < -kept[0][0]:
                heapq.heapreplace(kept, (-u, k, d, C, lever))
        kept.sort(key=lambda e: (-e[0], e[1]))
        n = arm.dof
        for K, (_, _, d, C, lever) in enumerate(kept):
            self.rows[K, :n] = C
            self.rows[K, n] = -self.gain * (d - self.margin)
            self.rows[K, n + 1 :] = lever
        K = len(kept)
        return self.rows[:K] if levers else self.rows[:K, : n + 1]

    def _point(self, i: int, p: np.ndarray) -> np.ndarray:
        """The 3 x dof Jacobian of the world point p fixed to geometry object i."""
        if i in self.follower:  # moved by a mimic joint off the chain
            joint = self.follower[i]
            J = mimic_frames.followed_jacobian(self.arm, self.full, joint)
            origin = self.full.oMi[joint].translation  # type: ignore[union-attr]
        else:
            joint = self.check.model.geometryObjects[i].parentJoint
            if joint == 0:
                return np.zeros((3, self.arm.dof))
            model, data = self.arm.model, self.data
            J = pin.getJointJacobian(model, data, joint, pin.LOCAL_WORLD_ALIGNED)
            J = J.reshape(6, self.arm.dof)  # one joint: Pinocchio gives (6,)
            origin = data.oMi[joint].translation
        rx, ry, rz = (p - origin).tolist()
        v, w = J[:3], J[3:]
        v[0] -= ry * w[2] - rz * w[1]  # v + w x r = v - r x w
        v[1] -= rz * w[0] - rx * w[2]
        v[2] -= rx * w[1] - ry * w[0]
        return v


def still(said: set[tuple[str, str]], a: str, b: str, d: float) -> None:
    """An ``ArmikWarning``, once a pair, that ``a`` and ``b`` are ``d`` m apart, inside the
    margin, and no joint moves them apart: no row can keep them from it."""
    if (a, b) in said:
        return
    said.add((a, b))
    # d < 0: the depth
    gap = f"{d:.4g} m apart" if d > 0 else "touching" if d == 0 else f"overlapping by {-d:.4g} m"
    warn(
        f"{a} and {b} are {gap}, inside the collision margin, and no joint the "
        "servo commands moves them apart: no row keeps them apart (move the obstacle, or "
        "lower margin=)"
    )


def ahead(state: np.ndarray, length: float) -> float:
    """m: how much farther than ``ACTIVE`` a servo's rows reach at the velocities of its
    ``state``, a bound on any pair's braking distance (``armik.servo.rows``): each joint
    braking at its acceleration limit turns v^2 / (2 a) on, which moves a point by at most
    ``length`` (the longest chain's reach, ``servo.curvature``) times that. A pair entering
    the rows nearer than that could not stop before the margin."""
    v, a = state[V], state[AMAX]
    return length * float(np.sum(v * v / (2.0 * a)))


def urgency(v: np.ndarray | None, amax: np.ndarray | None) -> np.ndarray | None:
    """Each joint's braking turn v^2 / (2 a) (rad, m) at the velocities v and acceleration
    limits ``amax`` (kept ``SAFE`` inside, as ``armik.servo.rows`` brakes), or None (none
    given): a pair's braking distance is its row's |C| times it, and the rows are the pairs
    whose gap less that is smallest, those that must brake first."""
    if v is None or amax is None:
        return None
    return v * v / (2.0 * amax * (1.0 - SAFE))


def asked(obstacles: object, self_collision: object) -> bool:
    """Whether collision rows are asked for (obstacles, or ``self_collision``); a
    ``CollisionError`` for a ``self_collision`` that is not True or False."""
    if not isinstance(self_collision, (bool, np.bool_)):  # (None too: solve's rule)
        raise CollisionError(
            f"self_collision must be True or False, got {self_collision!r}",
            option="self_collision",
            value=self_collision,
        )
    return obstacles is not None or bool(self_collision)


def rows_for(
    arm: ArmModel, obstacles: object, self_collision: object, margin: object, dt: float
) -> CollisionRows | None:
    """The servo's collision rows asked for, or None (no obstacle, no self-collision); a
    ``CollisionError`` naming a bad option."""
    if not asked(obstacles, self_collision):
        return None
    shapes = check_obstacles(obstacles)
    checker = collision.checker(arm, shapes, bool(self_collision))
    return CollisionRows(checker, margin_of(margin), RATE * dt)


def margin_given(options: dict[str, object]) -> None:
    """A ``CollisionError`` for a ``margin=`` the servo options ``options`` give that is not
    a distance in [0, 1) m, or that is more than 0 with nothing to keep it from (no
    obstacles, self_collision off): as ``solve`` says, it would check nothing."""
    if "margin" not in options:
        return
    margin = margin_of(options["margin"])
    obstacles, flag = options.get("obstacles"), options.get("self_collision", False)
    if margin > 0.0 and not asked(obstacles, flag):
        raise CollisionError(
            f"margin={margin:g} m with no obstacles and self_collision off checks nothing: "
            "give obstacles=[...] or self_collision=True",
            option="margin",
            value=options["margin"],
        )


def margin_of(margin: object) -> float:
    """``margin`` (m) as a float in [0, 1); a ``CollisionError`` naming it otherwise."""
    try:
        m = float(margin)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        m = float("nan")
    if not 0.0 <= m < 1.0:
        raise CollisionError(
            f"margin must be a distance in [0, 1) m, got {margin!r}",
            option="margin",
            value=margin,
        )
    return m
