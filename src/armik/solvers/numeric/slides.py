"""The positions a chain of prismatic joints only (a gantry) reaches, and a target beyond
them refused at once.

Without a turning joint the tip never turns and its position is affine in the joint values,
``p(q) = p0 + B q`` (a mimic follower adds its multiplier times its driver's column and its
offset to ``p0``): the positions within the limits are a box's image, and the least
distance from a target to them is a small box-constrained least-squares problem. Its
unlimited joints are taken out first (the target and the other columns projected off the
directions they span: every direction a column spans at all, so that nothing is missed),
then the bounded ones are solved for (least squares; ``scipy.optimize.lsq_linear``'s
bounded one where that answer leaves the box) and the distance
taken from a lower bound that holds whatever that answer's accuracy: for the convex
``f(x) = |B x - r|^2 / 2``, ``f(y) >= f(x) + g . (y - x)`` over the box, ``g`` the gradient
at x. Beyond ``tol_position`` no configuration passes the verdict, the joint limits of
mimic followers apart (they only shrink the set): the numeric solvers then answer
``unreachable`` without an iteration, where the reach bound (infinite with an unlimited
rail) did not refuse it and the descent spent every restart on it.
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

MARGIN = 1e-9  # m, and that much per metre of the problem's size: rounding
SPAN_TOL = 1e-14  # relative singular value of an unlimited joint's column still counted


class Slides(NamedTuple):
    """``p(q) = p0 + B q`` (base frame, m) for ``lower <= q <= upper``."""

    p0: np.ndarray  # (3,)
    B: np.ndarray  # (3, n)
    lower: np.ndarray  # (n,)
    upper: np.ndarray  # (n,)


def _slides(arm: ArmModel) -> Slides | None:
    ch = arm.kernel_chain.chain
    if (ch.joint_kind != PRISMATIC).any():
        return None
    R, p = np.eye(3), np.zeros(3)
    B = np.zeros((3, len(ch.kind)))
    for i in range(len(ch.joint_kind)):
        p = p + R @ ch.joint_p[i]
        R = R @ ch.joint_R[i]
        w = R @ ch.axis[i]
        B[:, ch.driver[i]] += ch.multiplier[i] * w
        p = p + ch.offset[i] * w
    p = p + R @ ch.tip_p
    return Slides(p, B, np.asarray(ch.lower, dtype=float), np.asarray(ch.upper, dtype=float))


SLIDES: Derived[Slides | None] = Derived("a prismatic chain's positions", _slides)


def _reduced(slides: Slides) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``distance``'s problem as (off, c, B, lo, hi): the least ``|B x - r|`` over
    ``lo <= x <= hi``, ``r = off p_t - c``; the unlimited joints' directions projected off
    (``off``) and the joints held still by their limits taken into ``c``."""
    lo, hi, B = slides.lower, slides.upper, slides.B
    off = np.eye(3)
    free = ~(np.isfinite(lo) & np.isfinite(hi))
    if free.any():  # project off every direction the unlimited joints span
        U, s, _ = np.linalg.svd(B[:, free], full_matrices=False)
        Q = U[:, s > SPAN_TOL * max(float(s.max(initial=0.0)), 1.0)]
        off = off - Q @ Q.T
        B, lo, hi = off @ B[:, ~free], lo[~free], hi[~free]
    c = off @ slides.p0
    fixed = lo >= hi  # limits that hold a joint still: its column moves the target
    if fixed.any():
        c = c + B[:, fixed] @ lo[fixed]
        B, lo, hi = B[:, ~fixed], lo[~fixed], hi[~fixed]
    return off, c, B, lo, hi


