"""The servo's step with collision rows ``C dq >= b`` besides the joints' boxes, compiled.

The box QP's step (``tick``) is kept where it meets every row. Otherwise the most violated
row joins the step as a stiff quadratic penalty ``WEIGHT |C_r dq - b_r|^2`` (relative to
the damped normal matrix's Frobenius norm, a bound on its largest eigenvalue) and the box
QP is solved again, one row a pass: the boxes stay hard (the joint, velocity, acceleration
and braking limits always hold), a row holds to about 1 / WEIGHT of its size where the
boxes leave room for it.
"""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.linalg import cholesky_factor, cholesky_substitute
from armik.kernel.step import active_set
from armik.servo.box_qp import nearest_in_box

WEIGHT = 1e6
PASSES = 8  # rows added at most
SHORT = 1e-12  # rad: a row short by less is met


@njit(cache=True, nogil=True, inline="always")
def _worst(C, b, dq, act):
    """The row most short of its bound among those not yet added, or -1."""
    n = dq.shape[0]
    worst, most = -1, SHORT
    for r in range(C.shape[0]):
        if act[r] != 0.0:
            continue
        s = 0.0
        for i in range(n):
            s += C[r, i] * dq[i]
        if b[r] - s > most:
            worst, most = r, b[r] - s
    return worst


@njit(cache=True, nogil=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def with_rows(C, b, Hl, xf, lb, ub, dq, act, Hp, Gi, gp, xp, unit, iscratch, mats, vecs):
    """dq (in place): the step within the boxes [lb, ub] nearest xf in the metric of the
    damped normal matrix ``Hl``, with the violated rows of ``C dq >= b`` as penalties; returns
    whether a row was added. ``act`` (rows), ``Hp``, ``Gi`` (n x n), ``gp``, ``xp``,
    ``unit`` (n) are scratch, as are ``iscratch`` (4, n) ints, ``mats`` (2, n, n) and
    ``vecs`` (3, n)."""
    n = dq.shape[0]
    top = 0.0
    for i in range(n):
        for j in range(n):
            top += Hl[i, j] * Hl[i, j]
    w = WEIGHT * math.sqrt(top)
    for r in range(C.shape[0]):
        act[r] = 0.0
    added = False
    side, held, sub, free = iscratch[0], iscratch[1], iscratch[2], iscratch[3]
    for _ in range(PASSES):
        r = _worst(C, b, dq, act)
        if r < 0:
            break
        act[r] = 1.0
        added = True
        for i in range(n):  # Hp = Hl + w sum c c^T; gp = Hl xf + w sum c b
            for j in range(n):
                Hp[i, j] = Hl[i, j]
        for i in range(n):
            s = 0.0
            for j in range(n):
                s += Hp[i, j] * xf[j]
            gp[i] = s
        for a in range(C.shape[0]):
            if act[a] == 0.0:
                continue
            for i in range(n):
                gp[i] += w * C[a, i] * b[a]
                for j in range(n):
                    Hp[i, j] += w * C[a, i] * C[a, j]
        for i in range(n):
            free[i] = 1
        if not cholesky_factor(Hp, free, mats[0]):
            break
        for c in range(n):  # Gi = Hp^-1
            for i in range(n):
                unit[i] = 1.0 if i == c else 0.0
            cholesky_substitute(mats[0], unit, free, vecs[0])
            for i in range(n):
                Gi[i, c] = vecs[0, i]
        for i in range(n):
            s = 0.0
            for j in range(n):
                s += Gi[i, j] * gp[j]
            xp[i] = s
        if not active_set(
            Gi, xp, lb, ub, xp, side, held, sub, mats[1], vecs[1], vecs[2], mats[0], dq
        ):  # cycled: the primal method, which cannot
            nearest_in_box(Hp, xp, lb, ub, dq, side, sub, mats[1], vecs[1], vecs[2])
        for i in range(n):
            dq[i] = min(max(dq[i], lb[i]), ub[i])
    return added
