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

from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.model.derived import DerivedBy
from armik.problem.settings import SolverSettings
from armik.solvers import registry
from armik.solvers.answers import Answers, one
from armik.solvers.claims import claim
from armik.solvers.closed_form import spin
from armik.status import Status
from armik.targets.pose import Target

_CONVERGED = Status.CONVERGED.code


def sense(arm: ArmModel, k: int) -> float:
    """+1 (-1) when turning the last joint by t turns the tip by t (-t) about its own axis
    ``k`` through its origin, on Pinocchio's FK at two configurations; 0 when it does not."""
    if arm.prismatic[-1]:
        return 0.0
    axis = np.eye(3)[k]
    for s in (1.0, -1.0):
        if all(_turns(arm, q, s * axis) for q in (arm.middle, arm.middle + 0.37)):
            return s
    return 0.0


def _turns(arm: ArmModel, q: np.ndarray, axis: np.ndarray) -> bool:
    turned = q.copy()
    turned[-1] += 0.4
    return bool(
        (arm.fk(q) * pin.SE3(pin.exp3(0.4 * axis), np.zeros(3))).isApprox(arm.fk(turned), 1e-9)
    )


def aligned(arm: ArmModel, k: int) -> bool:
    """Whether turning the last joint turns the tip about its own axis ``k`` (either sense)."""
    return _SENSE(arm, k) != 0.0


_SENSE = DerivedBy("the last joint's sense about each spin axis", sense)  # per axis k


def applies(
    arm: ArmModel, target: Target | None = None, opts: SolverSettings | None = None
) -> str | None:
    why = spin.applies(arm, target, opts)
    if why is not None:
        return why
    k, _ = spin.spin_of(opts.bounds)  # type: ignore[misc,union-attr]  # spin.applies checked it
    if not aligned(arm, k):
        return (
            f"turning the last joint does not turn the tool about its {spin.AXES[k]} axis "
            "(the 'spin' solver sweeps that angle instead)"
        )
    return None


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings, all_solutions: bool
) -> Answers:
    k, half = spin.spin_of(opts.bounds)  # type: ignore[misc]  # applies() checked it
    family = spin.family(arm, target)
    assert not isinstance(family, str)  # applies() checked it
    rotation, shift = _from_q0(arm, target.rotation, q0, k, half)
    turned = target if shift == 0.0 else frozen(Target, **{**target.__dict__, "rotation": rotation})
    found = _branches(arm, family, turned, q0, opts)
    centre, order = _chosen(arm, found.q, q0, half, all_solutions)
    if not order:  # the closed form is complete: no answer over the range
        return _none(family.name, q0, half, len(found) > 0)
    why = [
        _reason(family.name, spin.AXES[k], float(found.q[i, -1]), centre[i] - shift) for i in order
    ]
    return dataclasses.replace(found.take(order), reasons=tuple(why))


def prepare_pose(arm: ArmModel, opts: SolverSettings, position: bool):
    """``run_pose(H, q0, seed, every=False)`` for ``armik.solve.prepared``: ``run`` on a
    plain 4x4 pose through the family's prepared runner, the nearest answer a ``Claim``
    (with ``every``: every admissible branch's ``Answers``, q read-only); None where the
    family has no runner or it does not take the input (the general path then)."""
    spin_k, half = spin.spin_of(opts.bounds)  # type: ignore[misc]  # applies() checked it
    family = spin.family(arm, None)
    if position or isinstance(family, str) or family.prepare_pose is None:
        return None
    runner = _RUNNER(arm, family.name)
    if runner is None:
        return None
    name, axis = family.name, spin.AXES[spin_k]

    def run_pose(H: np.ndarray, q0: np.ndarray, seed: int, every: bool = False):
        rotation, shift = _from_q0(arm, H[:3, :3], q0, spin_k, half)
        if shift != 0.0:
            H = H.copy()
            H[:3, :3] = rotation
        got = runner(H, q0, 0, True)
        if got is None:
            return None
        keep = np.flatnonzero(got.claim == _CONVERGED).tolist()  # the branches reached
        Q = got.q[keep]  # a copy: the spin turns its last column
        centre, order = _chosen(arm, Q, q0, half, every)
        if not order:
            return _none(name, q0, half, len(keep) > 0)
        if every:
            said = tuple([_reason(name, axis, float(Q[i, -1]), centre[i] - shift) for i in order])
            chosen = got.take([keep[i] for i in order])
            chosen = dataclasses.replace(chosen, q=Q[order], reasons=said)
            chosen.q.setflags(write=False)  # solve_all's results' q are its rows
            return chosen
        i, k = order[0], keep[order[0]]  # claimed reached: the claim, its reason the spin's
        why = (name, axis, float(Q[i, -1]), centre[i] - shift)
        return claim((Q[i], 0, 0, got.label(k), got.is_singular(k), _reason, why))

    return run_pose


