"""A ``BatchResult``'s one line: how many were solved, by status, the time and the
throughput, the largest errors (or distances) of the solved and their smallest clearance."""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np

from armik.reasons import Cone


class Summarised(Protocol):
    """What the line reads of a batch (``armik.batch_result.BatchResult``, which imports
    this module: a protocol, not that class, so neither stands on the other)."""

    # properties: a frozen dataclass's fields are read-only
    @property
    def arm(self) -> str: ...

    @property
    def solver(self) -> str: ...

    @property
    def time(self) -> float: ...

    @property
    def region(self) -> bool: ...

    @property
    def free(self) -> tuple[bool, bool]: ...

    @property
    def success(self) -> np.ndarray: ...

    @property
    def position_error(self) -> np.ndarray: ...

    @property
    def orientation_error(self) -> np.ndarray: ...

    @property
    def cone(self) -> float | None: ...

    @property
    def looks_at(self) -> bool: ...

    @property
    def aims(self) -> bool: ...

    @property
    def errors(self) -> dict[str, np.ndarray]: ...

    @property
    def _measured(self) -> np.ndarray: ...

    @property
    def _distances(self) -> np.ndarray: ...

    def __len__(self) -> int: ...

    def counts(self) -> dict[str, int]: ...

    def closest_pair(self, i: int) -> tuple[str, str] | None: ...


def summary(batch: Summarised) -> str:
    """One line: how many were solved, by status, the time and the throughput."""
    n = len(batch)
    name = f"{batch.arm}/{batch.solver}" if batch.arm else batch.solver
    if n == 0:
        return f"{name}: 0 targets"
    solved = int(batch.success.sum())
    counts = ", ".join(f"{k} {v}" for k, v in batch.counts().items())
    rate = n / batch.time if batch.time > 0 else math.inf
    line = (
        f"{name}: {solved}/{n} solved ({100.0 * solved / n:.2f} %; {counts}) in "
        f"{batch.time:.3g} s, {rate:,.0f} targets/s"
    )
    if solved:
        pos = batch.position_error[batch.success]
        held = ~np.isnan(pos)  # rows whose target holds a position (NaN: an Axis alone)
        worst = pos[held].max() if held.any() else math.nan
        apart = batch._measured[batch.success]  # NaN where the distances were measured
        ori = batch.orientation_error[batch.success]
        if batch.aims:  # the axis' angle to its direction: an aim's terms
            line += _aimed(batch, worst, ori)
        else:  # a part no target holds (a position, a rotation) unsaid
            said = [] if worst != worst else [f"{worst:.2g} m"]
            if not np.isnan(ori).all():
                said.append(f"{np.nanmax(ori):.2g} rad")
            if np.isnan(apart[:, 0]).all():
                line += f"; largest error of the solved: {', '.join(said)}"
            else:  # the errors are distances; the verdicts measured the region or weights
                to = "their targets" if batch.errors else "the target"  # several tips: each's
                line += f"; largest distance to {to} of the solved: {', '.join(said)}"
        if not np.isnan(apart[:, 0]).all():  # a part left wholly free measured 0: unsaid
            free_p, free_r = batch.free
            said = [] if free_p or not held.any() else [f"{np.nanmax(apart[held, 0]):.2g} m"]
            if not (free_r or np.isnan(apart[:, 1]).all()):
                said.append(f"{np.nanmax(apart[:, 1]):.2g} rad")
            if said:
                line += f" (the verdicts measured at most {', '.join(said)})"
        d = batch._distances[batch.success]
        if not np.isnan(d).all():
            k = int(np.nanargmin(d))
            pair = batch.closest_pair(int(np.flatnonzero(batch.success)[k]))
            names = "" if pair is None else f" ({pair[0]} / {pair[1]})"
            line += f"; smallest clearance of the solved: {d[k]:.3g} m{names}"
    return line


def _aimed(batch: Summarised, worst: float, ori: np.ndarray) -> str:
    """The largest distances of the solved of a batch whose targets aim the tip's axis: the
    tip's to the target (a position it has not unsaid), its axis' angle from its direction
    or the line to the point."""
    sight = Cone(batch.cone or 0.0, batch.looks_at).sight
    axis = f"{np.nanmax(ori):.2g} rad from {sight}"
    if worst != worst:
        return f"; largest distance of the solved: the tip's axis {axis}"
    return (
        f"; largest distances of the solved: the tip {worst:.2g} m from the target, its axis {axis}"
    )