def distance(slides: Slides, p_t: np.ndarray) -> float:
    """A lower bound on the distance (m) from ``p_t`` (base frame) to every position
    ``slides`` reaches."""
    off, c, B, lo, hi = _reduced(slides)
    r = off @ np.asarray(p_t, dtype=float) - c
    if B.shape[1] == 0:
        return float(np.linalg.norm(r))
    x = np.linalg.lstsq(B, r, rcond=None)[0]  # the box apart: the usual answer, at once
    if not ((lo <= x) & (x <= hi)).all():
        from scipy.optimize import lsq_linear  # only for a target the box holds back

        x = np.clip(lsq_linear(B, r, bounds=(lo, hi), method="bvls").x, lo, hi)
    res = B @ x - r
    g = B.T @ res
    f = 0.5 * float(res @ res) + float(np.minimum(g * (lo - x), g * (hi - x)).sum())
    return math.sqrt(max(2.0 * f, 0.0))


class Near(NamedTuple):
    """``distance``'s unconstrained answer and its residual, affine in the target:
    ``(x, e) = A p_t + a0`` (k values, then 3), for ``lo <= x <= hi``."""

    A: np.ndarray  # (k + 3, 3)
    a0: np.ndarray  # (k + 3,)
    lower: np.ndarray  # (k,)
    upper: np.ndarray  # (k,)
    plain: tuple[tuple[float, ...], ...]  # ``near_one``'s: the rows (A's, a0's), the limits


def _near(arm: ArmModel) -> Near | None:
    slides = SLIDES(arm)
    if slides is None:
        return None
    off, c, B, lo, hi = _reduced(slides)
    P = np.linalg.pinv(B)  # the least-squares answer x = P r
    E = B @ P - np.eye(3)  # its residual B x - r = E r
    A = np.vstack([P @ off, E @ off])
    a0 = -np.concatenate([P @ c, E @ c])
    plain = tuple(tuple(row) for row in np.column_stack([A, a0]).tolist())
    return Near(A, a0, lo, hi, plain + (tuple(lo.tolist()), tuple(hi.tolist())))


NEAR: Derived[Near | None] = Derived("a prismatic chain's nearest positions", _near)


def near(arm: ArmModel, P: np.ndarray, tol: float) -> np.ndarray:
    """For positions ``P`` (m, 3, base frame): True where the least-squares answer within
    the limits leaves them within half of ``tol`` (so that ``refused`` never refuses
    them), or the arm has a turning joint; False says nothing."""
    n = NEAR(arm)
    if n is None:
        return np.ones(len(P), dtype=bool)
    Y = P @ n.A.T + n.a0
    k = len(n.lower)
    x, e = Y[:, :k], Y[:, k:]
    inside = ((n.lower <= x) & (x <= n.upper)).all(axis=1)
    return inside & ((e * e).sum(axis=1) <= (0.5 * tol) ** 2)


def near_one(n: Near, p_t: np.ndarray, tol: float) -> bool:
    """``near`` of one position ``p_t`` (3,) on ``NEAR(arm)``, on plain floats."""
    x, y, z = p_t.tolist()
    Y = [ax * x + ay * y + az * z + a0 for ax, ay, az, a0 in n.plain[:-2]]
    k = len(Y) - 3
    lo, hi = n.plain[-2:]
    if not all(lo[i] <= Y[i] <= hi[i] for i in range(k)):
        return False
    return Y[k] * Y[k] + Y[k + 1] * Y[k + 1] + Y[k + 2] * Y[k + 2] <= (0.5 * tol) ** 2


def refused(arm: ArmModel, p_t: np.ndarray, opts: SolverSettings) -> str | None:
    """Why no configuration of ``arm`` reaches the position ``p_t`` (base frame) within
    ``tol_position``, or None when one may or the arm has a turning joint. For a target
    measured plainly (no weights, no region)."""
    slides = SLIDES(arm)
    if slides is None or not np.isfinite(p_t).all():  # non-finite: the parser's to refuse
        return None
    d = distance(slides, p_t)
    size = float(np.abs(p_t).sum() + np.abs(slides.p0).sum())
    if not d > opts.tol_position + MARGIN * (1.0 + size):
        return None
    return reasons.slides_unreachable(d, opts.tol_position)
