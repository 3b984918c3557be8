"""A 6R closed form's every row measured and judged in the compiled call that solved it:
``solve_all``'s verdict where the rows alone decide it.

Each family's ``solve_all_into`` runs its kernel into the first 11 columns of ``rows``
(``sixr``'s layout, nearest q0 first), then ``judged``: each row's tip placed by the
compiled FK of the arm's own chain (``armik.kernel.measure.fk_checks_beside``, held to
Pinocchio's placement to 1e-12) and measured against the target into columns 11 to 13,
the verdict's ``RULE`` (``armik.verify.verdict``) applied into column 14 (its rank among
failures in 15 and 16), and the rows put in the order ``solve_all`` returns them: the
verified rows in the kernel's order, then the others by ``failure_rank``. Where the rule
alone does not decide (a claimed row the measure refutes within the limits, an unclaimed
row it verifies, a search's miss) or there is one row (Pinocchio measures it, as the
general verdict does), nothing is reordered and the general verdict decides
(``armik.solve.prepared``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.measure import fk_checks_beside
from armik.solvers.closed_form.sixr import LS, NOT_FOUND
from armik.status import FAILURE_RANK, Status

MEASURED = 11  # columns 11-13: position error (m), orientation error (rad, NaN), > 0 within
STATUS = 14  # the row's status code
RANK, ERROR = 15, 16  # its ``failure_rank`` pair (-1 and 0 verified): the order's key
WIDTH = 17  # columns of the rows ``solve_all_into`` writes

# verdicts ``judged`` returns
GENERAL = -1  # the general verdict decides
DISTINCT = 0  # decided, the branch labels distinct
REPEATED = 1  # decided, a branch label met twice (``verdict.numbered`` numbers them)


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


@njit(cache=True, nogil=True)
def judged(n, packed, kind, halton, frame, judge, H, rows):
    """(n, verdict) of a kernel's ``n`` rows in ``rows`` (n < 0: the pose or seed was not
    plain, nothing solved): measured, judged and ordered in place, see the module.
    ``packed``, ``kind``, ``halton``: the arm's ``kernel.chain.Flat``; ``frame``:
    ``kernel.measure.fk_check_frame``'s (unweighted); ``judge``: ``judge_array``'s."""
    if n < 2:
        return n, GENERAL
    fk_checks_beside(packed, kind, halton, frame, H, rows, n, np.int64(MEASURED))
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
            return n, GENERAL
        else:  # claimed outside the limits: joint_limits; not reached: its claim (unreachable)
            rows[i, STATUS], rows[i, RANK] = (
                (judge[3], judge[5]) if claimed else (judge[4], judge[6])
            )
            rows[i, ERROR] = pos + (ori if rot else 0.0)
        if i > 0 and _before(rows, i, i - 1):
            ordered = False
    if not ordered:
        _order(rows, n)
    seen = 0
    for i in range(n):
        bit = 1 << int(rows[i, 7])
        if seen & bit:
            return n, REPEATED
        seen |= bit
    return n, DISTINCT


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
        best = np.int64(-1)
        for r in range(n):
            if not taken & (1 << r) and (best < 0 or _before(W, r, best)):
                best = r
        taken |= 1 << best
        for c in range(rows.shape[1]):
            rows[k, c] = W[best, c]
