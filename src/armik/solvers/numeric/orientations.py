"""The orientations a chain can reach where its structure bounds them, and a target's
rotation beyond them refused at once.

A chain's tip rotation in the base frame is, by the product of exponentials,
``Rot(w_1, x_1) ... Rot(w_k, x_k) R0``: ``w_i`` the turning joints' axes (revolute and
continuous, mimic followers too) in the base frame with every physical joint at 0, ``x_i``
their values, ``R0`` the tip's rotation there; a prismatic joint turns nothing. Without a
turning joint (a gantry) the tip has one rotation, ``R0``; when every turning axis is
parallel to one ``a`` (a SCARA, a planar arm) it has the rotations ``Rot(a, x) R0``. An axis
``eps`` off ``a`` moves a rotation at most ``2 eps`` away (``Rot(w, x) = S Rot(a, x) S^T``
with ``S`` a turn by ``eps``), so the family holds every reachable rotation to within
``2 * sum(eps)`` (``Family.slack``). On any other arm there is no such family (None) and
nothing is refused.

The angle from a rotation ``M = R_t R0^T`` (quaternion ``(c, v)``) to the rotations about
``a`` is ``2 atan2(|v x a|, sqrt(c^2 + (v . a)^2))``; beyond the verdict's
``tol_orientation`` plus the slack, no configuration passes it, whatever the joint limits
(they only shrink the family): the numeric solvers then answer ``unreachable`` without an
iteration (``driver``), where the descent would spend every restart on it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from armik import reasons
from armik.kernel.chain import PRISMATIC
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.problem.settings import SolverSettings

# a family is read only where its axes are this close to parallel (rad, summed): beyond it
# the slack would refuse nothing a tolerance would notice
MAX_SLACK = 1e-3
MARGIN = 1e-9  # rad: rounding of the verdict's measure and of this one


class Family(NamedTuple):
    """The tip rotations a chain reaches: ``Rot(axis, x) R0`` (``axis`` None: ``R0`` only),
    each within ``slack`` rad."""

    axis: np.ndarray | None  # (3,) unit, base frame
    R0: np.ndarray  # (3, 3) the tip's rotation with every physical joint at 0, base frame
    slack: float  # rad
    # ``near_one``'s plain floats: ``R0`` row by row (no axis), or ``R0^T axis`` and ``axis``
    plain: tuple[float, ...] = ()


def _family(arm: ArmModel) -> Family | None:
    ch = arm.kernel_chain.chain
    R = np.eye(3)
    axes = []
    for i in range(len(ch.joint_kind)):
        R = R @ ch.joint_R[i]
        if ch.joint_kind[i] != PRISMATIC:
            axes.append(R @ ch.axis[i])
    R0 = R @ ch.tip_R
    if not axes:
        return Family(None, R0, 0.0, tuple(R0.ravel().tolist()))
    a = axes[0] / np.linalg.norm(axes[0])
    slack = 0.0
    for w in axes[1:]:  # the angle between the lines
        slack += math.atan2(float(np.linalg.norm(np.cross(w, a))), abs(float(w @ a)))
    if slack > MAX_SLACK:
        return None
    return Family(a, R0, 2.0 * slack, tuple((R0.T @ a).tolist() + a.tolist()))


FAMILY: Derived[Family | None] = Derived("reachable orientations", _family)


def gap(family: Family, R_t: np.ndarray) -> float:
    """The angle (rad) from ``R_t`` (base frame) to the nearest rotation of ``family``, the
    family's slack taken off."""
    M = np.asarray(R_t, dtype=float) @ family.R0.T
    c, v = _quaternion(M)
    if family.axis is None:
        angle = 2.0 * math.atan2(float(np.linalg.norm(v)), abs(c))
    else:
        along = float(v @ family.axis)
        across = float(np.linalg.norm(np.cross(v, family.axis)))
        angle = 2.0 * math.atan2(across, math.sqrt(c * c + along * along))
    return angle - family.slack


