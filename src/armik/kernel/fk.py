"""Forward kinematics and the tip Jacobian of a ``Chain`` (see ``chain.py``), compiled.

``T_base_tip`` for joint values q (rad, m); the Jacobian maps joint velocities to the tip's
twist (v, w) expressed in the tip frame, Pinocchio's LOCAL. A mimic joint takes the value
``multiplier * q[driver] + offset`` and its Jacobian column is folded into its driver's,
times the multiplier (see ``chain.py``). Scratch and outputs belong to the caller: nothing
is allocated per call.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import PRISMATIC, dof, joints, off_axis, off_joint_p, off_mimic, off_tip


# The running transform of the FK (rot: its rotation, 9 floats row-major; t: its
# translation), carried joint by joint: one copy of the arithmetic for ``forward`` and
# ``fk_shared.forward_row``, which must place alike to the last bit.
@njit(cache=True, nogil=True, inline="always")
def through_placement(X, i, jp, rot, t):
    """(rot, t) through physical joint i's fixed placement (rotation P, translation d):
    t += rot d ; rot = rot P."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = rot
    o = 9 * i
    P00, P01, P02 = X[o], X[o + 1], X[o + 2]
    P10, P11, P12 = X[o + 3], X[o + 4], X[o + 5]
    P20, P21, P22 = X[o + 6], X[o + 7], X[o + 8]
    o = jp + 3 * i
    d0, d1, d2 = X[o], X[o + 1], X[o + 2]
    t = (
        t[0] + (r00 * d0 + r01 * d1 + r02 * d2),
        t[1] + (r10 * d0 + r11 * d1 + r12 * d2),
        t[2] + (r20 * d0 + r21 * d1 + r22 * d2),
    )
    rot = (
        r00 * P00 + r01 * P10 + r02 * P20,
        r00 * P01 + r01 * P11 + r02 * P21,
        r00 * P02 + r01 * P12 + r02 * P22,
        r10 * P00 + r11 * P10 + r12 * P20,
        r10 * P01 + r11 * P11 + r12 * P21,
        r10 * P02 + r11 * P12 + r12 * P22,
        r20 * P00 + r21 * P10 + r22 * P20,
        r20 * P01 + r21 * P11 + r22 * P21,
        r20 * P02 + r21 * P12 + r22 * P22,
    )
    return rot, t


@njit(cache=True, nogil=True, inline="always")
def turned(rot, ux, uy, uz, x):
    """rot Rot(u, x), Rot = c I + s [u]x + (1 - c) u u^T (Rodrigues)."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = rot
    s, c = math.sin(x), math.cos(x)
    k = 1.0 - c
    m00 = c + k * ux * ux
    m01 = k * ux * uy - s * uz
    m02 = k * ux * uz + s * uy
    m10 = k * uy * ux + s * uz
    m11 = c + k * uy * uy
    m12 = k * uy * uz - s * ux
    m20 = k * uz * ux - s * uy
    m21 = k * uz * uy + s * ux
    m22 = c + k * uz * uz
    return (
        r00 * m00 + r01 * m10 + r02 * m20,
        r00 * m01 + r01 * m11 + r02 * m21,
        r00 * m02 + r01 * m12 + r02 * m22,
        r10 * m00 + r11 * m10 + r12 * m20,
        r10 * m01 + r11 * m11 + r12 * m21,
        r10 * m02 + r11 * m12 + r12 * m22,
        r20 * m00 + r21 * m10 + r22 * m20,
        r20 * m01 + r21 * m11 + r22 * m21,
        r20 * m02 + r21 * m12 + r22 * m22,
    )


@njit(cache=True, nogil=True, inline="always")
def tip_pose(X, tip, rot, t, R, p):
    """(R, p) = the tip frame's placement after the last joint's (rot, t)."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = rot
    d0, d1, d2 = X[tip + 9], X[tip + 10], X[tip + 11]
    p[0] = t[0] + r00 * d0 + r01 * d1 + r02 * d2
    p[1] = t[1] + r10 * d0 + r11 * d1 + r12 * d2
    p[2] = t[2] + r20 * d0 + r21 * d1 + r22 * d2
    for j in range(3):
        P0j, P1j, P2j = X[tip + j], X[tip + 3 + j], X[tip + 6 + j]
        R[0, j] = r00 * P0j + r01 * P1j + r02 * P2j
        R[1, j] = r10 * P0j + r11 * P1j + r12 * P2j
        R[2, j] = r20 * P0j + r21 * P1j + r22 * P2j