def _from_q0(arm: ArmModel, R, q0: np.ndarray, k: int, half: float):
    """(rotation, shift): for a spin free over a whole turn, ``R`` turned about its axis
    ``k`` to the tip's rotation at q0, and that turn in the last joint's values (the branch
    values then count from the user's target); else (R, 0). The same poses either way; from
    the tip's own spin, a closed form's branches at a singular q0 (a UR5's stretched wrist,
    whose joints 4 and 6 share an axis) include q0's own."""
    if half < math.pi or R is None:
        return R, 0.0
    rotation, theta = spin.nearest_spin(R, arm.fk(q0).rotation, k)
    return rotation, _SENSE(arm, k) * theta


def _chosen(arm: ArmModel, Q: np.ndarray, q0: np.ndarray, half: float, every: bool):
    """(centre, order): each branch's last joint turned to the value nearest q0's within
    the bound (in place in Q; ``centre``: the branch's own values), and the branches that
    hold the limits, nearest q0 first (ties: the branch order), checked only as far as one
    answer needs unless ``every``."""
    centre = Q[:, -1].tolist()
    Q[:, -1] = _turned(arm, centre, float(q0[-1]), half)  # NaN: no value within the bound
    distance = np.linalg.norm(Q - q0, axis=1).tolist()
    nearest = sorted(
        [i for i in range(len(Q)) if distance[i] == distance[i]], key=distance.__getitem__
    )
    order = []
    for i in nearest:
        if arm._within(Q[i].tolist()):
            order.append(i)
            if not every:
                break
    return centre, order


def _none(name: str, q0: np.ndarray, half: float, reached: bool) -> Answers:
    """No branch holds the limits over the range: the closed form is complete."""
    return one(
        np.array(q0, dtype=float),
        Status.JOINT_LIMITS if reached else Status.UNREACHABLE,
        f"no branch of {name} reaches the target with its last joint within "
        f"+-{half:g} rad of the spin and every joint within its limits; q is q0",
    )


def _reason(name: str, axis: str, last: float, centre: float) -> str:
    """The spin an answer turns through: from the branch's value, modulo whole turns."""
    turned = abs(math.remainder(last - centre, 2 * math.pi))
    return (
        f"{name}, the spin about the target's {axis} axis turned by the last joint "
        f"({turned:.6g} rad): nearest q0 over the range"
    )


def _branches(
    arm: ArmModel, family, target: Target, q0: np.ndarray, opts: SolverSettings
) -> Answers:
    """The closed form's branches that reach the target, nearest q0 first (q a writable
    copy: the spin turns its last column). The family's prepared runner where it takes the
    pose and seed as they are, else the family's answers."""
    run_pose = None if family.prepare_pose is None else _RUNNER(arm, family.name)
    if run_pose is not None:
        H = np.empty((4, 4))
        H[:3, :3], H[:3, 3], H[3] = target.rotation, target.position, (0.0, 0.0, 0.0, 1.0)
        got = run_pose(H, q0, 0, True)
        if got is not None:
            return _reached(got)
    return _reached(family.run(arm, target, q0, dataclasses.replace(opts, bounds=None), True))


def _reached(got: Answers) -> Answers:
    """The rows of ``got`` claimed reached (q a writable copy)."""
    picked = got.take(np.flatnonzero(got.claim == _CONVERGED).tolist())
    # one row is taken as a view of got's q, read-only where got holds solve_all's rows
    return dataclasses.replace(picked, q=picked.q.copy())


# per family name: the closed form's prepared runner (the families' runners take no option)
_RUNNER = DerivedBy(
    "spin_joint's closed-form runner",
    lambda arm, name: registry.get(name).prepare_pose(arm, SolverSettings(), False),  # type: ignore[misc]
)
_SHIFTS = tuple(2 * math.pi * k for k in (0, -1, 1, -2, 2))  # a branch's value's turns


def _turned(arm: ArmModel, centre: list[float], q0_last: float, half: float) -> list[float]:
    """Per branch (its last joint's value in ``centre``): the last joint's value nearest
    ``q0_last`` within +-``half`` of the branch's value or of one of its 2 pi turns (the
    same spin) and within that joint's limits, NaN where there is none. A full turn is
    every value of the joint; else the windows about the branch's value and its turns (a
    joint may span 4 pi), the first nearest in ``_SHIFTS``' order. Plain floats: a handful
    of branches, where array calls cost more than the sums."""
    lower, upper, _ = arm._limit_lists
    lo, hi = lower[-1], upper[-1]
    if half >= math.pi:
        return [min(max(q0_last, lo), hi)] * len(centre)
    out = []
    for c in centre:
        best, gap = math.nan, math.inf
        for shift in _SHIFTS:
            low = max(c + shift - half, lo)
            high = min(c + shift + half, hi)
            value = min(max(q0_last, low), high)
            if low <= high and abs(value - q0_last) < gap:
                best, gap = value, abs(value - q0_last)
        out.append(best)
    return out


SPEC = registry.register(
    registry.SolverSpec(
        name="spin_joint",
        kind="analytic",
        enforces_limits=True,
        priority=86,
        why_not=applies,
        solves=frozenset({"spin"}),
        needs=frozenset({"spin"}),
        run=run,
        prepare_pose=prepare_pose,
        summary="a free or bounded spin that is the last joint's: every branch, exactly",
    )
)
