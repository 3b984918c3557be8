"""The zeros of a one-dimensional search and the solutions built from them, for both
families that search (``search_1d``'s machinery): ``OVER_Q1`` (``two_parallel``, the
branches in ``search_q1``) and ``OVER_Q4`` (``two_intersecting``, ``search_q4``).

The family is a code read from the flat chain (``sixr.flat``'s variant), not a compiled
function passed in: numba does not cache a function that receives another, and one zero
finder for both families is compiled once.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.single import plain_pose, plain_seed
from armik.solvers.closed_form import search_q1, search_q4, sixr
from armik.solvers.closed_form.search_1d import (
    BRANCHES,
    CANDIDATES,
    DEPTH,
    DIP_STEPS,
    FOLD_STEPS,
    GOLDEN,
    GRID,
    ITERATIONS,
    JUMP,
    STATE,
    SUB,
    ZEROS,
    add_bracket,
    angle,
    copy_sample,
    dips,
    falsi,
    fold_brackets,
    is_new,
    nearest,
    pair_brackets,
    polish,
    put,
    rough,
    update,
)
from armik.solvers.closed_form.sixr import LS, NOT_FOUND
from armik.solvers.closed_form.sixr_judged import GENERAL, UNLABELLED, judged, split
from armik.solvers.closed_form.subproblems import mat, mmt, mv, norm, sub, vec

OVER_Q1, OVER_Q4 = 0, 1  # the family codes, as ``sixr.flat`` writes them
FOLD_ZERO = 0.02  # of the arm's length: a branch this near zero at a fold is polished
PROBE = 0.01  # of the arm's length: a branch this near zero at two samples is probed between
REACHED = 1e-10  # m and rad: a polished zero reaches the target (Pinocchio verifies it)
# dips' wrap, typed: a literal True and False would compile it twice
WRAP, INNER = np.bool_(True), np.bool_(False)


@njit(cache=True, no_cfunc_wrapper=True)
def _branches(family, x, h, p, R06, p16, e, s):
    """The family's branches at the trial angle ``x`` (``search_1d``)."""
    if family == OVER_Q1:
        return search_q1.branches(x, h, p, R06, p16, e, s)
    return search_q4.branches(x, h, p, R06, p16, e, s)


@njit(cache=True, no_cfunc_wrapper=True)
def _configuration(family, h, p, R06, p16, x, state, q):
    """The configuration of the zero at ``x`` on the branch ``state``, into ``q``."""
    if family == OVER_Q1:
        search_q1.configuration(h, p, R06, p16, x, state, q)
    else:
        search_q4.configuration(h, p, R06, p16, x, state, q)


@njit(cache=True, no_cfunc_wrapper=True)
def _zeros(family, h, p, R06, p16, X, XS):
    """Every bracketed zero of the error over one turn (``search_1d``), at folds and dips
    too: the angles into ``X``, each branch's state there into ``XS`` (``CANDIDATES``
    rows); returns the count."""
    E = np.empty((GRID, BRANCHES))
    S = np.zeros((GRID, BRANCHES, STATE))
    M = np.empty(GRID, np.int64)
    for k in range(GRID):
        M[k] = _branches(family, angle(k), h, p, R06, p16, E[k], S[k])
    Bx, Bs = np.empty((CANDIDATES, 5)), np.empty((CANDIDATES, STATE))
    e, s, st = np.empty(BRANCHES), np.zeros((BRANCHES, STATE)), np.empty(STATE)
    step = 2.0 * np.pi / GRID
    small = 0.0  # m: PROBE of the arm's length, the links' offsets added
    for r in range(1, 6):
        small += PROBE * norm(vec(p[r]))
    nb = np.int64(0)  # not a literal 0: the callees would compile for it too
    for k in range(GRID):
        k2, xa = (k + 1) % GRID, angle(k)
        if not rough(E[k], S[k], M[k], E[k2], S[k2], M[k2]):
            nb = pair_brackets(xa, E[k], S[k], M[k], xa + step, E[k2], S[k2], M[k2], Bx, Bs, nb)
            nb = _probe(family, xa, step, E, S, M, k, small, h, p, R06, p16, Bx, Bs, nb, e, s, st)
            continue
        nb = _sampled_finer(family, xa, step, E, S, M, k, k2, h, p, R06, p16, Bx, Bs, nb)
    D = np.empty((2 * CANDIDATES, 3), np.int64)  # side-2 rows too (see ``dips``)
    count = np.int64(0)
    for z in range(dips(E, S, M, D, WRAP)):  # the branch's extremum between its neighbours
        k, i = D[z, 0], D[z, 1]
        nb, count = _dip(
            family, angle(k), step, D[z, 2], E[k, i], S[k, i], h, p, R06, p16, Bx, Bs, nb,
            X, XS, count,
        )  # fmt: skip
    for z in range(nb):
        a, fa, b, fb, jump = Bx[z, 0], Bx[z, 1], Bx[z, 2], Bx[z, 3], Bx[z, 4]
        for c in range(STATE):
            st[c] = Bs[z, c]
        if jump < 0.0:  # a point next to a fold (``_refine``): polish takes it or not
            if count < X.shape[0]:
                X[count] = a
                for c in range(STATE):
                    XS[count, c] = st[c]
                count += 1
            continue
        x, status = b, 0
        for _ in range(ITERATIONS):
            x = falsi(a, fa, b, fb)
            m = _branches(family, x, h, p, R06, p16, e, s)
            a, fa, b, fb, status = update(a, fa, b, fb, x, e, s, m, st, jump)
            if status != 0:
                break
        if status == 1 and count < X.shape[0]:
            X[count] = x
            for c in range(STATE):
                XS[count, c] = st[c]
            count += 1
    if family == OVER_Q1:  # after the zeros: these may only fill what room is left
        count = _split_candidates(h, E, S, M, X, XS, count)
    return count