# ``forward`` and ``jacobian_local`` are compiled once and called, not inlined by numba:
# inlined, their IR was copied and typed again at each of a dozen call sites (4 s of CPU
# of the numeric solvers' compile, 3 s of the task solver's); called, a Panda iteration
# takes the same time (``benchmarks/kernel_iteration.py``: 648-688 ns against 661-685).
@njit(cache=True, nogil=True, no_cfunc_wrapper=True, _nrt=False)
def forward(ch, q, R, p, origins, axes):
    """T_base_tip = (R, p) for joint values q (``ch``: a ``chain.Flat``); ``origins`` and
    ``axes`` (N x 3) receive each physical joint's origin and unit axis in the base frame,
    for ``jacobian_local``."""
    n, N = dof(ch), joints(ch)
    X = ch.packed
    jp, ja, tip, mim = off_joint_p(N), off_axis(N), off_tip(N), off_mimic(N, n)
    kinds = ch.kind
    rot = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    t = (0.0, 0.0, 0.0)
    for i in range(N):
        rot, t = through_placement(X, i, jp, rot, t)
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = rot
        o = ja + 3 * i
        ux, uy, uz = X[o], X[o + 1], X[o + 2]
        wx = r00 * ux + r01 * uy + r02 * uz  # the axis in the base frame
        wy = r10 * ux + r11 * uy + r12 * uz
        wz = r20 * ux + r21 * uy + r22 * uz
        origins[i, 0], origins[i, 1], origins[i, 2] = t[0], t[1], t[2]
        axes[i, 0], axes[i, 1], axes[i, 2] = wx, wy, wz
        if N == n:  # no mimic joint: every joint is its own driver
            x = q[i]
        else:
            x = X[mim + i] * q[kinds[n + N + i]] + X[mim + N + i]
        if kinds[n + i] == PRISMATIC:
            t = (t[0] + wx * x, t[1] + wy * x, t[2] + wz * x)
        else:
            rot = turned(rot, ux, uy, uz, x)
    tip_pose(X, tip, rot, t, R, p)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True, _nrt=False)
