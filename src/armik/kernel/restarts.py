"""Restart seeds: a Halton sequence over the joint box with a shift drawn per solve.

The shift (a Cranley-Patterson rotation) comes from the solve's ``seed`` through SplitMix64,
so every target of a batch has its own deterministic stream whatever thread runs it.
Measured with the benchmark's protocol (2000 targets): against independent uniform samples
the Halton points took dls on the UR5 from 99.90 to 100 % and on the Z1 from 99.85 to
100 %, and qp on the Z1 from 99.05 to 99.55 %: hard targets need many restarts, and even
coverage finds their basin sooner. Unlimited joints are sampled in [-pi, pi].

``pick`` scores ``RESTART_CANDIDATES`` consecutive points by how far their tip lands from
the target (one FK each) and starts from the nearest. Measured together with the stop at
known minima (``descent.descend``) by ``armik bench -n 2000 --solvers dls qp --repeats 10``
against ``RESTART_CANDIDATES = 1`` and ``KNOWN_MINIMUM_RADIUS = 0``; failures out of 20000,
without -> with: Panda qp 28 -> 15, dls 18 -> 9; Z1 qp 38 -> 2, dls 17 -> 0; Kinova 5 -> 1
(both); xArm7 4 -> 0 (both); UR10 qp 2 -> 3, dls 3 -> 3; UR5 qp 1 -> 5, dls 5 -> 5.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from armik.kernel.chain import sample_box
from armik.kernel.error import candidate_score
from armik.kernel.linalg import copy_to
from armik.kernel.problem import CAND, SHIFT

RESTART_CANDIDATES = 4  # restart seeds scored per restart


@njit(cache=True, nogil=True, inline="always")
def _mix(z):
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


@njit(cache=True, nogil=True, inline="always")
def seed_shift(seed, shift):
    """shift (n,) in [0, 1): the SplitMix64 stream of ``seed`` (a non-negative integer)."""
    x = np.uint64(seed)
    for j in range(shift.shape[0]):
        x = x + np.uint64(0x9E3779B97F4A7C15)
        shift[j] = float(_mix(x) >> np.uint64(11)) * (1.0 / 9007199254740992.0)


# Each pass over the table past the first is turned by another rotation: pass w adds
# w * (WRAP + WRAP_STEP * j) to joint j (irrational steps: no pass repeats another), so a
# search of more restarts than the table holds (1000 by default, 128 a table of 512 points
# at RESTART_CANDIDATES each) does not start where it started before.
WRAP = 0.6180339887498949  # the golden ratio's fractional part
WRAP_STEP = 0.41421356237309515  # sqrt(2) - 1


@njit(cache=True, nogil=True, inline="always")
def restart_point(ch, shift, k, out):
    """out: the k-th restart configuration of the shifted sequence (rad, m)."""
    n = ch.halton.shape[0]
    passes = k // n
    row = ch.halton[k - passes * n]
    lo, span = sample_box(ch)
    for j in range(out.shape[0]):
        u = row[j] + shift[j] + passes * (WRAP + WRAP_STEP * j)
        u -= np.floor(u)
        out[j] = lo[j] + span[j] * u


@njit(cache=True, nogil=True, no_cpython_wrapper=True, no_cfunc_wrapper=True, _nrt=False)
def _pick(ch, st, R_t, p_t, ws, k, out):
    """out: of the restart points k .. k + RESTART_CANDIDATES - 1, the one whose tip lands
    nearest the target. Returns the index of the next unused point."""
    best = np.inf
    cand = ws.vec[CAND]
    for _ in range(RESTART_CANDIDATES):
        restart_point(ch, ws.vec[SHIFT], k, cand)
        k += 1
        score = candidate_score(ch, st, cand, R_t, p_t, ws)
        if not score >= best:  # NaN scores (overflowing models) never block a pick
            best = score
            copy_to(out, cand)
    return k


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def pick(ch, st, R_t, p_t, ws, k, out):
    """``_pick`` for Python callers (the kernel's copy goes without the CPython wrapper)."""
    return _pick(ch, st, R_t, p_t, ws, k, out)
