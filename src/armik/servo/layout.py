"""The servo's memory: one float array and one int array that hold everything a tick reads
and writes, laid out here for the ``Servo`` and its compiled tick alike.

A compiled call costs about 0.08 us an array argument to unbox, a sizeable share of a
tick, so the tick takes its target and these two arrays (and the collision rows): the
arm's chain (copied in once), the state kept between ticks, the settings, the outputs, the
last tick's target and the workspace are views into them.

Floats: state (``STATE_ROWS`` x n) | cfg (``CFG``) | out (``OUT``) | the last tick's table
(``MAX_TASKS`` x ``COLUMNS``) | a pose's table (1 x ``COLUMNS``) | the chain's packed
floats | one row of its restart table (its width is n) | the tick's workspace.
Ints: n, N, the packed floats' length, the kinds' length | the kinds | the workspace.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.chain import Flat
from armik.kernel.problem import NVEC

# columns of a task's row in a target's table; PARTS (2), 1.0 or 0.0: the parts its true
# distance has (``KernelRow.parts``: ``armik.servo.distances``)
ROT, POS, BOUNDS, WEIGHTS, CONE, AXIS, LOOK, SIGHT = 0, 9, 12, 18, 24, 25, 28, 29
PARTS = 32
COLUMNS = 34
MAX_TASKS = 4
MAX_ROWS = 16  # collision rows a tick (``armik.servo.collisions``), the nearest pairs'
RATE = 10.0  # 1/s: the share of its gap to the margin a pair may close a second (its damper)
# rows of the state (n columns): joint values, last velocity, limits; the tick's acceleration
Q, V, ACC, VMAX, AMAX, LO, HI, REST = range(8)  # Q, V, ACC first: the command
STATE_ROWS = 8
# entries of cfg (GRAM and LAST are kept by the tick between ticks, 0 at the start)
DT, TOL_P, TOL_R, SIGMA_EPS, LAM_MAX, LAM_MIN, GAIN, REACH_SLACK, PULL, LAM_ERR = range(10)
GRAM, LAST = 10, 11  # the size of the Gram matrix whose vector is kept; the last tasks
# from cfg[FIXED]: two 3 x 3 projectors onto the base frame's directions in which the tip
# never moves (linear) and never turns (angular) at any q, a planar arm's normal and its
# tilts (``armik.servo.fixed``): a task's row along them is not one the arm can follow
FIXED = 12
# the length (m) that bounds the task's second derivatives (``servo.curvature``)
CURVE = FIXED + 18
# the tip's structural ranks: its linear rows', its angular rows', the six's
# (``armik.servo.fixed.structural_ranks``): what bounds how many rows are independent
RANKS = CURVE + 1
CFG = RANKS + 3
# entries of out
POS_ERR, ORI_ERR, CODE, JOINT, SIGMA, CONFLICT = range(6)
OUT = 6
# An exact axis (bound 0) is given the bound -EXACT: ``kernel.region`` drops a row whose
# error lies within its bound, and the servo keeps every exact row in its step even at
# zero error (where the singular values are measured), for a residual of EXACT (m, rad).
EXACT = 1e-300
HEADER = 4  # ints: n, N, the packed floats' length, the kinds' length


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def workspace(n, N):
    """(floats, ints): the tick's workspace for n joint values and N physical joints:
    ``tick.views``' ``Workspace``, then ``step.scratch``'s arrays (the four in step)."""
    m = 6 * MAX_TASKS
    ws = 2 * n + 12 + 12 * n + 6 + NVEC * n + 4 * n * n + 6 * N + 6 * n + 18 + 9 + 36 + n
    ws += 36 + 12
    return ws + 4 * m + 2 * m * n + 8 * n * n + 19 * n + 2 * MAX_ROWS, 8 * n


def allocate(flat: Flat) -> tuple[np.ndarray, np.ndarray]:
    """(mem, imem) for the arm of ``flat``, zero but for its chain."""
    packed, kind, halton = flat
    n = halton.shape[1]
    N = (kind.shape[0] - n) // 2
    floats, ints = workspace(n, N)
    fixed = STATE_ROWS * n + CFG + OUT + (MAX_TASKS + 1) * COLUMNS
    mem = np.zeros(fixed + packed.shape[0] + n + floats)
    imem = np.zeros(HEADER + kind.shape[0] + ints, dtype=np.int64)
    imem[:HEADER] = n, N, packed.shape[0], kind.shape[0]
    mem[fixed : fixed + packed.shape[0]] = packed
    imem[HEADER : HEADER + kind.shape[0]] = kind
    return mem, imem


@njit(cache=True, nogil=True, inline="always")
def carve(mem, imem):
    """The views of the module docstring: (chain, state, cfg, out, last, pose, work,
    iwork)."""
    n, P, K = imem[0], imem[2], imem[3]
    o = STATE_ROWS * n
    state = mem[:o].reshape((STATE_ROWS, n))
    cfg = mem[o : o + CFG]
    o += CFG
    out = mem[o : o + OUT]
    o += OUT
    last = mem[o : o + MAX_TASKS * COLUMNS].reshape((MAX_TASKS, COLUMNS))
    o += MAX_TASKS * COLUMNS
    pose = mem[o : o + COLUMNS].reshape((1, COLUMNS))
    o += COLUMNS
    packed = mem[o : o + P]
    o += P
    halton = mem[o : o + n].reshape((1, n))  # (the restart table's width: n)
    o += n
    ch = Flat(packed, imem[HEADER : HEADER + K], halton)
    return ch, state, cfg, out, last, pose, mem[o:], imem[HEADER + K :]


def python_views(mem: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(state, cfg, out): ``carve``'s views that the ``Servo`` reads and sets."""
    o = STATE_ROWS * n
    return mem[:o].reshape((STATE_ROWS, n)), mem[o : o + CFG], mem[o + CFG : o + CFG + OUT]
