"""The positions a chain of prismatic joints only (a gantry) reaches, or a chain whose
prismatic joints all come before its turning ones (a gantry with a wrist), and a target
beyond them refused at once.

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
at x. With turning joints after the slides, ``p0 + B q`` places the first turning joint's
origin, and the tip is at most ``wrist`` from it (the fixed distances between the joint
origins after it and the tip, summed): the distance to the box's image less ``wrist`` bounds
the distance to every position the tip reaches. Beyond ``tol_position`` no configuration
passes the verdict, the joint limits of mimic followers apart (they only shrink the set):
the numeric solvers then answer ``unreachable`` without an iteration, also where the reach
bound (infinite with an unlimited rail) does not refuse it.
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
    """``p(q) = p0 + B q`` (base frame, m) for ``lower <= q <= upper``: the tip, or with
    turning joints after the slides the first one's origin, the tip within ``wrist`` of it."""

    p0: np.ndarray  # (3,)
    B: np.ndarray  # (3, n)
    lower: np.ndarray  # (n,)
    upper: np.ndarray  # (n,)
    wrist: float = 0.0  # m


def _slides(arm: ArmModel) -> Slides | None:
    ch = arm.kernel_chain.chain
    turning = np.flatnonzero(ch.joint_kind != PRISMATIC)
    k = int(turning[0]) if len(turning) else len(ch.joint_kind)  # the first turning joint
    if k == 0 or (ch.joint_kind[k:] == PRISMATIC).any():  # no slide first, or one after
        return None
    R, p = np.eye(3), np.zeros(3)
    B = np.zeros((3, len(ch.kind)))
    for i in range(k):
        p = p + R @ ch.joint_p[i]
        R = R @ ch.joint_R[i]
        w = R @ ch.axis[i]
        B[:, ch.driver[i]] += ch.multiplier[i] * w
        p = p + ch.offset[i] * w
    if k == len(ch.joint_kind):
        p, wrist = p + R @ ch.tip_p, 0.0
    else:
        p = p + R @ ch.joint_p[k]
        wrist = sum(float(np.linalg.norm(d)) for d in ch.joint_p[k + 1 :])
        wrist += float(np.linalg.norm(ch.tip_p))
    lower, upper = np.asarray(ch.lower, dtype=float), np.asarray(ch.upper, dtype=float)
    return Slides(p, B, lower, upper, wrist)


SLIDES: Derived[Slides | None] = Derived("a prismatic chain's positions", _slides)


def _reduced(slides: Slides) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``distance``'s problem as (off, c, B, lo, hi): the least ``|B x - r|`` over
    ``lo <= x <= hi``, ``r = off p_t - c``; the unlimited joints' directions projected off
    (``off``) and the joints held still by their limits taken into ``c``."""
    moves = (slides.B != 0.0).any(axis=0)  # a turning joint's driver moves none of them
    lo, hi, B = slides.lower[moves], slides.upper[moves], slides.B[:, moves]
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
    ``p0 + B q`` reaches (the tip's, less ``wrist``)."""
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
    """``distance``'s problem kept per arm (``_reduced``) with its unconstrained answer
    ``x = P r``: clipped into the limits, a configuration whose distance to ``r`` bounds
    ``distance`` from above."""

    off: np.ndarray  # (3, 3)
    c: np.ndarray  # (3,)
    P: np.ndarray  # (k, 3)
    B: np.ndarray  # (3, k)
    lower: np.ndarray  # (k,)
    upper: np.ndarray  # (k,)
    wrist: float  # m: ``Slides.wrist``
    # ``near_one``'s plain floats: off's rows, c, P's rows, B's columns, the limits
    plain: tuple[tuple[tuple[float, ...], ...], ...]


def _near(arm: ArmModel) -> Near | None:
    slides = SLIDES(arm)
    if slides is None:
        return None
    off, c, B, lo, hi = _reduced(slides)
    P = np.linalg.pinv(B)  # the least-squares answer x = P r
    plain = tuple(tuple(tuple(row) for row in a.tolist()) for a in (off, P, B.T))
    plain += ((tuple(c.tolist()), tuple(lo.tolist()), tuple(hi.tolist())),)
    return Near(off, c, P, B, lo, hi, slides.wrist, plain)


NEAR: Derived[Near | None] = Derived("a prismatic chain's nearest positions", _near)


def near(arm: ArmModel, P: np.ndarray, tol: float) -> np.ndarray:
    """For positions ``P`` (m, 3, base frame): True where the least-squares answer clipped
    into the limits places ``p0 + B q`` within ``wrist`` and half of ``tol`` of them (so
    that ``refused`` never refuses them: ``distance`` is at most that far), or the arm has
    no slides; False says nothing."""
    n = NEAR(arm)
    if n is None:
        return np.ones(len(P), dtype=bool)
    R = P @ n.off.T - n.c
    E = np.clip(R @ n.P.T, n.lower, n.upper) @ n.B.T - R
    return (E * E).sum(axis=1) <= (n.wrist + 0.5 * tol) ** 2


def near_one(n: Near, p_t: np.ndarray, tol: float) -> bool:
    """``near`` of one position ``p_t`` (3,) on ``NEAR(arm)``, on plain floats."""
    x, y, z = p_t.tolist()
    off, P, Bt, (c, lo, hi) = n.plain
    r = [a * x + b * y + d * z - ci for (a, b, d), ci in zip(off, c)]
    xs = [min(max(a * r[0] + b * r[1] + d * r[2], l_), h) for (a, b, d), l_, h in zip(P, lo, hi)]
    e = [-ri for ri in r]
    for xi, col in zip(xs, Bt):
        e = [ei + xi * bi for ei, bi in zip(e, col)]
    return e[0] * e[0] + e[1] * e[1] + e[2] * e[2] <= (n.wrist + 0.5 * tol) ** 2


def refused(arm: ArmModel, p_t: np.ndarray, opts: SolverSettings) -> str | None:
    """Why no configuration of ``arm`` reaches the position ``p_t`` (base frame) within
    ``tol_position``, or None when one may or the arm has no slides first (``SLIDES``).
    For a target measured plainly (no weights, no region)."""
    slides = SLIDES(arm)
    if slides is None or not np.isfinite(p_t).all():  # non-finite: the parser's to refuse
        return None
    d = distance(slides, p_t) - slides.wrist
    size = float(np.abs(p_t).sum() + np.abs(slides.p0).sum()) + slides.wrist
    if not d > opts.tol_position + MARGIN * (1.0 + size):
        return None
    if slides.wrist > 0.0:
        return reasons.slides_wrist_unreachable(d, slides.wrist, opts.tol_position)
    return reasons.slides_unreachable(d, opts.tol_position)
