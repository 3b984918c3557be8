"""The smallest singular value that the servo's damping reads, compiled: the r-th largest
singular value of the task Jacobian A (r = min(counted rows, n, the rows' structural
rank)), by inverse iteration.

Which rows count, and at which scale, is the row's ``scale`` (``armik.servo.tick``'s
``stack``): 0 for a row the task does not ask for (a freed axis, a zero weight, a region's
row inside its bounds, a direction the arm never moves), else 1 over the row's weight, so
that sigma is that of the unweighted rows the task asks for. A row that the task asks for
counts even where it is zero at this q: that is the singularity (a stretched arm's row
along its line), not a row to leave out.

It is the smallest eigenvalue of the smaller Gram matrix, ``A_r A_r^T`` over the r counted
rows when r <= n, else ``A^T A`` (their nonzero eigenvalues are the same). Each round is
shifted to just below the Rayleigh quotient, an upper bound of the eigenvalue (a shift
above it fails to factor, and a lower one is tried), so that from the last tick's vector
(the arm moves little in a tick) two or three rounds reach rounding. A full
eigen-decomposition (Jacobi, even from the last tick's eigenvectors) cost about a third
of a tick; the step itself solves with the damped normal matrix by Cholesky.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.linalg import cholesky_block

ROUNDS = 30  # at most; two or three from the last tick's vector
SETTLED = 1e-14  # stop when a round moves the estimate by less (of the Gram's trace)
SHIFT = 1e-13  # of the trace: keeps a singular Gram's factor positive definite
BELOW = 0.98  # the shift: this share of the Rayleigh quotient, where it keeps S - shift I
# positive definite
COLD = np.bool_(False)  # a fixed start (typed: a literal would compile ``smallest`` again)


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def gram(A, rows, active, scale, S, idx):
    """k: the size of the smaller Gram matrix of A's first ``rows`` rows, each row times
    its ``scale`` (0: not counted; ``active`` of them counted), written into S's top-left
    k x k block; ``idx`` (n ints) is scratch."""
    n = A.shape[1]
    if active > n:  # (A^T A over the counted rows: the others are zero or scaled out)
        for i in range(n):
            for j in range(i + 1):
                s = 0.0
                for r in range(rows):
                    if scale[r] != 0.0:
                        s += A[r, i] * A[r, j] * scale[r] * scale[r]
                S[i, j] = s
                S[j, i] = s
        return n
    k = 0
    for r in range(rows):
        if scale[r] != 0.0:
            idx[k] = r
            k += 1
    for a in range(k):
        for b in range(a + 1):
            s = 0.0
            for c in range(n):
                s += A[idx[a], c] * A[idx[b], c]
            s *= scale[idx[a]] * scale[idx[b]]
            S[a, b] = s
            S[b, a] = s
    return k


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def smallest(S, k, u, warm, L, y):
    """The smallest eigenvalue of the symmetric positive semidefinite k x k block of S, by
    shifted inverse iteration from u[:k] (``warm``: the last call's vector, of this size)
    or from a fixed start; u[:k] ends as its eigenvector. L (n x n) and y (n) are
    scratch."""
    if k == 0:
        return math.inf
    trace = 0.0
    for i in range(k):
        trace += S[i, i]
    if not trace > 0.0:
        return 0.0
    if not warm:  # any start with a share on every eigenvector
        for i in range(k):
            u[i] = 1.0 + 0.618034 * i
    _normalise(u, k)
    rq = _rayleigh(S, u, k)
    rung = _factor_below(S, k, rq, trace, L)
    for _ in range(ROUNDS):
        if rung < 0:
            return 0.0
        _substitute(L, k, u, y)
        for i in range(k):
            u[i] = y[i]
        _normalise(u, k)
        now = _rayleigh(S, u, k)
        settled = abs(rq - now) <= SETTLED * trace
        rq = min(rq, now)
        if settled:
            break
        if rung > 0:  # a shift far below: closer to the new quotient, if it factors
            rung = _factor_below(S, k, rq, trace, L)
    return max(rq, 0.0)


@njit(cache=True, nogil=True, inline="always")
def _factor_below(S, k, rq, trace, L):
    """L: the factor of S - mu I for the largest mu of ``BELOW`` rq, ``rq / 2``, 0 and
    then ``-SHIFT trace`` (raised a hundredfold at a time) that leaves it positive
    definite: a shift just below the smallest eigenvalue (rq bounds it from above) makes
    each round of inverse iteration converge fast. Returns which (0: the first), -1 for
    none."""
    for step in range(12):
        if step == 0:
            mu = BELOW * rq
        elif step == 1:
            mu = 0.5 * rq
        elif step == 2:
            mu = 0.0
        else:
            mu = -SHIFT * trace * 100.0 ** (step - 3)
        if cholesky_block(S, k, mu, L):
            return step
    return -1


@njit(cache=True, nogil=True, inline="always")
def _substitute(L, k, g, x):
    """x[:k]: the solution of L L^T x = g over the k x k block."""
    for i in range(k):
        s = g[i]
        for m in range(i):
            s -= L[i, m] * x[m]
        x[i] = s * L[i, i]
    for i in range(k - 1, -1, -1):
        s = x[i]
        for m in range(i + 1, k):
            s -= L[m, i] * x[m]
        x[i] = s * L[i, i]


@njit(cache=True, nogil=True, inline="always")
def _normalise(u, k):
    s = 0.0
    for i in range(k):
        s += u[i] * u[i]
    s = 1.0 / math.sqrt(s)
    for i in range(k):
        u[i] *= s


@njit(cache=True, nogil=True, inline="always")
def _rayleigh(S, u, k):
    """u^T S u over the k x k block (u of unit length)."""
    s = 0.0
    for i in range(k):
        t = 0.0
        for j in range(k):
            t += S[i, j] * u[j]
        s += u[i] * t
    return s


@njit(cache=True, nogil=True, inline="always")
def _lift(S, k, v):
    """S's k x k block plus its trace times v v^T (v of unit length): v's eigenvalue, near
    zero, raised above every other, which keep theirs where v is an eigenvector."""
    trace = 0.0
    for i in range(k):
        trace += S[i, i]
    for i in range(k):
        for j in range(k):
            S[i, j] += trace * v[i] * v[j]


@njit(cache=True, nogil=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def smallest_singular(A, rows, active, rank, scale, S, u, last_k, L, y, idx, v):
    """(sigma, k): the r-th largest singular value of A's rows times their ``scale`` (r =
    min(active, n, rank), ``active`` the rows of nonzero scale, ``rank`` at most how many
    of them are independent at any q: ``tick.rank_bound``) and the size k of the Gram
    matrix it came from; u holds the last call's vector where that was of size
    ``last_k``. Where r < k, the k - r smallest eigenvalues (zero at every q) are found
    first and lifted out of the way, each by inverse iteration from a fixed start into v
    (n floats, scratch). ``idx`` (n ints) is scratch."""
    k = gram(A, rows, active, scale, S, idx)
    for _ in range(k - min(k, rank)):
        smallest(S, k, v, COLD, L, y)
        _lift(S, k, v)
    ev = smallest(S, k, u, k == last_k, L, y)
    return (math.sqrt(ev) if ev < math.inf else math.inf), k
