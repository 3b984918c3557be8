"""Collisions of several tips (``Arms.min_distance``, ``Arms.in_collision``): the robot's
links at one configuration over every joint, against obstacles and against each other.

Each link is taken from a chain that places it where the robot does, and the pairs are
``armik.arms_links``': every link a joint moves against every obstacle (an obstacle that a
link fixed to the base sinks into is refused, as on one arm); with ``self_collision`` each
chain's own self-collision pairs among the links it places (its SRDF's disabled pairs left
out) and the links of two chains that no one chain places both. Coal measures each pair,
asked in the order of a lower bound on its distance (the bounding spheres) until that
bound passes the smallest distance found: the closest pair of all. With one tip these are
the pairs and distances of ``Arm.min_distance``.
"""

from __future__ import annotations

import dataclasses
import math
import threading
from collections.abc import Mapping
from typing import Any

import coal
import numpy as np
import pinocchio as pin

from armik import arms_every, checked, reasons
from armik.arms_joined import held, left_out
from armik.arms_links import UNBOUNDED, Links
from armik.arms_tasks import by_tip
from armik.batch_result import BatchResult
from armik.constraints.clear import Collisions
from armik.constraints.collision import BOUND_SLACK, _unmoved, obstacle_name
from armik.constraints.shapes import check_obstacles, margin_of
from armik.constraints.srdf import Pair
from armik.errors import CollisionError
from armik.model import mimic_frames
from armik.result import IKResult
from armik.status import Status

MOST_CHECKERS = 32  # kept per robot, one per set of obstacles, as one arm keeps them


class ArmsChecker:
    """The distances of every pair of ``arms`` (an ``armik.Arms``) to ``obstacles`` and,
    with ``self_collision``, among its links (the module's pairs)."""

    def __init__(self, arms: Any, obstacles: tuple, self_collision: bool) -> None:
        chains = [arms._chains[t] for t in arms.tips]
        self.cols = [arms._columns[t] for t in arms.tips]
        self.joint_names = arms.joint_names
        self.links = Links(chains, obstacles, self_collision)  # each link from its chain
        links = self.links
        if not len(links.moving):  # as one arm's checker refuses it (``Checker``)
            raise _unmoved(f"robot {chains[0].name!r}", links.names)
        self.chains = chains
        self.names = [
            *links.names,
            *(obstacle_name(s, shape) for s, shape in enumerate(links.shapes)),
        ]
        self._local = threading.local()

    def _data(self) -> tuple[list, list, list]:
        """This thread's data of each chain's model, geometry and whole model."""
        found = getattr(self._local, "data", None)
        if found is None:
            found = self._local.data = (
                [arm.model.createData() for arm in self.chains],
                [pin.GeometryData(g.model) for g in self.links.geometry],
                [arm.chain.full.createData() for arm in self.chains],
            )
        return found

    def distance(self, q: np.ndarray) -> tuple[float, Pair | None]:
        """(distance m, (name_a, name_b)) of the closest pair at the robot's joint values
        ``q`` (rad, m); negative when they overlap; (inf, None) with no pair."""
        links = self.links
        datas, gdatas, fulls = self._data()
        for arm, g, data, gd, full, cols in zip(
            self.chains, links.geometry, datas, gdatas, fulls, self.cols
        ):
            pin.updateGeometryPlacements(arm.model, data, g.model, gd, arm.to_pin(q[cols]))
            if g.followed:  # below a mimic joint off the chain: where the whole model puts it
                mimic_frames.place_followed(arm, q[cols], gd, g.followed, full)
        placed = [gdatas[c].oMg[i] for c, i in links.objects]
        centre = np.array(
            [M.translation + M.rotation @ c for M, c in zip(placed, links.centre)]
        ).reshape(-1, 3)
        pa, pb = links.pair_a, links.pair_b
        near = np.linalg.norm(centre[pa] - centre[pb], axis=1) - links.radius[pa] - links.radius[pb]
        bounds = list(zip(near.tolist(), pa.tolist(), pb.tolist()))
        m = links.moving
        for s in range(len(links.obstacles)):
            if links.obstacle_radius[s] < UNBOUNDED:
                d = np.linalg.norm(centre[m] - links.obstacle_centre[s], axis=1)
                gap = d - links.radius[m] - links.obstacle_radius[s]
            else:  # a half space: no bound, always asked
                gap = np.full(len(m), -math.inf)
            bounds += zip(gap.tolist(), m.tolist(), [-1 - s] * len(m))
        best, found = math.inf, None
        request = coal.DistanceRequest()
        for bound, a, b in sorted(bounds):
            if bound - BOUND_SLACK >= best:
                break  # every later bound is at least this one
            Ma = placed[a]
            if b >= 0:
                gb, Mb = links.geoms[b], placed[b]
                Tb = coal.Transform3s(Mb.rotation, Mb.translation)
            else:
                gb, Tb = links.obstacles[-1 - b]
            d = coal.distance(
                links.geoms[a],
                coal.Transform3s(Ma.rotation, Ma.translation),
                gb,
                Tb,
                request,
                coal.DistanceResult(),
            )
            if d < best:
                best, found = d, (a, b)
        if found is None:
            return math.inf, None
        a, b = found
        other = self.names[b] if b >= 0 else self.names[len(links.names) - 1 - b]
        return float(best), (self.names[a], other)


