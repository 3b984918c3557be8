"""The compiled SRS closed form (``armik.solvers.closed_form.srs``): every branch of a 7R
arm with a spherical shoulder and a spherical wrist at one elbow swivel angle.

The arm in product-of-exponentials form at q = 0 (base frame): unit axes h1..h7, the
shoulder S where axes 1, 2, 3 meet, the wrist W0 where axes 5, 6, 7 meet, E0 the point of
axis 4 nearest S (the elbow), the wrist in the tip frame ``w_tip``. For the target (R, p):

    W = p + R w_tip,  D = |W - S|
    |E0 - S + rot(h4, q4) (W0 - E0)| = D                        -> SP3: q4 (2 roots)
    R_s (W4 - S) = W - S,  R_s (E0 - S) = E - S                  -> the shoulder's rotation
    rot(h1, q1) rot(h2, q2) rot(h3, q3) = R_s                     -> SP2, SP1: 2 roots
    rot(h5, q5) rot(h6, q6) rot(h7, q7) = (R_s rot(h4, q4))^T R R_tip0^T  -> SP2, SP1: 2

W4 = E0 + rot(h4, q4) (W0 - E0) is the wrist with the elbow bent and the shoulder at zero.
The elbow E lies on the circle about the line S-W that the swivel angle psi runs round:
E - S = ((E0 - S) . a) n + rho (cos psi u1 + sin psi u2), with n = (W - S) / D, a the unit
W4 - S, rho the elbow's distance from the line, u1 the reference direction (axis 1, h1)
with its part along n taken out, u2 = n x u1. psi = 0 puts the elbow on the side axis 1
points to (up, on an iiwa standing on its base): ``swivel_of`` reads it from any
configuration. Up to 2 x 2 x 2 = 8 rows a swivel angle; the free angle of a singular
shoulder or wrist (axes 1 and 3, or 5 and 7, in line) is kept at q0 and the row flagged
singular, as is a stretched or folded elbow (the swivel then does not move the elbow: the
shoulder's roll about the line S-W is the one nearest q0's shoulder, ``_roll_of``).

The geometry is one flat array (``GEO`` long): h (21), S, W0, E0, w_tip (3 each), R_tip0
(9), lower, upper (7 each), the reference direction (3). Rows (``COLUMNS`` wide): q (7),
flags (``sixr.LS``, ``sixr.SINGULAR``), branch bits, reason code and its 2 values.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.solvers.closed_form import sixr
from armik.solvers.closed_form.sixr import (
    LS,
    ORIENTATION,
    SINGULAR,
    WRIST_ORIENTATION,
)
from armik.solvers.closed_form.subproblems import (
    add,
    cross,
    dot,
    elbow,
    mat,
    mm,
    mmt,
    mtm,
    mv,
    neg,
    norm,
    rot,
    scale,
    sp1,
    sp2,
    sub,
    vec,
    wrap,
)
from armik.tolerances import LIMIT_TOL

GEO = 59
COLUMNS = 12
ROWS = 8
SWEEP = 64  # swivel angles tried after q0's, spread over the circle
TINY = 1e-9  # m: an elbow this near the line S-W leaves the swivel no effect
BEND = 1e-6  # rad: joint 4 turned this far off a stretched elbow puts it ~1e-7 m off S-W
TWO_PI = 2.0 * math.pi


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def parts(geo):
    """(h (7, 3), S, W0, E0, w_tip, R_tip0 (3, 3), lower, upper, ref) views of ``geo``."""
    return (
        geo[0:21].reshape((7, 3)),
        geo[21:24],
        geo[24:27],
        geo[27:30],
        geo[30:33],
        geo[33:42].reshape((3, 3)),
        geo[42:49],
        geo[49:56],
        geo[56:59],
    )


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _basis(ref, h2, n):
    """(u1, u2): the reference direction with its part along ``n`` taken out, and n x u1
    (axis 2 at q = 0 stands in where the line S-W runs along the reference)."""
    u1 = sub(ref, scale(n, dot(ref, n)))
    if norm(u1) < TINY:
        u1 = sub(h2, scale(n, dot(h2, n)))
    u1 = scale(u1, 1.0 / norm(u1))
    return u1, cross(n, u1)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def elbow_wrist(geo, q):
    """The elbow E and the wrist W (3-tuples, base frame, m) of configuration ``q``: the
    arm's own forward kinematics of those two points (``swivel_of`` reads them; the tests
    check them against Pinocchio's)."""
    h, S, W0, E0, w_tip, R_tip0, lower, upper, ref = parts(geo)
    s, w, e0 = vec(S), vec(W0), vec(E0)
    Rs = mm(mm(rot(vec(h[0]), q[0]), rot(vec(h[1]), q[1])), rot(vec(h[2]), q[2]))
    W4 = add(e0, mv(rot(vec(h[3]), q[3]), sub(w, e0)))
    return add(s, mv(Rs, sub(e0, s))), add(s, mv(Rs, sub(W4, s)))


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def swivel_of(geo, q):
    """The swivel angle (rad, in (-pi, pi]) of configuration ``q`` (7 joint values):
    where its elbow lies on the circle about the line S-W; 0 where the elbow is on that
    line (stretched or folded: any angle)."""
    h, S, ref = geo[0:21].reshape((7, 3)), vec(geo[21:24]), vec(geo[56:59])
    E, W = elbow_wrist(geo, q)
    b = sub(W, S)
    nb = norm(b)
    if nb < TINY:
        return 0.0
    n = scale(b, 1.0 / nb)
    e = sub(E, S)
    e = sub(e, scale(n, dot(e, n)))
    if norm(e) < TINY:
        return 0.0
    u1, u2 = _basis(ref, vec(h[1]), n)
    return math.atan2(dot(e, u2), dot(e, u1))


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def sides_of(geo, q):
    """(psi, psi): q's swivel angle twice; where q's elbow is stretched or folded (on the
    line S-W: its swivel angle is undefined, ``swivel_of`` says 0), the angles of the
    elbow bent ``BEND`` either way from q: a continuous motion through such an elbow
    leaves it on one of them (the swivel angle turns by about pi as joint 4 passes)."""
    E, W = elbow_wrist(geo, q)
    S = vec(geo[21:24])
    b, e = sub(W, S), sub(E, S)
    nb = norm(b)
    if nb >= TINY and norm(sub(e, scale(b, dot(e, b) / (nb * nb)))) >= TINY:
        psi = swivel_of(geo, q)
        return psi, psi
    bent = q.copy()
    bent[3] = q[3] + BEND
    one = swivel_of(geo, bent)
    bent[3] = q[3] - BEND
    return one, swivel_of(geo, bent)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _distance(W, q0):
    """How far the first row of ``W`` lies from q0 (rad, Euclidean)."""
    d2 = 0.0
    for j in range(7):
        d2 += (W[0, j] - q0[j]) ** 2
    return math.sqrt(d2)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _three(M, ha, hb, hc, free):
    """rot(ha, a) rot(hb, b) rot(hc, c) = M: (a0, a1, b0, b1, c0, c1, n, ls, singular),
    a kept at ``free`` where M hc lies along ha (a and c then turn about one line)."""
    a0, a1, b0, b1, n, ls = sp2(mv(M, hc), hc, neg(ha), hb, free)
    singular = False
    if n == -1:
        n, singular = 1, True
    c0 = sp1(hb, mv(mtm(mm(rot(ha, a0), rot(hb, b0)), M), hb), hc)[0]
    c1 = c0
    if n == 2:
        c1 = sp1(hb, mv(mtm(mm(rot(ha, a1), rot(hb, b1)), M), hb), hc)[0]
    return a0, a1, b0, b1, c0, c1, n, ls, singular


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _bits(h, q):
    """Branch bits: 1 joint 2, 2 joint 4, 4 joint 6 turned the negative way (the sign of
    the sine of its turn, read from the axes, so that a label means one pose)."""
    bits = 0
    for k in range(3):
        hm, ho = vec(h[2 * k + 1]), vec(h[2 * k + 2])
        if dot(hm, cross(ho, mv(rot(hm, q[2 * k + 1]), ho))) < 0.0:
            bits |= 1 << k
    return bits


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _put(W, n, q, flags, code, v0, v1, h):
    for j in range(7):
        W[n, j] = wrap(q[j])
    W[n, 7] = flags
    W[n, 8] = _bits(h, q)
    W[n, 9] = code
    W[n, 10] = v0
    W[n, 11] = v1
    return n + 1


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _roll_of(h1, h2, h3, q0, n, g, ag, f):
    """(f, n x f): where the shoulder takes ``g`` when the elbow lies on the line S-W (a
    stretched or folded elbow: the swivel angle moves nothing, the shoulder's roll about
    the line is free), the roll nearest q0's shoulder rotation Rs0 (f maximises the trace
    of Rs0^T Rs: the part of Rs0 g across n plus (Rs0 (a x g)) x n); ``f`` (the swivel
    angle's) where q0's shoulder leaves no direction."""
    Rs0 = mm(mm(rot(h1, q0[0]), rot(h2, q0[1])), rot(h3, q0[2]))
    r = mv(Rs0, g)
    v = add(sub(r, scale(n, dot(r, n))), cross(mv(Rs0, ag), n))
    nv = norm(v)
    if nv < TINY:
        return f, cross(n, f)
    v = scale(v, 1.0 / nv)
    return v, cross(n, v)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def at_swivel(geo, R, pos, psi, q0, W):
    """Every row (up to 8) at swivel angle ``psi`` for the target rotation ``R`` (9-tuple)
    and position ``pos`` (3-tuple) into ``W`` (8, ``COLUMNS``), unsorted, each angle in
    (-pi, pi]; returns the count."""
    h, S, W0, E0, w_tip, R_tip0, lower, upper, ref = parts(geo)
    h1, h2, h3, h4 = vec(h[0]), vec(h[1]), vec(h[2]), vec(h[3])
    h5, h6, h7 = vec(h[4]), vec(h[5]), vec(h[6])
    s, w0, e0 = vec(S), vec(W0), vec(E0)
    Wt = add(pos, mv(R, vec(w_tip)))
    b = sub(Wt, s)
    D = norm(b)
    n = scale(b, 1.0 / max(D, TINY))
    u1, u2 = _basis(vec(ref), h2, n)
    f = add(scale(u1, math.cos(psi)), scale(u2, math.sin(psi)))
    nf = cross(n, f)
    R_tool = mmt(R, mat(R_tip0))
    t0, t1, n4, ls4 = elbow(sub(w0, e0), sub(s, e0), h4, D)
    flag4, code, v0, v1 = 0, 0, 0.0, 0.0
    if n4 == 1 and not ls4:
        flag4 |= SINGULAR  # stretched or folded
    if ls4:
        flag4 |= LS
        code, v1 = sixr.elbow_code(sub(e0, s), sub(w0, e0), h4, t0, D)
        v0 = D
    q = np.empty(7)
    count = np.int64(0)
    for i4 in range(max(n4, 1)):
        q4 = t0 if i4 == 0 else t1
        R4 = rot(h4, q4)
        a = sub(add(e0, mv(R4, sub(w0, e0))), s)
        a = scale(a, 1.0 / max(norm(a), TINY))
        e = sub(e0, s)
        g = sub(e, scale(a, dot(e, a)))
        rho = norm(g)
        flag = flag4
        on_line = rho < TINY
        if on_line:  # the elbow on the line S-W: any roll of the shoulder about it
            flag |= SINGULAR
            g = cross(a, h2) if norm(cross(a, h2)) > 0.1 else cross(a, h1)
            rho = norm(g)
        g = scale(g, 1.0 / rho)
        ag = cross(a, g)
        fr, nfr = f, nf
        if on_line:
            fr, nfr = _roll_of(h1, h2, h3, q0, n, g, ag, f)
        Rs = (
            n[0] * a[0] + fr[0] * g[0] + nfr[0] * ag[0],
            n[0] * a[1] + fr[0] * g[1] + nfr[0] * ag[1],
            n[0] * a[2] + fr[0] * g[2] + nfr[0] * ag[2],
            n[1] * a[0] + fr[1] * g[0] + nfr[1] * ag[0],
            n[1] * a[1] + fr[1] * g[1] + nfr[1] * ag[1],
            n[1] * a[2] + fr[1] * g[2] + nfr[1] * ag[2],
            n[2] * a[0] + fr[2] * g[0] + nfr[2] * ag[0],
            n[2] * a[1] + fr[2] * g[1] + nfr[2] * ag[1],
            n[2] * a[2] + fr[2] * g[2] + nfr[2] * ag[2],
        )
        x0, x1, y0, y1, z0, z1, ns, lss, sings = _three(Rs, h1, h2, h3, q0[0])
        Mw = mtm(mm(Rs, R4), R_tool)
        for i_s in range(ns):
            q[0] = x0 if i_s == 0 else x1
            q[1] = y0 if i_s == 0 else y1
            q[2] = z0 if i_s == 0 else z1
            q[3] = q4
            fs = flag | (SINGULAR if sings else 0)
            cs = code
            if lss:
                fs |= LS
                cs = ORIENTATION if cs == 0 else cs
            p0, p1, r0, r1, s0, s1, nw, lsw, singw = _three(Mw, h5, h6, h7, q0[4])
            for iw in range(nw):
                q[4] = p0 if iw == 0 else p1
                q[5] = r0 if iw == 0 else r1
                q[6] = s0 if iw == 0 else s1
                fw = fs | (SINGULAR if singw else 0)
                cw = cs
                if lsw:
                    fw |= LS
                    cw = WRIST_ORIENTATION if cw == 0 else cw
                count = _put(W, count, q, fw, cw, v0, v1, h)
    return count


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def nearest_equivalents(W, n, q0, lower, upper):
    """Each joint of the first ``n`` rows shifted by a multiple of 2 pi to the value
    nearest q0 within its limits (``sixr.nearest_equivalents`` over 7 joints)."""
    for r in range(n):
        for j in range(7):
            qi, ri, lo, hi = W[r, j], q0[j], lower[j], upper[j]
            best = math.nan
            base = qi + TWO_PI * round((ri - qi) / TWO_PI)
            for c in (base, base - TWO_PI, base + TWO_PI, qi):
                if lo - sixr.SNAP <= c <= hi + sixr.SNAP:
                    if math.isnan(best) or abs(c - ri) < abs(best - ri):
                        best = c
            if not math.isnan(best):
                W[r, j] = min(max(best, lo), hi)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def inside(W, r, lower, upper):
    """Whether row ``r`` is reached exactly and within the limits."""
    if int(W[r, 7]) & LS:
        return False
    for j in range(7):
        if not lower[j] - LIMIT_TOL <= W[r, j] <= upper[j] + LIMIT_TOL:
            return False
    return True


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def elbow_inside(W, n, lower, upper):
    """Whether joint 4 of a reached row of the first ``n`` is within its limits: the elbow
    angle does not change with the swivel angle, so when none is, none is at any."""
    for r in range(n):
        if not int(W[r, 7]) & LS and lower[3] - LIMIT_TOL <= W[r, 3] <= upper[3] + LIMIT_TOL:
            return True
    return False


