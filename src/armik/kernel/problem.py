"""The per-solve settings and the scratch memory of the kernel.

``Settings`` is built once per (options, kind of target, arm size) in Python; ``Workspace``
is allocated once per kernel call and reused by every target and iteration.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

STEP_DLS, STEP_QP = 0, 1
NO_LIMIT = -1  # for timeout_ns and iteration_budget: not used
NO_CONE = -1.0  # for Settings.cone: the rotation rows are the bounds'
NO_LOOK, LOOK_POINT, LOOK_TOWARD = 0, 1, 2  # Settings.look: the cone around R_t a, the
# line from the tip to look_point, the base-frame direction look_point


class Settings(NamedTuple):
    """What every target of a kernel call shares. Lengths m, angles rad, time ns."""

    w: np.ndarray  # (6,) weights on (v, w) of the error; 0 for a free axis
    full_task: bool  # every weight 1: skip the masking
    measure_position: bool  # some position weight is non-zero
    tol_pos: float  # the iteration's tolerances: half the verification's
    tol_rot: float
    null_gain: float  # null-space pull toward q0 or the posture (0: the task uses every joint)
    max_iterations: int  # per attempt
    max_restarts: int
    max_found: int  # stop after this many distinct solutions
    timeout_ns: int  # thread CPU time per target, or NO_LIMIT
    iteration_budget: int  # iterations per target, or NO_LIMIT
    step: int  # STEP_DLS or STEP_QP
    backend: int  # index of the QP backend in ``box_qp.backends()``
    check_reach: bool  # every position axis measured: far targets fail at once
    reach_slack: float  # m, added to the reach bound (the verification's tolerance)
    pull_scale: float  # 1 / the largest weight: the null-space pull's measure of the error
    translation_rows: bool  # free position and rotation axes both (see ``error._evaluate``)
    region: bool  # the target has bounds: ``region._evaluate_region`` measures the error
    bounds: np.ndarray  # (6,) the region's bounds (m, rad; inf: free), read when ``region``
    cone: float  # the tip axis' cone angle (rad), replacing the rotation rows; NO_CONE: none
    cone_axis: np.ndarray  # (3,) that axis, unit, in the tip frame
    look: int  # NO_LOOK, LOOK_POINT (a LookAt's), LOOK_TOWARD (an Axis around a box)
    look_point: np.ndarray  # (3,) that point (m) or unit direction, in the base frame
    posture: np.ndarray  # (n,) the null-space pull's reference, or (0,): q0
    posture_w: np.ndarray  # (n,) its weight on each joint, or (0,)


# Rows of Workspace.vec (n-vectors), .mat (n x n) and .ivec (integer n-vectors).
DQ, X, XF, LB, UB, G, UNIT, GAP, MULT, BEST, SHIFT, CAND, U = range(13)
NVEC = 13
H, L, GI, HH = range(4)  # normal matrix, Cholesky factor, H^-1, held block of H^-1
SIDE, HELD, FREE = range(3)


class Workspace(NamedTuple):
    """Scratch for one thread (uninitialised: every reader writes first). States live in
    slots 0 and 1 (current and trial). Few arrays, grouped by shape: numba's compile time
    grows with the arrays a tuple argument holds."""

    q: np.ndarray  # (2, n) joint values
    e: np.ndarray  # (2, 6) weighted error twist
    A: np.ndarray  # (2, 6, n) weighted error Jacobian
    val: np.ndarray  # (2, 3): position error, orientation error, |e|^2
    vec: np.ndarray  # (NVEC, n)
    mat: np.ndarray  # (4, n, n)
    ivec: np.ndarray  # (3, n) int64
    geo: np.ndarray  # (2, N, 3): the physical joints' origins and axes in the base frame
    J: np.ndarray  # (6, n) tip Jacobian, LOCAL
    m3: np.ndarray  # (2, 3, 3): tip rotation, T_tip^-1 T_target rotation
    v3: np.ndarray  # (3, 3): tip position, T_tip^-1 T_target translation, rotation vector
    Jlog: np.ndarray  # (6, 6)
    minima: np.ndarray  # (capacity, n) where earlier attempts of a solve got stuck
    task: np.ndarray  # (6, 6): the dls step's A A^T + lambda I
    tvec: np.ndarray  # (2, 6): its right-hand side and solution


def pack_settings(st: Settings) -> tuple[np.ndarray, np.ndarray]:
    """``st`` as a float and an int array (what compiled entries take; see ``unpack``)."""
    floats = [*st.w, st.tol_pos, st.tol_rot, st.null_gain, st.reach_slack, st.pull_scale]
    floats += [*st.bounds, *st.cone_axis, st.cone, *st.look_point, *st.posture, *st.posture_w]
    ints = [st.full_task, st.measure_position, st.max_iterations, st.max_restarts]
    ints += [st.max_found, st.timeout_ns, st.iteration_budget, st.step, st.backend]
    ints += [st.check_reach, st.translation_rows, st.region, st.look, len(st.posture)]
    return np.array(floats), np.array(ints, dtype=np.int64)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def unpack(sf, si):
    """The ``Settings`` that ``pack_settings`` flattened into (sf, si)."""
    m = si[13]  # the posture's length: 0 or n
    return Settings(
        sf[0:6],
        si[0] != 0,
        si[1] != 0,
        sf[6],
        sf[7],
        sf[8],
        si[2],
        si[3],
        si[4],
        si[5],
        si[6],
        si[7],
        si[8],
        si[9] != 0,
        sf[9],
        sf[10],
        si[10] != 0,
        si[11] != 0,
        sf[11:17],
        sf[20],
        sf[17:20],
        si[12],
        sf[21:24],
        sf[24 : 24 + m],
        sf[24 + m : 24 + 2 * m],
    )


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True)
def _workspace(n, capacity, nj):
    """Scratch for n joint values and nj physical joints (nj > n with mimic joints)."""
    return Workspace(
        np.empty((2, n)),
        np.empty((2, 6)),
        np.empty((2, 6, n)),
        np.empty((2, 3)),
        np.empty((NVEC, n)),
        np.empty((4, n, n)),
        np.empty((3, n), dtype=np.int64),
        np.empty((2, nj, 3)),
        np.empty((6, n)),
        np.empty((2, 3, 3)),
        np.empty((3, 3)),
        np.empty((6, 6)),
        np.empty((max(capacity, 1), n)),
        np.empty((6, 6)),
        np.empty((2, 6)),
    )


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def workspace(n, capacity, nj):
    """``_workspace`` for Python callers (the kernel's copy goes without the CPython wrapper,
    whose boxing of the 15 arrays cost compile time in every process)."""
    return _workspace(n, capacity, nj)