def near(family: Family, R_t: np.ndarray, tol: float) -> np.ndarray:
    """For rotations ``R_t`` (m, 3, 3, base frame): True where a cheap measure puts one
    within half of ``tol`` (the family's slack added) of ``family``, so that ``refused``
    never refuses it; False says nothing. The measure is ``gap``'s angle, as a chord: the
    angle of ``M = R_t R0^T`` (no axis: ``|R_t - R0| = 2 sqrt(2) sin(angle / 2)``,
    Frobenius) or of its swing off its twist about the axis, the angle between ``axis`` and
    ``M axis`` (``|R_t R0^T axis - axis| = 2 sin(angle / 2)``); a target's rotation is
    orthonormal to 1e-14, so that the two measures agree far within half the tolerance."""
    if family.axis is None:
        d = R_t - family.R0
        chord2 = 0.5 * (d * d).sum(axis=(1, 2))
    else:
        d = R_t @ (family.R0.T @ family.axis) - family.axis
        chord2 = (d * d).sum(axis=1)
    return chord2 <= chord2_within(family, tol)


def near_one(family: Family, R_t: np.ndarray, tol: float) -> bool:
    """``near`` of one rotation ``R_t`` (3, 3), on plain floats (a fifth of its cost)."""
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = R_t.tolist()
    if family.axis is None:
        s00, s01, s02, s10, s11, s12, s20, s21, s22 = family.plain
        d = [r00 - s00, r01 - s01, r02 - s02, r10 - s10, r11 - s11, r12 - s12]
        d += (r20 - s20, r21 - s21, r22 - s22)
        chord2 = 0.5 * sum(x * x for x in d)
    else:
        b0, b1, b2, a0, a1, a2 = family.plain
        d0 = r00 * b0 + r01 * b1 + r02 * b2 - a0
        d1 = r10 * b0 + r11 * b1 + r12 * b2 - a1
        d2 = r20 * b0 + r21 * b1 + r22 * b2 - a2
        chord2 = d0 * d0 + d1 * d1 + d2 * d2
    return chord2 <= chord2_within(family, tol)


def chord2_within(family: Family, tol: float) -> float:
    """The squared chord (``near``'s) of half of ``tol``, the family's slack added."""
    angle = 0.5 * (tol + family.slack)
    return math.inf if angle >= math.pi else (2.0 * math.sin(0.5 * angle)) ** 2


def _quaternion(M: np.ndarray) -> tuple[float, np.ndarray]:
    """(c, v) of a unit quaternion of rotation ``M`` (Shepperd's method: its largest
    component first, so every branch divides by at least 1/2)."""
    t = M[0, 0] + M[1, 1] + M[2, 2]
    d = (t, M[0, 0], M[1, 1], M[2, 2])
    k = int(np.argmax(d))
    if k == 0:
        s = 2.0 * math.sqrt(max(1.0 + t, 0.0))
        c = 0.25 * s
        v = np.array([M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]]) / s
        return c, v
    i = k - 1
    j, m = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(max(1.0 + M[i, i] - M[j, j] - M[m, m], 0.0))
    v = np.empty(3)
    v[i] = 0.25 * s
    v[j] = (M[j, i] + M[i, j]) / s
    v[m] = (M[m, i] + M[i, m]) / s
    return (M[m, j] - M[j, m]) / s, v


def refused(arm: ArmModel, R_t: np.ndarray, opts: SolverSettings) -> str | None:
    """Why no configuration of ``arm`` reaches the rotation ``R_t`` (base frame) within
    ``tol_orientation``, or None when one may (or the arm's rotations are not bounded by its
    structure). For a target measured plainly (no weights, no region, not position only)."""
    family = FAMILY(arm)
    if family is None:
        return None
    off = gap(family, R_t)
    if not off > opts.tol_orientation + MARGIN:
        return None
    return reasons.orientation_unreachable(off, family.axis is None, opts.tol_orientation)
