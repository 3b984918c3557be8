"""A singular waypoint's rungs in a global plan (``armik.solve.rungs.every_branch``): rows
whose free angle continues the waypoints beside it.

A closed form's singular row (a wrist's two in-line joints sharing one sum, a wrist point
on the first axis leaving that joint free) keeps its free angle at its seed's value. The
rungs are solved from the path's start, whose value may lie far from where the
neighbouring waypoints' rows go through: the plan then breaks there, or detours through
another branch, where following goes straight through (a UR5 whose wrist 2 passes exactly
0 between two waypoints: a 0.3 rad "smallest jump" of wrist 1, then a 2.9 rad change of
elbow). So each singular waypoint (one with a singular row) is solved again from seeds
beside it, and its singular row nearest each seed kept where steps within
``max_joint_step`` (angles turned by 2 pi as the plan turns them) reach it:

- a run of singular waypoints (one waypoint or more) between two regular ones (before the
  first waypoint, the start): from the answers at its two ends, each paired with the other
  end's nearest it where the steps through the run can join them (not both regular
  branches through it: no free angle there), interpolated along the run: the free angle
  moves from one end's value to the other's by a share a waypoint, as a least-motion path
  moves it (one singular waypoint: halfway between its neighbours);
- then from each answer of the waypoint before that no row of this one continues yet (a
  pass forward, carrying the rows it adds along a run), and of the waypoint after (a pass
  backward): where the ends do not join (a path that truly breaks in the run, or a run at
  the path's end), the break is reported where it is, not where the start's free angle
  puts it.

Only singular waypoints are solved again: a path that meets none costs one look at its
rows' ``singular`` flags.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from armik.model.arm_model import ArmModel
from armik.result import IKResult

SAME = 1e-6  # rad or m: a row this near one already there is that row
EDGE = 1e-9  # rad or m: a step this far over max_joint_step is on it (ladder.STEP_EDGE)

Solve = Callable[[int, np.ndarray], list]  # (waypoint, seed) -> its solve_all results


def continued(arm: ArmModel, found: list, start, step: np.ndarray, solve: Solve) -> list:
    """``found`` (each waypoint's ``solve_all`` rows, solved from ``start``) with the rows of
    each singular waypoint that continue the waypoints beside it (see the module), each
    solved by ``solve(waypoint, seed)``; ``step``: ``max_joint_step`` per joint."""
    singular = [any(r.success and r.singular for r in rs) for rs in found]
    if not any(singular):
        return found
    reach = _Reach.of(arm, step)
    added: list[list[IKResult]] = [[] for _ in found]
    for a, b in _runs(singular):
        if b < len(found) - 1:  # no waypoint after it: the forward pass carries it on
            first = np.array(start, dtype=float, ndmin=2) if a == 0 else reach.q(found[a - 1])
            _interpolated(reach, found, added, (a, b), first, solve)
    for before in (1, -1):
        _carried(reach, found, added, singular, before, solve)
    return [rs + more for rs, more in zip(found, added)]


@dataclass(frozen=True)
class _Reach:
    """Which configurations steps within ``step`` reach from which, each angle 2 pi turns
    next to the one it is reached from (kept within the limits), as the plan turns it."""

    lower: np.ndarray
    upper: np.ndarray
    periodic: np.ndarray
    step: np.ndarray

    @classmethod
    def of(cls, arm: ArmModel, step: np.ndarray) -> _Reach:
        lower, upper, no_period = (np.array(x) for x in arm._limit_lists)
        return cls(lower, upper, ~no_period.astype(bool), np.asarray(step, dtype=float))

    def turned(self, Q, to: np.ndarray) -> np.ndarray:
        """(N, dof): each row of ``Q`` with its angles 2 pi turns next to ``to``'s."""
        T = np.array(Q, dtype=float, ndmin=2)
        k = np.round((T - to)[:, self.periodic] / (2.0 * np.pi))
        T[:, self.periodic] -= 2.0 * np.pi * k
        return T

    def q(self, rows: list[IKResult]) -> np.ndarray:
        """(N, dof): the joint values of the successes among ``rows``."""
        return np.array([r.q for r in rows if r.success], dtype=float).reshape(-1, len(self.step))

    def near(self, Q, to: np.ndarray, steps: int) -> np.ndarray:
        """(N,): whether ``steps`` steps reach each row of ``Q`` from ``to``."""
        T = self.turned(Q, to)
        inside = ((T >= self.lower - EDGE) & (T <= self.upper + EDGE)).all(axis=1)
        return inside & (np.abs(T - to) <= steps * self.step + EDGE).all(axis=1)


def _interpolated(reach: _Reach, found, added, run: tuple[int, int], first, solve) -> None:
    """Into ``added``: the rows of the singular run ``run`` (first, last waypoint) solved
    from its ends' answers (``first`` before it, the waypoint's after it) interpolated."""
    a, b = run
    into, out = (reach.q([r for r in found[k] if not r.singular]) for k in (a, b))
    for qa, qb in _paired(reach, first, reach.q(found[b + 1])):
        if not reach.near(qb, qa, b - a + 2)[0]:
            continue  # no steps through the run join them: the passes show the break
        if reach.near(into, qa, 1).any() and reach.near(out, qb, 1).any():
            continue  # a regular branch into the run and out of it: no free angle
        for i in range(a, b + 1):
            w = (i - a + 1) / (b - a + 2)
            seed = (1.0 - w) * qa + w * qb
            row = _nearest_singular(solve(i, seed), seed)
            if row is None or not reach.near(row.q, qa, i - a + 1)[0]:
                continue
            if reach.near(row.q, qb, b + 1 - i)[0] and _new(row, found[i] + added[i]):
                added[i].append(row)


def _carried(reach: _Reach, found, added, singular, before: int, solve) -> None:
    """Into ``added``: a pass over the waypoints (forward with ``before`` 1, backward with
    -1): each singular waypoint solved from each answer of the waypoint before it along
    the pass that none of its rows continues, its singular row kept where a step reaches
    it; the rows added carried on to the next."""
    n = len(found)
    carried: list[list[IKResult]] = [[] for _ in found]
    for i in range(n) if before == 1 else range(n - 1, -1, -1):
        j = i - before
        if not singular[i] or not 0 <= j < n:
            continue
        for q in reach.q(found[j] + added[j] + carried[j]):
            if reach.near(reach.q(found[i] + added[i] + carried[i]), q, 1).any():
                continue  # a row here goes on from it already
            row = _nearest_singular(solve(i, q), q)
            if row is not None and reach.near(row.q, q, 1)[0]:
                carried[i].append(row)
    for i, rows in enumerate(carried):
        added[i] += rows


def _runs(flags: list[bool]) -> list[tuple[int, int]]:
    """(first, last) of each run of consecutive True in ``flags``."""
    runs: list[tuple[int, int]] = []
    for i, flag in enumerate(flags):
        if flag and runs and runs[-1][1] == i - 1:
            runs[-1] = (runs[-1][0], i)
        elif flag:
            runs.append((i, i))
    return runs


def _paired(reach: _Reach, A: np.ndarray, B: np.ndarray) -> list:
    """Pairs (a, b) of rows of ``A`` and ``B``: each of either with the other's nearest it,
    ``b`` turned next to ``a``; each pair once."""
    pairs: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
    if not len(A) or not len(B):
        return []
    for ours, theirs, flip in ((A, B, False), (B, A, True)):
        for q in ours:
            p = theirs[np.argmin(np.abs(reach.turned(theirs, q) - q).max(axis=1))]
            a = p if flip else q
            pair = (a, reach.turned(q if flip else p, a)[0])
            pairs.setdefault(np.concatenate(pair).tobytes(), pair)
    return list(pairs.values())


def _nearest_singular(rows: list[IKResult], q: np.ndarray) -> IKResult | None:
    """The singular success among ``rows`` nearest ``q`` (None if there is none)."""
    singular = [r for r in rows if r.success and r.singular]
    return min(singular, key=lambda r: float(np.abs(r.q - q).max()), default=None)


def _new(row: IKResult, rows: list[IKResult]) -> bool:
    """Whether no success among ``rows`` lies within ``SAME`` of ``row``."""
    return not any(r.success and np.abs(np.asarray(r.q) - row.q).max() <= SAME for r in rows)
