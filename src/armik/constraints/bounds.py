"""Lower bounds on the distances of a checker's pairs, compiled: one small kernel over plain
arrays (``collision.Checker.bounds`` gathers them). A link object is held by a sphere (its
centre in its joint's frame, its radius) and by a capsule (two ends, a radius); an obstacle
by a box (rotation, centre, half sides), all in the arm's base frame. A pair of two link
objects is bounded by the larger of sphere to sphere and segment to segment, a link and an
obstacle by the larger of sphere to box and the capsule's separation along a box axis.
``ordered_bounds`` places the joints by the chain's own FK (``kernel.fk.joint_frames``) and
puts the pairs of smallest bounds in order in the same call: reading Pinocchio's joint
placements one by one from Python cost more than coal's distances.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from armik.kernel.chain import Flat
from armik.kernel.fk import joint_frames

PREFIX = 16  # pairs put in order of their bounds; a check rarely asks coal for more


@njit(cache=True, nogil=True)
def ordered_bounds(
    packed, kind, halton, q, H, joint_of, centre, radius, capsule, self_a, self_b, link,
    box_R, box_t, box_half, out, order,
):  # fmt: skip
    """``pair_bounds`` at joint values ``q`` (rad, m) of the chain ``chain.Flat``'s arrays
    (``H``: (N + 1, 4, 4) scratch for the joint frames, ``joint_of``: each link object's
    Pinocchio joint), and ``order``: the ``PREFIX`` pairs of smallest bounds in increasing
    order (ties in pair order), then the others in pair order, none of whose bounds is
    smaller; returns how many are in order. (A selection, not a sort: the few pairs a check
    needs, each kept in place as the pairs go by, in a fraction of np.argsort's compile
    time.)"""
    joint_frames(Flat(packed, kind, halton), q, H)
    pair_bounds(
        H, joint_of, centre, radius, capsule, self_a, self_b, link, box_R, box_t, box_half, out
    )
    n = out.shape[0]
    m = min(PREFIX, n)
    if m == 0:
        return m
    # the m smallest, kept in order as the pairs go by: each smaller than the last kept is
    # put in its place (after any equal one: ties in pair order)
    kept = 0
    for j in range(n):
        v = out[j]
        if kept < m:
            at = kept
            kept += 1
        elif v < out[order[m - 1]]:
            at = m - 1
        else:
            continue
        while at > 0 and out[order[at - 1]] > v:
            order[at] = order[at - 1]
            at -= 1
        order[at] = j
    # then the others in pair order (a pair with a bound at most the m-th's may be kept)
    last = out[order[m - 1]]
    w = m
    for j in range(n):
        if out[j] > last:
            order[w] = j
            w += 1
            continue
        taken = False
        for s in range(m):
            if order[s] == j:
                taken = True
                break
        if not taken:
            order[w] = j
            w += 1
    return m


@njit(cache=True, nogil=True)
def ordered_bounds_many(
    packed, kind, halton, Q, H, joint_of, centre, radius, capsule, self_a, self_b, link,
    box_R, box_t, box_half, out, order, ranked,
):  # fmt: skip
    """``ordered_bounds`` at each row of ``Q`` (N, dof), into rows of ``out`` and
    ``order`` (N, pairs), how many are in order into ``ranked`` (N,): one call for the
    answers of a batch's chunk."""
    for i in range(Q.shape[0]):
        ranked[i] = ordered_bounds(
            packed, kind, halton, Q[i], H, joint_of, centre, radius, capsule, self_a, self_b,
            link, box_R, box_t, box_half, out[i], order[i],
        )  # fmt: skip


