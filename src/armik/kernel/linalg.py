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


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def cholesky6(H, g, x):
    """x solves the 6 x 6 system H x = g by Cholesky, every row free. The loops of
    ``cholesky_solve`` written out for six rows, in the same order (the same numbers): the
    factor stays in registers, where the loops stored it and read it back (the Panda's dls
    step: 390 -> 340 ns, ``benchmarks/kernel_iteration.py``). No caller reads the factor
    afterwards, so it is not stored. Returns False when H is not positive definite in
    floating point."""
    s = H[0, 0]
    if not s > 0.0:
        return False
    l00 = 1.0 / math.sqrt(s)
    s = H[1, 0]
    l10 = s * l00
    s = H[1, 1] - l10 * l10
    if not s > 0.0:
        return False
    l11 = 1.0 / math.sqrt(s)
    s = H[2, 0]
    l20 = s * l00
    s = H[2, 1] - l20 * l10
    l21 = s * l11
    s = H[2, 2] - l20 * l20 - l21 * l21
    if not s > 0.0:
        return False
    l22 = 1.0 / math.sqrt(s)
    s = H[3, 0]
    l30 = s * l00
    s = H[3, 1] - l30 * l10
    l31 = s * l11
    s = H[3, 2] - l30 * l20 - l31 * l21
    l32 = s * l22
    s = H[3, 3] - l30 * l30 - l31 * l31 - l32 * l32
    if not s > 0.0:
        return False
    l33 = 1.0 / math.sqrt(s)
    s = H[4, 0]
    l40 = s * l00
    s = H[4, 1] - l40 * l10
    l41 = s * l11
    s = H[4, 2] - l40 * l20 - l41 * l21
    l42 = s * l22
    s = H[4, 3] - l40 * l30 - l41 * l31 - l42 * l32
    l43 = s * l33
    s = H[4, 4] - l40 * l40 - l41 * l41 - l42 * l42 - l43 * l43
    if not s > 0.0:
        return False
    l44 = 1.0 / math.sqrt(s)
    s = H[5, 0]
    l50 = s * l00
    s = H[5, 1] - l50 * l10
    l51 = s * l11
    s = H[5, 2] - l50 * l20 - l51 * l21
    l52 = s * l22
    s = H[5, 3] - l50 * l30 - l51 * l31 - l52 * l32
    l53 = s * l33
    s = H[5, 4] - l50 * l40 - l51 * l41 - l52 * l42 - l53 * l43
    l54 = s * l44
    s = H[5, 5] - l50 * l50 - l51 * l51 - l52 * l52 - l53 * l53 - l54 * l54
    if not s > 0.0:
        return False
    l55 = 1.0 / math.sqrt(s)
    y0 = g[0] * l00
    y1 = (g[1] - l10 * y0) * l11
    y2 = (g[2] - l20 * y0 - l21 * y1) * l22
    y3 = (g[3] - l30 * y0 - l31 * y1 - l32 * y2) * l33
    y4 = (g[4] - l40 * y0 - l41 * y1 - l42 * y2 - l43 * y3) * l44
    y5 = (g[5] - l50 * y0 - l51 * y1 - l52 * y2 - l53 * y3 - l54 * y4) * l55
    z5 = y5 * l55
    z4 = (y4 - l54 * z5) * l44
    z3 = (y3 - l43 * z4 - l53 * z5) * l33
    z2 = (y2 - l32 * z3 - l42 * z4 - l52 * z5) * l22
    z1 = (y1 - l21 * z2 - l31 * z3 - l41 * z4 - l51 * z5) * l11
    z0 = (y0 - l10 * z1 - l20 * z2 - l30 * z3 - l40 * z4 - l50 * z5) * l00
    x[0], x[1], x[2], x[3], x[4], x[5] = z0, z1, z2, z3, z4, z5
    return True


@njit(cache=True, nogil=True, inline="always")
def cholesky_block(S, k, mu, L):
    """L: the Cholesky factor of the k x k leading block of S - mu I, with the INVERSE of
    its diagonal on the diagonal (one division per row instead of one per entry); False
    where that block is not positive definite."""
    for i in range(k):
        for j in range(i + 1):
            s = S[i, j] - mu if i == j else S[i, j]
            for m in range(j):
                s -= L[i, m] * L[j, m]
            if i == j:
                if not s > 0.0:
                    return False
                L[i, i] = 1.0 / math.sqrt(s)
            else:
                L[i, j] = s * L[j, j]
    return True


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def cholesky_factor(H, free, L):
    """L: the Cholesky factor of H[F][:, F] (F: the joints where ``free``, ints, is not 0),
    in the rows and columns of F, with the INVERSE of its diagonal on the diagonal (one
    division per row instead of one per entry). Returns False when H is not positive
    definite there."""
    n = H.shape[0]
    if _all(free):  # the usual case: no mask to test in the inner loops
        return cholesky_block(H, n, 0.0, L)
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


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
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


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def cholesky_solve(H, g, free, L, x):
    """x solves H[F][:, F] x = g[F] on the joints F where ``free`` (ints) is not 0 (H
    symmetric positive definite); x is 0 elsewhere. ``L`` is n x n scratch. Returns False
    when the factorisation fails (H not positive definite in floating point)."""
    if not cholesky_factor(H, free, L):
        return False
    cholesky_substitute(L, g, free, x)
    return True


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def solve_spd(H, g, free, L, x):
    """``cholesky_solve``; when H is not positive definite in floating point, the diagonal
    is raised by 1e-12, 1e-10, ... of its largest entry until it is (x = 0 if never)."""
    # factor and substitute called directly rather than through ``cholesky_solve``: one
    # compiled function less between the step and the loops (each costs compile time)
    if cholesky_factor(H, free, L):
        cholesky_substitute(L, g, free, x)
        return
    _solve_jittered(H, g, free, L, x)


# _nrt=True spelled out: a callee that does not set it inherits its caller's setting
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=True)
def _solve_jittered(H, g, free, L, x):
    """``solve_spd`` once the plain factorisation failed (it allocates: compiled with the
    runtime that ``solve_spd`` goes without)."""
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
        if cholesky_factor(H, free, L):
            cholesky_substitute(L, g, free, x)
            ok = True
            break
        jitter *= 100.0
    for i in range(n):
        H[i, i] = saved[i]
    if not ok:
        x[:] = 0.0
