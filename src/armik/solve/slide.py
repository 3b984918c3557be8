"""Sliding out of a collision: damped least squares on the pose with every checked pair
closer than an activation distance as a linear inequality on the step (a velocity
damper, as Pink's barriers): for the witness points p1, p2 of a pair at distance d, its
normal n (from p1 to p2) and the points' Jacobians,

    n . (J_p2 - J_p1) dq >= -XI (d - margin) / (D_ACT - margin)

so no pair closes faster than the damper allows, and one inside the margin is pushed out.
Each step solves that small QP (the joint limits as rows too) by an active set, exactly.
The pose is what the verdict measures (``_goal``): the axes ``weights`` and
``position_only`` free are free here too; a region (``bounds``) is its distance outside the
box, and a target with an aim (``targets.aim``: a cone, a look-at, a direction) its axis
within the cone (``aim_task``), not the rotation beside it: an answer the verdict takes
keeps what it took it for, and the region's freedom is the slide's too.
A Python loop over Pinocchio and coal calls: ``solve.avoid`` uses it only when a numeric
solver's verified answer collides, starting from that answer (it reaches the pose, so the
slide keeps the pose and moves the arm out of contact, through its redundancy or its
other reachable configurations nearby).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik import cpu_time
from armik.problem.settings import SolverSettings
from armik.problem.tasks.axis import Axis
from armik.problem.tasks.look_at import LookAt
from armik.problem.tasks.pose import Pose
from armik.verify.measure import measures_of

if TYPE_CHECKING:
    from armik.constraints.collision import Checker
    from armik.model.arm_model import ArmModel
    from armik.problem.tasks.base import Task
    from armik.targets.pose import Target

D_ACT = 0.05  # m beyond the margin: pairs closer than this get a row
XI = 0.5  # the damper's gain: the share of the gap a step may close
DAMPING = 1e-4  # of the least squares on the pose
MAX_STEP = 0.2  # rad (m): the largest joint move of one step
MAX_ROWS_ADDED = 12  # active-set passes of one step


def slide(
    arm: ArmModel,
    target: Target,
    q: np.ndarray,
    check: Checker,
    margin: float,
    iterations: int,
    deadline: float,
    tol: float,
    opts: SolverSettings | None = None,
) -> tuple[np.ndarray, int]:
    """(q, iterations used): the configuration reached from ``q`` (rad, m) within
    ``iterations`` steps and before ``deadline`` (``cpu_time.thread_time``), stopping once the
    error ``opts`` measure (``_goal``: None, an exact pose) is within ``tol`` (m, rad) and
    every checked pair ``margin`` (m) apart."""
    model, data = arm.model, arm.data
    frame = arm.tip_frame_id
    goal = _goal(arm, target, SolverSettings() if opts is None else opts)
    qp = arm.to_pin(q)
    lower, upper = arm.lower, arm.upper
    for it in range(iterations):
        if cpu_time.thread_time() > deadline:
            return arm.from_pin(qp), it
        pin.computeJointJacobians(model, data, qp)
        M = pin.updateFramePlacement(model, data, frame)
        e, J = goal(M)
        q_now = arm.from_pin(qp)
        A, b, d_min = _rows(arm, check, q_now, margin)
        if d_min >= margin and np.abs(e).max() < tol:
            return q_now, it
        A = np.vstack([A, np.eye(arm.dof), -np.eye(arm.dof)])
        b = np.concatenate([b, lower - q_now, q_now - upper])
        keep = np.isfinite(b)
        dq = _qp(J, e, A[keep], b[keep])
        biggest = np.abs(dq).max()
        if biggest > MAX_STEP:
            dq *= MAX_STEP / biggest
        qp = pin.integrate(model, qp, dq)
    return arm.from_pin(qp), iterations


def _goal(arm: ArmModel, target: Target, opts: SolverSettings):
    """``goal(M)`` -> (e, J): the error the slide drives to 0 at the tip placement ``M``
    (world) and its Jacobian in the tip's axes, the error the verdict measures
    (``verify.measure``): the axes ``weights`` and ``position_only`` free are no rows; with a
    region (``bounds``, an aim) the distance outside it (``verify.region``), the position
    within its box in the target's axes and the rotation within its box or the tip axis
    within its cone (``aim_task``), not the region's centre."""
    model, data, frame = arm.model, arm.data, arm.tip_frame_id
    w, weighted, rotation = measures_of(
        arm, opts.weights, opts.position_only, target.rotation is None
    )
    T_goal = arm.T_world_base * target.se3()
    if opts.bounds is not None or target.aim is not None:
        free = np.where(w > 0.0, np.array(opts.region_bounds), np.inf)  # as the verdict frees
        box, aim = Pose(target.se3(), bounds=free), aim_task(target)

        def region(M: pin.SE3) -> tuple[np.ndarray, np.ndarray]:
            J_tip = pin.getFrameJacobian(model, data, frame, pin.LOCAL)
            T_base = arm.T_base_world * M
            e, J = -box.residual(T_base), box.jacobian(T_base, J_tip)
            if aim is not None:  # the cone replaces the rotation's rows
                e, J = (
                    np.concatenate([e[:3], -aim.residual(T_base)]),
                    np.vstack([J[:3], aim.jacobian(T_base, J_tip)]),
                )
            return e, J

        return region
    if not rotation and not weighted:  # the distance to a point
        return lambda M: (
            T_goal.translation - M.translation,
            pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)[:3],
        )
    if not weighted:  # the full pose: its error twist in the tip's axes
        return lambda M: (
            pin.log6(M.actInv(T_goal)).vector,
            pin.getFrameJacobian(model, data, frame, pin.LOCAL),
        )
    rows = np.flatnonzero(w[:6] > 0.0 if rotation else w[:3] > 0.0)  # the axes measured

    def pose(M: pin.SE3) -> tuple[np.ndarray, np.ndarray]:
        # the verdict's errors in the tip's axes, each zero where the target is reached:
        # x = R^T (p_t - p), r = log3(R^T R_t); apart, as a weight frees one and not the
        # other (log6's translation turns with the rotation a zero weight leaves free)
        J_tip = pin.getFrameJacobian(model, data, frame, pin.LOCAL)
        Jv, Jw = J_tip[:3], J_tip[3:]
        x = M.rotation.T @ (T_goal.translation - M.translation)
        R = M.rotation.T @ T_goal.rotation
        r = pin.log3(R)
        e = np.concatenate([x, r])
        J = np.vstack([Jv - pin.skew(x) @ Jw, pin.Jlog3(R) @ R.T @ Jw])
        return e[rows], J[rows]

    return pose


