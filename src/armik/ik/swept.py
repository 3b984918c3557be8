"""7R arms by one swept joint: joint 7 held, joints 1 to 6 in closed form.

Held at theta, joint 7 turns the tip about its axis, so joints 1-6 (with the tip at its
q = 0 pose M0, a geometry that does not change with theta) must reach
T6 = T_target G(theta), G(theta) the turn by -theta about joint 7's axis line in the tip
frame. Read from the tip back to the base, joints 6, 5, ..., 1 form a 6R chain that reaches
T6^-1 (joint j becomes joint 7 - j, its axis negated, its angle the same). When that chain
is in the spherical-wrist class (its last three axes meet: joints 3, 2, 1, a spherical
shoulder; and its first two meet: joints 6 and 5), as on the Franka Panda, its closed form
(``spherical.kernel``) gives every branch exactly.

``solve`` holds joint 7 at q0's value first, then at ``SWEEP`` values over its range,
nearest q0's first, and stops at the first value with an exact answer within the limits:
the answer keeps joint 7 as near q0 as the target allows. ``solve_all`` returns every
branch of that value of joint 7 (a redundant arm has infinitely many solutions: these are
the ones with joint 7 there). Every answer is verified by Pinocchio FK as always. Not
chosen by ``solver="auto"``; ask for it with ``solver="swept"``.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np

from ..arm import Arm
from ..options import Options
from ..status import Status
from ..structure import Axes, Chain6R, axis_lines, spherical_wrist_axes
from ..targets import Target
from . import sixr, spherical
from .attempt import Attempt
from .registry import SolverSpec, register

SWEEP = 32  # values of joint 7 tried after q0's, spread over its range


@dataclass(frozen=True)
class Swept:
    """The reversed 6R chain of joints 6 to 1 and joint 7's axis line in the tip frame."""

    geo: Chain6R
    variant: int  # spherical.kernel's: 0 axes 2, 3 parallel, 1 axes 1, 2 meeting
    c: np.ndarray  # a point on joint 7's axis (tip frame at q = 0), m
    u: np.ndarray  # joint 7's unit axis (tip frame)


def reversed_chain(arm: Arm) -> Swept | str:
    """The geometry ``solve`` sweeps over, or the reason this arm is not in the class."""
    if arm.dof != 7:
        return f"the chain has {arm.dof} joints, this solver needs 7"
    if np.any(arm.prismatic):
        return "the chain has a prismatic joint, this solver needs 7 revolute joints"
    ax = axis_lines(arm)
    Rt = ax.tip_rotation.T
    t = ax.tip_position
    order = (5, 4, 3, 2, 1, 0)  # joints 6 to 1
    reversed_axes = Axes(
        np.array([Rt @ (ax.points[j] - t) for j in order]),
        np.array([-(Rt @ ax.directions[j]) for j in order]),
        np.ones(6, dtype=bool),
        -(Rt @ t),
        Rt.copy(),
    )
    geo = spherical_wrist_axes(reversed_axes)
    if isinstance(geo, str):
        return f"with joint 7 held, joints 6 to 1 from the tip are not a spherical wrist: {geo}"
    variant = 0 if geo.variant == "parallel_23" else 1
    return Swept(geo, variant, Rt @ (ax.points[6] - t), Rt @ ax.directions[6])


_GEOMETRY: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def geometry(arm: Arm) -> Swept | str:
    geo = _GEOMETRY.get(arm)
    if geo is None:
        geo = _GEOMETRY[arm] = reversed_chain(arm)
    return geo


def applies(arm: Arm, target: Target | None = None, opts: Options | None = None) -> str | None:
    geo = geometry(arm)
    if isinstance(geo, str):
        return geo
    if target is not None and target.rotation is None:
        return "a position target leaves the orientation free; the closed form needs a full pose"
    if opts is not None and (opts.position_only or opts.weights is not None):
        return "position_only and per-axis weights are for the numeric solvers"
    return None


