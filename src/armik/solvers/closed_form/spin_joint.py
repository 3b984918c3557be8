"""A spin that is the last joint's own: exact, so ``auto`` takes it for one answer too.

Where turning the arm's last joint turns the tool about the very axis the bounds free
(the tool's z on the flange of most 6R arms: that joint's axis, through the tool's
origin), the family of poses ``T R_k(t)`` over the spin is the last joint's range: each
branch of the closed form at ``T`` itself, its last joint moved by the spin. So every
admissible answer over the whole range comes from one closed-form call: each branch with
its last joint at the value nearest q0's within +- the bound of the branch's and within
the limits. The nearest of them is the admissible answer nearest q0 over the range; with
``solve_all``, each branch's. Elsewhere ``spin`` sweeps the angle (a search).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pinocchio as pin

from armik.model.arm_model import ArmModel
from armik.options import Options
from armik.solvers import registry
from armik.solvers.claims import Attempt
from armik.solvers.closed_form import spin
from armik.status import Status
from armik.targets.pose import Target

_ALIGNED = "spin axes that are the last joint's"  # the arm's memo key


def aligned(arm: ArmModel, k: int) -> bool:
    """Whether turning the last joint turns the tip about its own axis ``k`` through its
    origin (on Pinocchio's FK, at two configurations; either sense)."""
    if arm.prismatic[-1]:
        return False
    axis = np.eye(3)[k]
    for q in (arm.middle, arm.middle + 0.37):
        turned = q.copy()
        turned[-1] += 0.4
        T0, T1 = arm.fk(q), arm.fk(turned)
        if not any(
            (T0 * pin.SE3(pin.exp3(s * 0.4 * axis), np.zeros(3))).isApprox(T1, 1e-9)
            for s in (1.0, -1.0)
        ):
            return False
    return True


def applies(arm: ArmModel, target: Target | None = None, opts: Options | None = None) -> str | None:
    why = spin.applies(arm, target, opts)
    if why is not None:
        return why
    k, _ = spin.spin_of(opts.bounds)  # type: ignore[misc,union-attr]  # spin.applies checked it
    if not arm.memo((_ALIGNED, k), lambda a: aligned(a, k)):
        return (
            f"turning the last joint does not turn the tool about its {spin.AXES[k]} axis "
            "(the 'spin' solver sweeps that angle instead)"
        )
    return None


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: Options, all_solutions: bool
) -> list[Attempt]:
    k, half = spin.spin_of(opts.bounds)  # type: ignore[misc]  # applies() checked it
    family = spin.family(arm, target)
    assert not isinstance(family, str)  # applies() checked it
    rows = family.run(arm, target, q0, dataclasses.replace(opts, bounds=None), True)
    reached = [a for a in rows if a.claim is Status.CONVERGED]
    last, turned, ok = _turned(arm, reached, float(q0[-1]), half)
    if not ok.any():  # the closed form is complete: no branch, no answer over the range
        return [
            Attempt(
                q=np.array(q0, dtype=float),
                claim=Status.JOINT_LIMITS if reached else Status.UNREACHABLE,
                reason=f"no branch of {family.name} reaches the target with its last joint "
                f"within +-{half:g} rad of the spin and every joint within its limits; q is q0",
            )
        ]
    Q = np.array([a.q for a in reached], dtype=float)
    Q[:, -1] = last
    distance = np.where(ok, np.linalg.norm(Q - q0, axis=1), np.inf)
    order = np.argsort(distance, kind="stable")[: int(ok.sum())]
    axis = spin.AXES[k]
    return [
        dataclasses.replace(
            reached[i],
            q=Q[i],
            reason=f"{family.name}, the spin about the target's {axis} axis turned by the "
            f"last joint ({turned[i]:.6g} rad): nearest q0 over the range",
        )
        for i in (order if all_solutions else order[:1])
    ]


def _turned(
    arm: ArmModel, reached: list[Attempt], q0_last: float, half: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per branch: the last joint's value nearest ``q0_last`` within +-``half`` of the
    branch's value or of one of its 2 pi turns (the same spin) and within the limits, the
    turn that takes, and whether such a value exists with every joint within the limits."""
    lo, hi = float(arm.lower[-1]), float(arm.upper[-1])
    # a full turn is every value of the joint; else the windows about the branch's value
    # and its turns (a joint may span 4 pi); plain floats: a handful of branches
    shifts = (0.0,) if half >= math.pi else tuple(2 * math.pi * k for k in (0, -1, 1, -2, 2))
    last, turned, ok = [], [], []
    for a in reached:
        centre = float(a.q[-1])
        best, gap = math.nan, math.inf
        for shift in shifts:
            low, high = (
                (lo, hi)
                if half >= math.pi
                else (
                    max(centre + shift - half, lo),
                    min(centre + shift + half, hi),
                )
            )
            value = min(max(q0_last, low), high)
            if low <= high and abs(value - q0_last) < gap:
                best, gap = value, abs(value - q0_last)
        q = a.q.copy()
        q[-1] = best
        last.append(best)
        # the spin the answer turns through: from the branch's value, modulo whole turns
        turned.append(abs(math.remainder(best - centre, 2 * math.pi)) if gap < math.inf else 0.0)
        ok.append(gap < math.inf and arm.within_limits(q))
    return np.array(last), np.array(turned), np.array(ok, dtype=bool)


SPEC = registry.register(
    registry.SolverSpec(
        name="spin_joint",
        kind="analytic",
        enforces_limits=True,
        priority=86,
        why_not=applies,
        run=run,
        summary="a free or bounded spin that is the last joint's: every branch, exactly",
    )
)
