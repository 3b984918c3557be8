"""Keeping clear of collisions: ``armik.Collisions(obstacles=[...], self_collision=True,
margin=0.01)``, the constraint the options ``obstacles``, ``self_collision`` and ``margin``
spell. A check, not step rows: every answer's closest checked pair (coal's distances,
``armik.constraints.collision.Checker``) must be at least ``margin`` apart, else the
answer is ``Status.COLLISION`` naming that pair; numeric solvers restart from another
configuration (docs/collisions.md measures why restarts, not rows).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any

import numpy as np

from armik import reasons
from armik.constraints import carried
from armik.constraints.base import Check, Constraint
from armik.constraints.collision import checker
from armik.constraints.shapes import Shape, check_obstacles, flag, margin_of
from armik.errors import OptionError
from armik.frozen import frozen
from armik.status import Status

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


@dataclass(frozen=True)
class Collisions(Constraint):
    """Every checked pair ``margin`` (m) apart: the arm and ``obstacles`` (shapes in the
    base frame), and with ``self_collision`` the arm's own links."""

    obstacles: tuple[Shape, ...] = ()
    self_collision: bool = False
    margin: float = 0.0
    pose_only = True  # the links' placements: the same at every turn of an answer

    def __post_init__(self) -> None:
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        collision_options(values)
        for name, value in values.items():
            object.__setattr__(self, name, value)

    def said(self) -> dict[str, object]:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def check(self, arm: ArmModel, Q: np.ndarray) -> Check:
        check = checker(arm, self.obstacles, self.self_collision)
        return distances(check.distances(Q), self.margin)


def of_options(opts: Any) -> Collisions:
    """The collisions ``opts`` (``Options``, or the settings a solve reads: validated where
    they were read) check, as the constraint the verdict applies; built without reading
    them again (``frozen``)."""
    return frozen(
        Collisions,
        obstacles=opts.obstacles,
        self_collision=opts.self_collision,
        margin=opts.margin,
    )


def distances(found: list[tuple[float, Any]], margin: float) -> Check:
    """The check of N answers whose closest checked pairs are ``found`` ((distance m,
    pair) each): each must be at least ``margin`` apart, else ``Status.COLLISION``; the
    distance and pair go to each result's ``extra`` (``min_distance``, ``closest_pair``)."""
    return Check(
        np.array([d >= margin for d, _ in found], dtype=bool),
        Status.COLLISION,
        lambda i: _in_collision(found[i][1], found[i][0], margin),
        lambda i, reason: reasons.and_clear(reason, found[i][1], found[i][0], margin),
        lambda i: {"min_distance": found[i][0], "closest_pair": found[i][1]},
    )


def _in_collision(pair, distance: float, margin: float) -> str:
    """A collision's words, and what they say of a held link in ``pair`` (``carried``)."""
    said = carried.note(pair)
    text = reasons.in_collision(pair, distance, margin)
    return f"{text}; {said}" if said else text


def collision_check(check, Q, margin: float) -> Check:
    """The collision check of the answers ``Q`` by ``check`` (a ``Checker``)."""
    return distances([check.distance(q) for q in Q], margin)


def collision_options(values: dict[str, Any]) -> None:
    """Validate ``obstacles``, ``self_collision`` and ``margin`` in ``values``, in place."""
    if "obstacles" in values:
        values["obstacles"] = check_obstacles(values["obstacles"])
    if "self_collision" in values:
        values["self_collision"] = flag(values["self_collision"])
    if "margin" in values:
        margin = margin_of(values["margin"])
        if margin > 0 and not (values.get("obstacles") or values.get("self_collision")):
            raise OptionError(
                f"margin={margin:g} m with no obstacles and self_collision off checks "
                "nothing: give obstacles=[...] or self_collision=True",
                option="margin",
                value=margin,
            )
        values["margin"] = margin + 0.0