@njit(cache=True, no_cfunc_wrapper=True)
def _split_candidates(h, E, S, M, X, XS, count):
    """``search_q1``'s candidates where the rotation does not split q2 + s3 q3 from q5:
    at each grid sample where the branches come nearest that pose (a local minimum of
    ``search_q1.coupling`` below ``DEGENERATE``), the two configurations whose split the
    position fixes, for polish to take or not."""
    C = np.full((GRID, 2), np.inf)  # per sample and pose (h5 along h2, against)
    best = np.zeros((GRID, 2), np.int64)
    for k in range(GRID):
        for i in range(M[k]):
            c, side = search_q1.coupling(h, S[k, i])
            if c < C[k, side]:
                C[k, side], best[k, side] = c, i
    for k in range(GRID):
        for side in range(2):
            c = C[k, side]
            low = c <= C[(k - 1) % GRID, side] and c <= C[(k + 1) % GRID, side]
            if c >= search_q1.DEGENERATE or not low:
                continue
            for solution in (1.0, 2.0):
                if count < X.shape[0]:
                    X[count] = angle(k)
                    XS[count, 0] = S[k, best[k, side], 0]
                    XS[count, 1] = S[k, best[k, side], 1]
                    XS[count, 2] = solution
                    count += 1
    return count


@njit(cache=True, no_cfunc_wrapper=True)
def _sampled_finer(family, xa, step, E, S, M, k, k2, h, p, R06, p16, Bx, Bs, nb):
    """The brackets of the rough grid interval from sample k to k2 (at xa, xa + step):
    sampled ``SUB`` times finer, each piece refined (``_refine``), and the dips among the
    finer samples searched (``_dip``): next to a fold a branch may dip through zero and back
    within a grid step, where the grid's own dip test does not look."""
    Es, Ss = np.empty((SUB + 1, BRANCHES)), np.zeros((SUB + 1, BRANCHES, STATE))
    Ms = np.empty(SUB + 1, np.int64)
    copy_sample(E, S, M, k, Es, Ss, Ms, np.int64(0))
    copy_sample(E, S, M, k2, Es, Ss, Ms, np.int64(SUB))
    sub = step / SUB
    for u in range(1, SUB):
        Ms[u] = _branches(family, xa + sub * u, h, p, R06, p16, Es[u], Ss[u])
    for u in range(SUB):
        nb = _refine(
            family, xa + sub * u, Es[u], Ss[u], Ms[u], xa + sub * (u + 1), Es[u + 1],
            Ss[u + 1], Ms[u + 1], h, p, R06, p16, Bx, Bs, nb,
        )  # fmt: skip
    D = np.empty((2 * CANDIDATES, 3), np.int64)  # side-2 rows too (see ``dips``)
    X, XS = np.empty(1), np.zeros((1, STATE))  # a tangency here is left to the polish of
    count = np.int64(1)  # its neighbours' brackets: none is kept from this call
    for z in range(dips(Es, Ss, Ms, D, INNER)):
        u, i = D[z, 0], D[z, 1]
        nb, _ = _dip(
            family, xa + sub * u, sub, D[z, 2], Es[u, i], Ss[u, i], h, p, R06, p16, Bx, Bs,
            nb, X, XS, count,
        )  # fmt: skip
    return nb