@njit(cache=True, nogil=True, inline="always")
def _before(a, b):
    """a sorts before b: numba's and NumPy's order of floats, NaN after every number."""
    return a < b or (math.isnan(b) and not math.isnan(a))


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def ordered(W, n, q0, lower, upper, out):
    """The first ``n`` rows of ``W`` into ``out`` nearest q0 first (reached within the
    limits first, then reached, then the rest); returns whether the first is reached
    within the limits."""
    key = np.empty(n)
    for r in range(n):
        d2 = 0.0
        for j in range(7):
            d2 += (W[r, j] - q0[j]) ** 2
        key[r] = math.sqrt(d2) + (0.0 if inside(W, r, lower, upper) else 1e4)
        key[r] += 1e8 if int(W[r, 7]) & LS else 0.0
    # a stable insertion sort of at most ROWS keys, NaN last: np.argsort(kind="mergesort")'s
    # order, without compiling numba's merge sort (~2.5 s of CPU per process)
    order = np.empty(n, dtype=np.int64)
    for k in range(n):
        j = k
        while j > 0 and _before(key[k], key[order[j - 1]]):
            order[j] = order[j - 1]
            j -= 1
        order[j] = k
    for k in range(n):
        for c in range(COLUMNS):
            out[k, c] = W[order[k], c]
    return n > 0 and inside(out, np.int64(0), lower, upper)  # typed: no Literal copy


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_at(geo, R, pos, psi, q0, out):
    """``at_swivel`` with every row shifted to its 2 pi equivalent nearest q0 and
    ``ordered``: (n, first reached within the limits)."""
    lower, upper = geo[42:49], geo[49:56]
    W = np.empty((ROWS, COLUMNS))
    n = at_swivel(geo, R, pos, psi, q0, W)
    nearest_equivalents(W, n, q0, lower, upper)
    return n, ordered(W, n, q0, lower, upper, out)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def swept(geo, R, pos, q0, out):
    """The first swivel angle, q0's then ``SWEEP`` more round the circle nearest q0's
    first, with a row reached within the limits: (psi, n, found) and its rows in ``out``;
    q0's angle and its rows, found False, when none has one. A target whose shoulder to
    wrist span the elbow cannot make is not swept (no swivel angle changes that span)."""
    psi0, psi1 = sides_of(geo, q0)
    n, found = solve_at(geo, R, pos, psi0, q0, out)
    if psi1 != psi0:  # a stretched or folded q0: the side whose first row is nearer it
        other = np.empty_like(out)
        m, ok = solve_at(geo, R, pos, psi1, q0, other)
        nearer = n == 0 or (ok and not found)
        nearer = nearer or (ok == found and _distance(other, q0) < _distance(out, q0))
        if m > 0 and nearer:
            psi0, n, found = psi1, m, ok
            for r in range(m):
                for c in range(COLUMNS):
                    out[r, c] = other[r, c]
    if found or n == 0 or int(out[0, 9]) in (sixr.TOO_FAR, sixr.TOO_CLOSE):
        return psi0, n, found
    if not elbow_inside(out, n, geo[42:49], geo[49:56]):
        return psi0, n, False  # joint 4 is the same at every swivel angle
    first = out.copy()
    step = TWO_PI / SWEEP
    for k in range(1, SWEEP):
        psi = wrap(psi0 + (step * ((k + 1) // 2) if k % 2 else -step * (k // 2)))
        m, ok = solve_at(geo, R, pos, psi, q0, out)
        if ok:
            return psi, m, True
    for r in range(n):
        for c in range(COLUMNS):
            out[r, c] = first[r, c]
    return psi0, n, False
