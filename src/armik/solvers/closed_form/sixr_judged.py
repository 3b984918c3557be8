"""A 6R closed form's every row measured and judged in the compiled call that solved it:
``solve_all``'s verdict where the rows alone decide it.

Each family's ``solve_all_into(context, H, q0, rows)`` runs its kernel into the first 11
columns of ``rows`` (``sixr``'s layout, nearest q0 first, no branch labels yet), then
``judged``: each row's tip placed by the compiled FK of the arm's own chain
(``armik.kernel.measure.fk_checks_beside``, held to Pinocchio's placement to 1e-12) and
measured against the target into columns 11 to 13, the verdict's ``RULE``
(``armik.verify.verdict``) applied into column 14 (its rank among failures in 15 and 16),
and the rows put in the order ``solve_all`` returns them: the verified rows in the kernel's
order, then the others by ``failure_rank``. Where the rule alone does not decide (a
claimed row the measure refutes within the limits, an unclaimed row it verifies, a
search's miss) or there is one row (Pinocchio measures it, as the general verdict does),
nothing is reordered, every row is labelled with its branch (column 7) and the general
verdict decides (``armik.solve.prepared``).

A decided target's branch labels are read when its results are built (``labels``: one
call for every row, on the first access of any result, ``armik.verify.judged``), as the
rest of a result is: a caller that reads no result does not pay for them.

``context`` packs what the call reads besides the target, seed and rows (the family's
chain, the arm's compiled chain, the measure's frame, the rule's numbers) in one array:
numba's dispatch costs about as much for each array argument as the FK of a row.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.measure import fk_checks_beside
from armik.solvers.closed_form.sixr import LS, NOT_FOUND, branch_bits, unflatten
from armik.status import FAILURE_RANK, Status

MEASURED = 11  # columns 11-13: position error (m), orientation error (rad, NaN), > 0 within
STATUS = 14  # the row's status code
RANK, ERROR = 15, 16  # its ``failure_rank`` pair (-1 and 0 verified): the order's key
WIDTH = 17  # columns of the rows ``solve_all_into`` writes

# verdicts ``judged`` returns
GENERAL = -1  # the general verdict decides
DECIDED = 0  # decided by the rule: the rows are judged and ordered

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


@njit(cache=True, nogil=True)
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


@njit(cache=True, nogil=True)
def judged(n, chain, packed, kind, halton, frame, judge, H, rows):
    """(n, verdict) of a kernel's ``n`` unlabelled rows in ``rows`` (n < 0: the pose or
    seed was not plain, nothing solved): measured, judged and ordered in place, see the
    module. ``chain``: ``sixr.flat``; ``packed``, ``kind``, ``halton``: the arm's
    ``kernel.chain.Flat``; ``frame``: ``kernel.measure.fk_check_frame``'s (unweighted);
    ``judge``: ``judge_array``'s."""
    if n < 0:
        return n, GENERAL
    if n < 2:
        return _general(n, chain, rows)
    fk_checks_beside(packed, kind, halton, frame, H, rows, n, MEASURED)
    tol_p, tol_r = judge[0], judge[1]
    rot = int(frame[18]) & 2 != 0
    ordered = True  # already by (rank, error): nothing to move
    for i in range(n):
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
        if i > 0 and _before(rows, i, i - 1):
            ordered = False
    if not ordered:
        _order(rows, n)
    return n, DECIDED


@njit(cache=True, nogil=True)
def _general(n, chain, rows):
    """(n, GENERAL), every row labelled with its branch for the general verdict."""
    h, p, _, _, _, _ = unflatten(chain)
    for r in range(n):
        rows[r, 7] = branch_bits(h, p, rows[r, :6])
    return n, GENERAL


@njit(cache=True, nogil=True)
def labels(chain, rows, bits):
    """bits[r]: the branch bits (``sixr.branch_bits``) of row r of ``rows`` (read only: a
    decided target's rows, as its results hold them), for every row."""
    h, p, _, _, _, _ = unflatten(chain)
    q = np.empty(6)  # a writable copy: the rows' own are compiled once, for the kernels
    for r in range(rows.shape[0]):
        for j in range(6):
            q[j] = rows[r, j]
        bits[r] = branch_bits(h, p, q)


@njit(cache=True, nogil=True)
def _before(rows, a, b):
    """Whether row ``a`` ranks before row ``b``: (rank, error) less."""
    ra, rb = rows[a, RANK], rows[b, RANK]
    return ra < rb or (ra == rb and rows[a, ERROR] < rows[b, ERROR])


@njit(cache=True, nogil=True)
def _order(rows, n):
    """The rows by (rank, error), ties in their order (a stable selection sort: at most 16
    rows): the verified ones (rank -1, error 0) keep the kernel's order."""
    W = rows[:n].copy()
    taken = 0
    for k in range(n):
        best = -1
        for r in range(n):
            if not taken & (1 << r) and (best < 0 or _before(W, r, best)):
                best = r
        taken |= 1 << best
        for c in range(rows.shape[1]):
            rows[k, c] = W[best, c]
