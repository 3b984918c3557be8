"""Small dense solves of a step: Cholesky on a subset of the joints, no allocation."""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True, inline="always")
def copy_to(dst, src):
    """dst[:] = src for 1-d arrays of one length, as a loop: numba's array-to-array slice
    assignment compiles its shape-mismatch message (string formatting) at ~2 s per process."""
    for i in range(dst.shape[0]):
        dst[i] = src[i]


@njit(cache=True, nogil=True, inline="always")
def _all(free):
    for i in range(free.shape[0]):
        if not free[i]:
            return False
    return True


@njit(cache=True, nogil=True, inline="always")
def cholesky_dense(H, L, g, x):
    """x solves H x = g by Cholesky (L: scratch, lower factor with its inverse diagonal),
    every row free: ``cholesky_solve`` without the mask, for the 6 x 6 task-space system.
    Returns False when H is not positive definite in floating point."""
    n = H.shape[0]
    for i in range(n):
        for j in range(i + 1):
            s = H[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            if i == j:
                if not s > 0.0:
                    return False
                L[i, i] = 1.0 / math.sqrt(s)
            else:
                L[i, j] = s * L[j, j]
    for i in range(n):
        s = g[i]
        for k in range(i):
            s -= L[i, k] * x[k]
        x[i] = s * L[i, i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, n):
            s -= L[k, i] * x[k]
        x[i] = s * L[i, i]
    return True


@njit(cache=True, nogil=True)
def cholesky_factor(H, free, L):
    """L: the Cholesky factor of H[F][:, F] (F: the joints where ``free``, ints, is not 0),
    in the rows and columns of F, with the INVERSE of its diagonal on the diagonal (one
    division per row instead of one per entry). Returns False when H is not positive
    definite there."""
    n = H.shape[0]
    if _all(free):  # the usual case: no mask to test in the inner loops
        for i in range(n):
            for j in range(i + 1):
                s = H[i, j]
                for k in range(j):
                    s -= L[i, k] * L[j, k]
                if i == j:
                    if not s > 0.0:
                        return False
                    L[i, i] = 1.0 / math.sqrt(s)
                else:
                    L[i, j] = s * L[j, j]
        return True
    for i in range(n):
        if not free[i]:
            continue
        for j in range(i + 1):
            if not free[j]:
                continue
            s = H[i, j]
            for k in range(j):
                if free[k]:
                    s -= L[i, k] * L[j, k]
            if i == j:
                if not s > 0.0:
                    return False
                L[i, i] = 1.0 / math.sqrt(s)
            else:
                L[i, j] = s * L[j, j]
    return True


@njit(cache=True, nogil=True)
def cholesky_substitute(L, g, free, x):
    """x: the solution of L L^T x = g on the joints F of ``cholesky_factor``, 0 elsewhere."""
    n = L.shape[0]
    if _all(free):
        for i in range(n):  # L y = g
            s = g[i]
            for k in range(i):
                s -= L[i, k] * x[k]
            x[i] = s * L[i, i]
        for i in range(n - 1, -1, -1):  # L^T x = y
            s = x[i]
            for k in range(i + 1, n):
                s -= L[k, i] * x[k]
            x[i] = s * L[i, i]
        return
    for i in range(n):  # L y = g
        if not free[i]:
            x[i] = 0.0
            continue
        s = g[i]
        for k in range(i):
            if free[k]:
                s -= L[i, k] * x[k]
        x[i] = s * L[i, i]
    for i in range(n - 1, -1, -1):  # L^T x = y
        if not free[i]:
            continue
        s = x[i]
        for k in range(i + 1, n):
            if free[k]:
                s -= L[k, i] * x[k]
        x[i] = s * L[i, i]


@njit(cache=True, nogil=True)
def cholesky_solve(H, g, free, L, x):
    """x solves H[F][:, F] x = g[F] on the joints F where ``free`` (ints) is not 0 (H
    symmetric positive definite); x is 0 elsewhere. ``L`` is n x n scratch. Returns False
    when the factorisation fails (H not positive definite in floating point)."""
    if not cholesky_factor(H, free, L):
        return False
    cholesky_substitute(L, g, free, x)
    return True


@njit(cache=True, nogil=True)
def solve_spd(H, g, free, L, x):
    """``cholesky_solve``; when H is not positive definite in floating point, the diagonal
    is raised by 1e-12, 1e-10, ... of its largest entry until it is (x = 0 if never)."""
    if cholesky_solve(H, g, free, L, x):
        return
    n = H.shape[0]
    scale = 0.0
    for i in range(n):
        scale = max(scale, abs(H[i, i]))
    saved = np.empty(n)
    for i in range(n):
        saved[i] = H[i, i]
    jitter = 1e-12 * max(scale, 1e-300)
    ok = False
    for _ in range(12):
        for i in range(n):
            H[i, i] = saved[i] + jitter
        if cholesky_solve(H, g, free, L, x):
            ok = True
            break
        jitter *= 100.0
    for i in range(n):
        H[i, i] = saved[i]
    if not ok:
        x[:] = 0.0