@njit(cache=True, no_cfunc_wrapper=True)
def _probe(family, xa, step, E, S, M, k, small, h, p, R06, p16, Bx, Bs, nb, e, s, st):
    """Between grid samples k and k + 1 (at xa, xa + step), where a branch keeps its sign,
    stays within ``small`` of zero at both and is nearer zero there than at the samples
    either side (a minimum of |error| two samples wide), the branch at the midpoint: a dip
    through zero and back narrower than a grid step, which the three-sample parabola
    (``dips``) cannot see, shows there as a change of sign, one bracket each side.
    ``e``, ``s``, ``st``: scratch (called for every smooth grid interval)."""
    k2, kp, kn = (k + 1) % GRID, (k - 1) % GRID, (k + 2) % GRID
    for i in range(M[k]):
        ea = E[k, i]
        if abs(ea) > small:
            continue
        j, d = nearest(S[k2], M[k2], S[k, i])
        if j < 0 or d > JUMP or (ea < 0.0) != (E[k2, j] < 0.0) or abs(E[k2, j]) > small:
            continue
        jp, dp = nearest(S[kp], M[kp], S[k, i])
        if jp >= 0 and dp <= JUMP and abs(E[kp, jp]) <= abs(ea):
            continue  # still falling towards k: not a minimum here
        jn, dn = nearest(S[kn], M[kn], S[k2, j])
        if jn >= 0 and dn <= JUMP and abs(E[kn, jn]) <= abs(E[k2, j]):
            continue  # still falling past k + 1
        for c in range(STATE):
            st[c] = S[k, i, c]
        xm = xa + 0.5 * step
        fm = _follow(family, xm, h, p, R06, p16, e, s, st)
        if fm == fm and (fm < 0.0) != (ea < 0.0):
            nb = _bracket(family, xa, xm, fm, st, h, p, R06, p16, e, s, Bx, Bs, nb)
            nb = _bracket(family, xa + step, xm, fm, st, h, p, R06, p16, e, s, Bx, Bs, nb)
    return nb


@njit(cache=True, no_cfunc_wrapper=True)
def _dip(family, xk, step, side, ek, sk, h, p, R06, p16, Bx, Bs, nb, X, XS, count):
    """A dip at the sample ``xk`` (its branch's error ``ek``, state ``sk``; ``side`` as
    ``dips`` writes it, ``step`` to the neighbours): the extremum between the neighbours by
    golden section on the branch; two brackets if it passes zero, the extremum itself
    (into X, XS) if it touches it. Side 2 first looks at the two midpoints: only a change
    of sign there, or their parabola through zero, leads to the search. Returns (nb,
    count)."""
    e, s, st = np.empty(BRANCHES), np.zeros((BRANCHES, STATE)), np.empty(STATE)
    sign = 1.0 if ek > 0.0 else -1.0
    if side == 2:  # a local minimum the samples' parabola keeps on its side: the midpoints
        for c in range(STATE):
            st[c] = sk[c]
        fl = sign * _follow(family, xk - 0.5 * step, h, p, R06, p16, e, s, st)
        for c in range(STATE):
            st[c] = sk[c]
        fr = sign * _follow(family, xk + 0.5 * step, h, p, R06, p16, e, s, st)
        if not (fl == fl and fr == fr):
            return nb, count
        if fl > 0.0 and fr > 0.0:  # no change of sign there: the finer parabola decides
            curve = 0.5 * (fl + fr) - sign * ek
            slope = 0.5 * (fr - fl)
            if curve <= 0.0 or sign * ek - slope * slope / (4.0 * curve) > 0.0:
                return nb, count
        side = 0
    for c in range(STATE):
        st[c] = sk[c]
    a = xk - (step if side <= 0 else 0.0)
    b = xk + (step if side >= 0 else 0.0)
    lo, hi = a, b
    x1, x2 = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
    f1 = sign * _follow(family, x1, h, p, R06, p16, e, s, st)
    f2 = sign * _follow(family, x2, h, p, R06, p16, e, s, st)
    for _ in range(DIP_STEPS):  # golden section on sign * error, one trial a step
        if f1 < f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - GOLDEN * (hi - lo)
            f1 = sign * _follow(family, x1, h, p, R06, p16, e, s, st)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + GOLDEN * (hi - lo)
            f2 = sign * _follow(family, x2, h, p, R06, p16, e, s, st)
        if f1 < 0.0 or f2 < 0.0:
            break  # past zero: the dip holds two zeros
    xm = x1 if f1 < f2 else x2
    fm = _follow(family, xm, h, p, R06, p16, e, s, st)
    if (fm < 0.0) != (sign < 0.0):  # two zeros, one each side of the extremum
        nb = _bracket(family, a, xm, fm, st, h, p, R06, p16, e, s, Bx, Bs, nb)
        nb = _bracket(family, b, xm, fm, st, h, p, R06, p16, e, s, Bx, Bs, nb)
    elif abs(fm) < 1e-12 and count < X.shape[0]:  # a tangency: the extremum is the zero
        X[count] = xm
        for c in range(STATE):
            XS[count, c] = st[c]
        count += 1
    return nb, count