def min_distance(
    arms: Any, q: object, obstacles: object = (), self_collision: bool = False
) -> tuple[float, Pair | None]:
    """(distance m, (name_a, name_b)): the closest checked pair at ``q`` (the robot's joint
    values, rad, m); ``CollisionError`` when there is nothing to measure."""
    shapes = check_obstacles(obstacles)
    if not isinstance(self_collision, (bool, np.bool_)):
        raise CollisionError(
            f"self_collision must be True or False, got {self_collision!r:.80}",
            option="self_collision",
            value=self_collision,
        )
    if not shapes and not self_collision:
        raise CollisionError(
            "nothing to measure: give obstacles=[...] or self_collision=True",
            option="obstacles",
        )
    q = checked.configuration("q", q, arms.joint_names)
    return _checker(arms, shapes, bool(self_collision)).distance(q)


def in_collision(
    arms: Any,
    q: object,
    obstacles: object = (),
    self_collision: bool = False,
    margin: float = 0.0,
) -> bool:
    """Whether some checked pair at ``q`` is closer than ``margin`` (m, a distance: an
    overlap allowed is refused, as ``Arm.in_collision`` refuses it)."""
    return min_distance(arms, q, obstacles, self_collision)[0] < margin_of(margin)


def between(
    arms: Any, options: Mapping[str, Any], targets: object = None
) -> tuple[object, tuple, bool] | None:
    """(margin, obstacles, self_collision) of the check of the robot's configuration that
    ``options`` ask for on chains that share no joint, the margin as given (each chain's
    solve checks it); None where none is asked. With ``self_collision=True`` (or an
    ``armik.Collisions`` with it in a flat ``constraints`` list: then every ``Collisions``
    of the list together): each chain checks its own links, those another chain moves left
    out (``arms_apart``), so the robot checks its chains' answers together, the obstacles
    with them, and the closest pair it reports is the closest of all (``clear``,
    ``clear_rows``). With obstacles alone, where ``targets`` (``Arms.solve``'s, or tip ->
    rows) leave a tip out: no chain checked that tip's links at the values q0 keeps."""
    if not options or arms._union is not None:
        return None
    flag = options.get("self_collision")
    if isinstance(flag, (bool, np.bool_)) and flag:
        return options.get("margin", 0.0), check_obstacles(options.get("obstacles")), True
    given = options.get("constraints")
    found = []
    if given is not None and not isinstance(given, Mapping):  # by tip: each chain's own
        given = given if isinstance(given, (list, tuple)) else [given]
        found = [c for c in given if isinstance(c, Collisions)]
    # what they say together, as each chain checks it (``options._JOINED``): every scene
    # in their order, the largest margin kept by every pair
    shapes = tuple(s for c in found for s in c.obstacles)
    if any(c.self_collision for c in found):
        return max(c.margin for c in found), shapes, True
    if not found and options.get("obstacles") is None:
        return None
    tips = by_tip(arms._chains, targets)
    if not isinstance(tips, Mapping) or not set(arms.tips) - set(tips):
        return None  # every tip's chain checked its links against the obstacles
    if found:
        return max(c.margin for c in found), shapes, False
    shapes = check_obstacles(options.get("obstacles"))
    return (options.get("margin", 0.0), shapes, False) if shapes else None


