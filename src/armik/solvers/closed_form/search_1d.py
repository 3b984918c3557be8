"""The one-dimensional search of the 6R families that have no closed form (IK-Geo's
``search_1D``): one joint angle x is searched, every other joint follows from subproblems,
and a scalar error e(x) vanishes at the solutions.

A family has a compiled ``branches(x, ..., e, s)``: for the angle x (rad) the number m of
branches (up to ``BRANCHES``: the subproblem's solutions at x), their errors ``e[:m]`` and
their states ``s[:m]`` (the subproblem's angles, ``STATE`` columns, unused ones 0). It
samples e on a grid of ``GRID`` angles over one turn (``angle``). ``pair_brackets``
follows each branch from a sample to the next by its state (the nearest state, wrapped,
within ``JUMP``: the subproblem's solutions come in no fixed order) and brackets every
change of sign. Where the branches move fast or their count changes (``rough``: a fold,
where two branches are born or die together) the interval is sampled ``SUB`` times finer,
each finer piece halved where it is still rough (at most ``DEPTH`` times: two folds
between two samples leave the count unchanged but not the branches), and a fold is
located by bisection and bracketed from its side (``fold_brackets``); where a branch comes
close to zero without changing sign at the samples, the grid's or the finer ones
(``dips``), its
extremum is searched for two zeros closer than a grid step. The family refines every
bracket by regula falsi (Illinois: ``falsi`` and ``update``) on the same branch to full
precision. (The loops that call ``branches`` are in ``search_zeros``, which calls each
family's by a code: numba cannot cache a compiled function that receives another as an
argument.) ``polish`` then takes the configuration built from a zero to the target by
Newton steps on the whole pose; the family keeps it if it reaches the target, and
Pinocchio verifies it as every answer.

What can still be missed: a zero closer to a fold than 2^-17 of a grid step, or two zeros
of one branch within a grid step whose samples do not dip (``dips``' test); neither is
expected for a target away from a singularity, and ``benchmarks/families_6r.py`` counts
what is missed on random arms.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.solvers.closed_form.subproblems import (
    add,
    cross,
    mat,
    mm,
    mmt,
    mv,
    norm,
    rot,
    sp1,
    sub,
    vec,
)
from armik.solvers.closed_form.subproblems_56 import (
    ROOT_GATE,
    _circle,
    _on,
    _pairs,
    _system5,
    _system6,
)

BRANCHES = 4  # solutions of the subproblem at one angle
STATE = 3  # angles a branch is followed by
GRID = 200  # samples over one turn
JUMP = 0.5  # rad: a branch's state moves less than this between neighbouring samples
SMOOTH = 0.2  # rad: a branch moving more than this between samples is sampled finer
SUB = 8  # ... sampled this many times finer (the grid's dip test then runs on those)
DEPTH = 7  # ... and each finer piece halved at most this many times (to 2^-10 of a step)
ZEROS = 16  # at most this many zeros (solutions) are kept
ITERATIONS = 60  # of regula falsi in one bracket
CANDIDATES = 32  # brackets kept (a zero may be bracketed twice: at a fold and by samples)
FOLD_STEPS = 7  # bisections locating a fold in a piece (2^-17 of a grid step in all)
DIP_STEPS = 24  # golden-section steps locating a dip's extremum (0.618^24 of two steps)
GOLDEN = 0.6180339887498949
POLISH_TOL = 1e-13  # m and rad: Newton on the pose stops below this error


@njit(cache=True, no_cfunc_wrapper=True)
def _wrapped(a):
    return a - 2.0 * math.pi * round(a / (2.0 * math.pi))


@njit(cache=True, no_cfunc_wrapper=True)
def nearest(S, m, s):
    """(index, distance) of the state among ``S[:m]`` nearest ``s`` (largest wrapped
    angle difference); (-1, inf) when m = 0."""
    best, dbest = -1, math.inf
    for i in range(m):
        d = 0.0
        for c in range(STATE):
            d = max(d, abs(_wrapped(S[i, c] - s[c])))
        if d < dbest:
            best, dbest = i, d
    return best, dbest


@njit(cache=True, no_cfunc_wrapper=True)
def rough(Ea, Sa, ma, Eb, Sb, mb):
    """Whether the branches change too much between two samples to be bracketed from them
    alone (a different count: a fold between them; a branch whose state moves more than
    ``SMOOTH``; or two branches whose nearest states at the other sample are one, as next
    to a fold where they were born: each would be followed to it and the other's change
    of sign missed): then the family samples the interval finer."""
    if ma != mb:
        return True
    taken = 0  # the branches at b already followed to, as bits
    for i in range(ma):
        j, d = nearest(Sb, mb, Sa[i])
        if d > SMOOTH or taken & (1 << j):
            return True  # moving fast, or two branches nearest one: near a fold, told apart finer
        taken |= 1 << j
    return False


@njit(cache=True, no_cfunc_wrapper=True)
def pair_brackets(xa, Ea, Sa, ma, xb, Eb, Sb, mb, Bx, Bs, count):
    """The brackets between two samples at xa < xb (errors ``E``, states ``S``, counts
    ``m``): each branch at xa whose nearest at xb (within ``JUMP``) has the other sign
    gives (xa, f(xa), xb, f(xb), jump) in a row of ``Bx`` (``CANDIDATES``, 5; jump: how
    far the branch's state may move between two trials), its state at xb in ``Bs``.
    Returns the count."""
    for i in range(ma):
        j, d = nearest(Sb, mb, Sa[i])
        if j < 0 or d > JUMP or (Ea[i] < 0.0) == (Eb[j] < 0.0):
            continue
        count = add_bracket(Bx, Bs, count, xa, Ea[i], xb, Eb[j], Sb[j], JUMP)
    return count


@njit(cache=True, no_cfunc_wrapper=True)
def copy_sample(E, S, M, k, Es, Ss, Ms, u):
    """Sample k of (E, S, M) into row u of (Es, Ss, Ms)."""
    Ms[u] = M[k]
    for i in range(M[k]):
        Es[u, i] = E[k, i]
        for c in range(STATE):
            Ss[u, i, c] = S[k, i, c]


@njit(cache=True, no_cfunc_wrapper=True)
def add_bracket(Bx, Bs, count, a, fa, b, fb, st, jump):
    if count < Bx.shape[0]:
        Bx[count, 0], Bx[count, 1], Bx[count, 2], Bx[count, 3] = a, fa, b, fb
        Bx[count, 4] = jump
        for c in range(STATE):
            Bs[count, c] = st[c]
        count += 1
    return count


@njit(cache=True, no_cfunc_wrapper=True)
def fold_brackets(x, e, s, m, xf, Ef, Sf, mf, Bx, Bs, count):
    """Where branches are born or die between two samples, two of them meet at a fold and
    a zero near it is bracketed by neither sample: each of the ``mf`` branches of the
    sample at ``xf`` (``Ef``, ``Sf``) against the branch nearest its state at ``x``, just on
    the side of the fold that has them (``e``, ``s``, ``m`` branches); each change of sign
    a bracket (added to ``Bx``, ``Bs`` as ``brackets`` does, its branch followed however
    fast it moves: near a fold a state moves as the square root of the distance). Returns
    the count."""
    for j in range(mf):
        i, _ = nearest(s, m, Sf[j])
        if i >= 0 and (e[i] < 0.0) != (Ef[j] < 0.0):
            count = add_bracket(Bx, Bs, count, x, e[i], xf, Ef[j], Sf[j], math.pi)
    return count


@njit(cache=True, no_cfunc_wrapper=True)
def dips(E, S, M, D, wrap):
    """Where a branch comes close to zero between samples without changing sign at them:
    a sample k whose |error| is below its neighbours' on its branch and whose parabola
    through the three dips to zero or past it, or is below half theirs (two zeros closer
    than a grid step, or a tangency); next to a fold (one neighbour missing), below half
    the other's; a local minimum of |error| whose parabola stays on its side gets side 2
    (the search looks between the samples first). Rows (k, branch, side) into ``D``
    (``CANDIDATES``, 3; side: -1 search from sample k - 1 to k, 1 from k to k + 1, 0 from
    k - 1 to k + 1); returns the count.
    ``wrap``: the samples go round a turn (the grid); else only the inner samples of a
    row of them are tested (a grid interval sampled finer)."""
    count = 0
    n = M.shape[0]
    for k in range(0 if wrap else 1, n if wrap else n - 1):
        kp, kn = (k - 1) % n, (k + 1) % n
        for i in range(M[k]):
            jp, dp = nearest(S[kp], M[kp], S[k, i])
            jn, dn = nearest(S[kn], M[kn], S[k, i])
            has_p, has_n = jp >= 0 and dp <= JUMP, jn >= 0 and dn <= JUMP
            e0 = E[k, i]
            ep = E[kp, jp] if has_p else math.nan
            en = E[kn, jn] if has_n else math.nan
            if (has_p and (ep < 0.0) != (e0 < 0.0)) or (has_n and (en < 0.0) != (e0 < 0.0)):
                continue  # a change of sign: bracketed already
            side = 0
            if has_p and has_n:
                if not abs(e0) < abs(ep) or not abs(e0) < abs(en):
                    continue
                curve = 0.5 * (ep + en) - e0
                slope = 0.5 * (en - ep)
                low = e0 - slope * slope / (4.0 * curve) if curve != 0.0 else e0
                deep = abs(e0) < 0.5 * min(abs(ep), abs(en))  # sharper than a parabola
                if (low < 0.0) == (e0 < 0.0) and not deep:
                    side = 2  # a dip may still be sharper than the parabola: look between
            elif has_n and abs(e0) < 0.5 * abs(en):
                side = 1
            elif has_p and abs(e0) < 0.5 * abs(ep):
                side = -1
            else:
                continue
            if count < D.shape[0]:
                D[count, 0], D[count, 1], D[count, 2] = k, i, side
                count += 1
    return count


@njit(cache=True, no_cfunc_wrapper=True)
def angle(k):
    """The grid's k-th angle (rad)."""
    return -math.pi + 2.0 * math.pi * k / GRID


@njit(cache=True, no_cfunc_wrapper=True)
def falsi(a, fa, b, fb):
    """The next trial angle of regula falsi in the bracket (a, b) (bisection when the
    secant leaves it)."""
    x = b - fb * (b - a) / (fb - fa)
    if not min(a, b) < x < max(a, b):
        x = 0.5 * (a + b)
    return x


@njit(cache=True, no_cfunc_wrapper=True)
def update(a, fa, b, fb, x, e, s, m, st, jump):
    """One Illinois step: the branch at ``x`` (``e``, ``s``: its ``m`` branches) nearest
    the followed state ``st`` (the state at b, updated in place) replaces an end of the
    bracket, if it moved by at most ``jump`` (rad). Returns (a, fa, b, fb, status): status
    0 go on, 1 converged (x is the zero, to 1e-11 rad: ``polish`` does the rest), -1 the
    branch ended inside the bracket (no zero on it)."""
    jj, dd = nearest(s, m, st)
    if jj < 0 or dd > jump:
        return a, fa, b, fb, -1
    fx = e[jj]
    for c in range(STATE):
        st[c] = s[jj, c]
    if abs(fx) < 1e-15 or abs(x - b) < 1e-11:
        return a, fa, b, fb, 1
    if (fx < 0.0) != (fb < 0.0):
        a, fa = b, fb
    else:
        fa *= 0.5
    return a, fa, x, fx, 0


@njit(cache=True, no_cfunc_wrapper=True)
def _pose_error(h, p, R_tip0, R, pos, q, J, r):
    """The error (position, then rotation as a vector) of configuration ``q`` against the
    target into ``r`` (6) and the chain's Jacobian (world frame, at the tip) into ``J``
    (6, 6); returns the error's largest entry."""
    Rc = rot(vec(h[0]), 0.0)
    o = vec(p[0])
    axes = np.empty((6, 3))
    pts = np.empty((6, 3))
    for i in range(6):
        w = mv(Rc, vec(h[i]))
        for c in range(3):
            axes[i, c], pts[i, c] = w[c], o[c]
        Rc = mm(Rc, rot(vec(h[i]), q[i]))
        o = add(o, mv(Rc, vec(p[i + 1])))
    Rc = mm(Rc, mat(R_tip0))
    dp = sub(pos, o)
    E = mmt(R, Rc)  # the rotation still to turn, world frame
    dw = (0.5 * (E[7] - E[5]), 0.5 * (E[2] - E[6]), 0.5 * (E[3] - E[1]))
    big = 0.0
    for c in range(3):
        r[c], r[3 + c] = dp[c], dw[c]
        big = max(big, abs(dp[c]), abs(dw[c]))
    for i in range(6):
        w = vec(axes[i])
        v = cross(w, sub(o, vec(pts[i])))
        for c in range(3):
            J[c, i], J[3 + c, i] = v[c], w[c]
    return big


@njit(cache=True, no_cfunc_wrapper=True)
def solve6(A, b, tiny):
    """b = A^-1 b for the 6 x 6 ``A`` by Gaussian elimination with partial pivoting, in place
    (A is overwritten); False, b left half done, when a pivot is below ``tiny``."""
    for col in range(6):
        piv, big = col, abs(A[col, col])
        for r in range(col + 1, 6):
            if abs(A[r, col]) > big:
                piv, big = r, abs(A[r, col])
        if big < tiny:
            return False
        if piv != col:
            for c in range(6):
                A[col, c], A[piv, c] = A[piv, c], A[col, c]
            b[col], b[piv] = b[piv], b[col]
        for r in range(col + 1, 6):
            f = A[r, col] / A[col, col]
            for c in range(col, 6):
                A[r, c] -= f * A[col, c]
            b[r] -= f * b[col]
    for r in range(5, -1, -1):
        acc = b[r]
        for c in range(r + 1, 6):
            acc -= A[r, c] * b[c]
        b[r] = acc / A[r, r]
    return True


@njit(cache=True, no_cfunc_wrapper=True)
def polish(h, p, R_tip0, R, pos, q):
    """Newton steps on the whole pose from ``q`` (6, changed in place): returns the final
    error's largest entry (m or rad; see ``_pose_error``)."""
    J = np.empty((6, 6))
    r = np.empty(6)
    err = _pose_error(h, p, R_tip0, R, pos, q, J, r)
    for _ in range(6):
        if err <= POLISH_TOL:
            break
        if not solve6(J, r, 1e-14):
            break
        for i in range(6):
            q[i] += r[i]
        err = _pose_error(h, p, R_tip0, R, pos, q, J, r)
    return err


@njit(cache=True, no_cfunc_wrapper=True)
def is_new(W, n, q):
    """Whether ``q`` differs (modulo 2 pi, by more than 1e-6 rad) from every one of the
    first ``n`` rows of ``W``."""
    for r in range(n):
        same = True
        for j in range(6):
            if abs(_wrapped(W[r, j] - q[j])) > 1e-6:
                same = False
                break
        if same:
            return False
    return True


@njit(cache=True, no_cfunc_wrapper=True)
def put(W, n, q, flags, code):
    """Row ``n`` of ``W`` (``sixr``'s layout, 16 rows) from ``q``, wrapped; returns n + 1."""
    for j in range(6):
        W[n, j] = _wrapped(q[j])
    W[n, 6] = flags
    W[n, 8] = code
    W[n, 9] = 0.0
    W[n, 10] = 0.0
    return n + 1


# -- the subproblems as a search calls them ---------------------------------------------------


@njit(cache=True, no_cfunc_wrapper=True)
def sp5_roots(p0, p1, p2, p3, k1, k2, k3, out):
    """SP5's exact solutions as its quartic gives them, unrefined, no least-squares answer:
    (t1, t2, t3) rows into ``out`` (8, 3); returns the count (-1: a continuum, none
    written). For a search that calls SP5 many times and polishes what it finds on a larger
    problem (``search_1d``); ``sp5`` refines each root and is the subproblem itself."""
    q0, q1, q2, q3 = vec(p0), vec(p1), vec(p2), vec(p3)
    e1, e2, e3 = vec(k1), vec(k2), vec(k3)
    size = max(norm(q0), norm(q1), norm(q2), norm(q3))
    if size == 0.0:
        return -1
    M, f = _system5(q0, q1, q2, q3, e1, e2, e3, size)
    pairs = np.zeros((8, 2))
    m, free = _pairs(M, f, size, pairs)
    if free:
        return -1
    c1, a1, b1 = _circle(q0, e1, q1)
    c3, a3, b3 = _circle(q2, e3, q3)
    n = 0
    for i in range(m):
        v1, v3 = _on(c1, a1, b1, pairs[i, 0]), _on(c3, a3, b3, pairs[i, 1])
        t2, _ = sp1(v3, v1, e2)
        if norm(sub(v1, mv(rot(e2, t2), v3))) <= ROOT_GATE * size:
            out[n, 0], out[n, 1], out[n, 2] = pairs[i, 0], t2, pairs[i, 1]
            n += 1
    return n


@njit(cache=True, no_cfunc_wrapper=True)
def sp6_roots(h, k, p, d1, d2, out):
    """SP6's exact solutions as its quartic gives them, unrefined, no least-squares answer:
    (t1, t2) rows into ``out`` (8, 2); returns the count (-1: a continuum). For a search
    that calls SP6 many times and polishes what it finds on a larger problem
    (``search_1d``); ``sp6`` refines each root and is the subproblem itself."""
    M, f, size = _system6(h, k, p, d1, d2)
    if size == 0.0:
        return -1
    m, free = _pairs(M, f, size, out)
    return -1 if free else m
