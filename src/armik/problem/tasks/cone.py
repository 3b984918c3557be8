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


def skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def angle(a: np.ndarray, w: np.ndarray) -> float:
    """The angle between unit vectors ``a`` and ``w`` (rad), accurate at 0 and pi."""
    return math.atan2(float(np.linalg.norm(np.cross(a, w))), float(a @ w))


def residual(a: np.ndarray, w: np.ndarray, within: float) -> np.ndarray:
    c = np.cross(a, w)
    s = float(np.linalg.norm(c))
    h = max(math.atan2(s, float(a @ w)) - within, 0.0)
    if h == 0.0:
        return np.zeros(3)
    if s < _SMALL:  # opposite: any axis across a turns it towards w
        return h * _across(a)
    return c * (h / s)


def jacobian(a: np.ndarray, w: np.ndarray, dw: np.ndarray, within: float) -> np.ndarray:
    """(3, nv): the residual's derivative, given ``dw`` (3, nv), the derivative of ``w``."""
    c = np.cross(a, w)
    s, k = float(np.linalg.norm(c)), float(a @ w)
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


def _across(a: np.ndarray) -> np.ndarray:
    """A unit vector across ``a``."""
    other = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    v = np.cross(a, other)
    out: np.ndarray = v / np.linalg.norm(v)
    return out
