"""The check of answers whose target has a region (``bounds``): how far each reached tip
pose lies outside the target's box, as ``armik.problem.Pose.measure`` and the compiled
step (``armik.kernel.region``) read the bounds.

The error twist of the reached pose relative to the target, in the target frame
(``R_t^T (p - p_t)``, ``log3(R_t^T R)``), is compared component by component with its
bound (``inf`` or a zero weight frees the component); the position and orientation errors
are the lengths of what lies outside: 0 inside the region, so that the tolerances mean
what they mean for an exact target.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin


def region_errors(
    T_base_world: pin.SE3,
    R_w: np.ndarray,
    p_w: np.ndarray,
    R_t: np.ndarray,
    p_t: np.ndarray,
    bounds: np.ndarray,
    weights: np.ndarray,
) -> np.ndarray:
    """(n, 2): position (m) and orientation (rad) error outside the region of each of n
    tip placements (``R_w`` (n, 3, 3), ``p_w`` (n, 3), in the world frame) against the
    targets ``R_t`` (n, 3, 3), ``p_t`` (n, 3) in the base frame. A row with a non-finite
    placement gets NaN."""
    R_b = T_base_world.rotation
    R = np.einsum("ij,njk->nik", R_b, R_w)
    p = p_w @ R_b.T + T_base_world.translation
    free = np.where(np.asarray(weights) == 0.0, math.inf, np.asarray(bounds, dtype=float))
    out = np.full((len(R), 2), np.nan)
    for i in range(len(R)):
        if not (np.isfinite(R[i]).all() and np.isfinite(p[i]).all()):
            continue
        M = R_t[i].T @ R[i]
        e = np.concatenate([R_t[i].T @ (p[i] - p_t[i]), pin.log3(M)])
        outside = np.where(np.isinf(free), 0.0, np.maximum(np.abs(e) - free, 0.0))
        out[i, 0] = math.sqrt(float(outside[:3] @ outside[:3]))
        out[i, 1] = math.sqrt(float(outside[3:] @ outside[3:]))
    return out
