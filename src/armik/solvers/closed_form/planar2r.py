"""Closed-form IK of a planar two-revolute chain (the 2-link specialist).

In plane coordinates (see ``armik.model.geometry``) with the shoulder at A, target P, d = P - A,
r = |d|, effective link lengths l1, l2 read from the model:

    cos t2 = (r^2 - l1^2 - l2^2) / (2 l1 l2),   t2 = +/- arccos(cos t2)
    t1 = atan2(d_y, d_x) - atan2(l2 sin t2, l1 + l2 cos t2)

t1, t2 are the geometric link angles; the joint values follow from the zero-configuration
offsets and the axis signs: q_i = s_i (t_i - alpha_i). Branch "elbow-up" turns the elbow
counter-clockwise about its own axis (q2 > 0 on an arm without offsets).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, Plane, angle_between, axis_lines, fmt
from armik.model.mimic import reason as mimic_reason
from armik.options import Options
from armik.solvers.claims import Attempt
from armik.solvers.registry import SolverSpec, register
from armik.status import Status
from armik.targets.pose import Target
from armik.tolerances import PARALLEL_TOL

SINGULAR_TOL = 1e-12  # |cos t2| beyond 1 - this: the two branches merge
ZERO_LENGTH = 1e-9  # m


@dataclass(frozen=True)
class Geometry:
    """Effective 2-link geometry of an arm, in its plane (m, rad)."""

    shoulder: np.ndarray  # A, plane coordinates
    l1: float
    l2: float
    alpha1: float  # angle of link 1 at q = 0
    alpha2: float  # angle of link 2 relative to link 1 at q = 0
    s1: float
    s2: float
    R_tip0: np.ndarray  # tip orientation at q = 0, base frame

    def forward(self, q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
        """Tip position(s) in plane coordinates, shape (..., 2)."""
        t1 = self.alpha1 + self.s1 * np.asarray(q1)
        t12 = t1 + self.alpha2 + self.s2 * np.asarray(q2)
        x = self.shoulder[0] + self.l1 * np.cos(t1) + self.l2 * np.cos(t12)
        y = self.shoulder[1] + self.l1 * np.sin(t1) + self.l2 * np.sin(t12)
        return np.stack([x, y], axis=-1)


def classify(arm: ArmModel, ax: Axes | None = None) -> Plane | str:
    """The plane of motion of ``arm`` (every joint revolute, all axes parallel), or why it
    is not planar, with the measured angle."""
    if arm.mimics:
        return mimic_reason(arm.mimics)
    if arm.plane is not None:
        return arm.plane
    ax = ax or axis_lines(arm)
    names = [n for n, p in zip(arm.joint_names, arm.prismatic) if p]
    if names:
        return f"joint {names[0]!r} is prismatic"
    angles = [angle_between(ax.directions[0], d) for d in ax.directions[1:]]
    i = int(np.argmax(angles))
    return f"axes 1 and {i + 2} are {fmt(angles[i])} rad apart (tolerance {PARALLEL_TOL:g} rad)"


def geometry(arm: ArmModel) -> Geometry:
    """Link lengths and offsets read from the Pinocchio model (remembered per arm)."""
    return arm.memo("planar 2R geometry", _measure_geometry)


def _measure_geometry(arm: ArmModel) -> Geometry:
    plane = arm.plane
    zero = np.zeros(arm.model.nq)
    zero[:] = arm.to_pin(np.zeros(arm.dof))
    T_tip = arm.fk_pin(zero)
    elbow = arm.T_base_world.act(arm.data.oMi[2].translation)
    A = plane.joint_origins[0]
    u1 = plane.to_2d(elbow) - A
    u2 = plane.to_2d(T_tip.translation) - plane.to_2d(elbow)
    a1 = math.atan2(u1[1], u1[0])
    geo = Geometry(
        A,
        float(np.linalg.norm(u1)),
        float(np.linalg.norm(u2)),
        a1,
        math.atan2(u2[1], u2[0]) - a1,
        float(plane.signs[0]),
        float(plane.signs[1]),
        T_tip.rotation.copy(),
    )
    return geo


def applies(arm: ArmModel, target: Target | None = None, opts: Options | None = None) -> str | None:
    if arm.mimics:
        return mimic_reason(arm.mimics)
    if arm.dof != 2:
        return f"the chain has {arm.dof} joints, the specialist needs exactly 2"
    if any(t == "prismatic" for t in arm.joint_types):
        return "a joint is prismatic; the specialist needs two revolute joints"
    if arm.plane is None:
        return "the two joint axes are not parallel, so the chain is not planar"
    geo = geometry(arm)
    if geo.l1 < ZERO_LENGTH:
        return "link 1 has zero length in the plane (the elbow sits on the shoulder axis)"
    if geo.l2 < ZERO_LENGTH:
        return "link 2 has zero length in the plane (the tip sits on the elbow axis)"
    if opts is not None and opts.weights is not None:
        return "per-axis weights are for the numeric solvers"
    if opts is not None and opts.bounds is not None:
        return "bounds are for the numeric solvers (dls, qp)"
    return None


def _angle(a: float) -> float:
    return math.atan2(math.sin(a), math.cos(a))


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: Options, all_solutions: bool
) -> list[Attempt]:
    geo, plane = geometry(arm), arm.plane
    if target.planar_xy is not None:  # given in plane coordinates: on the plane
        off_plane, P = 0.0, target.planar_xy
    else:
        off_plane, P = plane.height(target.position), plane.to_2d(target.position)
    d = P - geo.shoulder
    r = math.hypot(d[0], d[1])
    l1, l2 = geo.l1, geo.l2
    c = (r * r - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    heading = math.atan2(d[1], d[0])

    def joints(t1: float, t2: float) -> np.ndarray:
        q = np.array([_angle(geo.s1 * (t1 - geo.alpha1)), _angle(geo.s2 * (t2 - geo.alpha2))])
        return arm.nearest_equivalent(q, q0)

    def merged(t1: float, t2: float, branch: str, reason: str) -> list[Attempt]:
        """The single answer where the two elbow branches coincide."""
        q = joints(t1, t2)
        one = Attempt(q=q, claim=Status.CONVERGED, singular=True, branch=branch, reason=reason)
        return _orient(arm, geo, target, opts, [one])

    if abs(off_plane) > opts.tol_position:
        t2 = math.acos(max(-1.0, min(1.0, c)))
        t1 = heading - math.atan2(l2 * math.sin(t2), l1 + l2 * math.cos(t2))
        return [
            Attempt(
                q=joints(t1, t2),
                claim=Status.UNREACHABLE,
                reason=f"target is {off_plane:.6g} m off the arm's plane of motion",
            )
        ]

    if r < ZERO_LENGTH and abs(l1 - l2) < ZERO_LENGTH:
        t1 = geo.alpha1 + geo.s1 * q0[0]
        free = "target at the shoulder with l1 = l2: joint 1 is free, kept nearest q0"
        return merged(t1, math.pi, "folded", free)

    excess = max(r - (l1 + l2), abs(l1 - l2) - r)
    if abs(c) >= 1.0 - SINGULAR_TOL:
        stretched = c > 0
        t2 = 0.0 if stretched else math.pi
        # Folded with l2 > l1 the tip points away from link 1.
        t1 = heading if (stretched or l1 >= l2) else heading + math.pi
        if excess > opts.tol_position:
            where = (
                f"too far: beyond the reach l1 + l2 = {l1 + l2:.6g} m"
                if stretched
                else f"inside the inner dead zone: closer than |l1 - l2| = {abs(l1 - l2):.6g} m"
            )
            return [
                Attempt(
                    q=joints(t1, t2),
                    claim=Status.UNREACHABLE,
                    branch=None,
                    reason=f"target at distance {r:.6g} m from the shoulder is {where}; "
                    "q is the closest reachable configuration",
                )
            ]
        name = "stretched" if stretched else "folded"
        return merged(
            t1, t2, name, f"singular: the arm is fully {name}, the two elbow branches coincide"
        )

    attempts = []
    for sign in (1.0, -1.0):
        t2 = sign * math.acos(c)
        t1 = heading - math.atan2(l2 * math.sin(t2), l1 + l2 * math.cos(t2))
        q = joints(t1, t2)
        up = geo.s2 * t2 > 0
        attempts.append(
            Attempt(
                q=q,
                claim=Status.CONVERGED,
                reason="closed form",
                branch="elbow-up" if up else "elbow-down",
            )
        )
    return _orient(arm, geo, target, opts, attempts)


def _orient(
    arm: ArmModel, geo: Geometry, target: Target, opts: Options, attempts: list[Attempt]
) -> list[Attempt]:
    """A full pose fixes the tip angle too: keep only branches whose angle matches."""
    if target.rotation is None or opts.position_only:
        return attempts
    n = arm.plane.normal
    M = target.rotation @ geo.R_tip0.T  # must be a rotation about the plane normal
    tilt = math.acos(max(-1.0, min(1.0, float(n @ M @ n))))
    if tilt > opts.tol_orientation:
        return [
            Attempt(
                q=a.q,
                claim=Status.UNREACHABLE,
                branch=a.branch,
                singular=a.singular,
                reason=f"target orientation is tilted {tilt:.3g} rad out of the arm's "
                "plane; a planar arm only turns about its joint axis",
            )
            for a in attempts
        ]
    x = arm.plane.x
    want = math.atan2(float(np.cross(x, M @ x) @ n), float(x @ M @ x))
    out = []
    for a in attempts:
        got = geo.s1 * a.q[0] + geo.s2 * a.q[1]
        miss = abs(_angle(got - want))
        if miss > opts.tol_orientation:
            a = Attempt(
                q=a.q,
                claim=Status.UNREACHABLE,
                branch=a.branch,
                singular=a.singular,
                reason=f"the {a.branch} branch reaches the position with tip angle "
                f"{_angle(got):.6g} rad, the target asks {want:.6g} rad; a 2-link "
                "arm cannot choose both",
            )
        out.append(a)
    return out


def solve_many(arm: ArmModel, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vectorised closed form for many plane targets.

    ``xy``: (N, 2) plane coordinates (m). Returns ``(q_up, q_down, reachable)``: two (N, 2)
    arrays of joint values in (-pi, pi] (NaN where unreachable) and an (N,) bool mask.
    Joint limits are not applied: filter with ``arm.lower``/``arm.upper``.
    """
    geo = geometry(arm)
    d = np.asarray(xy, dtype=float) - geo.shoulder
    r2 = np.einsum("ij,ij->i", d, d)
    c = (r2 - geo.l1**2 - geo.l2**2) / (2.0 * geo.l1 * geo.l2)
    reachable = np.abs(c) <= 1.0 + SINGULAR_TOL
    t2 = np.arccos(np.clip(c, -1.0, 1.0))
    heading = np.arctan2(d[:, 1], d[:, 0])
    s, k = geo.l2 * np.sin(t2), geo.l1 + geo.l2 * np.cos(t2)
    out = []
    for sign in (1.0, -1.0):
        t1 = heading - np.arctan2(sign * s, k)
        q = np.empty_like(d)
        q[:, 0] = geo.s1 * (t1 - geo.alpha1)
        q[:, 1] = geo.s2 * (sign * t2 - geo.alpha2)
        q = np.arctan2(np.sin(q), np.cos(q))
        q[~reachable] = np.nan
        out.append(q)
    up_is_plus = geo.s2 > 0
    q_up, q_down = out if up_is_plus else out[::-1]
    return q_up, q_down, reachable


SPEC = register(
    SolverSpec(
        name="planar2r",
        kind="analytic",
        enforces_limits=True,
        priority=100,
        why_not=applies,
        run=run,
        summary="closed form for planar two-revolute chains: both elbow branches",
    )
)
