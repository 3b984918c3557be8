"""From a 6R closed form's packed rows (``armik.solvers.closed_form.sixr``'s layout) to
``Answers``: the words of each row (its claim, branch label and reason), the prepared
solve's runner over a family's compiled kernel, and a batch's rows.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np

from armik import reasons
from armik.errors import SolverError
from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.solvers.answers import Answers, converged_claims, zero_counts
from armik.solvers.claims import claim
from armik.solvers.closed_form.sixr import LABELS, LS, NOT_FOUND, SINGULAR, flat, reason
from armik.solvers.closed_form.sixr_judged import WIDTH, context, finish, judge_array
from armik.status import Status


def claim_reason(closed_form: str, singular: bool) -> str:
    if singular:
        return (
            closed_form
            + "; singular: a free joint was kept at its q0 value or as near it as the target allows"
        )
    return closed_form


def pose_runner(
    arm: ArmModel,
    family: str,
    classify,
    solve_into,
    closed_form,
    size: int = 8,
    solve_all_into=None,
):
    """``run_pose(H, q0, seed, every=False)`` for ``armik.solve.prepared`` (see
    ``armik.solvers.numeric.driver.pose_runner``): ``solve_into(flat, H, q0, every, out)``
    is the family's compiled kernel for one plain 4x4 pose (n = -1 when the pose or q0 is
    not plain; see ``hand_over``). When the nearest row is reached within the limits, the
    answer ``solve`` verifies first, a ``Claim``; else every row's ``Answers``, as with
    ``every`` (``solve_all``, and ``solve`` when Pinocchio refuses that first answer; q
    read-only, nearest first). ``solve_all_into``: the family's kernel with every row
    measured and judged in the same call (``sixr_judged``), for ``run_pose.judging``."""
    chain = flat(arm, family, classify)
    why = ((closed_form, False), (closed_form, True))  # claim_reason's arguments
    empty = np.empty

    def run_pose(H: np.ndarray, q0: np.ndarray, seed: int, every: bool = False):
        out = empty((size, 11))  # size: the kernel's most rows
        n, head = solve_into(chain, H, q0, every, out)
        if n < 0:
            return None
        if head >= 0 and not every:
            singular = head >= 8
            label = LABELS[head & 7]
            return claim((out[0, :6], 0, 0, label, singular, claim_reason, why[singular]))
        return answers(out[:n], H)

    def answers(rows: np.ndarray, H: np.ndarray) -> Answers:
        """``rows`` as ``Answers`` (q read-only: solve_all's results' q are its rows)."""
        beyond = lambda: beyond_reach(arm, H[:3, 3])  # noqa: E731
        got = of_rows(rows, family, closed_form, beyond, (arm.lower, arm.upper))
        got.q.setflags(write=False)
        return got

    def judging(flat_chain, frame: np.ndarray, tol_p: float, tol_r: float):
        """``judged(H, q0)``: every row for ``H`` solved, measured against the arm's
        compiled chain ``flat_chain`` (``kernel.chain.Flat``) as ``frame`` says
        (``kernel.measure.fk_check_frame``) and judged with these tolerances (m, rad) in
        one compiled call (``sixr_judged.judged``): (rows (``size`` + 1,
        ``sixr_judged.WIDTH``), n, verdict: < 0 the general verdict decides its first n
        rows, labelled; else decided, ``judged.finish(rows, n)`` makes them whole), None
        when the pose or q0 is not plain. None without such a call."""
        if solve_all_into is None:
            return None
        ctx = context(chain, flat_chain, frame, judge_array(tol_p, tol_r))
        shape = (size + 1, WIDTH)  # the last row: the target, kept for finish

        def judged(H: np.ndarray, q0: np.ndarray):
            out = empty(shape)
            n, verdict = solve_all_into(ctx, H, q0, out)
            return None if n < 0 else (out, n, verdict)

        judged.finish = partial(finish, ctx)  # type: ignore[attr-defined]
        return judged

    # ``armik.solve.prepared``'s solve_all: the rows judged, their words
    run_pose.judging = judging  # type: ignore[attr-defined]
    run_pose.answers = answers  # type: ignore[attr-defined]
    run_pose.words = partial(words_of, family=family, closed_form=closed_form)  # type: ignore[attr-defined]
    return run_pose


def beyond_reach(arm: ArmModel, position) -> str | None:
    """Why a target at ``position`` (m) is out of reach when beyond the reach bound."""
    distance = math.dist(list(position), arm.first_joint_origin.tolist())
    return reasons.beyond_reach(distance, arm.reach) if distance > arm.reach else None


def of_rows(rows: np.ndarray, family: str, closed_form: str, beyond=None, limits=None) -> Answers:
    """The answers of a kernel's packed rows (see ``pack``), nearest first. ``beyond``:
    ``beyond_reach``'s reason (or a function giving it, asked only for an unreached row),
    which makes a search's miss unreachable. ``limits``: (lower, upper), the joint limits an
    unreached row's closest configuration is clipped into (a failure's q within them)."""
    known = _KNOWN[closed_form] if closed_form in _KNOWN else _know(closed_form)
    # a reached row's words by 8 flags + branch bits: indexed, not called (calls count)
    said = [known[int(8 * f + bits)] for f, bits in rows[:, 6:8].tolist()]
    reached = None not in said  # the common case: shared read-only claims
    if not reached:
        why = beyond() if callable(beyond) else beyond
        keys = rows[:, 6:11].tolist()
        said = [s or _said(r, family, why) for s, r in zip(said, keys)]
    codes, texts, labels, flags = zip(*said) if said else ((), (), (), ())
    n = len(said)
    counts = zero_counts(n)
    q = rows[:, :6].copy()
    if not reached and limits is not None:
        missed = np.array(codes) != Status.CONVERGED.code
        q[missed] = np.clip(q[missed], limits[0], limits[1])
    return frozen(
        Answers,
        q=q,
        claim=converged_claims(n) if reached else np.array(codes, dtype=np.int8),
        iterations=counts,
        restarts=counts,
        branch=labels,
        singular=np.array(flags, dtype=np.bool_) if True in flags else None,
        reasons=texts,
    )


def words_of(rows: list, family: str, closed_form: str) -> list | None:
    """Each packed row's (claim code, reason, branch label, singular), as ``of_rows`` gives
    them, from its flags, branch bits, code and values (columns 6 to 10 of ``rows``, lists
    of plain floats); None when a row is a search's miss (its words depend on the target's
    distance: ``of_rows`` writes them)."""
    known = _KNOWN[closed_form] if closed_form in _KNOWN else _know(closed_form)
    said = [known[int(8 * row[6] + row[7])] for row in rows]
    if None in said:
        for k, row in enumerate(rows):
            if said[k] is None:
                if int(row[8]) == NOT_FOUND:
                    return None
                said[k] = _said(row[6:11], family, None)
    return said


def _said(row: list, family: str, beyond: str | None):
    """(claim code, reason, branch label, singular) of one unreached packed row's flags,
    branch bits, code and values (``row``, plain floats)."""
    f, bits, code, v0, v1 = row
    claim, text = Status.UNREACHABLE, reason(int(code), (v0, v1), family)
    if int(code) == NOT_FOUND:  # a search's miss: no proof unless beyond reach
        claim = Status.NOT_CONVERGED if beyond is None else Status.UNREACHABLE
        text = text if beyond is None else f"{beyond}; q is q0"
    return claim.code, text, LABELS[int(bits)], bool(int(f) & SINGULAR)


def _know(closed_form: str) -> list:
    """``_said`` of every reached row by 8 flags + branch bits as the kernel writes them
    (flags 0 or singular), None for an unreached row's (flags with least squares)."""
    _KNOWN[closed_form] = [
        None
        if f & LS
        else (
            Status.CONVERGED.code,
            claim_reason(closed_form, f == SINGULAR),
            LABELS[bits],
            f == SINGULAR,
        )
        for f in range(4)
        for bits in range(8)
    ]
    return _KNOWN[closed_form]


