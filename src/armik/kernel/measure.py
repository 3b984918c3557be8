"""The verification's errors, computed from tip placements in compiled code.

Pinocchio computes the placements of one answer (``verify/measure.py``) and this module
measures them against the targets; the answers of one target, all together
(``fk_checks``), are placed by the compiled FK (``armik.kernel.fk.forward``, Pinocchio's
placement to 1e-12: tests/kernel/test_fk_checks.py) in the same call. Errors: position
error |p_target - p_tip| (m), orientation error the geodesic angle of R_tip^T R_target
(rad); with weights, the position error is measured in the tip frame on the
axes with non-zero weight and the orientation error on the rotation-vector components with
non-zero weight, as ``verify.measure.measure`` documents.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import Flat, joints
from armik.kernel.fk import forward
from armik.kernel.fk_shared import STATE, forward_row
from armik.kernel.se3 import log3, rotation_angle
from armik.tolerances import LIMIT_TOL

ONE = np.int64(1)  # a typed count: a literal would compile ``_checks`` once more


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
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


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def pose_errors(R_bw, p_bw, R_w, p_w, R_t, p_t, w, weighted, measure_rot, out):
    """out[i] = ``pose_error`` of placement i against target i, for every i."""
    for i in range(R_w.shape[0]):
        out[i, 0], out[i, 1] = pose_error(
            R_bw, p_bw, R_w[i], p_w[i], R_t[i], p_t[i], w, weighted, measure_rot
        )


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def inside_limits(q, lower, upper, tol):
    """Every value of q within [lower - tol, upper + tol] (NaN is outside)."""
    for j in range(q.shape[0]):
        if not (lower[j] - tol <= q[j] <= upper[j] + tol):
            return False
    return True


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def within_limits(Q, lower, upper, tol, out):
    """out[i]: ``inside_limits`` of row i of Q."""
    for i in range(Q.shape[0]):
        out[i] = inside_limits(Q[i], lower, upper, tol)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def split_pose(H):
    """(R, p) of the 4x4 ``H`` as new C-ordered arrays (the layout ``pose_error`` and the
    kernels are compiled for)."""
    R = np.empty((3, 3))
    p = np.empty(3)
    for a in range(3):
        p[a] = H[a, 3]
        for b in range(3):
            R[a, b] = H[a, b]
    return R, p


def check_frame(R_bw, p_bw, w, measure: int, lower, upper) -> np.ndarray:
    """What ``placement_check`` measures against, packed in one float array (one argument to
    pass instead of six: each array argument costs numba's dispatch ~45 ns):
    R_bw (9, row-major), p_bw (3), w (6), measure, lower (n), upper (n). (R_bw, p_bw):
    T_base_world; ``measure``: bit 1 weighted, bit 2 orientation measured."""
    return np.concatenate(
        [
            np.ravel(np.asarray(R_bw, dtype=float)),
            np.asarray(p_bw, dtype=float),
            np.asarray(w, dtype=float),
            [float(measure)],
            np.asarray(lower, dtype=float),
            np.asarray(upper, dtype=float),
        ]
    )


def fk_check_frame(w, measure: int, lower, upper) -> np.ndarray:
    """``check_frame`` for ``fk_checks``: the compiled FK places the tip in the base frame,
    so T_base_world is the identity (exact: ``pose_error`` multiplies by ones and adds
    zeros)."""
    return check_frame(np.eye(3), np.zeros(3), w, measure, lower, upper)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _frame(frame):
    """(R_bw, p_bw, w, measure, lower, upper) of a ``check_frame`` array (views)."""
    n = (frame.shape[0] - 19) // 2
    return (
        frame[0:9].reshape((3, 3)),
        frame[9:12],
        frame[12:18],
        int(frame[18]),
        frame[19 : 19 + n],
        frame[19 + n : 19 + 2 * n],
    )


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def placement_check(frame, R_w, p_w, H_t, q):
    """(position error, orientation error or NaN, within the limits) of one answer ``q``
    whose tip placement Pinocchio computed as (R_w, p_w) (world frame; read in place:
    ``ArmModel.tip_views``), against the 4x4 target ``H_t`` (base frame): ``pose_error`` and
    ``inside_limits`` in one call; ``frame`` from ``check_frame``."""
    R_bw, p_bw, w, measure, lower, upper = _frame(frame)
    weighted, measure_rot = measure & 1 != 0, measure & 2 != 0
    pos, ori = pose_error(R_bw, p_bw, R_w, p_w, H_t, H_t[:3, 3], w, weighted, measure_rot)
    return pos, ori, inside_limits(q, lower, upper, LIMIT_TOL)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def pose_checks(frame, H_w, H_t, Q, out):
    """out[i] = ``placement_check`` of answer Q[i] with tip placement H_w[i], for every i (the
    target split once)."""
    R_t, p_t = split_pose(H_t)
    for i in range(Q.shape[0]):
        pos, ori, inside = _check(frame, H_w[i], R_t, p_t, Q[i])
        out[i, 0], out[i, 1], out[i, 2] = pos, ori, 1.0 if inside else 0.0


@njit(cache=True, nogil=True, inline="always")
def _check(frame, H_w, R_t, p_t, q):
    R_bw, p_bw, w, measure, lower, upper = _frame(frame)
    R_w, p_w = split_pose(H_w)
    pos, ori = pose_error(R_bw, p_bw, R_w, p_w, R_t, p_t, w, measure & 1 != 0, measure & 2 != 0)
    return pos, ori, inside_limits(q, lower, upper, LIMIT_TOL)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def fk_checks(packed, kind, halton, frame, H_t, Q, out):
    """out[i] = (position error, orientation error or NaN, 1.0 within the limits else 0.0)
    of the answer in the first n values of row i of Q (rows of n or more values: a closed
    form's packed rows too) against the 4x4 target ``H_t`` (base frame), its tip placement
    T_base_tip by the compiled FK of the chain ``chain.Flat``'s arrays, every row in one
    call; ``frame`` from ``check_frame`` with the identity as T_base_world."""
    _checks(packed, kind, halton, frame, H_t, Q, Q.shape[0], out, np.int64(0))


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def fk_checks_beside(packed, kind, halton, frame, H_t, rows, n, col, skip):
    """``fk_checks`` of the first ``n`` rows of ``rows`` but those of the bit set ``skip``,
    each row's three values written into its own columns ``col`` to ``col + 2`` (a closed
    form's rows measured in the call that solved them:
    ``armik.solvers.closed_form.sixr_judged``). Unweighted, rows that share leading joint
    values share their partial placement (``fk_shared``: the same bits)."""
    ch = Flat(packed, kind, halton)
    _, _, _, measure, lower, upper = _frame(frame)
    if joints(ch) != halton.shape[1] or measure & 1:  # mimic joints, weights: row by row
        for i in range(n):
            if not skip >> i & 1:
                row = rows[i : i + 1]
                _checks(packed, kind, halton, frame, H_t, row, ONE, row, col)
        return
    R, p, M = np.empty((3, 3)), np.empty(3), np.empty((3, 3))
    S = np.empty((n, joints(ch) + 1, STATE))
    R_t, p_t = split_pose(H_t)
    measure_rot = measure & 2 != 0
    placed = np.int64(0)  # typed: a literal 0 compiles forward_row once more
    for i in range(n):
        if skip >> i & 1:
            continue
        forward_row(ch, rows, i, S, R, p, placed)
        placed |= 1 << i
        pos, ori = _unweighted(R, p, R_t, p_t, M, measure_rot)
        inside = 1.0
        for j in range(lower.shape[0]):
            if not (lower[j] - LIMIT_TOL <= rows[i, j] <= upper[j] + LIMIT_TOL):
                inside = 0.0
        rows[i, col], rows[i, col + 1], rows[i, col + 2] = pos, ori, inside


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _checks(packed, kind, halton, frame, H_t, Q, n, out, col):
    ch = Flat(packed, kind, halton)
    N = joints(ch)
    R, p, M = np.empty((3, 3)), np.empty(3), np.empty((3, 3))
    origins, axes = np.empty((N, 3)), np.empty((N, 3))
    R_t, p_t = split_pose(H_t)
    R_bw, p_bw, w, measure, lower, upper = _frame(frame)
    weighted, measure_rot = measure & 1 != 0, measure & 2 != 0
    for i in range(n):
        q = Q[i]
        forward(ch, q, R, p, origins, axes)
        if weighted:
            pos, ori = pose_error(R_bw, p_bw, R, p, R_t, p_t, w, weighted, measure_rot)
        else:
            pos, ori = _unweighted(R, p, R_t, p_t, M, measure_rot)
        inside = 1.0
        for j in range(lower.shape[0]):
            if not (lower[j] - LIMIT_TOL <= q[j] <= upper[j] + LIMIT_TOL):
                inside = 0.0
        out[i, col], out[i, col + 1], out[i, col + 2] = pos, ori, inside


@njit(cache=True, nogil=True, inline="always")
def _unweighted(R, p, R_t, p_t, M, measure_rot):
    """``pose_error``'s arithmetic with T_base_world the identity, unweighted, in place
    (M: scratch)."""
    d0, d1, d2 = p_t[0] - p[0], p_t[1] - p[1], p_t[2] - p[2]
    pos = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    ori = np.nan
    if measure_rot:
        for a in range(3):  # M = R^T R_target
            for b in range(3):
                M[a, b] = R[0, a] * R_t[0, b] + R[1, a] * R_t[1, b] + R[2, a] * R_t[2, b]
        ori = rotation_angle(M)
    return pos, ori
