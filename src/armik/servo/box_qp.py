"""The servo's box QP where the fast active-set iteration cycles, compiled: the step
within the velocity box nearest the desired one in the metric of the damped normal matrix,
by a primal active-set method (Nocedal and Wright, Numerical Optimization, 16.5).

``kernel.step.active_set`` (a primal-dual iteration: two or three solves with the inverse
already at hand) is tried first. It can cycle where the normal matrix couples the joints
strongly (a torso under an arm, joints at their limits); the step was then the desired
one clipped to the box, which need not lower the error at all: at a target the limits
keep out of reach the arm then wandered at up to 1 rad/s and never settled.

The primal method keeps every iterate inside the box and never raises the objective:
from a feasible start it moves to the minimiser over the joints not held at a bound,
stopping at the first bound in the way (that joint is then held), and frees the held
joint whose multiplier has the wrong sign once no free move helps. Each round lowers the
objective or grows the held set, so no set comes back and it ends in at most a few rounds
per joint; the rounds are capped all the same, and the last iterate (within the box, no
worse than its start) is then the step.
"""

from __future__ import annotations

from numba import njit

from armik.kernel.linalg import cholesky_factor, cholesky_substitute

ROUNDS = 4  # rounds per joint at most (each joint held and freed twice)
KKT = 1e-13  # a multiplier of the wrong sign by less than this (of the gradient's size) is 0


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def nearest_in_box(H, t, lb, ub, x, side, free, L, r, p):
    """x: the minimiser of ``(x - t)^T H (x - t)`` over ``lb <= x <= ub`` (H symmetric
    positive definite, lb <= ub). Starts from the better of t and 0 clipped into the box.
    Returns False where the rounds ran out (x is then the last iterate, within the box).
    ``side``, ``free`` (ints), ``L`` (n x n), ``r``, ``p`` (n) are scratch."""
    n = t.shape[0]
    # the start: t clipped (the bounds it crosses usually are the answer's), unless 0
    # clipped is nearer, so that the answer never lowers the error less than staying put
    for i in range(n):
        p[i] = min(max(t[i], lb[i]), ub[i]) - t[i]
        r[i] = min(max(0.0, lb[i]), ub[i]) - t[i]
    zero = _form(H, r, n) < _form(H, p, n)
    for i in range(n):
        s = 0.0 if zero else t[i]
        if s <= lb[i]:
            x[i], side[i] = lb[i], 1
        elif s >= ub[i]:
            x[i], side[i] = ub[i], -1
        else:
            x[i], side[i] = s, 0
    for _ in range(ROUNDS * n + 2):
        _gradient(H, x, t, p, r, n)
        held = 0
        for i in range(n):
            free[i] = 1 if side[i] == 0 else 0
            held += 1 - free[i]
        if held < n:  # the minimiser over the free joints: H_FF p_F = -r_F
            if not cholesky_factor(H, free, L):
                return False
            cholesky_substitute(L, r, free, p)
        alpha, block = 1.0, -1
        for i in range(n):
            if free[i] == 0:
                p[i] = 0.0
                continue
            p[i] = -p[i]
            if x[i] + p[i] < lb[i] and p[i] < 0.0:
                a = (lb[i] - x[i]) / p[i]
                if a < alpha:
                    alpha, block = a, i
            elif x[i] + p[i] > ub[i] and p[i] > 0.0:
                a = (ub[i] - x[i]) / p[i]
                if a < alpha:
                    alpha, block = a, i
        for i in range(n):
            x[i] = min(max(x[i] + alpha * p[i], lb[i]), ub[i])
        if block >= 0:  # a bound in the way: held there
            x[block] = lb[block] if p[block] < 0.0 else ub[block]
            side[block] = 1 if p[block] < 0.0 else -1
            continue
        # the minimiser over the free joints: free the held joint that most wants to
        # leave its bound (multiplier side * r < 0), if any
        _gradient(H, x, t, p, r, n)
        size = 0.0
        for i in range(n):
            size = max(size, abs(r[i]))
        worst, most = -1, KKT * size
        for i in range(n):
            if side[i] != 0 and side[i] * r[i] < -most:
                worst, most = i, -side[i] * r[i]
        if worst < 0:
            return True
        side[worst] = 0
    return False


@njit(cache=True, nogil=True, inline="always")
def _gradient(H, x, t, d, r, n):
    """r = H (x - t) (d: scratch)."""
    for i in range(n):
        d[i] = x[i] - t[i]
    for i in range(n):
        s = 0.0
        for j in range(n):
            s += H[i, j] * d[j]
        r[i] = s


@njit(cache=True, nogil=True, inline="always")
def _form(H, d, n):
    """d^T H d."""
    s = 0.0
    for i in range(n):
        for j in range(n):
            s += d[i] * H[i, j] * d[j]
    return s