@njit(cache=True, no_cfunc_wrapper=True)
def _refine(family, xa, Ea, Sa, ma, xb, Eb, Sb, mb, h, p, R06, p16, Bx, Bs, nb):
    """The brackets of a rough grid interval (xa, xb) (``search_1d.rough``): halved where
    the branches still change too much, at most ``DEPTH`` times, and each piece bracketed
    from its ends; where a piece's ends count different branches, the fold between them is
    located by bisection and bracketed from its side. A fold where two branches die and two
    others are born between two samples leaves the counts equal, so halving on roughness,
    not only on counts, is what finds the zeros next to such folds."""
    # pieces left to right: the left end in (xl, El, Sl, ml), the right ends still to
    # reach on a stack (X, Es, Ss, Ms), each with the number of halvings that made it
    n = DEPTH + 2
    X, Es, Ss = np.empty(n), np.empty((n, BRANCHES)), np.zeros((n, BRANCHES, STATE))
    Ms, Ds = np.empty(n, np.int64), np.empty(n, np.int64)
    El, Sl, ml, xl = Ea.copy(), Sa.copy(), ma, xa
    e, s = np.empty(BRANCHES), np.zeros((BRANCHES, STATE))
    top = 0
    X[0], Ms[0], Ds[0] = xb, mb, 0
    for i in range(mb):
        Es[0, i] = Eb[i]
        for c in range(STATE):
            Ss[0, i, c] = Sb[i, c]
    while top >= 0:
        xr, mr = X[top], Ms[top]
        if Ds[top] < DEPTH and rough(El, Sl, ml, Es[top], Ss[top], mr):
            Ds[top] += 1  # the right half keeps this end; the left half's end is pushed
            mid = 0.5 * (xl + xr)
            Ms[top + 1] = _branches(family, mid, h, p, R06, p16, Es[top + 1], Ss[top + 1])
            X[top + 1], Ds[top + 1] = mid, Ds[top]
            top += 1
            continue
        nb = pair_brackets(xl, El, Sl, ml, xr, Es[top], Ss[top], mr, Bx, Bs, nb)
        if ml != mr:
            x0, x1 = xl, xr  # a fold: ml branches at x0, mr at x1
            for _ in range(FOLD_STEPS):
                mid = 0.5 * (x0 + x1)
                if _branches(family, mid, h, p, R06, p16, e, s) == mr:
                    x1 = mid
                else:
                    x0 = mid
            near = x1 if mr > ml else x0
            m = _branches(family, near, h, p, R06, p16, e, s)
            if mr > ml:
                nb = fold_brackets(near, e, s, m, xr, Es[top], Ss[top], mr, Bx, Bs, nb)
            else:
                nb = fold_brackets(near, e, s, m, xl, El, Sl, ml, Bx, Bs, nb)
            # a zero closer to the fold than the bisection (the error grows as the root of
            # the distance from a fold, so a zero a few mrad of q4 away can be 1e-5 rad of
            # q1 from it): the fold's point is near enough for polish to take it there
            near_zero = 0.0
            for r in range(1, 6):
                near_zero += FOLD_ZERO * norm(vec(p[r]))
            for i in range(m):
                if abs(e[i]) < near_zero:
                    nb = add_bracket(Bx, Bs, nb, near, e[i], near, e[i], s[i], -1.0)
        xl, ml = xr, mr  # on to the next piece
        for i in range(mr):
            El[i] = Es[top, i]
            for c in range(STATE):
                Sl[i, c] = Ss[top, i, c]
        top -= 1
    return nb


@njit(cache=True, no_cfunc_wrapper=True)
def _follow(family, x, h, p, R06, p16, e, s, st):
    """The error at ``x`` of the branch nearest the state ``st`` (updated); nan if none."""
    m = _branches(family, x, h, p, R06, p16, e, s)
    j, _ = nearest(s, m, st)
    if j < 0:
        return np.nan
    for c in range(STATE):
        st[c] = s[j, c]
    return e[j]


