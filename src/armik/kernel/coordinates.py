"""Joint values to Pinocchio's configuration, compiled (``ArmModel.to_pin``).

A continuous joint is one angle for armik and a (cos, sin) pair for Pinocchio. numpy's
fancy indexing costs about 2 us per conversion at arm sizes; this loop a tenth of that.
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, no_cfunc_wrapper=True)
def pin_configuration(q, idx_q, continuous, out):
    """out: Pinocchio's configuration of joint values q: joint i at out[idx_q[i]], a
    continuous one as (cos, sin) there."""
    for i in range(q.shape[0]):
        k = idx_q[i]
        if continuous[i]:
            out[k] = math.cos(q[i])
            out[k + 1] = math.sin(q[i])
        else:
            out[k] = q[i]
