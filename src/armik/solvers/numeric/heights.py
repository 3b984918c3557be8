"""The heights a chain whose turning axes are all exactly parallel (a planar arm, a SCARA)
reaches along them, and a target beyond them refused at once.

A turn about a line parallel to ``a`` keeps every point's component along ``a``, so the
tip's height ``a . p(q)`` moves only with the prismatic joints, each by its value times
its direction's component along ``a`` (which no such turn changes): it is affine in their
values, ``h0 + c . q`` (a mimic follower adds its multiplier times its driver's and its
offset), and within the limits it spans ``[low, high]`` (infinite where a slide along the
axis has no limit). A target's height beyond them by more than ``tol_position`` is beyond
every configuration, the joint limits of mimic followers apart (they only shrink the set):
the numeric solvers answer ``unreachable`` without an iteration. Read only where the axes
are parallel to rounding (``orientations.Family.slack`` at most ``SLACK`` rad, as a URDF's
axes along one direction give, a joint turned by ``rpy="3.14159265 0 0"`` with its axis
reversed among them): a turn about an axis ``eps`` off ``a`` moves a point at most ``2 eps``
times its distance from the joint, so the heights are widened by the slack times the
chain's reach (``ArmModel.reach``, which bounds every such distance). The heights are found
by the kernel's FK (``kernel.fk_many``) at q = 0 and one slide moved, where every turning
joint is at 0 and the axes' slack moves nothing.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from armik import reasons
from armik.kernel.chain import PRISMATIC
from armik.kernel.fk_many import fk_many
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.problem.settings import SolverSettings
from armik.solvers.numeric import orientations

MARGIN = 1e-9  # m, and that much per metre of the problem's size: rounding
SLACK = 1e-12  # rad: the most ``orientations.Family.slack`` of axes read as parallel


class Heights(NamedTuple):
    """The tip's heights along ``axis`` (base frame): from ``low`` to ``high`` (m)."""

    axis: tuple[float, float, float]
    low: float
    high: float
    size: float  # m: the largest height met in finding them (rounding scales with it)


def _heights(arm: ArmModel) -> Heights | None:
    family = orientations.FAMILY(arm)
    if family is None or family.axis is None or family.slack > SLACK:
        return None
    ch = arm.kernel_chain.chain
    n = len(ch.kind)
    sliding = np.zeros(n, dtype=bool)  # drivers of a prismatic joint: they move the height
    sliding[ch.driver[ch.joint_kind == PRISMATIC]] = True
    Q = np.vstack([np.zeros(n), np.eye(n)])
    out = np.empty((n + 1, 4, 4))
    fk_many(*arm.kernel_chain.flat, Q, out)
    h = out[:, :3, 3] @ family.axis
    c = np.where(sliding, h[1:] - h[0], 0.0)
    with np.errstate(invalid="ignore"):  # 0 * inf: a joint that does not move the height
        ends = np.array([c * ch.lower, c * ch.upper])
    ends[:, c == 0.0] = 0.0
    low = float(h[0] + ends.min(axis=0).sum())
    high = float(h[0] + ends.max(axis=0).sum())
    if family.slack > 0.0:  # the turns about axes a little off ``a``
        low, high = low - family.slack * ch.reach, high + family.slack * ch.reach
    a = tuple(family.axis.tolist())
    return Heights(a, low, high, float(np.abs(h).max()))  # type: ignore[arg-type]


HEIGHTS: Derived[Heights | None] = Derived("heights along parallel axes", _heights)


def height(heights: Heights, p_t: np.ndarray | Sequence[float]) -> float:
    """How far (m) the position ``p_t`` (base frame) is beyond the heights, 0 within."""
    x, y, z = p_t.tolist() if isinstance(p_t, np.ndarray) else p_t
    ax, ay, az = heights.axis
    h = ax * x + ay * y + az * z
    return max(heights.low - h, h - heights.high, 0.0)


def near(arm: ArmModel, P: np.ndarray, tol: float) -> np.ndarray:
    """For positions ``P`` (m, 3, base frame): True where their heights are within half of
    ``tol`` of the tip's (so that ``refused`` never refuses them), or the arm has no such
    heights; False says nothing."""
    heights = HEIGHTS(arm)
    if heights is None:
        return np.ones(len(P), dtype=bool)
    h = P @ np.array(heights.axis)
    return (heights.low - 0.5 * tol <= h) & (h <= heights.high + 0.5 * tol)


def refused(arm: ArmModel, p_t: np.ndarray, opts: SolverSettings) -> str | None:
    """Why no configuration of ``arm`` reaches the position ``p_t`` (base frame) within
    ``tol_position``, by its height along the parallel turning axes; None when one may, or
    the arm has no such heights. For a target measured plainly (no weights, no region)."""
    heights = HEIGHTS(arm)
    if heights is None or not np.isfinite(p_t).all():  # non-finite: the parser's to refuse
        return None
    d = height(heights, p_t)
    size = float(np.abs(p_t).sum()) + heights.size
    if not d > opts.tol_position + MARGIN * (1.0 + size):
        return None
    return reasons.height_unreachable(d, opts.tol_position)
