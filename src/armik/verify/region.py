"""The check of answers whose target has a region (``bounds``): how far each reached tip
pose lies outside the target's box, as ``armik.problem.Pose.measure`` and the compiled
step (``armik.kernel.region``) read the bounds.

The error twist of the reached pose relative to the target, in the target frame
(``R_t^T (p - p_t)``, ``log3(R_t^T R)``), is compared component by component with its
bound (``inf`` or a zero weight frees the component); the position and orientation errors
are the lengths of what lies outside: 0 inside the region, so that the tolerances mean
what they mean for an exact target. With a cone (a target's ``aim``), the orientation error
is the angle by which the tip axis ``a`` lies outside the cone around ``R_t a`` instead,
or, for a look-at, around the line from the tip to its point, or around a base-frame
direction (``toward``).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from armik.problem.tasks.cone import angle
from armik.tolerances import SIGHT


def region_errors(
    T_base_world: pin.SE3,
    R_w: np.ndarray,
    p_w: np.ndarray,
    R_t: np.ndarray,
    p_t: np.ndarray,
    bounds: np.ndarray,
    weights: np.ndarray,
    cone: tuple[float, ...] | None = None,
    look_at: tuple[float, ...] | None = None,
    toward: tuple[float, ...] | None = None,
) -> np.ndarray:
    """(n, 2): position (m) and orientation (rad) error outside the region of each of n
    tip placements (``R_w`` (n, 3, 3), ``p_w`` (n, 3), in the world frame) against the
    targets ``R_t`` (n, 3, 3), ``p_t`` (n, 3) in the base frame. A row with a non-finite
    placement gets NaN."""
    b = tuple(np.asarray(bounds, dtype=float).tolist())
    w = np.asarray(weights, dtype=float)
    out = np.empty((len(R_w), 2))
    for i in range(len(R_w)):
        out[i] = region_error(
            T_base_world, R_w[i], p_w[i], R_t[i], p_t[i], b, w, cone, look_at, toward
        )
    return out


def region_error(
    T_base_world: pin.SE3,
    R_w: np.ndarray,
    p_w: np.ndarray,
    R_t: np.ndarray,
    p_t: np.ndarray,
    bounds: tuple[float, ...],
    weights: np.ndarray,
    cone: tuple[float, ...] | None = None,
    look_at: tuple[float, ...] | None = None,
    toward: tuple[float, ...] | None = None,
    distances: bool = False,
    along: tuple[float, ...] | None = None,
) -> tuple[float, ...]:
    """The position (m) and orientation (rad) error outside the region of one tip placement
    (``R_w`` (3, 3), ``p_w`` (3,), in the world frame) against one target (``R_t``, ``p_t``
    in the base frame); NaN for a non-finite placement. Plain floats past the products and
    ``log3``: a single solve's check. With ``distances``, the true distances to the target
    follow (``armik.verify.distances``): the tip's to its position, and the geodesic angle
    to its rotation, or where the rotation is not the target's own (a look-at, a direction:
    ``toward``; ``along``: an ``armik.Axis`` lowered to a pose) the axis' angle to its
    direction."""
    R_b = T_base_world.rotation
    R = R_b @ R_w
    p = p_w @ R_b.T + T_base_world.translation
    if not (np.isfinite(R).all() and np.isfinite(p).all()):
        return (math.nan,) * (4 if distances else 2)
    e = (R_t.T @ (p - p_t)).tolist()
    if cone is None:  # a cone replaces the rotation components
        e += pin.log3(R_t.T @ R).tolist()
    out = [
        0.0 if w == 0.0 or math.isinf(b) else max(abs(x) - b, 0.0)
        for x, b, w in zip(e, bounds, weights.tolist())
    ]
    position = math.sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2])
    if cone is None:
        orientation = tilt = math.sqrt(out[3] * out[3] + out[4] * out[4] + out[5] * out[5])
    elif look_at is not None:  # around the line of sight (``LookAt``)
        sight = np.array(look_at) - p
        distance = float(np.linalg.norm(sight))
        # on the point, to within ``SIGHT`` as ``LookAt.measure`` has it: no line of sight,
        # nothing aimed at it (a move of the tip by a micrometre turns the sight any way)
        if not distance > SIGHT:
            orientation = tilt = math.pi
        else:
            tilt = angle(R @ np.array(cone[:3]), sight / distance)
            orientation = max(tilt - cone[3], 0.0)
    elif toward is not None:  # around a base-frame direction
        tilt = angle(R @ np.array(cone[:3]), np.array(toward))
        orientation = max(tilt - cone[3], 0.0)
    else:  # the angle between the tip's axis and the target's image of it
        a = np.array(cone[:3])
        tilt = angle(R @ a, R_t @ a)
        orientation = max(tilt - cone[3], 0.0)
    if not distances:
        return position, orientation
    x, y, z = e[0], e[1], e[2]  # written out: no call (every solve with a region)
    if along is not None and cone is None:  # the axis' angle (a cone's: ``tilt`` already)
        a = np.array(along)
        tilt = angle(R @ a, R_t @ a)
    elif cone is None:  # the rotation's angle: |log3|
        u, v, w = e[3], e[4], e[5]
        tilt = math.sqrt(u * u + v * v + w * w)
    elif look_at is None and toward is None and along is None:  # a cone on a pose
        u, v, w = pin.log3(R_t.T @ R).tolist()
        tilt = math.sqrt(u * u + v * v + w * w)
    return position, orientation, math.sqrt(x * x + y * y + z * z), tilt