def _rotation(u: np.ndarray, angle: float) -> np.ndarray:
    """Rotation by ``angle`` about the unit axis ``u`` (Rodrigues)."""
    K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)


def thetas(arm: Arm, q7: float) -> list[float]:
    """q0's value of joint 7, then ``SWEEP`` values over its range, nearest to it first."""
    lo, hi = float(arm.lower[6]), float(arm.upper[6])
    if not (math.isfinite(lo) and math.isfinite(hi)):
        lo, hi = q7 - math.pi, q7 + math.pi
    grid = [lo + (hi - lo) * (k + 0.5) / SWEEP for k in range(SWEEP)]
    return [q7] + sorted(grid, key=lambda th: abs(th - q7))


def solve_held(arm: Arm, sw: Swept, R: np.ndarray, p: np.ndarray, q0: np.ndarray, theta: float,
               opts: Options) -> np.ndarray:  # fmt: skip
    """Every branch with joint 7 at ``theta``, nearest q0 first: ``sixr.pack``'s rows with
    the joint values mapped back to the 7R chain (q (7), flags, branch, code, values)."""
    Rg = _rotation(sw.u, -theta)
    R6 = R @ Rg
    p6 = R @ (sw.c - Rg @ sw.c) + p
    R_inv = np.ascontiguousarray(R6.T)
    p_inv = np.ascontiguousarray(-(R6.T @ p6))
    rev = slice(5, None, -1)
    out, _ = spherical.kernel(
        sw.geo.h, sw.geo.p, sw.geo.R_tip0, R_inv, p_inv,
        np.ascontiguousarray(q0[rev]), np.ascontiguousarray(arm.lower[rev]),
        np.ascontiguousarray(arm.upper[rev]), opts.tol_position, opts.tol_orientation,
        sw.variant, True,
    )  # fmt: skip
    rows = np.empty((out.shape[0], 12))
    rows[:, :6] = out[:, 5::-1]
    rows[:, 6] = theta
    rows[:, 7:] = out[:, 6:]
    return rows


def _attempts(rows: np.ndarray, theta: float) -> list[Attempt]:
    text = f"closed form with joint 7 held at {theta:.6g} rad (joints 6 to 1 as a spherical wrist)"
    result = []
    for row in rows:
        flags = int(row[7])
        singular = bool(flags & sixr.SINGULAR)
        if flags & sixr.LS:
            reason = sixr.reason(int(row[9]), row[10:12], spherical.FAMILY)
            claim = Status.UNREACHABLE
        else:
            reason, claim = sixr.claim_reason(text, singular), Status.CONVERGED
        result.append(Attempt(q=row[:7].copy(), claim=claim, reason=reason, singular=singular))
    return result


def run(
    arm: Arm, target: Target, q0: np.ndarray, opts: Options, all_solutions: bool
) -> list[Attempt]:
    sw = geometry(arm)
    R, p = sixr.pose_arrays(target)
    q0 = np.asarray(q0, dtype=float)
    first = None
    for theta in thetas(arm, float(q0[6])):
        rows = solve_held(arm, sw, R, p, q0, theta, opts)
        exact = [r for r in rows if not int(r[7]) & sixr.LS]
        inside = [r for r in exact if arm.within_limits(r[:7])]
        if first is None:
            first = (rows, theta)
        if inside:
            keep = np.array(exact if all_solutions else inside[:1])
            return _attempts(keep, theta)
    rows, theta = first  # nothing within the limits: q0's value, for the verdict's reasons
    return _attempts(rows if all_solutions else rows[:1], theta)


SPEC = register(
    SolverSpec(
        name="swept",
        kind="analytic",
        enforces_limits=True,
        priority=80,
        check=applies,
        run=run,
        summary="7R arms: joint 7 held (swept from q0's value), joints 6 to 1 in closed form",
        auto=False,
    )
)
