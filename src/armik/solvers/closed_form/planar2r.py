"""Closed-form IK of a planar two-revolute chain (the 2-link specialist).

In plane coordinates (see ``armik.model.geometry``) with the shoulder at A, target P, d = P - A,
r = |d|, effective link lengths l1, l2 read from the model:

    cos t2 = (r^2 - l1^2 - l2^2) / (2 l1 l2),   t2 = +/- arccos(cos t2)
    t1 = atan2(d_y, d_x) - atan2(l2 sin t2, l1 + l2 cos t2)

t1, t2 are the geometric link angles; the joint values follow from the zero-configuration
offsets and the axis signs: q_i = s_i (t_i - alpha_i). Branch "elbow-up" has the elbow to
the left of the line from the shoulder to the target, seen with joint 1's axis toward the
viewer (above it for axes along +z and a target to the right): the cross product of
d and the elbow's offset from A is along joint 1's axis, which is -l1 l2 sin(t2) s1 > 0,
so t2 s1 < 0 (q2 < 0 on an arm without offsets whose axes point the same way).

The arithmetic is compiled (``planar2r_kernel``), one kernel for the general path (``run``)
and the prepared solve (``prepare_pose``, for ``armik.solve.prepared``): (x, y), 3-vector
and full-pose targets get the same answers and claims both ways; this file writes the
reasons.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from armik import reasons
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.model.geometry import Axes, Plane, angle_between, axis_lines, fmt
from armik.model.mimic import reason as mimic_reason
from armik.problem.settings import SolverSettings
from armik.solvers.answers import Answers
from armik.solvers.claims import claim
from armik.solvers.closed_form import planar2r_kernel as kernel
from armik.solvers.closed_form.sixr import SNAP
from armik.solvers.registry import SolverSpec, register
from armik.status import Status
from armik.targets.pose import Target
from armik.tolerances import PARALLEL_TOL

SINGULAR_TOL = kernel.SINGULAR_TOL  # |cos t2| beyond 1 - this: the two branches merge
ZERO_LENGTH = kernel.ZERO_LENGTH  # m


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
    return _GEOMETRY(arm)


def _measure_geometry(arm: ArmModel) -> Geometry:
    plane = arm.plane
    assert plane is not None  # planar2r applies to planar arms only (``classify``)
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


_GEOMETRY = Derived("planar 2R geometry", _measure_geometry)


def applies(arm: ArmModel, target: Target | None = None, _opts: object = None) -> str | None:
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
    return None


def flat(arm: ArmModel, opts: SolverSettings, orient: bool) -> np.ndarray:
    """The kernel's ``flat`` array (``planar2r_kernel``): the arm's geometry, plane and
    limits (remembered per arm) and the tolerances of ``opts``; ``orient``: the target's
    orientation is checked (a full pose, not ``position_only``)."""
    chain = _FLAT(arm)
    tail = (opts.tol_position, opts.tol_orientation, 1.0 if orient else 0.0)
    return np.concatenate((chain, tail))


def _flat_chain(arm: ArmModel) -> np.ndarray:
    geo, plane = geometry(arm), arm.plane
    assert plane is not None  # planar2r applies to planar arms only (``classify``)
    parts = [
        geo.shoulder,
        [geo.l1, geo.l2, geo.alpha1, geo.alpha2, geo.s1, geo.s2],
        geo.R_tip0,
        plane.origin,
        plane.x,
        plane.y,
        plane.normal,
        arm.lower,
        arm.upper,
    ]
    chain = np.concatenate([np.ravel(np.asarray(x, dtype=float)) for x in parts])
    assert chain.size == kernel.TOL_POSITION
    return chain


_FLAT = Derived("planar 2R flat chain", _flat_chain)


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings, all_solutions: bool
) -> Answers:
    orient = target.rotation is not None and not opts.position_only
    H = np.eye(4)
    H[:3, 3] = target.position
    if target.rotation is not None:
        H[:3, :3] = target.rotation
    xy = target.planar_xy
    planar = xy is not None  # given in plane coordinates: on the plane
    x, y = (float(xy[0]), float(xy[1])) if xy is not None else (0.0, 0.0)
    if not (q0.dtype == float and q0.flags.c_contiguous and q0.flags.writeable):
        q0 = np.array(q0, dtype=float)  # one compiled signature: a writeable C array
    out = np.empty((2, 8))
    n = kernel.rows(flat(arm, opts, orient), H, q0, planar, x, y, out)
    return _answers(out[:n], out[:n, :2].copy(), arm)


_BRANCHES = {
    kernel.NO_BRANCH: None,
    kernel.UP: "elbow-up",
    kernel.DOWN: "elbow-down",
    kernel.STRETCHED: "stretched",
    kernel.FOLDED: "folded",
}
_FREE = "target at the shoulder with l1 = l2: joint 1 is free, kept nearest q0"
_CLOSEST = "q is the closest reachable configuration"


def _merged(name: str) -> str:
    return f"singular: the arm is fully {name}, the two elbow branches coincide"


def _reason(code: float, v0: float, v1: float, branch: str | None) -> str:
    """The text of a kernel row's reason code and values."""
    if code == kernel.CLOSED_FORM:
        return "closed form"
    if code == kernel.MERGED:
        return _merged(branch or "")
    if code == kernel.FREE:
        return _FREE
    if code == kernel.OFF_PLANE:
        return f"target is {v0:.6g} m off the arm's plane of motion"
    if code == kernel.TOO_FAR:
        where = f"too far: beyond the reach l1 + l2 = {v1:.6g} m{reasons.by_how_much(v0, v1, 6)}"
        return f"target at distance {v0:.6g} m from the shoulder is {where}; {_CLOSEST}"
    if code == kernel.DEAD_ZONE:
        by = reasons.by_how_much(v0, v1, 6)
        where = f"inside the inner dead zone: closer than |l1 - l2| = {v1:.6g} m{by}"
        return f"target at distance {v0:.6g} m from the shoulder is {where}; {_CLOSEST}"
    if code == kernel.TILTED:
        return (
            f"target orientation is tilted {v0:.3g} rad out of the arm's "
            "plane; a planar arm only turns about its joint axis"
        )
    return (
        f"the {branch} branch reaches the position with tip angle "
        f"{v0:.6g} rad, the target asks {v1:.6g} rad; a 2-link "
        "arm cannot choose both"
    )


