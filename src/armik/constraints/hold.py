"""A held joint: ``armik.Hold("joint_3", 0.5)`` keeps that joint at that value (rad or m)
and solves the others; ``armik.Hold("joint_3")`` keeps it at q0's value (the middle of its
limits without q0). The old spelling is the option ``hold={"joint_3": 0.5}``.

A held joint is the box row ``value <= q_j <= value`` of every step, and its check an
answer with that joint at the value. Several may be held (``hold={"a": 0.1, "b": None}``).
The compiled path solves a 7-joint arm with one joint held as a 6R chain
(``armik.solve.held``); the task solver holds any joints of any arm, a plain pose or
position given as its task.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from armik import reasons
from armik.constraints.base import Check, Constraint
from armik.errors import JointError, OptionError, did_you_mean, listing
from armik.model.mimic import not_a_joint
from armik.status import Status
from armik.tolerances import LIMIT_TOL

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


@dataclass(frozen=True)
class Hold(Constraint):
    """Joint ``joint`` held at ``value`` (rad or m; None: q0's value)."""

    joint: str
    value: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.joint, str):
            raise OptionError(
                f"Hold's joint must be a joint's name, got {self.joint!r}: e.g. "
                "armik.Hold('joint_3', 0.5)",
                option="hold",
                value=self.joint,
            )
        if self.value is not None:
            object.__setattr__(self, "value", _finite(self.joint, self.value))

    @classmethod
    def parse(cls, value: object) -> tuple[Hold, ...]:
        """The ``Hold``s of the option ``hold={"joint": value, ...}`` (one entry a joint)."""
        items = list(value.items()) if isinstance(value, Mapping) else None
        if not items or not all(isinstance(name, str) for name, _ in items):
            raise OptionError(
                f"hold must map joint names to their values (rad) or None (q0's value), "
                f"e.g. {{'joint_3': 0.5}}; got {value!r}",
                option="hold",
                value=value,
            )
        return tuple(cls(*item) for item in items)

    def said(self) -> dict[str, object]:
        return {"hold": {self.joint: self.value}}

    def index(self, arm: ArmModel) -> int:
        """The held joint's index among the arm's joints; a ``JointError`` saying why it is
        no joint of the arm (``not_free``), or naming the arm's joints."""
        if self.joint in arm.joint_names:
            return arm.joint_names.index(self.joint)
        why = self.not_free(arm) or self.off_chain(arm)
        if why is None:
            why = (
                f"hold: unknown joint {self.joint!r}; {did_you_mean(self.joint, arm.joint_names)}"
                f"the arm's joints: {listing(arm.joint_names)}"
            )
        raise JointError(why, joint=self.joint, candidates=arm.joint_names)

    def not_free(self, arm: ArmModel) -> str | None:
        """Why the held joint, a joint of ``arm``'s URDF but none of its free joints, cannot be
        held: it is locked, or a mimic joint (following a driver on the chain, or fixed
        there); None for any other name."""
        name = self.joint
        if name in arm.locked:
            at = arm.locked[name]
            return (
                f"hold: joint {name!r} is locked at {at!r} (locked=, --lock), not free: it "
                f"already stays at {at!r}; leave it out of hold=, or load the arm without "
                "locking it to hold it at another value"
            )
        m = next((m for m in arm.mimics if m.name == name), None)
        if m is not None:
            where = ""
            if self.value is not None:  # the driver's value that puts it at the held one
                driver = (self.value - m.offset) / m.multiplier
                where = f" ({m.driver} = {driver:g} holds {name} at {self.value:g})"
            return (
                f"hold: joint {name!r} is a mimic joint following {m.driver!r} on the chain to "
                f"{arm.tip!r} ({name} = {m.multiplier:g} x {m.driver} + {m.offset:g}): its "
                f"driver sets its value; hold {m.driver!r} instead{where}"
            )
        if name in (arm.chain.fixed_mimics or {}):
            return f"hold: joint {name!r} {not_a_joint(arm, name)}; leave it out of hold="
        return None

    def off_chain(self, arm: ArmModel) -> str | None:
        """Why the held joint, a joint of ``arm``'s URDF, cannot be held: a fixed joint, or a
        moving joint off the chain; None for any other name."""
        name, kind = self.joint, arm.info.joint_types.get(self.joint)
        if kind == "fixed":
            return f"hold: joint {name!r} is a fixed joint: it has no value to hold"
        if kind is None:
            return None
        return (
            f"hold: joint {name!r} is not on this arm's chain from {arm.base!r} to "
            f"{arm.tip!r} (joints {listing(arm.joint_names)}): off it, it is a fixed "
            f"transform at its neutral value; set that with arm.with_locked({{{name!r}: value}})"
        )

    def at(self, arm: ArmModel, seed: np.ndarray) -> Hold:
        """The hold at its value (the seed's where it has none), which must lie within the
        joint's limits (clipped to them within ``LIMIT_TOL``)."""
        k = self.index(arm)
        value = float(seed[k]) if self.value is None else self.value
        lo, hi = float(arm.lower[k]), float(arm.upper[k])
        if not lo - LIMIT_TOL <= value <= hi + LIMIT_TOL:
            unit = "m" if arm.prismatic[k] else "rad"
            # the limits to as many digits as tell them from a value just outside
            raise JointError(
                f"hold: {value!r} {unit} is outside joint {self.joint!r}, whose limits are "
                f"[{lo:.10g}, {hi:.10g}] {unit}: give a value within them",
                joint=self.joint,
            )
        return Hold(self.joint, min(max(value, lo), hi))

    def box(self, arm: ArmModel) -> tuple[np.ndarray, np.ndarray]:
        k, value = self.index(arm), self._value()
        lo, hi = arm.lower.copy(), arm.upper.copy()
        lo[k] = hi[k] = value
        return lo, hi

    def check(self, arm: ArmModel, Q: np.ndarray) -> Check:
        k, value = self.index(arm), self._value()
        ok = np.abs(Q[:, k] - value) <= HELD_TOL
        return Check(
            ok,
            Status.NOT_CONVERGED,
            lambda i: reasons.off_hold(self.joint, float(Q[i, k]), value),
            lambda i, reason: reasons.and_held(reason, self.joint, value),
        )

    def _value(self) -> float:
        if self.value is None:
            raise OptionError(
                f"Hold({self.joint!r}) takes its value from q0: resolve it with "
                "Hold.at(arm, seed) before its box or check",
                option="hold",
                value=self.joint,
            )
        return self.value


HELD_TOL = 1e-9  # rad or m: a held joint this near its value holds (the step puts it there)


def _finite(joint: str, value: object) -> float:
    """A held joint's value as a finite float; an ``OptionError`` naming it otherwise."""
    try:
        if isinstance(value, (str, bytes, bool, np.bool_)):
            raise TypeError
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        out = math.nan
    if not math.isfinite(out):
        raise OptionError(
            f"hold's value for joint {joint!r} must be a finite number (rad) or None (q0's "
            f"value), got {value!r}",
            option="hold",
            value=value,
        )
    return out