def aim_task(target: Target) -> Task | None:
    """The task a target's aim asks of the tip (``targets.aim``), whose residual is zero
    inside the cone and whose angle outside it is what the verdict measures; None without
    an aim. The rotation beside an aim only says where the cone points."""
    aim = target.aim
    if aim is None:
        return None
    if aim.point is not None:
        return LookAt(aim.point, aim.axis, aim.within)
    direction = aim.toward
    if direction is None:  # the target rotation's image of the axis
        direction = target.se3().rotation @ np.array(aim.axis)
    return Axis(aim.axis, direction, aim.within)


def _rows(
    arm: ArmModel, check: Checker, q: np.ndarray, margin: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """The damper's rows (A, b) of the pairs closer than ``margin + D_ACT`` at the arm's
    last FK, at joint values ``q``, and the smallest distance among them (inf when none is
    that close)."""
    model, data = arm.model, arm.data
    gm = check.model
    gd = check.geometry_data()
    pin.updateGeometryPlacements(model, data, gm, gd)
    bound = check.bounds(q)
    reach = margin + D_ACT
    rows, rhs = [], []
    d_min = np.inf
    for k in np.flatnonzero(bound < reach).tolist():
        r = pin.computeDistance(gm, gd, k)
        d = r.min_distance
        d_min = min(d_min, d)
        if d >= reach:
            continue
        pair = gm.collisionPairs[k]
        n = np.array(r.normal)
        Jd = _point_jacobian(arm, gm, pair.second, np.array(r.getNearestPoint2()))
        Jd -= _point_jacobian(arm, gm, pair.first, np.array(r.getNearestPoint1()))
        rows.append(n @ Jd)
        rhs.append(-XI * (d - margin) / D_ACT)
    if not rows:
        return np.zeros((0, arm.dof)), np.zeros(0), d_min
    return np.array(rows), np.array(rhs), d_min


def _point_jacobian(arm: ArmModel, gm: pin.GeometryModel, i: int, p: np.ndarray) -> np.ndarray:
    """The 3 x dof Jacobian of a point ``p`` (world) fixed to geometry object ``i``."""
    joint = gm.geometryObjects[i].parentJoint
    if joint == 0:
        return np.zeros((3, arm.dof))
    J = pin.getJointJacobian(arm.model, arm.data, joint, pin.LOCAL_WORLD_ALIGNED)
    r = p - arm.data.oMi[joint].translation
    return J[:3] - np.cross(r, J[3:].T).T  # v + w x r = Jv - [r]x Jw


def _qp(J: np.ndarray, e: np.ndarray, A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """argmin |J dq - e|^2 + DAMPING |dq|^2 subject to A dq >= b, by an active set: the
    most violated row joins, a row whose multiplier turns negative leaves."""
    n = J.shape[1]
    H = J.T @ J + DAMPING * np.eye(n)
    g = J.T @ e
    active: list[int] = []
    dq = np.linalg.solve(H, g)
    for _ in range(MAX_ROWS_ADDED):
        gap = A @ dq - b
        gap[active] = 0.0
        worst = int(np.argmin(gap)) if len(gap) else -1
        if worst < 0 or gap[worst] >= -1e-12:
            break
        active.append(worst)
        while active:
            Aw = A[active]
            K = np.block([[H, -Aw.T], [Aw, np.zeros((len(active), len(active)))]])
            sol = np.linalg.lstsq(K, np.concatenate([g, b[active]]), rcond=None)[0]
            dq, mult = sol[:n], sol[n:]
            if mult.min() >= -1e-12:
                break
            active.pop(int(np.argmin(mult)))
    return dq
