"""Solver options: one validated, frozen record shared by every solver."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, fields
from typing import Any, TypeVar, cast

import numpy as np

from armik.checked import integer, number, numbers, positive
from armik.constraints.base import Constraint
from armik.constraints.clear import Collisions, collision_options, of_options
from armik.constraints.hold import Hold
from armik.constraints.limits import JointLimits
from armik.constraints.shapes import Shape
from armik.errors import OptionError, did_you_mean, listing
from armik.problem.budget import Budget
from armik.problem.scores import Posture
from armik.problem.settings import SolverSettings
from armik.tolerances import (
    MAX_COUNT,
    MAX_LENGTH,
    MAX_SOLUTIONS,
    MAX_TIMEOUT,
    MAX_WEIGHT,
    MIN_TOLERANCE,
)


@dataclass(frozen=True, eq=False)  # equal as SolverSettings says: by class and every field
class Options(SolverSettings):
    """Options accepted by ``Arm.solve`` and ``Arm.solve_all`` (units: m, rad, s): every
    field of ``SolverSettings`` (``armik.problem.settings``), and what the stages around a
    solver read:

    - ``obstacles``: shapes in the base frame (``armik.Box``, ``armik.HalfSpace``, ...)
      every answer must keep clear of; ``self_collision``: also the arm's own links (the
      URDF's ``<collision>`` geometry, minus adjacent links and an SRDF's pairs).
    - ``margin``: the distance (m) every checked pair must keep (0.0); needs obstacles or
      ``self_collision``.
    - ``hold``: ``{"joint_name": value, ...}`` (rad) holds those joints at those values and
      solves the others; a value of None holds one at q0's value. One joint of a 7-joint
      arm: a 6R chain (``armik.solve.held``); else the task solver. Stored as (name,
      value) pairs. Checked against the arm when solving.
    - ``swivel``: the elbow swivel angle (rad) of an SRS arm (the KUKA iiwa): every branch
      at that angle, the self-motion's one value (``armik.solve.parameter``; None: q0's, then
      swept). Not a joint, so not a ``hold``.
    - ``constraints``: the collisions and held joints as objects (``armik.Collisions``,
      ``armik.Hold``), spelled here as those options (``Options.constraints`` gives them
      back); a list of tasks honours them too, a ``Hold`` there on any arm. Any other
      constraint (a user's own ``armik.constraints.base.Constraint``) is kept in
      ``checks``.
    - ``slide``: a collision-checked numeric solve slides its first colliding answer out of
      contact before it restarts (False; a followed path sets it: the answer stays near
      the previous waypoint's, where a restart lands anywhere).
    """

    obstacles: tuple[Shape, ...] = ()
    self_collision: bool = False
    margin: float = 0.0
    hold: tuple[tuple[str, float | None], ...] | None = None
    swivel: float | None = None
    slide: bool = False

    @property
    def collisions(self) -> bool:
        """Whether answers are checked for collisions (obstacles or ``self_collision``)."""
        return bool(self.obstacles) or self.self_collision

    @property
    def constraints(self) -> tuple[Constraint, ...]:
        """The constraints these options spell: the joint limits, a held joint, the
        collisions (``armik.constraints``); what ``constraints=[...]`` gave them."""
        found: list[Constraint] = [JointLimits()]
        if self.hold is not None:
            found.extend(Hold(*pair) for pair in self.hold)
        if self.collisions:
            found.append(of_options(self))  # validated as they were read
        return (*found, *self.checks)

    @property
    def secondary(self) -> tuple[Posture, ...]:
        """The secondary tasks these options spell: the posture, if any."""
        return () if self.posture is None else (Posture(*self.posture),)

    @classmethod
    def from_kwargs(cls, kwargs: dict[str, Any]) -> Options:
        if not kwargs:
            return _DEFAULT
        if "constraints" in kwargs or "budget" in kwargs or "secondary" in kwargs:
            kwargs = spelled(kwargs)
        for key in kwargs:
            if key not in _NAMES:
                raise OptionError(
                    f"unknown option {key!r}; {did_you_mean(key, _LISTED)}options: "
                    f"{listing(sorted(_LISTED))}",
                    option=key,
                )
        values = dict(kwargs)
        for key, most, unit in _BOUNDED:
            if key in values:
                values[key] = positive(key, values[key], most, unit)
                if key.startswith("tol_") and values[key] < MIN_TOLERANCE:
                    raise OptionError(
                        f"{key}={values[key]!r} is below what double precision can verify: "
                        f"give a tolerance of at least {MIN_TOLERANCE:g} {unit} (1e-6 by "
                        "default)",
                        option=key,
                        value=values[key],
                    )
        for key in ("max_restarts", "max_iterations", "max_solutions"):
            if key in values:
                values[key] = integer(
                    key,
                    values[key],
                    minimum=0 if key == "max_restarts" else 1,
                    maximum=MAX_SOLUTIONS if key == "max_solutions" else MAX_COUNT,
                )
        if "nullspace_gain" in values:
            gain = number(key="nullspace_gain", value=values["nullspace_gain"])
            if not 0.0 <= gain <= 10.0:
                raise OptionError(
                    f"nullspace_gain must be in [0, 10], got {gain}",
                    option="nullspace_gain",
                    value=gain,
                )
            values["nullspace_gain"] = gain
        if values.get("iteration_budget") is not None:
            values["iteration_budget"] = integer(
                "iteration_budget", values["iteration_budget"], 1, MAX_COUNT
            )
        if values.get("seed") is not None:
            values["seed"] = integer("seed", values["seed"], minimum=0)
            if values["seed"] >= 2**63:  # the compiled restarts take a signed 64-bit seed
                raise OptionError(
                    f"seed must be < 2**63, got {values['seed']}: give a smaller seed",
                    option="seed",
                    value=values["seed"],
                )
        if "weights" in values and values["weights"] is not None:
            values["weights"] = checked_weights(values["weights"])
        if values.get("bounds") is not None:
            values["bounds"] = _bounds(values["bounds"])
        for name in ("position_only", "slide"):
            if name in values:
                flag = values[name]
                if not isinstance(flag, (bool, np.bool_)):
                    raise OptionError(
                        f"{name} must be True or False, got {flag!r}", option=name, value=flag
                    )
                values[name] = bool(flag)
        if values.get("bounds") is not None:
            _refuse_all_free(values)
        collision_options(values)
        if values.get("hold") is not None:
            held = Hold.parse(values["hold"])
            values["hold"] = tuple((h.joint, h.value) for h in held)
        if values.get("swivel") is not None:
            values["swivel"] = number("swivel", values["swivel"])
        if values.get("posture") is not None:  # checked as the Posture that spells it
            values["posture"] = _checked_posture(values["posture"])
        if values.get("checks"):
            values["checks"] = tuple(
                _checked(c, Constraint, "constraints", _CONSTRAINTS)  # type: ignore[type-abstract]
                for c in _items(values["checks"])
            )
        if "qp_solver" in values and not isinstance(values["qp_solver"], str):
            raise OptionError(
                f"qp_solver must be a backend name, got {values['qp_solver']!r}",
                option="qp_solver",
                value=values["qp_solver"],
            )
        return cls(**values)


_DEFAULT = Options()
# the options a call may give: every field its ``__init__`` takes (``cone``, ``look_at`` and
# ``toward`` are the target's aim: ``armik.solve.read`` takes them out first)
_NAMES = frozenset(f.name for f in fields(Options) if f.init) | {
    "constraints",
    "budget",
    "secondary",
}
_LISTED = _NAMES | {"cone", "look_at", "toward"}  # what a call may give, the aim's too


def spelled(kwargs: dict[str, Any]) -> dict[str, Any]:
    """``kwargs`` with ``constraints=[...]`` and ``budget=Budget(...)`` spelled as the
    options they stand for (``Constraint.said``, ``Budget.said``): an ``OptionError`` for
    what is not a constraint or a budget, and for an option given twice."""
    values = dict(kwargs)
    said: dict[str, Any] = {}
    if "budget" in values and values.pop("budget") is not None:  # None: not given, as any
        given = _checked(kwargs["budget"], Budget, "budget", "must be an armik.Budget")
        _add(said, values, given.said(), "the budget")
    if "constraints" in values:
        checks = list(values.pop("checks", ()))
        for item in _items(values.pop("constraints")):
            constraint = _checked(item, Constraint, "constraints", _CONSTRAINTS)  # type: ignore[type-abstract]
            _add(said, values, constraint.said(), "a constraint")
            if type(constraint) not in _SPELLED:  # its check is its own: every verdict runs it
                checks.append(constraint)
        if checks:
            values["checks"] = tuple(checks)
    if "secondary" in values:
        for item in _items(values.pop("secondary")):
            posture = _checked(item, Posture, "secondary", "holds one armik.Posture(q_ref)")
            _add(said, values, posture.said(), "a secondary task")
    return {**values, **said}


def _checked_posture(value: object) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The option ``posture`` (q_ref, weights) as the ``Posture`` that spells it checks it."""
    if not isinstance(value, tuple) or len(value) != 2:
        raise OptionError(
            f"posture must be (q_ref, weights): say it as secondary=[armik.Posture(q_ref)], "
            f"got {value!r}",
            option="posture",
            value=value,
        )
    return Posture(*value).said()["posture"]  # type: ignore[return-value]


_CONSTRAINTS = "holds constraints (armik.Hold, armik.Collisions, or a Constraint of your own)"
# the constraints whose options say all they check (``said``); any other is kept as itself
_SPELLED = (JointLimits, Hold, Collisions)
_T = TypeVar("_T")


def _checked(value: object, kind: type[_T], option: str, what: str) -> _T:
    """``value`` where it is a ``kind``; an ``OptionError`` naming it otherwise."""
    if not isinstance(value, kind):
        raise OptionError(f"{option} {what}, got {value!r}", option=option, value=value)
    return value


def _items(given: object) -> list[object]:
    """The items of ``constraints=`` or ``secondary=``: one, an iterable of them, or None
    (none, as None is for every option)."""
    if given is None:
        return []
    if isinstance(given, Constraint) or isinstance(given, (str, bytes, Mapping)):
        return [given]
    try:
        return list(cast(Iterable[object], given))
    except TypeError:
        return [given]


def _add(said: dict[str, Any], values: dict[str, Any], more: dict[str, object], by: str) -> None:
    """``more`` (said ``by`` an object) added to ``said``: an ``OptionError`` for an
    option said before by another object or given as itself too."""
    for name, value in more.items():
        if name == "hold" and name in said and name not in values:  # several held joints
            for joint in value:  # type: ignore[attr-defined]
                if joint in said["hold"]:
                    raise OptionError(
                        f"{joint} is held twice (two armik.Hold constraints): hold it once",
                        option="hold",
                        value=joint,
                    )
            said["hold"] = {**said["hold"], **value}  # type: ignore[dict-item]
            continue
        if name in _JOINED and name in said and name not in values:  # two armik.Collisions
            said[name] = _JOINED[name](said[name], value)
            continue
        if name in said or name in values:
            raise OptionError(_twice(name, by, name in said), option=name, value=value)
        said[name] = value


# what two ``armik.Collisions`` say together: both scenes, either's self-collision, the
# larger margin (kept by every pair, it keeps each constraint's)
_JOINED: dict[str, Callable[[Any, Any], Any]] = {
    "obstacles": lambda a, b: (*_items(a), *_items(b)),
    "self_collision": lambda a, b: a or b,
    "margin": max,
}


def _twice(name: str, by: str, by_two: bool) -> str:
    how = f"by {by} and by another" if by_two else f"by {by} and as an option"
    return f"{name} is given twice ({how}): give it once"


# (option, largest value, unit): a tolerance beyond these passes every answer; a timeout
# beyond MAX_TIMEOUT overflows the kernel's budget in nanoseconds
_BOUNDED = (
    ("tol_position", MAX_LENGTH, "m"),
    ("tol_orientation", math.pi, "rad"),
    ("timeout", MAX_TIMEOUT, "s"),
)


def checked_weights(value: object) -> tuple[float, ...]:
    """The option ``weights`` as 6 floats; ``OptionError`` naming the rule otherwise (the
    servo reads a task's weights by the same rule)."""
    w = numbers(value)
    if (
        w.shape != (6,)
        or not np.all(np.isfinite(w))
        or np.any(w < 0)
        or not np.any(w > 0)
        or np.any(w > MAX_WEIGHT)
        or w.max() > MAX_WEIGHT * w[w > 0].min()
    ):
        raise OptionError(
            f"weights must be 6 finite non-negative numbers (x, y, z, rx, ry, rz), "
            f"not all zero, at most {MAX_WEIGHT:g} and at most {MAX_WEIGHT:g} times the "
            f"smallest positive one (only their ratios and zeros matter); got {value!r}",
            option="weights",
            value=value,
        )
    return tuple(float(v) for v in w)


def _refuse_all_free(values: dict[str, Any]) -> None:
    """An ``OptionError`` where the bounds, with the weights and ``position_only``, leave
    every component of the pose free: any configuration would hold it, a success that
    says nothing."""
    free = np.isinf(values["bounds"])
    if values.get("weights") is not None:
        free |= np.asarray(values["weights"]) == 0.0
    if values.get("position_only"):
        free[3:] = True
    if free.all():
        raise OptionError(
            f"bounds={values['bounds']!r} leave every component of the pose free (with "
            "the weights and position_only given): any configuration holds it; bound at "
            "least one component, or solve for a position (a 3-vector) or a rotation alone",
            option="bounds",
            value=values["bounds"],
        )


def _bounds(value: object) -> tuple[float, ...]:
    """6 bounds >= 0 (m, m, m, rad, rad, rad), ``inf`` allowed (a free axis)."""
    b = numbers(value)
    # a finite bound beyond any reach is a free axis said as a number: its square overflows
    if (
        b.shape != (6,)
        or np.isnan(b).any()
        or (b < 0).any()
        or (np.isfinite(b) & (b > MAX_LENGTH)).any()
    ):
        raise OptionError(
            "bounds must be 6 numbers >= 0 and at most 1e6 (bx, by, bz in m, brx, bry, brz in "
            "rad: how far each component of the error may lie on either side; math.inf frees "
            f"it); got "
            f"{value!r}",
            option="bounds",
            value=value,
        )
    return tuple(float(v) for v in b)