_KNOWN: dict[str, list] = {}


def batch(arm: ArmModel, targets, q0: np.ndarray, kernel_many, chain) -> Answers:
    """``run_batch`` of a family: ``kernel_many(chain, Rs, ps, q0s)``
    (compiled, GIL released; ``chain`` the family's ``flat`` array) solves every target and
    keeps its row nearest q0 (reached, within limits first)."""
    if targets.rotations is None:
        raise SolverError(
            "the closed form needs full poses, these targets are positions only: use a "
            "numeric solver",
            solver="auto",
            candidates=[],
        )
    n = len(targets)
    Rs = np.ascontiguousarray(targets.rotations, dtype=float)
    ps = np.ascontiguousarray(targets.positions, dtype=float)
    # a writable copy: broadcast_to's view is read-only, and ascontiguousarray keeps it
    # so when q0 is (n, dof) already; a read-only seed compiled the whole kernel a second
    # time inside kernel_many (solve_into passes writable seeds), minutes on an empty cache
    q0s = np.array(np.broadcast_to(q0, (n, arm.dof)), dtype=float, order="C")
    q, claim = kernel_many(chain, Rs, ps, q0s)
    zeros = np.zeros(n, np.int64)
    return Answers(q=q, claim=claim, iterations=zeros, restarts=zeros.copy())
