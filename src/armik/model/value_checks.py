"""A joint's value against its limits: a value to lock a joint at, checked against the arm's
own limits (``with_limits``' where it gave them, else the URDF's), and a value outside the
limits said in words."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from armik.errors import JointError
from armik.model.urdf import URDFInfo
from armik.tolerances import LIMIT_TOL, MAX_LIMIT

TWO_PI = 2.0 * math.pi

# Values that float() reads but that are no joint value: text, complex, bools (True is 1)
NOT_NUMBERS = (str, bytes, complex, bool, np.bool_)


def locked_value(
    full: pin.Model, info: URDFInfo, jid: int, value: object, own: tuple[float, float] | None
) -> float:
    """``value`` as the float a joint is locked at (rad or m). Raises ``JointError`` naming
    the joint, the value and the limits when it is not a finite number or lies outside the
    joint's limits: ``own`` (lower, upper), those ``with_limits`` gave the arm, else the
    URDF's. A continuous joint takes any value (an encoder's several turns), or with limits
    of its own, an angle one of whose turns lies within them; a side without a limit any."""
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
    if own is not None:
        lo, hi = own
        near = number
        if joint.nq == 2 and math.isfinite(lo):  # continuous: its first turn above lower
            near = number + TWO_PI * math.ceil((lo - LIMIT_TOL - number) / TWO_PI)
        elif joint.nq == 2:  # continuous without a lower limit: some turn lies below upper
            near = min(number, hi)
        whose = "limits (given by with_limits)"
    elif joint.nq != 1 or jname in info.unset_limits:  # continuous, or limits "0 0"
        return number
    else:
        lo = float(full.lowerPositionLimit[joint.idx_q])
        hi = float(full.upperPositionLimit[joint.idx_q])
        lo = lo if lo >= -MAX_LIMIT else -math.inf  # beyond MAX_LIMIT: free on that side
        hi = hi if hi <= MAX_LIMIT else math.inf
        near, whose = number, "URDF limits"
    if not lo - LIMIT_TOL <= near <= hi + LIMIT_TOL:
        unit = "m" if info.joint_types.get(jname) == "prismatic" else "rad"
        raise JointError(
            f"locked value {number:.10g} {unit} for {jname!r} is outside its {whose} "
            f"[{lo:.10g}, {hi:.10g}] {unit}: lock it at a value within them",
            joint=jname,
        )
    return number


def violation(name: str, v: float, lo: float, hi: float) -> str:
    """Joint ``name`` at ``v`` outside [``lo``, ``hi``], in words: the value and the limits to
    six digits; how far past which limit where six digits would hide it."""
    if float(f"{lo:.6g}") <= float(f"{v:.6g}") <= float(f"{hi:.6g}"):  # (False for NaN)
        side, limit, by = ("upper", hi, v - hi) if v > hi else ("lower", lo, lo - v)
        return f"{name} is {by:.2g} past its {side} limit {limit:.6g}"  # 1e-09 past 2.87979
    return f"{name} = {v:.6g} outside [{lo:.6g}, {hi:.6g}]"
