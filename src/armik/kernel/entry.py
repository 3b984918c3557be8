"""The kernel's entries: whole solves (first descent and restarts) for N targets.

``solve_targets_dls`` and ``solve_targets_qp`` (one per step, so that a program that solves
with one solver compiles only its step) run without the GIL: threads calling them on
different chunks of targets run in parallel (each call allocates its own scratch). Each
target gets its own budget (CPU time of the calling thread, or iterations) and its own
restart stream (its seed). A target with a region and one without take the same entry:
a second entry without the region's code compiled in cost 9 % of ``armik compile --all``'s
larger half and no measurable time per solve.
"""

from __future__ import annotations

from numba import njit

from armik.kernel.chain import Flat, joints
from armik.kernel.descent import solve_one_dls, solve_one_qp
from armik.kernel.problem import _workspace
from armik.kernel.problem import unpack as unpack_settings

MINIMA_CAPACITY = 256  # known minima kept per solve (the oldest are dropped beyond)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_targets_dls(packed, kind, halton, sf, si, R_t, p_t, q0, seeds, out_q, info, err):
    """Solve target i = (R_t[i], p_t[i]) (rotation, position in the base frame) from
    q0[i] with restart seed seeds[i], for every i, with the dls step. The chain is
    ``chain.Flat``'s arrays, the settings ``pack_settings``'s. Outputs per target as
    ``descent.solve_one``: out_q (N, S, n), info (N, 5), err (N, 2)."""
    ch = Flat(packed, kind, halton)
    st = unpack_settings(sf, si)
    ws = _workspace(q0.shape[1], min(st.max_restarts + 1, MINIMA_CAPACITY), joints(ch))
    for i in range(R_t.shape[0]):
        solve_one_dls(ch, st, R_t[i], p_t[i], q0[i], seeds[i], ws, out_q[i], info[i], err[i])


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def solve_targets_qp(packed, kind, halton, sf, si, R_t, p_t, q0, seeds, out_q, info, err):
    """``solve_targets_dls`` with the qp step."""
    ch = Flat(packed, kind, halton)
    st = unpack_settings(sf, si)
    ws = _workspace(q0.shape[1], min(st.max_restarts + 1, MINIMA_CAPACITY), joints(ch))
    for i in range(R_t.shape[0]):
        solve_one_qp(ch, st, R_t[i], p_t[i], q0[i], seeds[i], ws, out_q[i], info[i], err[i])


ENTRIES = (solve_targets_dls, solve_targets_qp)  # indexed by problem.STEP_DLS, STEP_QP
