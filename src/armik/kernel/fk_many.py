"""Forward kinematics of many configurations at once, compiled and without the GIL."""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.chain import Flat, joints
from armik.kernel.fk import forward, homogeneous


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def fk_many(packed, kind, halton, Q, out):
    """out[i] = T_base_tip (4x4) of joint values Q[i] (rad, m), for every row of Q (rows, n),
    on the chain ``chain.Flat``'s arrays."""
    ch = Flat(packed, kind, halton)
    N = joints(ch)
    R, p = np.empty((3, 3)), np.empty(3)
    origins, axes = np.empty((N, 3)), np.empty((N, 3))
    for i in range(Q.shape[0]):
        forward(ch, Q[i], R, p, origins, axes)
        homogeneous(R, p, out[i])
