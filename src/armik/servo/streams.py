"""Target streams for trying a servo (its tests, ``benchmarks/servo.py``, the example):
start configurations of bundled arms, a circle, a jump, and the check of a commanded
sequence against its limits by finite differences."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

# Start configurations with room for a 25 cm jump and a 10 cm circle around the tip.
START = {
    "panda": np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8]),
    "ur5": np.array([0.3, -1.2, 1.4, -1.5, -1.5, 0.2]),
    "xarm7": np.array([0.0, 0.2, 0.0, 0.9, 0.0, 0.7, 0.0]),
    "abb_irb120": np.array([0.0, 0.2, 0.2, 0.0, 0.8, 0.0]),
}
JUMP = np.array([0.0, 0.25, 0.0])  # m, in the base frame: reachable from each START


def circle(T0: pin.SE3, ticks: int, dt: float, radius: float = 0.1, hz: float = 0.5):
    """A circle of ``radius`` m in the base frame's y-z plane through the tip (its centre
    ``radius`` below it), at ``hz`` turns a second, the orientation held."""
    out = []
    for k in range(1, ticks + 1):
        a = 2.0 * math.pi * hz * k * dt
        d = radius * np.array([0.0, math.sin(a), math.cos(a) - 1.0])
        out.append(pin.SE3(T0.rotation, T0.translation + d))
    return out


def moved(T0: pin.SE3, d: np.ndarray) -> pin.SE3:
    return pin.SE3(T0.rotation, T0.translation + d)


def violations(q0, Q, lower, upper, vmax, amax, dt) -> dict[str, float]:
    """The largest excess (rad, rad/s, rad/s^2) over each limit of the sequence q0, Q[0],
    ... by finite differences (0 where none)."""
    P = np.vstack([q0, Q])
    V = np.diff(P, axis=0) / dt
    A = np.diff(np.vstack([np.zeros(P.shape[1]), V]), axis=0) / dt
    return {
        "position": float(max(np.max(lower - P), np.max(P - upper), 0.0)),
        "velocity": float(max(np.max(np.abs(V) - vmax), 0.0)),
        "acceleration": float(max(np.max(np.abs(A) - amax), 0.0)),
    }