def jacobian_local(ch, R, p, origins, axes, J):
    """J (6 x n): the tip Jacobian in the tip frame (LOCAL) from ``forward``'s outputs, a
    mimic joint's column added to its driver's times the multiplier."""
    n, N = dof(ch), joints(ch)
    mim = off_mimic(N, n)
    X, kinds = ch.packed, ch.kind
    # R and p read once into locals: the stores into J could alias them as far as the
    # compiler knows, which made it read them again for every column.
    r00, r01, r02 = R[0, 0], R[0, 1], R[0, 2]
    r10, r11, r12 = R[1, 0], R[1, 1], R[1, 2]
    r20, r21, r22 = R[2, 0], R[2, 1], R[2, 2]
    px, py, pz = p[0], p[1], p[2]
    own = N == n  # no mimic joint: column i is joint i's alone
    if not own:
        for c in range(n):
            for r in range(6):
                J[r, c] = 0.0
    for i in range(N):
        wx, wy, wz = axes[i, 0], axes[i, 1], axes[i, 2]
        if kinds[n + i] == PRISMATIC:
            vx, vy, vz = wx, wy, wz
            wx = wy = wz = 0.0
        else:  # v = w x (p_tip - o_i)
            dx, dy, dz = px - origins[i, 0], py - origins[i, 1], pz - origins[i, 2]
            vx = wy * dz - wz * dy
            vy = wz * dx - wx * dz
            vz = wx * dy - wy * dx
        # rotate into the tip frame: R^T
        if own:
            J[0, i] = r00 * vx + r10 * vy + r20 * vz
            J[1, i] = r01 * vx + r11 * vy + r21 * vz
            J[2, i] = r02 * vx + r12 * vy + r22 * vz
            J[3, i] = r00 * wx + r10 * wy + r20 * wz
            J[4, i] = r01 * wx + r11 * wy + r21 * wz
            J[5, i] = r02 * wx + r12 * wy + r22 * wz
            continue
        c, m = kinds[n + N + i], X[mim + i]  # into the driver's column, times the multiplier
        J[0, c] += m * (r00 * vx + r10 * vy + r20 * vz)
        J[1, c] += m * (r01 * vx + r11 * vy + r21 * vz)
        J[2, c] += m * (r02 * vx + r12 * vy + r22 * vz)
        J[3, c] += m * (r00 * wx + r10 * wy + r20 * wz)
        J[4, c] += m * (r01 * wx + r11 * wy + r21 * wz)
        J[5, c] += m * (r02 * wx + r12 * wy + r22 * wz)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def joint_frames(ch, q, H):
    """H (N + 1, 4, 4): the base frame's world placement inverted (row 0, where the model's
    fixed bodies hang), then each physical joint's frame after its motion, all in the base
    frame: Pinocchio's ``T_base_world * oMi[j]`` for j = 0..N. For the collision bounds;
    ``forward`` keeps its unrolled arithmetic for the solvers."""
    n, N = dof(ch), joints(ch)
    X = ch.packed
    jp, ja, mim = off_joint_p(N), off_axis(N), off_mimic(N, n)
    kinds = ch.kind
    base = mim - 12  # base_R (9), base_p (3) just before the multipliers (``flatten``)
    homogeneous(X[base : base + 9].reshape((3, 3)), X[base + 9 : base + 12], H[0])
    R, t = np.empty((3, 3)), np.empty(3)
    M, A = np.empty((3, 3)), np.empty((3, 3))
    for a in range(3):  # the identity, by loops (np.eye compiles a helper of its own)
        t[a] = 0.0
        for b in range(3):
            R[a, b] = 1.0 if a == b else 0.0
    for i in range(N):
        for a in range(3):  # t += R d ; R = R P
            t[a] += (
                R[a, 0] * X[jp + 3 * i] + R[a, 1] * X[jp + 3 * i + 1] + R[a, 2] * X[jp + 3 * i + 2]
            )
        for a in range(3):
            for b in range(3):
                A[a, b] = (
                    R[a, 0] * X[9 * i + b] + R[a, 1] * X[9 * i + 3 + b] + R[a, 2] * X[9 * i + 6 + b]
                )
        ux, uy, uz = X[ja + 3 * i], X[ja + 3 * i + 1], X[ja + 3 * i + 2]
        x = q[i] if N == n else X[mim + i] * q[kinds[n + N + i]] + X[mim + N + i]
        if kinds[n + i] == PRISMATIC:  # slides: R = A
            for a in range(3):
                t[a] += (A[a, 0] * ux + A[a, 1] * uy + A[a, 2] * uz) * x
                for b in range(3):
                    R[a, b] = A[a, b]
        else:  # turns: R = A M, M by Rodrigues: c I + s [u]x + (1 - c) u u^T
            s, c = math.sin(x), math.cos(x)
            k = 1.0 - c
            M[0, 0], M[0, 1], M[0, 2] = c + k * ux * ux, k * ux * uy - s * uz, k * ux * uz + s * uy
            M[1, 0], M[1, 1], M[1, 2] = k * uy * ux + s * uz, c + k * uy * uy, k * uy * uz - s * ux
            M[2, 0], M[2, 1], M[2, 2] = k * uz * ux - s * uy, k * uz * uy + s * ux, c + k * uz * uz
            for a in range(3):
                for b in range(3):
                    R[a, b] = A[a, 0] * M[0, b] + A[a, 1] * M[1, b] + A[a, 2] * M[2, b]
        homogeneous(R, t, H[i + 1])


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def homogeneous(R, p, T):
    """T (4 x 4) = [[R, p], [0, 0, 0, 1]] for the rotation R (3 x 3) and translation p."""
    for a in range(3):
        for b in range(3):
            T[a, b] = R[a, b]
        T[a, 3] = p[a]
        T[3, a] = 0.0
    T[3, 3] = 1.0
