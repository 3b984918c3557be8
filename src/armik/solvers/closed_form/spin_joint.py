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
    lo, hi = arm.lower[-1], arm.upper[-1]
    found = []
    for a in rows:
        if a.claim is not Status.CONVERGED:
            continue
        # a full turn (half = pi) is every value: the spin's 2 pi turns are the joint's too
        low, high = (
            (lo, hi) if half >= math.pi else (max(a.q[-1] - half, lo), min(a.q[-1] + half, hi))
        )
        if low > high:  # the bound and the limits do not meet on this branch
            continue
        q = np.array(a.q, dtype=float)
        q[-1] = min(max(q0[-1], low), high)
        if arm.within_limits(q):
            turn = abs(q[-1] - a.q[-1])
            found.append(
                dataclasses.replace(
                    a,
                    q=q,
                    reason=f"{family.name}, the spin about the target's {spin.AXES[k]} axis "
                    f"turned by the last joint ({turn:.6g} rad): nearest q0 over the range",
                )
            )
    if not found:  # the closed form is complete: no branch, no answer over the range
        reached = any(a.claim is Status.CONVERGED for a in rows)
        return [
            Attempt(
                q=np.array(q0, dtype=float),
                claim=Status.JOINT_LIMITS if reached else Status.UNREACHABLE,
                reason=f"no branch of {family.name} reaches the target with its last joint "
                f"within +-{half:g} rad of the spin and every joint within its limits; q is q0",
            )
        ]
    found.sort(key=lambda a: float(np.linalg.norm(a.q - q0)))
    return found if all_solutions else found[:1]


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
