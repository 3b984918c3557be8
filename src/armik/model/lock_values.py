"""The value a joint is locked at (``locked=``, ``with_locked``, and ``hold=`` through the
arm with its joint locked), checked: a finite number within the joint's limits, and on a
revolute or continuous joint within four turns each way where it has no limit there (a
value beyond, 170 say, is degrees by mistake, refused by name as ``with_limits`` refuses
such a limit, ``limit_units``).

The limits are the URDF's, unless the caller checked the value against the arm's own
(``with_limits`` may widen them): ``arm_limits`` says so for the joints it names.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar

import numpy as np
import pinocchio as pin

from armik.errors import JointError
from armik.model.limit_units import MAX_ANGLE
from armik.model.urdf import URDFInfo
from armik.tolerances import LIMIT_TOL, MAX_LIMIT

# Values that float() reads but that are no joint value: text, complex, bools (True is 1)
NOT_NUMBERS = (str, bytes, complex, bool, np.bool_)

# joint name -> (lower, upper): the arm's own limits, which stand in for the URDF's
_ARM_LIMITS: ContextVar[Mapping[str, tuple[float, float]] | None] = ContextVar(
    "arm_limits", default=None
)


@contextmanager
def arm_limits(limits: Mapping[str, tuple[float, float]]) -> Iterator[None]:
    """Within it, a joint named in ``limits`` is locked within those limits (an arm's own,
    ``with_limits``', which its caller checked the value against) instead of the URDF's."""
    token = _ARM_LIMITS.set({**(_ARM_LIMITS.get() or {}), **limits})
    try:
        yield
    finally:
        _ARM_LIMITS.reset(token)


def locked_value(full: pin.Model, info: URDFInfo, jid: int, value: object) -> float:
    """``value`` as the float a joint is locked at (rad or m). Raises ``JointError`` naming
    the joint, the value and the limits when it is not a finite number, lies outside the
    joint's URDF limits (or the arm's, ``arm_limits``; a continuous joint, or a side
    without a limit, takes any value), or is more than four turns on a revolute or
    continuous joint without a limit there (degrees by mistake: the radians meant named)."""
    jname = full.names[jid]
    try:
        # never parse text, drop an imaginary part, or read True as 1 rad
        if isinstance(value, NOT_NUMBERS) or np.iscomplexobj(value):  # type: ignore[arg-type]
            raise TypeError
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):  # OverflowError: an int beyond 1e308
        number = math.nan
    if not math.isfinite(number):
        raise JointError(
            f"locked value for {jname!r} must be a finite number (rad or m), got {value!r}",
            joint=jname,
        )
    joint = full.joints[jid]
    kind = info.joint_types.get(jname, "revolute")
    lo, hi, whose = -math.inf, math.inf, "URDF"
    arms = _ARM_LIMITS.get() or {}
    if jname in arms:
        (lo, hi), whose = arms[jname], "arm's"
    elif joint.nq == 1 and jname not in info.unset_limits:  # not continuous, nor "0 0"
        lo = float(full.lowerPositionLimit[joint.idx_q])
        hi = float(full.upperPositionLimit[joint.idx_q])
        lo = lo if lo >= -MAX_LIMIT else -math.inf  # beyond MAX_LIMIT: free on that side
        hi = hi if hi <= MAX_LIMIT else math.inf
    if not lo - LIMIT_TOL <= number <= hi + LIMIT_TOL:
        unit = "m" if kind == "prismatic" else "rad"
        raise JointError(
            f"locked value {number:.10g} {unit} for {jname!r} is outside its {whose} limits "
            f"[{lo:.10g}, {hi:.10g}] {unit}: lock it at a value within them",
            joint=jname,
        )
    if kind != "prismatic":
        beyond_turns("locked value", jname, kind, number, lo, hi)
    return number


def beyond_turns(what: str, jname: str, kind: str, value: float, lo: float, hi: float) -> None:
    """``JointError`` for ``value`` on a revolute or continuous joint (limits ``lo``,
    ``hi``, rad, each -inf/inf without one) beyond four turns each way and beyond its
    limits: degrees by mistake, the radians meant named."""
    bound = max([MAX_ANGLE, *(abs(v) for v in (lo, hi) if math.isfinite(v))])
    if abs(value) > bound:
        raise JointError(
            f"{what} {value:g} rad for {kind} joint {jname!r} is "
            f"{abs(value) / (2 * math.pi):.3g} turns, beyond +-{bound:.4g} rad (4 turns each "
            f"way): radians are meant; {value:g} degrees is {math.radians(value):.6g} rad",
            joint=jname,
        )
