"""Forward kinematics of several answers of one target that share leading joint values.

A closed form's answers come in branches: the IRB 120's eight share their first joint
value four by four and their first three two by two. ``forward_row`` places row ``r`` of
Q by ``fk.forward``'s arithmetic, but continues from the partial transform of an earlier
row whose leading joint values are the same (bit for bit, signed zeros apart): the same
operations from the same numbers, so the same placement to the last bit
(tests/kernel/test_fk_shared.py), for less work. For chains whose joints drive themselves
(no mimic joint: ``chain.joints(ch) == chain.dof(ch)``).
"""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.chain import PRISMATIC, joints, off_axis, off_joint_p, off_tip

STATE = 12  # a partial transform: its rotation (9, row-major), then its translation (3)


@njit(cache=True, nogil=True, inline="always")
def _same(a, b):
    """a and b the same number, signed zeros told apart (their sines differ)."""
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


@njit(cache=True, nogil=True)
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
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
        t0, t1, t2 = 0.0, 0.0, 0.0
    else:
        for i in range(1, k + 1):
            for c in range(STATE):
                S[r, i, c] = S[src, i, c]
        a = S[src, k]
        r00, r01, r02, r10, r11, r12 = a[0], a[1], a[2], a[3], a[4], a[5]
        r20, r21, r22, t0, t1, t2 = a[6], a[7], a[8], a[9], a[10], a[11]
    for i in range(k, N):
        o = 9 * i  # joint i's placement: rotation P (row-major), translation d
        P00, P01, P02 = X[o], X[o + 1], X[o + 2]
        P10, P11, P12 = X[o + 3], X[o + 4], X[o + 5]
        P20, P21, P22 = X[o + 6], X[o + 7], X[o + 8]
        o = jp + 3 * i
        d0, d1, d2 = X[o], X[o + 1], X[o + 2]
        # t += r d ; r = r P
        t0 += r00 * d0 + r01 * d1 + r02 * d2
        t1 += r10 * d0 + r11 * d1 + r12 * d2
        t2 += r20 * d0 + r21 * d1 + r22 * d2
        a00 = r00 * P00 + r01 * P10 + r02 * P20
        a01 = r00 * P01 + r01 * P11 + r02 * P21
        a02 = r00 * P02 + r01 * P12 + r02 * P22
        a10 = r10 * P00 + r11 * P10 + r12 * P20
        a11 = r10 * P01 + r11 * P11 + r12 * P21
        a12 = r10 * P02 + r11 * P12 + r12 * P22
        a20 = r20 * P00 + r21 * P10 + r22 * P20
        a21 = r20 * P01 + r21 * P11 + r22 * P21
        a22 = r20 * P02 + r21 * P12 + r22 * P22
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = a00, a01, a02, a10, a11, a12, a20, a21, a22
        o = ja + 3 * i
        ux, uy, uz = X[o], X[o + 1], X[o + 2]
        x = Q[r, i]
        if kinds[n + i] == PRISMATIC:
            wx = r00 * ux + r01 * uy + r02 * uz  # the axis in the base frame
            wy = r10 * ux + r11 * uy + r12 * uz
            wz = r20 * ux + r21 * uy + r22 * uz
            t0 += wx * x
            t1 += wy * x
            t2 += wz * x
        else:
            # r <- r Rot(u, x), Rot = c I + s [u]x + (1 - c) u u^T (Rodrigues)
            s, c = math.sin(x), math.cos(x)
            kc = 1.0 - c
            m00 = c + kc * ux * ux
            m01 = kc * ux * uy - s * uz
            m02 = kc * ux * uz + s * uy
            m10 = kc * uy * ux + s * uz
            m11 = c + kc * uy * uy
            m12 = kc * uy * uz - s * ux
            m20 = kc * uz * ux - s * uy
            m21 = kc * uz * uy + s * ux
            m22 = c + kc * uz * uz
            a00 = r00 * m00 + r01 * m10 + r02 * m20
            a01 = r00 * m01 + r01 * m11 + r02 * m21
            a02 = r00 * m02 + r01 * m12 + r02 * m22
            a10 = r10 * m00 + r11 * m10 + r12 * m20
            a11 = r10 * m01 + r11 * m11 + r12 * m21
            a12 = r10 * m02 + r11 * m12 + r12 * m22
            a20 = r20 * m00 + r21 * m10 + r22 * m20
            a21 = r20 * m01 + r21 * m11 + r22 * m21
            a22 = r20 * m02 + r21 * m12 + r22 * m22
            r00, r01, r02 = a00, a01, a02
            r10, r11, r12 = a10, a11, a12
            r20, r21, r22 = a20, a21, a22
        b = S[r, i + 1]
        b[0], b[1], b[2], b[3], b[4], b[5] = r00, r01, r02, r10, r11, r12
        b[6], b[7], b[8], b[9], b[10], b[11] = r20, r21, r22, t0, t1, t2
    d0, d1, d2 = X[tip + 9], X[tip + 10], X[tip + 11]
    p[0] = t0 + r00 * d0 + r01 * d1 + r02 * d2
    p[1] = t1 + r10 * d0 + r11 * d1 + r12 * d2
    p[2] = t2 + r20 * d0 + r21 * d1 + r22 * d2
    for j in range(3):
        P0j, P1j, P2j = X[tip + j], X[tip + 3 + j], X[tip + 6 + j]
        R[0, j] = r00 * P0j + r01 * P1j + r02 * P2j
        R[1, j] = r10 * P0j + r11 * P1j + r12 * P2j
        R[2, j] = r20 * P0j + r21 * P1j + r22 * P2j
