"""The eigen-decomposition of a small symmetric matrix (cyclic Jacobi), compiled: the servo's
normal matrix ``A^T A`` gives its singular values (how close the arm is to a singularity)
and, damped, its inverse, with no factorisation that can fail.
"""

from __future__ import annotations

import math

from numba import njit

SWEEPS = 30  # at most: the off-diagonal part falls quadratically, 5-8 sweeps in practice
OFF_TOL = 1e-30  # stop when the off-diagonal squares are below this times the diagonal's


# (numba's hints lack the target options: the kernel's modules are exempt in pyproject.toml)
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def jacobi(B, V, ev):
    """ev (n,), V (n, n): eigenvalues and eigenvectors (columns) of the symmetric B, so that
    B = V diag(ev) V^T; B is overwritten (its diagonal ends as ev)."""
    n = B.shape[0]
    for i in range(n):
        for j in range(n):
            V[i, j] = 1.0 if i == j else 0.0
    for _ in range(SWEEPS):
        off = diag = 0.0
        for i in range(n):
            diag += B[i, i] * B[i, i]
            for j in range(i + 1, n):
                off += B[i, j] * B[i, j]
        if not off > OFF_TOL * diag:
            break
        for p in range(n - 1):
            for q in range(p + 1, n):
                apq = B[p, q]
                if apq == 0.0:
                    continue
                theta = (B[q, q] - B[p, p]) / (2.0 * apq)
                t = 1.0 / (abs(theta) + math.sqrt(theta * theta + 1.0))
                if theta < 0.0:
                    t = -t
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(n):  # B J, then J^T (B J), V J: J rotates (p, q) by (c, s)
                    bp, bq = B[k, p], B[k, q]
                    B[k, p] = c * bp - s * bq
                    B[k, q] = s * bp + c * bq
                for k in range(n):
                    bp, bq = B[p, k], B[q, k]
                    B[p, k] = c * bp - s * bq
                    B[q, k] = s * bp + c * bq
                for k in range(n):
                    vp, vq = V[k, p], V[k, q]
                    V[k, p] = c * vp - s * vq
                    V[k, q] = s * vp + c * vq
    for i in range(n):
        ev[i] = B[i, i]


@njit(cache=True, nogil=True, inline="always")
def kth_largest(ev, k, tmp):
    """The k-th largest (k >= 1) of ev; ``tmp`` (n,) is scratch."""
    n = ev.shape[0]
    for i in range(n):  # insertion sort, descending (n is a joint count)
        x = ev[i]
        j = i
        while j > 0 and tmp[j - 1] < x:
            tmp[j] = tmp[j - 1]
            j -= 1
        tmp[j] = x
    return tmp[k - 1]


@njit(cache=True, nogil=True)
def eigen(B, V, ev):
    """``jacobi`` for Python callers (the tests)."""
    jacobi(B, V, ev)