@njit(cache=True, nogil=True)
def pair_bounds(
    H: np.ndarray,  # (J, 4, 4) the joints' placements in the base frame
    joint_of: np.ndarray,  # (n,) each link object's row of H
    centre: np.ndarray,  # (n, 3) each link object's sphere centre in its joint's frame (m)
    radius: np.ndarray,  # (n,) its radius (m)
    capsule: np.ndarray,  # (n, 7) a capsule holding it: two ends (joint frame), radius (m)
    self_a: np.ndarray,  # (s,) the arm's pairs: link objects a and b
    self_b: np.ndarray,
    link: np.ndarray,  # (o,) the obstacle pairs' link objects
    box_R: np.ndarray,  # (o, 3, 3) their obstacle's box: rotation, centre, half sides
    box_t: np.ndarray,  # (o, 3)
    box_half: np.ndarray,  # (o, 3)
    out: np.ndarray,  # (s + o,) the bounds (m, signed)
) -> None:
    n = centre.shape[0]
    c = np.empty((n, 3))
    ends = np.empty((2, n, 3))  # the capsules' ends in the base frame
    for i in range(n):
        j = joint_of[i]
        for r in range(3):
            c[i, r] = _placed(H, j, r, centre[i, 0], centre[i, 1], centre[i, 2])
            for e in range(2):
                x, y, z = capsule[i, 3 * e], capsule[i, 3 * e + 1], capsule[i, 3 * e + 2]
                ends[e, i, r] = _placed(H, j, r, x, y, z)
    s = self_a.shape[0]
    for k in range(s):
        a = self_a[k]
        b = self_b[k]
        dx = c[a, 0] - c[b, 0]
        dy = c[a, 1] - c[b, 1]
        dz = c[a, 2] - c[b, 2]
        spheres = math.sqrt(dx * dx + dy * dy + dz * dz) - radius[a] - radius[b]
        capsules = _segment_distance(ends, a, b) - capsule[a, 6] - capsule[b, 6]
        out[k] = max(spheres, capsules)  # both are lower bounds: the larger is tighter
    for k in range(link.shape[0]):
        a = link[k]
        outside = 0.0
        inside = -math.inf
        gap = -math.inf  # the capsule's segment apart from the box along one box axis
        for r in range(3):
            v = v0 = v1 = 0.0
            for m in range(3):
                v += box_R[k, m, r] * (c[a, m] - box_t[k, m])
                v0 += box_R[k, m, r] * (ends[0, a, m] - box_t[k, m])
                v1 += box_R[k, m, r] * (ends[1, a, m] - box_t[k, m])
            e = abs(v) - box_half[k, r]
            if e > 0.0:
                outside += e * e
            if e > inside:
                inside = e
            gap = max(gap, min(v0, v1) - box_half[k, r], -box_half[k, r] - max(v0, v1))
        sphere = math.sqrt(outside) + min(inside, 0.0) - radius[a]
        # a segment ``gap`` > 0 apart along an axis: moving the capsule by its radius - gap
        # along it parts them, so the signed distance is at least gap - radius
        out[s + k] = max(sphere, gap - capsule[a, 6]) if gap > 0.0 else sphere


@njit(cache=True, nogil=True)
def _placed(H, j, r, x, y, z):
    """Row r of the point (x, y, z) of joint j's frame, in the base frame."""
    return H[j, r, 0] * x + H[j, r, 1] * y + H[j, r, 2] * z + H[j, r, 3]


@njit(cache=True, nogil=True)
def _segment_distance(ends, a, b):
    """The distance between the segments ``ends[:, a]`` and ``ends[:, b]`` (Ericson,
    Real-Time Collision Detection, 5.1.9: the closest points, each clamped to its
    segment); scalars only (array arithmetic would compile numba's ufunc machinery)."""
    d1x, d1y, d1z = (
        ends[1, a, 0] - ends[0, a, 0],
        ends[1, a, 1] - ends[0, a, 1],
        ends[1, a, 2] - ends[0, a, 2],
    )
    d2x, d2y, d2z = (
        ends[1, b, 0] - ends[0, b, 0],
        ends[1, b, 1] - ends[0, b, 1],
        ends[1, b, 2] - ends[0, b, 2],
    )
    wx, wy, wz = (
        ends[0, a, 0] - ends[0, b, 0],
        ends[0, a, 1] - ends[0, b, 1],
        ends[0, a, 2] - ends[0, b, 2],
    )
    aa = d1x * d1x + d1y * d1y + d1z * d1z
    ee = d2x * d2x + d2y * d2y + d2z * d2z
    f = d2x * wx + d2y * wy + d2z * wz
    tiny = 1e-18
    if aa <= tiny and ee <= tiny:
        s = t = 0.0
    elif aa <= tiny:
        s, t = 0.0, min(max(f / ee, 0.0), 1.0)
    else:
        cc = d1x * wx + d1y * wy + d1z * wz
        if ee <= tiny:
            s, t = min(max(-cc / aa, 0.0), 1.0), 0.0
        else:
            bb = d1x * d2x + d1y * d2y + d1z * d2z
            den = aa * ee - bb * bb
            s = min(max((bb * f - cc * ee) / den, 0.0), 1.0) if den > tiny else 0.0
            t = (bb * s + f) / ee
            if t < 0.0:
                s, t = min(max(-cc / aa, 0.0), 1.0), 0.0
            elif t > 1.0:
                s, t = min(max((bb - cc) / aa, 0.0), 1.0), 1.0
    gx = wx + d1x * s - d2x * t
    gy = wy + d1y * s - d2y * t
    gz = wz + d1z * s - d2z * t
    return math.sqrt(gx * gx + gy * gy + gz * gz)