def _checker(arms: Any, shapes: tuple, self_collision: bool = True) -> ArmsChecker:
    """The robot's checker of ``shapes`` (and its own links with ``self_collision``), kept
    per robot, one per set of obstacles (the last ``MOST_CHECKERS``)."""
    checkers = arms._checkers
    key = (shapes, self_collision)
    found = checkers.get(key)
    if found is None:
        if len(checkers) >= MOST_CHECKERS:
            checkers.clear()
        found = checkers[key] = ArmsChecker(arms, shapes, self_collision)
    return found


def clear(arms: Any, r: IKResult, asked: tuple[object, tuple, bool]) -> IKResult:
    """``r``, a joined result of chains that share no joint, with the robot's closest pair
    at ``r.q`` (``min_distance``, ``closest_pair``) of those ``asked`` (``between``): a
    ``Status.COLLISION`` failure where it is nearer than the margin."""
    if not r.success:
        return r
    d, pair = _checker(arms, asked[1], asked[2]).distance(np.asarray(r.q, dtype=float))
    m = checked.number("margin", asked[0])
    extra = {**r.extra, "min_distance": d, "closest_pair": pair}
    if d >= m:
        return dataclasses.replace(r, extra=extra)
    return dataclasses.replace(
        r,
        success=False,
        status=Status.COLLISION,
        reason=_words(arms, pair, d, m, r.extra.get("results", arms._chains)),
        extra=extra,
    )


def _words(arms: Any, pair: Pair | None, d: float, m: float, solved: Mapping) -> str:
    """The reason of a collision ``clear`` finds: between the chains' answers, or where
    some tip is not ``solved`` (a mapping by tip), at the values q0 keeps for its chain."""
    left = [t for t in arms.tips if t not in solved]
    return reasons.left_collide(pair, d, m, left) if left else reasons.apart_collide(pair, d, m)


def clear_or_other(
    arms: Any, r: IKResult, request: Any, targets: dict, relative: dict, q0: object
) -> IKResult:
    """``r`` where the options of ``request`` (``Arms.solve``'s, an ``ArmsRequest``) ask no
    check between the chains (``between``), else ``clear(arms, r, asked)``, or where the
    chains' answers collide with each other the nearest clear combination of every chain's
    answers (``solve_all``'s, ``kept``) for ``targets`` (parsed, with their ``relative``
    tasks) from ``q0``: another branch of one arm often keeps it out of the other's way.
    Tips placed relative to each other take each chain's answers in turn (``_in_turn``)."""
    options = request.options
    r = held(arms, r, left_out(arms, options, targets))  # a tip left out: its constraints
    asked = between(arms, options, targets)
    if asked is None:
        return r
    found = clear(arms, r, asked)
    if found.success or found.status is not Status.COLLISION:
        return found
    others = kept(arms, arms_every.solve_all(arms, request, targets, relative, q0), asked)
    return others[0] if others and others[0].success else found


def kept(
    arms: Any, results: list[IKResult], asked: tuple[object, tuple, bool] | None
) -> list[IKResult]:
    """``solve_all``'s answers (``results``) clear of each other (``clear``); where none
    is, the first of them as the failure it is (``clear``)."""
    if asked is None:
        return results
    each = [clear(arms, r, asked) for r in results]
    found = [r for r in each if r.success]
    return found or each[:1]


def clear_rows(arms: Any, out: BatchResult, asked: tuple[object, tuple, bool] | None) -> list[int]:
    """``clear`` on every successful row of ``out`` (a joined batch or path), in place: the
    rows it finds in collision."""
    if asked is None:
        return []
    found = []
    m = checked.number("margin", asked[0])
    own = _checker(arms, asked[1], asked[2])
    object.__setattr__(out, "margin", m)
    for i in np.flatnonzero(out.success).tolist():
        d, pair = own.distance(out.q[i])
        out.put_distance(i, d, pair)
        if d < m:
            out.success[i] = False
            out.status_code[i] = Status.COLLISION.code
            out.reasons[i] = _words(arms, pair, d, m, out.errors)
            found.append(i)
    return found
