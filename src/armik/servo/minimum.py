"""Whether the servo has stalled, compiled: the nearest the arm gets to its target within
its position limits, where it then holds still.

First order (``first_order``): the gradient of the squared error, ``A^T E``, projected onto
the directions the position limits leave (a joint at its lower limit cannot move down), is
under ``STALL`` of the Jacobian's and the error's sizes. That also holds at a saddle: an
arm stretched in a plane of symmetry, its elbow and wrist at their limits, whose only way
on is to turn out of the plane (the error falls only at second order). So, second order
(``no_descent``): the Hessian of the squared error over the joints not held at a limit,
``A^T A`` plus the error times the rows' second derivatives (``curvature_column``, from
the rows at q moved a little along each such joint), has no eigenvalue below ``SADDLE``
times the curvature length times the error. Only then is the tick ``stalled`` and the
step held: a local minimum, within the limits, of the error, not a point the arm leaves
(a flat valley's slide, 1 % of the error over 30 s, is not followed).
"""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.linalg import cholesky_factor
from armik.servo.layout import CURVE, HI, LO, Q

# the error's part the joints can still remove, below which a tick makes no progress: the
# gradient of the squared error, |A^T E| over the joints free to move, against |A|_F |E|
# (zero at a least-squares minimum: a pose the arm cannot take, the nearest it gets)
STALL = 1e-3
# a curvature below -SADDLE x the curvature length x the error is a way on (the flat
# valley of a stretched TALOS arm, -1.3e-6 at an error of 9 mm, is not)
SADDLE = 1e-2
PROBE = 1e-6  # rad (m): the move along each joint that measures the rows' derivatives
# rad (m): a joint this near a limit is at it (braking reaches a limit to rounding within
# a few ticks: each leaves about the square of the gap over 2 amax dt^2)
ON_LIMIT = 1e-10


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def first_order(E, A, rows, state, cfg, h, free):
    """Whether the projected gradient is under ``STALL`` (the module docstring); h = A^T E,
    ``free`` (ints): 0 for a joint at a position limit (within ``ON_LIMIT``) that h pushes
    past it, else 1."""
    n = A.shape[1]
    q = state[Q]
    grad2 = trace = err2 = 0.0
    for r in range(rows):
        err2 += E[r] * E[r]
    for i in range(n):
        s = t = 0.0
        for r in range(rows):
            s += A[r, i] * E[r]
            t += A[r, i] * A[r, i]
        h[i] = s
        trace += t
        up, down = state[HI, i] - q[i] <= ON_LIMIT, q[i] - state[LO, i] <= ON_LIMIT
        free[i] = 0 if (s > 0.0 and up) or (s < 0.0 and down) else 1
        grad2 += s * s if free[i] else 0.0
    return grad2 < STALL * STALL * trace * err2


@njit(cache=True, nogil=True, inline="always")
def curvature_column(E, A, Ap, rows, step, j, R):
    """R[:, j]: minus the error times the rows' derivatives along joint j, from the rows
    A at q and Ap at q moved ``step`` along it (E(q + x) = E - A x to first order)."""
    n = A.shape[1]
    for i in range(n):
        s = 0.0
        for r in range(rows):
            s += E[r] * (Ap[r, i] - A[r, i])
        R[i, j] = -s / step


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def no_descent(E, A, rows, R, free, cfg, H, L):
    """Whether the Hessian A^T A + (R + R^T) / 2 over the ``free`` joints has no eigenvalue
    below ``-SADDLE`` curvature length |E| (its factor with that added exists). ``H``, ``L``
    (n x n) are scratch."""
    n = A.shape[1]
    err2 = 0.0
    for r in range(rows):
        err2 += E[r] * E[r]
    tau = SADDLE * cfg[CURVE] * math.sqrt(err2)
    for i in range(n):
        for j in range(i + 1):
            s = 0.0
            for r in range(rows):
                s += A[r, i] * A[r, j]
            s += 0.5 * (R[i, j] + R[j, i])
            H[i, j] = s
            H[j, i] = s
        H[i, i] += tau
    return cholesky_factor(H, free, L)
