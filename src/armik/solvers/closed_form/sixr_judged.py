"""A 6R closed form's every row measured and judged in the compiled call that solved it:
``solve_all``'s verdict where the rows alone decide it.

Each family's ``solve_all_into(context, H, q0, rows)`` runs its kernel into the first 11
columns of ``rows`` (``sixr``'s layout, nearest q0 first, no branch labels yet), then
``judged``: each row's tip placed by the compiled FK of the arm's own chain
(``armik.kernel.measure.fk_checks_beside``, held to Pinocchio's placement to 1e-12) and
measured against the target into columns 11 to 13, the verdict's ``RULE``
(``armik.verify.verdict``) applied into column 14 (its rank among failures in 15 and 16).
A row claimed outside the limits is ``joint_limits`` whatever it measures: its
measurement waits, with the order and the branch labels, for ``finish``, which the
results' first access calls (``armik.verify.judged``): the rows claimed outside the
limits measured as the others were, the rows put in the order ``solve_all`` returns them
(the verified rows in the kernel's order, then the others by ``failure_rank``) and
labelled. Every row a result says verified is measured in the call. Where the rule alone
does not decide (a claimed row the measure refutes within the limits, an unclaimed row it
verifies, a search's miss) or there is one row (Pinocchio measures it, as the general
verdict does), every row is labelled with its branch (column 7) and the general verdict
decides (``armik.solve.prepared``), measuring them all.

``rows`` has one row more than the kernel's most: ``judged`` keeps the target there for
``finish`` (its rotation row-major, then its position), so that a caller's array changed
after the call changes nothing.

``context`` packs what the call reads besides the target, seed and rows (the family's
chain, the arm's compiled chain, the measure's frame, the rule's numbers) in one array:
numba's dispatch costs about as much for each array argument as the FK of a row.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.descent import DUPLICATE_TOL
from armik.kernel.measure import fk_checks_beside
from armik.solvers.closed_form.sixr import LS, NOT_FOUND, branch_bits, unflatten
from armik.status import FAILURE_RANK, Status
from armik.tolerances import LIMIT_TOL

MEASURED = 11  # columns 11-13: position error (m), orientation error (rad, NaN), > 0 within
STATUS = 14  # the row's status code
RANK, ERROR = 15, 16  # its ``failure_rank`` pair (-1 and 0 verified): the order's key
WIDTH = 17  # columns of the rows ``solve_all_into`` writes

# verdicts ``judged`` returns
GENERAL = -1  # the general verdict decides
DECIDED = 0  # decided by the rule: the rows judged, ``finish`` makes them whole

UNLABELLED = np.int64(0)  # the kernel's ``labelled`` for ``solve_all_into``: no labels
CHAIN, JUDGE = 61, 7  # lengths of ``sixr.flat``'s array and ``judge_array``'s
HEAD = 3  # the context's header: the frame's length, the kinds' length, the joints


def judge_array(tol_position: float, tol_orientation: float) -> np.ndarray:
    """``judged``'s parameters: the tolerances (m, rad), the status codes it writes and the
    failure ranks that order them (``armik.status``)."""
    limits, unreachable = Status.JOINT_LIMITS, Status.UNREACHABLE
    return np.array(
        [
            tol_position,
            tol_orientation,
            Status.CONVERGED.code,
            limits.code,
            unreachable.code,
            FAILURE_RANK[limits],
            FAILURE_RANK[unreachable],
        ],
        dtype=float,
    )


def context(chain: np.ndarray, flat, frame: np.ndarray, judge: np.ndarray) -> np.ndarray:
    """One float array of what ``solve_all_into`` reads besides the target, seed and rows
    (``split`` reads it back): the family's ``chain`` (``sixr.flat``), ``judge``
    (``judge_array``), ``frame`` (``kernel.measure.fk_check_frame``) and the arm's
    compiled chain ``flat`` (``kernel.chain.Flat``: its kinds as floats; its restart table
    is not read, only its width)."""
    packed, kind, halton = flat
    head = [float(len(frame)), float(len(kind)), float(halton.shape[1])]
    parts = [head, chain, judge, frame, np.asarray(kind, dtype=float), packed]
    return np.concatenate([np.asarray(x, dtype=float).ravel() for x in parts])


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def split(ctx):
    """(chain, judge, frame, packed, kind, halton) of a ``context`` array: views, and the
    kinds and an empty restart table of the chain's width made here."""
    nf, nk, dof = int(ctx[0]), int(ctx[1]), int(ctx[2])
    a = HEAD + CHAIN
    b = a + JUDGE
    c = b + nf
    d = c + nk
    kind = np.empty(nk, np.int64)
    for i in range(nk):
        kind[i] = int(ctx[c + i])
    return ctx[HEAD:a], ctx[a:b], ctx[b:c], ctx[d:], kind, np.empty((0, dof))


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def judged(n, chain, packed, kind, halton, frame, judge, H, rows):
    """(n, verdict) of a kernel's ``n`` unlabelled rows in ``rows`` (n < 0: the pose or
    seed was not plain, nothing solved), judged in place, see the module; the target kept
    in the last row of ``rows`` (``TARGET``) for ``finish``. ``chain``: ``sixr.flat``;
    ``packed``, ``kind``, ``halton``: the arm's ``kernel.chain.Flat``; ``frame``:
    ``kernel.measure.fk_check_frame``'s (unweighted); ``judge``: ``judge_array``'s."""
    if n < 0:
        return n, GENERAL
    if n < 2:
        return _general(n, chain, rows)
    last = rows.shape[0] - 1
    for a in range(3):
        for b in range(3):
            rows[last, 3 * a + b] = H[a, b]
        rows[last, 9 + a] = H[a, 3]
    nj = (frame.shape[0] - 19) // 2
    lower, upper = frame[19 : 19 + nj], frame[19 + nj : 19 + 2 * nj]
    for i in range(n):  # an unreached row's closest configuration within the limits, as
        if int(rows[i, 6]) & LS:  # the general path's (``sixr_answers.of_rows``) is
            for j in range(nj):
                rows[i, j] = min(max(rows[i, j], lower[j]), upper[j])
    later = np.int64(0)  # bit i: row i claimed outside the limits, measured by ``finish``
    for i in range(n):
        claimed = not int(rows[i, 6]) & LS and int(rows[i, 8]) != NOT_FOUND
        if claimed and not _within(rows, i, lower, upper):
            later |= 1 << i
    fk_checks_beside(packed, kind, halton, frame, H, rows, n, np.int64(MEASURED), later)
    tol_p, tol_r = judge[0], judge[1]
    rot = int(frame[18]) & 2 != 0
    n, later = _once(rows, n, later, tol_p, tol_r, rot)
    for i in range(n):
        if later >> i & 1:  # joint_limits, whatever its errors: measured when read
            rows[i, MEASURED], rows[i, MEASURED + 1], rows[i, MEASURED + 2] = np.nan, np.nan, 0.0
            rows[i, STATUS], rows[i, RANK], rows[i, ERROR] = judge[3], judge[5], np.nan
            continue
        pos, ori, within = rows[i, MEASURED], rows[i, MEASURED + 1], rows[i, MEASURED + 2] > 0.0
        ok = within and pos <= tol_p and (not rot or ori <= tol_r)
        claimed = not int(rows[i, 6]) & LS
        if claimed and ok:
            rows[i, STATUS], rows[i, RANK], rows[i, ERROR] = judge[2], -1.0, 0.0
        elif ok or (claimed and within) or int(rows[i, 8]) == NOT_FOUND:
            return _general(n, chain, rows)
        else:  # claimed outside the limits: joint_limits; not reached: its claim (unreachable)
            rows[i, STATUS], rows[i, RANK] = (
                (judge[3], judge[5]) if claimed else (judge[4], judge[6])
            )
            rows[i, ERROR] = pos + (ori if rot else 0.0)
    return n, DECIDED


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def finish(ctx, rows, n):
    """A decided target's ``n`` rows made whole when its results are built: the rows
    claimed outside the limits measured as ``judged`` measures the others (against the
    target it kept in the last row), the rows put in ``solve_all``'s order (the verified
    ones in the kernel's, then the others by ``failure_rank``) and each labelled with its
    branch (column 7). ``ctx``: ``context``'s."""
    chain, judge, frame, packed, kind, halton = split(ctx)
    last = rows.shape[0] - 1
    H = np.zeros((4, 4))
    for a in range(3):
        for b in range(3):
            H[a, b] = rows[last, 3 * a + b]
        H[a, 3] = rows[last, 9 + a]
    H[3, 3] = 1.0
    later = np.int64(0)  # typed: a literal 0 compiles fk_checks_beside once more
    for i in range(n):
        if math.isnan(rows[i, ERROR]):
            later |= 1 << i
    if later:
        fk_checks_beside(packed, kind, halton, frame, H, rows, n, np.int64(MEASURED), ~later)
        rot = int(frame[18]) & 2 != 0
        for i in range(n):
            if later >> i & 1:
                rows[i, ERROR] = rows[i, MEASURED] + (rows[i, MEASURED + 1] if rot else 0.0)
    for i in range(1, n):
        if _before(rows, i, i - 1):  # not in order already
            _order(rows, n)
            break
    h, p, _, _, _, _ = unflatten(chain)
    for r in range(n):
        rows[r, 7] = branch_bits(h, p, rows[r, :6])


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _holds(rows, i, tol_p, tol_r, rot):
    """Whether row i's measure holds: within the limits, reaching the target."""
    pos, ori = rows[i, MEASURED], rows[i, MEASURED + 1]
    return rows[i, MEASURED + 2] > 0.0 and pos <= tol_p and (not rot or ori <= tol_r)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _once(rows, n, later, tol_p, tol_r, rot):
    """(n, later) of the first ``n`` measured rows without a row whose measure holds within
    ``DUPLICATE_TOL`` in every joint of an earlier such row (a double root the kernel found
    twice, 1e-8 apart at a singular target: one solution, listed once), the others moved up
    in their order; ``later``'s bits follow them."""
    kept = 0
    moved = np.int64(0)
    for i in range(n):
        waits = later >> i & 1
        if not waits and _holds(rows, i, tol_p, tol_r, rot):
            twice = False
            for k in range(kept):
                if not moved >> k & 1 and _holds(rows, k, tol_p, tol_r, rot):
                    twice = True
                    for j in range(6):
                        if not abs(rows[i, j] - rows[k, j]) < DUPLICATE_TOL:
                            twice = False
                            break
                    if twice:
                        break
            if twice:
                continue
        if kept != i:
            for c in range(rows.shape[1]):
                rows[kept, c] = rows[i, c]
        if waits:
            moved |= np.int64(1) << kept
        kept += 1
    return kept, moved


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _within(rows, i, lower, upper):
    """Row i's joint values within the limits (``kernel.measure``'s test: NaN is not)."""
    for j in range(lower.shape[0]):
        if not (lower[j] - LIMIT_TOL <= rows[i, j] <= upper[j] + LIMIT_TOL):
            return False
    return True


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _general(n, chain, rows):
    """(n, GENERAL), every row labelled with its branch for the general verdict."""
    h, p, _, _, _, _ = unflatten(chain)
    for r in range(n):
        rows[r, 7] = branch_bits(h, p, rows[r, :6])
    return n, GENERAL


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _before(rows, a, b):
    """Whether row ``a`` ranks before row ``b``: (rank, error) less."""
    ra, rb = rows[a, RANK], rows[b, RANK]
    return ra < rb or (ra == rb and rows[a, ERROR] < rows[b, ERROR])


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def _order(rows, n):
    """The rows by (rank, error), ties in their order (a stable selection sort: at most 16
    rows): the verified ones (rank -1, error 0) keep the kernel's order."""
    W = rows[:n].copy()
    taken = 0
    for k in range(n):
        best = np.int64(-1)
        for r in range(n):
            if not taken & (1 << r) and (best < 0 or _before(W, r, best)):
                best = r
        taken |= 1 << best
        for c in range(rows.shape[1]):
            rows[k, c] = W[best, c]
