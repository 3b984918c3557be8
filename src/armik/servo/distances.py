"""The true distances a servo command leaves to its target's tasks, compiled: what a tick
reports (``ServoStep.position_error``, ``orientation_error``) and whether a position target
lies beyond the arm's reach.

They are what ``solve`` reports (``armik.verify.distances``, docs/tolerances.md): the
frame's distance to the task's position and the geodesic angle to its rotation, whatever
its bounds (an infinite one included) and weights. A part a task does not have
(``PARTS``: a position's rotation, an axis' position) is not measured (NaN); an aim's is
the angle of the tip's axis from its direction.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.problem import LOOK_POINT, LOOK_TOWARD
from armik.servo.layout import (
    AXIS,
    BOUNDS,
    CONE,
    LOOK,
    ORI_ERR,
    PARTS,
    POS,
    POS_ERR,
    ROT,
    SIGHT,
)


@njit(cache=True, nogil=True, inline="always")
def _measured(row, k):
    """Whether the task's bounds measure position (k = 0) or rotation (k = 3) at all."""
    for i in range(k, k + 3):
        if row[BOUNDS + i] < math.inf:
            return True
    return False


@njit(cache=True, nogil=True, inline="always")
def _position(row, p):
    """The distance of p from the task's position, |p - p_t| (m)."""
    d0, d1, d2 = p[0] - row[POS], p[1] - row[POS + 1], p[2] - row[POS + 2]
    return math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)


@njit(cache=True, nogil=True, inline="always")
def _rotation(row, R):
    """The geodesic angle of R from the task's rotation, |log3(R_t^T R)| (rad): from the
    trace and the skew part of R_t^T R."""
    tr = sx = sy = sz = 0.0
    for i in range(3):
        for k in range(3):
            tr += row[ROT + 3 * k + i] * R[k, i]
    for k in range(3):  # M[2,1]-M[1,2], M[0,2]-M[2,0], M[1,0]-M[0,1], M = R_t^T R
        rk0, rk1, rk2 = row[ROT + 3 * k], row[ROT + 3 * k + 1], row[ROT + 3 * k + 2]
        sx += rk2 * R[k, 1] - rk1 * R[k, 2]
        sy += rk0 * R[k, 2] - rk2 * R[k, 0]
        sz += rk1 * R[k, 0] - rk0 * R[k, 1]
    s = 0.5 * math.sqrt(sx * sx + sy * sy + sz * sz)
    return math.atan2(s, 0.5 * (tr - 1.0))


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def distances(table, R, p, origin, reach_, slack, out):
    """out[POS_ERR], out[ORI_ERR]: the largest true distances to the tasks' targets (NaN
    where no task has that part); returns whether a position target is beyond the arm's
    reach."""
    pos = ori = -1.0
    far = False
    for t in range(table.shape[0]):
        row = table[t]
        cone = row[CONE]
        if row[PARTS] != 0.0:
            pos = max(pos, _position(row, p))
        if _measured(row, 0):
            b = 0.0
            for i in range(3):
                b += row[BOUNDS + i] * row[BOUNDS + i]
            x0, x1, x2 = row[POS] - origin[0], row[POS + 1] - origin[1], row[POS + 2] - origin[2]
            if math.sqrt(x0 * x0 + x1 * x1 + x2 * x2) > reach_ + math.sqrt(b) + slack:
                far = True
        if cone < 0.0 and row[PARTS + 1] != 0.0:
            ori = max(ori, _rotation(row, R))
        elif cone >= 0.0:  # the angle of the tip's axis from its direction
            look = np.int64(row[LOOK])
            x0, x1, x2 = row[SIGHT], row[SIGHT + 1], row[SIGHT + 2]
            if look == LOOK_POINT:
                x0, x1, x2 = x0 - p[0], x1 - p[1], x2 - p[2]
            elif look != LOOK_TOWARD:  # the target's image of the axis, in the base frame
                a0, a1, a2 = row[AXIS], row[AXIS + 1], row[AXIS + 2]
                x0 = row[ROT] * a0 + row[ROT + 1] * a1 + row[ROT + 2] * a2
                x1 = row[ROT + 3] * a0 + row[ROT + 4] * a1 + row[ROT + 5] * a2
                x2 = row[ROT + 6] * a0 + row[ROT + 7] * a1 + row[ROT + 8] * a2
            w0 = R[0, 0] * x0 + R[1, 0] * x1 + R[2, 0] * x2  # R^T x: in the tip frame
            w1 = R[0, 1] * x0 + R[1, 1] * x1 + R[2, 1] * x2
            w2 = R[0, 2] * x0 + R[1, 2] * x1 + R[2, 2] * x2
            a0, a1, a2 = row[AXIS], row[AXIS + 1], row[AXIS + 2]
            c0, c1, c2 = a1 * w2 - a2 * w1, a2 * w0 - a0 * w2, a0 * w1 - a1 * w0
            s = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
            k = a0 * w0 + a1 * w1 + a2 * w2
            ori = max(ori, math.atan2(s, k) if s > 0.0 or k != 0.0 else 0.0)
    out[POS_ERR] = pos if pos >= 0.0 else math.nan
    out[ORI_ERR] = ori if ori >= 0.0 else math.nan
    return far
