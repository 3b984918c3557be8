"""Every 6R arm by a two-dimensional search (IK-Geo's ``IK_gen_6_dof``): all solutions of a
chain no closed-form family fits.

With the chain in product-of-exponentials form (``sixr.Chain6R``), R_06 = R R_tip0^T and
d = p - p_01 - R_06 p_6T the point on axis 6, fixed by the target. For joints 1 and 2 at
(q1, q2), joints 3, 4, 5 put that point there when

    -p_34 + rot(-h3, q3) u = rot(h4, q4) (p_45 + rot(h5, q5) p_56),
    u = rot(h2, q2)^T (rot(h1, q1)^T d - p_12) - p_23                  -> SP5: up to 4

and joint 6 then turns the tip about h6, which must lie where the target puts it:
R_05 h6 = R_06 h6, two equations in (q1, q2). ``grid`` evaluates that alignment error on a
``GRID`` x ``GRID`` grid of (q1, q2) over the whole circle, for every SP5 branch; every
local minimum below ``THRESHOLD`` (a branch compared with its neighbours' branches on the
same sheet: q3, q4, q5 within ``SHEET``) seeds a Newton polish of the full 6-D pose error
(the chain's own FK, Pinocchio's to rounding), and the configurations that reach the target
to ``EXACT``, deduplicated, are the answers: up to 16 (a general 6R arm has at most 16).
IK-Geo refines its minima with a simplex search in (q1, q2); the 6-D Newton gives full
precision in a few steps.

A search, not a proof: two solutions closer than a grid cell on one sheet can merge, and a
solution at a tangency of SP5's circles can be missed. The benchmark
``benchmarks/general_6r.py`` measures how often the configuration that made the target is
found. Branch labels are the answers' indices, nearest q0 first.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numba import njit

from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, axis_lines
from armik.problem.settings import SolverSettings
from armik.solvers.answers import Answers
from armik.solvers.closed_form import sixr
from armik.solvers.closed_form.search_1d import solve6
from armik.solvers.closed_form.subproblems import (
    add,
    cross,
    dot,
    mat,
    mm,
    mmt,
    mtv,
    mv,
    neg,
    norm,
    rot,
    sp1,
    sub,
    vec,
    wrap,
)
from armik.solvers.closed_form.subproblems_56 import _circle, _on, _pairs
from armik.solvers.registry import SolverSpec, get, register
from armik.status import Status
from armik.targets.pose import Target

FAMILY = "general_6r"
CLOSED_FORM = "2-D search (joints 1 and 2) with SP5, every root polished by Newton steps"
SEARCH_FAILED = "the 2-D search found no configuration reaching the target"
GRID = 72  # samples of q1 and of q2 over the circle
THRESHOLD = 1.0  # alignment error (|R_05 h6 - R_06 h6|) below which a grid minimum is a seed
SHEET = 0.3  # rad: SP5 branches of neighbouring cells this close (q3, q4, q5) are one sheet
SEEDS = 128  # seeds polished at most, the lowest first
ROWS = 16  # at most 16 solutions
RANK_LOST = 1e-9  # of the largest singular value: a Jacobian this near rank 5 has lost one
SNAP_RANK = 1e-5  # of |J|: a smallest singular value below it puts a row on a limit
ITERATIONS = 60  # Newton steps at most (a root where the Jacobian is singular converges slowly)
TRIES, GIVE_UP = 12, 1e-3  # Newton steps after which a seed this far from the target is left
EXACT = 1e-11  # m and rad: a polished configuration this close to the target is an answer
SAME = 1e-6  # rad: answers this close (each joint, modulo 2 pi) are one
LENGTH = 0.1  # m: the shift along axis 6 that keeps the point on it off axis 5
# ``sixr.onto_limits``'s put, typed: the literals False and True compiled it twice
CHECK, PUT = np.bool_(False), np.bool_(True)


def classify(arm: ArmModel, ax: Axes | None = None) -> sixr.Chain6R | str:
    """The chain of any 6R arm for the 2-D search (the points on axes 1 to 5 as
    ``axis_lines`` chose them, the point on axis 6 moved along it when it lies on axis 5, so
    that SP5 sees joint 5), or the reason it is not a 6R arm."""
    why = sixr.not_6r(arm)
    if why:
        return why
    ax = ax or axis_lines(arm)
    P, H = ax.points, ax.directions
    pts = [np.asarray(P[i], dtype=float) for i in range(6)]
    off = pts[5] - pts[4]
    if np.linalg.norm(np.cross(off, H[4])) < LENGTH:
        for s in (LENGTH, -LENGTH, 3 * LENGTH):
            cand = pts[5] + s * H[5]
            if np.linalg.norm(np.cross(cand - pts[4], H[4])) >= 0.5 * LENGTH:
                pts[5] = cand
                break
    text = "general 6R (2-D search)"
    return sixr.chain_6r("general_6r", "", ax, pts, text)


@njit(cache=True, no_cfunc_wrapper=True)
def grid(h, p, R06, d, E, T, C):
    """The alignment error ``E[i, j, b]`` (with SP5's own miss, relative) and (q3, q4, q5)
    ``T[i, j, b]`` of SP5's branch b at q1 = -pi + 2 pi i / N, q2 likewise; ``C[i, j]`` the
    branch count."""
    N = E.shape[0]
    h1, h2, h3, h4, h5, h6 = vec(h[0]), vec(h[1]), vec(h[2]), vec(h[3]), vec(h[4]), vec(h[5])
    p1, p2, p3, p4, p5 = vec(p[1]), vec(p[2]), vec(p[3]), vec(p[4]), vec(p[5])
    g6 = mv(R06, h6)
    k1, m3 = neg(h3), neg(p3)
    c3, a3, b3 = _circle(p4, h5, p5)
    M, f, pairs = np.empty(8), np.empty(2), np.empty((8, 2))
    fixed = max(norm(p3), norm(p4), norm(p5))
    for i in range(N):
        R1 = rot(h1, -math.pi + 2.0 * math.pi * i / N)
        a = sub(mtv(R1, d), p1)
        g1 = mtv(R1, g6)
        for j in range(N):
            R2 = rot(h2, -math.pi + 2.0 * math.pi * j / N)
            u = sub(mtv(R2, a), p2)
            g = mtv(R2, g1)
            c1, a1, b1 = _circle(m3, k1, u)
            size = max(fixed, norm(u))
            M[0], M[1], M[2], M[3] = dot(h4, a1), dot(h4, b1), -dot(h4, a3), -dot(h4, b3)
            M[4], M[5] = dot(c1, a1) / size, dot(c1, b1) / size
            M[6], M[7] = -dot(c3, a3) / size, -dot(c3, b3) / size
            f[0] = dot(h4, c3) - dot(h4, c1)
            f[1] = 0.5 * (dot(c3, c3) + dot(a3, a3) - dot(c1, c1) - dot(a1, a1)) / size
            m, free = _pairs(M, f, size, pairs)
            n = 0
            for r in range(0 if free else min(m, 4)):
                t3, t5 = pairs[r, 0], pairs[r, 1]
                v1, v3 = _on(c1, a1, b1, t3), _on(c3, a3, b3, t5)
                t4, _ = sp1(v3, v1, h4)
                R4 = rot(h4, t4)
                miss = norm(sub(v1, mv(R4, v3))) / size
                w = mv(rot(h3, t3), mv(R4, mv(rot(h5, t5), h6)))
                E[i, j, n] = norm(sub(w, g)) + miss
                T[i, j, n, 0], T[i, j, n, 1], T[i, j, n, 2] = t3, t4, t5
                n += 1
            C[i, j] = n


@njit(cache=True, no_cfunc_wrapper=True)
def _lower_near(E, T, C, i, j, b, e):
    """Whether a neighbour of cell (i, j) has a branch on b's sheet lower than ``e``."""
    N = E.shape[0]
    for di in range(-1, 2):
        for dj in range(-1, 2):
            if di == 0 and dj == 0:
                continue
            ii, jj = (i + di) % N, (j + dj) % N
            for c in range(C[ii, jj]):
                if E[ii, jj, c] >= e:
                    continue
                near = True
                for k in range(3):
                    if abs(wrap(T[ii, jj, c, k] - T[i, j, b, k])) > SHEET:
                        near = False
                if near:
                    return True
    return False


@njit(cache=True, no_cfunc_wrapper=True)
def seeds(E, T, C, threshold, S):
    """The grid's local minima below ``threshold``, lowest first, as rows (i, j, b) of
    ``S``; returns their count (at most ``len(S)``)."""
    N = E.shape[0]
    vals = np.full(S.shape[0], np.inf)
    n = 0
    for i in range(N):
        for j in range(N):
            for b in range(C[i, j]):
                e = E[i, j, b]
                if e >= threshold or (n == S.shape[0] and e >= vals[n - 1]):
                    continue
                if _lower_near(E, T, C, i, j, b, e):
                    continue
                k = min(n, S.shape[0] - 1)  # insert, keeping vals ascending
                while k > 0 and vals[k - 1] > e:
                    vals[k] = vals[k - 1]
                    S[k, 0], S[k, 1], S[k, 2] = S[k - 1, 0], S[k - 1, 1], S[k - 1, 2]
                    k -= 1
                vals[k] = e
                S[k, 0], S[k, 1], S[k, 2] = i, j, b
                n = min(n + 1, S.shape[0])
    return n


@njit(cache=True, no_cfunc_wrapper=True)
def pose_error(h, p, R_tip0, R, pos, q, J, e):
    """The tip's error (target minus reached: position, then the rotation vector of
    R R_tip^T, world frame) into ``e`` and the world-frame Jacobian into ``J`` (6, 6) at
    ``q``; returns |e|."""
    Rk = rot(vec(h[0]), q[0])
    o = vec(p[0])
    axes = np.empty((6, 3))
    points = np.empty((6, 3))
    Rprev = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    for k in range(6):
        w = mv(Rprev, vec(h[k]))
        for c in range(3):
            axes[k, c], points[k, c] = w[c], o[c]
        Rk = mm(Rprev, rot(vec(h[k]), q[k]))
        o = add(o, mv(Rk, vec(p[k + 1])))
        Rprev = Rk
    Rt = mm(Rk, mat(R_tip0))
    for k in range(6):
        w = vec(axes[k])
        v = cross(w, sub(o, vec(points[k])))
        for c in range(3):
            J[c, k], J[3 + c, k] = v[c], w[c]
    De = mmt(R, Rt)
    s = (0.5 * (De[7] - De[5]), 0.5 * (De[2] - De[6]), 0.5 * (De[3] - De[1]))
    sn = norm(s)
    cs = 0.5 * (De[0] + De[4] + De[8] - 1.0)
    k = 1.0 if sn < 1e-12 else math.atan2(sn, cs) / sn
    for c in range(3):
        e[c] = pos[c] - o[c]
        e[3 + c] = k * s[c]
    total = 0.0
    for c in range(6):
        total += e[c] * e[c]
    return math.sqrt(total)


@njit(cache=True, no_cfunc_wrapper=True)
def polish(h, p, R_tip0, R, pos, q, iters):
    """Damped Newton steps (Levenberg-Marquardt) on the 6-D pose error from ``q`` (changed
    in place); returns the final |error|. A seed still ``GIVE_UP`` away after ``TRIES``
    steps is left (a root converges in a few: most seeds lead nowhere)."""
    J, e, A, b, dq, qn = (np.empty((6, 6)), np.empty(6), np.empty((6, 6)), np.empty(6),
                          np.empty(6), np.empty(6))  # fmt: skip
    Jn, en = np.empty((6, 6)), np.empty(6)
    r = pose_error(h, p, R_tip0, R, pos, q, J, e)
    mu = 1e-12
    for it in range(iters):
        if r < 1e-14 or (it == TRIES and r > GIVE_UP):
            break
        for a in range(6):
            b[a] = 0.0
            for k in range(6):
                b[a] += J[k, a] * e[k]
            for c in range(6):
                s = 0.0
                for k in range(6):
                    s += J[k, a] * J[k, c]
                A[a, c] = s + (mu if a == c else 0.0)
        for a in range(6):
            dq[a] = b[a]
        if not solve6(A, dq, 1e-300):
            mu = max(mu * 100.0, 1e-9)
            continue
        for a in range(6):
            qn[a] = q[a] + dq[a]
        rn = pose_error(h, p, R_tip0, R, pos, qn, Jn, en)
        if rn < r:
            for a in range(6):
                q[a], e[a] = qn[a], en[a]
                for c in range(6):
                    J[a, c] = Jn[a, c]
            r = rn
            mu = max(mu * 0.1, 1e-15)
        else:
            mu *= 100.0
            if mu > 1e6:
                break
    return r


@njit(cache=True, no_cfunc_wrapper=True)
def onto_limits(h, p, R_tip0, R, pos, W, n, lower, upper):
    """Put each joint of the first ``n`` rows of ``W`` up to ``sixr.POLISHED_SNAP`` past a
    limit on it (``sixr.onto_limits``) in the rows whose Jacobian is near rank 5: its
    smallest singular value (two steps of inverse iteration) below ``SNAP_RANK`` of its
    size. Newton left such a double root up to ~1e-6 rad from where it lies; a regular root
    it leaves within 1e-14 over that value, so that a row past a limit by more than
    ``sixr.SNAP`` (``nearest_equivalents`` put the nearer on it) is past it, as the exact
    solution is: the Panda's joint 1 5e-7 rad past its limit was put on it, a success."""
    J, A, e, x, q = np.empty((6, 6)), np.empty((6, 6)), np.empty(6), np.empty(6), np.empty(6)
    for r in range(n):
        if not sixr.onto_limits(W, r, lower, upper, CHECK):
            continue
        for j in range(6):
            q[j], x[j] = W[r, j], 1.0 / math.sqrt(6.0)
        pose_error(h, p, R_tip0, R, pos, q, J, e)
        size = 0.0
        for a in range(6):
            for c in range(6):
                size += J[a, c] * J[a, c]
                A[a, c] = J[a, c]
        smallest = 0.0  # 1 / |J^-1 x| for a unit x: the smallest singular value or more
        for it in range(2):
            if it > 0:
                for a in range(6):
                    for c in range(6):
                        A[a, c] = J[a, c]
            grown = 0.0
            if solve6(A, x, 1e-300):
                for j in range(6):
                    grown += x[j] * x[j]
            grown = math.sqrt(grown)
            if not (grown > 0.0 and math.isfinite(grown)):
                smallest = 0.0
                break
            smallest = 1.0 / grown
            for j in range(6):
                x[j] /= grown
        if smallest < SNAP_RANK * math.sqrt(size):
            sixr.onto_limits(W, r, lower, upper, PUT)


@njit(cache=True, no_cfunc_wrapper=True)
def _seed_q(h, R06, i, j, t, N, q):
    """The full seed configuration of grid cell (i, j) and SP5 branch angles ``t``: q6 by
    SP1 from the rotation left to joint 6."""
    q[0] = -math.pi + 2.0 * math.pi * i / N
    q[1] = -math.pi + 2.0 * math.pi * j / N
    q[2], q[3], q[4] = t[0], t[1], t[2]
    R05 = rot(vec(h[0]), q[0])
    for k in range(1, 5):
        R05 = mm(R05, rot(vec(h[k]), q[k]))
    h6 = vec(h[5])
    x = cross(h6, vec(h[4]))
    if norm(x) < 0.1:
        x = cross(h6, (1.0, 0.0, 0.0)) if abs(h6[0]) < 0.9 else cross(h6, (0.0, 1.0, 0.0))
    q[5], _ = sp1(x, mtv(R05, mv(R06, x)), h6)


@njit(cache=True, no_cfunc_wrapper=True)
def kernel(h, p, R_tip0, R, pos, q0, lower, upper, N, threshold, out):
    """Every solution found for the target rotation ``R`` (3 x 3) and position ``pos`` (3),
    packed nearest-first into ``out`` (``ROWS``, 11) (``sixr.pack``; branches unlabelled);
    returns (n, first reached). The grid has ``N`` x ``N`` cells, its seeds are below
    ``threshold``. No solution: one least-squares row, the best polished configuration (q0
    when no seed was found)."""
    R9 = mat(R)
    R06 = mmt(R9, mat(R_tip0))
    P3 = vec(pos)
    d = sub(sub(P3, mv(R06, vec(p[6]))), vec(p[0]))
    E = np.empty((N, N, 4))
    T = np.empty((N, N, 4, 3))
    C = np.empty((N, N), np.int64)
    grid(h, p, R06, d, E, T, C)
    S = np.empty((SEEDS, 3), np.int64)
    m = seeds(E, T, C, threshold, S)
    W = np.empty((ROWS, 11))
    q, best = np.empty(6), np.empty(6)
    for k in range(6):
        best[k] = q0[k]
    rbest = math.inf
    n = np.int64(0)
    for s in range(m):
        _seed_q(h, R06, S[s, 0], S[s, 1], T[S[s, 0], S[s, 1], S[s, 2]], N, q)
        r = polish(h, p, R_tip0, R9, P3, q, ITERATIONS)
        if r < rbest:
            rbest = r
            for k in range(6):
                best[k] = q[k]
        if r > EXACT or n == ROWS:
            continue
        if is_new(W, n, q):
            zero = np.int64(0)  # typed: literal 0s compile put_row once more
            n = sixr.put_row(W, n, q[0], q[1], q[2], q[3], q[4], q[5], zero, zero, 0.0, 0.0)
    if n == 0:
        n = sixr.put_row(W, n, best[0], best[1], best[2], best[3], best[4], best[5],
                         np.int64(sixr.LS), np.int64(0), 0.0, 0.0)  # fmt: skip
    sixr.nearest_equivalents(W, n, q0, lower, upper)
    onto_limits(h, p, R_tip0, R9, P3, W, n, lower, upper)  # a double root a hair past one
    return n, sixr.pack(W, n, q0, lower, upper, h, p, np.int64(0), out)


@njit(cache=True, no_cfunc_wrapper=True)
def is_new(W, n, q):
    """Whether ``q`` is no answer among the first ``n`` rows of ``W``: some joint differs
    from each row's by more than ``SAME`` (modulo 2 pi)."""
    for t in range(n):
        same = True
        for k in range(6):
            if abs(wrap(W[t, k] - q[k])) > SAME:
                same = False
        if same:
            return False
    return True


def _classify(arm: ArmModel):
    return classify(arm)


def applies(arm: ArmModel, target: Target | None = None, _opts: object = None) -> str | None:
    return sixr.applies(arm, target, FAMILY, _classify)


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings, all_solutions: bool
) -> Answers:
    h, p, R_tip0, lower, upper, _ = sixr.unflatten.py_func(sixr.flat(arm, FAMILY, _classify))
    R, pos = sixr.pose_arrays(target)
    out = np.empty((ROWS, 11))
    # fresh writable copies: read-only arrays (a result's q, a frozen target) are another
    # numba type and would compile the kernel again
    R, pos, q0 = np.array(R), np.array(pos), np.array(q0, dtype=float)
    n, _ = kernel(h, p, R_tip0, R, pos, q0, lower, upper, GRID, THRESHOLD, out)
    if n == 1 and int(out[0, 6]) & sixr.LS:
        # none found: a solution at a tangency of SP5's circles (an elbow folded or
        # stretched) can hide from the grid; the numeric solver tries from q0, its answers
        # verified like any other
        found = get("dls").run(arm, target, q0, opts, all_solutions)
        said = [f"{SEARCH_FAILED}; dls: {found.reason(i)}" for i in range(len(found))]
        return found.reworded(said)
    labels = [str(k) for k in range(n)]
    found = Answers.of(out[:n, :6], [Status.CONVERGED] * n, [CLOSED_FORM] * n, 6, branch=labels)
    return rank_lost(arm, found)


