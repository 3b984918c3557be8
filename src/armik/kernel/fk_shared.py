"""Forward kinematics of several answers of one target that share leading joint values.

A closed form's answers come in branches: the IRB 120's eight share their first joint
value four by four and their first three two by two. ``forward_row`` places row ``r`` of
Q by ``fk.forward``'s arithmetic (its steps: ``fk.through_placement``, ``fk.turned``,
``fk.tip_pose``), but continues from the partial transform of an earlier
row whose leading joint values are the same (bit for bit, signed zeros apart): the same
operations from the same numbers, so the same placement to the last bit
(tests/kernel/test_fk_shared.py), for less work. For chains whose joints drive themselves
(no mimic joint: ``chain.joints(ch) == chain.dof(ch)``).
"""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.chain import PRISMATIC, joints, off_axis, off_joint_p, off_tip
from armik.kernel.fk import through_placement, tip_pose, turned

STATE = 12  # a partial transform: its rotation (9, row-major), then its translation (3)


@njit(cache=True, nogil=True, inline="always")
def _same(a, b):
    """a and b the same number, signed zeros told apart (their sines differ)."""
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def forward_row(ch, Q, r, S, R, p, placed):
    """T_base_tip = (R, p) of row ``r`` of Q (``fk.forward``'s), the rows of the bit set
    ``placed`` (rows before r) placed already by this function with the same scratch
    ``S`` (rows, joints + 1, ``STATE``): S[r, i] receives the partial transform after
    joint i - 1's motion (i >= 1)."""
    N = joints(ch)
    X = ch.packed
    jp, ja, tip = off_joint_p(N), off_axis(N), off_tip(N)
    kinds = ch.kind
    n = ch.halton.shape[1]
    k, src = 0, -1  # the most leading joints row r shares, with which earlier row
    for j in range(r):
        if not placed >> j & 1:
            continue
        m = 0
        while m < N and _same(Q[j, m], Q[r, m]):
            m += 1
        if m > k:
            k, src = m, j
    if k == 0:
        rot = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
        t = (0.0, 0.0, 0.0)
    else:
        for i in range(1, k + 1):
            for c in range(STATE):
                S[r, i, c] = S[src, i, c]
        a = S[src, k]
        rot = (a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8])
        t = (a[9], a[10], a[11])
    for i in range(k, N):
        rot, t = through_placement(X, i, jp, rot, t)
        o = ja + 3 * i
        ux, uy, uz = X[o], X[o + 1], X[o + 2]
        x = Q[r, i]
        if kinds[n + i] == PRISMATIC:
            r00, r01, r02, r10, r11, r12, r20, r21, r22 = rot
            wx = r00 * ux + r01 * uy + r02 * uz  # the axis in the base frame
            wy = r10 * ux + r11 * uy + r12 * uz
            wz = r20 * ux + r21 * uy + r22 * uz
            t = (t[0] + wx * x, t[1] + wy * x, t[2] + wz * x)
        else:
            rot = turned(rot, ux, uy, uz, x)
        b = S[r, i + 1]
        b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7], b[8] = rot
        b[9], b[10], b[11] = t
    tip_pose(X, tip, rot, t, R, p)
