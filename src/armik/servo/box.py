"""The servo's per-joint velocity box: every limit a tick's command must keep, compiled.

For joint i at q with the last commanded velocity v_prev, the next velocity v (rad/s or
m/s) lies in the intersection of

- the position box ``(lo - q) / dt <= v <= (hi - q) / dt``;
- the velocity box ``|v| <= vmax``;
- the acceleration box ``|v - v_prev| <= amax dt``;
- the braking box: moving by ``v dt`` and then braking at ``amax`` every tick stops within
  the limit, ``v dt + v^2 / (2 amax) <= hi - q``, that is
  ``v <= -amax dt + sqrt((amax dt)^2 + 2 amax (hi - q))`` (and alike toward ``lo``).

The braking box keeps the intersection non-empty from one tick to the next: a velocity
inside it at one tick leaves ``v_prev - amax dt`` inside it at the next (the servo starts
at rest within the limits). Should rounding ever empty the intersection, the braking,
position and velocity boxes win over the acceleration box, and the tick says so.
"""

from __future__ import annotations

import math

from numba import njit

FREE, POSITION, VELOCITY, ACCELERATION, BRAKING = range(5)  # which box gave a bound
SAFE = 1e-7  # the velocity and acceleration limits are kept to this fraction inside


@njit(cache=True, nogil=True, inline="always")
def braking(a, dt, d):
    """The fastest velocity toward a limit ``d`` away (>= 0) from which braking at ``a``
    every tick of ``dt`` stops within it (inf for no limit)."""
    if d == math.inf:
        return math.inf
    # -a dt + sqrt((a dt)^2 + 2 a d), written without its cancellation at small d
    return 2.0 * a * d / (a * dt + math.sqrt(a * a * dt * dt + 2.0 * a * d))


@njit(cache=True, nogil=True, inline="always")
def velocity_box(q, v_prev, lo, hi, vmax, amax, dt):
    """(lower, upper, lower's box, upper's box, conflict) for one joint: the velocity
    interval of the module docstring and which box set each end (``POSITION``...)."""
    a = amax * (1.0 - SAFE)
    vm = vmax * (1.0 - SAFE)
    d_hi = max(hi - q, 0.0)
    d_lo = max(q - lo, 0.0)
    # the boxes that always meet (position, velocity, braking: they all hold v = 0)
    ub, uk = d_hi / dt, POSITION
    if vm < ub:
        ub, uk = vm, VELOCITY
    b = braking(a, dt, d_hi)
    if b < ub:
        ub, uk = b, BRAKING
    lb, lk = -d_lo / dt, POSITION
    if -vm > lb:
        lb, lk = -vm, VELOCITY
    b = -braking(a, dt, d_lo)
    if b > lb:
        lb, lk = b, BRAKING
    if lb > ub:  # a joint outside its limits: stay
        return 0.0, 0.0, lk, uk, True
    # the acceleration box; on a conflict the braking side wins
    au, al = v_prev + a * dt, v_prev - a * dt
    if al > ub:
        return ub, ub, uk, uk, True
    if au < lb:
        return lb, lb, lk, lk, True
    if au < ub:
        ub, uk = au, ACCELERATION
    if al > lb:
        lb, lk = al, ACCELERATION
    return lb, ub, lk, uk, False
