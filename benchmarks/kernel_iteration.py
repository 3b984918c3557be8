"""Time one iteration of the kernel (pose error + Jacobian, then the dls step) in compiled code.

    PYTHONPATH=src python benchmarks/kernel_iteration.py [robot] [--qp]

Cycles through 64 random configurations against 64 reachable targets, so that the times are
those of typical iterations (no Python in the loop); reports ns per call, best of 7 runs.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np
from numba import njit

import armik
from armik.kernel import error, step
from armik.kernel.problem import pack_settings, unpack, workspace
from armik.options import Options
from armik.solvers.numeric import driver as numeric

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

ROUNDS = 20_000


# error._evaluate: what the descent calls (error.evaluate is its entry for Python callers,
# one call more in between)
@njit(nogil=True)
def _evaluate(ch, st, R_t, p_t, ws, Q, rounds):
    for r in range(rounds):
        k = r % Q.shape[0]
        for i in range(Q.shape[1]):
            ws.q[0, i] = Q[k, i]
        error._evaluate(ch, st, R_t[k], p_t[k], ws, 0)


@njit(nogil=True)
def _iteration(ch, st, R_t, p_t, ws, Q, q0, use_qp, rounds):
    for r in range(rounds):
        k = r % Q.shape[0]
        for i in range(Q.shape[1]):
            ws.q[0, i] = Q[k, i]
        error._evaluate(ch, st, R_t[k], p_t[k], ws, 0)
        if use_qp:
            step.qp(ch, st, ws, 0, q0, 1.0)
        else:
            step.dls(ch, st, ws, 0, q0, 1.0)


def best_ns(fn, *args) -> float:
    fn(*args[:-1], 10)  # compile
    times = []
    for _ in range(7):
        t = time.perf_counter()
        fn(*args)
        times.append(time.perf_counter() - t)
    return min(times) / ROUNDS * 1e9


def main() -> None:
    robot = next((a for a in sys.argv[1:] if not a.startswith("-")), "panda")
    use_qp = "--qp" in sys.argv
    arm = armik.load(robot)
    rng = np.random.default_rng(0)
    Q = np.array([arm.random_q(rng) for _ in range(64)])
    R_t, p_t = [], []
    for _ in range(64):
        T = arm.fk(arm.random_q(rng))
        R_t.append(T.rotation)
        p_t.append(T.translation)
    R_t, p_t = np.ascontiguousarray(R_t), np.ascontiguousarray(p_t)
    st_py = numeric.settings(Options(), False, arm.dof, 1, numeric.DLS_STEP)
    st = unpack(*pack_settings(st_py))
    kernel_chain = arm.kinematics.kernel_chain
    ch = kernel_chain.flat
    ws = workspace(arm.dof, 4, kernel_chain.chain.joint_kind.shape[0])
    q0 = np.ascontiguousarray(arm.middle)  # joint values (rad, m), as the kernel takes them
    ev = best_ns(_evaluate, ch, st, R_t, p_t, ws, Q, ROUNDS)
    it = best_ns(_iteration, ch, st, R_t, p_t, ws, Q, q0, use_qp, ROUNDS)
    name = "qp" if use_qp else "dls"
    print(f"{robot}: evaluate {ev:.0f} ns, {name} step {it - ev:.0f} ns, iteration {it:.0f} ns")


if __name__ == "__main__":
    main()
