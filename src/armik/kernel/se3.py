"""log3, log6 and their Jacobians, as in Pinocchio, with care at small angles and near pi.

Motion vectors are (linear, angular), as in Pinocchio. Rotations are 3x3 arrays, the
translation a 3-vector; outputs are written into arrays the caller owns (no allocation).
"""

from __future__ import annotations

import math

from numba import njit

SMALL = 1e-4  # rad: below this angle theta / sin(theta) is its series to rounding
# rad: below this angle the coefficients of log6 and the Jacobians come from their series
# (to t^4: truncation below 1e-13), above it from half-angle forms without cancellation.
SERIES = 0.05
NEAR_PI = 1e-2  # rad from pi: the axis comes from the symmetric part of R


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def rotation_angle(R):
    """The geodesic angle of R in [0, pi] (rad), accurate at 0 and at pi: atan2 of the
    sine (half the skew part) and the cosine (from the trace)."""
    sx = R[2, 1] - R[1, 2]
    sy = R[0, 2] - R[2, 0]
    sz = R[1, 0] - R[0, 1]
    s = 0.5 * math.sqrt(sx * sx + sy * sy + sz * sz)
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    return math.atan2(s, c)


# Compiled once and called, not inlined: inlined, numba copied and compiled it again at
# each of its three sites (log6_ab, the restart score, the check), ~1.3 s per process.
@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def log3(R, w):
    """w = log(R) (rad, the rotation vector); returns its angle theta = |w| in [0, pi]."""
    sx = R[2, 1] - R[1, 2]
    sy = R[0, 2] - R[2, 0]
    sz = R[1, 0] - R[0, 1]
    s = 0.5 * math.sqrt(sx * sx + sy * sy + sz * sz)
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    theta = math.atan2(s, c)
    if theta < math.pi - NEAR_PI:
        # w = theta / (2 sin theta) (R - R^T)^vee; theta / sin theta by its series near 0
        if theta < SMALL:
            f = 0.5 * (1.0 + theta * theta / 6.0)
        else:
            f = 0.5 * theta / s
        w[0], w[1], w[2] = f * sx, f * sy, f * sz
        return theta
    # Near pi the skew part vanishes: R + R^T = 2 (1 - c) a a^T + 2 c I gives the axis a
    # from the largest diagonal entry, the skew part only its sign.
    k = 0
    if R[1, 1] > R[k, k]:
        k = 1
    if R[2, 2] > R[k, k]:
        k = 2
    omc = 1.0 - c
    akk = (R[k, k] - c) / omc
    ak = math.sqrt(max(akk, 0.0))
    a0 = a1 = a2 = 0.0
    if ak > 0.0:
        inv = 1.0 / (2.0 * omc * ak)
        a0 = ak if k == 0 else (R[0, k] + R[k, 0]) * inv
        a1 = ak if k == 1 else (R[1, k] + R[k, 1]) * inv
        a2 = ak if k == 2 else (R[2, k] + R[k, 2]) * inv
    norm = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    if norm > 0.0:
        a0, a1, a2 = a0 / norm, a1 / norm, a2 / norm
    if a0 * sx + a1 * sy + a2 * sz < 0.0:
        a0, a1, a2 = -a0, -a1, -a2
    w[0], w[1], w[2] = theta * a0, theta * a1, theta * a2
    return theta


@njit(cache=True, nogil=True, inline="always")
def alpha_beta(theta):
    """(alpha, beta, sin(theta / 2)): alpha = (t/2) cot(t/2) and beta = 1/t^2 - cot(t/2) / (2t),
    shared by log6, Jlog3 and Jlog6 (Pinocchio's forms t sin t / (2 (1 - cos t)) lose digits
    to 1 - cos t); the sine is 0 below SERIES, where the series are used."""
    t2 = theta * theta
    if theta < SERIES:
        alpha = 1.0 - t2 / 12.0 - t2 * t2 / 720.0 - t2 * t2 * t2 / 30240.0
        beta = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1209600.0
        return alpha, beta, 0.0
    sh = math.sin(0.5 * theta)
    cot_half = math.cos(0.5 * theta) / sh
    return 0.5 * theta * cot_half, 1.0 / t2 - cot_half / (2.0 * theta), sh


@njit(cache=True, nogil=True, inline="always")
def jlog3(theta, w, J):
    """J = Jlog3: the derivative of log3 (Pinocchio's convention: right Jacobian inverse)."""
    alpha, diag, _ = alpha_beta(theta)
    jlog3_ab(alpha, diag, w, J)