def _farther(out: np.ndarray, q0: np.ndarray) -> bool:
    """Whether the kernel's first row is farther from ``q0`` than its second, by the
    verdict's own distance (``seed_distance``: a tie keeps the kernel's order)."""
    d = out[:2, :2] - q0
    return math.sqrt(d[0].dot(d[0])) > math.sqrt(d[1].dot(d[1]))


def _answers(rows: np.ndarray, Q: np.ndarray, arm: ArmModel) -> Answers:
    """The answers of the kernel's rows, in their order, q the rows of ``Q`` (a joint up to
    ``sixr.SNAP`` past a limit put on it, in place: the elbow's acos near the fold loses
    digits, so a configuration on a limit there comes back up to ~1e-11 rad past it; the
    FK check measures the move, 1e-7 m per metre of reach at most)."""
    np.clip(
        Q,
        np.where(Q >= arm.lower - SNAP, arm.lower, Q),
        np.where(Q <= arm.upper + SNAP, arm.upper, Q),
        out=Q,
    )
    claims, texts, labels, flags = [], [], [], []
    for claimed, branch, singular, code, v0, v1 in rows[:, 2:].tolist():
        label = _BRANCHES[branch]
        claims.append(Status.CONVERGED if claimed == kernel.CONVERGED else Status.UNREACHABLE)
        texts.append(_reason(code, v0, v1, label))
        labels.append(label)
        flags.append(bool(singular))
    return Answers.of(Q, claims, texts, 2, branch=labels, singular=flags)


# A claim of the prepared solve by its kind (``kernel.solve_into``'s head >> 1): its
# branch, singular, and reason (as ``Claim.reason(*reason_args)``: str(text))
_CLAIMS = (
    ("elbow-up", False, ("closed form",)),
    ("elbow-down", False, ("closed form",)),
    ("stretched", True, (_merged("stretched"),)),
    ("folded", True, (_merged("folded"),)),
    ("folded", True, (_FREE,)),
)


def prepare_pose(arm: ArmModel, opts: SolverSettings, position: bool):
    """``run_pose(H, q0, seed, every=False, xy=None)`` for ``armik.solve.prepared``: the
    kernel's answer for one plain 4x4 target ``H`` (a position's: ``position``), or with
    ``xy`` the target (x, y) in plane coordinates (then ``H`` holds it in the base frame):
    the ``Claim`` of the row the general verdict would verify first when it is claimed
    converged within the limits; else (and with ``every``) every row's ``Answers``, nearest
    q0 first, q read-only; None when ``H`` or ``q0`` is not plain."""
    chain = flat(arm, opts, not position and not opts.position_only)
    solve_into = kernel.solve_into
    empty = np.empty

    def run_pose(H: np.ndarray, q0: np.ndarray, seed: int, every: bool = False, xy=None):
        out = empty((2, 8))
        if xy is None:
            n, head = solve_into(chain, H, q0, False, 0.0, 0.0, every, out)
        else:
            n, head = solve_into(chain, H, q0, True, xy[0], xy[1], every, out)
        if head >= 0:
            label, singular, text = _CLAIMS[head >> 1]
            return claim((out[head & 1, :2], 0, 0, label, singular, str, text))
        if n < 0:
            return None
        if n == 2 and _farther(out, q0):  # nearest q0 first, as solve_all lists them
            out[:2] = out[1::-1].copy()
        got = _answers(out[:n], out[:n, :2], arm)
        got.q.setflags(write=False)  # solve_all's results' q are its rows
        return got

    run_pose.takes_xy = True  # type: ignore[attr-defined]  # prepared reads it: (x, y) too
    return run_pose


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
    up_is_plus = geo.s1 < 0  # elbow-up: t2 s1 < 0 (the module)
    q_up, q_down = out if up_is_plus else out[::-1]
    return q_up, q_down, reachable


SPEC = register(
    SolverSpec(
        name="planar2r",
        kind="analytic",
        enforces_limits=True,
        priority=100,
        why_not=applies,
        solves=frozenset({"position_only"}),
        run=run,
        summary="closed form for planar two-revolute chains: both elbow branches",
        prepare_pose=prepare_pose,
    )
)
