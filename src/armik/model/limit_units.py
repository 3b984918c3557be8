"""A revolute joint's limits given to ``with_limits`` read as radians: a limit beyond four
turns each way (and beyond the joint's own limits) is taken for degrees and refused by
name, as ``hold=`` and ``locked=`` refuse a value beyond the limits."""

from __future__ import annotations

import math
from typing import Any

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
