"""The verification's errors, computed from Pinocchio's tip placements in compiled code.

Pinocchio computes the placements (``verify.py``); this module only measures them against
the targets: position error |p_target - p_tip| (m), orientation error the geodesic angle of
R_tip^T R_target (rad); with weights, the position error is measured in the tip frame on the
axes with non-zero weight and the orientation error on the rotation-vector components with
non-zero weight, as ``verify.check`` documents.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .se3 import log3, rotation_angle

LIMIT_TOL = 1e-12  # armik.arm.LIMIT_TOL: this close outside a limit counts as inside


@njit(cache=True, nogil=True)
def pose_error(R_bw, p_bw, R_w, p_w, R_t, p_t, w, weighted, measure_rot):
    """(position error, orientation error or NaN) of the tip placement T_world_tip =
    (R_w, p_w) against the target (R_t, p_t) in the base frame; T_base_world = (R_bw, p_bw)."""
    R = np.empty((3, 3))
    M = np.empty((3, 3))
    d = np.empty(3)
    for a in range(3):  # T_base_tip = T_base_world T_world_tip
        pa = p_bw[a]
        for b in range(3):
            pa += R_bw[a, b] * p_w[b]
            R[a, b] = R_bw[a, 0] * R_w[0, b] + R_bw[a, 1] * R_w[1, b] + R_bw[a, 2] * R_w[2, b]
        d[a] = p_t[a] - pa
    for a in range(3):  # M = R^T R_target
        for b in range(3):
            M[a, b] = R[0, a] * R_t[0, b] + R[1, a] * R_t[1, b] + R[2, a] * R_t[2, b]
    if not weighted:
        ori = rotation_angle(M) if measure_rot else np.nan
        return math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), ori
    s = 0.0
    for a in range(3):  # the position error in the tip frame, measured axes only
        if w[a] > 0.0:
            x = R[0, a] * d[0] + R[1, a] * d[1] + R[2, a] * d[2]
            s += x * x
    pos = math.sqrt(s)
    if not measure_rot:
        return pos, np.nan
    wv = np.empty(3)
    log3(M, wv)
    s = 0.0
    for a in range(3):
        if w[3 + a] > 0.0:
            s += wv[a] * wv[a]
    return pos, math.sqrt(s)


@njit(cache=True, nogil=True)
def pose_errors(R_bw, p_bw, R_w, p_w, R_t, p_t, w, weighted, measure_rot, out):
    """out[i] = ``pose_error`` of placement i against target i, for every i."""
    for i in range(R_w.shape[0]):
        out[i, 0], out[i, 1] = pose_error(
            R_bw, p_bw, R_w[i], p_w[i], R_t[i], p_t[i], w, weighted, measure_rot
        )


@njit(cache=True, nogil=True)
def within_limits(Q, lower, upper, tol, out):
    """out[i]: every joint of row i within [lower - tol, upper + tol] (NaN is outside)."""
    for i in range(Q.shape[0]):
        ok = True
        for j in range(Q.shape[1]):
            if not (lower[j] - tol <= Q[i, j] <= upper[j] + tol):
                ok = False
                break
        out[i] = ok


@njit(cache=True, nogil=True)
def pose_check(R_bw, p_bw, limits, H_w, H_t, w, measure, q):
    """(position error, orientation error or NaN, within the limits) of one answer ``q``
    whose tip placement Pinocchio computed as the 4x4 ``H_w`` (world frame), against the
    4x4 target ``H_t`` (base frame): ``pose_error`` and ``within_limits`` in one call.
    (R_bw, p_bw): T_base_world; ``limits``: (2, n) lower and upper; ``measure``: bit 1
    weighted, bit 2 orientation measured."""
    # C-ordered copies: ``pose_error`` is then the one ``verify.check`` has compiled
    R_w, p_w, R_t, p_t = np.empty((3, 3)), np.empty(3), np.empty((3, 3)), np.empty(3)
    for a in range(3):
        p_w[a] = H_w[a, 3]
        p_t[a] = H_t[a, 3]
        for b in range(3):
            R_w[a, b] = H_w[a, b]
            R_t[a, b] = H_t[a, b]
    pos, ori = pose_error(R_bw, p_bw, R_w, p_w, R_t, p_t, w, measure & 1 != 0, measure & 2 != 0)
    inside = True
    for j in range(q.shape[0]):
        if not (limits[0, j] - LIMIT_TOL <= q[j] <= limits[1, j] + LIMIT_TOL):  # NaN fails
            inside = False
    return pos, ori, inside


@njit(cache=True, nogil=True)
def pose_checks(R_bw, p_bw, limits, H_w, H_t, w, measure, Q, out):
    """out[i] = ``pose_check`` of answer Q[i] with tip placement H_w[i], for every i."""
    for i in range(Q.shape[0]):
        out[i, 0], out[i, 1], inside = pose_check(R_bw, p_bw, limits, H_w[i], H_t, w, measure, Q[i])
        out[i, 2] = 1.0 if inside else 0.0
