"""Pushing a colliding answer clear with the servo's collision rows.

A numeric solve whose verified answer collides is stepped out of contact before any
restart: at the answer, each checked pair nearer than ``margin + CLEARANCE`` gives the
servo's row (``armik.servo.collisions``: coal's distance d, its witness points' Jacobians
along the normal, the broad phase by the checker's bounds)

    n . (J_p2 - J_p1) dq >= margin + CLEARANCE - d

and the step is the least joint motion that meets those rows while keeping the tip's pose
to first order (the pose Jacobian's rows weighted ``POSE_WEIGHT``), within the joint
limits. The numeric solver then starts from the pushed joint values with no restart, so
that the pose is met again exactly; its answer gets the verdict and the collision check as
any other (``armik.solve.avoid``). A redundant arm moves through its self-motion, any arm
through the configurations next to the answer on its branch.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik.servo.collisions import CollisionRows

if TYPE_CHECKING:
    from armik.constraints.collision import Checker
    from armik.model.arm_model import ArmModel

CLEARANCE = 0.02  # m beyond the margin that a push opens each near pair to
PUSHES = 3  # pushes of one solve, at most, each followed by one descent
POSE_WEIGHT = 30.0  # of the tip's pose rows against the pairs' rows (unit weight)
MOTION_WEIGHT = 0.01  # of the joint motion itself (keeps the step small where rows allow)
MAX_STEP = 0.5  # rad (m): the largest joint move of one push


def pushed(arm: ArmModel, check: Checker, q: np.ndarray, margin: float) -> np.ndarray | None:
    """The joint values (rad, m) one push from ``q`` opens every checked pair nearer than
    ``margin + CLEARANCE`` (m) toward that distance, the tip's pose held to first order;
    None when no pair is that near (nothing to push)."""
    rows = CollisionRows(check, margin + CLEARANCE, 1.0, active=0.0)
    near = rows.at(q)  # the pairs inside the clearance
    if near.shape[0] == 0:
        return None
    model, data = arm.model, rows.data  # ``at`` computed the joints' Jacobians there
    frame = arm.tip_frame_id
    pin.updateFramePlacements(model, data)
    J = pin.getFrameJacobian(model, data, frame, pin.LOCAL)
    n = arm.dof
    A = np.vstack([POSE_WEIGHT * J, near[:, :-1], MOTION_WEIGHT * np.eye(n)])
    y = np.concatenate([np.zeros(6), near[:, -1], np.zeros(n)])
    dq = np.linalg.lstsq(A, y, rcond=None)[0]
    biggest = float(np.abs(dq).max())
    if biggest > MAX_STEP:
        dq *= MAX_STEP / biggest
    return np.clip(q + dq, arm.lower, arm.upper)
