"""Each chain of a robot of several tips (``armik.Arms``) as its solves that check
collisions read it: the chain's model, the links another chain moves left out of its
collision geometry.

A chain alone (``robot.chain(tip)``) holds the other chains where it was cut: their links
are part of its scene, fixed to its base or carried by its own joints. Within the robot
another chain moves them: that chain checks them against the obstacles, and with
``self_collision`` the robot checks the chains' answers against each other
(``armik.arms_collision``). So a chain's solve with collisions on chains that share no
joint takes a copy of its model (its kinematics, limits and solvers the chain's) whose
geometry leaves out the objects another chain places (``arms_links.moved_elsewhere``);
``robot.chain(tip)`` is left as it is.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any, Protocol

from armik.arms_links import moved_elsewhere
from armik.constraints.base import Constraint
from armik.constraints.clear import Collisions
from armik.model.arm_model import ArmModel
from armik.model.union import Union


class Chains(Protocol):
    """What ``chains`` reads and keeps of a robot (``armik.arms_kinematics.ArmsKinematics``,
    which stands on this module through its collisions: a protocol, not that class)."""

    tips: tuple[str, ...]
    _chains: dict[str, ArmModel]
    _union: Union | None  # the chains in one model where they share joints
    _apart: dict[str, ArmModel] | None


def asks(options: Mapping[str, Any] | None) -> bool:
    """Whether one chain's ``options`` (``ArmsRequest.each``'s) check collisions."""
    if not options:
        return False
    if options.get("obstacles") is not None or options.get("self_collision"):
        return True
    given = options.get("constraints")
    items = [given] if isinstance(given, Constraint) else given
    return isinstance(items, (list, tuple)) and any(isinstance(c, Collisions) for c in items)


def chains(arms: Chains, each: Mapping[str, Mapping[str, Any]] | None) -> dict[str, ArmModel]:
    """The model each chain's solve with its options ``each`` (tip -> options) takes:
    ``arms._chains`` unless they check collisions on chains that share no joint (then
    ``arms._apart``, built on the first such solve)."""
    if arms._union is not None or not each or not any(asks(o) for o in each.values()):
        return arms._chains
    found = arms._apart
    if found is None:
        tips = list(arms.tips)
        left = moved_elsewhere([arms._chains[t] for t in tips])
        found = arms._apart = {t: _without(arms._chains[t], out) for t, out in zip(tips, left)}
    return found


def model(arms: Any, tip: str, options: Mapping[str, Any] | None) -> ArmModel:
    """The model ``tip``'s chain solves with ``options`` (its own) on."""
    return chains(arms, {tip: options} if options else None)[tip]


def facade(arms: Any, tip: str, options: Mapping[str, Any] | None) -> Any:
    """The ``Arm`` ``tip``'s chain solves with ``options`` (its own) as: ``arms.chain(tip)``,
    or one on the chain's model within the robot (``chains``)."""
    arm = arms.chain(tip)
    found = model(arms, tip, options)
    return arm if found is arm.kinematics else type(arm)(found)


@dataclass(frozen=True)
class InRobot:
    """How a chain's model within a robot is built again (as it pickles: an ``ArmModel``
    travels as its recipe): the chain's own recipe, the objects left out, the limits
    replaced since (``ArmModel.with_limits`` replaces them here, as in a ``Recipe``)."""

    recipe: Any
    left_out: frozenset[str]
    limits: tuple[tuple[str, float, float], ...]

    @property
    def text(self) -> str | None:  # the viewer reads the URDF of an arm read from text
        return self.recipe.text  # type: ignore[no-any-return]

    def build_model(self) -> ArmModel:
        return _without(replace(self.recipe, limits=self.limits).build_model(), self.left_out)

    def locked_model(self, locked: object, example: str) -> ArmModel:
        """The chain's model with ``locked`` locked too, within the robot as this one is."""
        chain = replace(self.recipe, limits=self.limits)
        return _without(chain.locked_model(locked, example), self.left_out)


def _without(arm: ArmModel, left_out: frozenset[str]) -> ArmModel:
    """A copy of ``arm`` whose collision geometry leaves out the objects ``left_out``
    (``arm`` itself when there are none)."""
    if not left_out:
        return arm
    copy = arm.with_limits({})  # the same limits, nothing derived kept
    copy.left_out = left_out
    if arm._recipe is not None:
        copy._recipe = InRobot(arm._recipe, left_out, arm._recipe.limits)
    return copy
