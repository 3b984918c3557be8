"""Entries for one plain pose: the common input checked in compiled code, then the solve.

``solve`` spends most of its time outside the iteration when the target is easy; these
entries take the target as the 4x4 matrix the caller has (``SE3.homogeneous`` or the user's
array) and the seed as given, check in compiled code that both are what the parser and
``ArmModel.seed`` would pass through unchanged (``plain_pose``, ``plain_seed``), and only then
solve. Anything else returns False at once, and the caller takes the general path, which
parses, clips or refuses with the reason.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import Flat, joints, lower, upper
from armik.kernel.descent import solve_one_dls, solve_one_qp
from armik.kernel.entry import MINIMA_CAPACITY
from armik.kernel.measure import inside_limits, split_pose
from armik.kernel.problem import _workspace
from armik.kernel.problem import unpack as unpack_settings
from armik.tolerances import LAST_ROW_TOL, LIMIT_TOL, MAX_POSITION

ORTHONORMAL_TOL = 1e-14  # |R^T R - I| that the parser keeps without snapping to a rotation


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def plain_pose(H):
    """True when the 4x4 ``H`` is a pose the parser keeps exactly as given: finite, last
    row (0, 0, 0, 1), position within MAX_POSITION, rotation orthonormal to 1e-14 with
    determinant +1."""
    for a in range(3):
        if not abs(H[a, 3]) <= MAX_POSITION:  # NaN fails too
            return False
        for b in range(3):
            if not math.isfinite(H[a, b]):
                return False
    for b in range(4):
        if not abs(H[3, b] - (1.0 if b == 3 else 0.0)) <= LAST_ROW_TOL:
            return False
    worst = 0.0
    for a in range(3):
        for b in range(a, 3):
            g = H[0, a] * H[0, b] + H[1, a] * H[1, b] + H[2, a] * H[2, b]
            worst = max(worst, abs(g - (1.0 if a == b else 0.0)))
    det = (
        H[0, 0] * (H[1, 1] * H[2, 2] - H[1, 2] * H[2, 1])
        - H[0, 1] * (H[1, 0] * H[2, 2] - H[1, 2] * H[2, 0])
        + H[0, 2] * (H[1, 0] * H[2, 1] - H[1, 1] * H[2, 0])
    )
    return worst <= ORTHONORMAL_TOL and det > 0.0


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def plain_seed(q, lo, hi):
    """True when every value of ``q`` is finite and within [lo - tol, hi + tol]: the seeds
    ``ArmModel.seed`` returns unchanged."""
    for v in q:  # an unbounded (continuous) joint's limits let inf through
        if not math.isfinite(v):
            return False
    return inside_limits(q, lo, hi, LIMIT_TOL)


# The two entries spell out the same few lines rather than inline one helper taking the
# step: numba inlines by copying the callee's IR (compile time in every process). The solve
# itself is ``descent.solve_one_dls`` (or ``_qp``), compiled once for these entries and
# ``entry``'s.
@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_pose_dls(packed, kind, halton, sf, si, H, q0, seed, out_q, info, err):
    """One target, the 4x4 pose ``H`` in the base frame, from ``q0`` with restart seed
    ``seed``, with the dls step; outputs as ``descent.solve_one`` (out_q (S, n), info (5,),
    err (2,)). False, without solving, when ``H`` or ``q0`` is not plain."""
    ch = Flat(packed, kind, halton)
    if not plain_pose(H) or not plain_seed(q0, lower(ch), upper(ch)):
        return False
    st = unpack_settings(sf, si)
    R_t, p_t = split_pose(H)
    ws = _workspace(q0.shape[0], min(st.max_restarts + 1, MINIMA_CAPACITY), joints(ch))
    solve_one_dls(ch, st, R_t, p_t, q0, np.uint64(seed), ws, out_q, info, err)
    return True


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_pose_qp(packed, kind, halton, sf, si, H, q0, seed, out_q, info, err):
    """``solve_pose_dls`` with the qp step."""
    ch = Flat(packed, kind, halton)
    if not plain_pose(H) or not plain_seed(q0, lower(ch), upper(ch)):
        return False
    st = unpack_settings(sf, si)
    R_t, p_t = split_pose(H)
    ws = _workspace(q0.shape[0], min(st.max_restarts + 1, MINIMA_CAPACITY), joints(ch))
    solve_one_qp(ch, st, R_t, p_t, q0, np.uint64(seed), ws, out_q, info, err)
    return True


POSE_ENTRIES = (solve_pose_dls, solve_pose_qp)  # indexed by problem.STEP_DLS, STEP_QP