@njit(cache=True, nogil=True, inline="always")
def jlog3_ab(alpha, diag, w, J):
    """``jlog3`` from ``alpha_beta(theta)``."""
    for i in range(3):
        for j in range(3):
            J[i, j] = diag * w[i] * w[j]
        J[i, i] += alpha
    J[0, 1] -= 0.5 * w[2]
    J[0, 2] += 0.5 * w[1]
    J[1, 0] += 0.5 * w[2]
    J[1, 2] -= 0.5 * w[0]
    J[2, 0] -= 0.5 * w[1]
    J[2, 1] += 0.5 * w[0]


@njit(cache=True, nogil=True, inline="always")
def log6(R, p, out):
    """out = log6((R, p)) = (v, w); returns the angle |w| (rad)."""
    theta, _, _, _ = log6_ab(R, p, out)
    return theta


@njit(cache=True, nogil=True, inline="always")
def log6_ab(R, p, out):
    """``log6``, returning (theta, ``alpha_beta(theta)``) for ``jlog6_ab``."""
    w = out[3:]
    theta = log3(R, w)
    alpha, beta, sh = alpha_beta(theta)
    wp = w[0] * p[0] + w[1] * p[1] + w[2] * p[2]
    # v = alpha p - 1/2 w x p + beta (w . p) w
    out[0] = alpha * p[0] - 0.5 * (w[1] * p[2] - w[2] * p[1]) + beta * wp * w[0]
    out[1] = alpha * p[1] - 0.5 * (w[2] * p[0] - w[0] * p[2]) + beta * wp * w[1]
    out[2] = alpha * p[2] - 0.5 * (w[0] * p[1] - w[1] * p[0]) + beta * wp * w[2]
    return theta, alpha, beta, sh


@njit(cache=True, nogil=True, inline="always")
def jlog6(R, p, J, w):
    """J (6 x 6) = Jlog6((R, p)) = [[Jlog3, B], [0, Jlog3]]; ``w`` is 3-vector scratch."""
    jlog6_of_log(log3(R, w), w, p, J)


@njit(cache=True, nogil=True, inline="always")
def jlog6_of_log(theta, w, p, J):
    """Jlog6 of the transform (exp3(w), p) with |w| = theta: for callers that have log3."""
    alpha, beta, sh = alpha_beta(theta)
    jlog6_ab(theta, alpha, beta, sh, w, p, J)


@njit(cache=True, nogil=True, inline="always")
def jlog6_ab(theta, alpha, beta, sh, w, p, J):
    """``jlog6_of_log`` from ``alpha_beta(theta)`` (computed once per evaluation)."""
    A = J[:3, :3]
    jlog3_ab(alpha, beta, w, A)
    t2 = theta * theta
    if theta < SERIES:
        beta_dot_over_theta = 1.0 / 360.0 + t2 / 7560.0 + t2 * t2 / 201600.0
    else:
        tinv = 1.0 / theta
        t2inv = tinv * tinv
        inv_2_2ct = 0.25 / (sh * sh)  # 1 / (2 (1 - cos theta))
        beta_dot_over_theta = (
            -2.0 * t2inv * t2inv + (1.0 + math.sin(theta) * tinv) * t2inv * inv_2_2ct
        )
    wp = w[0] * p[0] + w[1] * p[1] + w[2] * p[2]
    f1 = beta_dot_over_theta * wp
    f2 = t2 * beta_dot_over_theta + 2.0 * beta
    # C = v3 w^T + beta w p^T + wp beta I + skew(p / 2), v3 = f1 w - f2 p; B = C A
    C = J[3:, :3]  # scratch, zeroed below
    for i in range(3):
        v3 = f1 * w[i] - f2 * p[i]
        for j in range(3):
            C[i, j] = v3 * w[j] + beta * w[i] * p[j]
        C[i, i] += wp * beta
    C[0, 1] -= 0.5 * p[2]
    C[0, 2] += 0.5 * p[1]
    C[1, 0] += 0.5 * p[2]
    C[1, 2] -= 0.5 * p[0]
    C[2, 0] -= 0.5 * p[1]
    C[2, 1] += 0.5 * p[0]
    for i in range(3):
        for j in range(3):
            J[i, 3 + j] = C[i, 0] * A[0, j] + C[i, 1] * A[1, j] + C[i, 2] * A[2, j]
    for i in range(3):
        for j in range(3):
            J[3 + i, j] = 0.0
            J[3 + i, 3 + j] = A[i, j]
