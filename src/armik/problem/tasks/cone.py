"""The residual of a direction kept within a cone, shared by ``Axis`` and ``LookAt``.

With ``a`` the frame's axis and ``w`` the wanted direction, both unit and in the frame's
own axes, and ``theta`` the angle between them, the residual is the 3-vector along
``a x w`` of length ``max(theta - within, 0)``: zero inside the cone, smooth at its axis
when ``within`` is 0 (there it is ``a x w`` itself), and rank two, as a direction has two
degrees of freedom.
"""

from __future__ import annotations

import math

import numpy as np

_SMALL = 1e-12  # |a x w| below this: a and w (anti)parallel


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.cross`` of two 3-vectors, the same floats: numpy's general version costs ten
    times a task's residual on one pair."""
    a0, a1, a2 = a.tolist() if type(a) is np.ndarray else a
    b0, b1, b2 = b.tolist() if type(b) is np.ndarray else b
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def _norm(v: np.ndarray) -> float:
    """``np.linalg.norm`` of a vector (its square root of the dot product), without its
    dispatch."""
    return math.sqrt(float(v @ v))


def skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def angle(a: np.ndarray, w: np.ndarray) -> float:
    """The angle between unit vectors ``a`` and ``w`` (rad), accurate at 0 and pi."""
    return math.atan2(_norm(cross(a, w)), float(a @ w))


def residual(a: np.ndarray, w: np.ndarray, within: float) -> np.ndarray:
    c = cross(a, w)
    s = _norm(c)
    h = max(math.atan2(s, float(a @ w)) - within, 0.0)
    if h == 0.0:
        return np.zeros(3)
    if s < _SMALL:  # opposite: any axis across a turns it towards w
        return h * across(a)
    return c * (h / s)


def jacobian(a: np.ndarray, w: np.ndarray, dw: np.ndarray, within: float) -> np.ndarray:
    """(3, nv): the residual's derivative, given ``dw`` (3, nv), the derivative of ``w``."""
    c = cross(a, w)
    s, k = _norm(c), float(a @ w)
    theta = math.atan2(s, k)
    h = theta - within
    if h <= 0.0:
        return np.zeros_like(dw)
    if s < _SMALL:
        # at the axis (within 0): the residual is a x w; opposite: no useful derivative
        return skew(a) @ dw if k > 0 else np.zeros_like(dw)
    dc = skew(a) @ dw
    ds = c @ dc / s
    dtheta = k * ds - s * (a @ dw)  # |a| = |w| = 1: s^2 + k^2 = 1
    f = h / s
    df = (dtheta * s - h * ds) / (s * s)
    out: np.ndarray = dc * f + np.outer(c, df)
    return out


def across(a: np.ndarray) -> np.ndarray:
    """A unit vector across ``a``."""
    other = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    v = cross(a, other)
    out: np.ndarray = v / np.linalg.norm(v)
    return out
