"""The planar 2-link closed form, compiled: one target's rows for the general path
(``planar2r.run``) and the prepared solve (``solve_into``), so that both give the same
numbers.

``flat`` (``planar2r.flat``): the arm's geometry, limits and the solve's settings in one
float array (see the offsets below). ``H``: the target as a 4x4 (a position target's
rotation is not read); ``planar``: the target was given as (x, y) in plane coordinates,
``x``, ``y`` (then ``H`` is not read either: the target lies on the plane).

``rows`` writes up to 2 rows into ``out`` (2, 8), in the order the general path lists
them (elbow branch +acos first): the joint values (columns 0, 1), the claim (column 2:
``CONVERGED`` or ``UNREACHABLE``), the branch (column 3: ``UP``, ``DOWN``, ``STRETCHED``,
``FOLDED``, or ``NO_BRANCH``), singular (column 4: 0 or 1), the reason code (column 5) and
its two values (columns 6, 7). ``planar2r`` writes the texts.

The arithmetic is the one the closed form had in Python, operation for operation
(``hypot`` is CPython's ``math.hypot``, which is not the C library's), so that the answers
stay those of before to the last bit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.single import plain_pose, plain_seed
from armik.solvers.closed_form.sixr import TIE as HALF_TURN_TIE
from armik.tolerances import LIMIT_TOL

SINGULAR_TOL = 1e-12  # |cos t2| beyond 1 - this: the two branches merge
ZERO_LENGTH = 1e-9  # m
TWO_PI = 2.0 * math.pi
DBL_MIN = 2.2250738585072014e-308
TIE = 1e-12  # rad: two answers this close in distance to q0 are left to the general verdict

# offsets in ``flat``
SHOULDER, L1, L2, ALPHA1, ALPHA2, S1, S2 = 0, 2, 3, 4, 5, 6, 7
R_TIP0 = 8  # 9 values, row-major
ORIGIN, X, Y, NORMAL = 17, 20, 23, 26  # the plane, 3 values each
LOWER, UPPER = 29, 31  # 2 values each
TOL_POSITION, TOL_ORIENTATION, ORIENT = 33, 34, 35  # ORIENT: 1.0 when a full pose is checked
SIZE = 36

# claims, branches and reason codes: floats, as ``out`` holds them (and not literal ints,
# which would compile the callees that take them once per value)
CONVERGED, UNREACHABLE = 0.0, 1.0
NO_BRANCH, UP, DOWN, STRETCHED, FOLDED = -1.0, 0.0, 1.0, 2.0, 3.0
CLOSED_FORM = 0.0  # two elbow branches
MERGED = 1.0  # the arm fully stretched or folded: one answer, singular
FREE = 2.0  # target at the shoulder with l1 = l2: joint 1 free
OFF_PLANE = 3.0  # values: the distance off the plane
TOO_FAR = 4.0  # values: r, l1 + l2
DEAD_ZONE = 5.0  # values: r, |l1 - l2|
TILTED = 6.0  # values: the tilt of the target orientation out of the plane
MISSED = 7.0  # values: the branch's tip angle, the target's


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _two_product(x, y):
    """(x * y, its rounding error), exactly (Dekker)."""
    z = x * y
    t = x * 134217729.0
    xh = t - (t - x)
    xl = x - xh
    t = y * 134217729.0
    yh = t - (t - y)
    yl = y - yh
    return z, ((xh * yh - z) + xh * yl + xl * yh) + xl * yl


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def hypot(a, b):
    """CPython's ``math.hypot(a, b)`` to the last bit (its ``vector_norm``: lossless
    scaling, exact squares, compensated sums, a differential correction)."""
    a, b = abs(a), abs(b)
    m = a if a > b else b
    if math.isinf(m):
        return m
    if math.isnan(a) or math.isnan(b):
        return math.nan
    if m == 0.0:
        return m
    post = 1.0
    e = math.frexp(m)[1]
    if e < -1023:  # subnormal: made normal first
        a, b, m, post = a / DBL_MIN, b / DBL_MIN, m / DBL_MIN, DBL_MIN
        e = math.frexp(m)[1]
    scale = math.ldexp(1.0, -e)
    csum, frac1, frac2 = 1.0, 0.0, 0.0
    for x in (a * scale, b * scale):
        hi, lo = _two_product(x, x)
        s = csum + hi
        frac2 += (csum - s) + hi
        csum = s
        frac1 += lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    hi, lo = _two_product(-h, h)
    s = csum + hi
    frac2 += (csum - s) + hi
    csum = s
    frac1 += lo
    x = csum - 1.0 + (frac1 + frac2)
    h += x / (2.0 * h)
    return post * (h / scale)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _angle(a):
    return math.atan2(math.sin(a), math.cos(a))


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _nearest(qi, ri, lo, hi):
    """``ArmModel.nearest_equivalent`` for one revolute joint: ``qi`` shifted by a multiple
    of 2 pi to the value nearest ``ri`` within [lo, hi] (up to ``LIMIT_TOL`` outside counts
    as on the limit; a tie goes to ri + pi, ``sixr.nearest_equivalents``' rule); ``qi`` when
    no such value exists. Python's min and max, spelled out."""
    d = qi - ri
    if -math.pi <= d <= math.pi + HALF_TURN_TIE and lo <= qi <= hi:
        tie = d <= -math.pi + HALF_TURN_TIE and qi + TWO_PI <= hi
        return qi + TWO_PI if tie else qi
    near = qi + TWO_PI * round((ri - qi) / TWO_PI)
    if near - ri <= -math.pi + HALF_TURN_TIE and near + TWO_PI <= hi + LIMIT_TOL:
        near += TWO_PI
    best = math.nan
    for c in (near, near - TWO_PI, near + TWO_PI, qi):
        if lo - LIMIT_TOL <= c <= hi + LIMIT_TOL and (
            math.isnan(best) or abs(c - ri) < abs(best - ri)
        ):
            best = c
    if math.isnan(best):
        return qi
    best = lo if lo > best else best
    return hi if hi < best else best


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _row(flat, q0, out, k, t1, t2, claim, branch, singular, code, v0, v1):
    """Write row ``k``: the joint values of link angles t1, t2 nearest q0, and the rest."""
    q1 = _angle(flat[S1] * (t1 - flat[ALPHA1]))
    q2 = _angle(flat[S2] * (t2 - flat[ALPHA2]))
    out[k, 0] = _nearest(q1, q0[0], flat[LOWER], flat[UPPER])
    out[k, 1] = _nearest(q2, q0[1], flat[LOWER + 1], flat[UPPER + 1])
    out[k, 2] = claim
    out[k, 3] = branch
    out[k, 4] = singular
    out[k, 5] = code
    out[k, 6] = v0
    out[k, 7] = v1


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _elbow(flat, heading, t2):
    """Link 1's angle for elbow angle t2 (the tip at the target's heading)."""
    l1, l2 = flat[L1], flat[L2]
    return heading - math.atan2(l2 * math.sin(t2), l1 + l2 * math.cos(t2))


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def rows(flat, H, q0, planar, x, y, out):
    """The target's rows (see the module); returns how many."""
    first = np.int64(0)  # not a literal 0: _row would compile for it too
    if planar:  # given in plane coordinates: on the plane
        off, P0, P1 = 0.0, x, y
    else:
        # Plane.height and Plane.to_2d
        o = ORIGIN
        d = (H[0, 3] - flat[o], H[1, 3] - flat[o + 1], H[2, 3] - flat[o + 2])
        off = _dot(d, _vec(flat, NORMAL))
        P0, P1 = _dot(d, _vec(flat, X)), _dot(d, _vec(flat, Y))
    l1, l2, tol_p = flat[L1], flat[L2], flat[TOL_POSITION]
    d0, d1 = P0 - flat[SHOULDER], P1 - flat[SHOULDER + 1]
    r = hypot(d0, d1)
    c = (r * r - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    heading = math.atan2(d1, d0)
    clipped = c if c < 1.0 else 1.0
    clipped = clipped if clipped > -1.0 else -1.0

    if abs(off) > tol_p:
        t2 = math.acos(clipped)
        t1 = _elbow(flat, heading, t2)
        _row(flat, q0, out, first, t1, t2, UNREACHABLE, NO_BRANCH, 0.0, OFF_PLANE, off, 0.0)
        return 1

    if r < ZERO_LENGTH and abs(l1 - l2) < ZERO_LENGTH:
        t1 = flat[ALPHA1] + flat[S1] * q0[0]
        _row(flat, q0, out, first, t1, math.pi, CONVERGED, FOLDED, 1.0, FREE, 0.0, 0.0)
        n = 1
    else:
        inner = abs(l1 - l2)
        a, b = r - (l1 + l2), inner - r
        excess = b if b > a else a
        if abs(c) >= 1.0 - SINGULAR_TOL:
            stretched = c > 0
            t2 = 0.0 if stretched else math.pi
            # Folded with l2 > l1 the tip points away from link 1.
            t1 = heading if (stretched or l1 >= l2) else heading + math.pi
            if excess > tol_p:
                code, reach = (TOO_FAR, l1 + l2) if stretched else (DEAD_ZONE, inner)
                _row(flat, q0, out, first, t1, t2, UNREACHABLE, NO_BRANCH, 0.0, code, r, reach)
                return 1
            branch = STRETCHED if stretched else FOLDED
            _row(flat, q0, out, first, t1, t2, CONVERGED, branch, 1.0, MERGED, 0.0, 0.0)
            n = 1
        else:
            s1 = flat[S1]
            for k in range(2):
                t2 = (1.0 if k == 0 else -1.0) * math.acos(c)
                t1 = _elbow(flat, heading, t2)
                # the elbow left of the shoulder-target line seen down joint 1's axis: the
                # link turns clockwise about that axis at the elbow (``planar2r``)
                branch = UP if s1 * t2 < 0 else DOWN
                _row(flat, q0, out, k, t1, t2, CONVERGED, branch, 0.0, CLOSED_FORM, 0.0, 0.0)
            n = 2
    if flat[ORIENT] != 0.0:
        _orient(flat, H, out, n)
    return n


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, nogil=True, inline="always")
def _vec(flat, i):
    return flat[i], flat[i + 1], flat[i + 2]


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _left(v, M0, M1, M2):
    """v @ M, M by its rows."""
    return (
        v[0] * M0[0] + v[1] * M1[0] + v[2] * M2[0],
        v[0] * M0[1] + v[1] * M1[1] + v[2] * M2[1],
        v[0] * M0[2] + v[1] * M1[2] + v[2] * M2[2],
    )


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _times_transposed(h, T):
    """h @ T^T, T by its rows."""
    return _dot(h, T[0]), _dot(h, T[1]), _dot(h, T[2])


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _orient(flat, H, out, n):
    """A full pose fixes the tip angle too: rows whose angle misses it are unreachable.
    M = R_target R_tip0^T must be a rotation about the plane normal."""
    T0 = (_vec(flat, R_TIP0), _vec(flat, R_TIP0 + 3), _vec(flat, R_TIP0 + 6))  # its rows
    M0 = _times_transposed((H[0, 0], H[0, 1], H[0, 2]), T0)
    M1 = _times_transposed((H[1, 0], H[1, 1], H[1, 2]), T0)
    M2 = _times_transposed((H[2, 0], H[2, 1], H[2, 2]), T0)
    normal, x = _vec(flat, NORMAL), _vec(flat, X)
    cos_tilt = _dot(_left(normal, M0, M1, M2), normal)
    cos_tilt = cos_tilt if cos_tilt < 1.0 else 1.0
    tilt = math.acos(cos_tilt if cos_tilt > -1.0 else -1.0)
    tol_r = flat[TOL_ORIENTATION]
    if tilt > tol_r:
        for k in range(n):
            out[k, 2], out[k, 5], out[k, 6], out[k, 7] = UNREACHABLE, TILTED, tilt, 0.0
        return
    Mx = (_dot(M0, x), _dot(M1, x), _dot(M2, x))
    cross = (x[1] * Mx[2] - x[2] * Mx[1], x[2] * Mx[0] - x[0] * Mx[2], x[0] * Mx[1] - x[1] * Mx[0])
    want = math.atan2(_dot(cross, normal), _dot(_left(x, M0, M1, M2), x))
    for k in range(n):
        got = flat[S1] * out[k, 0] + flat[S2] * out[k, 1]
        if abs(_angle(got - want)) > tol_r:
            out[k, 2], out[k, 5], out[k, 6], out[k, 7] = UNREACHABLE, MISSED, _angle(got), want


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _eligible(flat, out, k):
    """Row ``k`` claimed converged and within the limits (``ArmModel.within_limits``)."""
    if out[k, 2] != CONVERGED:
        return False
    for j in range(2):
        if not flat[LOWER + j] - LIMIT_TOL <= out[k, j] <= flat[UPPER + j] + LIMIT_TOL:
            return False
    return True


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_into(flat, H, q0, planar, x, y, every, out):
    """``rows`` for the prepared solve, after checking in compiled code that ``H`` and
    ``q0`` are plain (``kernel.single``; else n = -1 and nothing solved). Returns (n,
    head): head >= 0 when the general verdict would verify one row first and that row is
    claimed converged within the limits: the row (head & 1) and its kind (head >> 1: the
    branch, or 4 for joint 1 free); -1 otherwise (and with ``every``),
    when the general verdict decides from every row. The verdict's order: claimed
    converged, within the limits, nearest q0 first; two rows nearly as near are left to
    it."""
    if not plain_pose(H) or not plain_seed(q0, flat[LOWER : LOWER + 2], flat[UPPER : UPPER + 2]):
        return -1, -1
    n = rows(flat, H, q0, planar, x, y, out)
    if every:
        return n, -1
    k, other = np.int64(0), np.int64(1)  # not literals: _eligible would compile for each
    if not _eligible(flat, out, k):
        if n == 1 or not _eligible(flat, out, other):
            return n, -1
        k = other
    elif n == 2 and _eligible(flat, out, other):
        a0, a1 = out[0, 0] - q0[0], out[0, 1] - q0[1]
        b0, b1 = out[1, 0] - q0[0], out[1, 1] - q0[1]
        da, db = math.sqrt(a0 * a0 + a1 * a1), math.sqrt(b0 * b0 + b1 * b1)
        if abs(da - db) <= TIE:
            return n, -1
        k = k if da < db else other
    # the claim's kind: its branch (UP, DOWN, STRETCHED, FOLDED), or 4 for joint 1 free
    kind = 4 if out[k, 5] == FREE else int(out[k, 3])
    return n, 2 * kind + k
