"""The kernel's one entry: whole solves (first descent and restarts) for N targets.

``solve_targets`` runs without the GIL: threads calling it on different chunks of targets
run in parallel (each call allocates its own scratch). Each target gets its own budget
(CPU time of the calling thread, or iterations) and its own restart stream (its seed).
"""

from __future__ import annotations

from numba import njit

from .descent import solve_one
from .problem import workspace


@njit(cache=True, nogil=True)
def solve_targets(ch, st, R_t, p_t, q0, seeds, out_q, info, err):
    """Solve target i = (R_t[i], p_t[i]) (rotation, position in the base frame) from
    q0[i] with restart seed seeds[i], for every i. Outputs per target as ``solve_one``:
    out_q (N, S, n), info (N, 5), err (N, 2)."""
    n = q0.shape[1]
    ws = workspace(n, min(st.max_restarts + 1, 1024))
    for i in range(R_t.shape[0]):
        solve_one(ch, st, R_t[i], p_t[i], q0[i], seeds[i], ws, out_q[i], info[i], err[i])
