"""Two joints whose axes lie in one line: only their sum (or difference) turns the tip, so
the closed forms choose the split, the first at a seed's value or the value nearest it
that keeps the other within its limits (a spherical wrist's joints 4 and 6, the swept 7R
arm's joints 3 and 5 at joint 4 = 0)."""

from __future__ import annotations

import math

from numba import njit

TWO_PI = 2.0 * math.pi


@njit(cache=True, no_cfunc_wrapper=True)
def split_at(qi, qj, s, ti, lower, upper, i, j):
    """Joint i's value nearest ``ti`` at which joint j = qj + s (qi - value) lies within
    its limits, turns by 2 pi allowed (joint i within its own, or within pi of ``ti``
    without them); ``ti`` itself where none does."""
    lo, hi = max(lower[i], ti - math.pi), min(upper[i], ti + math.pi)
    if math.isfinite(lower[i]) and math.isfinite(upper[i]):
        lo, hi = lower[i], upper[i]
    if not (math.isfinite(lower[j]) and math.isfinite(upper[j])):
        return min(max(ti, lo), hi)
    c = qj + s * qi  # joint j = c - s t (+ 2 pi k) at joint i = t
    a, b = (c - upper[j], c - lower[j]) if s > 0 else (lower[j] - c, upper[j] - c)
    best = ti
    gap = math.inf
    for m in range(math.ceil((lo - b) / TWO_PI), math.floor((hi - a) / TWO_PI) + 1):
        x0, x1 = max(a + TWO_PI * m, lo), min(b + TWO_PI * m, hi)
        if x0 <= x1:
            t = min(max(ti, x0), x1)
            if abs(t - ti) < gap:
                best, gap = t, abs(t - ti)
    return best
