"""Revolute joints read in radians. A limit given to ``with_limits`` beyond four turns each
way (and beyond the joint's own limits) is taken for degrees and refused by name, as
``hold=`` and ``locked=`` refuse a value beyond the limits. A joint value by the same rule
(a q0, a posture's reference, what fk is given) on a joint with limits is said in degrees'
radians (``degrees_note``): it is no angle the joint can hold, and degrees by the look of
it; a joint without limits (continuous) may turn any number of times."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from armik.errors import JointError

MAX_ANGLE = 8.0 * math.pi  # rad: four turns each way; beyond it a limit reads as degrees


def in_radians(checked: dict[str, tuple[float, float]], arm: Any) -> dict[str, tuple[float, float]]:
    """``checked`` (joint name -> (lower, upper), ``reduce.check_limits``'), each revolute or
    continuous joint's finite limits within +-``MAX_ANGLE`` rad or within its limits on
    ``arm`` (a URDF's multi-turn joint narrowed); ``JointError`` naming the joint, the value
    and the fix otherwise. A prismatic joint's (m) are as given; -inf/inf mean no limit."""
    for jname, (lo, hi) in checked.items():
        k = arm.joint_index(jname)
        if arm.prismatic[k]:
            continue
        own = [abs(float(v)) for v in (arm.lower[k], arm.upper[k]) if math.isfinite(v)]
        bound = max([MAX_ANGLE, *own])
        far = [v for v in (lo, hi) if math.isfinite(v) and abs(v) > bound]
        if far:
            rad = tuple(math.radians(v) if math.isfinite(v) else v for v in (lo, hi))
            raise JointError(
                f"limits for {jname!r}: {far[0]:g} rad is {abs(far[0]) / (2 * math.pi):.3g} "
                f"turns of a {arm.joint_types[k]} joint, beyond +-{bound:.4g} rad "
                f"({bound / (2 * math.pi):.3g} turns each way, its own limits or 4): "
                f"radians are meant; for ({lo:g}, {hi:g}) degrees give ({rad[0]:.6g}, "
                f"{rad[1]:.6g}), and -inf/inf for a joint that turns without a limit",
                joint=jname,
            )
    return checked


def degrees_note(values: Sequence[float] | Any, arm: Any) -> str:
    """``"; radians are meant: ..."`` naming each revolute joint of ``arm`` (its
    ``joint_names``, ``lower``, ``upper``, ``prismatic``) with finite limits whose value in
    ``values`` lies beyond +-``MAX_ANGLE`` and beyond those limits, and that value read as
    degrees, in radians; "" where there is none (or ``values`` is not one per joint)."""
    values = values.tolist() if isinstance(values, np.ndarray) else [float(v) for v in values]
    if len(values) != len(arm.joint_names) or max(map(abs, values), default=0.0) <= MAX_ANGLE:
        return ""
    said = []
    for name, v, lo, hi, linear in zip(
        arm.joint_names, values, arm.lower.tolist(), arm.upper.tolist(), arm.prismatic.tolist()
    ):
        limited = math.isfinite(lo) and math.isfinite(hi)
        if not linear and limited and abs(v) > max(MAX_ANGLE, abs(lo), abs(hi)):
            said.append(f"{name} {v:g} ({math.radians(v):.6g} rad)")
    if not said:
        return ""
    return (
        "; radians are meant: beyond 4 turns each way and their limits, these read as "
        f"degrees: {', '.join(said)}"
    )