@njit(cache=True, no_cfunc_wrapper=True)
def _bracket(family, xa, xm, fm, st, h, p, R06, p16, e, s, Bx, Bs, nb):
    """The bracket (xa, xm) of a dip's branch (its state ``st`` at xm), if it changes sign."""
    keep = st.copy()
    fa = _follow(family, xa, h, p, R06, p16, e, s, keep)
    if fa == fa and (fa < 0.0) != (fm < 0.0):
        nb = add_bracket(Bx, Bs, nb, xa, fa, xm, fm, st, JUMP)
    return nb


@njit(cache=True, no_cfunc_wrapper=True)
def kernel(h, p, R_tip0, R, pos, q0, lower, upper, family, labelled, out):
    """Every solution the search finds for the target rotation ``R`` (9-tuple, row-major)
    and position ``pos`` (3-tuple), each polished on the whole pose, packed nearest-first
    into ``out`` (16, 11), the first ``labelled`` with their branch; returns (n, first
    reached) (see ``sixr.pack``). None found: one row, q0, flagged least squares."""
    W = np.empty((ZEROS, 11))
    R06 = mmt(R, mat(R_tip0))
    p16 = sub(sub(pos, mv(R06, vec(p[6]))), vec(p[0]))
    X, XS = np.empty(CANDIDATES), np.zeros((CANDIDATES, STATE))
    nz = _zeros(family, h, p, R06, p16, X, XS)
    n = np.int64(0)
    q = np.empty(6)
    for z in range(nz):
        _configuration(family, h, p, R06, p16, X[z], XS[z], q)
        if n < ZEROS and polish(h, p, R_tip0, R, pos, q) <= REACHED and is_new(W, n, q):
            n = put(W, n, q, 0.0, 0.0)
    if n == 0:
        n = put(W, n, q0, float(LS), float(NOT_FOUND))
    sixr.nearest_equivalents(W, n, q0, lower, upper)
    return n, sixr.pack(W, n, q0, lower, upper, h, p, labelled, out)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_into(chain, H, q0, every, out):
    """``kernel`` for one 4x4 pose ``H``, its rows packed into ``out`` (16, 11); returns
    ``sixr.hand_over``'s (n, head), or n = -1 and nothing solved when ``H`` or ``q0`` is
    not plain (``kernel.single``). ``chain``: ``sixr.flat``."""
    h, p, R_tip0, lower, upper, family = sixr.unflatten(chain)
    if not plain_pose(H) or not plain_seed(q0, lower, upper):
        return -1, 0
    labelled = ZEROS if every else 1
    n, reached = kernel(
        h, p, R_tip0, mat(H), sixr.column(H), q0, lower, upper, family, labelled, out
    )
    return sixr.hand_over(n, reached, labelled, h, p, out)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_all_into(ctx, H, q0, rows):
    """``kernel``'s every row for ``H`` in ``rows`` (16, ``sixr_judged.WIDTH``), unlabelled,
    measured and judged in the same call: ``sixr_judged.judged``'s (n, verdict), n = -1 and
    nothing solved when ``H`` or ``q0`` is not plain. ``ctx``: ``sixr_judged.context``."""
    chain, judge, frame, packed, kind, halton = split(ctx)
    h, p, R_tip0, lower, upper, family = sixr.unflatten(chain)
    if not plain_pose(H) or not plain_seed(q0, lower, upper):
        return -1, GENERAL
    n, _ = kernel(h, p, R_tip0, mat(H), sixr.column(H), q0, lower, upper, family, UNLABELLED, rows)
    return judged(n, chain, packed, kind, halton, frame, judge, H, rows)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def kernel_many(chain, Rs, ps, q0s):
    """``kernel`` for N targets: the row nearest q0 of each, and its claim code."""
    h, p, R_tip0, lower, upper, family = sixr.unflatten(chain)
    N = ps.shape[0]
    Q = np.empty((N, 6))
    claim = np.empty(N, np.int8)
    out = np.empty((ZEROS, 11))  # one for every target
    unlabelled = np.int64(0)  # no branch labels (not a literal 0: one compile of kernel)
    for i in range(N):
        kernel(h, p, R_tip0, mat(Rs[i]), vec(ps[i]), q0s[i], lower, upper, family, unlabelled, out)
        for j in range(6):  # a loop: a slice copy compiles numba's shape-error path
            Q[i, j] = out[0, j]
        # finding nothing is no proof of unreachability: not converged, never unreachable
        claim[i] = sixr.NOT_CONVERGED_CODE if int(out[0, 6]) & LS else sixr.CONVERGED_CODE
    return Q, claim
