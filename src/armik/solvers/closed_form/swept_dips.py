"""The swept 7R closed form's (``swept_7r``) search where no swept value of joint 7 gave an
answer within the limits: the exact rows' least limit violation at each cell's centre, and
its dips between cells searched by golden section for a value where it is 0 (``narrow``);
``dip_within`` here and in the preference's sweep (``armik.solve.prefer``). The golden
section's values come from ``search`` (``swept_7r.golden_search``), passed in."""

from __future__ import annotations

import math
from collections.abc import Callable
from operator import itemgetter

import numpy as np

from armik.solvers.closed_form import sixr

DIP_STEPS = 16  # golden-section steps in a dip of the limit violation
NARROW_DIPS = 4  # dips of the limit violation between swept values searched, least first


def golden(fn: Callable[[float], float], a: float, b: float, steps: int, search, until=-math.inf):
    """(fn(x), x) at each value ``search`` (a golden-section search) tries."""
    out: list[tuple[float, float]] = []
    for x in search(a, b, steps, out, until):
        out.append((fn(x), x))
    return out


def dip_within(violation: Callable[[float], float], a: float, b: float, search) -> float | None:
    """A value of [a, b] where ``violation`` (a branch's limit violation, 0 within the
    limits, inf where it is not reached) is 0, the first a golden-section search of its
    dip tried (``DIP_STEPS`` steps); None where it stays above 0."""
    least, x = min(golden(violation, a, b, DIP_STEPS, search, until=0.0), key=itemgetter(0))
    return x if least <= 0.0 else None


def narrow(rows_at, lo: float, hi: float, lower, upper, cells: int, near: float, search):
    """A value of [lo, hi] where one of the exact rows ``rows_at`` gives (theta -> rows,
    ``swept_7r``'s) lies within the limits, in an interval narrower than the ``cells``
    cells' spacing, or None: the rows' least limit violation at each cell's centre; where it
    dips between cells without reaching 0 there, a search of the dip for a value where it
    does (``dip_within``: the ``NARROW_DIPS`` least dips, the value nearest ``near`` kept)."""
    lower, upper = lower - sixr.LIMIT_TOL, upper + sixr.LIMIT_TOL

    def violation(theta: float) -> float:
        rows = rows_at(theta)
        Q = rows[(rows[:, 7].astype(np.int64) & sixr.LS) == 0, :7]
        if not len(Q):
            return math.inf
        return max(float(np.maximum(lower - Q, Q - upper).max(axis=1).min()), 0.0)

    width = (hi - lo) / cells
    x = [lo + (k + 0.5) * width for k in range(cells)]
    f = [violation(t) for t in x]
    dips = [
        (f[k], k)
        for k in range(cells)
        if 0.0 < f[k] < math.inf
        and f[k] <= (f[k - 1] if k else math.inf)
        and f[k] <= (f[k + 1] if k + 1 < cells else math.inf)
    ]
    found = []
    for _, k in sorted(dips)[:NARROW_DIPS]:
        a, b = (x[k - 1] if k else lo), (x[k + 1] if k + 1 < cells else hi)
        theta = dip_within(violation, a, b, search)
        if theta is not None:
            found.append(theta)
    return min(found, key=lambda t: abs(t - near)) if found else None
