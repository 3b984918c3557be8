"""A stretched or folded elbow's one root where rounding split a double root, and its
mirror: both solved, and of each pair of rows the better kept where they are one solution
(within ``DUPLICATE_TOL``), both where they are two. The 6R closed forms' elbows
(``three_parallel``, ``spherical_wrist``, ``three_parallel_general``); the exported C has
the same (``export.c_source``'s ``elbow_roots`` and ``keep_nearer``)."""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.descent import DUPLICATE_TOL
from armik.solvers.closed_form.sixr import SNAP, TIE, TWO_PI
from armik.solvers.closed_form.subproblems import elbow, elbow_extreme, wrap


@njit(cache=True, no_cfunc_wrapper=True)
def _from_ref(v, ref, lo, hi):
    """|c - ref| for c the value of angle ``v`` (by whole turns) nearest ``ref`` within
    [lo, hi] (up to ``SNAP`` past a limit counts as on it); inf when no turn of it is."""
    near = v + TWO_PI * round((ref - v) / TWO_PI)
    best = math.inf
    for c in (near, near - TWO_PI, near + TWO_PI):
        if lo - SNAP <= c <= hi + SNAP and abs(c - ref) < best:
            best = abs(c - ref)
    return best


@njit(cache=True, no_cfunc_wrapper=True)
def mirror_root(p1, p2, k, theta):
    """The other root of a merged elbow root ``theta`` (``subproblems.elbow``'s one root
    where rounding split a double root): its mirror about the extreme beside it; theta
    itself where it lies on the extreme."""
    return wrap(2.0 * elbow_extreme(p1, p2, k, theta) - theta)


@njit(cache=True, no_cfunc_wrapper=True)
def elbow_roots(p1, p2, k, d, free):
    """``subproblems.elbow``'s (c0, c1, n, ls) for the span ``d`` and how many roots to
    solve: one, c0 = ``free`` (q0's), where every turn spans d (n = -1); two where rounding
    split a stretched or folded elbow's double root into one (n = 1, not least squares):
    c1 its mirror (``mirror_root``, both exact; ``keep_nearer`` keeps the better row of
    each pair that is one solution), one where that is c0 itself; else n."""
    c0, c1, n, ls = elbow(p1, p2, k, d)
    if n == -1:
        return free, c1, n, ls, 1
    if n == 1 and not ls:
        c1 = mirror_root(p1, p2, k, c0)
        return c0, c1, n, ls, 1 if c1 == c0 else 2
    return c0, c1, n, ls, n


@njit(cache=True, no_cfunc_wrapper=True)
def _row_cost(W, r, q0, lower, upper):
    """(joints of row ``r`` with no turn within their limits, the distance of joint 3's turn
    nearest q0's within its limits to q0's: the elbow's, whose root the row was solved
    from)."""
    outside = 0
    for j in range(6):
        if _from_ref(W[r, j], q0[j], lower[j], upper[j]) == math.inf:
            outside += 1
    return outside, _from_ref(W[r, 2], q0[2], lower[2], upper[2])


@njit(cache=True, no_cfunc_wrapper=True)
def keep_nearer(W, a, b, c, q0, lower, upper):
    """Rows [a, b) of ``W`` solved from a merged elbow root and rows [b, c) from its mirror
    (``mirror_root``: both exact, the same branches in the same order): of each pair whose
    rows lie within ``DUPLICATE_TOL`` of each other in every joint (one solution, split by
    rounding) the row with fewer joints outside the limits, then with joint 3 nearer q0's
    within its limits by more than ``TIE``, is left in [a, b); a pair further apart is two
    solutions, the mirror's row kept after [a, b). Returns the row count (where the counts
    differ the first rows are kept). The other joints follow the root to first order (1e-7
    rad and more on the Kinova's stretched elbow): the wrong root puts one on its limit
    past it, or the elbow itself (the UR5's at pi, a limit of +-pi)."""
    if c - b != b - a:
        return b
    n = b
    for i in range(b - a):
        if _apart(W, a + i, b + i):  # rows from [b, c) move down to n <= b + i
            for col in range(W.shape[1]):
                W[n, col] = W[b + i, col]
            n += 1
            continue
        out_a, d_a = _row_cost(W, a + i, q0, lower, upper)
        out_b, d_b = _row_cost(W, b + i, q0, lower, upper)
        if out_b < out_a or (out_b == out_a and d_b < d_a - TIE):
            for col in range(W.shape[1]):
                W[a + i, col] = W[b + i, col]
    return n


@njit(cache=True, no_cfunc_wrapper=True)
def _apart(W, r, s):
    """Whether rows r and s of ``W`` differ by ``DUPLICATE_TOL`` or more in a joint (by
    whole turns): two solutions, not one."""
    for j in range(6):
        if abs(wrap(W[r, j] - W[s, j])) >= DUPLICATE_TOL:
            return True
    return False