def rank_lost(arm: ArmModel, found: Answers) -> Answers:
    """``found`` with each claimed row where the Jacobian loses a rank (smallest singular
    value below ``RANK_LOST`` of the largest) flagged singular and said so: the target
    then has a family of solutions (the Panda's axes 1 and 3 in line with a joint held),
    of which the search's grid gives samples."""
    flags = np.zeros(len(found), np.bool_) if found.singular is None else found.singular.copy()
    said = [found.reason(i) for i in range(len(found))]
    lost = False
    for i in range(len(found)):
        if not found.claimed(i) or flags[i]:
            continue
        s = np.linalg.svd(arm.jacobian(found.q[i]), compute_uv=False)
        if s[-1] < RANK_LOST * s[0]:
            flags[i], lost = True, True
            said[i] += (
                f"; singular: the joints lose a rank here (smallest singular value of the "
                f"Jacobian {s[-1]:.1e}), the target has a family of solutions and this is one"
            )
    if not lost:
        return found
    return dataclasses.replace(found, singular=flags, reasons=tuple(said))


SPEC = register(
    SolverSpec(
        name="general_6r",
        kind="analytic",
        enforces_limits=True,
        priority=55,
        why_not=applies,
        solves=frozenset(),
        run=run,
        summary="every 6R arm: a 2-D search over joints 1 and 2 with SP5, up to 16 solutions",
        complete=False,
    )
)
